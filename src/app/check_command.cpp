// `voxgi check SCENE`: loads a glTF scene with every check `render` makes, without
// a GL context, and prints what it holds (tools/gltf-validate runs it on every file).
#include <cstdio>

#include "app/cli.h"
#include "scene/gltf_loader.h"

namespace voxgi::app {

int runCheck(const CheckOptions& o) {
  const scene::Scene s = scene::loadGltf(o.scene);
  std::printf("%s: %zu triangles, %zu materials, %zu textures, %zu lights, %zu warnings\n",
              o.scene.c_str(), s.triangleCount(), s.materials.size(), s.textures.size(),
              s.lights.size(), s.warnings.size());
  return 0;
}

}  // namespace voxgi::app

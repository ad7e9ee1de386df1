// libFuzzer target: bytes -> the glTF loader and its validation, as `voxgi render`
// reaches them (scene::loadGltfFromMemory shares every check with loadGltf).
// Input starting with the GLB magic is read as .glb, anything else as .gltf JSON.
// A refused input must end in voxgi::Error; anything else (a crash, a sanitizer
// report, another exception, a scene that breaks the loader's own invariants) is
// a finding. Built by the `fuzz` preset; run by tools/test and tools/fuzz.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/log.h"
#include "scene/gltf_loader.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

// What every loaded scene promises its users (the renderer indexes with these).
void checkInvariants(const voxgi::scene::Scene& s) {
  size_t covered = 0;
  for (const voxgi::scene::Draw& d : s.draws) {
    check(d.firstIndex == covered && d.indexCount % 3 == 0 && d.indexCount > 0);
    check(d.material >= 0 && static_cast<size_t>(d.material) < s.materials.size());
    covered += d.indexCount;
  }
  check(covered == s.indices.size());
  for (uint32_t i : s.indices) check(i < s.vertices.size());
  for (const voxgi::scene::Vertex& v : s.vertices) {
    check(std::isfinite(v.position.x) && std::isfinite(v.position.y) &&
          std::isfinite(v.position.z));
    const float n = v.normal.x * v.normal.x + v.normal.y * v.normal.y + v.normal.z * v.normal.z;
    check(std::fabs(n - 1.0f) < 1e-3f);
  }
  for (const voxgi::scene::Material& m : s.materials)
    check(m.baseColorTexture < 0 || static_cast<size_t>(m.baseColorTexture) < s.textures.size());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  voxgi::setLogLevel(voxgi::LogLevel::kError);  // warnings for every input would drown the run
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  voxgi::scene::LoadOptions options;
  options.maxTextureSize = 512;  // keeps decoded images within libFuzzer's memory limit
  try {
    const voxgi::scene::Scene s =
        voxgi::scene::loadGltfFromMemory(data, size, glb ? "fuzz.glb" : "fuzz.gltf", options);
    checkInvariants(s);
  } catch (const voxgi::Error&) {
    // A refusal with a message: what malformed input should get.
  }
  return 0;
}

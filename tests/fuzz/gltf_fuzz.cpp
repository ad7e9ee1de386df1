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

bool finite(float v) {
  return std::isfinite(v);
}
bool finite(glm::vec2 v) {
  return finite(v.x) && finite(v.y);
}
bool finite(glm::vec3 v) {
  return finite(v.x) && finite(v.y) && finite(v.z);
}
bool finite(glm::vec4 v) {
  return finite(glm::vec3(v)) && finite(v.w);
}

// A texture slot: none, or a texture of the scene read through channel 0 or 1, with
// a finite transform.
void checkSlot(const voxgi::scene::Scene& s, int texture, int channel,
               const voxgi::scene::TextureTransform& t) {
  check(texture >= -1 && (texture < 0 || static_cast<size_t>(texture) < s.textures.size()));
  check(channel == 0 || channel == 1);
  check(t.texCoord >= 0);
  for (const glm::vec2& c : t.columns) check(finite(c));
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
    check(finite(v.position));
    const float n = v.normal.x * v.normal.x + v.normal.y * v.normal.y + v.normal.z * v.normal.z;
    check(std::fabs(n - 1.0f) < 1e-3f);
    // Both texture-coordinate channels are baked through finite transforms.
    check(finite(v.uv) && finite(v.uv2));
  }
  // Colours and tangents: none, or one per vertex; colours finite and within [0, 1],
  // tangents unit length with a handedness of +1 or -1.
  check(s.colors.empty() || s.colors.size() == s.vertices.size());
  for (const glm::vec4& c : s.colors)
    for (int k = 0; k < 4; ++k) check(c[k] >= 0.0f && c[k] <= 1.0f);
  check(s.tangents.empty() || s.tangents.size() == s.vertices.size());
  for (const glm::vec4& t : s.tangents) {
    check(finite(t));
    check(std::fabs(glm::dot(glm::vec3(t), glm::vec3(t)) - 1.0f) < 1e-3f);
    check(t.w == 1.0f || t.w == -1.0f);
  }
  for (const voxgi::scene::Material& m : s.materials) {
    check(finite(m.baseColor) && finite(m.emission) && finite(m.metallic) && finite(m.roughness) &&
          finite(m.normalScale) && finite(m.occlusionStrength));
    checkSlot(s, m.baseColorTexture, m.baseColorChannel, m.baseColorUv);
    checkSlot(s, m.emissiveTexture, m.emissiveChannel, m.emissiveUv);
    checkSlot(s, m.metallicRoughnessTexture, m.metallicRoughnessChannel, m.metallicRoughnessUv);
    checkSlot(s, m.normalTexture, m.normalChannel, m.normalUv);
    checkSlot(s, m.occlusionTexture, m.occlusionChannel, m.occlusionUv);
  }
  for (const voxgi::scene::Texture& t : s.textures)
    check(t.width > 0 && t.height > 0 &&
          t.rgba8.size() == 4 * static_cast<size_t>(t.width) * static_cast<size_t>(t.height));
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

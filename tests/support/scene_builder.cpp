#include "support/scene_builder.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support/test_paths.h"

namespace voxgi::test {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string base64(const std::string& data) {
  static const char* kTable = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = static_cast<uint8_t>(data[i]) << 16;
    if (i + 1 < data.size()) v |= static_cast<uint8_t>(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= static_cast<uint8_t>(data[i + 2]);
    out += kTable[(v >> 18) & 63];
    out += kTable[(v >> 12) & 63];
    out += i + 1 < data.size() ? kTable[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kTable[v & 63] : '=';
  }
  return out;
}

}  // namespace

int SceneBuilder::addMaterial(glm::vec3 albedo, glm::vec3 emission, bool doubleSided) {
  scene::Material m;
  m.baseColor = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.emission = emission;
  m.doubleSided = doubleSided;
  scene_.materials.push_back(m);
  return static_cast<int>(scene_.materials.size() - 1);
}

void SceneBuilder::addTriangles(const std::vector<glm::vec3>& corners, int material,
                                const glm::mat4& transform) {
  scene::Draw d;
  d.firstIndex = static_cast<uint32_t>(scene_.indices.size());
  d.material = material;
  for (size_t i = 0; i + 2 < corners.size(); i += 3) {
    glm::vec3 p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = glm::vec3(transform * glm::vec4(corners[i + static_cast<size_t>(k)], 1.0f));
    const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
    for (int k = 0; k < 3; ++k) {
      scene_.indices.push_back(static_cast<uint32_t>(scene_.vertices.size()));
      scene_.vertices.push_back({p[k], n, glm::vec2(0.0f)});
    }
  }
  d.indexCount = static_cast<uint32_t>(scene_.indices.size()) - d.firstIndex;
  scene_.draws.push_back(d);
}

void SceneBuilder::addBox(glm::vec3 lo, glm::vec3 hi, int material, const glm::mat4& transform) {
  auto c = [&](int i) {
    return glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  };
  // Corner bits: x=1, y=2, z=4; two counter-clockwise triangles per face, seen from outside.
  const int faces[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3},
                           {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
  std::vector<glm::vec3> corners;
  for (const auto& f : faces) {
    corners.insert(corners.end(), {c(f[0]), c(f[1]), c(f[2]), c(f[0]), c(f[2]), c(f[3])});
  }
  addTriangles(corners, material, transform);
}

scene::Scene SceneBuilder::finish() {
  scene_.path = "<test scene>";
  scene_.finalize();
  return scene_;
}

std::string writeTransformedGltf(const std::string& source, glm::dvec3 translation, double scale) {
  nlohmann::json g = nlohmann::json::parse(readFile(source));
  const std::string dir = std::filesystem::path(source).parent_path().string();
  for (auto& buffer : g["buffers"]) {
    const std::string uri = buffer["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0) continue;
    buffer["uri"] = "data:application/octet-stream;base64," + base64(readFile(dir + "/" + uri));
  }
  const size_t sceneIndex = g.value("scene", size_t{0});
  const size_t root = g["nodes"].size();
  g["nodes"].push_back({{"translation", {translation.x, translation.y, translation.z}},
                        {"scale", {scale, scale, scale}},
                        {"children", g["scenes"][sceneIndex]["nodes"]}});
  g["scenes"][sceneIndex]["nodes"] = nlohmann::json::array({root});
  const std::string path =
      scratchDir() + "/" + std::filesystem::path(source).stem().string() + "_moved.gltf";
  std::ofstream(path) << g.dump();
  return path;
}

}  // namespace voxgi::test

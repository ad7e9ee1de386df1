#include "support/scene_builder.h"

#include <cmath>
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

std::string writeJson(const std::string& name, const nlohmann::json& g) {
  const std::string path = scratchDir() + "/" + name;
  std::ofstream(path) << g.dump();
  return path;
}

void appendBytes(std::string* bin, const void* data, size_t bytes) {
  bin->append(static_cast<const char*>(data), bytes);
  bin->append(-bin->size() & 3u, '\0');  // the next view starts 4-byte aligned
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

void SceneBuilder::addSphere(glm::vec3 centre, float radius, int rings, int material,
                             const glm::mat4& transform) {
  auto at = [&](int i, int j) {
    const float theta = 3.14159265f * static_cast<float>(i) / static_cast<float>(rings);
    const float phi = 3.14159265f * static_cast<float>(j) / static_cast<float>(rings);
    return centre + radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                       std::sin(theta) * std::sin(phi));
  };
  std::vector<glm::vec3> t;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < 2 * rings; ++j) {
      t.insert(t.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.insert(t.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  addTriangles(t, material, transform);
}

void addQuad(scene::Scene* s, int material, const glm::vec3 (&p)[4], const glm::vec2 (&uv)[4]) {
  const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
  const auto first = static_cast<uint32_t>(s->vertices.size());
  const auto firstIndex = static_cast<uint32_t>(s->indices.size());
  for (int i = 0; i < 4; ++i) s->vertices.push_back({p[i], n, uv[i]});
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s->indices.push_back(first + i);
  s->draws.push_back({firstIndex, 6, material, -1, -1});
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
  if (g.contains("extensions") && g["extensions"].contains("KHR_lights_punctual"))
    for (auto& light : g["extensions"]["KHR_lights_punctual"]["lights"])
      if (light.value("type", "") != "directional")
        light["intensity"] = light.value("intensity", 1.0) * scale * scale;
  const std::string path =
      scratchDir() + "/" + std::filesystem::path(source).stem().string() + "_moved.gltf";
  std::ofstream(path) << g.dump();
  return path;
}

std::string writeMeshGltf(const std::string& name, const std::vector<glm::vec3>& positions,
                          const std::vector<uint32_t>& indices,
                          const std::vector<glm::vec3>& normals, double lightIntensity) {
  using nlohmann::json;
  std::string bin;
  auto append = [&bin](const void* data, size_t bytes) {
    bin.append(static_cast<const char*>(data), bytes);
  };
  json views = json::array(), accessors = json::array(), attributes = json::object();
  auto addVec3 = [&](const std::vector<glm::vec3>& v, const char* attribute) {
    const size_t offset = bin.size();
    append(v.data(), v.size() * sizeof(glm::vec3));
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bin.size() - offset}});
    json a = {{"bufferView", views.size() - 1},
              {"componentType", 5126},
              {"count", v.size()},
              {"type", "VEC3"}};
    if (std::string(attribute) == "POSITION") {
      glm::vec3 lo(1e30f), hi(-1e30f);
      for (const glm::vec3& p : v) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      a["min"] = {lo.x, lo.y, lo.z};
      a["max"] = {hi.x, hi.y, hi.z};
    }
    accessors.push_back(a);
    attributes[attribute] = accessors.size() - 1;
  };
  addVec3(positions, "POSITION");
  if (!normals.empty()) addVec3(normals, "NORMAL");
  const size_t offset = bin.size();
  append(indices.data(), indices.size() * sizeof(uint32_t));
  views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bin.size() - offset}});
  accessors.push_back({{"bufferView", views.size() - 1},
                       {"componentType", 5125},
                       {"count", indices.size()},
                       {"type", "SCALAR"}});
  const json g = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_lights_punctual"}},
      {"extensions",
       {{"KHR_lights_punctual",
         {{"lights", {{{"type", "point"}, {"intensity", lightIntensity}}}}}}}},
      {"buffers",
       {{{"byteLength", bin.size()},
         {"uri", "data:application/octet-stream;base64," + base64(bin)}}}},
      {"bufferViews", views},
      {"accessors", accessors},
      {"materials",
       {{{"doubleSided", true},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {0.7, 0.7, 0.7, 1.0}}, {"metallicFactor", 0.0}}}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", attributes}, {"indices", accessors.size() - 1}, {"material", 0}}}}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}}}}}},
      {"nodes",
       {{{"mesh", 0}},
        {{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}},
        {{"translation", {0.0, 0.0, 2.0}},
         {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
      {"scenes", {{{"nodes", {0, 1, 2}}}}},
      {"scene", 0}};
  const std::string path = scratchDir() + "/" + name;
  std::ofstream(path) << g.dump();
  return path;
}

std::string writeDeepChainGltf(const std::string& name, int depth, glm::dvec3 step, bool animated) {
  using nlohmann::json;
  const glm::vec3 corners[3] = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  const uint16_t triangle[3] = {0, 1, 2};
  std::string bin;
  appendBytes(&bin, corners, sizeof corners);
  const size_t indicesAt = bin.size();
  appendBytes(&bin, triangle, sizeof triangle);
  json views = {{{"buffer", 0}, {"byteLength", sizeof corners}},
                {{"buffer", 0}, {"byteOffset", indicesAt}, {"byteLength", sizeof triangle}}};
  json accessors = {{{"bufferView", 0},
                     {"componentType", 5126},
                     {"count", 3},
                     {"type", "VEC3"},
                     {"min", {0.0, 0.0, 0.0}},
                     {"max", {1.0, 1.0, 0.0}}},
                    {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}};
  json g = {{"asset", {{"version", "2.0"}}},
            {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
            {"scenes", {{{"nodes", {0}}}}},
            {"scene", 0}};
  if (animated) {
    // The root's translation: `step` at t = 0, step + (1, 0, 0) at t = 1.
    const float times[2] = {0.0f, 1.0f};
    const glm::vec3 moves[2] = {glm::vec3(step), glm::vec3(step + glm::dvec3(1.0, 0.0, 0.0))};
    const size_t timesAt = bin.size();
    appendBytes(&bin, times, sizeof times);
    const size_t movesAt = bin.size();
    appendBytes(&bin, moves, sizeof moves);
    views.push_back({{"buffer", 0}, {"byteOffset", timesAt}, {"byteLength", sizeof times}});
    views.push_back({{"buffer", 0}, {"byteOffset", movesAt}, {"byteLength", sizeof moves}});
    accessors.push_back({{"bufferView", 2},
                         {"componentType", 5126},
                         {"count", 2},
                         {"type", "SCALAR"},
                         {"min", {0.0}},
                         {"max", {1.0}}});
    accessors.push_back(
        {{"bufferView", 3}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    g["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
         {"samplers", {{{"input", 2}, {"output", 3}}}}}};
  }
  g["buffers"] = {
      {{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
  g["bufferViews"] = views;
  g["accessors"] = accessors;
  json nodes = json::array();
  for (int i = 0; i < depth; ++i) {
    json node = json::object();
    if (step != glm::dvec3(0.0)) node["translation"] = {step.x, step.y, step.z};
    if (i + 1 < depth)
      node["children"] = {i + 1};
    else
      node["mesh"] = 0;
    nodes.push_back(std::move(node));
  }
  g["nodes"] = std::move(nodes);
  return writeJson(name, g);
}

scene::Scene squareBeforeWall() {
  SceneBuilder b;
  const int white = b.addMaterial(glm::vec3(0.8f));
  const int black = b.addMaterial(glm::vec3(0.0f));
  // A square of half-width h at depth z, facing +z: two triangles.
  auto square = [&](float h, float z, int material) {
    b.addTriangles({{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, -h, z}, {h, h, z}, {-h, h, z}},
                   material);
  };
  square(0.5f, 0.5f, white);
  square(3.0f, 0.0f, black);
  scene::Scene s = b.finish();
  lightHeadOnFromZ(&s, 3.0f);
  return s;
}

void lightHeadOnFromZ(scene::Scene* s, float distance) {
  scene::Light sun;
  sun.type = scene::LightType::kDirectional;
  sun.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  sun.intensity = 3.0f;
  s->lights = {sun};
  s->camera.position = glm::vec3(0.0f, 0.0f, distance) - glm::vec3(s->origin);
  s->camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  s->camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s->camera.znear = 0.1f;
  s->camera.zfar = 10.0f;
}

scene::Scene sealedBox(float thickness, bool outsideOn) {
  SceneBuilder b;
  const int wall = b.addMaterial(glm::vec3(0.7f));
  const float in = 1.0f, out = 1.0f + thickness;
  b.addBox({-out, -out, -out}, {out, -in, out}, wall);
  b.addBox({-out, in, -out}, {out, out, out}, wall);
  b.addBox({-out, -out, -out}, {-in, out, out}, wall);
  b.addBox({in, -out, -out}, {out, out, out}, wall);
  b.addBox({-out, -out, -out}, {out, out, -in}, wall);
  b.addBox({-out, -out, in}, {out, out, out}, wall);
  scene::Scene s = b.finish();
  s.scale.gridOrigin = glm::vec3(-2.0f);
  s.scale.gridSize = 4.0f;
  scene::Light inside;
  inside.position = glm::vec3(0.0f, 0.5f, 0.0f);
  inside.intensity = 1.0f;
  s.lights = {inside};
  if (outsideOn) {
    scene::Light outside = inside;
    outside.position = glm::vec3(0.0f, 0.0f, out + 0.3f);
    outside.intensity = 1000.0f;
    s.lights.push_back(outside);
  }
  s.defaultLight = false;
  return s;
}

}  // namespace voxgi::test

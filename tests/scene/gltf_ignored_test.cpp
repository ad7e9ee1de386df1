// glTF loader: what voxgi ignores or reads only in part (optional extensions it does
// not implement, extra scenes, skins, morph targets, points and lines, cameras not
// used) is printed once per kind when the file loads, naming the
// file, however many places share it. The files are built in memory around one
// triangle.
#include "scene/gltf_loader.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/log.h"

namespace voxgi::scene {
namespace {

using nlohmann::json;

// Three float corners, (0,0,0) (1,0,0) (0,1,0), base64.
constexpr const char* kTriangleData =
    "data:application/octet-stream;base64,"
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

// One node drawing one triangle without a material.
json triangleFile() {
  return json{{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", json::array({{{"nodes", json::array({0})}}})},
              {"nodes", json::array({{{"mesh", 0}}})},
              {"meshes",
               json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}})},
              {"accessors", json::array({{{"bufferView", 0},
                                          {"componentType", 5126},
                                          {"count", 3},
                                          {"type", "VEC3"},
                                          {"min", {0.0, 0.0, 0.0}},
                                          {"max", {1.0, 1.0, 0.0}}}})},
              {"bufferViews", json::array({{{"buffer", 0}, {"byteLength", 36}}})},
              {"buffers", json::array({{{"byteLength", 36}, {"uri", kTriangleData}}})}};
}

// The primitive of triangleFile(), with `extra` fields merged in.
json primitive(const json& extra = json::object()) {
  json p = {{"attributes", {{"POSITION", 0}}}};
  p.update(extra);
  return p;
}

// `count` nodes each drawing mesh 0, all roots of scene 0.
void meshNodes(json* f, int count, const json& extra = json::object()) {
  (*f)["nodes"] = json::array();
  (*f)["scenes"][0]["nodes"] = json::array();
  for (int i = 0; i < count; ++i) {
    json n = {{"mesh", 0}, {"translation", {2.0 * i, 0.0, 0.0}}};
    n.update(extra);
    (*f)["nodes"].push_back(n);
    (*f)["scenes"][0]["nodes"].push_back(i);
  }
}

struct Loaded {
  Scene scene;
  std::vector<std::string> printed;  // the warning lines on stderr
};

// Loads `f` from memory as scene.gltf, with the warnings it prints.
Loaded load(const json& f) {
  const std::string bytes = f.dump();
  const LogLevel level = logLevel();
  setLogLevel(LogLevel::kInfo);
  ::testing::internal::CaptureStderr();
  Loaded out;
  try {
    out.scene = loadGltfFromMemory(bytes.data(), bytes.size(), "scene.gltf");
  } catch (...) {
    ::testing::internal::GetCapturedStderr();
    setLogLevel(level);
    throw;
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  setLogLevel(level);
  size_t at = 0;
  for (size_t end; (end = err.find('\n', at)) != std::string::npos; at = end + 1) {
    const std::string line = err.substr(at, end - at);
    if (line.find("warning: ") != std::string::npos) out.printed.push_back(line);
  }
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

// Exactly `expected`, in order, each printed once as "scene.gltf: " + it.
void expectWarnings(const Loaded& l, const std::vector<std::string>& expected) {
  EXPECT_EQ(l.scene.warnings, expected) << joined(l.scene.warnings);
  ASSERT_EQ(l.printed.size(), expected.size()) << joined(l.printed);
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_NE(l.printed[i].find("warning: scene.gltf: " + expected[i]), std::string::npos)
        << l.printed[i];
}

TEST(GltfLoaderIgnored, PlainTriangleSaysNothing) {
  const Loaded l = load(triangleFile());
  EXPECT_EQ(l.scene.triangleCount(), 1u);
  expectWarnings(l, {});
}

TEST(GltfLoaderIgnored, OptionalExtensionsOneLineEach) {
  json f = triangleFile();
  f["extensionsUsed"] = {"KHR_materials_transmission", "KHR_lights_punctual",
                         "KHR_materials_clearcoat",    "EXT_texture_webp",
                         "KHR_draco_mesh_compression", "KHR_texture_transform"};
  // Used on 40 materials: still one line per extension.
  for (int i = 0; i < 40; ++i)
    f["materials"].push_back({{"extensions", {{"KHR_materials_transmission", json::object()}}}});
  f["meshes"][0]["primitives"][0]["material"] = 39;
  expectWarnings(load(f),
                 {"extension KHR_materials_transmission is not supported; materials render "
                  "without it",
                  "extension KHR_materials_clearcoat is not supported; materials render without it",
                  "extension EXT_texture_webp is not supported; textures read their PNG or JPEG "
                  "source",
                  "extension KHR_draco_mesh_compression is not supported; the uncompressed "
                  "geometry is drawn"});
  // Required, an unsupported extension is still refused.
  f["extensionsRequired"] = json::array({"KHR_materials_transmission"});
  EXPECT_THROW(load(f), Error);
}

// BLEND is drawn (as coverage: scene_shared.h's kMaterialAlphaBlend), so it is read
// without a warning.
TEST(GltfLoaderIgnored, BlendMaterialsAreReadWithoutAWarning) {
  json f = triangleFile();
  f["materials"] =
      json::array({{{"alphaMode", "OPAQUE"}}, {{"alphaMode", "MASK"}}, {{"alphaMode", "BLEND"}}});
  json prims = json::array();
  for (int m = 0; m < 3; ++m) prims.push_back(primitive({{"material", m}}));
  f["meshes"][0]["primitives"] = prims;
  const Loaded l = load(f);
  expectWarnings(l, {});
  EXPECT_EQ(l.scene.materials[0].alphaMode, AlphaMode::kOpaque);
  EXPECT_EQ(l.scene.materials[1].alphaMode, AlphaMode::kMask);
  EXPECT_EQ(l.scene.materials[2].alphaMode, AlphaMode::kBlend);
}

TEST(GltfLoaderIgnored, SkinsOneLine) {
  json f = triangleFile();
  meshNodes(&f, 4, {{"skin", 0}});
  f["nodes"].push_back(json::object());  // the joint
  f["skins"] = json::array({{{"joints", json::array({4})}}});
  const Loaded l = load(f);
  EXPECT_EQ(l.scene.triangleCount(), 4u);
  expectWarnings(l, {"4 nodes (nodes[0] first): skins are not applied; the meshes are drawn "
                     "undeformed, as stored"});
}

TEST(GltfLoaderIgnored, MorphTargetsAndWeightChannelsOneLineEach) {
  json f = triangleFile();
  f["meshes"][0]["primitives"] =
      json::array({primitive({{"targets", json::array({{{"POSITION", 0}}})}}),
                   primitive({{"targets", json::array({{{"POSITION", 0}}})}}), primitive()});
  f["meshes"][0]["weights"] = json::array({0.5});
  meshNodes(&f, 3);
  json sampler = {{"input", 0}, {"output", 0}};
  json channel = {{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}};
  f["animations"] = json::array(
      {{{"samplers", json::array({sampler})}, {"channels", json::array({channel, channel})}},
       {{"samplers", json::array({sampler})}, {"channels", json::array({channel})}}});
  const Loaded l = load(f);
  EXPECT_EQ(l.scene.triangleCount(), 9u);
  expectWarnings(
      l, {"2 primitives (mesh 0 primitive 0 first): morph targets are not applied; the base "
          "geometry is drawn",
          "3 channels (animation 0 channel 0 first): morph target weights are not animated; "
          "skipped"});
}

TEST(GltfLoaderIgnored, PointsAndLinesOneLine) {
  json f = triangleFile();
  f["meshes"][0]["primitives"] = json::array({primitive({{"mode", 0}}), primitive({{"mode", 1}}),
                                              primitive({{"mode", 3}}), primitive({{"mode", 4}})});
  meshNodes(&f, 5);
  const Loaded l = load(f);
  EXPECT_EQ(l.scene.triangleCount(), 5u);
  expectWarnings(l, {"3 primitives (mesh 0 primitive 0 first): points and lines are not "
                     "rendered; skipped"});
}

TEST(GltfLoaderIgnored, CamerasNotUsedOneLineEach) {
  json f = triangleFile();
  const json ortho = {
      {"type", "orthographic"},
      {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}};
  const json persp = {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}};
  f["cameras"] = json::array({ortho, ortho, persp, persp});
  for (int c = 0; c < 4; ++c) {
    f["nodes"].push_back({{"camera", c}, {"translation", {0.0, 0.0, 5.0}}});
    f["scenes"][0]["nodes"].push_back(c + 1);
  }
  const Loaded l = load(f);
  EXPECT_TRUE(l.scene.camera.fromFile);
  expectWarnings(
      l, {"2 cameras (cameras[0] first): orthographic cameras are not used; the view is from "
          "cameras[2]",
          "cameras[3]: only the first perspective camera is used; the view is from cameras[2]"});

  json only = triangleFile();
  only["cameras"] = json::array({ortho});
  only["nodes"].push_back({{"camera", 0}});
  only["scenes"][0]["nodes"].push_back(1);
  const Loaded o = load(only);
  EXPECT_FALSE(o.scene.camera.fromFile);
  expectWarnings(o, {"cameras[0]: orthographic cameras are not used; framing the scene instead"});
}

TEST(GltfLoaderIgnored, ScenesOtherThanTheDrawnOneOneLine) {
  json f = triangleFile();
  f["scenes"] = json::array(
      {{{"nodes", json::array({0})}}, {{"nodes", json::array()}}, {{"nodes", json::array({0})}}});
  f["scene"] = 2;
  expectWarnings(load(f), {"3 scenes: only scenes[2] is drawn (the default)"});
  f.erase("scene");
  expectWarnings(load(f), {"3 scenes: only scenes[0] is drawn (the first; the file names no "
                           "default)"});
}

}  // namespace
}  // namespace voxgi::scene

// glTF loader: the samples load with the expected content, auto-scale follows the
// scene's size, loads are deterministic, and every file of the malformed corpus
// (tests/data/malformed, written by make_corpus.py) is refused with a one-line
// voxgi::Error that names the file and the problem.
#include "scene/gltf_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/log.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::scene {
namespace {

namespace fs = std::filesystem;

constexpr float kPi = 3.14159265358979f;

std::string sample(const std::string& relative) {
  return test::samplesDir() + "/" + relative;
}
std::string darkPlane() {
  return test::sourceDir() + "/scenes/dark_plane/dark_plane.gltf";
}
std::string malformedDir() {
  return test::testDataDir() + "/malformed";
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeFile(const std::string& path, const std::string& data) {
  std::ofstream out(path, std::ios::binary);
  out << data;
  ASSERT_TRUE(out.good()) << path;
}

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) |
                       (uint32_t(uint8_t(bytes[i + 1])) << 8) | uint32_t(uint8_t(bytes[i + 2]));
    for (int k = 3; k >= 0; --k) out += kAlphabet[(v >> (6 * k)) & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

// The first few lines, indented, and how many more there are.
std::string joined(const std::vector<std::string>& lines, size_t most = 6) {
  std::string s;
  for (size_t i = 0; i < lines.size() && i < most; ++i) s += "\n  " + lines[i];
  if (lines.size() > most) s += "\n  ... and " + std::to_string(lines.size() - most) + " more";
  return s;
}

// A message as a failure shows it: at most `most` characters.
std::string shown(const std::string& what, size_t most = 300) {
  if (what.size() <= most) return what;
  return what.substr(0, most) + "... (" + std::to_string(what.size()) + " characters in all)";
}

// What follows "PATH: " (the file name itself must not satisfy an expectation).
std::string problem(const std::string& what, const std::string& path) {
  return what.rfind(path + ": ", 0) == 0 ? what.substr(path.size() + 2) : what;
}

// Sum of N over the loader's "dropped N degenerate triangles" warnings.
size_t droppedZeroArea(const std::vector<std::string>& warnings) {
  size_t total = 0;
  for (const std::string& w : warnings) {
    const size_t at = w.find("dropped ");
    if (at == std::string::npos || w.find(" degenerate triangles", at) == std::string::npos)
      continue;
    total += std::stoul(w.substr(at + 8));
  }
  return total;
}

// Structural invariants every loaded scene keeps, whatever the file.
void expectWellFormed(const Scene& s) {
  for (uint32_t i : s.indices) ASSERT_LT(i, s.vertices.size());
  size_t covered = 0;
  for (const Draw& d : s.draws) {
    EXPECT_EQ(d.firstIndex, covered);
    EXPECT_EQ(d.indexCount % 3, 0u);
    ASSERT_GE(d.material, 0);
    ASSERT_LT(static_cast<size_t>(d.material), s.materials.size());
    covered += d.indexCount;
  }
  EXPECT_EQ(covered, s.indices.size());
  for (const Vertex& v : s.vertices) {
    ASSERT_TRUE(std::isfinite(v.position.x) && std::isfinite(v.position.y) &&
                std::isfinite(v.position.z));
    ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-3f);
  }
  for (const Material& m : s.materials) {
    if (m.baseColorTexture >= 0) {
      EXPECT_LT(static_cast<size_t>(m.baseColorTexture), s.textures.size());
    }
  }
  EXPECT_FALSE(s.bounds.empty());
  EXPECT_GT(s.scale.gridSize, 0.0f);
  EXPECT_GT(s.scale.cameraSpeed, 0.0f);
  EXPECT_GT(s.camera.zfar, s.camera.znear);
  EXPECT_GT(s.camera.znear, 0.0f);
}

// --- the samples -------------------------------------------------------------

struct SampleCase {
  const char* name;
  const char* path;      // relative to samplesDir()
  size_t fileTriangles;  // triangles in the file's index data (scenes/README.md)
  size_t zeroArea;       // of which are degenerate (see below): dropped, with a warning
  // Every other warning, in order: what the file uses that voxgi ignores.
  std::vector<std::string> ignored = {};
};

class SampleTest : public ::testing::TestWithParam<SampleCase> {};

TEST_P(SampleTest, LoadsWithExactTriangleCount) {
  const SampleCase& c = GetParam();
  const Scene s = loadGltf(sample(c.path));
  const size_t dropped = droppedZeroArea(s.warnings);
  // Every triangle of the file is either kept or reported as dropped...
  EXPECT_EQ(s.triangleCount() + dropped, c.fileTriangles)
      << c.path << "; warnings:" << joined(s.warnings);
  // ...and exactly the known degenerate ones are dropped.
  EXPECT_EQ(dropped, c.zeroArea) << c.path << "; warnings:" << joined(s.warnings);
  EXPECT_EQ(s.triangleCount(), c.fileTriangles - c.zeroArea) << c.path;
  EXPECT_EQ(s.path, sample(c.path));
  std::vector<std::string> others;
  for (const std::string& w : s.warnings)
    if (w.find(" degenerate triangles") == std::string::npos) others.push_back(w);
  EXPECT_EQ(others, c.ignored) << c.path << "; warnings:" << joined(s.warnings);
  expectWellFormed(s);
}

// Degenerate triangles in the samples, checked against the files with an
// independent script:
// - cornell_box: both UV spheres (meshes 7 and 8, 8318 triangles each) have 190
//   pole triangles with two bit-identical corners (380), and 40 pole slivers each
//   whose corners differ by ~1e-8: they keep a tiny area in double precision, but
//   in the float positions the GPU gets they are collinear or collapse (80): 460.
// - metal_rough_spheres_no_textures: each of the 98 drawn sphere instances has 2
//   triangles with two bit-identical corners (e.g. indices 2 and 74): 196.

INSTANTIATE_TEST_SUITE_P(
    Samples, SampleTest,
    ::testing::Values(
        SampleCase{"cornell_room", "cornell_room/cornell_room.gltf", 32268, 0},
        SampleCase{"dark_plane", "dark_plane/dark_plane.gltf", 48386, 0},
        SampleCase{"cornell_box",
                   "cornell_box/cornellBox.gltf",
                   16732,
                   460,
                   {"extension NV_materials_mdl is not supported; materials render without it"}},
        SampleCase{"box", "box/Box.gltf", 12, 0}, SampleCase{"duck", "duck/Duck.gltf", 4212, 0},
        SampleCase{"avocado", "avocado/Avocado.gltf", 682, 0},
        SampleCase{"metal_rough_spheres_no_textures",
                   "metal_rough_spheres_no_textures/MetalRoughSpheresNoTextures.gltf", 1040409,
                   196},
        SampleCase{"lights_punctual_lamp",
                   "lights_punctual_lamp/LightsPunctualLamp.gltf",
                   6000,
                   0,
                   {"extension KHR_materials_transmission is not supported; materials render "
                    "without it"}},
        SampleCase{"emissive_strength_test", "emissive_strength_test/EmissiveStrengthTest.gltf", 90,
                   0},
        SampleCase{"normal_tangent_mirror_test",
                   "normal_tangent_mirror_test/NormalTangentMirrorTest.gltf", 5240, 0},
        SampleCase{"texture_transform_test", "texture_transform_test/TextureTransformTest.gltf", 24,
                   0},
        SampleCase{"texture_coordinate_test", "texture_coordinate_test/TextureCoordinateTest.gltf",
                   10, 0},
        SampleCase{"vertex_color_test", "vertex_color_test/VertexColorTest.gltf", 36, 0}),
    [](const ::testing::TestParamInfo<SampleCase>& param) {
      return std::string(param.param.name);
    });

// The shipped copy needs no samples: scenes/cornell_room.
TEST(GltfLoaderCornellRoom, CameraFromFile) {
  const Scene s = loadGltf(test::cornellRoom());
  EXPECT_TRUE(s.camera.fromFile);
  EXPECT_NEAR(s.camera.position.x + s.origin.x, 0.0f, 1e-5f);
  EXPECT_NEAR(s.camera.position.y + s.origin.y, 1.0f, 1e-5f);
  EXPECT_NEAR(s.camera.position.z + s.origin.z, 3.4f, 1e-5f);
  EXPECT_NEAR(s.camera.yfov, 40.0f * kPi / 180.0f, 1e-5f);
  EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-5f);
  EXPECT_NEAR(s.camera.up.y, 1.0f, 1e-5f);
}

TEST(GltfLoaderCornellRoom, EmissiveStrengthApplied) {
  const Scene s = loadGltf(test::cornellRoom());
  int emissive = 0;
  for (const Material& m : s.materials) {
    if (!m.isEmissive()) continue;
    ++emissive;
    EXPECT_NEAR(m.emission.x, 15.0f, 1e-4f) << m.name;
    EXPECT_NEAR(m.emission.y, 15.0f, 1e-4f) << m.name;
    EXPECT_NEAR(m.emission.z, 15.0f, 1e-4f) << m.name;
    EXPECT_FALSE(m.doubleSided) << m.name;
  }
  EXPECT_EQ(emissive, 1);
  EXPECT_TRUE(s.hasEmission());
}

TEST(GltfLoaderCornellRoom, MirrorMaterial) {
  const Scene s = loadGltf(test::cornellRoom());
  const auto mirror = std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) {
    return m.metallic == 1.0f && m.roughness == 0.0f;
  });
  ASSERT_NE(mirror, s.materials.end());
  EXPECT_NEAR(mirror->baseColor.r, 0.95f, 1e-6f);
  EXPECT_NEAR(mirror->baseColor.g, 0.95f, 1e-6f);
  EXPECT_NEAR(mirror->baseColor.b, 0.95f, 1e-6f);
  EXPECT_NEAR(mirror->baseColor.a, 1.0f, 1e-6f);
}

TEST(GltfLoaderCornellRoom, LitByEmissionOnly) {
  const Scene s = loadGltf(test::cornellRoom());
  EXPECT_TRUE(s.lights.empty());
  EXPECT_FALSE(s.defaultLight);
}

TEST(GltfLoaderCornellRoom, Bounds) {
  const Scene s = loadGltf(test::cornellRoom());
  EXPECT_NEAR(s.bounds.min.x + s.origin.x, -1.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.min.y + s.origin.y, 0.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.min.z + s.origin.z, -1.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.max.x + s.origin.x, 1.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.max.y + s.origin.y, 2.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.max.z + s.origin.z, 1.0f, 1e-4f);
  EXPECT_EQ(s.triangleCount(), 32268u);
  EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
}

TEST(GltfLoaderDarkPlane, SphereLightEmission) {
  const Scene s = loadGltf(darkPlane());
  int emissive = 0;
  for (const Material& m : s.materials) {
    if (!m.isEmissive()) continue;
    ++emissive;
    EXPECT_NEAR(m.emission.x, 100.0f, 1e-3f);
    EXPECT_NEAR(m.emission.y, 100.0f, 1e-3f);
    EXPECT_NEAR(m.emission.z, 100.0f, 1e-3f);
  }
  EXPECT_EQ(emissive, 1);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_FALSE(s.defaultLight);
  EXPECT_EQ(s.triangleCount(), 48386u);
}

TEST(GltfLoaderSamples, UnlitBoxGetsDefaultDirectionalLight) {
  const Scene s = loadGltf(sample("box/Box.gltf"));
  EXPECT_FALSE(s.hasEmission());
  for (const Material& m : s.materials) EXPECT_FALSE(m.isEmissive()) << m.name;
  EXPECT_TRUE(s.defaultLight);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::kDirectional);
  EXPECT_FALSE(s.camera.fromFile);
}

TEST(GltfLoaderSamples, DefaultLightCanBeTurnedOff) {
  LoadOptions options;
  options.addDefaultLight = false;
  const Scene s = loadGltf(sample("box/Box.gltf"), options);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_FALSE(s.defaultLight);
}

TEST(GltfLoaderSamples, PunctualLightsFromExtension) {
  const Scene s = loadGltf(sample("lights_punctual_lamp/LightsPunctualLamp.gltf"));
  EXPECT_FALSE(s.defaultLight);
  ASSERT_EQ(s.lights.size(), 5u);  // five point lights in KHR_lights_punctual
  for (const Light& l : s.lights) {
    EXPECT_EQ(l.type, LightType::kPoint) << l.name;
    EXPECT_GT(l.intensity, 0.0f) << l.name;
  }
  const auto point = std::find_if(s.lights.begin(), s.lights.end(),
                                  [](const Light& l) { return l.name == "Point"; });
  ASSERT_NE(point, s.lights.end());
  EXPECT_FLOAT_EQ(point->intensity, 15.0f);
  EXPECT_NEAR(point->color.r, 1.0f, 1e-6f);
  EXPECT_NEAR(point->color.g, 0.631875f, 1e-5f);
  EXPECT_NEAR(point->color.b, 0.2390998f, 1e-5f);
  // The node's translation column.
  EXPECT_NEAR(point->position.x + s.origin.x, 0.0462236f, 1e-5f);
  EXPECT_NEAR(point->position.y + s.origin.y, 0.9077973f, 1e-5f);
  EXPECT_NEAR(point->position.z + s.origin.z, 0.0066966f, 1e-5f);
}

TEST(GltfLoaderSamples, EmissiveStrengthMultipliesEmissiveFactor) {
  const Scene s = loadGltf(sample("emissive_strength_test/EmissiveStrengthTest.gltf"));
  const std::map<std::string, float> strength = {
      {"Emit1", 1.0f}, {"Emit2", 2.0f}, {"Emit4", 4.0f}, {"Emit8", 8.0f}, {"Emit16", 16.0f}};
  int found = 0;
  for (const Material& m : s.materials) {
    auto it = strength.find(m.name);
    if (it == strength.end()) continue;
    ++found;
    EXPECT_NEAR(m.emission.x, 0.1f * it->second, 1e-5f * it->second) << m.name;
    EXPECT_NEAR(m.emission.y, 0.5f * it->second, 1e-5f * it->second) << m.name;
    EXPECT_NEAR(m.emission.z, 0.9f * it->second, 1e-5f * it->second) << m.name;
  }
  EXPECT_EQ(found, 5);
}

// COLOR_0 (normalized unsigned bytes, tests/data/vertex_colors): red on the left
// half, green on the right; the primitive without COLOR_0 reads white.
TEST(GltfLoaderVertexColors, RedGreenQuad) {
  const Scene s = loadGltf(test::testDataDir() + "/vertex_colors/red_green_quad.gltf");
  ASSERT_TRUE(s.hasVertexColors());
  ASSERT_EQ(s.colors.size(), s.vertices.size());
  ASSERT_EQ(s.vertices.size(), 12u);
  for (size_t i = 0; i < s.vertices.size(); ++i) {
    const glm::vec3 p = s.vertices[i].position + glm::vec3(s.origin);
    const glm::vec4 c = s.colors[i];
    const glm::vec4 want = p.z < -0.5f           ? glm::vec4(1.0f)
                           : i < 4 || p.x < 0.0f ? glm::vec4(1, 0, 0, 1)
                                                 : glm::vec4(0, 1, 0, 1);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(c[k], want[k]) << "vertex " << i << " component " << k;
  }
}

// The Khronos VertexColorTest (scenes/vertex_color_test): COLOR_0 is float VEC4 on
// the checks' mesh only. Its top row of checks is multiplied by pure red, green and
// blue (left to right, 4 vertices each), the bottom row and the backdrop by white or
// grey; the label mesh, without COLOR_0, reads white.
TEST(GltfLoaderVertexColors, KhronosVertexColorTest) {
  const Scene s = loadGltf(sample("vertex_color_test/VertexColorTest.gltf"));
  EXPECT_EQ(s.triangleCount(), 36u);
  ASSERT_TRUE(s.hasVertexColors());
  ASSERT_EQ(s.colors.size(), s.vertices.size());
  size_t red = 0, green = 0, blue = 0, grey = 0, white = 0;
  for (size_t i = 0; i < s.vertices.size(); ++i) {
    SCOPED_TRACE("vertex " + std::to_string(i));
    const glm::vec3 p = s.vertices[i].position + glm::vec3(s.origin);
    const glm::vec4 c = s.colors[i];
    EXPECT_EQ(c.a, 1.0f);
    if (c == glm::vec4(1, 0, 0, 1)) {
      ++red;
      EXPECT_LT(p.x, -0.3f);
    } else if (c == glm::vec4(0, 1, 0, 1)) {
      ++green;
      EXPECT_LT(std::abs(p.x), 0.24f);
    } else if (c == glm::vec4(0, 0, 1, 1)) {
      ++blue;
      EXPECT_GT(p.x, 0.3f);
    } else if (c.r == c.g && c.g == c.b && c.r > 0.5f && c.r < 0.52f) {
      ++grey;
      continue;
    } else {
      EXPECT_GT(c.r, 0.99f);
      EXPECT_GT(c.g, 0.99f);
      EXPECT_EQ(c.b, 1.0f);
      ++white;
      continue;
    }
    EXPECT_GT(p.y, 0.1f) << "the coloured checks are the top row";
  }
  EXPECT_EQ(red, 4u);
  EXPECT_EQ(green, 4u);
  EXPECT_EQ(blue, 4u);
  EXPECT_EQ(grey, 18u);
  EXPECT_EQ(red + green + blue + grey + white, s.vertices.size());
}

// Scenes without COLOR_0 carry no colour stream.
TEST(GltfLoaderVertexColors, NoneWithoutColor0) {
  EXPECT_FALSE(loadGltf(darkPlane()).hasVertexColors());
}

// --- accessors: KHR_mesh_quantization and sparse (tests/data/accessors) ---------------

std::string accessorsDir() {
  return test::testDataDir() + "/accessors";
}

// Two loads hold the same triangles: positions (in the file's frame), normals and
// UVs per vertex within `tolerance`, and the same indices.
void expectSameVertices(const Scene& a, const Scene& b, float tolerance) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  EXPECT_EQ(a.indices, b.indices);
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    SCOPED_TRACE("vertex " + std::to_string(i));
    const Vertex& u = a.vertices[i];
    const Vertex& v = b.vertices[i];
    const glm::vec3 pu = u.position + glm::vec3(a.origin), pv = v.position + glm::vec3(b.origin);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(pu[k], pv[k], tolerance);
      EXPECT_NEAR(u.normal[k], v.normal[k], tolerance);
    }
    EXPECT_NEAR(u.uv.x, v.uv.x, tolerance);
    EXPECT_NEAR(u.uv.y, v.uv.y, tolerance);
  }
}

// Every component type of KHR_mesh_quantization's table (POSITION 8/16-bit signed
// and unsigned, normalized or not, under dequantizing node transforms; normalized
// BYTE and SHORT normals; TEXCOORD_0 of all four integer types) reads as the float
// twin's values, which make_accessors.py dequantized on its own.
TEST(GltfLoaderAccessors, QuantizedMatchesFloatTwin) {
  const Scene q = loadGltf(accessorsDir() + "/quantized.gltf");
  const Scene f = loadGltf(accessorsDir() + "/quantized_float.gltf");
  EXPECT_TRUE(q.warnings.empty()) << joined(q.warnings);
  EXPECT_EQ(q.triangleCount(), 7u);
  expectSameVertices(q, f, 2e-6f);
  // Spot checks against the numbers of the generator: the wall spans 2 x 2 (SHORT
  // +-100 under scale 0.01) and repeats the checker twice (UNSIGNED_BYTE 0..2).
  const glm::vec3 corner = q.vertices[2].position + glm::vec3(q.origin);
  EXPECT_NEAR(corner.x, 1.0f, 1e-6f);
  EXPECT_NEAR(corner.y, 1.0f, 1e-6f);
  EXPECT_EQ(q.vertices[0].uv, glm::vec2(0.0f, 2.0f));
  // The tile's normalized SHORT UVs reach -1 and 1 exactly.
  EXPECT_EQ(q.vertices[4].uv, glm::vec2(-1.0f, 1.0f));
}

// Sparse accessors: POSITION's base with four vertices replaced (UNSIGNED_BYTE
// indices), TEXCOORD_0's with two (UNSIGNED_SHORT), NORMAL of zeros (no bufferView)
// with every vertex given (UNSIGNED_INT): the same vertices as the dense twin.
TEST(GltfLoaderAccessors, SparseMatchesDenseTwin) {
  const Scene sp = loadGltf(accessorsDir() + "/sparse.gltf");
  const Scene dense = loadGltf(accessorsDir() + "/sparse_float.gltf");
  EXPECT_TRUE(sp.warnings.empty()) << joined(sp.warnings);  // no normal was repaired
  EXPECT_EQ(sp.triangleCount(), 4u);
  expectSameVertices(sp, dense, 0.0f);
  // The second quad moved from x = 10 to beside the first: the bounds end near x = 1.08.
  EXPECT_LT(sp.bounds.extent().x, 2.1f);
  EXPECT_EQ(sp.vertices[1].uv, glm::vec2(2.0f, 1.0f));
}

// The corpus's base scene with a sparse part: vertex 1 at (2, 0, 0).
TEST(GltfLoaderAccessors, SparseVertexSubstituted) {
  const Scene s = loadGltf(malformedDir() + "/valid/sparse_accessor.gltf");
  ASSERT_EQ(s.vertices.size(), 4u);
  EXPECT_EQ(s.vertices[1].position + glm::vec3(s.origin), glm::vec3(2.0f, 0.0f, 0.0f));
  EXPECT_EQ(s.vertices[2].position + glm::vec3(s.origin), glm::vec3(1.0f, 1.0f, 0.0f));
}

// --- samplers (tests/data/samplers) ------------------------------------------------

TEST(GltfLoaderSamplers, WrapAndFilterAsTheFileStates) {
  const std::string dir = test::testDataDir() + "/samplers";
  const Scene s = loadGltf(dir + "/wrap_clamp_mirror_nearest.gltf");
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.wrapS, kWrapClampToEdge);
  EXPECT_EQ(t.wrapT, kWrapMirroredRepeat);
  EXPECT_EQ(t.magFilter, kFilterNearest);
  EXPECT_EQ(t.minFilter, kFilterNearest);
  EXPECT_TRUE(t.srgb);  // emissive: colour
  EXPECT_EQ(t.tableFlags(), 1u | 2u | (1u << 2) | (2u << 4));
  // Copies: a reference into a temporary Scene would dangle.
  const Texture linear = loadGltf(dir + "/wrap_repeat_clamp_linear.gltf").textures[0];
  EXPECT_EQ(linear.wrapS, kWrapRepeat);
  EXPECT_EQ(linear.wrapT, kWrapClampToEdge);
  EXPECT_EQ(linear.magFilter, kFilterLinear);
  EXPECT_EQ(linear.minFilter, kFilterLinear);
  // No sampler: repeat, bilinear, trilinear.
  const Texture d = loadGltf(dir + "/no_sampler.gltf").textures[0];
  EXPECT_EQ(d.wrapS, kWrapRepeat);
  EXPECT_EQ(d.wrapT, kWrapRepeat);
  EXPECT_EQ(d.magFilter, kFilterLinear);
  EXPECT_EQ(d.minFilter, kFilterLinearMipmapLinear);
  EXPECT_EQ(d.tableFlags(), 1u);
}

// --- texture coordinates (tests/data/texcoords) -------------------------------------

void expectNear(glm::vec2 got, glm::vec2 want, const char* what) {
  EXPECT_NEAR(got.x, want.x, 1e-6f) << what;
  EXPECT_NEAR(got.y, want.y, 1e-6f) << what;
}

// KHR_texture_transform's matrix, T * R * S with the extension's R (counter-clockwise
// in UV space: u' = cos u + sin v, v' = -sin u + cos v), worked by hand.
TEST(GltfLoaderTextureTransform, MatrixOfOffsetRotationScale) {
  const float quarter = kPi / 2.0f;
  expectNear(textureTransform({0.5f, 0.25f}, 0.0f, {1.0f, 1.0f}).apply({0.2f, 0.3f}), {0.7f, 0.55f},
             "offset");
  expectNear(textureTransform({0.0f, 0.0f}, quarter, {1.0f, 1.0f}).apply({1.0f, 0.0f}),
             {0.0f, -1.0f}, "rotation of u");
  expectNear(textureTransform({0.0f, 0.0f}, quarter, {1.0f, 1.0f}).apply({0.0f, 1.0f}),
             {1.0f, 0.0f}, "rotation of v");
  expectNear(textureTransform({0.0f, 0.0f}, 0.0f, {2.0f, 3.0f}).apply({1.0f, 1.0f}), {2.0f, 3.0f},
             "scale");
  // Scale first, then rotation, then offset: (0.25, 0.5) -> (0.5, 0.5) -> (0.5, -0.5)
  // -> (1.0, 0.5).
  expectNear(textureTransform({0.5f, 1.0f}, quarter, {2.0f, 1.0f}).apply({0.25f, 0.5f}),
             {1.0f, 0.5f}, "all three");
  // The sample's "All" quad: offset (-0.2, -0.1), rotation 0.3, scale 1.5.
  const float c = std::cos(0.3f), sn = std::sin(0.3f);
  expectNear(textureTransform({-0.2f, -0.1f}, 0.3f, {1.5f, 1.5f}).apply({1.0f, 0.0f}),
             {1.5f * c - 0.2f, -1.5f * sn - 0.1f}, "sample's All");
  const TextureTransform identity;
  EXPECT_EQ(textureTransform({0.0f, 0.0f}, 0.0f, {1.0f, 1.0f}), identity);
}

// tests/data/texcoords: the UVs a material's texture reads are baked into the
// vertices, through TEXCOORD_1 and the transform (make_texcoords.py's numbers).
TEST(GltfLoaderTextureTransform, BakedIntoTheVertexUvs) {
  const std::string dir = test::testDataDir() + "/texcoords";
  // Corners as the file lists them: the right coordinates (s, t), then transformed:
  // (t + 0.5, 1 - 2 s).
  const glm::vec2 right[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  const Scene t1 = loadGltf(dir + "/texcoord1.gltf");
  EXPECT_TRUE(t1.warnings.empty()) << joined(t1.warnings);
  ASSERT_EQ(t1.vertices.size(), 4u);
  EXPECT_EQ(t1.materials[0].emissiveUv.texCoord, 1);
  for (size_t i = 0; i < 4; ++i) expectNear(t1.vertices[i].uv, right[i], "TEXCOORD_1");
  for (const char* file : {"/transform.gltf", "/transform_texcoord1.gltf"}) {
    SCOPED_TRACE(file);
    const Scene s = loadGltf(dir + file);  // transform.gltf requires the extension
    EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
    ASSERT_EQ(s.vertices.size(), 4u);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.emissiveUv.texCoord, std::string(file) == "/transform.gltf" ? 0 : 1);
    EXPECT_EQ(m.uv, m.emissiveUv);
    for (size_t i = 0; i < 4; ++i)
      expectNear(s.vertices[i].uv, {right[i].y + 0.5f, 1.0f - 2.0f * right[i].x}, file);
  }
}

// A material whose textures read different coordinates: the base colour's into
// channel 0 (Vertex::uv), the other one into channel 1 (Vertex::uv2), no warning.
TEST(GltfLoaderTextureTransform, DifferingSlotsReadTheirOwnChannels) {
  const std::string dir = test::testDataDir() + "/texcoords";
  const glm::vec2 right[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  const glm::vec2 transformed[4] = {{1.5f, 1.0f}, {1.5f, -1.0f}, {0.5f, -1.0f}, {0.5f, 1.0f}};
  {
    SCOPED_TRACE("mixed_transforms.gltf: emissive transformed");
    const Scene s = loadGltf(dir + "/mixed_transforms.gltf");
    EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.uv, TextureTransform{});
    EXPECT_TRUE(m.hasUv2);
    EXPECT_EQ(m.uv2, m.emissiveUv);
    EXPECT_EQ(m.baseColorChannel, 0);
    EXPECT_EQ(m.emissiveChannel, 1);
    ASSERT_EQ(s.vertices.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      expectNear(s.vertices[i].uv, right[i], "base colour's UVs");
      expectNear(s.vertices[i].uv2, transformed[i], "emissive UVs");
    }
  }
  {
    SCOPED_TRACE("occlusion_texcoord1.gltf: occlusion on TEXCOORD_1");
    const Scene s = loadGltf(dir + "/occlusion_texcoord1.gltf");
    EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.uv.texCoord, 0);
    EXPECT_EQ(m.uv2.texCoord, 1);
    EXPECT_EQ(m.baseColorChannel, 0);
    EXPECT_EQ(m.emissiveChannel, 0);
    EXPECT_EQ(m.occlusionChannel, 1);
    ASSERT_EQ(s.vertices.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      expectNear(s.vertices[i].uv, right[i], "TEXCOORD_0");
      expectNear(s.vertices[i].uv2, glm::vec2(1.0f) - right[i], "TEXCOORD_1");
    }
  }
  {
    SCOPED_TRACE("normal_transform.gltf: the normal map transformed");
    const Scene s = loadGltf(dir + "/normal_transform.gltf");
    EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.normalChannel, 1);
    EXPECT_EQ(m.emissiveChannel, 0);
    EXPECT_EQ(m.uv2, m.normalUv);
    ASSERT_EQ(s.vertices.size(), 4u);
    ASSERT_EQ(s.tangents.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      expectNear(s.vertices[i].uv2, transformed[i], "normal texture's UVs");
      // The tangents follow the normal texture's u (t + 0.5: down the image, -y),
      // not channel 0's (+x).
      EXPECT_NEAR(s.tangents[i].x, 0.0f, 1e-5f);
      EXPECT_NEAR(s.tangents[i].y, -1.0f, 1e-5f);
    }
  }
  {
    // A material whose textures all share one mapping: channel 1 is channel 0.
    const Scene s = loadGltf(dir + "/texcoord1.gltf");
    EXPECT_FALSE(s.materials[0].hasUv2);
    for (const Vertex& v : s.vertices) EXPECT_EQ(v.uv2, v.uv);
  }
}

// A third distinct mapping: one warning, and that texture reads channel 0.
TEST(GltfLoaderTextureTransform, ThirdMappingWarnsOnceAndReadsChannelZero) {
  const Scene s = loadGltf(test::testDataDir() + "/texcoords/three_mappings.gltf");
  ASSERT_EQ(s.warnings.size(), 1u) << joined(s.warnings);
  EXPECT_NE(s.warnings[0].find("materials[0]: occlusionTexture reads a third set of texture "
                               "coordinates"),
            std::string::npos)
      << s.warnings[0];
  const Material& m = s.materials[0];
  EXPECT_EQ(m.baseColorChannel, 0);
  EXPECT_EQ(m.emissiveChannel, 1);
  EXPECT_EQ(m.occlusionChannel, 0);
  EXPECT_EQ(m.uv, TextureTransform{});
  EXPECT_EQ(m.uv2, m.emissiveUv);
}

// The Khronos samples load without a warning (texCoord, transform) and keep the
// file's transforms.
TEST(GltfLoaderTextureTransform, KhronosSamples) {
  const Scene tt = loadGltf(sample("texture_transform_test/TextureTransformTest.gltf"));
  EXPECT_TRUE(tt.warnings.empty()) << joined(tt.warnings);
  const auto named = [&](const char* name) -> const Material& {
    for (const Material& m : tt.materials)
      if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return tt.materials.back();
  };
  EXPECT_EQ(named("Offset UV").baseColorUv, textureTransform({0.5f, 0.5f}, 0.0f, {1.0f, 1.0f}));
  EXPECT_EQ(named("Rotation").baseColorUv,
            textureTransform({0.0f, 0.0f}, 0.39269908169872414f, {1.0f, 1.0f}));
  EXPECT_EQ(named("Scale").baseColorUv, textureTransform({0.0f, 0.0f}, 0.0f, {1.5f, 1.5f}));
  EXPECT_EQ(named("Correct").baseColorUv, TextureTransform{});
  const Scene tc = loadGltf(sample("texture_coordinate_test/TextureCoordinateTest.gltf"));
  EXPECT_TRUE(tc.warnings.empty()) << joined(tc.warnings);
}

class TexturedSampleTest : public ::testing::TestWithParam<const char*> {};

// The duck has a base-colour texture; the avocado a base-colour (sRGB) and a
// metallic-roughness texture (linear data): each decoded once.
TEST_P(TexturedSampleTest, OneDecodedBaseColourTexture) {
  const Scene s = loadGltf(sample(GetParam()));
  const bool avocado = std::string(GetParam()).find("avocado") != std::string::npos;
  ASSERT_EQ(s.textures.size(), avocado ? 3u : 1u);
  for (const Texture& t : s.textures) {
    EXPECT_GT(t.width, 0);
    EXPECT_GT(t.height, 0);
    EXPECT_EQ(t.rgba8.size(), static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * 4);
  }
  const Material& m = s.materials[0];
  ASSERT_EQ(m.baseColorTexture, 0);
  EXPECT_TRUE(s.textures[0].srgb);
  EXPECT_EQ(m.emissiveTexture, -1);
  if (avocado) {
    ASSERT_EQ(m.metallicRoughnessTexture, 1);
    EXPECT_FALSE(s.textures[1].srgb);
    // And a normal map (linear), with the file's tangents.
    ASSERT_EQ(m.normalTexture, 2);
    EXPECT_FALSE(s.textures[2].srgb);
    EXPECT_TRUE(s.hasNormalMaps());
    EXPECT_EQ(s.tangents.size(), s.vertices.size());
  } else {
    EXPECT_EQ(m.metallicRoughnessTexture, -1);
    EXPECT_EQ(m.normalTexture, -1);
    EXPECT_FALSE(s.hasNormalMaps());
  }
}

// tests/data/normal_maps (make_normal_maps.py): the normal texture and its scale,
// the file's TANGENT, and tangents generated where the file has none.
TEST(GltfLoaderNormalMaps, TangentsFromTheFile) {
  const Scene s = loadGltf(test::testDataDir() + "/normal_maps/tilted_quad.gltf");
  ASSERT_TRUE(s.hasNormalMaps());
  ASSERT_EQ(s.tangents.size(), s.vertices.size());
  const Material& m = s.materials[0];
  ASSERT_EQ(m.normalTexture, 0);
  EXPECT_FALSE(s.textures[0].srgb);
  EXPECT_EQ(m.normalScale, 1.0f);
  for (const glm::vec4& t : s.tangents) EXPECT_EQ(t, glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(loadGltf(test::testDataDir() + "/normal_maps/tilted_quad_scale.gltf")
                .materials[0]
                .normalScale,
            0.5f);
}

TEST(GltfLoaderNormalMaps, GeneratedTangentsMatchTheFile) {
  const Scene file = loadGltf(test::testDataDir() + "/normal_maps/tilted_quad.gltf");
  const Scene gen = loadGltf(test::testDataDir() + "/normal_maps/tilted_quad_generated.gltf");
  ASSERT_EQ(gen.tangents.size(), file.tangents.size());
  for (size_t i = 0; i < gen.tangents.size(); ++i)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(gen.tangents[i][k], file.tangents[i][k], 1e-6f);
  // Mirrored UVs: the tangent turns round and the handedness flips.
  const Scene mirrored = loadGltf(test::testDataDir() + "/normal_maps/mirrored_quad.gltf");
  ASSERT_EQ(mirrored.tangents.size(), 4u);
  for (const glm::vec4& t : mirrored.tangents) {
    EXPECT_NEAR(t.x, -1.0f, 1e-6f);
    EXPECT_NEAR(t.y, 0.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
    EXPECT_EQ(t.w, -1.0f);
  }
}

// The Khronos NormalTangentMirrorTest (scenes/normal_tangent_mirror_test): with its
// TANGENT removed, the generated tangents equal the file's (the handedness
// everywhere, the direction within a degree), mirrored UV islands included.
TEST(GltfLoaderNormalMaps, GeneratedTangentsMatchKhronosMirrorTest) {
  const std::filesystem::path dir =
      std::filesystem::path(test::samplesDir()) / "normal_tangent_mirror_test";
  const std::filesystem::path file = dir / "NormalTangentMirrorTest.gltf";
  // A copy without TANGENT beside copies of the buffer and images.
  const std::filesystem::path out = std::filesystem::path(test::scratchDir()) / "mirror_test";
  std::filesystem::create_directories(out);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    std::filesystem::copy_file(e.path(), out / e.path().filename(),
                               std::filesystem::copy_options::overwrite_existing);
  std::ifstream in(file);
  std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::regex tangent("\"TANGENT\"\\s*:\\s*[0-9]+\\s*,");
  ASSERT_TRUE(std::regex_search(json, tangent));
  std::ofstream(out / "no_tangents.gltf") << std::regex_replace(json, tangent, "");
  const Scene withFile = loadGltf(file.string());
  const Scene generated = loadGltf((out / "no_tangents.gltf").string());
  ASSERT_TRUE(withFile.hasNormalMaps());
  ASSERT_EQ(generated.tangents.size(), withFile.tangents.size());
  size_t sameHand = 0, within1 = 0;
  for (size_t i = 0; i < withFile.tangents.size(); ++i) {
    const glm::vec4 a = withFile.tangents[i], b = generated.tangents[i];
    sameHand += a.w == b.w;
    within1 += glm::dot(glm::vec3(a), glm::vec3(b)) > std::cos(glm::radians(1.0f));
  }
  std::printf("%zu tangents: %zu of the same handedness, %zu within 1 degree\n",
              withFile.tangents.size(), sameHand, within1);
  EXPECT_EQ(sameHand, withFile.tangents.size());
  EXPECT_EQ(within1, withFile.tangents.size());
}

// Scenes without normal maps carry no tangent stream.
TEST(GltfLoaderNormalMaps, NoneWithoutNormalTexture) {
  EXPECT_FALSE(loadGltf(darkPlane()).hasNormalMaps());
  EXPECT_FALSE(
      loadGltf(test::testDataDir() + "/vertex_colors/red_green_quad.gltf").hasNormalMaps());
}

INSTANTIATE_TEST_SUITE_P(
    Samples, TexturedSampleTest, ::testing::Values("duck/Duck.gltf", "avocado/Avocado.gltf"),
    [](const ::testing::TestParamInfo<const char*>& param) {
      return std::string(param.param).substr(0, std::string(param.param).find('/'));
    });

TEST(GltfLoaderSamples, TextureLimitRefusesLargerImages) {
  LoadOptions options;
  options.maxTextureSize = 8;
  const std::string path = sample("duck/Duck.gltf");
  try {
    loadGltf(path, options);
    FAIL() << "a texture larger than maxTextureSize was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_NE(problem(what, path).find("exceeds"), std::string::npos) << what;
  }
}

// --- auto-scale ----------------------------------------------------------------

// Box.gltf with its buffer embedded as a data: URI, under a new root node with the
// given uniform scale. Written to a scratch directory; returns the path.
std::string writeScaledBox(double scale) {
  const std::string source = sample("box/Box.gltf");
  nlohmann::json g = nlohmann::json::parse(readFile(source));
  for (auto& buffer : g["buffers"]) {
    const std::string bin = readFile(sample("box/" + buffer["uri"].get<std::string>()));
    EXPECT_EQ(bin.size(), buffer["byteLength"].get<size_t>());
    buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
  }
  const size_t scene = g.value("scene", size_t{0});
  const size_t root = g["nodes"].size();
  g["nodes"].push_back(
      {{"scale", {scale, scale, scale}}, {"children", g["scenes"][scene]["nodes"]}});
  g["scenes"][scene]["nodes"] = nlohmann::json::array({root});
  const std::string path = test::scratchDir() + "/box_scaled.gltf";
  writeFile(path, g.dump(1));
  return path;
}

void expectRelative(float actual, float expected, float tolerance, const char* what) {
  EXPECT_LE(std::abs(actual - expected), tolerance * std::abs(expected))
      << what << ": " << actual << " vs " << expected;
}

TEST(GltfLoaderAutoScale, EmbeddedCopyMatchesOriginal) {
  const Scene original = loadGltf(sample("box/Box.gltf"));
  const Scene copy = loadGltf(writeScaledBox(1.0));
  ASSERT_EQ(copy.triangleCount(), original.triangleCount());
  expectRelative(copy.scale.cameraSpeed, original.scale.cameraSpeed, 1e-6f, "cameraSpeed");
  expectRelative(copy.scale.gridSize, original.scale.gridSize, 1e-6f, "gridSize");
}

TEST(GltfLoaderAutoScale, ScalesWithTheScene) {
  const Scene box = loadGltf(sample("box/Box.gltf"));
  const Scene big = loadGltf(writeScaledBox(1000.0));
  ASSERT_EQ(big.triangleCount(), box.triangleCount());
  expectRelative(big.scale.cameraSpeed, 1000.0f * box.scale.cameraSpeed, 1e-4f, "cameraSpeed");
  expectRelative(big.scale.gridSize, 1000.0f * box.scale.gridSize, 1e-4f, "gridSize");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(big.scale.gridOrigin[k], 1000.0f * box.scale.gridOrigin[k],
                1e-4f * big.scale.gridSize);
    EXPECT_NEAR(big.bounds.min[k], 1000.0f * box.bounds.min[k], 1e-4f * big.scale.gridSize);
    EXPECT_NEAR(big.bounds.max[k], 1000.0f * box.bounds.max[k], 1e-4f * big.scale.gridSize);
    EXPECT_NEAR(big.camera.position[k], 1000.0f * box.camera.position[k],
                1e-4f * big.scale.gridSize);
  }
  expectRelative(big.camera.znear, 1000.0f * box.camera.znear, 1e-4f, "znear");
  expectRelative(big.camera.zfar, 1000.0f * box.camera.zfar, 1e-4f, "zfar");
}

// --- determinism -----------------------------------------------------------------

void expectSameScene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.indices.size(), b.indices.size());
  static_assert(sizeof(Vertex) == 10 * sizeof(float), "Vertex has padding; compare fields instead");
  EXPECT_EQ(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vertex)),
            0);
  EXPECT_EQ(a.indices, b.indices);
  ASSERT_EQ(a.draws.size(), b.draws.size());
  for (size_t i = 0; i < a.draws.size(); ++i) {
    EXPECT_EQ(a.draws[i].firstIndex, b.draws[i].firstIndex);
    EXPECT_EQ(a.draws[i].indexCount, b.draws[i].indexCount);
    EXPECT_EQ(a.draws[i].material, b.draws[i].material);
    EXPECT_EQ(a.draws[i].node, b.draws[i].node);
  }
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (size_t i = 0; i < a.textures.size(); ++i)
    EXPECT_EQ(a.textures[i].rgba8, b.textures[i].rgba8);
}

TEST(GltfLoaderDeterminism, CornellRoomTwice) {
  expectSameScene(loadGltf(test::cornellRoom()), loadGltf(test::cornellRoom()));
}

TEST(GltfLoaderDeterminism, DuckTwice) {
  expectSameScene(loadGltf(sample("duck/Duck.gltf")), loadGltf(sample("duck/Duck.gltf")));
}

// --- paths that are not glTF files ----------------------------------------------------

// Loads `path`, which must fail; returns what() (empty after a failure is recorded).
std::string loadError(const std::string& path) {
  try {
    loadGltf(path);
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": threw a non-voxgi exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << path << ": loaded without an error";
  return "";
}

void expectOneLineNamingFile(const std::string& what, const std::string& path) {
  EXPECT_EQ(what.find('\n'), std::string::npos) << shown(what);
  EXPECT_EQ(what.find('\r'), std::string::npos) << shown(what);
  EXPECT_EQ(what.rfind(path + ": ", 0), 0u)
      << "does not start with '" << path << ": ': " << shown(what);
  EXPECT_GT(what.size(), path.size() + 2) << "no problem named: " << what;
}

TEST(GltfLoaderPaths, MissingFile) {
  const std::string path = test::scratchDir() + "/does_not_exist.gltf";
  const std::string what = loadError(path);
  expectOneLineNamingFile(what, path);
  EXPECT_NE(problem(what, path).find("no such file"), std::string::npos) << what;
}

TEST(GltfLoaderPaths, Directory) {
  const std::string dir = test::scratchDir();
  expectOneLineNamingFile(loadError(dir), dir);
  // Even when the directory is named like a glTF file.
  const std::string named = dir + "/folder.gltf";
  fs::create_directories(named);
  const std::string what = loadError(named);
  expectOneLineNamingFile(what, named);
  EXPECT_NE(problem(what, named).find("directory"), std::string::npos) << what;
}

TEST(GltfLoaderPaths, UnknownExtension) {
  const std::string path = test::scratchDir() + "/scene.obj";
  writeFile(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string what = loadError(path);
  expectOneLineNamingFile(what, path);
  EXPECT_NE(problem(what, path).find(".obj"), std::string::npos) << what;
}

// --- the malformed corpus --------------------------------------------------------

bool isGltfName(const fs::path& p) {
  return p.extension() == ".gltf" || p.extension() == ".glb";
}

std::vector<std::string> corpusFiles() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(malformedDir(), ec))
    if (entry.is_regular_file() && isGltfName(entry.path()))
      names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// expected.txt: "filename<TAB>expected substring" per line.
std::map<std::string, std::string> expectedMessages() {
  std::map<std::string, std::string> out;
  std::istringstream in(readFile(malformedDir() + "/expected.txt"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const size_t tab = line.find('\t');
    EXPECT_NE(tab, std::string::npos) << "expected.txt: no tab in '" << line << "'";
    if (tab == std::string::npos) continue;
    const std::string name = line.substr(0, tab);
    EXPECT_EQ(out.count(name), 0u) << "expected.txt lists " << name << " twice";
    out[name] = line.substr(tab + 1);
    EXPECT_FALSE(out[name].empty()) << "expected.txt: empty expectation for " << name;
  }
  return out;
}

TEST(GltfLoaderCorpus, EveryFileListedAndEveryListingPresent) {
  const std::vector<std::string> files = corpusFiles();
  const std::map<std::string, std::string> expected = expectedMessages();
  EXPECT_GE(files.size(), 20u);
  for (const auto& f : files)
    EXPECT_EQ(expected.count(f), 1u) << f << " is not listed in expected.txt";
  for (const auto& [name, substring] : expected)
    EXPECT_TRUE(std::find(files.begin(), files.end(), name) != files.end())
        << "expected.txt lists " << name << ", which is not in " << malformedDir();
}

// The scenes the corpus files are edited from load cleanly, so each file's defect is
// what gets it refused.
TEST(GltfLoaderCorpus, ValidBaseScenesLoad) {
  const std::string dir = malformedDir() + "/valid";
  const std::map<std::string, size_t> triangles = {{"quad.gltf", 2},
                                                   {"quad_normals.gltf", 2},
                                                   {"triangle.gltf", 1},
                                                   {"textured.gltf", 2},
                                                   {"quad.glb", 2},
                                                   {"no_scenes.gltf", 6},
                                                   {"unread_texture_points_nowhere.gltf", 2},
                                                   {"sparse_accessor.gltf", 2}};
  for (const auto& [name, count] : triangles) {
    SCOPED_TRACE(name);
    const Scene s = loadGltf(dir + "/" + name);
    EXPECT_EQ(s.triangleCount(), count);
    EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
    expectWellFormed(s);
    if (name == "textured.gltf") {
      ASSERT_EQ(s.textures.size(), 1u);
      EXPECT_EQ(s.textures[0].width, 2);
      EXPECT_EQ(s.textures[0].height, 2);
      ASSERT_EQ(s.textures[0].rgba8.size(), 16u);
      EXPECT_EQ(s.textures[0].rgba8[0], 255);  // red first pixel
      EXPECT_EQ(s.textures[0].rgba8[1], 0);
    }
  }
}

// A file without scenes is valid glTF: every root node is drawn (two here, one with
// a child: three quads), and one line says so.
TEST(GltfLoaderCorpus, NoScenesDrawsEveryRootNode) {
  const Scene s = loadGltf(malformedDir() + "/valid/no_scenes.gltf");
  EXPECT_EQ(s.triangleCount(), 6u);
  EXPECT_EQ(s.draws.size(), 3u);
  ASSERT_EQ(s.notes.size(), 1u) << joined(s.notes);
  EXPECT_NE(s.notes[0].find("no scenes: rendering all 2 root nodes"), std::string::npos)
      << s.notes[0];
  EXPECT_EQ(s.notes[0].find('\n'), std::string::npos);
  // A file with scenes says nothing of the kind.
  EXPECT_TRUE(loadGltf(malformedDir() + "/valid/quad.gltf").notes.empty());
}

// Loads `path` in a forked child (stderr to /dev/null, its stack held to the
// default 8 MB whatever the shell allows, killed after `seconds`) and returns how
// it ended: "" when it returned or threw voxgi::Error (with `mustLoad`, only when it
// returned), else what went wrong ("killed by signal 11"). A plain fork, not a
// gtest death test: "threadsafe" death tests re-execute the whole binary for every
// file.
std::string crashInChild(const std::string& path, bool mustLoad = false, unsigned seconds = 30) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return "";  // no child to be had: skip the guard
  if (pid == 0) {
    alarm(seconds);
    constexpr rlim_t kDefaultStack = 8u << 20;
    rlimit stack{};
    if (getrlimit(RLIMIT_STACK, &stack) == 0 && stack.rlim_cur > kDefaultStack) {
      stack.rlim_cur = kDefaultStack;  // RLIM_INFINITY is the largest value
      setrlimit(RLIMIT_STACK, &stack);
    }
    const int devNull = open("/dev/null", O_WRONLY);
    if (devNull >= 0) dup2(devNull, 2);
    try {
      loadGltf(path);
    } catch (const Error&) {
      if (mustLoad) std::_Exit(4);
    } catch (...) {
      std::_Exit(3);
    }
    std::_Exit(0);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return "waitpid failed";
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return "killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 3)
    return "threw something other than voxgi::Error";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 4) return "refused it (voxgi::Error)";
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return "exited with status " + std::to_string(status);
  return "";
}

class MalformedTest : public ::testing::TestWithParam<std::string> {};
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(MalformedTest);

TEST_P(MalformedTest, RefusedWithOneLineNamingFileAndProblem) {
  const std::string name = GetParam();
  const std::map<std::string, std::string> expected = expectedMessages();
  const auto it = expected.find(name);
  ASSERT_NE(it, expected.end()) << name << " is not listed in expected.txt";
  const std::string path = malformedDir() + "/" + name;
  // First in a child, so that a file that crashes the loader fails this test
  // instead of taking the whole run down.
  const std::string crash = crashInChild(path);
  ASSERT_EQ(crash, "") << path << ": the loader crashed instead of throwing voxgi::Error";
  const std::string what = loadError(path);
  if (what.empty()) return;  // failure already recorded
  expectOneLineNamingFile(what, path);
  EXPECT_NE(problem(what, path).find(it->second), std::string::npos)
      << "expected the message to contain '" << it->second << "'\n  got: " << shown(what);
  // One line a person can read: no data: URIs or other blobs pasted in.
  EXPECT_LE(what.size(), path.size() + 400) << shown(what);
}

INSTANTIATE_TEST_SUITE_P(Corpus, MalformedTest, ::testing::ValuesIn(corpusFiles()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string n = param.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// --- deep hierarchies ---------------------------------------------------------------

// A node hierarchy tens of thousands of levels deep is valid glTF, and small: it
// loads, poses and renders. The files are written at run time (a 50,000-level
// chain is some 3 MB of JSON), each level translated by binary fractions whose sums
// are exact.
constexpr int kDeepChain = 50000;
const glm::dvec3 kDeepStep(1.0 / 1024.0, -1.0 / 2048.0, 0.0);

// The chain's one triangle, (0, 0, 0), (1, 0, 0), (0, 1, 0), lies moved by `offset`.
void expectTriangleAt(const Scene& s, const glm::dvec3& offset) {
  ASSERT_EQ(s.triangleCount(), 1u);
  glm::dvec3 lo(1e30), hi(-1e30);
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 p =
        glm::dvec3(s.vertices[s.indices[static_cast<size_t>(k)]].position) + s.origin;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(lo[a], offset[a], 1e-6) << "axis " << a;
    EXPECT_NEAR(hi[a], offset[a] + (a < 2 ? 1.0 : 0.0), 1e-6) << "axis " << a;
  }
}

// Loaded first in a child held to the default 8 MB stack (crashInChild): a walk
// that recursed once per level would overflow it.
TEST(GltfLoaderDeep, ChainOf50000LevelsLoadsWithItsComposedTransform) {
  const std::string path = test::writeDeepChainGltf("deep_chain.gltf", kDeepChain, kDeepStep);
  ASSERT_EQ(crashInChild(path, true), "") << path;
  const Scene s = loadGltf(path);
  EXPECT_TRUE(s.warnings.empty()) << joined(s.warnings);
  EXPECT_EQ(s.nodes.size(), static_cast<size_t>(kDeepChain));
  EXPECT_FALSE(s.animated());
  expectTriangleAt(s, static_cast<double>(kDeepChain) * kDeepStep);
}

// The root's channel moves the triangle at the chain's far end: pose() composes
// all 50,000 levels.
TEST(GltfLoaderDeep, AnimatedChainPosesItsDeepestNode) {
  const std::string path =
      test::writeDeepChainGltf("deep_chain_animated.gltf", kDeepChain, kDeepStep, true);
  ASSERT_EQ(crashInChild(path, true), "") << path;
  Scene s = loadGltf(path);
  ASSERT_TRUE(s.meshesAnimated());
  const glm::dvec3 rest = static_cast<double>(kDeepChain) * kDeepStep;
  expectTriangleAt(s, rest);  // loaded at t = 0
  for (double t : {0.25, 0.75, 0.5}) {
    SCOPED_TRACE(testing::Message() << "t = " << t);
    s.pose(t);
    expectTriangleAt(s, rest + glm::dvec3(t, 0.0, 0.0));
  }
  // The bounds cover the motion: the triangle's x from rest.x on.
  EXPECT_LE(s.motionBounds.min.x + s.origin.x, rest.x + 1e-5);
  EXPECT_GE(s.motionBounds.max.x + s.origin.x, rest.x + 1.75);
}

// Walking each node up to its root (to find cycles, or what an animation moves)
// would make the load quadratic in the depth: some 10^10 steps for 200,000 levels,
// minutes. Each node visited once, it takes a few seconds (a sanitizer build some
// more); the child's 60 s alarm is the bound.
TEST(GltfLoaderDeep, ChainOf200000LevelsLoadsInLinearTime) {
  const std::string path = test::writeDeepChainGltf("deeper_chain.gltf", 200000, glm::dvec3(0.0));
  EXPECT_EQ(crashInChild(path, true, 60), "") << path;
}

// --- loading from memory (the fuzzer's entry point) -------------------------------

// What loadGltfFromMemory says about `bytes` named `name`: "" when it loads.
std::string memoryError(const std::string& bytes, const std::string& name) {
  try {
    loadGltfFromMemory(bytes.data(), bytes.size(), name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Every corpus file is refused from memory exactly as from its file, so fuzzing the
// memory path fuzzes what `voxgi render` runs. Files with external URIs are the
// exception: from memory those are refused for the reference itself.
TEST(GltfLoaderMemory, CorpusRefusedAsFromFile) {
  for (const std::string& name : corpusFiles()) {
    SCOPED_TRACE(name);
    const std::string path = malformedDir() + "/" + name;
    const std::string bytes = readFile(path);
    const std::string fromFile = problem(loadError(path), path);
    const std::string fromMemory = memoryError(bytes, name);
    ASSERT_EQ(fromMemory.rfind(name + ": ", 0), 0u) << fromMemory;
    const bool external = bytes.find("\"uri\": \"missing") != std::string::npos;
    if (!external) {
      EXPECT_EQ(problem(fromMemory, name), fromFile);
    }
  }
}

TEST(GltfLoaderMemory, ValidScenesLoadAsFromFile) {
  for (const char* name : {"quad.gltf", "quad_normals.gltf", "textured.gltf", "quad.glb"}) {
    SCOPED_TRACE(name);
    const std::string path = malformedDir() + "/valid/" + name;
    const std::string bytes = readFile(path);
    const Scene a = loadGltf(path);
    const Scene b = loadGltfFromMemory(bytes.data(), bytes.size(), name);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    for (size_t i = 0; i < a.vertices.size(); ++i)
      EXPECT_EQ(a.vertices[i].position, b.vertices[i].position);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.textures.size(), b.textures.size());
  }
}

// From memory, no file is opened: an external buffer is refused by name.
TEST(GltfLoaderMemory, ExternalFilesNotRead) {
  const std::string bytes = readFile(malformedDir() + "/missing_bin.gltf");
  const std::string what = memoryError(bytes, "scene.gltf");
  EXPECT_NE(what.find("missing_buffer.bin"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

}  // namespace
}  // namespace voxgi::scene

// The binding registry (shaders/include/bindings_shared.h) against the shaders that
// use it: within one program, no two names of one kind share a number, and image
// units stay within what every GL 4.5 driver has.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bindings_shared.h"
#include "support/test_paths.h"

namespace voxgi::gpu {
namespace {

namespace fs = std::filesystem;

enum class Kind { UniformBlock, Ssbo, Texture, Image };

const char* kindName(Kind k) {
  switch (k) {
    case Kind::UniformBlock:
      return "uniform block";
    case Kind::Ssbo:
      return "SSBO";
    case Kind::Texture:
      return "texture unit";
    case Kind::Image:
      return "image unit";
  }
  return "?";
}

struct Entry {
  Kind kind;
  uint number;
};

#define VOXGI_ENTRY(kind, name) \
  {                             \
#name, {                    \
      Kind::kind, name          \
    }                           \
  }

// Every name bindings_shared.h declares, with its kind (the test below checks the
// header declares no other).
const std::map<std::string, Entry>& registry() {
  static const std::map<std::string, Entry> r = {
      VOXGI_ENTRY(UniformBlock, kFrameBinding),
      VOXGI_ENTRY(UniformBlock, kVoxelParamsBinding),
      VOXGI_ENTRY(UniformBlock, kPtParamsBinding),
      VOXGI_ENTRY(UniformBlock, kOctreeParamsBinding),
      VOXGI_ENTRY(UniformBlock, kRtgiParamsBinding),
      VOXGI_ENTRY(UniformBlock, kUpsampleParamsBinding),
      VOXGI_ENTRY(Ssbo, kMaterialBinding),
      VOXGI_ENTRY(Ssbo, kLightBinding),
      VOXGI_ENTRY(Ssbo, kEmitterBinding),
      VOXGI_ENTRY(Ssbo, kLightTreeBinding),
      VOXGI_ENTRY(Ssbo, kNonfiniteCountBinding),
      VOXGI_ENTRY(Ssbo, kRtgiReservoirBinding),
      VOXGI_ENTRY(Ssbo, kRtgiCausticBinding),
      VOXGI_ENTRY(Ssbo, kRtgiCausticTargetBinding),
      VOXGI_ENTRY(Ssbo, kVoxelStatsBinding),
      VOXGI_ENTRY(Ssbo, kVoxelListBinding),
      VOXGI_ENTRY(Ssbo, kBrickMapBinding),
      VOXGI_ENTRY(Ssbo, kSlotSumsABinding),
      VOXGI_ENTRY(Ssbo, kSlotSumsNBinding),
      VOXGI_ENTRY(Ssbo, kSlotSumsEBinding),
      VOXGI_ENTRY(Ssbo, kBrickPoolBinding),
      VOXGI_ENTRY(Ssbo, kVoxelAttribBinding),
      VOXGI_ENTRY(Ssbo, kLargeIndexBinding),
      VOXGI_ENTRY(Ssbo, kDrawCommandBinding),
      VOXGI_ENTRY(Ssbo, kVoxelDeferredBinding),
      VOXGI_ENTRY(Ssbo, kOctreeNodeBinding),
      VOXGI_ENTRY(Ssbo, kOctreeRadianceBinding),
      VOXGI_ENTRY(Ssbo, kOctreeMaterialBinding),
      VOXGI_ENTRY(Ssbo, kOctreeEmissionBinding),
      VOXGI_ENTRY(Ssbo, kOctreeCounterBinding),
      VOXGI_ENTRY(Ssbo, kOctreeSurfaceBinding),
      VOXGI_ENTRY(Ssbo, kOctreeScratchBinding),
      VOXGI_ENTRY(Ssbo, kOctreeLightCdfBinding),
      VOXGI_ENTRY(Ssbo, kOctreeDirectBinding),
      VOXGI_ENTRY(Ssbo, kOctreeRayBinding),
      VOXGI_ENTRY(Ssbo, kOctreeRayHitBinding),
      VOXGI_ENTRY(Ssbo, kOctreeReplayBinding),
      VOXGI_ENTRY(Ssbo, kOctreeMeanBinding),
      VOXGI_ENTRY(Ssbo, kOctreeBounceBinding),
      VOXGI_ENTRY(Ssbo, kPixelListBinding),
      VOXGI_ENTRY(Ssbo, kMaskHistogramBinding),
      VOXGI_ENTRY(Ssbo, kSpecularListBinding),
      VOXGI_ENTRY(Ssbo, kRtgiBvhIndexBinding),
      VOXGI_ENTRY(Ssbo, kRtgiBvhTextureBinding),
      VOXGI_ENTRY(Ssbo, kRtgiBvhColorBinding),
      VOXGI_ENTRY(Ssbo, kRtgiBvhTangentBinding),
      VOXGI_ENTRY(Ssbo, kPtIndexBinding),
      VOXGI_ENTRY(Ssbo, kPtEmissiveBinding),
      VOXGI_ENTRY(Ssbo, kPtCounterBinding),
      VOXGI_ENTRY(Ssbo, kPtTextureBinding),
      VOXGI_ENTRY(Ssbo, kPtColorBinding),
      VOXGI_ENTRY(Ssbo, kPtTangentBinding),
      VOXGI_ENTRY(Texture, kBaseColorUnit),
      VOXGI_ENTRY(Texture, kEmissiveUnit),
      VOXGI_ENTRY(Texture, kMetallicRoughnessUnit),
      VOXGI_ENTRY(Texture, kNormalUnit),
      VOXGI_ENTRY(Texture, kOcclusionUnit),
      VOXGI_ENTRY(Texture, kHdrInputUnit),
      VOXGI_ENTRY(Texture, kVoxelVertexUnit),
      VOXGI_ENTRY(Texture, kVoxelIndexUnit),
      VOXGI_ENTRY(Texture, kVoxelColorUnit),
      VOXGI_ENTRY(Texture, kOctreeNodeTexUnit),
      VOXGI_ENTRY(Texture, kPtNodeTexUnit),
      VOXGI_ENTRY(Texture, kPtTriangleTexUnit),
      VOXGI_ENTRY(Texture, kPtVertexTexUnit),
      VOXGI_ENTRY(Texture, kPtTexelTexUnit),
      VOXGI_ENTRY(Texture, kRtgiBvhNodeUnit),
      VOXGI_ENTRY(Texture, kRtgiBvhTriangleUnit),
      VOXGI_ENTRY(Texture, kRtgiBvhVertexUnit),
      VOXGI_ENTRY(Texture, kRtgiBvhTexelUnit),
      VOXGI_ENTRY(Texture, kGPositionUnit),
      VOXGI_ENTRY(Texture, kGNormalUnit),
      VOXGI_ENTRY(Texture, kGAlbedoUnit),
      VOXGI_ENTRY(Texture, kGEmissionUnit),
      VOXGI_ENTRY(Texture, kHistoryUnit),
      VOXGI_ENTRY(Texture, kGPreviousPositionUnit),
      VOXGI_ENTRY(Texture, kGPreviousNormalUnit),
      VOXGI_ENTRY(Texture, kGMotionUnit),
      VOXGI_ENTRY(Texture, kHistoryMomentsUnit),
      VOXGI_ENTRY(Texture, kHistoryDirectUnit),
      VOXGI_ENTRY(Texture, kReprojectedMomentsUnit),
      VOXGI_ENTRY(Texture, kReprojectedDirectUnit),
      VOXGI_ENTRY(Texture, kUpsampleHistoryUnit),
      VOXGI_ENTRY(Texture, kUpsampleShownUnit),
      VOXGI_ENTRY(Image, kGbufferPositionImage),
      VOXGI_ENTRY(Image, kGbufferNormalImage),
      VOXGI_ENTRY(Image, kGbufferAlbedoImage),
      VOXGI_ENTRY(Image, kGbufferEmissionImage),
      VOXGI_ENTRY(Image, kGbufferMotionImage),
      VOXGI_ENTRY(Image, kDirectImage),
      VOXGI_ENTRY(Image, kIndirectImage),
      VOXGI_ENTRY(Image, kSpecularImage),
      VOXGI_ENTRY(Image, kAccumImage),
      VOXGI_ENTRY(Image, kEdgeImage),
      VOXGI_ENTRY(Image, kMaskImage),
      VOXGI_ENTRY(Image, kTracedImage),
      VOXGI_ENTRY(Image, kMaskKeyImage),
      VOXGI_ENTRY(Image, kReprojectedImage),
      VOXGI_ENTRY(Image, kMomentsImage),
      VOXGI_ENTRY(Image, kDirectMeanImage),
      VOXGI_ENTRY(Image, kReprojectedMomentsImage),
      VOXGI_ENTRY(Image, kReprojectedDirectImage),
      VOXGI_ENTRY(Image, kDenoiseInImage),
      VOXGI_ENTRY(Image, kDenoiseOutImage),
      VOXGI_ENTRY(Image, kDenoiseKeyImage),
      VOXGI_ENTRY(Image, kDenoisedImage),
      VOXGI_ENTRY(Image, kUpsampleHistoryImage),
      VOXGI_ENTRY(Image, kPtSumImage),
      VOXGI_ENTRY(Image, kPtCompensationImage),
      VOXGI_ENTRY(Image, kPtOutputImage),
  };
  return r;
}

#undef VOXGI_ENTRY

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text without // and /* */ comments.
std::string stripComments(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 2, "//") == 0) {
      while (i < text.size() && text[i] != '\n') ++i;
      out += '\n';
    } else if (text.compare(i, 2, "/*") == 0) {
      const size_t end = text.find("*/", i + 2);
      i = end == std::string::npos ? text.size() : end + 1;
    } else {
      out += text[i];
    }
  }
  return out;
}

fs::path shaderRoot() {
  return fs::path(test::sourceDir()) / "shaders";
}

// The shader's text with its includes (as gl/program_cache.cpp resolves them: next
// to the including file, then shaders/include), comments removed. The registry
// itself is left out: it names everything.
void expand(const fs::path& file, std::set<fs::path>* seen, std::string* out) {
  if (!seen->insert(fs::weakly_canonical(file)).second) return;
  static const std::regex includeRe(R"(^\s*#\s*include\s+"([^"]+)\")");
  std::istringstream in(stripComments(readText(file)));
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, includeRe)) {
      const std::string name = m[1].str();
      if (name == "bindings_shared.h") continue;
      fs::path inc = file.parent_path() / name;
      if (!fs::exists(inc)) inc = shaderRoot() / "include" / name;
      ASSERT_TRUE(fs::exists(inc)) << file << ": " << name;
      expand(inc, seen, out);
      continue;
    }
    *out += line;
    *out += '\n';
  }
}

// The registry's names a program's shaders mention.
std::set<std::string> namesUsed(const std::vector<std::string>& files) {
  std::string text;
  std::set<fs::path> seen;
  for (const std::string& f : files) expand(shaderRoot() / f, &seen, &text);
  std::set<std::string> used;
  static const std::regex identRe(R"(\bk[A-Za-z0-9_]+\b)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), identRe);
       it != std::sregex_iterator(); ++it)
    if (registry().count(it->str())) used.insert(it->str());
  return used;
}

// Every program the renderer links: each compute shader alone, and the stages the
// host links together (src/*/*_pass.cpp).
std::vector<std::vector<std::string>> programs() {
  std::vector<std::vector<std::string>> p = {
      {"voxel/voxelize.vert", "voxel/voxelize.geom", "voxel/voxelize.frag"},
      {"render/voxel_points.vert", "render/voxel_points.frag"},
      {"render/fullscreen.vert", "render/tonemap.frag"},
      {"render/raster.vert", "render/raster.frag"},
      {"render/raster.vert", "render/gbuffer.frag"},
  };
  std::set<std::string> linked;
  for (const auto& program : p) linked.insert(program.begin(), program.end());
  for (const char* dir : {"render", "voxel"})
    for (const auto& e : fs::recursive_directory_iterator(shaderRoot() / dir)) {
      if (!e.is_regular_file()) continue;
      const std::string name = fs::relative(e.path(), shaderRoot()).generic_string();
      if (e.path().extension() == ".comp") {
        p.push_back({name});
      } else {
        EXPECT_TRUE(linked.count(name)) << name << " is in no program this test checks";
      }
    }
  return p;
}

TEST(Bindings, RegistryListsEveryNameTheHeaderDeclares) {
  const std::string text = stripComments(readText(shaderRoot() / "include" / "bindings_shared.h"));
  static const std::regex declRe(R"(VOXGI_CONST\s+uint\s+(k\w+)\s*=\s*(\d+)u\s*;)");
  std::set<std::string> declared;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), declRe);
       it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1].str();
    if (name == "kMinImageUnits" || name.starts_with("kRequired")) continue;
    declared.insert(name);
    ASSERT_TRUE(registry().count(name)) << name << " has no kind in this test's registry";
    EXPECT_EQ(registry().at(name).number, static_cast<uint>(std::stoul((*it)[2].str()))) << name;
  }
  EXPECT_EQ(declared.size(), registry().size());
}

TEST(Bindings, NoProgramReadsTwoNamesOfOneKindOnOneNumber) {
  for (const auto& files : programs()) {
    std::map<std::pair<Kind, uint>, std::string> taken;
    for (const std::string& name : namesUsed(files)) {
      const Entry& e = registry().at(name);
      const auto [it, fresh] = taken.emplace(std::make_pair(e.kind, e.number), name);
      EXPECT_TRUE(fresh) << files.back() << ": " << name << " and " << it->second << " are both "
                         << kindName(e.kind) << " " << e.number;
    }
  }
}

TEST(Bindings, EveryNameIsReadBySomeProgram) {
  std::set<std::string> used;
  for (const auto& files : programs()) {
    const std::set<std::string> u = namesUsed(files);
    used.insert(u.begin(), u.end());
  }
  for (const auto& [name, entry] : registry()) EXPECT_TRUE(used.count(name)) << name;
}

// The SSBO needs bindings_shared.h states (and the context checks against the
// driver) are what the shaders use: the highest binding + 1, and the most SSBOs in
// one compute program and in one program with a fragment shader.
TEST(Bindings, SsboNeedsAreWhatTheShadersUse) {
  uint bindings = 0, compute = 0, fragment = 0;
  for (const auto& files : programs()) {
    uint count = 0;
    for (const std::string& name : namesUsed(files)) {
      const Entry& e = registry().at(name);
      if (e.kind != Kind::Ssbo) continue;
      ++count;
      bindings = std::max(bindings, e.number + 1);
    }
    const bool isCompute = files.size() == 1 && files[0].ends_with(".comp");
    (isCompute ? compute : fragment) = std::max(isCompute ? compute : fragment, count);
  }
  EXPECT_EQ(bindings, kRequiredSsboBindings);
  EXPECT_EQ(compute, kRequiredComputeSsboBlocks);
  EXPECT_EQ(fragment, kRequiredFragmentSsboBlocks);
}

TEST(Bindings, ImageUnitsAreWithinTheMinimumEveryDriverHas) {
  for (const auto& [name, entry] : registry()) {
    if (entry.kind != Kind::Image) continue;
    EXPECT_LT(entry.number, kMinImageUnits) << name;
  }
}

}  // namespace
}  // namespace voxgi::gpu

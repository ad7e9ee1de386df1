// Voxelization on llvmpipe: exact counts, order independence, agreement with a
// CPU triangle-box reference, watertightness, fixed-point precision, invariance to
// where the scene sits and how big it is.
#include "voxel/voxelize_pass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "core/log.h"
#include "scene/gltf_loader.h"
#include "support/cpu_voxelizer.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

struct Voxelized {
  voxel::VoxelGridStats stats;
  std::vector<uint8_t> albedo;  // RGBA8
  std::vector<uint8_t> occupied;
};

Voxelized voxelize(const scene::Scene& s, int n, bool readBack = true) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  scene::GpuScene gs(s);
  gl::FrameContext ctx{programs, timer, n, n, 0};
  voxel::VoxelizePass pass(programs, "llvmpipe", {n, false});
  pass.execute(ctx, gs);
  timer.resolve();
  Voxelized out;
  out.stats = pass.stats();
  if (readBack) {
    out.albedo = pass.readAlbedo();
    out.occupied = occupancyFromAlbedo(out.albedo);
  }
  return out;
}

size_t countSet(const std::vector<uint8_t>& v) {
  return static_cast<size_t>(std::count(v.begin(), v.end(), 1));
}

class VoxelizeTest : public GlTest {};

// A box whose faces lie in the middle of voxel layers: every face covers whole
// voxels, so the surface is exactly the shell of a 21 x 11 x 31 block.
TEST_F(VoxelizeTest, AxisAlignedBoxGivesExactCount) {
  SceneBuilder b;
  b.addBox({10.5f, 10.5f, 10.5f}, {30.5f, 20.5f, 40.5f}, b.addMaterial(glm::vec3(0.5f)));
  scene::Scene s = b.finish();
  s.scale.gridOrigin = glm::vec3(0.0f);
  s.scale.gridSize = 64.0f;  // one unit per voxel
  const Voxelized v = voxelize(s, 64);
  const uint32_t shell = 21 * 11 * 31 - 19 * 9 * 29;
  EXPECT_EQ(v.stats.occupied, shell);
  EXPECT_EQ(countSet(v.occupied), shell);
  EXPECT_EQ(countSet(cpuVoxelize(s, 64)), shell);  // the reference agrees
}

// The same triangles in other orders: shuffled within each primitive (corners
// rotated too) with the primitives shuffled, or split in two.
scene::Scene shuffledCopy(const scene::Scene& original, unsigned seed) {
  scene::Scene shuffled = original;
  std::mt19937 rng(seed);
  for (const scene::Draw& d : shuffled.draws) {
    std::vector<std::array<uint32_t, 3>> tris;
    for (uint32_t i = d.firstIndex; i < d.firstIndex + d.indexCount; i += 3)
      tris.push_back({shuffled.indices[i], shuffled.indices[i + 1], shuffled.indices[i + 2]});
    std::shuffle(tris.begin(), tris.end(), rng);
    for (size_t t = 0; t < tris.size(); ++t) {
      const size_t r = t % 3;  // rotate the corners too; the winding stays the same
      for (size_t k = 0; k < 3; ++k)
        shuffled.indices[d.firstIndex + t * 3 + k] = tris[t][(k + r) % 3];
    }
  }
  std::shuffle(shuffled.draws.begin(), shuffled.draws.end(), rng);
  return shuffled;
}

scene::Scene splitCopy(const scene::Scene& original) {
  scene::Scene split = original;
  split.draws.clear();
  for (const scene::Draw& d : original.draws) {
    const uint32_t half = d.indexCount / 6 * 3;
    scene::Draw first = d, second = d;
    first.indexCount = half;
    second.firstIndex = d.firstIndex + half;
    second.indexCount = d.indexCount - half;
    if (first.indexCount) split.draws.push_back(first);
    split.draws.push_back(second);
  }
  return split;
}

// Voxelizes with one program cache (the shaders compile once), each time afresh.
class Voxelizer {
 public:
  Voxelized run(const scene::Scene& s, voxel::VoxelizePass::Settings settings, bool readBack) {
    gl::StageTimer timer;
    scene::GpuScene gs(s);
    gl::FrameContext ctx{programs_, timer, settings.resolution, settings.resolution, 0};
    voxel::VoxelizePass pass(programs_, "llvmpipe", settings);
    pass.execute(ctx, gs);
    timer.resolve();
    Voxelized out;
    out.stats = pass.stats();
    if (readBack) out.albedo = pass.readAlbedo();
    return out;
  }

 private:
  gl::ProgramCache programs_{sourceDir() + "/shaders"};
};

// Shuffled triangles, rotated corners and differently split primitives give a
// bit-identical grid, run after run: the integer sums do not care about order. Five
// orders, each voxelized 8 times at 128^3 (a race that lost a fragment 2 times in
// 10 runs of one shuffled order went unseen by a single run of each).
TEST_F(VoxelizeTest, OrderAndSplitDoNotChangeTheGrid) {
  const scene::Scene original = scene::loadGltf(cornellRoom());
  const std::vector<scene::Scene> orders = {original, shuffledCopy(original, 7),
                                            shuffledCopy(original, 8), shuffledCopy(original, 9),
                                            splitCopy(original)};
  Voxelizer voxelizer;
  const Voxelized first = voxelizer.run(original, {128, false}, true);
  ASSERT_GT(first.stats.occupied, 0u);
  for (size_t o = 0; o < orders.size(); ++o)
    for (int run = 0; run < 8; ++run) {
      SCOPED_TRACE(testing::Message() << "order " << o << ", run " << run);
      const Voxelized v = voxelizer.run(orders[o], {128, false}, run == 0);
      EXPECT_EQ(v.stats.occupied, first.stats.occupied);
      EXPECT_EQ(v.stats.checksum, first.stats.checksum);
      if (run == 0) {
        EXPECT_EQ(v.albedo, first.albedo);
      }
    }
}

// A fragment that finds its voxel still being claimed by another thread after the
// wait is deferred, and added after the raster as it would have been. Deferring
// every fragment (a test variant) gives the same grid bit for bit, through a
// deferred buffer that had to grow.
TEST_F(VoxelizeTest, DeferredFragmentsAddWhatTheyWouldHave) {
  const scene::Scene s = scene::loadGltf(cornellRoom());
  Voxelizer voxelizer;
  const Voxelized direct = voxelizer.run(s, {64, false}, true);
  voxel::VoxelizePass::Settings all{64, false};
  all.deferAll = true;
  const Voxelized deferred = voxelizer.run(s, all, true);
  EXPECT_GT(deferred.stats.deferred, 30000u);  // every fragment (36,084), in a grown buffer
  EXPECT_GE(deferred.stats.rounds, 2);
  EXPECT_EQ(deferred.stats.occupied, direct.stats.occupied);
  EXPECT_EQ(deferred.stats.checksum, direct.stats.checksum);
  EXPECT_EQ(deferred.albedo, direct.albedo);
  // No wait at all: whatever meets a claim in progress is deferred.
  voxel::VoxelizePass::Settings impatient{128, false};
  impatient.claimSpins = 0;
  const Voxelized reference = voxelizer.run(s, {128, false}, false);
  for (int run = 0; run < 3; ++run)
    EXPECT_EQ(voxelizer.run(s, impatient, false).stats.checksum, reference.stats.checksum);
}

// A raster that ran out of pool bricks, or of voxel slots, runs again in a fresh
// epoch with room for what it found; what the first round added to the sums must
// not stay there.
TEST_F(VoxelizeTest, ARoundThatDidNotFitLeavesNothingInTheSums) {
  const scene::Scene s = scene::loadGltf(cornellRoom());
  Voxelizer voxelizer;
  const Voxelized roomy = voxelizer.run(s, {64, false}, true);
  EXPECT_EQ(roomy.stats.rounds, 1);
  for (bool bricks : {true, false}) {
    voxel::VoxelizePass::Settings tight{64, false};
    if (bricks)
      tight.initialBricks = 16;
    else
      tight.initialListEntries = 1000;
    const Voxelized grown = voxelizer.run(s, tight, true);
    EXPECT_GE(grown.stats.rounds, 2) << (bricks ? "bricks" : "slots");
    EXPECT_EQ(grown.stats.occupied, roomy.stats.occupied);
    EXPECT_EQ(grown.stats.checksum, roomy.stats.checksum);
    EXPECT_EQ(grown.albedo, roomy.albedo);
  }
}

// The list and its slots are sized for the scene's surfaces (listEntriesFor), not
// the dense grid: enough for what they occupy in one round, and a small part of the
// grid. Overlapping surfaces make the estimate larger (never smaller): these scenes
// have none.
TEST_F(VoxelizeTest, ListSizedForTheSceneFitsInOneRound) {
  struct Case {
    const char* name;
    scene::Scene scene;
    int n;
  };
  std::vector<Case> cases;
  const scene::Scene cornell = scene::loadGltf(cornellRoom());
  for (int n : {64, 128}) cases.push_back({"cornell_room", cornell, n});
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 4; ++i) {
    SceneBuilder b;
    const glm::mat4 t = glm::rotate(glm::mat4(1.0f), 3.0f * u(rng),
                                    glm::normalize(glm::vec3(u(rng), u(rng), u(rng))));
    const int m = b.addMaterial(glm::vec3(0.5f));
    b.addBox({-1, -0.6f, -0.8f}, {1, 0.6f, 0.8f}, m, t);
    b.addSphere(glm::vec3(0.3f), 0.25f, 48, m, t);  // small triangles
    for (int n : {32, 128}) cases.push_back({"tilted box and sphere", b.finish(), n});
  }
  Voxelizer voxelizer;
  for (const Case& c : cases) {
    const float voxelSize = c.scene.scale.gridSize / static_cast<float>(c.n);
    const uint32_t entries = voxel::listEntriesFor(c.scene, c.n, voxelSize);
    const Voxelized v = voxelizer.run(c.scene, {c.n, false}, false);
    const uint32_t n2 = static_cast<uint32_t>(c.n * c.n);
    EXPECT_EQ(v.stats.rounds, 1) << c.name << " at " << c.n;
    EXPECT_GE(entries, v.stats.occupied) << c.name << " at " << c.n;
    // At most 2.5 times what they occupy (walls along the axes) plus a grid face,
    // give or take the estimate's error; a small part of the dense grid's memory.
    EXPECT_LE(entries, 3 * v.stats.occupied + n2) << c.name << " at " << c.n;
    if (c.n >= 128) {
      EXPECT_LT(v.stats.peakBytes, voxel::voxelMemory(c.n).peakBytes / 4) << c.name;
    }
  }
}

struct Agreement {
  size_t gpu = 0, cpu = 0, both = 0;
  double recall() const { return cpu ? static_cast<double>(both) / static_cast<double>(cpu) : 1.0; }
  double precision() const {
    return gpu ? static_cast<double>(both) / static_cast<double>(gpu) : 1.0;
  }
};

Agreement agreement(const std::vector<uint8_t>& gpu, const std::vector<uint8_t>& cpu) {
  Agreement a;
  for (size_t i = 0; i < gpu.size(); ++i) {
    a.gpu += gpu[i];
    a.cpu += cpu[i];
    a.both += gpu[i] & cpu[i];
  }
  return a;
}

void report(const char* what, int n, const Agreement& a) {
  std::printf("[agreement] %s %d^3: gpu %zu, cpu %zu, recall %.4f, precision %.4f\n", what, n,
              a.gpu, a.cpu, a.recall(), a.precision());
}

class VoxelizeAgreementTest : public GlTest, public ::testing::WithParamInterface<int> {
 protected:
  void SetUp() override { GlTest::SetUp(); }
  void TearDown() override { GlTest::TearDown(); }
};

// Against the triangle-box reference: MSAA coverage catches nearly every voxel a
// triangle touches; what it misses are voxels grazed at a corner or edge by less
// than the distance to the nearest sample point.
TEST_P(VoxelizeAgreementTest, CornellRoomAgreesWithReference) {
  const int n = GetParam();
  const scene::Scene s = scene::loadGltf(cornellRoom());
  const Agreement a = agreement(voxelize(s, n).occupied, cpuVoxelize(s, n));
  report("cornell_room", n, a);
  EXPECT_GE(a.recall(), 0.90);
  EXPECT_GE(a.precision(), 0.99);
}

// Thin planes tilted in every direction: each is one voxel thick or less.
TEST_P(VoxelizeAgreementTest, ThinTiltedPlanesAgreeWithReference) {
  const int n = GetParam();
  SceneBuilder b;
  const int m = b.addMaterial(glm::vec3(0.8f));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f);
  for (int i = 0; i < 12; ++i) {
    glm::mat4 t = glm::translate(glm::mat4(1.0f), glm::vec3((i % 4) * 2.5f, (i / 4) * 2.5f, 0.0f));
    t = glm::rotate(t, angle(rng),
                    glm::normalize(glm::vec3(angle(rng) - 3.0f, angle(rng) - 3.0f, 1.0f)));
    // A 2 x 2 square, and a sliver 2 long and 1/20 of a voxel at 128^3 wide.
    b.addTriangles({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, m, t);
    b.addTriangles({{-1, 1.1f, 0}, {1, 1.1f, 0}, {1, 1.1005f, 0}}, m, t);
  }
  const scene::Scene s = b.finish();
  const Agreement a = agreement(voxelize(s, n).occupied, cpuVoxelize(s, n));
  report("tilted planes", n, a);
  // Extra voxels come from the plane's depth span over a partly covered pixel (the
  // price of watertight steep surfaces); misses from slivers between samples.
  EXPECT_GE(a.recall(), 0.90);
  EXPECT_GE(a.precision(), 0.97);
}

INSTANTIATE_TEST_SUITE_P(Resolutions, VoxelizeAgreementTest, ::testing::Values(64, 128));

// A closed box stays closed: no 6-connected path of empty voxels leads from the
// grid's border to its centre, at any of these orientations.
TEST_F(VoxelizeTest, ClosedBoxIsWatertightAtEveryOrientation) {
  struct Orientation {
    const char* name;
    glm::vec3 axis;
    float degrees;
  };
  std::vector<Orientation> orientations = {
      {"axis aligned", {0, 1, 0}, 0.0f},     {"30 about y", {0, 1, 0}, 30.0f},
      {"45 about y", {0, 1, 0}, 45.0f},      {"45 about x", {1, 0, 0}, 45.0f},
      {"45 about z", {0, 0, 1}, 45.0f},      {"corner up", {1, 0, -1}, 54.7356f},
      {"45 about (1,1,0)", {1, 1, 0}, 45.0f}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 5; ++i)
    orientations.push_back({"random", {u(rng), u(rng), u(rng)}, 180.0f * u(rng)});
  for (const Orientation& o : orientations) {
    SceneBuilder b;
    const glm::mat4 t =
        glm::rotate(glm::mat4(1.0f), glm::radians(o.degrees), glm::normalize(o.axis));
    b.addBox({-1, -0.6f, -0.8f}, {1, 0.6f, 0.8f}, b.addMaterial(glm::vec3(0.5f)), t);
    for (int n : {32, 64}) {
      scene::Scene s = b.finish();
      const Voxelized v = voxelize(s, n);
      const glm::vec3 c =
          (glm::vec3(0.0f) - s.scale.gridOrigin) / s.scale.gridSize * static_cast<float>(n);
      EXPECT_FALSE(reachableFromOutside(v.occupied, n, glm::ivec3(c))) << o.name << " at " << n;
    }
  }
}

// 10,000 triangles stacked on one voxel average to exactly the value one triangle
// gives: the sums stay far from their limit and no fragment order can change them.
TEST_F(VoxelizeTest, TenThousandCoplanarTrianglesAverageExactly) {
  SceneBuilder b;
  const int m = b.addMaterial(glm::vec3(0.3f, 0.6f, 0.9f));
  std::vector<glm::vec3> tris;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.05f, 0.95f);
  for (int i = 0; i < 10000; ++i) {
    const glm::vec3 a(u(rng), u(rng), 0.5f);
    tris.insert(tris.end(), {a, a + glm::vec3(0.6f, 0.0f, 0.0f), a + glm::vec3(0.0f, 0.6f, 0.0f)});
  }
  // Keep every corner inside the voxel [0,1)^3.
  for (glm::vec3& p : tris) p = glm::vec3(glm::min(glm::vec2(p), glm::vec2(0.999f)), p.z);
  b.addTriangles(tris, m);
  scene::Scene s = b.finish();
  s.scale.gridOrigin = glm::vec3(-16.0f);  // voxel (16,16,16) is [0,1)^3
  s.scale.gridSize = 32.0f;
  const Voxelized v = voxelize(s, 32);
  ASSERT_EQ(v.stats.occupied, 1u);
  const size_t at = (16 + 32 * (16 + 32 * 16)) * 4;
  EXPECT_EQ(v.albedo[at + 0], 77);   // round(0.3 * 255)
  EXPECT_EQ(v.albedo[at + 1], 153);  // round(0.6 * 255)
  EXPECT_EQ(v.albedo[at + 2], 230);  // round(0.9 * 255)
  EXPECT_EQ(v.albedo[at + 3], 255);
}

// Past 2^32 - 1 a sum stays at 2^32 - 1 instead of wrapping to a small value.
TEST_F(VoxelizeTest, SumsSaturateNeverWrap) {
  SceneBuilder b;
  const int m = b.addMaterial(glm::vec3(1.0f, 0.0f, 0.0f));
  std::vector<glm::vec3> tris;
  for (int i = 0; i < 60000; ++i)
    tris.insert(tris.end(), {{0.01f, 0.01f, 0.5f}, {0.99f, 0.01f, 0.5f}, {0.01f, 0.99f, 0.5f}});
  b.addTriangles(tris, m);
  scene::Scene s = b.finish();
  s.scale.gridOrigin = glm::vec3(-16.0f);
  s.scale.gridSize = 32.0f;
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  scene::GpuScene gs(s);
  gl::FrameContext ctx{programs, timer, 32, 32, 0};
  voxel::VoxelizePass pass(programs, "llvmpipe", {32, false, true});
  pass.execute(ctx, gs);
  timer.resolve();
  const size_t at = 16 + 32 * (16 + 32 * 16);
  const std::vector<uint32_t> red = pass.readSum(gpu::kSumAlbedo);
  const std::vector<uint32_t> weight = pass.readSum(gpu::kSumWeight);
  EXPECT_GE(weight[at], 60000u * 2u);  // every fragment covers 2 or 3 of the 4 samples
  EXPECT_EQ(red[at], 0xFFFFFFFFu);     // 60000 x >=2 x 65535 > 2^32: saturated
  EXPECT_EQ(pass.readSum(gpu::kSumAlbedo + 1)[at], 0u);
}

// One pass voxelizing a scene after another (as with --revoxelize) gives exactly
// what a fresh pass gives: albedo, normal and emission of voxels the first scene
// reached and the second does not are zeroed, emissive voxels included.
TEST_F(VoxelizeTest, RevoxelizingLeavesNothingOfTheLastScene) {
  auto scene = [](float lampX, glm::vec3 lampEmission) {
    SceneBuilder b;
    b.addBox({-10, -10, -10}, {10, -9, 10}, b.addMaterial(glm::vec3(0.7f)));
    b.addBox({lampX, 0, -2}, {lampX + 4, 4, 2}, b.addMaterial(glm::vec3(0.9f), lampEmission));
    b.addBox({-5, 5, -5}, {5, 6, 5}, b.addMaterial(glm::vec3(0.2f), glm::vec3(0.5f, 0, 0)));
    scene::Scene s = b.finish();
    s.scale.gridOrigin = glm::vec3(-12.0f);
    s.scale.gridSize = 24.0f;
    return s;
  };
  const scene::Scene first = scene(-8.0f, glm::vec3(3.0f)), second = scene(3.0f, glm::vec3(0.0f));
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  gl::FrameContext ctx{programs, timer, 64, 64, 0};
  voxel::VoxelizePass reused(programs, "llvmpipe", {64, true});
  voxel::VoxelizePass fresh(programs, "llvmpipe", {64, false});
  scene::GpuScene a(first), b(second);
  reused.execute(ctx, a);
  reused.execute(ctx, b);
  fresh.execute(ctx, b);
  timer.resolve();
  EXPECT_EQ(reused.stats().occupied, fresh.stats().occupied);
  EXPECT_EQ(reused.stats().checksum, fresh.stats().checksum);
  EXPECT_EQ(reused.readAlbedo(), fresh.readAlbedo());
  EXPECT_EQ(reused.readNormal(), fresh.readNormal());
  EXPECT_EQ(reused.readEmission(), fresh.readEmission());
  const std::vector<uint16_t> e = fresh.readEmission();
  EXPECT_GT(std::count_if(e.begin(), e.end(), [](uint16_t h) { return h != 0; }), 0);
}

// Without the checksum (bench, the viewer) the resolve lists the same voxels with
// the same attributes; the checksum reads 0.
TEST_F(VoxelizeTest, GridWithoutChecksumIsTheSame) {
  SceneBuilder b;
  b.addBox({-5, -5, -5}, {5, 5, 5}, b.addMaterial(glm::vec3(0.3f, 0.6f, 0.9f)));
  b.addBox({-2, -2, -2}, {2, 2, 2}, b.addMaterial(glm::vec3(0.9f), glm::vec3(1.0f, 0.5f, 0)));
  const scene::Scene s = b.finish();
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  gl::FrameContext ctx{programs, timer, 64, 64, 0};
  voxel::VoxelizePass::Settings without{64, false};
  without.checksum = false;
  voxel::VoxelizePass with(programs, "llvmpipe", {64, false}), plain(programs, "llvmpipe", without);
  scene::GpuScene gs(s);
  with.execute(ctx, gs);
  plain.execute(ctx, gs);
  timer.resolve();
  EXPECT_GT(with.stats().occupied, 1000u);
  EXPECT_NE(with.stats().checksum, 0u);
  EXPECT_EQ(plain.stats().checksum, 0u);
  EXPECT_EQ(plain.stats().occupied, with.stats().occupied);
  EXPECT_EQ(plain.readAlbedo(), with.readAlbedo());
  EXPECT_EQ(plain.readNormal(), with.readNormal());
  EXPECT_EQ(plain.readEmission(), with.readEmission());
}

// Voxelized once, the list is trimmed to its voxels; voxelizing a larger scene with
// the same pass grows it again (the raster runs again in a fresh epoch) and gives
// exactly what a fresh pass gives.
TEST_F(VoxelizeTest, TrimmedListGrowsForALargerScene) {
  auto scene = [](int boxes) {
    SceneBuilder b;
    const int m = b.addMaterial(glm::vec3(0.6f), glm::vec3(0.25f, 0, 0));
    for (int i = 0; i < boxes; ++i) {
      const float x = -10.0f + 5.0f * static_cast<float>(i);
      b.addBox({x, -10, -10}, {x + 3, 10, 10}, m);
    }
    scene::Scene s = b.finish();
    s.scale.gridOrigin = glm::vec3(-12.0f);
    s.scale.gridSize = 24.0f;
    return s;
  };
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  gl::FrameContext ctx{programs, timer, 64, 64, 0};
  voxel::VoxelizePass reused(programs, "llvmpipe", {64, false});
  voxel::VoxelizePass fresh(programs, "llvmpipe", {64, false});
  const scene::Scene one = scene(1), four = scene(4);  // GpuScene keeps a reference
  scene::GpuScene small(one), large(four);
  reused.execute(ctx, small);
  const voxel::VoxelGridStats first = reused.stats();
  EXPECT_EQ(first.bytes, uint64_t{first.occupied} * 20);  // trimmed: 20 bytes a voxel
  reused.execute(ctx, large);
  fresh.execute(ctx, large);
  timer.resolve();
  EXPECT_GT(reused.stats().occupied, 3 * first.occupied);
  EXPECT_EQ(reused.stats().occupied, fresh.stats().occupied);
  EXPECT_EQ(reused.stats().checksum, fresh.stats().checksum);
  EXPECT_EQ(reused.readAlbedo(), fresh.readAlbedo());
  EXPECT_EQ(reused.readNormal(), fresh.readNormal());
  EXPECT_EQ(reused.readEmission(), fresh.readEmission());
}

struct PathResult {
  voxel::VoxelGridStats stats;
  std::vector<uint8_t> occupied;
  std::vector<int8_t> normal;
  std::vector<uint32_t> weight;
};

PathResult voxelizeWithPath(const scene::Scene& s, int n, bool smallInCompute) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  gl::StageTimer timer;
  scene::GpuScene gs(s);
  gl::FrameContext ctx{programs, timer, n, n, 0};
  voxel::VoxelizePass::Settings settings{n, false, true};
  settings.smallTrianglesInCompute = smallInCompute;
  voxel::VoxelizePass pass(programs, "llvmpipe", settings);
  pass.execute(ctx, gs);
  timer.resolve();
  return {pass.stats(), occupancyFromAlbedo(pass.readAlbedo()), pass.readNormal(),
          pass.readSum(gpu::kSumWeight)};
}

// Small triangles take the compute path, which tests the rasterizer's own samples
// on its sub-pixel grid: the grid matches the one the raster gives for the same
// triangles. The covered samples add up to the same total (a triangle taken by
// both paths, or by neither, would double or drop its share), the voxels and the
// normals agree.
TEST_F(VoxelizeTest, SmallTrianglePathMatchesTheRaster) {
  SceneBuilder b;
  const int m = b.addMaterial(glm::vec3(0.4f, 0.5f, 0.6f));
  b.addSphere(glm::vec3(0.0f), 1.0f, 48, m);  // 9216 small triangles
  const glm::mat4 tilt = glm::rotate(glm::mat4(1.0f), 0.4f, glm::normalize(glm::vec3(1, 2, 3)));
  b.addTriangles({{-1.2f, -1.2f, 0}, {1.2f, -1.2f, 0}, {1.2f, 1.2f, 0}}, m, tilt);  // one large
  const scene::Scene s = b.finish();
  for (int n : {64, 128}) {
    const PathResult compute = voxelizeWithPath(s, n, true);
    const PathResult raster = voxelizeWithPath(s, n, false);
    EXPECT_GT(compute.stats.smallTriangles, 9216u * 9 / 10) << n;
    EXPECT_LT(compute.stats.smallTriangles, 9216u + 1u) << n;  // never the large one
    // The large one, and only it, is passed on to the raster (the facets are about 2
    // voxels wide at 128^3; the rest of the 9217 have no area in grid space).
    EXPECT_EQ(compute.stats.rasterTriangles, 1u) << n;
    EXPECT_EQ(raster.stats.smallTriangles, 0u) << n;

    uint64_t wCompute = 0, wRaster = 0;
    size_t differ = 0, both = 0;
    double cosine = 0.0;
    for (size_t i = 0; i < raster.occupied.size(); ++i) {
      wCompute += compute.weight[i];
      wRaster += raster.weight[i];
      differ += compute.occupied[i] != raster.occupied[i];
      if (!compute.occupied[i] || !raster.occupied[i]) continue;
      ++both;
      glm::vec3 a(0.0f), c(0.0f);
      for (int k = 0; k < 3; ++k) {
        a[k] = compute.normal[i * 4 + static_cast<size_t>(k)] / 127.0f;
        c[k] = raster.normal[i * 4 + static_cast<size_t>(k)] / 127.0f;
      }
      cosine += glm::length(a) > 0.5f && glm::length(c) > 0.5f
                    ? glm::dot(glm::normalize(a), glm::normalize(c))
                    : 1.0;
    }
    std::printf(
        "[small triangles] %d^3: %u of 9217 in compute, %u passed on, %zu voxels differ of %u, "
        "samples %llu vs %llu, mean normal cosine %.5f\n",
        n, compute.stats.smallTriangles, compute.stats.rasterTriangles, differ,
        raster.stats.occupied, static_cast<unsigned long long>(wCompute),
        static_cast<unsigned long long>(wRaster), cosine / static_cast<double>(both));
    EXPECT_LE(static_cast<double>(differ), 0.002 * raster.stats.occupied) << n;
    EXPECT_NEAR(static_cast<double>(wCompute) / static_cast<double>(wRaster), 1.0, 0.002) << n;
    EXPECT_GT(cosine / static_cast<double>(both), 0.999) << n;
  }
}

// A closed sphere of small triangles stays closed, whichever path takes them.
TEST_F(VoxelizeTest, ClosedSphereOfSmallTrianglesIsWatertight) {
  for (int rings : {24, 64}) {
    SceneBuilder b;
    const glm::mat4 t = glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(3, 1, 2)));
    b.addSphere(glm::vec3(0.0f), 1.0f, rings, b.addMaterial(glm::vec3(0.5f)), t);
    const scene::Scene s = b.finish();
    for (int n : {32, 64}) {
      const glm::vec3 c =
          (glm::vec3(0.0f) - s.scale.gridOrigin) / s.scale.gridSize * static_cast<float>(n);
      for (bool compute : {true, false}) {
        const PathResult r = voxelizeWithPath(s, n, compute);
        if (compute) {
          EXPECT_GT(r.stats.smallTriangles, 0u);
        }
        EXPECT_FALSE(reachableFromOutside(r.occupied, n, glm::ivec3(c)))
            << rings << " rings at " << n << (compute ? " (compute)" : " (raster)");
      }
    }
  }
}

// The voxel count does not depend on where the scene is or on its unit.
TEST_F(VoxelizeTest, CountIgnoresTranslationAndScale) {
  const uint32_t base = voxelize(scene::loadGltf(cornellRoom()), 64, false).stats.occupied;
  struct Move {
    glm::dvec3 translation;
    double scale;
  };
  for (const Move& m : {Move{{1e4, 1e4, -1e4}, 1.0}, Move{{0, 0, 0}, 1e-3}, Move{{0, 0, 0}, 1e3},
                        Move{{-3e4, 2e4, 1e4}, 1e3}}) {
    const scene::Scene s =
        scene::loadGltf(writeTransformedGltf(cornellRoom(), m.translation, m.scale));
    EXPECT_EQ(voxelize(s, 64, false).stats.occupied, base)
        << "translation " << m.translation.x << " scale " << m.scale;
  }
}

TEST_F(VoxelizeTest, RefusesResolutionsOutOfRangeOrBudget) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  EXPECT_THROW(voxel::VoxelizePass(programs, "llvmpipe", {16, false}), Error);
  EXPECT_THROW(voxel::VoxelizePass(programs, "llvmpipe", {1024, false}), Error);
  voxel::VoxelizePass::Settings tight{128, false};
  tight.memoryBudgetBytes = uint64_t{10} << 20;
  try {
    voxel::VoxelizePass(programs, "llvmpipe", tight);
    ADD_FAILURE() << "a 128^3 grid fit in 10 MiB";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GiB"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace voxgi::test

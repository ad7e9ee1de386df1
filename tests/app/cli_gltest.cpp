// The voxgi executable end to end: bad input gets one line naming the file and the
// problem, a non-zero exit, no crash and no partial file; good input writes what
// was asked for.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/metrics.h"
#include "render/pathtrace/pathtracer.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {
namespace fs = std::filesystem;

std::string voxgi(const std::string& args) {
  return voxgiBinary() + " " + args;
}

// Error output is one line starting "voxgi: error: ".
void expectOneLineError(const CommandResult& r, int code, const std::string& needle) {
  EXPECT_EQ(r.exitCode, code) << r.output;
  EXPECT_EQ(r.output.rfind("voxgi: error: ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos)
      << "missing '" << needle << "' in: " << r.output;
}

TEST(Cli, HelpAndVersion) {
  auto r = runCommand(voxgi("--help"));
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.output.find("render"), std::string::npos);
  r = runCommand(voxgi("render --help"));
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.output.find("--size"), std::string::npos);
  EXPECT_NE(r.output.find("--backend"), std::string::npos);
  r = runCommand(voxgi("--version"));
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.output.rfind("voxgi ", 0), 0u);
}

TEST(Cli, UsageErrorsExitTwo) {
  expectOneLineError(runCommand(voxgi("render --frobnicate")), 2, "--frobnicate");
  expectOneLineError(runCommand(voxgi("paint")), 2, "paint");
  expectOneLineError(runCommand(voxgi("render --size 64")), 2, "WxH");
  expectOneLineError(runCommand(voxgi("render --size -5x10")), 2, "--size");
  expectOneLineError(runCommand(voxgi("render --mode teleport")), 2, "teleport");
  expectOneLineError(runCommand(voxgi("render --backend vulkan")), 2, "vulkan");
  expectOneLineError(runCommand(voxgi("render --frames")), 2, "needs a value");
}

TEST(Cli, MissingAndMalformedScenes) {
  const std::string dir = scratchDir();
  expectOneLineError(runCommand(voxgi("render " + dir + "/nope.gltf --size 8x8")), 1,
                     dir + "/nope.gltf: no such file");
  std::ofstream(dir + "/broken.gltf") << "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [";
  expectOneLineError(runCommand(voxgi("render " + dir + "/broken.gltf --size 8x8")), 1,
                     dir + "/broken.gltf");
  std::ofstream(dir + "/scene.obj") << "v 0 0 0\n";
  expectOneLineError(runCommand(voxgi("render " + dir + "/scene.obj --size 8x8")), 1, "scene.obj");
}

TEST(Cli, AbsurdSizeIsRefused) {
  const std::string dir = scratchDir();
  const auto r = runCommand(voxgi("render --size 100000x100000 --out " + dir + "/big.png"));
  expectOneLineError(r, 1, "100000x100000");
  EXPECT_FALSE(fs::exists(dir + "/big.png"));
  EXPECT_TRUE(fs::is_empty(dir));  // no partial or temporary file either
}

TEST(Cli, VoxelGridBeyondMemoryIsRefused) {
  const std::string dir = scratchDir();
  expectOneLineError(
      runCommand("env VOXGI_VOXEL_BUDGET_MB=8 " +
                 voxgi("render --mode points --voxels 128 --size 8x8 --out " + dir + "/p.png")),
      1, "--voxels 128");
  expectOneLineError(runCommand(voxgi("render --mode points --voxels 1024")), 2, "--voxels");
  EXPECT_TRUE(fs::is_empty(dir));
}

// The stats count decoded texture memory: the GL texture with its mip chain (a 2 x 2
// RGBA8 image: 4 + 1 texels of 4 bytes), the texels of the BVH's reads on the GL
// path tracer (4 texels and a 16-byte table entry), the scene's decoded image and
// the CPU path tracer's copy.
TEST(Cli, TextureMemoryInStats) {
  const std::string dir = scratchDir();
  const std::string scene = testDataDir() + "/samplers/wrap_clamp_clamp_nearest.gltf";
  struct Expected {
    const char* args;
    int gpu, bvh, cpu, cpuPathtracer;
  };
  for (const Expected& e : {Expected{"--mode raster", 20, 0, 16, 0},
                            Expected{"--mode pathtrace --pt-device gl --spp 1", 52, 32, 16, 0},
                            Expected{"--mode pathtrace --pt-device cpu --spp 1", 20, 0, 48, 32}}) {
    SCOPED_TRACE(e.args);
    const auto r = runCommand(
        voxgi("render " + scene + " " + e.args + " --size 8x8 --stats " + dir + "/s.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(dir + "/s.json");
    const auto stats = nlohmann::json::parse(in);
    const auto& t = stats["texture_bytes"];
    EXPECT_EQ(t["gl_textures"], 20);
    EXPECT_EQ(t["bvh_texels"], e.bvh);
    EXPECT_EQ(t["gpu"], e.gpu);
    EXPECT_EQ(t["scene_images"], 16);
    EXPECT_EQ(t["cpu_pathtracer"], e.cpuPathtracer);
    EXPECT_EQ(t["cpu"], e.cpu);
  }
}

// The stats report the process's peak resident memory and the bytes of the GPU's BVH
// with its hit data: for this textured quad's 2 triangles, 1 node (64), 2 triangles
// (48 each), 4 texels (16), the table of textures (16) and, as the quad emits, 2
// emitter entries (96 each); normals and UVs are read from the scene's own buffers.
// OpenImageIO and the 260 shared libraries it brings are loaded only when an image
// needs them (an EXR here): a PNG render and the help start without them, which
// took 0.15-0.3 s of every command's start.
TEST(Cli, OpenImageIoLoadsOnlyForTheImagesThatNeedIt) {
  const std::string dir = scratchDir();
  const auto loads = [](const std::string& args) {
    const auto r = runCommand("env LD_DEBUG=libs " + voxgi(args));
    EXPECT_EQ(r.exitCode, 0) << r.output.substr(r.output.size() > 2000 ? r.output.size() - 2000
                                                                       : 0);
    return r.output.find("libOpenImageIO") != std::string::npos;
  };
  EXPECT_FALSE(loads("--help"));
  const std::string render = "render " + cornellRoom() + " --size 8x8 --frames 1 -q ";
  EXPECT_FALSE(loads(render + "-o " + dir + "/a.png"));
  EXPECT_TRUE(loads(render + "-o " + dir + "/a.exr"));
  EXPECT_TRUE(fs::exists(dir + "/a.png"));
  EXPECT_TRUE(fs::exists(dir + "/a.exr"));
}

// The start-up is named, stage by stage, in the order it runs: the context, the
// scene's upload, the BVH (rtgi here), the passes and the warm-up frame; with the
// load they account for it, all but what no stage holds (a few lines of setup).
TEST(Cli, StartUpStagesAccountForTheStartUp) {
  const std::string dir = scratchDir();
  const auto r = runCommand(voxgi("render " + cornellRoom() + " --size 16x16 --frames 1 --stats " +
                                  dir + "/s.json -o " + dir + "/s.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::ordered_json::parse(in);
  std::vector<std::string> names;
  double sum = stats["load_ms"].get<double>();
  for (const auto& [name, ms] : stats["startup_stages"].items()) {
    names.push_back(name);
    EXPECT_GE(ms.get<double>(), 0.0) << name;
    sum += ms.get<double>();
  }
  EXPECT_EQ(names, (std::vector<std::string>{"context", "upload", "bvh", "passes", "warmup"}));
  const double startup = stats["startup_ms"].get<double>();
  EXPECT_LE(sum, startup * 1.001);
  EXPECT_GE(sum, startup * 0.8);
  EXPECT_NE(r.output.find("start-up"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warmup"), std::string::npos) << r.output;
}

// The raster mode builds no BVH.
TEST(Cli, MemoryInStats) {
  const std::string dir = scratchDir();
  const std::string scene = testDataDir() + "/samplers/wrap_clamp_clamp_nearest.gltf";
  for (const char* mode : {"--mode pathtrace --pt-device gl --spp 1", "--mode raster"}) {
    SCOPED_TRACE(mode);
    const auto r = runCommand(
        voxgi("render " + scene + " " + mode + " --size 8x8 --stats " + dir + "/s.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("peak RSS"), std::string::npos) << r.output;
    std::ifstream in(dir + "/s.json");
    const auto stats = nlohmann::json::parse(in);
    EXPECT_GT(stats["peak_rss_bytes"].get<double>(), 8e6);
    EXPECT_LT(stats["peak_rss_bytes"].get<double>(), 8e9);
    if (std::string(mode).find("pathtrace") != std::string::npos) {
      EXPECT_EQ(stats["gpu_bvh_bytes"], 64 + 2 * 48 + 16 + 16 + 2 * 96);
      // The tree's own build, a part of the bvh start-up stage.
      EXPECT_GE(stats["bvh_tree_ms"].get<double>(), 0.0);
      EXPECT_LE(stats["bvh_tree_ms"].get<double>(), stats["startup_stages"]["bvh"].get<double>());
    } else {
      EXPECT_FALSE(stats.contains("gpu_bvh_bytes"));
      EXPECT_FALSE(stats.contains("bvh_tree_ms"));
    }
  }
}

TEST(Cli, PointsModeReportsVoxels) {
  const std::string dir = scratchDir();
  const auto r = runCommand(
      voxgi("render --mode points --voxels 32 --size 32x32 --frames 2 --revoxelize --stats " + dir +
            "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["voxels"]["resolution"], 32);
  EXPECT_GT(stats["voxels"]["count"].get<int>(), 1000);
  // Resident: the list of occupied voxels, 4 bytes of coordinates and 16 of
  // attributes an entry; re-voxelizing keeps room for every voxel at this size.
  EXPECT_EQ(stats["voxels"]["bytes"], 32 * 32 * 32 * (4 + 16));
  EXPECT_EQ(stats["voxels"]["checksum"].get<std::string>().size(), 16u);
  EXPECT_TRUE(stats["stages"].contains("voxelize"));
  EXPECT_TRUE(stats["stages"].contains("points"));
  EXPECT_FALSE(stats["stages"].contains("raster"));
}

TEST(Cli, VoxelizedOnceKeepsOnlyItsOccupiedVoxels) {
  const std::string dir = scratchDir();
  const auto r = runCommand(
      voxgi("render --mode points --voxels 64 --size 32x32 --frames 1 --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  const auto count = stats["voxels"]["count"].get<uint64_t>();
  EXPECT_GT(count, 10000u);
  // 20 bytes per occupied voxel and nothing else: no N^3 texture, no spare list room.
  EXPECT_EQ(stats["voxels"]["bytes"].get<uint64_t>(), count * (4 + 16));
  EXPECT_GT(stats["voxels"]["peak_bytes"].get<uint64_t>(), count * (4 + 16));
}

TEST(Cli, BenchPrintsATableAndWritesJson) {
  const std::string dir = scratchDir();
  const auto r =
      runCommand(voxgi("bench --voxels 32,64 --frames 2 --size 32x32 --json " + dir + "/b.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("voxelize"), std::string::npos) << r.output;
  std::ifstream in(dir + "/b.json");
  const auto b = nlohmann::json::parse(in);
  ASSERT_EQ(b["runs"].size(), 2u);
  EXPECT_EQ(b["runs"][0]["voxels"], 32);
  EXPECT_EQ(b["runs"][1]["voxels"], 64);
  for (const auto& run : b["runs"]) {
    EXPECT_GT(run["stages"]["voxelize"].get<double>(), 0.0);  // measured every frame
    EXPECT_GT(run["occupied"].get<int>(), 0);
  }
  EXPECT_GT(b["runs"][1]["occupied"].get<int>(), b["runs"][0]["occupied"].get<int>());
  // The header every stats file starts with, in the same order.
  std::ifstream again(dir + "/b.json");
  const auto ordered = nlohmann::ordered_json::parse(again);
  std::vector<std::string> keys;
  for (const auto& [key, value] : ordered.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"voxgi_version", "scene", "mode", "size", "backend",
                                            "renderer", "gl_version", "triangles", "frames",
                                            "stage_timing", "runs", "gl_errors"}));
  expectOneLineError(runCommand(voxgi("bench --voxels 64,abc")), 2, "--voxels");
  expectOneLineError(runCommand(voxgi("bench --out x.png")), 2, "--out");
}

TEST(Cli, UnwritableOutputsAreRefusedBeforeRendering) {
  const std::string dir = scratchDir();
  expectOneLineError(runCommand(voxgi("render --size 8x8 --out " + dir + "/no/such/dir/x.png")), 1,
                     "does not exist");
  expectOneLineError(runCommand(voxgi("render --size 8x8 --out " + dir + "/x.jpg")), 1, "x.jpg");
  expectOneLineError(runCommand(voxgi("render --size 8x8 --out " + dir)), 1, "is a directory");
  expectOneLineError(runCommand(voxgi("render --size 8x8 --stats " + dir + "/no/such/s.json")), 1,
                     "does not exist");
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(Cli, FailedRenderLeavesExistingOutputAlone) {
  const std::string dir = scratchDir();
  const std::string out = dir + "/keep.png";
  std::ofstream(out) << "the user's file";
  const auto r = runCommand(voxgi("render " + dir + "/missing.gltf --size 8x8 --out " + out));
  EXPECT_EQ(r.exitCode, 1);
  std::ifstream in(out);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "the user's file");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

// The frame budget end to end: the mask is written, the stats record the budget
// and each frame's share; the mask without a budget, or a bad interleave, is a
// usage error before any work.
TEST(Cli, FrameBudgetWritesItsMaskAndStats) {
  const std::string dir = scratchDir();
  const auto r =
      runCommand(voxgi("render --size 48x40 --voxels 64 --frames 6 --target-fps 30 "
                       "--out-mask " +
                       dir + "/mask.png --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const image::Image mask = image::readImage(dir + "/mask.png");
  EXPECT_EQ(mask.width, 48);
  EXPECT_EQ(mask.height, 40);
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["budget"]["target_fps"], 30.0);
  EXPECT_EQ(stats["budget"]["frame_ms_each"].size(), 6u);
  EXPECT_EQ(stats["interleave"], 16);
  for (double share : stats["budget"]["traced_fraction_each"]) {
    EXPECT_GE(share, 1.0 / 16.0 - 1e-9);
    EXPECT_LE(share, 1.0);
  }
  for (const std::string& bad : {"--out-mask " + dir + "/m2.png", std::string("--interleave 3"),
                                 std::string("--target-fps 0"), std::string("--budget-select x")}) {
    const auto e = runCommand(voxgi("render --size 16x16 " + bad));
    EXPECT_EQ(e.exitCode, 2) << bad << ": " << e.output;
    EXPECT_EQ(std::count(e.output.begin(), e.output.end(), '\n'), 1) << e.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/m2.png"));
}

// --stats says how the direct light sampled the emitters and the punctual lights in
// the run, which the settings alone do not say: it follows the scene's counts.
TEST(Cli, StatsSayHowTheLightsWereSampled) {
  const std::string dir = scratchDir();
  const auto sampling = [&](const std::string& scene, const std::string& options) {
    const std::string stats = dir + "/s.json";
    const auto r = runCommand(voxgi("render " + scene + " --size 16x16 --frames 1 --voxels 32 " +
                                    options + " --stats " + stats));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(stats);
    const auto s = nlohmann::json::parse(in);
    return s["emitter_sampling"].get<std::string>() + " " +
           s["punctual_sampling"].get<std::string>();
  };
  const std::string hall = sourceDir() + "/scenes/hall/";
  EXPECT_EQ(sampling(cornellRoom(), ""), "exact none");      // one emitter
  EXPECT_EQ(sampling(darkPlane(), ""), "light_tiles none");  // 96 emitters
  EXPECT_EQ(sampling(darkPlane(), "--light-tiles off"), "light_tree none");
  EXPECT_EQ(sampling(hall + "hall.gltf", ""), "restir exact");        // 2,882; 6 lights
  EXPECT_EQ(sampling(hall + "hall_night.gltf", ""), "none sampled");  // 23 lights
}

TEST(Cli, RendersPngExrAndStats) {
  const std::string dir = scratchDir();
  // Without caustics: at this size a pixel on the light's edge whose sample showed
  // the light can take a photon that landed on the ceiling in its footprint, and
  // stand a little above the light's own radiance for a frame.
  const auto r = runCommand(voxgi("render --size 64x48 --frames 2 --caustics off --out " + dir +
                                  "/a.png --out " + dir + "/a.exr --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("rtgi"), std::string::npos);  // the default mode
  const image::Image png = image::readImage(dir + "/a.png");
  EXPECT_EQ(png.width, 64);
  EXPECT_EQ(png.height, 48);
  const image::Image exr = image::readImage(dir + "/a.exr");
  EXPECT_EQ(exr.width, 64);
  // The EXR holds linear radiance: the light (L = 15) shows unclamped.
  float maxValue = 0.0f;
  for (float v : exr.pixels) maxValue = std::max(maxValue, v);
  EXPECT_NEAR(maxValue, 15.0f, 0.01f);
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  for (const char* key : {"frame_ms", "stages", "triangles", "backend", "renderer", "size"})
    EXPECT_TRUE(stats.contains(key)) << key;
  EXPECT_EQ(stats["triangles"], 32268);
  EXPECT_EQ(stats["backend"], "egl");
  EXPECT_EQ(stats["size"]["width"], 64);
  EXPECT_EQ(stats["gl_errors"], 0);
  EXPECT_EQ(stats["nonfinite_terms"], 0);
  for (const char* stage : {"voxelize", "octree", "inject", "gbuffer", "shadows", "indirect",
                            "specular", "accumulate", "tonemap"})
    EXPECT_TRUE(stats["stages"].contains(stage)) << stage;
  EXPECT_EQ(stats["frames"], 2);
  EXPECT_GT(stats["frame_ms"].get<double>(), 0.0);
  EXPECT_LT(stats["stages"]["gbuffer"].get<double>(), 60000.0);  // a sane timer, not a stale clock
  for (const char* key : {"nodes", "bytes", "dense_bytes"})
    EXPECT_GT(stats["octree"][key].get<double>(), 0.0) << key;
  EXPECT_LT(stats["octree"]["bytes"].get<double>(), stats["octree"]["dense_bytes"].get<double>());
  // rtgi's defaults: its rays and the voxels' own on the exact triangles.
  EXPECT_EQ(stats["rays"], "triangles");
  EXPECT_EQ(stats["octree"]["rays"], "triangles");
  // 32,268 triangles on 64x64 pixels, 7.9 a pixel: on a software GL --primary auto
  // casts the G-buffer's rays, on a hardware rasterizer it rasterizes.
  const std::string renderer = stats["renderer"];
  const bool software = renderer.find("llvmpipe") != std::string::npos ||
                        renderer.find("softpipe") != std::string::npos;
  EXPECT_EQ(stats["primary"], software ? "rays" : "raster") << renderer;
  // Nothing but the three outputs in the folder.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
}

// A node hierarchy 50,000 levels deep is valid glTF: it renders under the default
// 8 MB stack, still and animated (the root's channel moves the deepest node's
// triangle; frame 1 at 2 fps poses it at t = 0.5 s).
TEST(Cli, RendersAHierarchy50000LevelsDeep) {
  const std::string dir = scratchDir();
  const glm::dvec3 step(1.0 / 1024.0, -1.0 / 2048.0, 0.0);
  for (bool animated : {false, true}) {
    SCOPED_TRACE(animated ? "animated" : "still");
    const std::string scene = writeDeepChainGltf(
        animated ? "deep_chain_animated.gltf" : "deep_chain.gltf", 50000, step, animated);
    const auto r =
        runCommand("ulimit -s 8192 2>/dev/null; " +
                   voxgi("render " + scene + " --mode raster --size 64x64 --frames 2 " +
                         "--fps 2 --out " + dir + "/deep.png --stats " + dir + "/deep.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(dir + "/deep.json");
    const auto stats = nlohmann::json::parse(in);
    EXPECT_EQ(stats["triangles"], 1);
    EXPECT_EQ(stats["animated"], animated);
    // The triangle is in the picture: lit pixels beside the black background.
    const image::Image png = image::readImage(dir + "/deep.png");
    ASSERT_EQ(png.width, 64);
    size_t lit = 0;
    for (size_t i = 0; i < png.pixels.size(); i += static_cast<size_t>(png.channels))
      if (png.pixels[i] + png.pixels[i + 1] + png.pixels[i + 2] > 0.0f) ++lit;
    EXPECT_GT(lit, 64u * 64u / 20u);
    EXPECT_LT(lit, 64u * 64u);
  }
}

TEST(Cli, PathtraceWritesImagesAndThroughput) {
  const std::string dir = scratchDir();
  const auto r =
      runCommand(voxgi("render --mode pathtrace --size 32x24 --spp 4 --seed 3 --out " + dir +
                       "/p.exr --out " + dir + "/p.png --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("ETA"), std::string::npos) << "progress bar on a pipe: " << r.output;
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["mode"], "pathtrace");
  EXPECT_EQ(stats["spp"], 4);
  EXPECT_GT(stats["samples_per_second"].get<double>(), 0.0);
  EXPECT_EQ(stats["truncated_paths"], 0);
  // --pt-device auto: cpu on a software GL, gl on a GPU.
  EXPECT_EQ(stats["pt_device"],
            render::pathtraceDeviceName(render::resolvePathtraceDevice(
                render::PathtraceDevice::kAuto, stats["renderer"].get<std::string>())));
  EXPECT_TRUE(stats["stages"].contains("pathtrace"));
  EXPECT_TRUE(stats["stages"].contains("tonemap"));
  EXPECT_FALSE(stats["stages"].contains("bvh"));  // start-up, not per frame
  // Sane stage times: compute is timed at all, and the query after it is not garbage.
  EXPECT_GT(stats["stages"]["pathtrace"].get<double>(), 0.0);
  EXPECT_LT(stats["stages"]["tonemap"].get<double>(), 1000.0);
  EXPECT_TRUE(stats["startup_stages"].contains("bvh"));
  const image::Image exr = image::readImage(dir + "/p.exr");
  EXPECT_EQ(exr.width, 32);
  EXPECT_EQ(exr.height, 24);
  float maxValue = 0.0f;
  for (float v : exr.pixels) maxValue = std::max(maxValue, v);
  EXPECT_NEAR(maxValue, 15.0f, 0.01f);  // the light seen directly, as in raster
}

TEST(Cli, CompareReportsMetricsAndRefusesMismatches) {
  const std::string dir = scratchDir();
  ASSERT_EQ(runCommand(voxgi("render --size 16x16 --out " + dir + "/a.exr --out " + dir + "/a.png"))
                .exitCode,
            0);
  ASSERT_EQ(runCommand(voxgi("render --size 16x8 --out " + dir + "/b.exr")).exitCode, 0);
  auto r = runCommand(voxgi("compare " + dir + "/a.exr " + dir + "/a.exr"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  for (const char* key : {"rmse", "rel_mse", "psnr", "ssim", "mean_luminance_ratio"})
    EXPECT_NE(r.output.find(key), std::string::npos) << key;
  r = runCommand(voxgi("compare " + dir + "/a.exr " + dir + "/a.exr --json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["rmse"], 0.0);
  EXPECT_EQ(j["ssim"], 1.0);
  EXPECT_TRUE(j["psnr"].is_null());  // identical: infinite PSNR
  EXPECT_EQ(j["mean_luminance_ratio"], 1.0);
  EXPECT_FALSE(j.contains("block_ratio_max"));
  r = runCommand(voxgi("compare " + dir + "/a.exr " + dir + "/a.exr --json --blocks 8"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto jb = nlohmann::json::parse(r.output);
  EXPECT_EQ(jb["block_size"], 8);
  EXPECT_EQ(jb["blocks"].get<int>() + jb["blocks_skipped"].get<int>(), 4);
  EXPECT_EQ(jb["block_ratio_max"], 1.0);
  EXPECT_EQ(jb["blocks_off_3_percent"], 0.0);
  expectOneLineError(runCommand(voxgi("compare " + dir + "/a.exr " + dir + "/a.exr --blocks 0")), 2,
                     "--blocks");
  expectOneLineError(runCommand(voxgi("compare " + dir + "/nope.exr " + dir + "/a.exr")), 1,
                     dir + "/nope.exr: no such file");
  expectOneLineError(runCommand(voxgi("compare " + dir + "/a.exr " + dir + "/b.exr")), 1,
                     "differ in size: 16x16 vs 16x8");
  ASSERT_EQ(runCommand("oiiotool " + dir + "/a.png --ch R -o " + dir + "/grey.png").exitCode, 0);
  expectOneLineError(runCommand(voxgi("compare " + dir + "/grey.png " + dir + "/a.png")), 1,
                     "differ in channel count: 1 vs 3");
  expectOneLineError(runCommand(voxgi("compare " + dir + "/a.exr")), 2, "two images");
}

TEST(Cli, OsMesaBackendRenders) {
  const std::string dir = scratchDir();
  const auto r =
      runCommand(voxgi("render --size 32x32 --backend osmesa --stats " + dir + "/s.json"));
  if (r.exitCode != 0 && !std::getenv("VOXGI_REQUIRE_OSMESA")) GTEST_SKIP() << r.output;
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/s.json");
  EXPECT_EQ(nlohmann::json::parse(in)["backend"], "osmesa");
}

// The GLFW backend (a hidden GLX window) under Xvfb renders the same image as EGL.
TEST(Cli, GlfwBackendUnderXvfbMatchesEgl) {
  if (runCommand("sh -c 'command -v xvfb-run'").exitCode != 0) {
    if (::voxgi::test::toolsRequired()) FAIL() << "xvfb-run missing (tools/setup installs xvfb)";
    GTEST_SKIP() << "xvfb-run not installed";
  }
  const std::string dir = scratchDir();
  auto r = runCommand("xvfb-run -a " + voxgi("render --backend glfw --size 64x64 --out " + dir +
                                             "/glfw.png --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = runCommand(voxgi("render --size 64x64 --out " + dir + "/egl.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/s.json");
  EXPECT_EQ(nlohmann::json::parse(in)["backend"], "glfw");
  const image::Difference d = image::compare(image::readImage(dir + "/glfw.png"),
                                             image::readImage(dir + "/egl.png"), 1.5 / 255.0);
  EXPECT_LE(d.maxAbs, 1.5 / 255.0);
}

}  // namespace
}  // namespace voxgi::test

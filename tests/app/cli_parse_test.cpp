// Command-line parsing, without a GL context.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "app/cli.h"
#include "app/cli_options.h"
#include "support/test_paths.h"

namespace voxgi::app {
namespace {

Invocation parse(std::vector<std::string> args) {
  return parseCommandLine(args);
}

TEST(CliParse, Defaults) {
  const Invocation inv = parse({"render"});
  EXPECT_EQ(inv.command, Command::kRender);
  EXPECT_TRUE(inv.render.scene.empty());
  EXPECT_EQ(inv.render.render.width, 512);
  EXPECT_EQ(inv.render.render.height, 512);
  EXPECT_EQ(inv.render.backend, gl::Backend::kEgl);
  // rtgi is the default mode, accumulating enough frames for a converged image;
  // other modes render one frame unless told.
  EXPECT_EQ(inv.render.render.mode, render::Mode::kRtgi);
  EXPECT_EQ(inv.render.frames, render::kRtgiDefaultFrames);
  // Every bounce by default: the voxels' light feeds back into itself as it refines.
  EXPECT_EQ(inv.render.render.octree.bounces, voxel::Octree::Settings::kAllBounces);
  EXPECT_EQ(inv.render.render.octree.refineRays, 1);
  EXPECT_TRUE(inv.render.render.jitter);
  EXPECT_EQ(parse({"render", "--mode", "raster"}).render.frames, 1);
  EXPECT_EQ(parse({"render", "--frames", "3"}).render.frames, 3);
  EXPECT_EQ(parse({"render", "--bounces", "0"}).render.render.octree.bounces, 0);
  EXPECT_EQ(parse({"render", "--bounces", "all"}).render.render.octree.bounces,
            voxel::Octree::Settings::kAllBounces);
  EXPECT_EQ(parse({"render", "--refine-rays", "0"}).render.render.octree.refineRays, 0);
  EXPECT_FALSE(parse({"render", "--no-jitter"}).render.render.jitter);
  const Invocation view =
      parse({"render", "--look-from", "0.75,1.5,1.1", "--look-at", "-0.4,0.35,-0.5"});
  ASSERT_TRUE(view.render.lookFrom && view.render.lookAt);
  EXPECT_EQ(*view.render.lookFrom, glm::vec3(0.75f, 1.5f, 1.1f));
  EXPECT_EQ(*view.render.lookAt, glm::vec3(-0.4f, 0.35f, -0.5f));
  EXPECT_TRUE(inv.render.outputs.empty());
}

// --name=value is --name value, so a value that starts with '-' can follow its flag;
// a positional argument with '=' in it is left as it is.
TEST(CliParse, OptionValuesAfterAnEqualsSign) {
  const Invocation inv = parse({"render", "a=b.gltf", "--size=64x32", "--look-from=0.75,1.5,1.1",
                                "--look-at=-0.4,0.35,-0.5", "--frames=3"});
  EXPECT_EQ(inv.render.scene, "a=b.gltf");
  EXPECT_EQ(inv.render.render.width, 64);
  EXPECT_EQ(inv.render.render.height, 32);
  EXPECT_EQ(inv.render.frames, 3);
  ASSERT_TRUE(inv.render.lookAt);
  EXPECT_EQ(*inv.render.lookAt, glm::vec3(-0.4f, 0.35f, -0.5f));
  EXPECT_EQ(parse({"view", "--render-scale=0.5"}).view.render.renderScale, 0.5f);
  EXPECT_THROW(parse({"render", "--size="}), UsageError);
  // A flag that takes no value leaves "1" as a second scene: an error.
  EXPECT_THROW(parse({"render", "s.gltf", "--no-jitter=1"}), UsageError);
}

TEST(CliParse, AllOptions) {
  const Invocation inv = parse(
      {"render",    "s.gltf", "--size",   "640x360", "--out",     "a.png",  "--out",      "a.exr",
       "--stats",   "s.json", "--frames", "7",       "--backend", "osmesa", "--exposure", "0.5",
       "--tonemap", "aces",   "--mode",   "raster",  "--ambient", "0.25"});
  const RenderOptions& o = inv.render;
  EXPECT_EQ(o.scene, "s.gltf");
  EXPECT_EQ(o.render.width, 640);
  EXPECT_EQ(o.render.height, 360);
  EXPECT_EQ(o.outputs, (std::vector<std::string>{"a.png", "a.exr"}));
  EXPECT_EQ(o.stats, "s.json");
  EXPECT_EQ(o.frames, 7);
  EXPECT_EQ(o.backend, gl::Backend::kOsMesa);
  EXPECT_FLOAT_EQ(o.render.tonemap.exposure, 0.5f);
  EXPECT_EQ(o.render.tonemap.op, render::Tonemap::kAces);
  EXPECT_FLOAT_EQ(o.render.ambient, 0.25f);
}

TEST(CliParse, PathtraceOptions) {
  const Invocation inv = parse({"render", "--mode", "pathtrace", "--spp", "256", "--seed", "9",
                                "--max-depth", "3", "--rr-depth", "2", "--no-progress"});
  const RenderOptions& o = inv.render;
  EXPECT_EQ(o.render.mode, render::Mode::kPathtrace);
  EXPECT_EQ(o.render.spp, 256);
  EXPECT_EQ(o.render.pathtrace.seed, 9u);
  EXPECT_EQ(o.render.pathtrace.maxDepth, 3);
  EXPECT_EQ(o.render.pathtrace.rrDepth, 2);
  EXPECT_FALSE(o.progress);
  // Defaults match scenes/reference_scenes.md: max depth 8, roulette from 5.
  const Invocation d = parse({"render", "--mode", "pathtrace"});
  EXPECT_EQ(d.render.render.pathtrace.maxDepth, 8);
  EXPECT_EQ(d.render.render.pathtrace.rrDepth, 5);
  EXPECT_EQ(d.render.render.spp, 64);
  // The device: auto by default; cpu and gl on request; threads for cpu.
  EXPECT_EQ(d.render.render.pathtrace.device, render::PathtraceDevice::kAuto);
  EXPECT_EQ(
      parse({"render", "--pt-device", "cpu", "--pt-threads", "3"}).render.render.pathtrace.device,
      render::PathtraceDevice::kCpu);
  EXPECT_EQ(parse({"render", "--pt-threads", "3"}).render.render.pathtrace.threads, 3);
  EXPECT_EQ(parse({"render", "--pt-device", "gl"}).render.render.pathtrace.device,
            render::PathtraceDevice::kGl);
  EXPECT_THROW(parse({"render", "--pt-device", "gpu"}), UsageError);
  EXPECT_THROW(parse({"render", "--pt-threads", "0"}), UsageError);
  // auto: cpu on a software rasterizer, gl on a GPU.
  EXPECT_EQ(render::resolvePathtraceDevice(render::PathtraceDevice::kAuto,
                                           "llvmpipe (LLVM 15.0.6, 256 bits)"),
            render::PathtraceDevice::kCpu);
  EXPECT_EQ(render::resolvePathtraceDevice(render::PathtraceDevice::kAuto, "NVIDIA H200/PCIe/SSE2"),
            render::PathtraceDevice::kGl);
  EXPECT_EQ(render::resolvePathtraceDevice(render::PathtraceDevice::kGl, "llvmpipe"),
            render::PathtraceDevice::kGl);
}

TEST(CliParse, DenoiseOption) {
  // On by default in render and view; the library's default is the raw mean.
  EXPECT_TRUE(parse({"render"}).render.render.rtgi.denoise);
  EXPECT_TRUE(parse({"view"}).view.render.rtgi.denoise);
  EXPECT_FALSE(render::RenderSettings{}.rtgi.denoise);
  EXPECT_FALSE(parse({"render", "--denoise", "off"}).render.render.rtgi.denoise);
  EXPECT_FALSE(parse({"view", "--denoise", "off"}).view.render.rtgi.denoise);
  // The viewer's default depends on the GL; a choice on the command line does not.
  EXPECT_FALSE(parse({"view"}).view.denoiseChosen);
  EXPECT_TRUE(parse({"view", "--denoise", "on"}).view.denoiseChosen);
  EXPECT_TRUE(render::isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(render::isSoftwareRenderer("softpipe"));
  EXPECT_FALSE(render::isSoftwareRenderer("NVIDIA H200/PCIe/SSE2"));
  EXPECT_TRUE(parse({"render", "--denoise", "on"}).render.render.rtgi.denoise);
  EXPECT_THROW(parse({"render", "--denoise", "yes"}), UsageError);
  EXPECT_THROW(parse({"render", "--denoise"}), UsageError);
}

TEST(CliParse, ReprojectionOptions) {
  // On by default, for render and view alike; the cap defaults to 16 frames.
  const Invocation d = parse({"render"});
  EXPECT_TRUE(d.render.render.rtgi.reproject);
  EXPECT_EQ(d.render.render.rtgi.historyCap, 16);
  EXPECT_TRUE(parse({"view"}).view.render.rtgi.reproject);
  const Invocation off = parse({"render", "--reproject", "off", "--history-cap", "4"});
  EXPECT_FALSE(off.render.render.rtgi.reproject);
  EXPECT_EQ(off.render.render.rtgi.historyCap, 4);
  EXPECT_FALSE(parse({"view", "--reproject", "off"}).view.render.rtgi.reproject);
  EXPECT_THROW(parse({"render", "--reproject", "yes"}), UsageError);
  EXPECT_THROW(parse({"render", "--reproject"}), UsageError);
  EXPECT_THROW(parse({"render", "--history-cap", "0"}), UsageError);
}

TEST(CliParse, RenderScale) {
  EXPECT_EQ(parse({"render"}).render.render.renderScale, 1.0f);
  EXPECT_EQ(parse({"render", "--render-scale", "0.5"}).render.render.renderScale, 0.5f);
  const Invocation v = parse({"view", "--render-scale", "0.25"});
  EXPECT_EQ(v.view.render.renderScale, 0.25f);
  EXPECT_TRUE(v.view.renderScaleChosen);
  EXPECT_FALSE(parse({"view"}).view.renderScaleChosen);
  for (const char* bad : {"0.2", "1.5", "0", "-1", "nan", "half"})
    EXPECT_THROW(parse({"render", "--render-scale", bad}), UsageError) << bad;
  EXPECT_THROW(parse({"render", "--render-scale"}), UsageError);
}

TEST(CliParse, Primary) {
  using Primary = render::RtgiPass::Settings::Primary;
  EXPECT_EQ(parse({"render"}).render.render.rtgi.primary, Primary::kAuto);
  EXPECT_EQ(parse({"render", "--primary", "rays"}).render.render.rtgi.primary, Primary::kRays);
  EXPECT_EQ(parse({"render", "--primary", "raster"}).render.render.rtgi.primary, Primary::kRaster);
  EXPECT_EQ(parse({"view", "--primary", "rays"}).view.render.rtgi.primary, Primary::kRays);
  EXPECT_EQ(parse({"render", "--primary", "auto"}).render.render.rtgi.primary, Primary::kAuto);
  EXPECT_THROW(parse({"render", "--primary", "bogus"}), UsageError);
  EXPECT_THROW(parse({"render", "--primary"}), UsageError);
}

TEST(CliParse, IndirectMethod) {
  using Method = render::RtgiPass::Settings::IndirectMethod;
  EXPECT_EQ(parse({"render"}).render.render.rtgi.indirectMethod, Method::kRays);
  EXPECT_EQ(parse({"render", "--indirect", "cones"}).render.render.rtgi.indirectMethod,
            Method::kCones);
  EXPECT_EQ(parse({"render", "--indirect", "rays"}).render.render.rtgi.indirectMethod,
            Method::kRays);
  EXPECT_EQ(parse({"view", "--indirect", "cones"}).view.render.rtgi.indirectMethod, Method::kCones);
  EXPECT_THROW(parse({"render", "--indirect", "foo"}), UsageError);
  EXPECT_THROW(parse({"render", "--indirect"}), UsageError);
}

TEST(CliParse, Compare) {
  Invocation inv = parse({"compare", "a.exr", "b.exr", "--json"});
  EXPECT_EQ(inv.command, Command::kCompare);
  EXPECT_EQ(inv.compare.test, "a.exr");
  EXPECT_EQ(inv.compare.reference, "b.exr");
  EXPECT_TRUE(inv.compare.json);
  inv = parse({"compare", "--help"});
  EXPECT_EQ(inv.command, Command::kHelp);
  EXPECT_EQ(inv.helpTopic, "compare");
  EXPECT_THROW(parse({"compare", "a.exr"}), UsageError);
  EXPECT_THROW(parse({"compare", "a.exr", "b.exr", "c.exr"}), UsageError);
  EXPECT_THROW(parse({"compare", "a.exr", "b.exr", "--bogus"}), UsageError);
}

TEST(CliParse, Check) {
  Invocation inv = parse({"check", "scene.gltf"});
  EXPECT_EQ(inv.command, Command::kCheck);
  EXPECT_EQ(inv.check.scene, "scene.gltf");
  inv = parse({"check", "--help"});
  EXPECT_EQ(inv.command, Command::kHelp);
  EXPECT_EQ(inv.helpTopic, "check");
  EXPECT_THROW(parse({"check"}), UsageError);
  EXPECT_THROW(parse({"check", "a.gltf", "b.gltf"}), UsageError);
  EXPECT_THROW(parse({"check", "a.gltf", "--bogus"}), UsageError);
}

TEST(CliParse, HelpAndVersion) {
  EXPECT_EQ(parse({}).command, Command::kHelp);
  EXPECT_EQ(parse({"--help"}).command, Command::kHelp);
  EXPECT_EQ(parse({"--version"}).command, Command::kVersion);
  const Invocation inv = parse({"render", "--size", "5x5", "--help"});
  EXPECT_EQ(inv.command, Command::kHelp);
  EXPECT_EQ(inv.helpTopic, "render");
}

TEST(CliParse, Rejects) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"render", "--size", "10"},
           {"render", "--size", "0x10"},
           {"render", "--size", "10x"},
           {"render", "--size", "axb"},
           {"render", "--size", "10x10x10"},
           {"render", "--frames", "0"},
           {"render", "--frames", "1e3"},
           {"render", "--exposure", "nan"},
           {"render", "--exposure", "inf"},
           {"render", "--ambient", "-0.5"},
           {"render", "--ambient", "nan"},
           {"render", "--backend", "d3d"},
           {"render", "--tonemap", "filmic"},
           {"render", "--mode", "magic"},
           {"render", "--spp", "0"},
           {"render", "--bounces", "17"},
           {"render", "--bounces", "-1"},
           {"render", "--bounces", "every"},
           {"render", "--refine-rays", "-1"},
           {"render", "--look-from", "1,2,3"},
           {"render", "--look-from", "1,2", "--look-at", "0,0,0"},
           {"render", "--look-from", "1,2,3,4", "--look-at", "0,0,0"},
           {"render", "--look-from", "0,0,0", "--look-at", "0,0,0"},
           {"render", "--spp", "many"},
           {"render", "--seed", "-1"},
           {"render", "--max-depth", "0"},
           {"render", "--rr-depth", "0"},
           {"render", "a.gltf", "b.gltf"},
           {"render", "--out"},
           {"render", "--bogus"},
           {"frobnicate"},
       }) {
    EXPECT_THROW(parse(args), UsageError) << args.back();
  }
}

TEST(CliParse, ViewDefaultsAndOptions) {
  Invocation inv = parse({"view"});
  EXPECT_EQ(inv.command, Command::kView);
  EXPECT_TRUE(inv.view.scene.empty());
  EXPECT_EQ(inv.view.render.width, 960);
  EXPECT_EQ(inv.view.render.height, 540);
  EXPECT_EQ(inv.view.frames, 0);  // until the window closes
  EXPECT_TRUE(inv.view.panel);
  // Interactive: rtgi holds 30 fps, and a restart costs no more than other frames.
  EXPECT_EQ(inv.view.render.targetFps, kViewTargetFps);
  EXPECT_TRUE(inv.view.render.rtgi.sparseStart);
  EXPECT_EQ(parse({"view", "--target-fps", "off"}).view.render.targetFps, 0.0);
  EXPECT_EQ(parse({"view", "--target-fps", "60"}).view.render.targetFps, 60.0);
  EXPECT_EQ(parse({"render"}).render.render.targetFps, 0.0);  // render: every pixel
  EXPECT_FALSE(parse({"render"}).render.render.rtgi.sparseStart);
  EXPECT_TRUE(parse({"render", "--sparse-start"}).render.render.rtgi.sparseStart);
  EXPECT_TRUE(parse({"render"}).render.render.rtgi.exactReflections);
  EXPECT_FALSE(parse({"render", "--voxel-reflections"}).render.render.rtgi.exactReflections);
  EXPECT_TRUE(parse({"render"}).render.render.rtgi.exactRays);
  EXPECT_FALSE(parse({"render", "--voxel-rays"}).render.render.rtgi.exactRays);
  EXPECT_TRUE(parse({"render", "--voxel-rays"}).render.render.rtgi.exactReflections);
  EXPECT_FALSE(parse({"view", "--voxel-rays"}).view.render.rtgi.exactRays);
  inv = parse({"view",         "s.glb",  "--size",           "320x200", "--frames",  "30",
               "--screenshot", "a.png",  "--screenshot-dir", "shots",   "--keys",    "10:2,5:+",
               "--stats",      "s.json", "--exposure",       "2",       "--tonemap", "aces",
               "--mode",       "raster", "--no-panel"});
  const ViewOptions& o = inv.view;
  EXPECT_EQ(o.scene, "s.glb");
  EXPECT_EQ(o.render.width, 320);
  EXPECT_EQ(o.render.height, 200);
  EXPECT_EQ(o.frames, 30);
  EXPECT_EQ(o.screenshot, "a.png");
  EXPECT_EQ(o.screenshotDir, "shots");
  ASSERT_EQ(o.keys.size(), 2u);
  EXPECT_EQ(o.keys[0].frame, 5);
  EXPECT_EQ(o.keys[1].action, (Action{Action::Kind::kMode, 2}));
  EXPECT_EQ(o.stats, "s.json");
  EXPECT_FLOAT_EQ(o.render.tonemap.exposure, 2.0f);
  EXPECT_EQ(o.render.tonemap.op, render::Tonemap::kAces);
  EXPECT_FALSE(o.panel);
  inv = parse({"view", "--help"});
  EXPECT_EQ(inv.command, Command::kHelp);
  EXPECT_EQ(inv.helpTopic, "view");
}

TEST(CliParse, ViewRejects) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"view", "--keys", "10:q"},
           {"view", "--keys", ""},
           {"view", "--keys"},
           {"view", "--frames", "0"},
           {"view", "--size", "10"},
           {"view", "--mode", "magic"},
           {"view", "--out", "a.png"},  // render's option, not the viewer's
           {"view", "a.gltf", "b.gltf"},
       }) {
    EXPECT_THROW(parse(args), UsageError) << args.back();
  }
}

// The option table is the one source of the parser and the help: no option is in
// it twice for one command (the second would never be reached), every one is in its
// commands' help, and each command accepts it.
TEST(CliOptions, EachOptionOnceInItsCommandsHelpAndParser) {
  std::set<std::pair<std::string, unsigned>> seen;
  for (const CliOption& o : cliOptions()) {
    for (unsigned command : {unsigned{kRenderOption}, unsigned{kViewOption}}) {
      if ((o.commands & command) == 0) continue;
      EXPECT_TRUE(seen.insert({o.name, command}).second) << o.name << " twice";
      const std::string help = command == kRenderOption ? renderHelp() : viewHelp();
      EXPECT_NE(help.find(o.name), std::string::npos) << o.name;
      const auto which = static_cast<OptionCommands>(command);
      EXPECT_EQ(findCliOption(o.name, which), &o) << o.name;
      if (o.alias) {
        EXPECT_EQ(findCliOption(o.alias, which), &o) << o.alias;
      }
    }
  }
  EXPECT_EQ(findCliOption("--screenshot", kRenderOption), nullptr);
  EXPECT_EQ(findCliOption("--spp", kViewOption), nullptr);
}

// The README's option table names only options the table holds, so it cannot keep
// one that was renamed or removed.
TEST(CliOptions, ReadmeNamesOnlyOptionsThatExist) {
  std::ifstream in(test::sourceDir() + "/README.md");
  ASSERT_TRUE(in) << "README.md";
  const std::regex option("--[a-z][a-z-]*");
  std::string line;
  int named = 0;
  while (std::getline(in, line)) {
    if (line.rfind("| `--", 0) != 0) continue;
    const std::string first = line.substr(0, line.find(" | ", 1));
    for (auto it = std::sregex_iterator(first.begin(), first.end(), option);
         it != std::sregex_iterator(); ++it) {
      ++named;
      EXPECT_NE(findCliOption(it->str(), kBothOptions), nullptr) << it->str();
    }
  }
  EXPECT_GE(named, 20);
}

}  // namespace
}  // namespace voxgi::app

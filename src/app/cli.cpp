#include "app/cli.h"

#include <cstdlib>
#include <filesystem>

#include "app/cli_options.h"

namespace voxgi::app {
std::string versionText() {
  return std::string("voxgi ") + VOXGI_VERSION;
}

std::string defaultScenePath() {
  if (const char* env = std::getenv("VOXGI_SCENE_DIR"))
    return (std::filesystem::path(env) / "cornell_room" / "cornell_room.gltf").string();
  return std::string(VOXGI_SCENE_DIR) + "/cornell_room/cornell_room.gltf";
}

std::string mainHelp() {
  return "voxgi - voxel global illumination on any OpenGL 4.5 device\n"
         "\n"
         "usage: voxgi <command> [options]\n"
         "\n"
         "commands:\n"
         "  render [SCENE]   render a glTF scene headless to PNG/EXR (default: the Cornell room)\n"
         "  view [SCENE]     open a window: fly camera, mode keys, panel, shader hot reload\n"
         "  bench [SCENE]    per-stage timings (medians) for a list of voxel resolutions\n"
         "  compare TEST REF error metrics of a linear image against a reference\n"
         "  check SCENE      load a glTF scene as render would, without a GL context\n"
         "\n"
         "  An option's value follows it as the next word or after '=' (--size=640x360).\n"
         "  voxgi --help, voxgi render|view|bench|compare|check --help, voxgi --version\n";
}

std::string benchHelp() {
  return "usage: voxgi bench [SCENE] [options]\n"
         "\n"
         "Renders --frames frames (default 5) after one warm-up frame, re-voxelizing every\n"
         "frame, and prints the median time of each stage, one row per grid resolution.\n"
         "\n"
         "options:\n"
         "  --voxels N,M,...  grid resolutions, 32..512 (default 128,256)\n"
         "  --json FILE       write the results as JSON\n"
         "  --mode, --size, --frames, --backend, --exposure, --tonemap, --small-triangles,\n"
         "  --verbose, --quiet\n"
         "                    as for render (default mode points, size 256x256)\n";
}

std::string renderHelp() {
  return "usage: voxgi render [SCENE.gltf|SCENE.glb] [options]\n"
         "\n"
         "Renders SCENE (default: the built-in Cornell room) and prints per-stage timings.\n"
         "\n"
         "options:\n" +
         cliOptionsHelp(kRenderOption, OptionSection::kGeneral) +
         "  -h, --help        this text\n"
         "\n"
         "rtgi and dvr:\n" +
         cliOptionsHelp(kRenderOption, OptionSection::kRtgi) +
         "\n"
         "pathtrace:\n" +
         cliOptionsHelp(kRenderOption, OptionSection::kPathtrace) +
         "\n"
         "Exit status: 0 on success, 1 on bad input or a failed render, 2 on a usage error.\n";
}

std::string viewHelp() {
  return "usage: voxgi view [SCENE.gltf|SCENE.glb] [options]\n"
         "\n"
         "Opens SCENE (default: the built-in Cornell room) in a window (GLFW, GL 4.5 core)\n"
         "with a panel of the mode's knobs, the effect plan, per-stage timings and shader\n"
         "state. Shaders are reloaded when a file under the shader folder changes\n"
         "($VOXGI_SHADER_DIR, default: the source tree's shaders/); a broken file shows\n"
         "its error in the panel while the last good program keeps running.\n"
         "\n"
         "keys:\n"
         "  W A S D / Q E     move / down, up (Shift faster, Ctrl slower); speed from the\n"
         "                    scene's size\n"
         "  right mouse drag  look (or left drag outside the panel)\n"
         "  1 2 3 4 5 6       mode: raster, points, dvr, rtgi, pathtrace, reserved (a mode\n"
         "                    this build lacks says so in the panel and the log)\n"
         "  + -               exposure up / down half a stop\n"
         "  t                 tonemap operator clamp <-> aces\n"
         "  r                 camera back to the start (the glTF camera)\n"
         "  p, F12            screenshot: voxgi-DATE-TIME-N.png (display) + .exr (linear),\n"
         "                    never overwriting an earlier one\n"
         "  m                 rtgi's work mask (with a frame budget) in place of the image\n"
         "  n                 rtgi's denoiser on / off\n"
         "  tab, F1           panel on / off\n"
         "  esc               quit\n"
         "\n"
         "options:\n" +
         cliOptionsHelp(kViewOption, OptionSection::kGeneral) +
         "  -h, --help        this text\n"
         "\n"
         "Closing the window, esc, Ctrl-C (SIGINT) and SIGTERM end the run cleanly.\n"
         "Exit status: 0 on success, 1 on bad input or a GL error, 2 on a usage error.\n";
}

std::string compareHelp() {
  return "usage: voxgi compare TEST REF [--json] [--blocks N]\n"
         "\n"
         "Error metrics of image TEST against reference REF (same size and channel count;\n"
         "EXR for linear radiance), over the colour channels:\n"
         "  rmse                  root mean square error\n"
         "  rel_mse               mean of (t - r)^2 / (r^2 + 0.01)\n"
         "  psnr                  10 log10(1 / MSE) in dB: the peak is display white (1.0)\n"
         "  ssim                  mean SSIM (Wang et al. 2004; 11x11 Gaussian window, sigma\n"
         "                        1.5) of luminance clamped to the display range [0, 1]\n"
         "  mean_luminance_ratio  mean luminance of TEST / mean luminance of REF\n"
         "\n"
         "options:\n"
         "  --json            print the metrics as one JSON object\n"
         "  --blocks N        also cut the images into N x N-pixel blocks and compare\n"
         "                    mean luminance block by block (blocks darker than 1% of\n"
         "                    the reference's mean are left out): the lowest and highest\n"
         "                    ratio of TEST to REF, where they are, and the share of\n"
         "                    blocks off by more than 3% and 10% (block_* in the JSON)\n"
         "  -h, --help        this text\n"
         "\n"
         "Exit status: 0 on success, 1 on bad input, 2 on a usage error.\n";
}

std::string checkHelp() {
  return "usage: voxgi check SCENE\n"
         "\n"
         "Loads SCENE (.gltf or .glb) with every check render makes, prints one line\n"
         "(triangles, materials, textures, lights) and any warnings, and exits. No GL\n"
         "context is created.\n"
         "\n"
         "Exit status: 0 when the scene loads, 1 on bad input (one line naming the file\n"
         "and the problem), 2 on a usage error.\n";
}

namespace {

// One option of `command` and its value from the arguments after args[*i] (moving
// *i past it): false if `a` is none of its options.
bool parseTableOption(const std::vector<std::string>& args, size_t* i, OptionCommands command,
                      const OptionTargets& to) {
  const std::string& a = args[*i];
  const CliOption* option = findCliOption(a, command);
  if (!option) return false;
  std::string value;
  if (option->value) {
    if (*i + 1 >= args.size()) throw UsageError(a + ": needs a value");
    value = args[++*i];
  }
  option->apply(to, value);
  return true;
}

Invocation parseView(const std::vector<std::string>& args) {
  Invocation inv;
  inv.command = Command::kView;
  ViewOptions& o = inv.view;
  o.render.width = 960;
  o.render.height = 540;
  // Interactive by default: rtgi holds 30 fps by tracing a share of the pixels, and
  // a restarted accumulation (every camera move) costs no more than other frames.
  o.render.targetFps = kViewTargetFps;
  o.render.rtgi.sparseStart = true;
  o.render.rtgi.denoise = true;  // on a software GL the viewer starts it off (viewer.h)
  const OptionTargets to{&o.render, nullptr, &o};
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "view";
      return inv;
    } else if (parseTableOption(args, &i, kViewOption, to)) {
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "' (see voxgi view --help)");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      throw UsageError("more than one scene given ('" + o.scene + "' and '" + a + "')");
    }
  }
  return inv;
}

Invocation parseCheck(const std::vector<std::string>& args) {
  Invocation inv;
  inv.command = Command::kCheck;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "check";
      return inv;
    }
    if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option '" + a + "' (see voxgi check --help)");
    if (!inv.check.scene.empty())
      throw UsageError("more than one scene given ('" + inv.check.scene + "' and '" + a + "')");
    inv.check.scene = a;
  }
  if (inv.check.scene.empty()) throw UsageError("check: needs a SCENE");
  return inv;
}

Invocation parseCompare(const std::vector<std::string>& args) {
  Invocation inv;
  inv.command = Command::kCompare;
  std::vector<std::string> files;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "compare";
      return inv;
    } else if (a == "--json") {
      inv.compare.json = true;
    } else if (a == "--blocks") {
      if (i + 1 >= args.size()) throw UsageError("--blocks: needs a value");
      inv.compare.blocks = parseIntValue("--blocks", args[++i], 1, 4096);
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "' (see voxgi compare --help)");
    } else {
      files.push_back(a);
    }
  }
  if (files.size() != 2)
    throw UsageError(strf("compare: needs two images, TEST and REF (got %zu)", files.size()));
  inv.compare.test = files[0];
  inv.compare.reference = files[1];
  return inv;
}

// "128,256": the voxel grid resolutions `bench` measures.
std::vector<int> parseVoxelList(const std::string& v) {
  std::vector<int> voxels;
  size_t start = 0;
  while (start <= v.size()) {
    const size_t comma = v.find(',', start);
    const std::string item =
        v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    voxels.push_back(parseIntValue("--voxels", item, 32, 512));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return voxels;
}

// The render options, plus a list of resolutions and a JSON file.
Invocation parseBench(const std::vector<std::string>& args) {
  Invocation inv;
  std::vector<std::string> rest = {"render",  "--mode",   "points", "--size",
                                   "256x256", "--frames", "5"};
  BenchOptions bench;
  bench.voxels = {128, 256};
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      inv.helpTopic = "bench";
      return inv;
    }
    if (a == "--voxels" || a == "--json") {
      if (i + 1 >= args.size()) throw UsageError(a + ": needs a value");
      const std::string v = args[++i];
      if (a == "--json")
        bench.json = v;
      else
        bench.voxels = parseVoxelList(v);
      continue;
    }
    if (a == "--out" || a == "--stats" || a == "--revoxelize")
      throw UsageError(a + ": not a bench option (see voxgi bench --help)");
    rest.push_back(a);
  }
  bench.render = parseCommandLine(rest).render;
  inv.bench = bench;
  inv.command = Command::kBench;
  return inv;
}

Invocation parseRender(const std::vector<std::string>& args) {
  Invocation inv;
  inv.command = Command::kRender;
  RenderOptions& o = inv.render;
  o.render.width = 512;
  o.render.height = 512;
  // rtgi's image is denoised: closer to the path tracer at every frame count measured
  // (docs/rtgi.md, "Denoiser").
  o.render.rtgi.denoise = true;
  const OptionTargets to{&o.render, &o, nullptr};
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "render";
      return inv;
    } else if (parseTableOption(args, &i, kRenderOption, to)) {
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "' (see voxgi render --help)");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      throw UsageError("more than one scene given ('" + o.scene + "' and '" + a + "')");
    }
  }
  if (o.frames == 0) o.frames = render::defaultFrames(o.render.mode);
  if (o.lookFrom.has_value() != o.lookAt.has_value())
    throw UsageError("--look-from and --look-at go together");
  if (o.lookFrom && *o.lookFrom == *o.lookAt)
    throw UsageError("--look-from and --look-at: the same point");
  return inv;
}

// GNU style: an option's value may follow it after '=' ("--size=640x360"), which
// also passes a value that starts with '-' ("--look-at=-0.4,0.35,-0.5").
std::vector<std::string> splitOptionValues(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  out.reserve(args.size());
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const size_t eq = a.find('=');
    if (i > 0 && a.rfind("--", 0) == 0 && eq != std::string::npos && eq > 2) {
      out.push_back(a.substr(0, eq));
      out.push_back(a.substr(eq + 1));
    } else {
      out.push_back(a);
    }
  }
  return out;
}

}  // namespace

Invocation parseCommandLine(const std::vector<std::string>& original) {
  const std::vector<std::string> args = splitOptionValues(original);
  Invocation inv;
  if (args.empty()) return inv;
  const std::string& cmd = args[0];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") return inv;
  if (cmd == "--version" || cmd == "-V") {
    inv.command = Command::kVersion;
    return inv;
  }
  if (cmd == "view") return parseView(args);
  if (cmd == "bench") return parseBench(args);
  if (cmd == "compare") return parseCompare(args);
  if (cmd == "check") return parseCheck(args);
  if (cmd != "render") {
    if (!cmd.empty() && cmd[0] == '-')
      throw UsageError("unknown option '" + cmd + "' (see voxgi --help)");
    throw UsageError("unknown command '" + cmd + "' (see voxgi --help)");
  }
  return parseRender(args);
}

}  // namespace voxgi::app

#include "app/cli.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace voxgi::app {
namespace {

int parseInt(const std::string& flag, const std::string& v, int lo, int hi) {
  int x = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), x);
  if (r.ec != std::errc() || r.ptr != v.data() + v.size())
    throw UsageError(strf("%s: '%s' is not an integer", flag.c_str(), v.c_str()));
  if (x < lo || x > hi)
    throw UsageError(strf("%s: %d is outside [%d, %d]", flag.c_str(), x, lo, hi));
  return x;
}

float parseFloat(const std::string& flag, const std::string& v) {
  char* end = nullptr;
  const float x = std::strtof(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(x))
    throw UsageError(strf("%s: '%s' is not a finite number", flag.c_str(), v.c_str()));
  return x;
}

void parseSize(const std::string& v, int* w, int* h) {
  const size_t x = v.find('x');
  if (x == std::string::npos)
    throw UsageError("--size: expected WxH, e.g. 640x360, got '" + v + "'");
  // Up to 10^6 per side parses; what the GL can hold is checked once a context exists.
  *w = parseInt("--size", v.substr(0, x), 1, 1000000);
  *h = parseInt("--size", v.substr(x + 1), 1, 1000000);
}

}  // namespace

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
         "  compare TEST REF error metrics of a linear image against a reference\n"
         "\n"
         "  voxgi --help, voxgi render --help, voxgi compare --help, voxgi --version\n";
}

std::string renderHelp() {
  return "usage: voxgi render [SCENE.gltf|SCENE.glb] [options]\n"
         "\n"
         "Renders SCENE (default: the built-in Cornell room) and prints per-stage timings.\n"
         "\n"
         "options:\n"
         "  --mode M          render mode: " +
         render::availableModes() +
         " (default raster)\n"
         "  --size WxH        image size in pixels (default 512x512)\n"
         "  --out FILE        write the image; .png is tonemapped sRGB 8-bit, .exr linear\n"
         "                    float radiance. Repeat to write both. An existing file is\n"
         "                    replaced only once the new one is complete.\n"
         "  --stats FILE      write timings and scene facts as JSON\n"
         "  --frames N        frames to render; timings are medians (default 1); a\n"
         "                    pathtrace frame is a whole image of --spp samples\n"
         "  --backend B       egl (default; surfaceless Mesa or an NVIDIA device), osmesa,\n"
         "                    or glfw (a hidden window; needs a display)\n"
         "  --exposure E      linear exposure before tonemapping (default 1)\n"
         "  --tonemap T       clamp (default) or aces\n"
         "  --verbose         log GL debug output and loader details\n"
         "  --quiet           print errors only\n"
         "  -h, --help        this text\n"
         "\n"
         "pathtrace:\n"
         "  --spp N           samples per pixel of one frame (default 64: enough to judge\n"
         "                    an image; the references of tools/sweep use 2048)\n"
         "  --seed S          random seed; the same seed gives the same image (default 0)\n"
         "  --max-depth D     longest path, Mitsuba's convention: 1 = emitters seen directly,\n"
         "                    2 = direct light (default 8: up to 7 bounces)\n"
         "  --rr-depth D      Russian roulette from this depth on (default 5)\n"
         "  --no-progress     no progress bar (shown on stderr only when it is a terminal)\n"
         "\n"
         "Exit status: 0 on success, 1 on bad input or a failed render, 2 on a usage error.\n";
}

std::string compareHelp() {
  return "usage: voxgi compare TEST REF [--json]\n"
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
         "  -h, --help        this text\n"
         "\n"
         "Exit status: 0 on success, 1 on bad input, 2 on a usage error.\n";
}

namespace {

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

}  // namespace

Invocation parseCommandLine(const std::vector<std::string>& args) {
  Invocation inv;
  if (args.empty()) return inv;
  const std::string& cmd = args[0];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") return inv;
  if (cmd == "--version" || cmd == "-V") {
    inv.command = Command::kVersion;
    return inv;
  }
  if (cmd == "compare") return parseCompare(args);
  if (cmd != "render") {
    if (!cmd.empty() && cmd[0] == '-')
      throw UsageError("unknown option '" + cmd + "' (see voxgi --help)");
    throw UsageError("unknown command '" + cmd + "' (see voxgi --help)");
  }
  inv.command = Command::kRender;
  RenderOptions& o = inv.render;
  o.render.width = 512;
  o.render.height = 512;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError(a + ": needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "render";
      return inv;
    } else if (a == "--mode") {
      const std::string m = value();
      auto mode = render::parseMode(m);
      if (!mode)
        throw UsageError("--mode: unknown mode '" + m +
                         "' (available: " + render::availableModes() + ")");
      o.render.mode = *mode;
    } else if (a == "--size") {
      parseSize(value(), &o.render.width, &o.render.height);
    } else if (a == "--out" || a == "-o") {
      o.outputs.push_back(value());
    } else if (a == "--stats") {
      o.stats = value();
    } else if (a == "--frames") {
      o.frames = parseInt("--frames", value(), 1, 100000);
    } else if (a == "--backend") {
      const std::string b = value();
      auto backend = gl::parseBackend(b);
      if (!backend) throw UsageError("--backend: unknown backend '" + b + "' (egl, osmesa, glfw)");
      o.backend = *backend;
    } else if (a == "--exposure") {
      o.render.tonemap.exposure = parseFloat("--exposure", value());
    } else if (a == "--tonemap") {
      const std::string t = value();
      auto op = render::parseTonemap(t);
      if (!op) throw UsageError("--tonemap: unknown operator '" + t + "' (clamp, aces)");
      o.render.tonemap.op = *op;
    } else if (a == "--spp") {
      o.render.spp = parseInt("--spp", value(), 1, 1 << 20);
    } else if (a == "--seed") {
      o.render.pathtrace.seed = static_cast<uint32_t>(parseInt("--seed", value(), 0, 2147483647));
    } else if (a == "--max-depth") {
      o.render.pathtrace.maxDepth = parseInt("--max-depth", value(), 1, 1024);
    } else if (a == "--rr-depth") {
      o.render.pathtrace.rrDepth = parseInt("--rr-depth", value(), 1, 1024);
    } else if (a == "--no-progress") {
      o.progress = false;
    } else if (a == "--verbose" || a == "-v") {
      o.verbose = true;
    } else if (a == "--quiet" || a == "-q") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "' (see voxgi render --help)");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      throw UsageError("more than one scene given ('" + o.scene + "' and '" + a + "')");
    }
  }
  return inv;
}

}  // namespace voxgi::app

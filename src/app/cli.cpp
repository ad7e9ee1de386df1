#include "app/cli.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <utility>

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

glm::vec3 parseVec3(const std::string& flag, const std::string& v) {
  glm::vec3 out(0.0f);
  size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t comma = v.find(',', start);
    if ((k < 2) != (comma != std::string::npos))
      throw UsageError(flag + ": '" + v + "' is not X,Y,Z");
    out[k] = parseFloat(flag, v.substr(start, comma == std::string::npos ? comma : comma - start));
    start = comma + 1;
  }
  return out;
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

namespace {

// The render help: usage and the options every mode takes.
std::string renderHelpGeneral() {
  return "usage: voxgi render [SCENE.gltf|SCENE.glb] [options]\n"
         "\n"
         "Renders SCENE (default: the built-in Cornell room) and prints per-stage timings.\n"
         "\n"
         "options:\n"
         "  --mode M          render mode: " +
         render::availableModes() +
         " (default rtgi)\n"
         "  --size WxH        image size in pixels (default 512x512)\n"
         "  --out FILE        write the image; .png is tonemapped sRGB 8-bit, .exr linear\n"
         "                    float radiance. Repeat to write both. An existing file is\n"
         "                    replaced only once the new one is complete.\n"
         "  --stats FILE      write timings and scene facts as JSON\n"
         "  --frames N        frames to render; timings are medians. rtgi accumulates\n"
         "                    them into one image (default 64, a converged image); other\n"
         "                    modes render each whole (default 1); a pathtrace frame is\n"
         "                    an image of --spp samples\n"
         "  --voxels N        voxel grid resolution, N^3 voxels, 32..512 (default 128);\n"
         "                    used by modes that voxelize (points, dvr, rtgi)\n"
         "  --revoxelize      voxelize every frame instead of once per scene (animated scenes)\n"
         "  --small-triangles P  voxelize triangles that span at most 6x6 voxels in a\n"
         "                    compute pass (compute, the default) or rasterize every\n"
         "                    triangle (raster); the grids agree to a few voxels\n"
         "  --time T          animated scenes: pose of the first frame, seconds (default 0)\n"
         "  --look-from X,Y,Z, --look-at X,Y,Z\n"
         "                    another viewpoint than the file's camera, in the file's\n"
         "                    coordinates (same field of view; every mode, so a reference\n"
         "                    can be rendered there too)\n"
         "  --fps F           animated scenes: frame f shows T + f/F (default 30); meshes,\n"
         "                    lights and an animated camera (a camera path) move; the\n"
         "                    image is the last frame. After the animation's end the\n"
         "                    last pose stays\n"
         "  --loop            animated scenes: time wraps around the end instead\n"
         "  --backend B       egl (default; surfaceless Mesa or an NVIDIA device), osmesa,\n"
         "                    or glfw (a hidden window; needs a display)\n"
         "  --exposure E      linear exposure before tonemapping (default 1)\n"
         "  --tonemap T       clamp (default) or aces\n"
         "  --ambient A       raster: uniform ambient radiance A (grey, >= 0) times the\n"
         "                    albedo and the occlusion texture (default 0: none)\n"
         "  --effects LIST    override the effect plan, e.g. +specular,-shadows (names:\n"
         "                    shadows, emission, indirect, specular, textures, alpha,\n"
         "                    colors, normalmaps, animation, or all). The plan comes from\n"
         "                    the scene: an effect it lacks is skipped (stage absent,\n"
         "                    shader code compiled out) and printed with its reason;\n"
         "                    forcing one on makes it run\n"
         "  --verbose         log GL debug output and loader details\n"
         "  --quiet           print errors only\n"
         "  -h, --help        this text\n";
}

std::string renderHelpRtgi() {
  return "\n"
         "rtgi and dvr:\n"
         "  --bounces N       diffuse bounces of indirect light: all (default) or 0..16.\n"
         "                    The pixel's ray gives one, the voxels hold the rest; with\n"
         "                    all, the voxels' light feeds back into itself as it refines;\n"
         "                    a finite N >= 2 keeps its first estimate (the N-bounce chain)\n"
         "  --no-jitter       every frame samples the pixel's centre (default: a sub-pixel\n"
         "                    offset per frame, so accumulation antialiases edges)\n"
         "  --refine-rays N   rays per voxel and frame that refine the voxels' light while\n"
         "                    the scene is still (default 2; 0 keeps the first estimate)\n"
         "  --interleave N    each pixel traces new rays every N-th frame (1, 2, 4, 8, 16;\n"
         "                    default 1): N times less work per frame, N times more\n"
         "                    frames to converge; the first frame traces every pixel\n"
         "  --target-fps F    hold F frames per second: a PID controller on the frame time\n"
         "                    sets the share of pixels that trace each frame (at least\n"
         "                    1/16, an interleave of 16); the extra pixels are those the\n"
         "                    work mask finds noisy (edges of the noisy image, blurred);\n"
         "                    off (the default) traces as --interleave says\n"
         "  --render-scale S  rtgi renders at S times the output's width and height\n"
         "                    (0.25 to 1, default 1): G-buffer, rays, accumulation and\n"
         "                    denoiser cost about S^2 as much, and a temporal upsampler\n"
         "                    rebuilds the output from the jittered frames; a still\n"
         "                    image converges to the full-resolution one\n"
         "  --sparse-start    with interleaving or a frame budget, the first frame traces\n"
         "                    its share only, like the others; pixels that have not traced\n"
         "                    yet show their traced neighbours' light (as the viewer does)\n"
         "  --budget-select S mask (default) or uniform: how the budget picks its pixels\n"
         "  --reproject on|off  on (default): a camera move (a camera path, the viewer)\n"
         "                    keeps the image, each pixel's history following its surface\n"
         "                    (dropped where the view reveals another); off: a move\n"
         "                    restarts accumulation\n"
         "  --history-cap N   while the camera moves, a pixel's history counts at most N\n"
         "                    frames (default 16; glossy surfaces 4, mirrors none), so\n"
         "                    light follows the view; a still camera accumulates on\n"
         "  --light-reuse on|off  on (default): with many emitters, each pixel's emitter\n"
         "                    sample is resampled with its neighbours' (ReSTIR DI);\n"
         "                    off: its own candidates only\n"
         "  --denoise on|off  on (default): the image is each pixel's running mean\n"
         "                    filtered by a variance-guided, edge-avoiding wavelet (SVGF),\n"
         "                    as strongly as its measured noise asks, so less and less as\n"
         "                    a still image converges; off: the running mean itself\n"
         "  --voxel-reflections  mirrors and glossy surfaces reflect the voxels they see\n"
         "                    (default: the exact triangles, through a BVH, lit exactly)\n"
         "  --voxel-rays      shadow and indirect rays march the voxels, which stop them\n"
         "                    too early near contacts (default: they hit the exact\n"
         "                    triangles, through a BVH; the voxels give only the light\n"
         "                    at an indirect ray's hit). A scene whose meshes move\n"
         "                    always marches the voxels\n"
         "  --primary P       how the G-buffer finds what each pixel shows: raster draws\n"
         "                    every triangle; rays casts one ray a pixel through the BVH,\n"
         "                    a cost that grows with the log of the triangle count; auto\n"
         "                    (default): rays on a software GL for scenes with more\n"
         "                    than 4 triangles a pixel, else raster\n"
         "  --indirect M      how diffuse indirect light is gathered: rays (default), one\n"
         "                    random ray per pixel and frame, averaged by accumulation; or\n"
         "                    cones, six cones through the octree's filtered levels (voxel\n"
         "                    cone tracing): the same smooth light every frame, biased\n"
         "                    (it leaks through walls thinner than a cone's footprint)\n"
         "  --out-mask FILE   write the last work mask (grey PNG, or EXR)\n"
         "  --inject-rays N   shadow rays per voxel towards emissive surfaces in the first\n"
         "                    estimate of the voxels' light (default 4; refinement adds more)\n"
         "  --bounce-rays N   rays per voxel for each voxel bounce of that estimate (default 4)\n"
         "  --seed S          random seed (as for pathtrace)\n";
}

std::string renderHelpPathtrace() {
  return "\n"
         "pathtrace:\n"
         "  --spp N           samples per pixel of one frame (default 64: enough to judge\n"
         "                    an image; the references of tools/sweep use 2048)\n"
         "  --seed S          random seed; the same seed gives the same image (default 0)\n"
         "  --max-depth D     longest path, Mitsuba's convention: 1 = emitters seen directly,\n"
         "                    2 = direct light (default 8: up to 7 bounces)\n"
         "  --rr-depth D      Russian roulette from this depth on (default 5)\n"
         "  --pt-device D     auto (default), cpu or gl: cpu traces with Embree on every core,\n"
         "                    gl in a compute shader; auto takes cpu when GL is a software\n"
         "                    renderer (llvmpipe, softpipe) and gl on a GPU\n"
         "  --pt-threads N    cpu device: worker threads (default: one per core)\n"
         "  --no-progress     no progress bar (shown on stderr only when it is a terminal)\n";
}

}  // namespace

std::string renderHelp() {
  return renderHelpGeneral() + renderHelpRtgi() + renderHelpPathtrace() +
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
         "options:\n"
         "  --mode M          start mode: " +
         render::availableModes() +
         " (default rtgi)\n"
         "  --size WxH        window size at start (default 960x540); rendering follows\n"
         "                    the window's framebuffer\n"
         "  --exposure E      linear exposure before tonemapping (default 1)\n"
         "  --tonemap T       clamp (default) or aces\n"
         "  --frames N        render N frames, then exit (default: until the window closes)\n"
         "  --screenshot FILE at the end of the run write FILE.png and FILE.exr (FILE may end\n"
         "                    in .png or .exr); an existing file is replaced once the new one\n"
         "                    is complete\n"
         "  --screenshot-dir D  where the screenshot key writes (default: current folder)\n"
         "  --keys SCRIPT     press keys at given frames: FRAME:KEY,... with KEY one of\n"
         "                    1-6 + - t r p m n tab esc, e.g. --keys 10:2,20:1,25:+\n"
         "  --stats FILE      at exit write JSON: frames, timings, mode, reloads ok and\n"
         "                    failed, the last reload error, screenshots, gl_errors\n"
         "  --effects LIST    override the effect plan (see voxgi render --help), e.g.\n"
         "                    +specular,-shadows; the panel shows the plan\n"
         "  --voxels N, --revoxelize, --small-triangles P, --bounces N, --inject-rays N,\n"
         "  --bounce-rays N, --refine-rays N, --interleave N, --budget-select S,\n"
         "  --reproject on|off, --history-cap N, --light-reuse on|off, --indirect M,\n"
         "  --ambient A\n"
         "                    as for voxgi render\n"
         "  --denoise on|off  the image shown is denoised (see voxgi render --help); on by\n"
         "                    default on a hardware GL, off on a software one (llvmpipe),\n"
         "                    where it costs more than a frame; the n key toggles it\n"
         "  --target-fps F    rtgi holds F frames per second by tracing a share of the\n"
         "                    pixels each frame (default 30; off: every pixel, every\n"
         "                    frame). A camera move keeps each pixel's history where its\n"
         "                    surface stays in view (--reproject); pixels that lost it and\n"
         "                    have not traced since show their traced neighbours' light\n"
         "  --render-scale S  rtgi renders at S times the window's size and upsamples\n"
         "                    over time (see voxgi render --help): default 0.5 on a\n"
         "                    software GL (llvmpipe), 1 on a hardware one\n"
         "  --no-panel        start with the panel hidden\n"
         "  --verbose         log GL debug output and loader details\n"
         "  --quiet           print errors only\n"
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

bool parseOnOff(const std::string& option, const std::string& v) {
  if (v != "on" && v != "off") throw UsageError(option + ": expected on or off, got '" + v + "'");
  return v == "on";
}

// The value of `choices` named `v`; a usage error listing the names otherwise.
template <typename T>
T parseChoice(const std::string& option, const std::string& v,
              std::initializer_list<std::pair<const char*, T>> choices) {
  std::string names;
  for (const auto& [name, value] : choices) {
    if (v == name) return value;
    names += (names.empty() ? "" : ", ") + std::string(name);
  }
  throw UsageError(option + ": unknown '" + v + "' (" + names + ")");
}

// Mode, size and display: true if `a` was one of them.
bool parseImageSetting(const std::string& a, const std::function<std::string()>& value,
                       render::RenderSettings* rs) {
  if (a == "--mode") {
    const std::string m = value();
    auto mode = render::parseMode(m);
    if (!mode)
      throw UsageError("--mode: unknown mode '" + m + "' (available: " + render::availableModes() +
                       ")");
    rs->mode = *mode;
  } else if (a == "--size") {
    parseSize(value(), &rs->width, &rs->height);
  } else if (a == "--exposure") {
    rs->tonemap.exposure = parseFloat("--exposure", value());
  } else if (a == "--ambient") {
    rs->ambient = parseFloat("--ambient", value());
    if (rs->ambient < 0.0f) throw UsageError("--ambient: must not be negative");
  } else if (a == "--tonemap") {
    const std::string t = value();
    auto op = render::parseTonemap(t);
    if (!op) throw UsageError("--tonemap: unknown operator '" + t + "' (clamp, aces)");
    rs->tonemap.op = *op;
  } else if (a == "--no-jitter") {
    rs->jitter = false;
  } else if (a == "--effects") {
    const std::string v = value();
    try {
      scene::checkOverrides(v);
    } catch (const Error& e) {
      throw UsageError(e.what());
    }
    rs->effects += (rs->effects.empty() ? "" : ",") + v;
  } else {
    return false;
  }
  return true;
}

// The voxel grid and the octree's light: true if `a` was one of them.
bool parseVoxelSetting(const std::string& a, const std::function<std::string()>& value,
                       render::RenderSettings* rs) {
  if (a == "--voxels") {
    rs->voxels = parseInt("--voxels", value(), 32, 512);
  } else if (a == "--revoxelize") {
    rs->revoxelize = true;
  } else if (a == "--small-triangles") {
    const std::string v = value();
    if (v != "compute" && v != "raster")
      throw UsageError("--small-triangles: '" + v + "' is neither compute nor raster");
    rs->smallTrianglesInCompute = v == "compute";
  } else if (a == "--bounces") {
    const std::string v = value();
    int n = 0;
    const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
    if (v != "all" && (r.ec != std::errc() || r.ptr != v.data() + v.size() || n < 0 || n > 16))
      throw UsageError("--bounces: '" + v + "' is neither all nor an integer in [0, 16]");
    rs->octree.bounces = v == "all" ? voxel::Octree::Settings::kAllBounces : n;
  } else if (a == "--refine-rays") {
    rs->octree.refineRays = parseInt("--refine-rays", value(), 0, 1024);
  } else if (a == "--inject-rays") {
    rs->octree.injectRays = parseInt("--inject-rays", value(), 1, 1024);
  } else if (a == "--bounce-rays") {
    rs->octree.bounceRays = parseInt("--bounce-rays", value(), 1, 1024);
  } else {
    return false;
  }
  return true;
}

// rtgi's rays, history and frame budget: true if `a` was one of them.
bool parseRtgiSetting(const std::string& a, const std::function<std::string()>& value,
                      render::RenderSettings* rs) {
  using Settings = render::RtgiPass::Settings;
  if (a == "--interleave") {
    const int n = parseInt("--interleave", value(), 1, 16);
    if ((n & (n - 1)) != 0) throw UsageError("--interleave: must be 1, 2, 4, 8 or 16");
    rs->rtgi.interleave = n;
  } else if (a == "--target-fps") {
    const std::string v = value();
    rs->targetFps = v == "off" ? 0.0 : parseFloat("--target-fps", v);
    if (v != "off" && !(rs->targetFps > 0.0 && rs->targetFps <= 1000.0))
      throw UsageError("--target-fps: must be in (0, 1000], or off");
  } else if (a == "--render-scale") {
    const double scale = parseFloat("--render-scale", value());
    if (!(scale >= render::kMinRenderScale && scale <= render::kMaxRenderScale))
      throw UsageError("--render-scale: must be in [0.25, 1]");
    rs->renderScale = static_cast<float>(scale);
  } else if (a == "--sparse-start") {
    rs->rtgi.sparseStart = true;
  } else if (a == "--voxel-reflections") {
    rs->rtgi.exactReflections = false;
  } else if (a == "--voxel-rays") {
    rs->rtgi.exactRays = false;
  } else if (a == "--primary") {
    rs->rtgi.primary = parseChoice<Settings::Primary>("--primary", value(),
                                                      {{"auto", Settings::Primary::kAuto},
                                                       {"raster", Settings::Primary::kRaster},
                                                       {"rays", Settings::Primary::kRays}});
  } else if (a == "--indirect") {
    rs->rtgi.indirectMethod = parseChoice<Settings::IndirectMethod>(
        "--indirect", value(),
        {{"rays", Settings::IndirectMethod::kRays}, {"cones", Settings::IndirectMethod::kCones}});
  } else if (a == "--reproject") {
    rs->rtgi.reproject = parseOnOff("--reproject", value());
  } else if (a == "--light-reuse") {
    rs->rtgi.reuseLights = parseOnOff("--light-reuse", value());
  } else if (a == "--denoise") {
    rs->rtgi.denoise = parseOnOff("--denoise", value());
  } else if (a == "--history-cap") {
    rs->rtgi.historyCap = parseInt("--history-cap", value(), 1, 1 << 20);
  } else if (a == "--budget-select") {
    rs->rtgi.select = parseChoice<Settings::Select>(
        "--budget-select", value(),
        {{"mask", Settings::Select::kMask}, {"uniform", Settings::Select::kUniform}});
  } else {
    return false;
  }
  return true;
}

// The options `render` and `view` share (mode, size, tonemap, voxels); true if `a`
// was one of them. `value` returns the option's argument.
bool parseRenderSetting(const std::string& a, const std::function<std::string()>& value,
                        render::RenderSettings* rs) {
  return parseImageSetting(a, value, rs) || parseVoxelSetting(a, value, rs) ||
         parseRtgiSetting(a, value, rs);
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
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError(a + ": needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      inv.command = Command::kHelp;
      inv.helpTopic = "view";
      return inv;
    } else if (parseRenderSetting(a, value, &o.render)) {
      if (a == "--denoise") o.denoiseChosen = true;
      if (a == "--render-scale") o.renderScaleChosen = true;
    } else if (a == "--frames") {
      o.frames = parseInt("--frames", value(), 1, 10000000);
    } else if (a == "--screenshot") {
      o.screenshot = value();
    } else if (a == "--screenshot-dir") {
      o.screenshotDir = value();
    } else if (a == "--keys") {
      try {
        o.keys = parseKeyScript(value());
      } catch (const UsageError&) {
        throw;
      } catch (const Error& e) {
        throw UsageError(e.what());
      }
    } else if (a == "--stats") {
      o.stats = value();
    } else if (a == "--no-panel") {
      o.panel = false;
    } else if (a == "--verbose" || a == "-v") {
      o.verbose = true;
    } else if (a == "--quiet" || a == "-q") {
      o.quiet = true;
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
      inv.compare.blocks = parseInt("--blocks", args[++i], 1, 4096);
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
    voxels.push_back(parseInt("--voxels", item, 32, 512));
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

// The path tracer's samples, seed, depths and device: true if `a` was one of them.
bool parsePathtraceOption(const std::string& a, const std::function<std::string()>& value,
                          render::RenderSettings& rs) {
  if (a == "--spp") {
    rs.spp = parseInt("--spp", value(), 1, 1 << 20);
  } else if (a == "--seed") {
    const auto seed = static_cast<uint32_t>(parseInt("--seed", value(), 0, 2147483647));
    rs.pathtrace.seed = seed;
    rs.rtgi.seed = seed;
    rs.octree.seed = seed;
  } else if (a == "--max-depth") {
    rs.pathtrace.maxDepth = parseInt("--max-depth", value(), 1, 1024);
  } else if (a == "--rr-depth") {
    rs.pathtrace.rrDepth = parseInt("--rr-depth", value(), 1, 1024);
  } else if (a == "--pt-device") {
    const std::string d = value();
    if (d != "auto" && d != "cpu" && d != "gl")
      throw UsageError("--pt-device: expected auto, cpu or gl, got '" + d + "'");
    rs.pathtrace.device = render::parsePathtraceDevice(d);
  } else if (a == "--pt-threads") {
    rs.pathtrace.threads = parseInt("--pt-threads", value(), 1, 1024);
  } else {
    return false;
  }
  return true;
}

// The options only `render` takes (outputs, frames, backend, animation time, the
// path tracer's): true if `a` was one of them.
bool parseRenderOnlyOption(const std::string& a, const std::function<std::string()>& value,
                           RenderOptions& o) {
  if (a == "--out" || a == "-o") {
    o.outputs.push_back(value());
  } else if (a == "--stats") {
    o.stats = value();
  } else if (a == "--out-mask") {
    o.maskOutput = value();
    o.render.rtgi.keepMask = true;
  } else if (a == "--frames") {
    o.frames = parseInt("--frames", value(), 1, 100000);
  } else if (a == "--backend") {
    const std::string b = value();
    auto backend = gl::parseBackend(b);
    if (!backend) throw UsageError("--backend: unknown backend '" + b + "' (egl, osmesa, glfw)");
    o.backend = *backend;
  } else if (a == "--time") {
    o.time = parseFloat("--time", value());
  } else if (a == "--fps") {
    o.fps = parseFloat("--fps", value());
    if (!(o.fps > 0.0)) throw UsageError("--fps: must be positive");
  } else if (a == "--loop") {
    o.loop = true;
  } else if (a == "--look-from") {
    o.lookFrom = parseVec3("--look-from", value());
  } else if (a == "--look-at") {
    o.lookAt = parseVec3("--look-at", value());
  } else if (a == "--no-progress") {
    o.progress = false;
  } else if (a == "--verbose" || a == "-v") {
    o.verbose = true;
  } else if (a == "--quiet" || a == "-q") {
    o.quiet = true;
  } else {
    return parsePathtraceOption(a, value, o.render);
  }
  return true;
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
    } else if (parseRenderSetting(a, value, &o.render) || parseRenderOnlyOption(a, value, o)) {
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

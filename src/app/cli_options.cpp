#include "app/cli_options.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <utility>

#include "app/viewer_input.h"
#include "light_tree_shared.h"

namespace voxgi::app {

int parseIntValue(const std::string& flag, const std::string& v, int lo, int hi) {
  int x = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), x);
  if (r.ec != std::errc() || r.ptr != v.data() + v.size())
    throw UsageError(strf("%s: '%s' is not an integer", flag.c_str(), v.c_str()));
  if (x < lo || x > hi)
    throw UsageError(strf("%s: %d is outside [%d, %d]", flag.c_str(), x, lo, hi));
  return x;
}

namespace {

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
  *w = parseIntValue("--size", v.substr(0, x), 1, 1000000);
  *h = parseIntValue("--size", v.substr(x + 1), 1, 1000000);
}

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

using Targets = OptionTargets;
using Rtgi = render::RtgiPass::Settings;
constexpr auto kGeneral = OptionSection::kGeneral;
constexpr auto kRtgi = OptionSection::kRtgi;
constexpr auto kPathtrace = OptionSection::kPathtrace;
constexpr const char* kVerboseHelp = "log GL debug output and loader details";
constexpr const char* kQuietHelp = "print errors only";

// "{modes}" in a help text stands for the modes this build has.
const std::vector<CliOption> kOptions = {
    // Image, display and scene: both commands.
    {"--mode", nullptr, "M", kBothOptions, kGeneral, "render mode: {modes} (default rtgi)",
     "start mode: {modes} (default rtgi)",
     [](const Targets& to, const std::string& v) {
       auto mode = render::parseMode(v);
       if (!mode)
         throw UsageError("--mode: unknown mode '" + v +
                          "' (available: " + render::availableModes() + ")");
       to.settings->mode = *mode;
     }},
    {"--size", nullptr, "WxH", kBothOptions, kGeneral, "image size in pixels (default 512x512)",
     "window size at start (default 960x540); rendering follows\n"
     "the window's framebuffer",
     [](const Targets& to, const std::string& v) {
       parseSize(v, &to.settings->width, &to.settings->height);
     }},
    {"--out", "-o", "FILE", kRenderOption, kGeneral,
     "write the image; .png is tonemapped sRGB 8-bit, .exr linear\n"
     "float radiance. Repeat to write both. An existing file is\n"
     "replaced only once the new one is complete.",
     nullptr, [](const Targets& to, const std::string& v) { to.render->outputs.push_back(v); }},
    {"--stats", nullptr, "FILE", kRenderOption, kGeneral, "write timings and scene facts as JSON",
     nullptr, [](const Targets& to, const std::string& v) { to.render->stats = v; }},
    {"--stats", nullptr, "FILE", kViewOption, kGeneral,
     "at exit write JSON: frames, timings, mode, reloads ok and\n"
     "failed, the last reload error, screenshots, gl_errors",
     nullptr, [](const Targets& to, const std::string& v) { to.view->stats = v; }},
    {"--frames", nullptr, "N", kRenderOption, kGeneral,
     "frames to render; timings are medians. rtgi accumulates\n"
     "them into one image (default 64, a converged image); other\n"
     "modes render each whole (default 1); a pathtrace frame is\n"
     "an image of --spp samples",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.render->frames = parseIntValue("--frames", v, 1, 100000);
     }},
    {"--frames", nullptr, "N", kViewOption, kGeneral,
     "render N frames, then exit (default: until the window closes)", nullptr,
     [](const Targets& to, const std::string& v) {
       to.view->frames = parseIntValue("--frames", v, 1, 10000000);
     }},
    {"--screenshot", nullptr, "FILE", kViewOption, kGeneral,
     "at the end of the run write FILE.png and FILE.exr (FILE may end\n"
     "in .png or .exr); an existing file is replaced once the new one\n"
     "is complete",
     nullptr, [](const Targets& to, const std::string& v) { to.view->screenshot = v; }},
    {"--screenshot-dir", nullptr, "D", kViewOption, kGeneral,
     "where the screenshot key writes (default: current folder)", nullptr,
     [](const Targets& to, const std::string& v) { to.view->screenshotDir = v; }},
    {"--keys", nullptr, "SCRIPT", kViewOption, kGeneral,
     "press keys at given frames: FRAME:KEY,... with KEY one of\n"
     "1-6 + - t r p m n tab esc, e.g. --keys 10:2,20:1,25:+",
     nullptr,
     [](const Targets& to, const std::string& v) {
       try {
         to.view->keys = parseKeyScript(v);
       } catch (const UsageError&) {
         throw;
       } catch (const Error& e) {
         throw UsageError(e.what());
       }
     }},
    {"--voxels", nullptr, "N", kBothOptions, kGeneral,
     "voxel grid resolution, N^3 voxels, 32..512 (default 128);\n"
     "used by modes that voxelize (points, dvr, rtgi)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->voxels = parseIntValue("--voxels", v, 32, 512);
     }},
    {"--revoxelize", nullptr, nullptr, kBothOptions, kGeneral,
     "voxelize every frame instead of once per scene (animated scenes)", nullptr,
     [](const Targets& to, const std::string&) { to.settings->revoxelize = true; }},
    {"--small-triangles", nullptr, "P", kBothOptions, kGeneral,
     "voxelize triangles that span at most 6x6 voxels in a\n"
     "compute pass (compute, the default) or rasterize every\n"
     "triangle (raster); the grids agree to a few voxels",
     nullptr,
     [](const Targets& to, const std::string& v) {
       if (v != "compute" && v != "raster")
         throw UsageError("--small-triangles: '" + v + "' is neither compute nor raster");
       to.settings->smallTrianglesInCompute = v == "compute";
     }},
    {"--time", nullptr, "T", kRenderOption, kGeneral,
     "animated scenes: pose of the first frame, seconds (default 0)", nullptr,
     [](const Targets& to, const std::string& v) { to.render->time = parseFloat("--time", v); }},
    {"--look-from", nullptr, "X,Y,Z", kRenderOption, kGeneral,
     "another viewpoint than the file's camera, looking at\n"
     "--look-at X,Y,Z, both in the file's coordinates (same field\n"
     "of view; every mode, so a reference can be rendered there too)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.render->lookFrom = parseVec3("--look-from", v);
     }},
    {"--look-at", nullptr, "X,Y,Z", kRenderOption, kGeneral, "the point --look-from looks at",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.render->lookAt = parseVec3("--look-at", v);
     }},
    {"--fps", nullptr, "F", kRenderOption, kGeneral,
     "animated scenes: frame f shows T + f/F (default 30); meshes,\n"
     "lights and an animated camera (a camera path) move; the\n"
     "image is the last frame. After the animation's end the\n"
     "last pose stays",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.render->fps = parseFloat("--fps", v);
       if (!(to.render->fps > 0.0)) throw UsageError("--fps: must be positive");
     }},
    {"--loop", nullptr, nullptr, kRenderOption, kGeneral,
     "animated scenes: time wraps around the end instead", nullptr,
     [](const Targets& to, const std::string&) { to.render->loop = true; }},
    {"--backend", nullptr, "B", kRenderOption, kGeneral,
     "egl (default; surfaceless Mesa or an NVIDIA device), osmesa,\n"
     "or glfw (a hidden window; needs a display)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       auto backend = gl::parseBackend(v);
       if (!backend)
         throw UsageError("--backend: unknown backend '" + v + "' (egl, osmesa, glfw)");
       to.render->backend = *backend;
     }},
    {"--exposure", nullptr, "E", kBothOptions, kGeneral,
     "linear exposure before tonemapping (default 1)",
     "linear exposure before tonemapping (default 1)",
     [](const Targets& to, const std::string& v) {
       to.settings->tonemap.exposure = parseFloat("--exposure", v);
     }},
    {"--tonemap", nullptr, "T", kBothOptions, kGeneral, "clamp (default) or aces",
     "clamp (default) or aces",
     [](const Targets& to, const std::string& v) {
       auto op = render::parseTonemap(v);
       if (!op) throw UsageError("--tonemap: unknown operator '" + v + "' (clamp, aces)");
       to.settings->tonemap.op = *op;
     }},
    {"--ambient", nullptr, "A", kBothOptions, kGeneral,
     "raster: uniform ambient radiance A (grey, >= 0) times the\n"
     "albedo and the occlusion texture (default 0: none)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->ambient = parseFloat("--ambient", v);
       if (to.settings->ambient < 0.0f) throw UsageError("--ambient: must not be negative");
     }},
    {"--effects", nullptr, "LIST", kBothOptions, kGeneral,
     "override the effect plan, e.g. +specular,-shadows (names:\n"
     "shadows, emission, indirect, specular, textures, alpha,\n"
     "colors, normalmaps, animation, or all). The plan comes from\n"
     "the scene: an effect it lacks is skipped (stage absent,\n"
     "shader code compiled out) and printed with its reason;\n"
     "forcing one on makes it run",
     "override the effect plan (see voxgi render --help), e.g.\n"
     "+specular,-shadows; the panel shows the plan",
     [](const Targets& to, const std::string& v) {
       try {
         scene::checkOverrides(v);
       } catch (const Error& e) {
         throw UsageError(e.what());
       }
       std::string& effects = to.settings->effects;
       effects += (effects.empty() ? "" : ",") + v;
     }},
    // rtgi (and dvr, whose voxels rtgi lights).
    {"--bounces", nullptr, "N", kBothOptions, kRtgi,
     "diffuse bounces of indirect light: all (default) or 0..16.\n"
     "The pixel's ray gives one, the voxels hold the rest; with\n"
     "all, the voxels' light feeds back into itself as it refines;\n"
     "a finite N >= 2 keeps its first estimate (the N-bounce chain)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       int n = 0;
       const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
       if (v != "all" && (r.ec != std::errc() || r.ptr != v.data() + v.size() || n < 0 || n > 16))
         throw UsageError("--bounces: '" + v + "' is neither all nor an integer in [0, 16]");
       to.settings->octree.bounces = v == "all" ? voxel::Octree::Settings::kAllBounces : n;
     }},
    {"--no-jitter", nullptr, nullptr, kBothOptions, kRtgi,
     "every frame samples the pixel's centre (default: a sub-pixel\n"
     "offset per frame, so accumulation antialiases edges)",
     nullptr, [](const Targets& to, const std::string&) { to.settings->jitter = false; }},
    {"--refine-rays", nullptr, "N", kBothOptions, kRtgi,
     "rays per voxel and frame that refine the voxels' light while\n"
     "the scene is still (default 1; 0 keeps the first estimate)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->octree.refineRays = parseIntValue("--refine-rays", v, 0, 1024);
     }},
    {"--interleave", nullptr, "N", kBothOptions, kRtgi,
     "each pixel traces new rays every N-th frame (1, 2, 4, 8, 16;\n"
     "default 1): N times less work per frame, N times more\n"
     "frames to converge; the first frame traces every pixel",
     nullptr,
     [](const Targets& to, const std::string& v) {
       const int n = parseIntValue("--interleave", v, 1, 16);
       if ((n & (n - 1)) != 0) throw UsageError("--interleave: must be 1, 2, 4, 8 or 16");
       to.settings->rtgi.interleave = n;
     }},
    {"--target-fps", nullptr, "F", kBothOptions, kRtgi,
     "hold F frames per second: a PID controller on the frame time\n"
     "sets the share of pixels that trace each frame (at least\n"
     "1/16, an interleave of 16); the extra pixels are those the\n"
     "work mask finds noisy (edges of the noisy image, blurred);\n"
     "every frame is then denoised, as the viewer shows each; off\n"
     "(the default) traces as --interleave says",
     "rtgi holds F frames per second by tracing a share of the\n"
     "pixels each frame (default 30; off: every pixel, every\n"
     "frame). A camera move keeps each pixel's history where its\n"
     "surface stays in view (--reproject); pixels that lost it and\n"
     "have not traced since show their traced neighbours' light",
     [](const Targets& to, const std::string& v) {
       to.settings->targetFps = v == "off" ? 0.0 : parseFloat("--target-fps", v);
       if (v != "off" && !(to.settings->targetFps > 0.0 && to.settings->targetFps <= 1000.0))
         throw UsageError("--target-fps: must be in (0, 1000], or off");
     }},
    {"--render-scale", nullptr, "S", kBothOptions, kRtgi,
     "rtgi renders at S times the output's width and height\n"
     "(0.25 to 1, default 1): G-buffer, rays, accumulation and\n"
     "denoiser cost about S^2 as much, and a temporal upsampler\n"
     "rebuilds the output from the jittered frames; a still\n"
     "image converges to the full-resolution one",
     "rtgi renders at S times the window's size and upsamples\n"
     "over time (see voxgi render --help): default 0.5 on a\n"
     "software GL (llvmpipe), 1 on a hardware one",
     [](const Targets& to, const std::string& v) {
       const double scale = parseFloat("--render-scale", v);
       if (!(scale >= render::kMinRenderScale && scale <= render::kMaxRenderScale))
         throw UsageError("--render-scale: must be in [0.25, 1]");
       to.settings->renderScale = static_cast<float>(scale);
       if (to.view) to.view->renderScaleChosen = true;
     }},
    {"--sparse-start", nullptr, nullptr, kBothOptions, kRtgi,
     "with interleaving or a frame budget, the first frame traces\n"
     "its share only, like the others; pixels that have not traced\n"
     "yet show their traced neighbours' light (as the viewer does)",
     nullptr, [](const Targets& to, const std::string&) { to.settings->rtgi.sparseStart = true; }},
    {"--budget-select", nullptr, "S", kBothOptions, kRtgi,
     "mask (default) or uniform: how the budget picks its pixels", nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.select = parseChoice<Rtgi::Select>(
           "--budget-select", v, {{"mask", Rtgi::Select::kMask}, {"uniform", Rtgi::Select::kUniform}});
     }},
    {"--reproject", nullptr, "on|off", kBothOptions, kRtgi,
     "on (default): a camera move (a camera path, the viewer)\n"
     "keeps the image, each pixel's history following its surface\n"
     "(dropped where the view reveals another); off: a move\n"
     "restarts accumulation",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.reproject = parseOnOff("--reproject", v);
     }},
    {"--history-cap", nullptr, "N", kBothOptions, kRtgi,
     "while the camera moves, a pixel's history counts at most N\n"
     "frames (default 16; glossy surfaces 4, mirrors none), so\n"
     "light follows the view; a still camera accumulates on",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.historyCap = parseIntValue("--history-cap", v, 1, 1 << 20);
     }},
    {"--light-reuse", nullptr, "on|off", kBothOptions, kRtgi,
     "on (default): with many emitters, each pixel's emitter\n"
     "sample is resampled with its neighbours' (ReSTIR DI);\n"
     "off: its own candidates only",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.reuseLights = parseOnOff("--light-reuse", v);
     }},
    {"--light-tiles", nullptr, "on|off", kBothOptions, kRtgi,
     "on (default): with 5 to 128 emitters, each pixel draws its\n"
     "emitter candidates from its 8x8 tile's distribution and\n"
     "resamples them (not with --target-fps or an interleave\n"
     "above 4); off: it weighs every emitter at its point",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.lightTiles = parseOnOff("--light-tiles", v);
     }},
    {"--leaf-draw-at-hits", nullptr, "N", kBothOptions, kRtgi,
     "at the indirect rays' hits, the light tree's walk goes down\n"
     "to nodes of at most N emitters (1-128, default 16) and\n"
     "draws among them by each one's bound; 128: as at the pixels",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.leafDrawAtHits = parseIntValue(
           "--leaf-draw-at-hits", v, 1, static_cast<int>(gpu::kLightTreeLeafDraw));
     }},
    {"--first-lobe-rays", nullptr, "N", kBothOptions, kRtgi,
     "rays a glossy pixel, or a mirror pixel whose reflection is\n"
     "strongly minified (a small ball), traces in a frame while\n"
     "its mean holds fewer than 4 samples (1-16; default 4, or 1\n"
     "under --target-fps); one after",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.firstLobeRays = parseIntValue("--first-lobe-rays", v, 1, 16);
     }},
    {"--caustics", nullptr, "on|off", kBothOptions, kRtgi,
     "on (default): light that reaches a surface by way of\n"
     "mirrors, by photons sent from the emissive surfaces\n"
     "through the mirrors to the camera (scenes with mirrors\n"
     "and emitters); off: none",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.caustics = parseOnOff("--caustics", v);
     }},
    {"--caustic-photons", nullptr, "N", kBothOptions, kRtgi,
     "photons the caustics stage sends a frame (1024-4194304;\n"
     "default one for every 16 pixels that trace, 256 at least)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.causticPhotons = parseIntValue("--caustic-photons", v, 1024, 1 << 22);
     }},
    {"--denoise", nullptr, "on|off", kBothOptions, kRtgi,
     "on (default): the image is each pixel's running mean\n"
     "filtered by a variance-guided, edge-avoiding wavelet (SVGF),\n"
     "as strongly as its measured noise asks, so less and less as\n"
     "a still image converges; off: the running mean itself",
     "the image shown is denoised (see voxgi render --help); on by\n"
     "default on a hardware GL, off on a software one (llvmpipe),\n"
     "where it costs more than a frame; the n key toggles it",
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.denoise = parseOnOff("--denoise", v);
       if (to.view) to.view->denoiseChosen = true;
     }},
    {"--voxel-reflections", nullptr, nullptr, kBothOptions, kRtgi,
     "mirrors and glossy surfaces reflect the voxels they see\n"
     "(default: the exact triangles, through a BVH, lit exactly)",
     nullptr,
     [](const Targets& to, const std::string&) { to.settings->rtgi.exactReflections = false; }},
    {"--voxel-rays", nullptr, nullptr, kBothOptions, kRtgi,
     "shadow and indirect rays march the voxels, which stop them\n"
     "too early near contacts (default: they hit the exact\n"
     "triangles, through a BVH; the voxels give only the light\n"
     "at an indirect ray's hit). A scene whose meshes move\n"
     "always marches the voxels",
     nullptr, [](const Targets& to, const std::string&) { to.settings->rtgi.exactRays = false; }},
    {"--primary", nullptr, "P", kBothOptions, kRtgi,
     "how the G-buffer finds what each pixel shows: raster draws\n"
     "every triangle; rays casts one ray a pixel through the BVH,\n"
     "a cost that grows with the log of the triangle count; auto\n"
     "(default): rays on a software GL for scenes with more\n"
     "than 4 triangles a pixel, else raster",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.primary = parseChoice<Rtgi::Primary>(
           "--primary", v,
           {{"auto", Rtgi::Primary::kAuto},
            {"raster", Rtgi::Primary::kRaster},
            {"rays", Rtgi::Primary::kRays}});
     }},
    {"--indirect", nullptr, "M", kBothOptions, kRtgi,
     "how diffuse indirect light is gathered: rays (default), one\n"
     "random ray per pixel and frame, averaged by accumulation; or\n"
     "cones, six cones through the octree's filtered levels (voxel\n"
     "cone tracing): the same smooth light every frame, biased\n"
     "(it leaks through walls thinner than a cone's footprint)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->rtgi.indirectMethod = parseChoice<Rtgi::IndirectMethod>(
           "--indirect", v,
           {{"rays", Rtgi::IndirectMethod::kRays}, {"cones", Rtgi::IndirectMethod::kCones}});
     }},
    {"--out-mask", nullptr, "FILE", kRenderOption, kRtgi,
     "write the last work mask (grey PNG, or EXR)", nullptr,
     [](const Targets& to, const std::string& v) {
       to.render->maskOutput = v;
       to.render->render.rtgi.keepMask = true;
     }},
    {"--inject-rays", nullptr, "N", kBothOptions, kRtgi,
     "shadow rays per voxel towards emissive surfaces in the first\n"
     "estimate of the voxels' light (default 4; refinement adds more)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->octree.injectRays = parseIntValue("--inject-rays", v, 1, 1024);
     }},
    {"--bounce-rays", nullptr, "N", kBothOptions, kRtgi,
     "rays per voxel for each voxel bounce of that estimate (default 4;\n"
     "with all bounces the first traces them and, up to 16, the later\n"
     "bounces read the light where they met the leaves again)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->octree.bounceRays = parseIntValue("--bounce-rays", v, 1, 1024);
     }},

    // The path tracer.
    {"--spp", nullptr, "N", kRenderOption, kPathtrace,
     "samples per pixel of one frame (default 64: enough to judge\n"
     "an image; the references of tools/sweep use 2048)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->spp = parseIntValue("--spp", v, 1, 1 << 20);
     }},
    {"--seed", nullptr, "S", kRenderOption, kPathtrace,
     "random seed of pathtrace, rtgi and the voxels' light; the\n"
     "same seed gives the same image (default 0)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       const auto seed = static_cast<uint32_t>(parseIntValue("--seed", v, 0, 2147483647));
       to.settings->pathtrace.seed = seed;
       to.settings->rtgi.seed = seed;
       to.settings->octree.seed = seed;
     }},
    {"--max-depth", nullptr, "D", kRenderOption, kPathtrace,
     "longest path, Mitsuba's convention: 1 = emitters seen directly,\n"
     "2 = direct light (default 8: up to 7 bounces)",
     nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->pathtrace.maxDepth = parseIntValue("--max-depth", v, 1, 1024);
     }},
    {"--rr-depth", nullptr, "D", kRenderOption, kPathtrace,
     "Russian roulette from this depth on (default 5)", nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->pathtrace.rrDepth = parseIntValue("--rr-depth", v, 1, 1024);
     }},
    {"--pt-device", nullptr, "D", kRenderOption, kPathtrace,
     "auto (default), cpu or gl: cpu traces with Embree on every core,\n"
     "gl in a compute shader; auto takes cpu when GL is a software\n"
     "renderer (llvmpipe, softpipe) and gl on a GPU",
     nullptr,
     [](const Targets& to, const std::string& v) {
       if (v != "auto" && v != "cpu" && v != "gl")
         throw UsageError("--pt-device: expected auto, cpu or gl, got '" + v + "'");
       to.settings->pathtrace.device = render::parsePathtraceDevice(v);
     }},
    {"--pt-threads", nullptr, "N", kRenderOption, kPathtrace,
     "cpu device: worker threads (default: one per core)", nullptr,
     [](const Targets& to, const std::string& v) {
       to.settings->pathtrace.threads = parseIntValue("--pt-threads", v, 1, 1024);
     }},
    {"--no-progress", nullptr, nullptr, kRenderOption, kPathtrace,
     "no progress bar (shown on stderr only when it is a terminal)", nullptr,
     [](const Targets& to, const std::string&) { to.render->progress = false; }},

    // Both commands, listed last in each help.
    {"--no-panel", nullptr, nullptr, kViewOption, kGeneral, "start with the panel hidden",
     nullptr, [](const Targets& to, const std::string&) { to.view->panel = false; }},
    {"--verbose", "-v", nullptr, kBothOptions, kGeneral, kVerboseHelp, kVerboseHelp,
     [](const Targets& to, const std::string&) {
       (to.render ? to.render->verbose : to.view->verbose) = true;
     }},
    {"--quiet", "-q", nullptr, kBothOptions, kGeneral, kQuietHelp, kQuietHelp,
     [](const Targets& to, const std::string&) {
       (to.render ? to.render->quiet : to.view->quiet) = true;
     }},
};

// "--size WxH" as the help shows it.
std::string head(const CliOption& o) {
  std::string h = o.alias ? std::string(o.alias) + ", " + o.name : std::string(o.name);
  if (o.value) h += std::string(" ") + o.value;
  return h;
}

// One option's lines: its head at column 2, its text from column 20 (after the head
// when that leaves room, else two spaces after it).
std::string entry(const std::string& name, const std::string& text) {
  constexpr size_t kColumn = 20;
  std::string out = "  " + name;
  out += out.size() + 1 <= kColumn ? std::string(kColumn - out.size(), ' ') : "  ";
  size_t start = 0;
  while (true) {
    const size_t nl = text.find('\n', start);
    out += text.substr(start, nl == std::string::npos ? nl : nl - start) + "\n";
    if (nl == std::string::npos) break;
    out += std::string(kColumn, ' ');
    start = nl + 1;
  }
  const size_t modes = out.find("{modes}");
  if (modes != std::string::npos) out.replace(modes, 7, render::availableModes());
  return out;
}

}  // namespace

const std::vector<CliOption>& cliOptions() {
  return kOptions;
}

const CliOption* findCliOption(const std::string& name, OptionCommands command) {
  for (const CliOption& o : kOptions)
    if ((o.commands & command) != 0 && (name == o.name || (o.alias && name == o.alias))) return &o;
  return nullptr;
}

std::string cliOptionsHelp(OptionCommands command, OptionSection section) {
  std::string out;
  if (command == kRenderOption) {
    for (const CliOption& o : kOptions)
      if ((o.commands & kRenderOption) != 0 && o.section == section) out += entry(head(o), o.help);
    return out;
  }
  // view: its own texts, then one list of the options as for render.
  std::string shared;
  size_t line = 2;
  for (const CliOption& o : kOptions) {
    if ((o.commands & kViewOption) == 0) continue;
    const char* text = o.commands == kViewOption ? o.help : o.viewHelp;
    if (text) {
      out += entry(head(o), text);
      continue;
    }
    std::string item = head(o);
    if (!shared.empty()) {
      shared += ",";
      ++line;
      if (line + 1 + item.size() + 1 > 80) {
        shared += "\n ";
        line = 1;
      }
      shared += " ";
      ++line;
    } else {
      shared = "  ";
    }
    shared += item;
    line += item.size();
  }
  if (!shared.empty()) out += shared + "\n" + std::string(20, ' ') + "as for voxgi render\n";
  return out;
}

}  // namespace voxgi::app

// `voxgi render`: context, scene, frames, images, stats.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/stage_report.h"
#include "core/memory.h"
#include "core/statistics.h"
#include "gl/debug.h"
#include "image/image.h"
#include "scene/gltf_loader.h"

namespace voxgi::app {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

std::string shaderRoot() {
  if (const char* env = std::getenv("VOXGI_SHADER_DIR")) return env;
  return VOXGI_SHADER_DIR;
}

namespace {

// A one-line progress bar with rate and ETA, redrawn in place on stderr.
class ProgressBar {
 public:
  explicit ProgressBar(int64_t pixels) : pixels_(pixels) {}
  void update(int done, int total) {
    const auto now = Clock::now();
    if (done == 0) start_ = now;
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    const double rate = s > 0.0 ? static_cast<double>(pixels_) * done / s : 0.0;
    const double eta = done > 0 ? s * (total - done) / done : 0.0;
    constexpr int kWidth = 30;
    const int filled = total > 0 ? kWidth * done / total : kWidth;
    std::fprintf(stderr, "\r[%s%s] %3d%% %d/%d spp  %.2f M samples/s  ETA %.0f s ",
                 std::string(static_cast<size_t>(filled), '#').c_str(),
                 std::string(static_cast<size_t>(kWidth - filled), '.').c_str(),
                 total > 0 ? 100 * done / total : 100, done, total, rate * 1e-6, eta);
    if (done >= total) std::fputs("\n", stderr);
    std::fflush(stderr);
  }
  void begin() { start_ = last_ = Clock::now(); }

 private:
  int64_t pixels_;
  Clock::time_point start_ = Clock::now(), last_;
};

}  // namespace

namespace {

// "effects": {"enabled": [...], "skipped": {"name": "reason"}}, in scene::kEffects order.
nlohmann::ordered_json effectsJson(const scene::EffectPlan& plan) {
  nlohmann::ordered_json skipped = nlohmann::ordered_json::object();
  for (const auto& [effect, reason] : plan.skipped) skipped[scene::effectName(effect)] = reason;
  nlohmann::ordered_json out;
  out["enabled"] = plan.enabledNames();
  out["skipped"] = skipped;
  return out;
}

// Everything that can be refused without GL is refused before any work.
void checkOutputs(const RenderOptions& o) {
  for (const std::string& out : o.outputs) {
    image::checkWritable(out);
    image::formatForPath(out);
  }
  if (!o.stats.empty()) image::checkWritable(o.stats);
  if (!o.maskOutput.empty()) {
    image::checkWritable(o.maskOutput);
    image::formatForPath(o.maskOutput);
    if (o.render.mode != render::Mode::kRtgi || o.render.targetFps <= 0.0)
      throw UsageError("--out-mask: the work mask exists in rtgi with --target-fps only");
  }
}

// The scene posed at --time, seen from --look-from when it is given.
scene::Scene loadScene(const std::string& scenePath, const RenderOptions& o) {
  scene::Scene scene = scene::loadGltf(scenePath);
  scene.loopAnimation = o.loop;
  scene.pose(o.time);
  if (o.lookFrom) scene.lookAt(*o.lookFrom, *o.lookAt);
  return scene;
}

// What a render measured, for the stats file and the console summary.
struct RenderRecord {
  std::string scenePath;
  double loadMs = 0.0, startupMs = 0.0, totalMs = 0.0;
  double contextMs = 0.0;  // Stage::kContext
  StageTimes times;
  std::vector<double> traced;  // rtgi: each frame's traced share of the pixels
  double samplesPerSecond = 0.0;
  int glErrors = 0;

  double tracedMedian() const { return traced.empty() ? 1.0 : median(traced); }
};

// Where the start-up went, in order: the context, then the renderer's stages (the
// scene's loading is loadMs).
std::vector<gl::StageTime> startupTimes(const render::Renderer& renderer,
                                        const RenderRecord& record) {
  std::vector<gl::StageTime> t = {{Stage::kContext, 0.0, record.contextMs}};
  t.insert(t.end(), renderer.startupStages().begin(), renderer.startupStages().end());
  return t;
}

// The timed frames: frame f shows time + f / fps when the scene is animated.
void renderFrames(const RenderOptions& o, scene::Scene& scene, render::Renderer& renderer,
                  ProgressBar& bar, RenderRecord& record) {
  for (int f = 0; f < o.frames; ++f) {
    const auto t = Clock::now();
    // Frame f shows time + f / fps, with the animation effect (else the first pose
    // stays): meshes, lights and the camera along its path.
    if (scene.animated() && renderer.effects().has(scene::Effect::kAnimation) && f > 0) {
      scene.pose(o.time + f / o.fps);
      renderer.posed();
    }
    bar.begin();
    // Only the last frame is written: the frames before it need no denoising. With a
    // frame budget every frame is denoised, as the viewer shows each: the budget and
    // the frame times then count the filter's cost, as the viewer pays it.
    renderer.setFrameShown(f + 1 == o.frames || o.render.targetFps > 0.0);
    renderer.renderFrame();
    const double ms = msSince(t);
    if (const render::RtgiPass* rt = renderer.rtgi())
      record.traced.push_back(rt->lastTracedFraction());
    record.times.add(ms, renderer.lastStages());
  }
}

void writeImages(const RenderOptions& o, const render::Renderer& renderer) {
  for (const std::string& out : o.outputs) {
    if (image::formatForPath(out) == image::Format::kPng) {
      const auto px = renderer.readDisplay();
      image::writePng(out, o.render.width, o.render.height, px.data());
    } else {
      const auto px = renderer.readLinear();
      image::writeExr(out, o.render.width, o.render.height, px.data());
    }
  }
}

// The rtgi work mask as a grey image.
void writeMask(const std::string& path, const render::RtgiPass& rt) {
  const std::vector<float> mask = rt.readMask();
  if (mask.empty()) throw Error("--out-mask: no work mask was computed (render more than 1 frame)");
  std::vector<float> rgba;
  rgba.reserve(mask.size() * 4);
  for (float m : mask) rgba.insert(rgba.end(), {m, m, m, 1.0f});
  if (image::formatForPath(path) == image::Format::kPng) {
    std::vector<uint8_t> px;
    px.reserve(rgba.size());
    for (float v : rgba)
      px.push_back(static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f));
    image::writePng(path, rt.maskWidth(), rt.maskHeight(), px.data());
  } else {
    image::writeExr(path, rt.maskWidth(), rt.maskHeight(), rgba.data());
  }
}

void addPathtraceStats(nlohmann::ordered_json& stats, const RenderOptions& o,
                       const render::Renderer& renderer, const RenderRecord& record) {
  stats["spp"] = o.render.spp;
  stats["samples_per_second"] = record.samplesPerSecond;
  stats["seed"] = o.render.pathtrace.seed;
  stats["max_depth"] = o.render.pathtrace.maxDepth;
  stats["rr_depth"] = o.render.pathtrace.rrDepth;
  stats["pt_device"] = render::pathtraceDeviceName(renderer.pathtrace()->device());
  stats["bvh_nodes"] = renderer.pathtrace()->bvhNodes();
  stats["emissive_triangles"] = renderer.pathtrace()->emissiveTriangles();
  const uint64_t truncated = renderer.pathtrace()->truncatedPaths();
  stats["truncated_paths"] = truncated;
  if (truncated > 0)
    logWarning(
        strf("pathtrace: %llu of the last frame's paths ran out of loop budget and were "
             "cut short (the image is biased dark)",
             static_cast<unsigned long long>(truncated)));
}

void addRtgiStats(nlohmann::ordered_json& stats, const RenderOptions& o, const render::RtgiPass& rt,
                  const render::GpuScene& gs, const RenderRecord& record) {
  using Settings = render::RtgiPass::Settings;
  stats["interleave"] = rt.settings().interleave;
  stats["reproject"] = rt.settings().reproject;
  stats["light_reuse"] = rt.settings().reuseLights;
  stats["light_tiles"] = rt.settings().lightTiles;
  stats["emitter_sampling"] = rt.emitterSampling(gs);
  stats["punctual_sampling"] = rt.punctualSampling(gs);
  stats["leaf_draw_at_hits"] = rt.settings().leafDrawAtHits;
  stats["first_lobe_rays"] = rt.firstLobeRays();
  stats["caustic_photons"] = rt.lastCausticPhotons();
  stats["caustic_mirrors"] = rt.causticTargets();
  stats["history_cap"] = rt.settings().historyCap;
  stats["denoise"] = rt.settings().denoise;
  stats["rays"] = rt.raysHitTriangles() ? "triangles" : "voxels";
  stats["primary"] = rt.primaryRays() ? "rays" : "raster";
  stats["indirect"] =
      rt.settings().indirectMethod == Settings::IndirectMethod::kCones ? "cones" : "rays";
  stats["reflections"] = !rt.settings().specular ? "none"
                         : rt.tracesTriangles()  ? "triangles"
                                                 : "voxels";
  stats["traced_fraction"] = record.tracedMedian();
  stats["specular_fraction"] = rt.lastSpecularFraction();  // the last frame's
  const glm::ivec2 internal =
      render::scaledSize(o.render.width, o.render.height, o.render.renderScale);
  stats["render_scale"] = o.render.renderScale;
  stats["internal_size"] = {internal.x, internal.y};
  if (o.render.targetFps > 0.0)
    stats["budget"] = {
        {"target_fps", o.render.targetFps},
        {"target_ms", 1000.0 / o.render.targetFps},
        {"select", rt.settings().select == Settings::Select::kUniform ? "uniform" : "mask"},
        {"frame_ms_median", record.times.frameMedian()},
        {"frame_ms_each", record.times.frameMs()},
        {"traced_fraction_each", record.traced},
        {"traced_fraction_median", record.tracedMedian()}};
}

void addSceneStats(nlohmann::ordered_json& stats, const RenderOptions& o, const scene::Scene& scene,
                   const render::Renderer& renderer) {
  stats["triangles"] = scene.triangleCount();
  stats["materials"] = scene.materials.size();
  stats["textures"] = scene.textures.size();
  stats["lights"] = scene.lights.size();
  stats["emitters"] = renderer.gpuScene().emitterCount();
  stats["default_light"] = scene.defaultLight;
  stats["animated"] = scene.animated();
  stats["effects"] = effectsJson(renderer.effects());
  if (scene.animated()) {
    stats["time"] = o.time;
    stats["fps"] = o.fps;
    stats["animation_seconds"] = scene.animationDuration;
    stats["camera_path"] = scene.cameraMoves && scene.poseCamera;
    stats["moving_lights"] = std::count_if(scene.lights.begin(), scene.lights.end(),
                                           [](const scene::Light& l) { return l.moves; });
  }
  stats["scene_warnings"] = scene.warnings;
}

void addMemoryStats(nlohmann::ordered_json& stats, const RenderOptions& o,
                    const render::Renderer& renderer) {
  stats["peak_rss_bytes"] = peakResidentBytes();
  stats["gpu_scene_bytes"] = renderer.gpuScene().bytes();
  if (const render::GpuBvh* bvh = renderer.bvh()) {
    stats["gpu_bvh_bytes"] = bvh->gpuBytes();
    stats["bvh_tree_ms"] = bvh->treeMs();
  }
  const render::Renderer::TextureMemory tm = renderer.textureMemory();
  stats["texture_bytes"] = {
      {"gpu", tm.gpu()}, {"gl_textures", tm.glTextures},   {"bvh_texels", tm.bvhTexels},
      {"cpu", tm.cpu()}, {"scene_images", tm.sceneImages}, {"cpu_pathtracer", tm.cpuPathtracer}};
  if (const voxel::VoxelizePass* grid = renderer.voxelGrid()) {
    const voxel::VoxelGridStats& vs = grid->stats();
    stats["voxels"] = {
        {"resolution", vs.resolution},
        {"count", vs.occupied},
        {"checksum", strf("%016llx", static_cast<unsigned long long>(vs.checksum))},
        {"bytes", vs.bytes},
        {"peak_bytes", vs.peakBytes},
        {"rounds", vs.rounds},
        {"revoxelize", o.render.revoxelize},
        {"small_triangles", o.render.smallTrianglesInCompute ? "compute" : "raster"}};
  }
  if (const voxel::Octree* tree = renderer.octree()) {
    const voxel::OctreeStats& os = tree->stats();
    stats["octree"] = {{"nodes", os.nodes},
                       {"leaves", os.leaves},
                       {"two_sided_leaves", os.twoSidedLeaves},
                       {"depth", os.depth},
                       {"bytes", os.bytes},
                       {"refine_bytes", os.refineBytes},
                       {"dense_bytes", os.denseBytes},
                       {"build_bytes", os.buildBytes},
                       {"bounces", tree->allBounces() ? nlohmann::json("all")
                                                      : nlohmann::json(o.render.octree.bounces)},
                       {"refine_rays", o.render.octree.refineRays},
                       {"estimates", tree->estimates()},
                       {"rays", tree->settings().bvhDefines.empty() ? "voxels" : "triangles"}};
  }
}

// The stats file's contents, in the order the keys are written.
nlohmann::ordered_json renderStats(const RenderOptions& o, const gl::Context& context,
                                   const scene::Scene& scene, const render::Renderer& renderer,
                                   const RenderRecord& record) {
  nlohmann::ordered_json stats = statsHeaderJson(
      {"", record.scenePath, render::modeName(o.render.mode), o.render.width, o.render.height,
       gl::backendName(context.backend()), context.renderer(), context.version()});
  stats["frames"] = o.frames;
  stats["frame_ms"] = record.times.frameMedian();
  stats["total_ms"] = record.totalMs;
  stats["startup_ms"] = record.startupMs;
  stats["load_ms"] = record.loadMs;
  nlohmann::ordered_json startupStages = nlohmann::ordered_json::object();
  for (const gl::StageTime& st : startupTimes(renderer, record))
    startupStages[stageName(st.stage)] = st.cpuMs;
  stats["startup_stages"] = startupStages;
  if (o.render.mode == render::Mode::kPathtrace) addPathtraceStats(stats, o, renderer, record);
  if (o.render.mode == render::Mode::kRtgi)
    addRtgiStats(stats, o, *renderer.rtgi(), renderer.gpuScene(), record);
  const nlohmann::ordered_json stages = record.times.json();
  stats["stages"] = stages;
  stats["stage_timing"] = gl::stageTimingMethod();
  addSceneStats(stats, o, scene, renderer);
  addMemoryStats(stats, o, renderer);
  // Stages run once per scene (in the untimed warm-up frame): that run's time.
  for (const gl::StageTime& st : renderer.sceneStages())
    if (!stages.contains(stageName(st.stage))) stats["stages"][stageName(st.stage)] = st.gpuMs;
  stats["nonfinite_terms"] = renderer.nonfiniteTerms();
  stats["gl_errors"] = record.glErrors;
  return stats;
}

// Voxel grid and octree sizes, below the stage table.
void printVoxelSummary(const render::Renderer& renderer) {
  if (const voxel::VoxelizePass* grid = renderer.voxelGrid()) {
    const voxel::VoxelGridStats& vs = grid->stats();
    std::printf("  voxels %d^3: %u occupied, %.1f MiB resident, %.1f MiB while voxelizing\n",
                vs.resolution, vs.occupied, static_cast<double>(vs.bytes) / (1 << 20),
                static_cast<double>(vs.peakBytes) / (1 << 20));
  }
  if (const voxel::Octree* tree = renderer.octree()) {
    const voxel::OctreeStats& os = tree->stats();
    std::printf("  octree depth %d: %u nodes, %.1f MiB (%.1f%% of the dense grid's %.1f MiB)\n",
                os.depth, os.nodes, static_cast<double>(os.bytes) / (1 << 20),
                100.0 * static_cast<double>(os.bytes) / static_cast<double>(os.denseBytes),
                static_cast<double>(os.denseBytes) / (1 << 20));
    std::printf("  voxel light: %s bounces, %d estimates per voxel, %.1f MiB to refine it\n",
                tree->allBounces() ? "all" : std::to_string(tree->settings().bounces).c_str(),
                tree->estimates(), static_cast<double>(os.refineBytes) / (1 << 20));
  }
}

void printOutputs(const RenderOptions& o) {
  for (const std::string& out : o.outputs) std::printf("wrote %s\n", out.c_str());
  if (!o.maskOutput.empty()) std::printf("wrote %s\n", o.maskOutput.c_str());
  if (!o.stats.empty()) std::printf("wrote %s\n", o.stats.c_str());
  if (o.outputs.empty()) std::printf("(no --out given: no image written)\n");
}

// The console summary: scene, stage table, sizes, timings and what was written.
void printSummary(const RenderOptions& o, const gl::Context& context, const scene::Scene& scene,
                  const render::Renderer& renderer, const RenderRecord& record) {
  std::printf("%s: %zu triangles, %zu materials, %zu lights%s, %d emitter groups\n",
              record.scenePath.c_str(), scene.triangleCount(), scene.materials.size(),
              scene.lights.size(), scene.defaultLight ? " (default light added)" : "",
              renderer.gpuScene().emitterCount());
  std::printf("%s %dx%d on %s (%s)\n", render::modeName(o.render.mode), o.render.width,
              o.render.height, gl::backendName(context.backend()), context.renderer().c_str());
  std::fputs(record.times.table(gl::stageTimingMethod()).c_str(), stdout);
  for (const gl::StageTime& st : renderer.sceneStages())
    if (!record.times.has(st.stage))
      std::printf("  %-10s %10.2f   (once, at start-up; --revoxelize for every frame)\n",
                  stageName(st.stage), st.gpuMs);
  printVoxelSummary(renderer);
  std::printf("  %-10s %10.2f   (wall clock, median of %d)\n", "frame", record.times.frameMedian(),
              o.frames);
  if (o.render.mode == render::Mode::kPathtrace)
    std::printf("  %d spp, %.2f M samples/s (pixel samples, whole paths)\n", o.render.spp,
                record.samplesPerSecond * 1e-6);
  std::printf("  load %.1f ms, start-up %.1f ms", record.loadMs, record.startupMs);
  const char* sep = " (";
  for (const gl::StageTime& st : startupTimes(renderer, record)) {
    std::printf("%s%s %.1f", sep, stageName(st.stage), st.cpuMs);
    sep = ", ";
  }
  std::printf(")");
  std::printf(", peak RSS %.0f MiB\n", static_cast<double>(peakResidentBytes()) / (1 << 20));
  if (o.render.targetFps > 0.0)
    std::printf("  budget: target %.1f ms, median frame %.1f ms, median traced share %.3f\n",
                1000.0 / o.render.targetFps, record.times.frameMedian(), record.tracedMedian());
  printOutputs(o);
}

}  // namespace

int runRender(const RenderOptions& o) {
  if (o.verbose) setLogLevel(LogLevel::kDebug);
  if (o.quiet) setLogLevel(LogLevel::kError);
  const auto start = Clock::now();
  checkOutputs(o);
  RenderRecord record;
  record.scenePath = o.scene.empty() ? defaultScenePath() : o.scene;

  gl::ContextOptions co;
  co.backend = o.backend;
  co.eglDevice = o.eglDevice;
  co.width = o.render.width;
  co.height = o.render.height;
  const auto contextStart = Clock::now();
  auto context = gl::Context::create(co);
  record.contextMs = msSince(contextStart);
  render::checkImageSize(o.render.width, o.render.height);

  const auto loadStart = Clock::now();
  scene::Scene scene = loadScene(record.scenePath, o);
  record.loadMs = msSince(loadStart);

  gl::ProgramCache programs(shaderRoot());
  const bool pathtrace = o.render.mode == render::Mode::kPathtrace;
  render::Renderer renderer(programs, scene, o.render);
  if (!o.quiet) {
    std::printf("effects: %s%s\n", renderer.effects().summary().c_str(),
                pathtrace ? " [pathtrace, the reference, renders every effect]" : "");
    std::fflush(stdout);
  }
  // Untimed warm-up: drivers compile shader variants at first draw (llvmpipe
  // JIT-compiles them), which is start-up cost, not frame cost. The path tracer
  // warms up on one work group, not a whole image.
  renderer.warmUp();
  pauseHugePages(false);  // started: the frames want them (core/memory.h)
  record.startupMs = msSince(start);
  ProgressBar bar(static_cast<int64_t>(o.render.width) * o.render.height);
  if (pathtrace && o.progress && !o.quiet && isatty(STDERR_FILENO)) {
    renderer.setProgress([&bar](int done, int total) { bar.update(done, total); });
  }

  renderFrames(o, scene, renderer, bar, record);
  record.totalMs = msSince(start) - record.startupMs;

  writeImages(o, renderer);
  if (!o.maskOutput.empty()) writeMask(o.maskOutput, *renderer.rtgi());

  record.glErrors = gl::debugErrorCount();
  // Pixel samples (whole paths) per second of wall clock, over the median frame.
  const double frameMedian = record.times.frameMedian();
  if (pathtrace && frameMedian > 0.0)
    record.samplesPerSecond =
        static_cast<double>(o.render.width) * o.render.height * o.render.spp / (frameMedian * 1e-3);
  const nlohmann::ordered_json stats = renderStats(o, *context, scene, renderer, record);
  if (!o.stats.empty()) image::writeText(o.stats, stats.dump(2) + "\n");

  if (!o.quiet) printSummary(o, *context, scene, renderer, record);
  if (record.glErrors > 0) {
    logError(strf("%d GL error(s) during the render; first: %s", record.glErrors,
                  gl::lastDebugError().c_str()));
    return 1;
  }
  return 0;
}

}  // namespace voxgi::app

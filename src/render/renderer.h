// Frame order for one render mode, and the targets the passes share:
//   raster:    raster (HDR radiance + depth) -> tonemap (sRGB 8-bit)
//   points:    [voxelize, once per scene or every frame with revoxelize]
//              -> points (HDR radiance + depth) -> tonemap
//   dvr:       [voxelize, octree, inject: once per scene, or every frame with
//              revoxelize] -> dvr (HDR radiance) -> tonemap
//   rtgi:      [voxelize, octree, inject as for dvr] -> gbuffer -> shadows ->
//              indirect -> specular -> accumulate (the mean over frames since
//              accumulation restarted) -> tonemap; at a render scale below 1 those
//              run at the internal size, then upsample (the fresh samples into the
//              output's history) -> tonemap (which shows history and internal image)
// The effect plan (scene/effects.h, effects()) decides which of shadows, indirect
// and specular run, and the shader variants of every pass but pathtrace.
//   pathtrace: pathtrace (spp samples per pixel accumulated, the mean into the same
//              HDR target) -> tonemap; its BVH is built once, when the mode is first used.
// Only the passes a mode uses are built (their shaders compiled, memory taken).
// Output sizes are checked against the driver's limits and a memory budget
// before anything is allocated.
//
// `render` draws the scene's camera at a fixed size; the viewer passes its own
// camera every frame and resizes the targets with the window. Any change of size,
// mode or knob restarts accumulation (accumulatedFrames() counts the frames since),
// which progressive modes read to start their average over; so does a change of
// camera, except in rtgi with reprojection (RtgiPass::Settings::reproject), which
// carries each pixel's history over to the new view.
#ifndef VOXGI_RENDER_RENDERER_H
#define VOXGI_RENDER_RENDERER_H

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "gl/stage_timer.h"
#include "render/dvr_pass.h"
#include "render/frame_budget.h"
#include "render/frame_context.h"
#include "render/gpu_scene.h"
#include "render/knob.h"
#include "render/pathtrace/pathtracer.h"
#include "render/points_pass.h"
#include "render/raster_pass.h"
#include "render/rtgi_pass.h"
#include "render/tonemap_pass.h"
#include "scene/effects.h"
#include "voxel/octree.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::render {

enum class Mode { kRaster, kPoints, kDvr, kRtgi, kPathtrace };
// Whether the mode reads the voxel grid, and the octree built from it.
bool modeUsesVoxels(Mode m);
bool modeUsesOctree(Mode m);
// rtgi accumulates this many frames by default: its error against the reference
// stops falling well before (README: "rtgi: frames").
constexpr int kRtgiDefaultFrames = 64;
// Frames `render` accumulates by default for a converged image (rtgi), else 1.
int defaultFrames(Mode m);
std::optional<Mode> parseMode(const std::string& name);
const char* modeName(Mode m);
// The modes this build has, comma separated (for --help and errors).
std::string availableModes();

struct RenderSettings {
  int width = 256;
  int height = 256;
  Mode mode = Mode::kRtgi;
  TonemapPass::Settings tonemap;
  int voxels = 128;         // grid resolution N (N^3 voxels) for modes that use voxels
  bool revoxelize = false;  // voxelize every frame (animated scenes) instead of once
  // Voxelize small triangles in the compute path (false: all of them in the raster).
  bool smallTrianglesInCompute = true;
  // Checksum the voxel grid (the stats JSON's "voxels"."checksum"); off where nothing
  // shows it (bench, the viewer): it costs the resolve two shared atomics a voxel.
  bool voxelChecksum = true;
  // The voxel grid's memory budget in bytes; 0: the driver's estimate
  // (voxel::voxelMemoryBudget).
  uint64_t voxelBudgetBytes = 0;
  voxel::Octree::Settings octree;  // bounces (total diffuse bounces), rays for light
  RtgiPass::Settings rtgi;
  // rtgi: each accumulated frame rasterizes its G-buffer with a sub-pixel offset of
  // a low-discrepancy sequence, so the mean converges to the box-filtered pixel (the
  // path tracer's) rather than to the value at its centre. The first frame is not
  // offset.
  bool jitter = true;
  // rtgi: the share of the output's width and height it renders at, in [0.25, 1].
  // Below 1, the G-buffer, the rays, accumulation, reprojection and the denoiser run
  // at the internal size (internalSize()), and a temporal upsampler rebuilds the
  // output from the jittered frames (RtgiPass::upsample): still, it converges to the
  // full-resolution image. Other modes render at the output size.
  float renderScale = 1.0f;
  // rtgi: hold this frame rate (0: off) by tracing a varying share of the pixels,
  // chosen by the work mask (rtgi.select; kMask unless set) on top of an interleave
  // of 16 (unless set).
  double targetFps = 0.0;
  // raster: a uniform ambient radiance (grey) the baseline adds, times the diffuse
  // albedo and the material's occlusion texture; 0 (the default): direct light only.
  // The GI modes compute their own indirect light and ignore it.
  float ambient = 0.0f;
  PathtraceSettings pathtrace;
  int spp = 64;  // pathtrace: samples per pixel of one frame
  // pathtrace: frames add their samples to the image until accumulation restarts
  // (the viewer); otherwise each frame is a whole image of `spp` samples.
  bool progressive = false;
  // --effects: overrides ("+name,-name") of the plan made from the scene.
  std::string effects;
};

// The effect plan a renderer with these settings follows: planEffects(scene), less
// indirect with --bounces 0, then the --effects overrides. Throws voxgi::Error on a
// bad override.
scene::EffectPlan effectPlan(const scene::Scene& scene, const RenderSettings& settings);

// The sub-pixel offset, in pixels in [-0.5, 0.5)^2, of jittered frame k: the R2
// sequence (Roberts 2018, the plastic constant's additive recurrence), which stays
// evenly spread over any run of consecutive k; k = 0 is the pixel's centre.
glm::vec2 subpixelJitter(int k);

// The render scale's range (RenderSettings::renderScale).
constexpr float kMinRenderScale = 0.25f;
constexpr float kMaxRenderScale = 1.0f;
// rtgi's internal size for an output of width x height at render scale `scale`:
// each side scaled and rounded, at least 1.
glm::ivec2 scaledSize(int width, int height, float scale);

// Throws voxgi::Error when width x height cannot be rendered on this context.
void checkImageSize(int width, int height);

class Renderer {
 public:
  Renderer(gl::ProgramCache& programs, const scene::Scene& scene, const RenderSettings& settings);

  // Renders one frame from the scene's camera and waits for it; stage times land
  // in lastStages(). A pathtrace frame is a whole image of `spp` samples per pixel,
  // from sample 0; with `progressive`, it adds `spp` samples to those of the frames
  // since accumulation restarted (the image is their mean).
  void renderFrame();
  // The same from another camera (the viewer's).
  void renderFrame(const scene::Camera& camera);
  const std::vector<gl::StageTime>& lastStages() const { return stages_; }
  // What the driver compiles at first use, without a whole frame's work: a frame at
  // most kWarmUpSize pixels on its longer side (the path tracer: one work group).
  // Its wall-clock time is the start-up stage kWarmUp: the scene stages (voxelize,
  // octree, inject: sceneStages()) and each program's first-use JIT.
  void warmUp();
  static constexpr int kWarmUpSize = 32;
  // Pathtrace: called while a frame runs with samples per pixel done and total.
  void setProgress(Pathtracer::Progress progress) { progress_ = std::move(progress); }
  // Work done once before the first frame, by stage and wall-clock ms: kUpload,
  // kBvh, kPasses at construction, then kWarmUp (warmUp()).
  const std::vector<gl::StageTime>& startupStages() const { return startup_; }
  const Pathtracer* pathtrace() const { return pathtrace_.get(); }
  // The scene's BVH, shared by the path tracer and rtgi's reflections; null until a
  // mode needs one (rtgi only with the specular effect in the plan).
  const GpuBvh* bvh() const { return bvh_.get(); }

  // Decoded texture data. On the GPU: the scene's GL textures with their mip chains,
  // and the texels the BVH's texture reads use (path tracer on GL, rtgi's
  // reflections), when built. On the CPU: the scene's decoded images (kept for
  // re-uploads and emitter measurement) and the CPU path tracer's copy, when built.
  struct TextureMemory {
    size_t glTextures = 0, bvhTexels = 0, sceneImages = 0, cpuPathtracer = 0;
    size_t gpu() const { return glTextures + bvhTexels; }
    size_t cpu() const { return sceneImages + cpuPathtracer; }
  };
  TextureMemory textureMemory() const;

  // Re-creates the targets at width x height (checked as in the constructor).
  void resize(int width, int height);
  void setMode(Mode mode);
  // The scene was re-posed (Scene::pose): upload it; voxels follow with revoxelize.
  // Restarts accumulation, except in rtgi with reprojection, which follows each
  // point's motion from the previous vertex positions.
  void geometryChanged();
  // The same for everything Scene::pose() moves: the animated vertices (as
  // geometryChanged), and moved lights, which also re-light the voxels (the octree's
  // inject runs again on the next frame) and restart accumulation. The camera needs
  // nothing here: a frame from another camera restarts accumulation, or reprojects,
  // by itself.
  void posed();
  // The knobs of the current mode, then the tonemap's; setting one restarts
  // accumulation. Valid until the mode changes.
  std::vector<Knob> knobs();
  const TonemapPass::Settings& tonemapSettings() { return tonemap_.settings(); }
  void setTonemapSettings(const TonemapPass::Settings& s);

  // The size rtgi renders at: the output's under the render scale.
  glm::ivec2 internalSize() const {
    return scaledSize(settings_.width, settings_.height, settings_.renderScale);
  }
  int accumulatedFrames() const { return accumulated_; }
  void restartAccumulation() { accumulated_ = 0; }

  // The tonemapped RGBA8 target (for presenting) and the bytes of all targets.
  GLuint displayFramebuffer() const { return ldrFbo_.id(); }
  size_t targetBytes() const;

  // Top-left origin, RGBA.
  std::vector<float> readLinear() const;
  std::vector<uint8_t> readDisplay() const;

  const RenderSettings& settings() const { return settings_; }
  // What this renderer simulates (fixed at construction, for every mode but
  // pathtrace, which is the reference and renders everything).
  const scene::EffectPlan& effects() const { return plan_; }
  const GpuScene& gpuScene() const { return gpuScene_; }
  // Null unless the mode uses voxels (rtgi without shadows, indirect and specular
  // light does not).
  const voxel::VoxelizePass* voxelGrid() const { return voxelize_.get(); }
  // Null unless the mode uses the octree.
  const voxel::Octree* octree() const { return octree_.get(); }
  const RtgiPass* rtgi() const { return rtgi_.get(); }
  // NaN or Inf values rtgi's accumulation and the octree's passes met and replaced
  // (nonfinite.glsl); 0 when shading is sound. Reads back from the GPU.
  uint32_t nonfiniteTerms() const;
  // The frame budget's current traced fraction (1 without a budget).
  double traceFraction() const { return budget_ ? budget_->fraction() : 1.0; }
  // Display the work mask instead of the image (rtgi with a frame budget).
  // It keeps the mask made while it is shown (RtgiPass::Settings::keepMask).
  void setShowMask(bool show);
  // rtgi: turns the denoiser on or off (RtgiPass::Settings::denoise); accumulation
  // restarts, since the denoiser's moments are kept only while it is on.
  void setDenoise(bool on);
  // Whether the frames rendered from now on are shown (default) or only steps of an
  // accumulation whose last frame is: rtgi denoises only frames that are shown.
  void setFrameShown(bool shown);
  bool showMask() const { return showMask_; }
  // Stages that run once per scene (voxelize, octree, inject): GPU ms of their most
  // recent run, in order.
  const std::vector<gl::StageTime>& sceneStages() const { return sceneStages_; }

 private:
  gl::ProgramCache& programs_;
  const scene::Scene& scene_;
  RenderSettings settings_;
  scene::EffectPlan plan_;
  GpuScene gpuScene_;
  std::unique_ptr<RasterPass> raster_;
  std::unique_ptr<voxel::VoxelizePass> voxelize_;
  std::unique_ptr<PointsPass> points_;
  std::unique_ptr<voxel::Octree> octree_;
  std::unique_ptr<RtgiPass> rtgi_;
  std::unique_ptr<DvrPass> dvr_;
  std::unique_ptr<FrameBudget> budget_;
  bool showMask_ = false;
  bool frameShown_ = true;
  bool octreeBuilt_ = false;
  bool lightsMoved_ = false;  // the voxel light is stale: inject again
  std::vector<gl::StageTime> sceneStages_;
  TonemapPass tonemap_;
  bool voxelized_ = false;
  std::shared_ptr<const GpuBvh> bvh_;
  std::unique_ptr<Pathtracer> pathtrace_;
  Pathtracer::Progress progress_;
  std::vector<gl::StageTime> startup_;
  gl::StageTimer timer_;
  gl::Buffer frameUniforms_;
  gl::Texture hdr_, depth_, ldr_;
  // rtgi's accumulation target at the internal size (a render scale below 1), and
  // this frame's jitter, in its pixels.
  gl::Texture lowHdr_;
  glm::vec2 jitter_{0.0f};
  bool upsamples() const { return settings_.mode == Mode::kRtgi && settings_.renderScale < 1.0f; }
  gl::Framebuffer hdrFbo_, ldrFbo_;
  // The display image and the HDR target as one framebuffer: rtgi's upsampled
  // output writes both (TonemapPass::executeUpsampled).
  gl::Framebuffer upsampledFbo_;
  std::vector<gl::StageTime> stages_;
  int accumulated_ = 0;
  scene::Camera lastCamera_;
  glm::mat4 lastViewProj_{1.0f};  // lastCamera_'s, without jitter
  // Animated meshes moved since the last frame (rtgi reprojects along their motion);
  // the vertices' previous positions differ from the current ones.
  bool meshesMoved_ = false, geometryUnsettled_ = false;
  // Whether a camera or mesh move keeps rtgi's history (reprojection).
  bool reprojects() const;
  // The HDR image shown: rtgi's denoised one when it denoises, else the target.
  GLuint shownHdr() const;

  // The steps of renderFrame. followCamera: restarts or keeps the accumulation
  // after a camera or mesh move (true: rtgi reprojects its history).
  bool followCamera(const scene::Camera& camera);
  // This frame's uniforms (jittered in rtgi); returns the previous frame's
  // view-projection, without jitter.
  glm::mat4 uploadFrameUniforms(const scene::Camera& camera);
  // Which of the scene stages ran this frame (updateVoxels).
  struct SceneUpdate {
    bool voxelized = false;  // voxelize
    bool built = false;      // octree and inject
  };
  // Voxelizes, builds the octree, injects or refines its light, as the mode needs.
  // `moving`: the camera or meshes moved this frame and the pixels follow them.
  SceneUpdate updateVoxels(gl::FrameContext& ctx, bool moving);
  // The mode's pass, into the HDR target.
  void executeMode(gl::FrameContext& ctx, const scene::Camera& camera,
                   const glm::mat4* previousViewProj);
  // Keeps the latest times of the scene stages (sceneStages()).
  void recordSceneStages(bool voxelized);
  void createTargets();
  void warmUpFrame();  // warmUp's work
  // Builds the BVH at its first use (the "bvh" start-up stage).
  std::shared_ptr<const GpuBvh> sharedBvh();
  void createPasses();
  // modeUsesOctree / modeUsesVoxels under this renderer's effect plan.
  bool usesOctree(Mode m) const;
  bool usesVoxels(Mode m) const;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RENDERER_H

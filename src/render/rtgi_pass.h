// `--mode rtgi`: hybrid raster + ray-marched global illumination (the default mode).
//
// Reads: the GpuScene and a lit Octree. Writes: the running mean of linear HDR
// radiance into the renderer's RGBA32F target (which it keeps between frames).
// Stages, each timed:
//   gbuffer     primary visibility: position, normal + roughness, base colour
//               + metallic, emission, motion (rtgi_shared.h), rasterized or
//               (Settings::primary) cast as one ray a pixel through the BVH;
//   shadows     direct light with shadow rays through the octree (rtgi_direct.comp);
//               with the shadows effect off, "direct": the same without shadow rays,
//               and absent when there is no light at all;
//   indirect    one cosine ray per pixel into the lit voxels (rtgi_indirect.comp),
//               or six cones through the octree's filtered levels (rtgi_cones.glsl),
//               with the indirect effect;
//   specular    the reflected ray of mirrors and glossy surfaces (rtgi_specular.comp),
//               with the specular effect (the scene has such materials): traced
//               against the exact triangles when given a BVH (render/gpu_bvh.h), the
//               hit shaded with exact direct light (BVH shadow rays) plus voxel
//               indirect light; without one, the light of the voxel the ray meets;
//   caustics    with the specular effect, a BVH and emissive surfaces: light that
//               reaches a surface by way of mirrors, by photons sent from the
//               emitters through the mirrors and connected to the camera
//               (rtgi_caustics.comp);
//   reproject   after a camera move, first of all: each pixel's running mean follows
//               the surface it shows from the previous frame's pixels, dropped where
//               they showed another surface, its count capped (rtgi_reproject.comp,
//               RtgiHistory);
//   accumulate  emission + the three terms, into each pixel's running mean.
//   denoise     with Settings::denoise: the image shown is the running mean filtered
//               by a variance-guided, edge-avoiding wavelet (Schied et al. 2017,
//               rtgi_denoise.glsl; RtgiDenoiser), the direct light and the rest each
//               against its own noise; the mean itself stays as it was.
//   mask, select  with a frame budget: which pixels trace beyond the pattern, by
//               the work mask (RtgiWorkMask) or uniformly (rtgi_select.comp).
// Every stage draws its random numbers from a hash of (seed, pixel, frame, stage):
// each frame brings new samples, so accumulation converges.
#ifndef VOXGI_RENDER_RTGI_PASS_H
#define VOXGI_RENDER_RTGI_PASS_H

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "render/frame_context.h"
#include "render/gpu_bvh.h"
#include "render/gpu_scene.h"
#include "render/rtgi_denoiser.h"
#include "render/rtgi_history.h"
#include "render/rtgi_work_mask.h"
#include "rtgi_shared.h"
#include "scene/effects.h"
#include "scene/scene.h"
#include "voxel/octree.h"

namespace voxgi::render {

class RtgiPass {
 public:
  struct Settings {
    // From the effect plan (scene/effects.h): whether the indirect and specular
    // stages run, and the shader variants of the others.
    bool indirect = true;
    bool specular = true;
    scene::ShaderFeatures features;
    // Up to this many emitters: their summed contribution x one shadow ray; more:
    // one drawn from the light tree (rtgi_direct_light.glsl).
    int exactEmitters = 4;
    // Up to this many punctual lights: each its own shadow ray; more: one per pixel
    // and frame, drawn in proportion to its unshadowed contribution, which knows
    // nothing of shadows: in a room lit by its own lamp, behind walls that hide a
    // sun and the lights of the hall beside it, the lamp is drawn 1 time in 20.
    int exactLights = 8;
    // The same at the indirect rays' hits, whose light a cosine ray already scatters.
    int exactLightsAtHits = 4;
    // At the indirect rays' hits, the light tree's walk goes on down to nodes of at
    // most this many emitters before it weighs each one's bound (elsewhere: up to
    // gpu::kLightTreeLeafDraw, 128, or candidateLeafDraw where candidates are
    // resampled). A bound per emitter at every hit cost dark_plane (96 emitters)
    // half its indirect stage.
    int leafDrawAtHits = 16;
    // Rays a glossy pixel, or a mirror pixel whose reflection is strongly minified
    // (spread over its footprint), traces in a frame while its mean holds fewer than
    // 4 samples (a restart, a disocclusion); 1 after (rtgi_specular.comp). Those
    // pixels are few and, lit along one ray drawn from their lobe or showing one
    // point of their patch, were the noisiest of a first frame's. 0: kFirstLobeRays, but 1
    // under a frame budget (the Renderer decides), where the budget sets the work.
    int firstLobeRays = 0;
    // Many emitters (where the light tree walks nodes): each pixel's emitter sample
    // is resampled with its neighbours' (ReSTIR DI's spatial reuse,
    // rtgi_restir.glsl); false: each pixel draws from its own candidates only.
    bool reuseLights = true;
    // There, each pixel's light-tree candidates, each walking down to nodes of at
    // most candidateLeafDraw emitters before it weighs each one's bound: more,
    // cheaper candidates than two walks to 128 each (the hall's `shadows` -30%, FLIP
    // at 16 frames 0.072 -> 0.069). The same walks where candidates are resampled
    // without reuse (the mirrors' hits, --light-reuse off).
    int restirCandidates = 4;
    int candidateLeafDraw = 8;
    // There, the candidates of a pixel with a sharp glossy highlight (a metal or
    // glossy surface below roughness 0.5, not a mirror): its target peaks inside its
    // lobe, which the tree's bounds know nothing of, so few candidates seldom hold
    // the emitter the lobe sees (the hall's bronze knot: its variance at one frame
    // 0.234 -> 0.172, and 0.085 with lobeShareWeight below).
    int glossyCandidates = 16;
    // The lobe ray's weight against the light sample's in the balance heuristic that
    // shares a glossy pixel's highlights of triangle emitters between the two
    // (RTGI_HIGHLIGHT_MIS, rtgi_direct_light.glsl): the light's pdf is taken as
    // uniform over the triangle, above the draw's, and the lobe traces
    // firstLobeRays in a pixel's first frames. 1: the plain balance heuristic.
    float lobeShareWeight = 4.0f;
    // Few emitters (where the light tree draws among them all): each pixel takes its
    // emitter candidates among those drawn for its 8x8 tile (rtgi_light_tiles.comp)
    // and resamples them by its own bound on each; false: every pixel weighs every
    // emitter at its own point and draws one.
    bool lightTiles = true;
    // Candidates resampled per pixel from its light tile: each costs a read and one
    // bound. dark_plane's first frame (FLIP, seeds 7 and 8): 4 give 0.0452/0.0461, 8
    // 0.0453/0.0457, each pixel's own draw 0.0449/0.0456, at the same cost within
    // this machine's noise.
    int tileCandidates = 8;
    int interleave = 1;  // a pixel traces every N-th frame (1, 2, 4, 8, 16)
    // Beyond the interleave pattern, which further pixels trace (frame budget):
    // none, those the work mask marks as noisy, or a uniform random share.
    enum class Select { kPattern, kMask, kUniform } select = Select::kPattern;
    // With kMask, the mask is made only on frames that choose pixels by it: not
    // while the budget allows the pattern alone (a moving camera on a slow GL).
    // keepMask makes it on its period all the same, for whoever shows or writes it
    // (the viewer's mask view, `render --out-mask`).
    bool keepMask = false;
    // With interleaving: the first frame of an accumulation traces the pattern only,
    // like the others, instead of every pixel, and a pixel that has not traced yet
    // shows the light its traced neighbours on the same surface found. Every frame
    // costs the same, the first included: what a moving camera needs, since each
    // move restarts the accumulation (the viewer).
    bool sparseStart = false;
    // Reflections of the exact triangles (the Renderer then builds a BVH for the
    // specular stage); false: of the voxels, as before (no BVH).
    bool exactReflections = true;
    // The shadow and indirect rays of the pixels find their hits on the exact
    // triangles (the Renderer then builds a BVH); the voxels serve only as the light
    // cache at an indirect ray's hit. false: the rays march the voxels, which stop
    // them too early near contacts (the previous behaviour).
    bool exactRays = true;
    // How the G-buffer finds the surface each pixel shows: kRaster draws every
    // triangle (gbuffer.frag); kRays casts one ray a pixel through the BVH
    // (rtgi_gbuffer.comp), whose cost grows with the logarithm of the triangle
    // count rather than with it; kAuto is resolved by resolvePrimary before the pass
    // is made. kRays needs a BVH (meshes that do not move).
    enum class Primary { kAuto, kRaster, kRays } primary = Primary::kAuto;
    // How the indirect stage gathers diffuse indirect light: one random ray per pixel
    // and frame (accumulation averages them), or six cones through the octree's
    // filtered levels (voxel cone tracing; the same light every frame).
    enum class IndirectMethod { kRays, kCones } indirectMethod = IndirectMethod::kRays;
    // A camera move keeps the image: each pixel's history is reprojected onto the
    // surface it now shows (false: a move restarts accumulation).
    bool reproject = true;
    // While the camera moves, a pixel's history counts at most this many frames
    // (glossy surfaces at most kGlossyHistory, mirrors none), so the light follows
    // the view; a still camera accumulates without a cap.
    int historyCap = 16;
    // After meshes moved, a pixel whose history disagrees with this frame's light
    // around it beyond their noise (a shadow or bounce that moved) drops it
    // (rtgi_accumulate.comp, RTGI_RELIGHT).
    bool dropStaleHistory = true;
    // The image shown is the running mean denoised (rtgi_denoise.glsl): each pixel's
    // light filtered with its neighbours' on the same surface, as strongly as the
    // mean's measured noise asks, so less and less as a still image converges.
    bool denoise = false;
    // Its edge stops: how far two pixels' luminances may differ, in units of their
    // noise (the standard deviation of the mean), and a neighbour's distance from the
    // pixel's tangent plane, relative to the pixel's distance from the camera.
    float denoiseLuminance = 4.0f;
    float denoisePlane = 0.01f;
    // Light by way of mirrors (the caustics stage): photons from the emissive
    // surfaces, aimed at the mirrors, connected to the camera; causticPhotons a
    // frame, 0: kCausticPhotonsPerPixel of the internal image's pixels.
    bool caustics = true;
    int causticPhotons = 0;
    uint32_t seed = 1;
  };

  // `bvh`: the scene's triangles, for the specular stage's rays (with
  // exactReflections) and the shadow and indirect rays (with exactRays); null: every
  // ray marches the voxels.
  RtgiPass(gl::ProgramCache& programs, const Settings& settings,
           std::shared_ptr<const GpuBvh> bvh = nullptr);
  // Renders frame `frameIndex` of the accumulation (0 restarts it) into `accum`.
  // `octree` may be null when the settings trace nothing (no shadows, indirect or
  // specular light). `camera`: this frame's (its position and field of view).
  // `previousViewProj`, on a frame after the camera moved (not the
  // first): the view-projection, without jitter, of the frame before, whose image
  // `accum` holds; the history is reprojected from it.
  void execute(gl::FrameContext& ctx, const GpuScene& scene, const voxel::Octree* octree,
               const scene::Camera& camera, int frameIndex, GLuint accum,
               const glm::mat4* previousViewProj = nullptr);
  // A render scale below 1 (RenderSettings::renderScale): after execute() at the
  // internal size, upsample() adds this frame's fresh samples to the output's
  // history (at ctx's size), each in the output pixel it landed in
  // (rtgi_upsample.comp, a temporal upsampler). `jitter`: this frame's G-buffer
  // offset, in internal pixels. `restart`: accumulation restarted, or the camera or
  // meshes moved; the history starts again (the internal image, which follows the
  // move, carries what is shown meanwhile). What is shown blends the history with
  // the internal image (TonemapPass::executeUpsampled).
  void upsample(gl::FrameContext& ctx, glm::vec2 jitter, bool restart);
  // The output's history after upsample(): rgba32f, per pixel the sum of the samples
  // that landed in it and their count.
  GLuint upsampleHistory() const { return upsampleHistory_.id(); }
  // The internal image shown (the denoised mean, or the mean `accum`), and the
  // bilinear sampler the output reads it through.
  GLuint upsampleShown(GLuint accum) const { return denoised_ ? denoiser_.image() : accum; }
  GLuint linearSampler() const { return linear_.id(); }
  // The internal image's weight in what is shown, in samples of the output pixel's
  // own: it fills in where they are few and fades as they come. A single sample is
  // as noisy as a path; the internal image is a mean of many (denoised where the
  // denoiser runs) but blurred to the internal pixel. cornell_room at 256x256, scale
  // 0.5, 64 frames: FLIP 0.071 / 0.070 / 0.067 at weights 2 / 8 / 32, 0.068 with the
  // internal image alone; 256 frames: 0.059 at 16, 0.065 alone (scale 1: 0.049).
  static constexpr float kUpsampleInternalWeight = 16.0f;
  // Glossy surfaces (not mirrors) keep at most this many frames of history across a
  // camera move: their highlights move with the view.
  static constexpr int kGlossyHistory = 4;
  static constexpr int kFirstLobeRays = 4;  // Settings::firstLobeRays' default
  // Settings::causticPhotons' default, per pixel of the internal image.
  static constexpr double kCausticPhotonsPerPixel = 1.0 / 16.0;
  // Whether the caustics stage runs in scene gs: the settings ask for it, the
  // specular stage traces the triangles, the scene has emissive surfaces and
  // mirrors, and its meshes stay still (the mirrors' spheres are made once).
  bool tracesCaustics(const GpuScene& gs);
  // The photons a frame of the caustics stage sends at the internal size when a
  // share `traced` of the pixels trace (their light is added only to those):
  // Settings::causticPhotons, or kCausticPhotonsPerPixel of the pixels that trace,
  // kMinCausticPhotons at least.
  int causticPhotons(double traced = 1.0) const;
  static constexpr int kMinCausticPhotons = 256;
  // The photons the last frame's caustics stage sent (0: it did not run), and the
  // mirrors' spheres they aimed at (0 before a frame asked).
  int lastCausticPhotons() const { return causticsThisFrame_ ? lastCausticPhotons_ : 0; }
  bool lastFrameCaustics() const { return causticsThisFrame_; }
  int causticTargets() const { return std::max(causticTargets_, 0); }
  // The specular stage's rays in a pixel's first frames.
  int firstLobeRays() const {
    return settings_.firstLobeRays > 0 ? settings_.firstLobeRays : kFirstLobeRays;
  }
  // Nor do pixels on an edge between surfaces.
  static constexpr int kEdgeHistory = 2;
  const Settings& settings() const { return settings_; }
  Settings& settings() { return settings_; }
  // The share of all pixels, pattern included, the next frame should trace (frame
  // budget; with Select::kMask or kUniform).
  void setTraceFraction(double f) { traceFraction_ = f; }
  // Whether meshes moved since the last frame (the next execute() reprojects).
  void setMeshesMoved(bool moved) { meshesMoved_ = moved; }
  // Pixels that traced in the last frame, as a share of all.
  double lastTracedFraction() const { return lastTraced_; }
  // Of all pixels, those the last frame's specular stage traced (the specular ones
  // among those that traced; 0 without the specular effect).
  double lastSpecularFraction() const { return lastSpecular_; }
  // Non-finite terms accumulate met and dropped since the pass was made
  // (nonfinite.glsl); reads back from the GPU.
  uint32_t nonfiniteTerms() const;
  // The last work mask, [0, 1) per pixel, top-left origin (empty before one ran).
  std::vector<float> readMask() const { return mask_.read(); }
  GLuint maskTexture() const { return mask_.valid() ? mask_.image() : 0; }
  int maskWidth() const { return mask_.valid() ? mask_.width() : 0; }
  int maskHeight() const { return mask_.valid() ? mask_.height() : 0; }
  size_t targetBytes() const { return targetBytes_; }
  // The denoised image of the last frame (rgba32f, the accumulation target's layout),
  // or 0 when the denoiser is off: what the renderer shows in place of the mean.
  GLuint denoisedTexture() const { return denoised_ ? denoiser_.image() : 0; }
  // Whether the next frames are shown (default): the denoiser filters only those.
  // `voxgi render` shows only the last frame it accumulates, so only that one pays
  // for the filter; the moments it needs are kept every frame.
  void setShown(bool shown) { shown_ = shown; }
  // Whether the specular stage runs and traces the exact triangles.
  bool tracesTriangles() const {
    return bvh_ != nullptr && settings_.specular && settings_.exactReflections;
  }
  // Whether the specular stage's lobe rays share the glossy pixels' highlights of
  // emitters with the direct stage (RTGI_HIGHLIGHT_MIS, rtgi_direct_light.glsl): they
  // trace the triangles, and the direct stage traces shadow rays to emitters.
  bool sharesHighlights(const GpuScene& gs) const {
    return tracesTriangles() && settings_.indirectMethod != Settings::IndirectMethod::kCones &&
           settings_.features.shadows && settings_.features.emission && gs.emitterCount() > 0;
  }
  // Whether the shadow and indirect rays do.
  bool raysHitTriangles() const { return bvh_ != nullptr && settings_.exactRays; }
  // How the pixels' direct light samples gs's emitters, as --stats says it: "none",
  // "exact" (each one weighed at every pixel), "light_tiles", "light_tree" or
  // "restir"; and its punctual lights: "none", "exact" (a shadow ray each) or
  // "sampled" (one drawn a pixel). What runs, which the settings alone do not say.
  const char* emitterSampling(const GpuScene& gs) const;
  const char* punctualSampling(const GpuScene& gs) const;
  // Whether the G-buffer is made by rays (Settings::primary).
  bool primaryRays() const {
    return bvh_ != nullptr && settings_.primary == Settings::Primary::kRays;
  }
  // Whether rtgi with settings `s` (s.indirect as the effect plan sets it) lights its
  // indirect rays' hits exactly and reads the voxel bounces there apart from their
  // direct light (voxel::Octree::Settings::keepBounces): its indirect rays are rays
  // on the triangles, which a scene whose meshes move does not get.
  static bool readsVoxelBounces(const Settings& s, bool meshesAnimated) {
    return s.indirect && s.exactRays && s.indirectMethod == Settings::IndirectMethod::kRays &&
           !meshesAnimated;
  }

 private:
  // The defines of an rtgi stage that traces the BVH (rtgi_bvh.glsl) in scene gs,
  // and its buffers bound for such stages, or unbound (bvh_ set).
  std::vector<std::string> bvhDefines(const GpuScene& gs) const;
  void bindBvh(const GpuScene& gs) const;
  void unbindBvh() const;
  // This frame's choices, from the settings, the scene and the frame (execute).
  struct FramePlan {
    bool reprojecting = false;  // after a camera move, not on the first frame
    bool relight = false;       // reprojecting after meshes moved: stale history drops
    bool shadows = false;       // the direct stage traces shadow rays
    bool direct = false;        // the direct stage runs
    int interleave = 1;         // this frame's (a sparse start's first may differ)
    bool everyPixel = false;    // every pixel traces this frame
    bool listed = false;        // the select stage lists the pixels that trace
    bool lends = false;         // accumulate lends light to pixels not yet traced
    GLuint gx = 0, gy = 0;      // groups of the per-pixel stages
    GLuint tx = 0, ty = 0;      // groups of the tracing stages, by pattern
    uint64_t pixelsTotal = 0;
  };
  FramePlan planFrame(const gl::FrameContext& ctx, const GpuScene& gs, int frameIndex,
                      bool moved) const;
  gpu::RtgiParams frameParams(const gl::FrameContext& ctx, const GpuScene& gs,
                              const scene::Camera& camera, int frameIndex,
                              const glm::mat4* previousViewProj, const FramePlan& plan) const;
  // The gbuffer stage, into fbo_[current_].
  void drawGBuffer(gl::FrameContext& ctx, const GpuScene& gs);
  // The parameters, scene buffers, G-buffer and images the compute stages read.
  void bindFrameInputs(const GpuScene& gs, const voxel::Octree* octree, GLuint accum);
  // This frame's direct, indirect and specular images on their image units.
  void bindTermImages(GLenum access) const;
  // The select stage (frame budget): the list of pixels that trace; sets the
  // selection's level and kind in `p` and uploads it.
  void selectPixels(gl::FrameContext& ctx, int frameIndex, const FramePlan& plan,
                    gpu::RtgiParams* p);
  // One timed compute stage over the pixels that trace (accumulate: every pixel).
  void runStage(gl::FrameContext& ctx, Stage stage, const gl::Program& program,
                const FramePlan& plan);
  // The caustics stage (rtgi_caustics.comp), into caustic_.
  void traceCaustics(gl::FrameContext& ctx, const GpuScene& gs);
  // The shadows (or direct), indirect and specular stages.
  void traceLight(gl::FrameContext& ctx, const GpuScene& gs, const FramePlan& plan);
  // The specular stage: the specular pixels among those that trace listed, then
  // traced (rtgi_specular_select.comp).
  void traceSpecular(gl::FrameContext& ctx, const GpuScene& gs, const FramePlan& plan);
  void accumulateFrame(gl::FrameContext& ctx, const FramePlan& plan);
  // The traced share of a listed frame, and the units the frame bound, unbound.
  void finishFrame(const FramePlan& plan);
  void resize(int width, int height);

  // `restir`: the variant of the direct stage's reservoir resampling, "" none.
  const gl::Program& directProgram(const GpuScene& gs, const char* restir = "");
  // Whether the direct stage resamples reservoirs of emitters (reuseLights with many
  // emitters and shadow rays).
  bool reusesLights(const GpuScene& gs) const;
  // Whether the direct stage draws its emitters from light tiles (lightTiles with
  // few enough emitters that the tree draws among them all, and frames that trace a
  // quarter of the pixels or more).
  bool usesLightTiles(const GpuScene& gs) const;
  // The light tiles for this frame's G-buffer (rtgi_light_tiles.comp).
  void makeLightTiles(gl::FrameContext& ctx);
  const gl::Program& specularProgram(const GpuScene& gs);
  const gl::Program& indirectProgram(const GpuScene& gs);
  // {"RTGI_CONES"} with cone-traced indirect light (glossy reflections are cones too).
  std::vector<std::string> conesDefine() const;
  // The specular stage's rays in a pixel's first frames (Settings::firstLobeRays).
  std::string firstLobeRaysDefine() const;
  // The lobe ray's weight in the shared highlights (Settings::lobeShareWeight).
  std::string lobeShareDefine() const;
  // The direct light's variant for gs's lights, at the pixels or (atHits) at the
  // indirect rays' hits.
  std::vector<std::string> lightDefines(const GpuScene& gs, bool atHits = false) const;
  // The programs of the indirect and specular stages, built only when they run.
  void buildOptionalStages();
  // The G-buffer made by one ray a pixel through the BVH (primaryRays()).
  void castGBuffer(gl::FrameContext& ctx, const GpuScene& gs);

  Settings settings_;
  gl::ProgramCache& programs_;
  std::shared_ptr<const GpuBvh> bvh_;
  const gl::Program& gbuffer_;
  const gl::Program& accumulate_;
  const gl::Program* accumulateVariant_ = nullptr;  // this frame's, when not accumulate_
  const gl::Program* indirect_ = nullptr;
  const gl::Program* specular_ = nullptr;
  double traceFraction_ = 1.0;
  bool meshesMoved_ = false;
  double lastTraced_ = 1.0;
  double lastSpecular_ = 0.0;
  RtgiWorkMask mask_;
  gl::Texture tracedImage_;
  gl::Buffer pixelList_;
  gl::Buffer params_;
  gl::Buffer nonfinite_;  // uint: terms dropped by accumulate (kNonfiniteCountBinding)
  // The shadows stage's reservoirs (kRtgiReservoirBinding), made on first use.
  gl::Buffer reservoirs_;
  size_t reservoirBytes_ = 0;
  // The light tiles (at kRtgiReservoirBinding), made on first use.
  gl::Buffer lightTiles_;
  size_t lightTileBytes_ = 0;
  // The specular stage's pixels (kSpecularListBinding), made on first use.
  gl::Buffer specularList_;
  // The caustics stage: its light per pixel, and the mirrors' bounding spheres
  // (causticTargets_ of them; -1 before they are made).
  gl::Buffer caustic_;
  size_t causticBytes_ = 0;
  gl::Buffer causticSpheres_;
  int causticTargets_ = -1;
  bool causticsThisFrame_ = false;
  int lastCausticPhotons_ = 0;
  size_t specularListBytes_ = 0;
  // Two G-buffers, this frame's ([current_]) and the previous one's, for reprojection:
  // they share all but position and normal.
  gl::Texture position_[2], normal_[2], albedo_, emission_, motion_, depth_;
  gl::Framebuffer fbo_[2];
  int current_ = 0;
  gl::Texture directImage_, indirectImage_, specularImage_;
  // The moments and direct mean beside the mean, and the reprojected history.
  RtgiHistory history_;
  RtgiDenoiser denoiser_;
  bool denoised_ = false;  // denoiser_ filtered this frame
  bool shown_ = true;
  int width_ = 0, height_ = 0;
  size_t targetBytes_ = 0;
  // The temporal upsampler: the output's history (sum and count per pixel), its
  // parameters, and the linear filter the output's reads of the internal image use.
  gl::Texture upsampleHistory_;
  int outputWidth_ = 0, outputHeight_ = 0;
  gl::Buffer upsampleParams_;
  gl::Sampler linear_;
};

// Settings::primary resolved: kAuto casts rays on a software GL (`software`) when the
// scene has more than kPrimaryRaysPerPixel triangles per pixel of the G-buffer
// (`pixels`) and its meshes do not move, and rasterizes otherwise. kRays for a scene
// whose meshes move throws Error: its BVH would need a rebuild every pose. On
// llvmpipe a primary ray costs about 0.5 us, rasterizing 0.09 us a triangle plus
// 0.1-0.2 us a pixel: the two meet near 4 triangles a pixel (measured at 256x256 and
// 640x360 on halls of 37 k to 2.4 M triangles, docs/scale.md). A hardware
// rasterizer is far ahead of rays at any count.
inline constexpr double kPrimaryRaysPerPixel = 4.0;
RtgiPass::Settings::Primary resolvePrimary(RtgiPass::Settings::Primary primary, bool software,
                                           size_t triangles, size_t pixels, bool meshesAnimated);

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RTGI_PASS_H

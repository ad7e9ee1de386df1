#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/log.h"
#include "core/memory.h"
#include "gl/debug.h"
#include "render/pathtrace/pathtrace_cpu.h"
#include "render/pathtrace/pathtrace_pass.h"

namespace voxgi::render {

std::optional<Mode> parseMode(const std::string& name) {
  if (name == "raster") return Mode::kRaster;
  if (name == "points") return Mode::kPoints;
  if (name == "dvr") return Mode::kDvr;
  if (name == "rtgi") return Mode::kRtgi;
  if (name == "pathtrace") return Mode::kPathtrace;
  return std::nullopt;
}

const char* modeName(Mode m) {
  switch (m) {
    case Mode::kRaster:
      return "raster";
    case Mode::kPoints:
      return "points";
    case Mode::kDvr:
      return "dvr";
    case Mode::kRtgi:
      return "rtgi";
    case Mode::kPathtrace:
      return "pathtrace";
  }
  return "?";
}

bool modeUsesVoxels(Mode m) {
  return m == Mode::kPoints || modeUsesOctree(m);
}

bool modeUsesOctree(Mode m) {
  return m == Mode::kDvr || m == Mode::kRtgi;
}

int defaultFrames(Mode m) {
  return m == Mode::kRtgi ? kRtgiDefaultFrames : 1;
}

std::string availableModes() {
  return "rtgi, raster, points, dvr, pathtrace";
}

scene::EffectPlan effectPlan(const scene::Scene& scene, const RenderSettings& settings) {
  scene::EffectPlan plan = scene::planEffects(scene);
  if (settings.octree.bounces == 0 && plan.has(scene::Effect::kIndirect))
    plan.skip(scene::Effect::kIndirect, "--bounces 0");
  scene::applyOverrides(&plan, settings.effects);
  return plan;
}

glm::vec2 subpixelJitter(int k) {
  // 1/g and 1/g^2 for g the plastic number (the real root of x^3 = x + 1).
  constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
  const double n = static_cast<double>(k);
  return glm::vec2(static_cast<float>(std::fmod(0.5 + a1 * n, 1.0) - 0.5),
                   static_cast<float>(std::fmod(0.5 + a2 * n, 1.0) - 0.5));
}

glm::ivec2 scaledSize(int width, int height, float scale) {
  return glm::ivec2(
      std::max(1, static_cast<int>(std::lround(static_cast<double>(width) * scale))),
      std::max(1, static_cast<int>(std::lround(static_cast<double>(height) * scale))));
}

void checkImageSize(int width, int height) {
  if (width < 1 || height < 1)
    throw Error(strf("image size %dx%d: must be at least 1x1", width, height));
  GLint maxTex = 0, maxRb = 0, maxVp[2] = {0, 0};
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRb);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxVp);
  const int limit = std::min({maxTex, maxRb, maxVp[0], maxVp[1]});
  if (width > limit || height > limit)
    throw Error(strf("image size %dx%d: larger than this GL's limit of %dx%d", width, height, limit,
                     limit));
  // HDR RGBA32F + depth + RGBA8 on the GPU, and the same again for readback.
  const double bytes = static_cast<double>(width) * height * (16 + 4 + 4) * 2.0;
  constexpr double kBudget = 8.0 * 1024 * 1024 * 1024;
  if (bytes > kBudget)
    throw Error(
        strf("image size %dx%d: needs %.1f GiB of image memory, more than the %.0f GiB budget",
             width, height, bytes / (1 << 30), kBudget / (1 << 30)));
}

namespace {
double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}
}  // namespace

Renderer::Renderer(gl::ProgramCache& programs, const scene::Scene& scene,
                   const RenderSettings& settings)
    : programs_(programs),
      scene_(scene),
      settings_(settings),
      plan_(effectPlan(scene, settings)),
      gpuScene_(scene),
      tonemap_(programs, settings.tonemap) {
  if (!(settings.renderScale >= kMinRenderScale && settings.renderScale <= kMaxRenderScale))
    throw Error(strf("render scale %g: must be between %g and %g", settings.renderScale,
                     kMinRenderScale, kMaxRenderScale));
  startup_.push_back({Stage::kUpload, 0.0, gpuScene_.uploadMs()});
  const auto start = std::chrono::steady_clock::now();
  const size_t before = startup_.size();
  createPasses();
  createTargets();
  frameUniforms_ = gl::createBuffer(sizeof(gpu::GpuFrame), nullptr, GL_DYNAMIC_STORAGE_BIT);
  // The passes' own time: the BVH, built while they are made, is a stage of its own.
  double passes = msSince(start);
  for (size_t i = before; i < startup_.size(); ++i) passes -= startup_[i].cpuMs;
  startup_.push_back({Stage::kPasses, 0.0, std::max(passes, 0.0)});
}

// rtgi traces the octree for shadows, indirect and specular light; with none of
// them in the plan it needs no voxels at all.
bool Renderer::usesOctree(Mode m) const {
  if (m == Mode::kRtgi)
    return plan_.has(scene::Effect::kShadows) || plan_.has(scene::Effect::kIndirect) ||
           plan_.has(scene::Effect::kSpecular);
  return modeUsesOctree(m);
}

bool Renderer::usesVoxels(Mode m) const {
  return m == Mode::kPoints || usesOctree(m);
}

// Builds what the current mode needs and nothing else (a mode never used costs
// neither shader compiles nor memory); passes of earlier modes are kept.
void Renderer::createPasses() {
  const Mode mode = settings_.mode;
  scene::ShaderFeatures features = scene::shaderFeatures(plan_);
  features.secondUv = gpuScene_.scene().hasSecondUv();
  if (mode == Mode::kRaster && !raster_) {
    RasterPass::Settings rs;
    rs.features = features;
    rs.ambient = settings_.ambient;
    raster_ = std::make_unique<RasterPass>(programs_, rs);
  }
  if (usesVoxels(mode) && !voxelize_) {
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    voxel::VoxelizePass::Settings vs;
    vs.resolution = settings_.voxels;
    vs.keepSums = settings_.revoxelize;
    vs.smallTrianglesInCompute = settings_.smallTrianglesInCompute;
    vs.checksum = settings_.voxelChecksum;
    vs.memoryBudgetBytes = settings_.voxelBudgetBytes;
    vs.features = features;
    voxelize_ = std::make_unique<voxel::VoxelizePass>(programs_, r ? r : "", vs);
    voxelized_ = false;
  }
  if (mode == Mode::kPoints && !points_)
    points_ = std::make_unique<PointsPass>(programs_, PointsPass::Settings{});
  if (mode == Mode::kRtgi && !rtgi_) {
    RtgiPass::Settings rs = settings_.rtgi;
    rs.keepMask = rs.keepMask || showMask_;
    rs.indirect = plan_.has(scene::Effect::kIndirect);
    rs.specular = plan_.has(scene::Effect::kSpecular);
    rs.features = features;
    if (settings_.targetFps > 0.0) {
      if (rs.interleave == 1) rs.interleave = static_cast<int>(gpu::kMaxInterleave);
      if (rs.select == RtgiPass::Settings::Select::kPattern)
        rs.select = RtgiPass::Settings::Select::kMask;
      const double floor = 1.0 / rs.interleave;
      budget_ = std::make_unique<FrameBudget>(1000.0 / settings_.targetFps, floor, 1.0, floor,
                                              FrameBudget::Gains{});
      // The budget sets the work: a glossy pixel traces one ray a frame, unless
      // asked for more.
      if (rs.firstLobeRays == 0) rs.firstLobeRays = 1;
    }
    // Reflections of the exact triangles need a BVH (when the plan has mirrors or
    // glossy surfaces), and so do shadow and indirect rays on them. A scene whose
    // meshes move keeps every ray on the voxels: its BVH would need a rebuild per
    // pose (a moving camera or light leaves it as it is).
    std::shared_ptr<const GpuBvh> bvh;
    const char* glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const glm::ivec2 internal = internalSize();
    rs.primary = resolvePrimary(
        rs.primary, isSoftwareRenderer(glRenderer ? glRenderer : ""), scene_.triangleCount(),
        static_cast<size_t>(internal.x) * static_cast<size_t>(internal.y), scene_.meshesAnimated());
    const bool raysUseBvh = rs.exactRays && (rs.indirect || features.shadows);
    if (((rs.specular && rs.exactReflections) || raysUseBvh ||
         rs.primary == RtgiPass::Settings::Primary::kRays) &&
        !scene_.meshesAnimated())
      bvh = sharedBvh();
    rtgi_ = std::make_unique<RtgiPass>(programs_, rs, std::move(bvh));
    rtgi_->setShown(frameShown_);
  }
  // rtgi's indirect rays on the triangles read the voxel bounces apart from the
  // direct light: an octree made for another mode without them is made again.
  RtgiPass::Settings rt = settings_.rtgi;
  rt.indirect = plan_.has(scene::Effect::kIndirect);
  const bool keepBounces =
      mode == Mode::kRtgi && RtgiPass::readsVoxelBounces(rt, scene_.meshesAnimated());
  // With rtgi's BVH, the voxels' shadow and bounce rays run on the exact triangles.
  const bool exactVoxelRays =
      mode == Mode::kRtgi && rtgi_ && rtgi_->raysHitTriangles() && features.shadows;
  if (usesOctree(mode) && (!octree_ || (keepBounces && !octree_->settings().keepBounces) ||
                           (exactVoxelRays && octree_->settings().bvhDefines.empty()))) {
    voxel::Octree::Settings os = settings_.octree;
    if (exactVoxelRays) os.bvhDefines = bvh_->traceDefines(scene_, features);
    os.features = features;
    // Voxel bounces are indirect light too (mirrors see them): without the indirect
    // effect the voxels hold direct light only.
    if (!plan_.has(scene::Effect::kIndirect)) os.bounces = std::min(os.bounces, 1);
    os.keepBounces = keepBounces;
    octree_ = std::make_unique<voxel::Octree>(programs_, os);
    octreeBuilt_ = false;
  }
  if (mode == Mode::kDvr && !dvr_) dvr_ = std::make_unique<DvrPass>(programs_, DvrPass::Settings{});
  if (mode == Mode::kPathtrace && !pathtrace_) {
    PathtraceSettings ps = settings_.pathtrace;
    ps.textures = features.textures;
    ps.colors = features.colors;
    ps.normalMaps = features.normalMaps;
    ps.alpha = features.alpha;
    const char* glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    ps.device = resolvePathtraceDevice(ps.device, glRenderer ? glRenderer : "");
    if (ps.device == PathtraceDevice::kCpu)
      pathtrace_ = std::make_unique<CpuPathtracer>(scene_, ps);
    else
      pathtrace_ = std::make_unique<PathtracePass>(programs_, gpuScene_, ps, sharedBvh());
    if (ps.device == PathtraceDevice::kCpu)
      startup_.push_back({Stage::kBvh, 0.0, pathtrace_->bvhBuildMs()});
  }
}

std::shared_ptr<const GpuBvh> Renderer::sharedBvh() {
  if (!bvh_) {
    // The stage is the whole of it: the build (GpuBvh::buildMs) and the uploads of
    // the nodes and the triangles' records after it (0.18 s of 0.75 at 2.44 M).
    const auto start = std::chrono::steady_clock::now();
    bvh_ = std::make_shared<const GpuBvh>(gpuScene_, scene::shaderFeatures(plan_).textures);
    releaseFreedMemory();  // the build's working arrays
    startup_.push_back({Stage::kBvh, 0.0, msSince(start)});
  }
  return bvh_;
}

void Renderer::createTargets() {
  checkImageSize(settings_.width, settings_.height);
  const int w = settings_.width, h = settings_.height;
  hdr_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(hdr_.id(), 1, GL_RGBA32F, w, h);
  depth_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(depth_.id(), 1, GL_DEPTH_COMPONENT32F, w, h);
  ldr_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(ldr_.id(), 1, GL_RGBA8, w, h);
  for (GLuint t : {hdr_.id(), depth_.id(), ldr_.id()}) {
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  hdrFbo_ = gl::createFramebuffer();
  glNamedFramebufferTexture(hdrFbo_.id(), GL_COLOR_ATTACHMENT0, hdr_.id(), 0);
  glNamedFramebufferTexture(hdrFbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  ldrFbo_ = gl::createFramebuffer();
  glNamedFramebufferTexture(ldrFbo_.id(), GL_COLOR_ATTACHMENT0, ldr_.id(), 0);
  lowHdr_.reset();
  if (settings_.renderScale < 1.0f) {
    const glm::ivec2 low = internalSize();
    lowHdr_ = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(lowHdr_.id(), 1, GL_RGBA32F, low.x, low.y);
    glTextureParameteri(lowHdr_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(lowHdr_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  upsampledFbo_ = gl::createFramebuffer();
  glNamedFramebufferTexture(upsampledFbo_.id(), GL_COLOR_ATTACHMENT0, ldr_.id(), 0);
  glNamedFramebufferTexture(upsampledFbo_.id(), GL_COLOR_ATTACHMENT1, hdr_.id(), 0);
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(upsampledFbo_.id(), 2, both);
  for (GLuint f : {hdrFbo_.id(), ldrFbo_.id(), upsampledFbo_.id()}) {
    const GLenum status = glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw Error(strf("image size %dx%d: framebuffer incomplete (0x%x)", w, h, status));
  }
  accumulated_ = 0;
}

void Renderer::resize(int width, int height) {
  if (width == settings_.width && height == settings_.height) return;
  checkImageSize(width, height);
  settings_.width = width;
  settings_.height = height;
  createTargets();
}

void Renderer::geometryChanged() {
  gpuScene_.updateGeometry();
  // rtgi with reprojection carries the history over, along the meshes' motion.
  if (reprojects() && accumulated_ > 0)
    meshesMoved_ = true;
  else
    accumulated_ = 0;
}

bool Renderer::reprojects() const {
  return settings_.mode == Mode::kRtgi && rtgi_ && rtgi_->settings().reproject;
}

void Renderer::posed() {
  if (scene_.meshesAnimated()) {
    geometryChanged();
    // The path tracer traces the triangles of the pose its BVH (or the CPU device's
    // scene) was built at: both are made again for the new one.
    if (pathtrace_) {
      pathtrace_.reset();
      bvh_.reset();
      createPasses();
    }
  }
  if (scene_.lightsAnimated()) {
    gpuScene_.updateLights();
    lightsMoved_ = true;
    accumulated_ = 0;
  }
}

void Renderer::setMode(Mode mode) {
  if (mode == settings_.mode) return;
  const Mode previous = settings_.mode;
  settings_.mode = mode;
  try {
    createPasses();
  } catch (...) {
    settings_.mode = previous;  // e.g. a voxel grid that does not fit: stay as we were
    throw;
  }
  accumulated_ = 0;
}

std::vector<Knob> Renderer::knobs() {
  std::vector<Knob> out;
  switch (settings_.mode) {
    case Mode::kRaster:
    case Mode::kPoints:
    case Mode::kDvr:
    case Mode::kRtgi:
    case Mode::kPathtrace:
      break;  // nothing to turn yet (grid resolution, bounces and spp are fixed at start)
  }
  tonemap_.appendKnobs(&out);
  for (Knob& k : out) {
    k.set = [this, set = std::move(k.set)](double v) {
      set(v);
      settings_.tonemap = tonemap_.settings();
      accumulated_ = 0;
    };
  }
  return out;
}

void Renderer::setTonemapSettings(const TonemapPass::Settings& s) {
  tonemap_.settings() = s;
  settings_.tonemap = s;
  accumulated_ = 0;
}

uint32_t Renderer::nonfiniteTerms() const {
  return (rtgi_ ? rtgi_->nonfiniteTerms() : 0u) + (octree_ ? octree_->nonfiniteTerms() : 0u);
}

size_t Renderer::targetBytes() const {
  const glm::ivec2 low = internalSize();
  return static_cast<size_t>(settings_.width) * static_cast<size_t>(settings_.height) *
             (16 + 4 + 4) +
         (lowHdr_ ? static_cast<size_t>(low.x) * static_cast<size_t>(low.y) * 16 : 0) +
         (rtgi_ ? rtgi_->targetBytes() : 0);
}

Renderer::TextureMemory Renderer::textureMemory() const {
  TextureMemory m;
  m.glTextures = gpuScene_.textureBytes();
  if (bvh_) m.bvhTexels = bvh_->textureBytes();
  for (const scene::Texture& t : scene_.textures) m.sceneImages += t.rgba8.size();
  if (pathtrace_) m.cpuPathtracer = pathtrace_->hostTextureBytes();
  return m;
}

void Renderer::warmUp() {
  const auto start = std::chrono::steady_clock::now();
  warmUpFrame();
  startup_.push_back({Stage::kWarmUp, 0.0, msSince(start)});
}

void Renderer::warmUpFrame() {
  if (settings_.mode != Mode::kPathtrace) {
    // A frame at most kWarmUpSize pixels wide or high: the programs are compiled at
    // their first dispatch, whatever the size, and the voxels are made and lit,
    // which do not depend on it, while the per-pixel stages cost next to nothing
    // (at full size the warm-up was a whole frame of work thrown away: 0.4 s in the
    // hall). It is not part of the image. The first frame after it still makes
    // llvmpipe build variants of its own for refine, shadows, indirect and specular
    // (a second state, as after a full-size warm-up): read back from Mesa's disk
    // cache in a few ms, 0.6-1.4 s each with the cache off or cold.
    const int w = settings_.width, h = settings_.height;
    const int longest = std::max(w, h);
    if (longest > kWarmUpSize)
      resize(std::max(1, w * kWarmUpSize / longest), std::max(1, h * kWarmUpSize / longest));
    renderFrame();
    resize(w, h);
    accumulated_ = 0;
    return;
  }
  gl::FrameContext ctx{programs_, timer_, settings_.width, settings_.height, frameUniforms_.id()};
  pathtrace_->warmUp(ctx, hdr_.id());
  tonemap_.execute(ctx, hdr_.id(), ldrFbo_.id());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glFinish();
  timer_.resolve();
}

void Renderer::renderFrame() {
  renderFrame(scene_.camera);
}

namespace {
bool sameCamera(const scene::Camera& a, const scene::Camera& b) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up && a.yfov == b.yfov &&
         a.znear == b.znear && a.zfar == b.zfar;
}
}  // namespace

void Renderer::renderFrame(const scene::Camera& camera) {
  const auto frameStart = std::chrono::steady_clock::now();
  if (settings_.mode == Mode::kRtgi && rtgi_) rtgi_->setMeshesMoved(meshesMoved_);
  const bool reproject = followCamera(camera);
  const glm::mat4 previousViewProj = uploadFrameUniforms(camera);
  gl::FrameContext ctx{programs_, timer_, settings_.width, settings_.height, frameUniforms_.id()};
  const SceneUpdate update = updateVoxels(ctx, reproject);
  executeMode(ctx, camera, reproject ? &previousViewProj : nullptr);
  if (showMask_ && settings_.mode == Mode::kRtgi && rtgi_->maskTexture() != 0)
    tonemap_.executeMask(
        ctx, rtgi_->maskTexture(),
        glm::vec2(static_cast<float>(rtgi_->maskWidth()) / static_cast<float>(settings_.width),
                  static_cast<float>(rtgi_->maskHeight()) / static_cast<float>(settings_.height)),
        ldrFbo_.id());
  else if (upsamples())
    tonemap_.executeUpsampled(ctx, rtgi_->upsampleHistory(), rtgi_->upsampleShown(lowHdr_.id()),
                              rtgi_->linearSampler(), RtgiPass::kUpsampleInternalWeight,
                              upsampledFbo_.id());
  else
    tonemap_.execute(ctx, shownHdr(), ldrFbo_.id());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glFinish();
  stages_ = timer_.resolve();
  if (update.voxelized || update.built) recordSceneStages(update.voxelized);
  // The budget learns from frames that trace their share; the first frame of an
  // accumulation traces every pixel and a scene build is start-up, not frame cost.
  if (budget_ && settings_.mode == Mode::kRtgi && accumulated_ > 0 &&
      (settings_.revoxelize || (!update.voxelized && !update.built)))
    budget_->update(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart)
            .count());
  ++accumulated_;
}

bool Renderer::followCamera(const scene::Camera& camera) {
  // A camera move restarts accumulation, except in rtgi with reprojection, whose
  // pixels carry their history over to where their surfaces now are (as after a
  // mesh move, geometryChanged()).
  bool reproject = meshesMoved_ && accumulated_ > 0;
  if (!sameCamera(camera, lastCamera_)) {
    reproject = reprojects() && accumulated_ > 0;
    if (!reproject) accumulated_ = 0;
  }
  // After a frame that drew moved meshes, one that draws them where they are has no
  // motion: their previous positions catch up.
  if (geometryUnsettled_ && !meshesMoved_) {
    gpuScene_.settleGeometry();
    geometryUnsettled_ = false;
  }
  geometryUnsettled_ = geometryUnsettled_ || meshesMoved_;
  meshesMoved_ = false;
  lastCamera_ = camera;
  return reproject;
}

glm::mat4 Renderer::uploadFrameUniforms(const scene::Camera& camera) {
  gpu::GpuFrame frame{};
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  glm::mat4 projection = camera.projection(aspect);
  const glm::mat4 previousViewProj = lastViewProj_;
  lastViewProj_ = projection * camera.view();
  jitter_ = glm::vec2(0.0f);
  if (settings_.mode == Mode::kRtgi && settings_.jitter) {
    // A pixel traces once every `interleave` frames (all of them on the first): its
    // k-th sample takes offset k. The offset is in the pixels rtgi renders.
    const int n = rtgi_->settings().interleave;
    jitter_ = subpixelJitter((accumulated_ + n - 1) / n);
    const glm::ivec2 size = internalSize();
    glm::mat4 shift(1.0f);  // clip space: xy += offset x w, an NDC shift
    shift[3] = glm::vec4(2.0f * jitter_.x / static_cast<float>(size.x),
                         2.0f * jitter_.y / static_cast<float>(size.y), 0.0f, 1.0f);
    projection = shift * projection;
  }
  const glm::mat4 vp = projection * camera.view();
  for (int i = 0; i < 4; ++i) frame.viewProj[i] = vp[i];
  frame.cameraPosition = glm::vec4(camera.position, 1.0f);
  frame.counts = glm::vec4(static_cast<float>(gpuScene_.lightCount()),
                           static_cast<float>(gpuScene_.emitterCount()), 0.0f, 0.0f);
  glNamedBufferSubData(frameUniforms_.id(), 0, sizeof(frame), &frame);
  return previousViewProj;
}

Renderer::SceneUpdate Renderer::updateVoxels(gl::FrameContext& ctx, bool moving) {
  SceneUpdate update;
  update.voxelized = usesVoxels(settings_.mode) && (!voxelized_ || settings_.revoxelize);
  if (update.voxelized) {
    voxelize_->execute(ctx, gpuScene_);
    voxelized_ = true;
    octreeBuilt_ = false;
  }
  update.built = usesOctree(settings_.mode) && !octreeBuilt_;
  // The BVH the voxels' rays trace (Octree::Settings::bvhDefines).
  const bool voxelRaysOnBvh = octree_ && !octree_->settings().bvhDefines.empty();
  if (voxelRaysOnBvh) {
    const scene::ShaderFeatures features = scene::shaderFeatures(plan_);
    bvh_->bind(gpuScene_.materials(), features.colors, features.normalMaps);
  }
  if (update.built) {
    octree_->build(ctx, *voxelize_);
    octree_->inject(ctx, gpuScene_);
    octreeBuilt_ = true;
    lightsMoved_ = false;
  } else if (usesOctree(settings_.mode) && lightsMoved_) {
    // A light moved: the voxels' light starts again from a first estimate.
    octree_->inject(ctx, gpuScene_);
    lightsMoved_ = false;
  } else if (usesOctree(settings_.mode) && !(budget_ && moving)) {
    // The scene is still: the voxels' light converges frame by frame, whatever the
    // camera does; except under a frame budget while the view moves, when the
    // frame's time goes to the pixels, which must follow the view (refinement costs
    // the same at any size: 7 ms of a 33 ms frame at 640x360, render scale 0.5),
    // and the voxels converge once it stops.
    octree_->refine(ctx, gpuScene_);
  }
  if (voxelRaysOnBvh) GpuBvh::unbind();
  return update;
}

void Renderer::executeMode(gl::FrameContext& ctx, const scene::Camera& camera,
                           const glm::mat4* previousViewProj) {
  switch (settings_.mode) {
    case Mode::kRaster:
      raster_->execute(ctx, gpuScene_, hdrFbo_.id());
      break;
    case Mode::kPoints:
      points_->execute(ctx, *voxelize_, hdrFbo_.id());
      break;
    case Mode::kDvr:
      dvr_->execute(ctx, *octree_, camera, hdr_.id());
      break;
    case Mode::kRtgi: {
      if (budget_) rtgi_->setTraceFraction(budget_->fraction());
      if (!upsamples()) {
        rtgi_->execute(ctx, gpuScene_, octree_.get(), camera, accumulated_, hdr_.id(),
                       previousViewProj);
        break;
      }
      // At the internal size, then the output rebuilt from it.
      const glm::ivec2 low = internalSize();
      gl::FrameContext lowCtx{ctx.programs, ctx.timer, low.x, low.y, ctx.frameUniforms};
      rtgi_->execute(lowCtx, gpuScene_, octree_.get(), camera, accumulated_, lowHdr_.id(),
                     previousViewProj);
      // The output's history restarts with accumulation and after a move: the
      // internal image, which follows the move, carries what is shown meanwhile.
      rtgi_->upsample(ctx, jitter_, accumulated_ == 0 || previousViewProj != nullptr);
      break;
    }
    case Mode::kPathtrace:
      // Progressive: this frame's samples join those since accumulation restarted.
      if (!settings_.progressive || accumulated_ == 0) pathtrace_->reset();
      pathtrace_->setCamera(camera);
      pathtrace_->execute(ctx, settings_.spp, hdr_.id(), progress_);
      break;
  }
}

void Renderer::recordSceneStages(bool voxelized) {
  if (voxelized) sceneStages_.clear();
  for (const gl::StageTime& t : stages_) {
    if (t.stage != Stage::kVoxelize && t.stage != Stage::kOctree && t.stage != Stage::kInject)
      continue;
    auto same = std::find_if(sceneStages_.begin(), sceneStages_.end(),
                             [&](const gl::StageTime& s) { return s.stage == t.stage; });
    if (same != sceneStages_.end())
      *same = t;
    else
      sceneStages_.push_back(t);
  }
}

namespace {
template <typename T>
void flipRows(std::vector<T>& px, int width, int height, int channels) {
  const size_t row = static_cast<size_t>(width) * static_cast<size_t>(channels);
  std::vector<T> tmp(row);
  for (int y = 0; y < height / 2; ++y) {
    T* a = px.data() + static_cast<size_t>(y) * row;
    T* b = px.data() + static_cast<size_t>(height - 1 - y) * row;
    std::memcpy(tmp.data(), a, row * sizeof(T));
    std::memcpy(a, b, row * sizeof(T));
    std::memcpy(b, tmp.data(), row * sizeof(T));
  }
}
}  // namespace

void Renderer::setFrameShown(bool shown) {
  frameShown_ = shown;
  if (rtgi_) rtgi_->setShown(shown);
}

void Renderer::setShowMask(bool show) {
  showMask_ = show;
  if (rtgi_) rtgi_->settings().keepMask = show || settings_.rtgi.keepMask;
}

void Renderer::setDenoise(bool on) {
  settings_.rtgi.denoise = on;
  if (!rtgi_ || rtgi_->settings().denoise == on) return;
  rtgi_->settings().denoise = on;
  accumulated_ = 0;
}

GLuint Renderer::shownHdr() const {
  if (upsamples()) return hdr_.id();  // the upsampled output, written with the display image
  if (settings_.mode == Mode::kRtgi && rtgi_ && rtgi_->denoisedTexture() != 0)
    return rtgi_->denoisedTexture();
  return hdr_.id();
}

std::vector<float> Renderer::readLinear() const {
  std::vector<float> px(static_cast<size_t>(settings_.width) *
                        static_cast<size_t>(settings_.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(shownHdr(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  flipRows(px, settings_.width, settings_.height, 4);
  return px;
}

std::vector<uint8_t> Renderer::readDisplay() const {
  std::vector<uint8_t> px(static_cast<size_t>(settings_.width) *
                          static_cast<size_t>(settings_.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(ldr_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(px.size()),
                    px.data());
  flipRows(px, settings_.width, settings_.height, 4);
  return px;
}

}  // namespace voxgi::render

#include "render/rtgi_pass.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include "core/log.h"
#include "interleave_shared.h"
#include "light_tree_shared.h"
#include "octree_shared.h"
#include "render/pathtrace/pathtrace_scene.h"
#include "render/raster_pass.h"
#include "scene_shared.h"

namespace voxgi::render {

RtgiPass::RtgiPass(gl::ProgramCache& programs, const Settings& settings,
                   std::shared_ptr<const GpuBvh> bvh)
    : settings_(settings),
      programs_(programs),
      bvh_(std::move(bvh)),
      gbuffer_(programs.get(
          {{"render/raster.vert", "render/gbuffer.frag"}, settings.features.defines()})),
      accumulate_(
          programs.get({{"render/rtgi/rtgi_accumulate.comp"}, settings.features.defines()})),
      mask_(programs),
      history_(programs),
      denoiser_(programs) {
  params_ = gl::createBuffer(sizeof(gpu::RtgiParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const uint32_t zero = 0;
  nonfinite_ = gl::createBuffer(sizeof(zero), &zero);
  buildOptionalStages();
}

uint32_t RtgiPass::nonfiniteTerms() const {
  uint32_t n = 0;
  glGetNamedBufferSubData(nonfinite_.id(), 0, sizeof(n), &n);
  return n;
}

void RtgiPass::buildOptionalStages() {
  // With a BVH the variants depend on the scene (indirectProgram, specularProgram).
  if (settings_.indirect && !indirect_ && !raysHitTriangles() &&
      settings_.indirectMethod == Settings::IndirectMethod::kRays)
    indirect_ = &programs_.get({{"render/rtgi/rtgi_indirect.comp"}, {}});
  if (settings_.specular && !specular_ && !tracesTriangles()) {
    std::vector<std::string> defines = conesDefine();
    defines.push_back(firstLobeRaysDefine());
    defines.emplace_back("RTGI_SPECULAR_LIST");
    specular_ = &programs_.get({{"render/rtgi/rtgi_specular.comp"}, defines});
  }
}

std::vector<std::string> RtgiPass::bvhDefines(const GpuScene& gs) const {
  std::vector<std::string> defines = bvh_->traceDefines(gs.scene(), settings_.features);
  // The indirect rays of the specular stage's hits on it too.
  if (raysHitTriangles()) defines.emplace_back("RTGI_BVH_RAYS");
  return defines;
}

void RtgiPass::bindBvh(const GpuScene& gs) const {
  bvh_->bind(gs.materials(), settings_.features.colors, settings_.features.normalMaps);
}

void RtgiPass::unbindBvh() const {
  GpuBvh::unbind();
}

// The direct stage's variant for what the scene has (see rtgi_direct.comp), its
// shadow rays through the BVH (RTGI_BVH) or the voxels.
const gl::Program& RtgiPass::directProgram(const GpuScene& gs, const char* restir) {
  std::vector<std::string> defines = settings_.features.defines();
  if (raysHitTriangles() && settings_.features.shadows)
    for (std::string& d : bvhDefines(gs)) defines.push_back(std::move(d));
  for (std::string& d : lightDefines(gs)) defines.push_back(std::move(d));
  if (sharesHighlights(gs)) {
    defines.emplace_back("RTGI_HIGHLIGHT_MIS");
    defines.push_back(lobeShareDefine());
  }
  // Without a specular stage that shares them (none, or one of cones or voxel
  // reflections, which do not see the emitters), the light sample carries the
  // highlights whole.
  if (!sharesHighlights(gs)) defines.emplace_back("RTGI_HIGHLIGHT_SAMPLED");
  if (*restir != '\0') {
    defines.emplace_back(restir);
    defines.push_back("RTGI_RESTIR_CANDIDATES=" + std::to_string(settings_.restirCandidates));
    defines.push_back("RTGI_GLOSSY_CANDIDATES=" + std::to_string(settings_.glossyCandidates));
    defines.push_back("RTGI_RESTIR_LEAF_DRAW=" + std::to_string(settings_.candidateLeafDraw) +
                      ".0");
  }
  if (usesLightTiles(gs)) {
    defines.emplace_back("RTGI_EMITTER_TILES");
    // In place of lightDefines' one candidate: a candidate from a tile costs a read
    // and one bound, not a bound per emitter, and the tile's distribution is looser
    // than the pixel's own bounds.
    std::erase(defines, std::string("RTGI_EMITTER_CANDIDATES=1"));
    defines.push_back("RTGI_EMITTER_CANDIDATES=" + std::to_string(settings_.tileCandidates));
  }
  return programs_.get({{"render/rtgi/rtgi_direct.comp"}, defines});
}

// The tile pass costs what weighing every emitter at about a sixth of the pixels
// does, whatever share of them traces: tiles pay where the frames trace a quarter
// of the pixels or more (dark_plane at 640x360, render scale 0.5, an interleave of
// 16: `shadows` 4.2-4.3 ms without tiles, 6.9-8.5 with them). A frame budget
// (select mask or uniform) traces as little as a sixteenth, and would switch
// variants from frame to frame: no tiles there.
bool RtgiPass::usesLightTiles(const GpuScene& gs) const {
  return settings_.lightTiles && settings_.features.shadows && settings_.features.emission &&
         static_cast<int>(gs.emitterCount()) > settings_.exactEmitters &&
         static_cast<float>(gs.emitterCount()) <= gpu::kLightTreeLeafDraw &&
         settings_.select == Settings::Select::kPattern && settings_.interleave <= 4;
}

void RtgiPass::makeLightTiles(gl::FrameContext& ctx) {
  const GLuint tilesX =
      (static_cast<GLuint>(width_) + gpu::kLightTileSize - 1) / gpu::kLightTileSize;
  const GLuint tilesY =
      (static_cast<GLuint>(height_) + gpu::kLightTileSize - 1) / gpu::kLightTileSize;
  const size_t bytes = 8 * size_t{tilesX} * size_t{tilesY} * gpu::kLightTileSamples;
  if (!lightTiles_ || lightTileBytes_ != bytes) {
    lightTiles_ = gl::createBuffer(static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    lightTileBytes_ = bytes;
  }
  gl::StageScope scope(ctx.timer, Stage::kShadows);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiReservoirBinding, lightTiles_.id());
  glUseProgram(programs_.get({{"render/rtgi/rtgi_light_tiles.comp"}, {}}).id());
  glDispatchCompute(tilesX, tilesY, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

// Where the tree draws among all the emitters at once, each with its own tight
// bound (lightDefines), reuse gains nothing either: dark_plane's 96 clusters give the
// same direct light (FLIP 0.0140 against 0.0141 at 64 frames) at more cost.
bool RtgiPass::reusesLights(const GpuScene& gs) const {
  return settings_.reuseLights && settings_.features.shadows && settings_.features.emission &&
         static_cast<int>(gs.emitterCount()) > settings_.exactEmitters &&
         static_cast<float>(gs.emitterCount()) > gpu::kLightTreeLeafDraw;
}

const char* RtgiPass::emitterSampling(const GpuScene& gs) const {
  if (gs.emitterCount() == 0 || !settings_.features.emission) return "none";
  // Without shadows every emitter's unshadowed light is summed.
  if (static_cast<int>(gs.emitterCount()) <= settings_.exactEmitters || !settings_.features.shadows)
    return "exact";
  if (reusesLights(gs)) return "restir";
  return usesLightTiles(gs) ? "light_tiles" : "light_tree";
}

const char* RtgiPass::punctualSampling(const GpuScene& gs) const {
  if (gs.lightCount() == 0) return "none";
  return static_cast<int>(gs.lightCount()) > settings_.exactLights ? "sampled" : "exact";
}

// How direct light treats the scene's lights (rtgi_direct_light.glsl): punctual
// lights each with its shadow ray (RTGI_LIGHTS) or, beyond exactLights (at the
// indirect hits exactLightsAtHits), one drawn per pixel (RTGI_LIGHTS_SAMPLED); emitters summed
// (RTGI_EMITTERS_EXACT) or drawn from the light tree (RTGI_EMITTERS_SAMPLED), with candidates
// resampled (RTGI_EMITTER_CANDIDATES).
std::vector<std::string> RtgiPass::lightDefines(const GpuScene& gs, bool atHits) const {
  std::vector<std::string> defines;
  if (gs.lightCount() > 0) defines.emplace_back("RTGI_LIGHTS");
  if (static_cast<int>(gs.lightCount()) >
      (atHits ? settings_.exactLightsAtHits : settings_.exactLights))
    defines.emplace_back("RTGI_LIGHTS_SAMPLED");
  if (gs.emitterCount() > 0)
    defines.emplace_back(static_cast<int>(gs.emitterCount()) <= settings_.exactEmitters
                             ? "RTGI_EMITTERS_EXACT"
                             : "RTGI_EMITTERS_SAMPLED");
  // Where the tree draws among all its emitters at once, each with its own tight
  // bound, resampling candidates gains nothing (dark_plane's 96 clusters: the same
  // FLIP at twice the cost); where it walks nodes of emitters far apart, it does.
  // `atHits` (the indirect rays' hits, whose light a cosine ray already scatters):
  // one candidate; four there cost 2x the indirect stage for less gain than the
  // frames that time buys (the hall at equal time).
  if (atHits || static_cast<float>(gs.emitterCount()) <= gpu::kLightTreeLeafDraw)
    defines.emplace_back("RTGI_EMITTER_CANDIDATES=1");
  // Where candidates are resampled by their exact contribution (the mirrors' hits,
  // the pixels without reuse), walks end in small nodes, as ReSTIR's candidates do.
  const int leafDraw = atHits ? settings_.leafDrawAtHits
                       : static_cast<float>(gs.emitterCount()) > gpu::kLightTreeLeafDraw
                           ? settings_.candidateLeafDraw
                           : static_cast<int>(gpu::kLightTreeLeafDraw);
  if (static_cast<float>(gs.emitterCount()) > static_cast<float>(leafDraw))
    defines.push_back("RTGI_LEAF_DRAW=" + std::to_string(leafDraw) + ".0");
  return defines;
}

std::string RtgiPass::firstLobeRaysDefine() const {
  return "RTGI_FIRST_LOBE_RAYS=" + std::to_string(firstLobeRays());
}

std::string RtgiPass::lobeShareDefine() const {
  return "RTGI_LOBE_SHARE=" + std::to_string(settings_.lobeShareWeight);
}

// With cones for indirect light, glossy reflections are cones too.
std::vector<std::string> RtgiPass::conesDefine() const {
  if (settings_.indirectMethod == Settings::IndirectMethod::kCones) return {"RTGI_CONES"};
  return {};
}

// The indirect stage's variant: the voxel march, the triangles (RTGI_BVH, their hits
// lit exactly), or cones (RTGI_CONES).
const gl::Program& RtgiPass::indirectProgram(const GpuScene& gs) {
  if (settings_.indirectMethod == Settings::IndirectMethod::kCones)
    return programs_.get({{"render/rtgi/rtgi_indirect.comp"}, {"RTGI_CONES"}});
  if (!raysHitTriangles()) return *indirect_;
  // The hit's direct light as the direct stage's scene variants estimate it.
  std::vector<std::string> defines = settings_.features.defines();
  for (std::string& d : bvhDefines(gs)) defines.push_back(std::move(d));
  for (std::string& d : lightDefines(gs, true)) defines.push_back(std::move(d));
  return programs_.get({{"render/rtgi/rtgi_indirect.comp"}, defines});
}

// The specular stage's variant: the voxel march, or with a BVH (RTGI_BVH) the
// triangles, shading the hit with the direct stage's scene variants.
const gl::Program& RtgiPass::specularProgram(const GpuScene& gs) {
  if (!tracesTriangles()) return *specular_;
  std::vector<std::string> defines = settings_.features.defines();
  for (std::string& d : bvhDefines(gs)) defines.push_back(std::move(d));
  for (std::string& d : lightDefines(gs)) defines.push_back(std::move(d));
  for (std::string& d : conesDefine()) defines.push_back(std::move(d));
  if (sharesHighlights(gs)) {
    defines.emplace_back("RTGI_HIGHLIGHT_MIS");
    defines.push_back(lobeShareDefine());
  }
  defines.push_back(firstLobeRaysDefine());
  defines.emplace_back("RTGI_SPECULAR_LIST");  // traceSpecular's list
  return programs_.get({{"render/rtgi/rtgi_specular.comp"}, defines});
}

void RtgiPass::resize(int width, int height) {
  width_ = width;
  height_ = height;
  auto make = [&](gl::Texture& t, GLenum format) { t = gl::createImage2D(format, width, height); };
  for (int i = 0; i < 2; ++i) {
    make(position_[i], GL_RGBA32F);
    make(normal_[i], GL_RGBA16F);
  }
  make(albedo_, GL_RGBA8);
  make(emission_, GL_RGBA16F);
  make(motion_, GL_RGBA16F);
  make(depth_, GL_DEPTH_COMPONENT32F);
  make(directImage_, GL_RGBA16F);
  make(indirectImage_, GL_RGBA16F);
  make(specularImage_, GL_RGBA16F);
  caustic_ = gl::Buffer();  // made again at this size, and counted, by traceCaustics
  causticBytes_ = 0;
  // The denoiser's images are made on the first frame that denoises
  // (RtgiHistory::makeMoments, RtgiDenoiser::execute).
  history_.resize(width, height);
  denoiser_.resize(width, height);
  denoised_ = false;
  mask_.resize(width, height);
  make(tracedImage_, GL_R8UI);
  pixelList_ = gl::createBuffer(
      static_cast<GLsizeiptr>(sizeof(gpu::PixelListHeader) +
                              4 * static_cast<size_t>(width) * static_cast<size_t>(height)),
      nullptr, GL_DYNAMIC_STORAGE_BIT);
  for (int i = 0; i < 2; ++i) {
    fbo_[i] = gl::createFramebuffer();
    const GLuint f = fbo_[i].id();
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, position_[i].id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, normal_[i].id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT2, albedo_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT3, emission_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT4, motion_.id(), 0);
    glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    const GLenum buffers[5] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                               GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4};
    glNamedFramebufferDrawBuffers(f, 5, buffers);
    const GLenum status = glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw Error(
          strf("rtgi G-buffer %dx%d: framebuffer incomplete (0x%x)", width, height, status));
  }
  current_ = 0;
  targetBytes_ = static_cast<size_t>(width) * static_cast<size_t>(height) *
                 (2 * (16 + 8) + RtgiHistory::kBytesPerPixel + 4 + 8 + 8 + 4 + 8 * 3 + 16 + 9);
  if (outputWidth_ > 0)
    targetBytes_ += static_cast<size_t>(outputWidth_) * static_cast<size_t>(outputHeight_) * 16;
}

void RtgiPass::execute(gl::FrameContext& ctx, const GpuScene& gs, const voxel::Octree* octree,
                       const scene::Camera& camera, int frameIndex, GLuint accum,
                       const glm::mat4* previousViewProj) {
  if (ctx.width != width_ || ctx.height != height_) resize(ctx.width, ctx.height);
  if (settings_.denoise && !history_.hasMoments()) {
    // The first frame that denoises makes the moments, and the denoiser its images.
    const size_t pixels = static_cast<size_t>(width_) * static_cast<size_t>(height_);
    targetBytes_ += history_.makeMoments() + pixels * RtgiDenoiser::kBytesPerPixel;
  }
  // The G-buffer drawn last frame becomes the previous one.
  current_ ^= 1;
  buildOptionalStages();
  const FramePlan plan = planFrame(ctx, gs, frameIndex, previousViewProj != nullptr);
  gpu::RtgiParams p = frameParams(ctx, gs, camera, frameIndex, previousViewProj, plan);
  if (octree && octree->allBounces()) p.flags |= gpu::kRtgiAllBounces;
  causticsThisFrame_ = octree != nullptr && tracesCaustics(gs);
  if (causticsThisFrame_) {
    // Photons for the pixels that trace this frame: the others drop their light.
    const double traced = plan.everyPixel ? 1.0
                          : plan.listed   ? std::clamp(traceFraction_, 0.0, 1.0)
                                          : 1.0 / plan.interleave;
    lastCausticPhotons_ = causticPhotons(traced);
    p.flags |= gpu::kRtgiHasCaustics;
    p.causticPhotons = static_cast<uint32_t>(lastCausticPhotons_);
    p.causticTargets = static_cast<uint32_t>(causticTargets_);
  }
  glNamedBufferSubData(params_.id(), 0, sizeof(p), &p);
  drawGBuffer(ctx, gs);
  bindFrameInputs(gs, octree, accum);
  if (plan.reprojecting)
    history_.reproject(ctx, plan.gx, plan.gy, accum,
                       {position_[current_ ^ 1].id(), normal_[current_ ^ 1].id(), motion_.id()},
                       gs.materials(), settings_.denoise, settings_.features.defines());
  lastTraced_ = plan.everyPixel ? 1.0 : 1.0 / plan.interleave;
  if (plan.listed) selectPixels(ctx, frameIndex, plan, &p);
  traceLight(ctx, gs, plan);
  if (causticsThisFrame_) traceCaustics(ctx, gs);
  accumulateFrame(ctx, plan);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  denoised_ = settings_.denoise && shown_;
  if (denoised_)
    denoiser_.execute(ctx, plan.gx, plan.gy, accum, history_.moments(), history_.directMean());
  finishFrame(plan);
}

RtgiPass::FramePlan RtgiPass::planFrame(const gl::FrameContext& ctx, const GpuScene& gs,
                                        int frameIndex, bool moved) const {
  if (settings_.interleave < 1 || settings_.interleave > static_cast<int>(gpu::kMaxInterleave) ||
      (settings_.interleave & (settings_.interleave - 1)) != 0)
    throw Error(strf("rtgi: interleave %d: must be 1, 2, 4, 8 or 16", settings_.interleave));
  FramePlan f;
  f.reprojecting = moved && frameIndex > 0;
  f.relight = f.reprojecting && meshesMoved_ && settings_.dropStaleHistory;
  // Without shadow rays the direct stage is cheap unshadowed light, run only when
  // there is light to add.
  f.shadows = settings_.features.shadows;
  f.direct =
      f.shadows || gs.lightCount() > 0 || (settings_.features.emission && gs.emitterCount() > 0);
  // This frame's interleave: the setting's, except on the first frame of a sparse
  // start under a frame budget, which takes the pattern nearest below the budget's
  // share (a restart costs what the budget allows; every pixel where it allows all).
  f.interleave = settings_.interleave;
  if (frameIndex == 0 && settings_.sparseStart && settings_.select != Settings::Select::kPattern)
    while (f.interleave > 1 && 2.0 / f.interleave <= traceFraction_ + 1e-9) f.interleave /= 2;
  // Every pixel traces without interleaving, and on the first frame unless it starts
  // sparse.
  f.everyPixel =
      gpu::interleaveEveryPixel(static_cast<uint32_t>(f.interleave),
                                static_cast<uint32_t>(frameIndex), settings_.sparseStart);
  // Which pixels trace: the interleave pattern by formula, or (frame budget) a list
  // built by the select stage, dispatched indirectly.
  f.listed = settings_.select != Settings::Select::kPattern && frameIndex > 0;
  // A sparse start: until every pixel has had its turn (n frames; a budget's list
  // includes the pattern), the variant that lends traced light to those still
  // waiting. It is a separate program because a SIMD software rasterizer would run
  // the lending code, masked, for every pixel of every frame. A frame after a move
  // lends too, to the pixels that lost their history, and starts from the
  // reprojected mean (RTGI_REPROJECTED).
  f.lends = !f.everyPixel &&
            ((settings_.sparseStart && frameIndex < settings_.interleave) || f.reprojecting);
  f.gx = static_cast<GLuint>((ctx.width + gpu::kRtgiGroupX - 1) / gpu::kRtgiGroupX);
  f.gy = static_cast<GLuint>((ctx.height + gpu::kRtgiGroupY - 1) / gpu::kRtgiGroupY);
  f.pixelsTotal = uint64_t{static_cast<uint32_t>(ctx.width)} * static_cast<uint32_t>(ctx.height);
  const uint64_t tracing =
      gpu::interleaveTraceCount(static_cast<uint32_t>(ctx.width), static_cast<uint32_t>(ctx.height),
                                static_cast<uint32_t>(f.interleave), f.everyPixel);
  const uint64_t groups = (tracing + gpu::kRtgiTraceGroup - 1) / gpu::kRtgiTraceGroup;
  f.tx = static_cast<GLuint>(std::min<uint64_t>(groups, 65535));
  f.ty = static_cast<GLuint>((groups + f.tx - 1) / f.tx);
  return f;
}

gpu::RtgiParams RtgiPass::frameParams(const gl::FrameContext& ctx, const GpuScene& gs,
                                      const scene::Camera& camera, int frameIndex,
                                      const glm::mat4* previousViewProj,
                                      const FramePlan& plan) const {
  gpu::RtgiParams p{};
  p.frameIndex = static_cast<uint32_t>(frameIndex);
  p.seed = settings_.seed;
  p.width = static_cast<uint32_t>(ctx.width);
  p.height = static_cast<uint32_t>(ctx.height);
  p.lightCount = static_cast<uint32_t>(gs.lightCount());
  p.emitterCount = static_cast<uint32_t>(gs.emitterCount());
  p.flags = (plan.direct ? gpu::kRtgiHasDirect : 0u) |
            (settings_.indirect ? gpu::kRtgiHasIndirect : 0u) |
            (settings_.specular ? gpu::kRtgiHasSpecular : 0u) |
            (plan.reprojecting ? gpu::kRtgiReprojecting : 0u);
  p.camera = glm::vec4(camera.position, 1.0f);
  p.cameraForward = glm::vec4(glm::normalize(camera.forward), 0.0f);
  p.pixelSpread = 2.0f * std::tan(0.5f * camera.yfov) / static_cast<float>(ctx.height);
  p.denoiseLuminance = settings_.denoiseLuminance;
  p.denoisePlane = settings_.denoisePlane;
  p.interleave = static_cast<uint32_t>(plan.interleave);
  p.workFlags = settings_.sparseStart ? gpu::kRtgiSparseStart : 0u;
  if (plan.reprojecting) {
    for (int i = 0; i < 4; ++i) p.previousViewProj[i] = (*previousViewProj)[i];
    const auto cap = static_cast<float>(std::max(settings_.historyCap, 0));
    p.historyCap = cap;
    p.glossyHistory = std::min(cap, static_cast<float>(kGlossyHistory));
    p.mirrorHistory = 0.0f;
    p.edgeHistory = std::min(cap, static_cast<float>(kEdgeHistory));
  }
  return p;
}

void RtgiPass::drawGBuffer(gl::FrameContext& ctx, const GpuScene& gs) {
  if (primaryRays()) {
    castGBuffer(ctx, gs);
    return;
  }
  gl::StageScope stage(ctx.timer, Stage::kGbuffer);
  beginOpaquePass(ctx, fbo_[current_].id(), glm::vec4(0.0f), 5);  // the G-buffer's 5 targets
  glUseProgram(gbuffer_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
  drawSceneGeometry(gs);
  glDisable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void RtgiPass::castGBuffer(gl::FrameContext& ctx, const GpuScene& gs) {
  std::vector<std::string> defines = settings_.features.defines();
  for (std::string& d : bvhDefines(gs)) defines.push_back(std::move(d));
  const gl::Program& program = programs_.get({{"render/rtgi/rtgi_gbuffer.comp"}, defines});
  gl::StageScope stage(ctx.timer, Stage::kGbuffer);
  bindBvh(gs);
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
  const struct {
    GLuint unit;
    const gl::Texture& image;
    GLenum format;
  } images[] = {{gpu::kGbufferPositionImage, position_[current_], GL_RGBA32F},
                {gpu::kGbufferNormalImage, normal_[current_], GL_RGBA16F},
                {gpu::kGbufferAlbedoImage, albedo_, GL_RGBA8},
                {gpu::kGbufferEmissionImage, emission_, GL_RGBA16F},
                {gpu::kGbufferMotionImage, motion_, GL_RGBA16F}};
  for (const auto& i : images)
    glBindImageTexture(i.unit, i.image.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, i.format);
  glUseProgram(program.id());
  glDispatchCompute(static_cast<GLuint>((width_ + 7) / 8), static_cast<GLuint>((height_ + 7) / 8),
                    1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void RtgiPass::bindFrameInputs(const GpuScene& gs, const voxel::Octree* octree, GLuint accum) {
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  if (octree) octree->bind();
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kRtgiParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, gs.lights());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmitterBinding, gs.emitters());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeLightCdfBinding, gs.emitterCdf());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightTreeBinding, gs.lightTree());
  glBindTextureUnit(gpu::kGPositionUnit, position_[current_].id());
  glBindTextureUnit(gpu::kGNormalUnit, normal_[current_].id());
  glBindTextureUnit(gpu::kGAlbedoUnit, albedo_.id());
  glBindTextureUnit(gpu::kGEmissionUnit, emission_.id());
  bindTermImages(GL_READ_WRITE);
  glBindImageTexture(gpu::kAccumImage, accum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  // Declared by the tracing stages and accumulate; read only when a list is used.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPixelListBinding, pixelList_.id());
  glBindImageTexture(gpu::kTracedImage, tracedImage_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8UI);
}

void RtgiPass::bindTermImages(GLenum access) const {
  glBindImageTexture(gpu::kDirectImage, directImage_.id(), 0, GL_FALSE, 0, access, GL_RGBA16F);
  glBindImageTexture(gpu::kIndirectImage, indirectImage_.id(), 0, GL_FALSE, 0, access, GL_RGBA16F);
  glBindImageTexture(gpu::kSpecularImage, specularImage_.id(), 0, GL_FALSE, 0, access, GL_RGBA16F);
}

void RtgiPass::selectPixels(gl::FrameContext& ctx, int frameIndex, const FramePlan& plan,
                            gpu::RtgiParams* p) {
  const double patternShare = 1.0 / plan.interleave;
  const double extraShare = std::max(0.0, traceFraction_ - patternShare);
  float level = 0.0f;
  uint32_t kind = gpu::kSelectUniform;
  if (settings_.select == Settings::Select::kMask && extraShare <= 0.0 && !settings_.keepMask) {
    // The budget allows the pattern only (a moving camera on a slow GL): no pixel is
    // chosen by the mask, so it is not made; it is made again, up to date, on the
    // next frame that chooses by it (once a period at most, as when it is made on
    // every period). What is selected: none beyond the pattern.
    mask_.skip(frameIndex);
    level = 0.0f;
  } else if (settings_.select == Settings::Select::kMask) {
    kind = gpu::kSelectMask;
    // The mask changes slowly as the image converges: it is made again every
    // RtgiWorkMask::kPeriod frames; the threshold follows the budget every frame.
    mask_.update(ctx, plan.gx, plan.gy, frameIndex);
    level = traceFraction_ >= 1.0 ? -1.0f  // every pixel
                                  : mask_.threshold(static_cast<uint64_t>(
                                        extraShare * static_cast<double>(plan.pixelsTotal)));
  } else {
    level = static_cast<float>(std::min(1.0, extraShare / (1.0 - patternShare)));
  }
  p->selectLevel = std::bit_cast<uint32_t>(level);
  p->selectKind = kind;
  glNamedBufferSubData(params_.id(), 0, sizeof(*p), p);
  gl::StageScope stage(ctx.timer, Stage::kSelect);
  const gpu::PixelListHeader header{glm::uvec4(0u, 1u, 1u, 0u), glm::uvec4(0u)};
  glNamedBufferSubData(pixelList_.id(), 0, sizeof(header), &header);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPixelListBinding, pixelList_.id());
  glBindImageTexture(gpu::kMaskImage, mask_.image(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R16F);
  glBindImageTexture(gpu::kTracedImage, tracedImage_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8UI);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_select.comp"}, {}}).id());
  glDispatchCompute(plan.gx, plan.gy, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                  GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindImageTexture(gpu::kTracedImage, tracedImage_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8UI);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pixelList_.id());
}

void RtgiPass::runStage(gl::FrameContext& ctx, Stage stage, const gl::Program& program,
                        const FramePlan& plan) {
  gl::StageScope scope(ctx.timer, stage);
  glUseProgram(program.id());
  if (&program == &accumulate_ || &program == accumulateVariant_)
    glDispatchCompute(plan.gx, plan.gy, 1);
  else if (plan.listed)
    glDispatchComputeIndirect(0);
  else
    glDispatchCompute(plan.tx, plan.ty, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void RtgiPass::traceLight(gl::FrameContext& ctx, const GpuScene& gs, const FramePlan& plan) {
  if (bvh_) bindBvh(gs);
  if (plan.direct && reusesLights(gs)) {
    // Reservoir resampling (rtgi_restir.glsl): each pixel's candidates, then
    // their reuse among neighbours and the shadow rays.
    const size_t bytes = 16 * static_cast<size_t>(width_) * static_cast<size_t>(height_);
    if (!reservoirs_ || reservoirBytes_ != bytes) {
      reservoirs_ =
          gl::createBuffer(static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
      glClearNamedBufferData(reservoirs_.id(), GL_R32F, GL_RED, GL_FLOAT, nullptr);
      reservoirBytes_ = bytes;
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiReservoirBinding, reservoirs_.id());
    runStage(ctx, Stage::kShadows, directProgram(gs, "RTGI_RESTIR_INITIAL"), plan);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    runStage(ctx, Stage::kShadows, directProgram(gs, "RTGI_RESTIR"), plan);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  } else if (plan.direct) {
    if (usesLightTiles(gs)) makeLightTiles(ctx);
    runStage(ctx, plan.shadows ? Stage::kShadows : Stage::kDirect, directProgram(gs), plan);
  }
  if (settings_.indirect) {
    // The indirect stage reads each pixel's count of samples so far (a first sample
    // reads the voxels): after a camera move, in the reprojected mean.
    if (plan.reprojecting)
      glBindImageTexture(gpu::kReprojectedImage, history_.reprojectedMean(), 0, GL_FALSE, 0,
                         GL_READ_ONLY, GL_RGBA32F);
    runStage(ctx, Stage::kIndirect, indirectProgram(gs), plan);
  }
  if (settings_.specular) traceSpecular(ctx, gs, plan);
  if (bvh_) unbindBvh();
}

void RtgiPass::traceSpecular(gl::FrameContext& ctx, const GpuScene& gs, const FramePlan& plan) {
  gl::StageScope scope(ctx.timer, Stage::kSpecular);
  // The specular pixels among those that trace, listed (rtgi_specular_select.comp),
  // then the stage over the list alone.
  const size_t bytes =
      sizeof(gpu::PixelListHeader) + 4 * static_cast<size_t>(width_) * static_cast<size_t>(height_);
  if (!specularList_ || specularListBytes_ != bytes) {
    specularList_ =
        gl::createBuffer(static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    specularListBytes_ = bytes;
  }
  const gpu::PixelListHeader header{glm::uvec4(0u, 1u, 1u, 0u), glm::uvec4(0u)};
  glNamedBufferSubData(specularList_.id(), 0, sizeof(header), &header);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSpecularListBinding, specularList_.id());
  glUseProgram(programs_.get({{"render/rtgi/rtgi_specular_select.comp"}, {}}).id());
  if (plan.listed)
    glDispatchComputeIndirect(0);
  else
    glDispatchCompute(plan.tx, plan.ty, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                  GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPixelListBinding, specularList_.id());
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, specularList_.id());
  // The stage reads each pixel's count of samples so far (rtgi_specular.comp): after a
  // camera move, in the reprojected mean.
  if (plan.reprojecting)
    glBindImageTexture(gpu::kReprojectedImage, history_.reprojectedMean(), 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
  glUseProgram(specularProgram(gs).id());
  glDispatchComputeIndirect(0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  // The frame's own list again, for the stages after.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPixelListBinding, pixelList_.id());
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, plan.listed ? pixelList_.id() : 0);
}

int RtgiPass::causticPhotons(double traced) const {
  if (settings_.causticPhotons > 0) return settings_.causticPhotons;
  const double pixels = static_cast<double>(width_) * static_cast<double>(height_) * traced;
  return std::clamp(static_cast<int>(pixels * kCausticPhotonsPerPixel), kMinCausticPhotons,
                    1 << 22);
}

namespace {

struct Sphere {
  glm::vec3 centre{0.0f};
  float radius = -1.0f;  // negative: empty
};

// The sphere about the centre of the box of the corners of `runs` of sc's indexed
// triangles that holds them all (two passes: no copy of the corners).
Sphere boundingSphere(const scene::Scene& sc, const std::vector<const scene::Draw*>& runs) {
  auto each = [&](auto&& f) {
    for (const scene::Draw* d : runs)
      for (uint32_t i = 0; i < d->indexCount; ++i) {
        const uint32_t v = sc.indices[d->firstIndex + i];
        if (v < sc.vertices.size()) f(sc.vertices[v].position);
      }
  };
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  each([&](glm::vec3 q) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  });
  if (!(lo.x <= hi.x)) return {};
  Sphere s{0.5f * (lo + hi), 0.0f};
  each([&](glm::vec3 q) { s.radius = std::max(s.radius, glm::length(q - s.centre)); });
  s.radius *= 1.0001f;  // rounding: every corner strictly inside
  return s;
}

}  // namespace

// The mirrors the caustics stage aims at: a sphere about each run of triangles
// drawn with a mirror material (its roughness factor below kMirrorRoughness); beyond
// kMaxCausticTargets, the runs sorted along the axis their centres spread most on
// and cut into that many groups, a sphere about each group.
bool RtgiPass::tracesCaustics(const GpuScene& gs) {
  if (!settings_.caustics || !tracesTriangles() || !settings_.features.emission ||
      gs.emitterCount() == 0 || gs.scene().meshesAnimated())
    return false;
  if (causticTargets_ < 0) {
    const scene::Scene& sc = gs.scene();
    std::vector<const scene::Draw*> runs;
    std::vector<Sphere> single;  // each run's own sphere
    for (const scene::Draw& d : sc.draws) {
      if (d.material < 0 || d.material >= static_cast<int>(sc.materials.size())) continue;
      if (!(sc.materials[static_cast<size_t>(d.material)].roughness < gpu::kMirrorRoughness))
        continue;
      const Sphere one = boundingSphere(sc, {&d});
      if (one.radius < 0.0f) continue;
      single.push_back(one);
      runs.push_back(&d);
    }
    std::vector<Sphere> spheres;
    const auto groups = static_cast<size_t>(gpu::kMaxCausticTargets);
    if (runs.size() <= groups) {
      spheres = single;
    } else {
      glm::vec3 lo = single[0].centre, hi = single[0].centre;
      for (const Sphere& one : single) {
        lo = glm::min(lo, one.centre);
        hi = glm::max(hi, one.centre);
      }
      const glm::vec3 extent = hi - lo;
      const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                       : extent.y >= extent.z                       ? 1
                                                                    : 2;
      std::vector<size_t> order(runs.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return single[a].centre[axis] < single[b].centre[axis];
      });
      for (size_t g = 0; g < groups; ++g) {
        std::vector<const scene::Draw*> group;
        for (size_t i = g * order.size() / groups; i < (g + 1) * order.size() / groups; ++i)
          group.push_back(runs[order[i]]);
        spheres.push_back(boundingSphere(sc, group));
      }
    }
    std::vector<glm::vec4> packed;
    for (const Sphere& s : spheres)
      if (s.radius > 0.0f && std::isfinite(s.radius)) packed.emplace_back(s.centre, s.radius);
    causticTargets_ = static_cast<int>(packed.size());
    if (!packed.empty())
      causticSpheres_ = gl::createBuffer(static_cast<GLsizeiptr>(packed.size() * sizeof(glm::vec4)),
                                         packed.data());
  }
  return causticTargets_ > 0;
}

void RtgiPass::traceCaustics(gl::FrameContext& ctx, const GpuScene& gs) {
  std::vector<std::string> defines = settings_.features.defines();
  for (std::string& d : bvhDefines(gs)) defines.push_back(std::move(d));
  const gl::Program& program = programs_.get({{"render/rtgi/rtgi_caustics.comp"}, defines});
  gl::StageScope stage(ctx.timer, Stage::kCaustics);
  const size_t bytes = 24 * static_cast<size_t>(width_) * static_cast<size_t>(height_);
  if (!caustic_ || causticBytes_ != bytes) {
    caustic_ = gl::createBuffer(static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    causticBytes_ = bytes;
    targetBytes_ += bytes;
  }
  glClearNamedBufferData(caustic_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  bindBvh(gs);
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiCausticBinding, caustic_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiCausticTargetBinding, causticSpheres_.id());
  glUseProgram(program.id());
  const auto photons = static_cast<GLuint>(lastCausticPhotons_);
  glDispatchCompute((photons + gpu::kRtgiTraceGroup - 1) / gpu::kRtgiTraceGroup, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  unbindBvh();
}

void RtgiPass::accumulateFrame(gl::FrameContext& ctx, const FramePlan& plan) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kNonfiniteCountBinding, nonfinite_.id());
  if (settings_.denoise) {
    // The moments and the direct term's mean use the mask's image units
    // (bindings_shared.h): bound here, after it ran; so does the reprojected mean
    // (below).
    glBindImageTexture(gpu::kMomentsImage, history_.moments(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RGBA32F);
    glBindImageTexture(gpu::kDirectMeanImage, history_.directMean(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RGBA32F);
    glBindTextureUnit(gpu::kReprojectedMomentsUnit, history_.reprojectedMoments());
    glBindTextureUnit(gpu::kReprojectedDirectUnit, history_.reprojectedDirect());
  }
  if (causticsThisFrame_)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiCausticBinding, caustic_.id());
  if (plan.lends || plan.reprojecting || settings_.denoise || causticsThisFrame_) {
    std::vector<std::string> defines = settings_.features.defines();
    if (causticsThisFrame_) defines.emplace_back("RTGI_CAUSTICS");
    if (settings_.denoise) defines.emplace_back("RTGI_MOMENTS");
    if (plan.lends) defines.emplace_back("RTGI_SPARSE_START");
    if (plan.relight) defines.emplace_back("RTGI_RELIGHT");
    if (plan.reprojecting) {
      defines.emplace_back("RTGI_REPROJECTED");
      glBindImageTexture(gpu::kReprojectedImage, history_.reprojectedMean(), 0, GL_FALSE, 0,
                         GL_READ_ONLY, GL_RGBA32F);
    }
    const gl::Program& variant = programs_.get({{"render/rtgi/rtgi_accumulate.comp"}, defines});
    accumulateVariant_ = &variant;
    runStage(ctx, Stage::kAccumulate, variant, plan);
  } else {
    runStage(ctx, Stage::kAccumulate, accumulate_, plan);
  }
  if (settings_.denoise)
    for (GLuint u : {gpu::kReprojectedMomentsUnit, gpu::kReprojectedDirectUnit})
      glBindTextureUnit(u, 0);
}

void RtgiPass::finishFrame(const FramePlan& plan) {
  if (settings_.specular && specularList_) {
    gpu::PixelListHeader header{};
    glGetNamedBufferSubData(specularList_.id(), 0, sizeof(header), &header);
    lastSpecular_ = static_cast<double>(header.count.x) / static_cast<double>(plan.pixelsTotal);
  }
  if (plan.listed) {
    gpu::PixelListHeader header{};
    glGetNamedBufferSubData(pixelList_.id(), 0, sizeof(header), &header);
    lastTraced_ = static_cast<double>(header.count.x) / static_cast<double>(plan.pixelsTotal);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  }
  for (GLuint u = 0; u < gpu::kMinImageUnits; ++u)
    glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  for (GLuint u : {gpu::kGPositionUnit, gpu::kGNormalUnit, gpu::kGAlbedoUnit, gpu::kGEmissionUnit})
    glBindTextureUnit(u, 0);
}

void RtgiPass::upsample(gl::FrameContext& ctx, glm::vec2 jitter, bool restart) {
  if (ctx.width != outputWidth_ || ctx.height != outputHeight_) {
    upsampleHistory_ = gl::createImage2D(GL_RGBA32F, ctx.width, ctx.height);
    if (outputWidth_ == 0) {
      upsampleParams_ =
          gl::createBuffer(sizeof(gpu::UpsampleParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
      linear_ = gl::createSampler();
      glSamplerParameteri(linear_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glSamplerParameteri(linear_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glSamplerParameteri(linear_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glSamplerParameteri(linear_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    } else {
      targetBytes_ -= static_cast<size_t>(outputWidth_) * static_cast<size_t>(outputHeight_) * 16;
    }
    outputWidth_ = ctx.width;
    outputHeight_ = ctx.height;
    targetBytes_ += static_cast<size_t>(outputWidth_) * static_cast<size_t>(outputHeight_) * 16;
    restart = true;
  }
  gpu::UpsampleParams u{};
  u.size = glm::uvec4(static_cast<uint32_t>(ctx.width), static_cast<uint32_t>(ctx.height), 0u, 0u);
  u.jitter = glm::vec4(jitter, 0.0f, 0.0f);
  glNamedBufferSubData(upsampleParams_.id(), 0, sizeof(u), &u);

  gl::StageScope stage(ctx.timer, Stage::kUpsample);
  if (restart) {
    glClearTexImage(upsampleHistory_.id(), 0, GL_RGBA, GL_FLOAT, nullptr);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  }
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kRtgiParamsBinding, params_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kUpsampleParamsBinding, upsampleParams_.id());
  glBindTextureUnit(gpu::kGEmissionUnit, emission_.id());
  bindTermImages(GL_READ_ONLY);
  glBindImageTexture(gpu::kTracedImage, tracedImage_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8UI);
  glBindImageTexture(gpu::kUpsampleHistoryImage, upsampleHistory_.id(), 0, GL_FALSE, 0,
                     GL_READ_WRITE, GL_RGBA32F);
  glUseProgram(
      programs_.get({{"render/rtgi/rtgi_upsample.comp"}, settings_.features.defines()}).id());
  glDispatchCompute(static_cast<GLuint>((width_ + gpu::kRtgiGroupX - 1) / gpu::kRtgiGroupX),
                    static_cast<GLuint>((height_ + gpu::kRtgiGroupY - 1) / gpu::kRtgiGroupY), 1);
  // The tonemap pass reads the history as a texture.
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindTextureUnit(gpu::kGEmissionUnit, 0);
  for (GLuint unit = 0; unit < gpu::kMinImageUnits; ++unit)
    glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
}

RtgiPass::Settings::Primary resolvePrimary(RtgiPass::Settings::Primary primary, bool software,
                                           size_t triangles, size_t pixels, bool meshesAnimated) {
  using Primary = RtgiPass::Settings::Primary;
  if (primary == Primary::kRays && meshesAnimated)
    throw Error("rtgi: primary rays need a scene whose meshes do not move (--primary raster)");
  if (primary != Primary::kAuto) return primary;
  const bool many =
      static_cast<double>(triangles) > kPrimaryRaysPerPixel * static_cast<double>(pixels);
  return software && many && !meshesAnimated ? Primary::kRays : Primary::kRaster;
}

}  // namespace voxgi::render

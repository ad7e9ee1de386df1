#include "render/pathtrace/pathtrace_pass.h"

#include <algorithm>
#include <cmath>

#include "core/log.h"
#include "pathtrace_shared.h"
#include "render/pathtrace/pathtrace_scene.h"

namespace voxgi::render {
namespace {

// The kernel's variant: without textures when none are read, with alpha tests in
// traversal when some material is masked.
std::vector<std::string> kernelDefines(const scene::Scene& s, const PathtraceSettings& settings,
                                       bool textured) {
  std::vector<std::string> defines;
  if (!textured) defines.push_back("VOXGI_NO_TEXTURES");
  if (!(settings.colors && s.hasVertexColors())) defines.push_back("VOXGI_NO_COLORS");
  if (!(settings.normalMaps && s.hasNormalMaps() && textured))
    defines.push_back("VOXGI_NO_NORMALMAPS");
  if (ptReadsAlphaMasks(s, settings.alpha)) defines.push_back("VOXGI_BVH_ALPHA");
  return defines;
}

}  // namespace

PathtracePass::PathtracePass(gl::ProgramCache& programs, const GpuScene& gs,
                             const Settings& settings, std::shared_ptr<const GpuBvh> bvh)
    : settings_(settings),
      scene_(gs),
      gpuBvh_(bvh ? std::move(bvh) : std::make_shared<GpuBvh>(gs, settings.textures)),
      textured_(gpuBvh_->textured()),
      program_(programs.get(
          {{"render/pathtrace.comp"}, kernelDefines(gs.scene(), settings, textured_)})),
      camera_(gs.scene().camera) {
  const scene::Scene& s = gs.scene();
  params_ = gl::createBuffer(sizeof(gpu::GpuPtParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const uint32_t zero = 0;
  counter_ = gl::createBuffer(sizeof(uint32_t), &zero, GL_DYNAMIC_STORAGE_BIT);
  // Ray offsets scaled to the scene: 1e-5 of its diagonal.
  epsilon_ = 1e-5f * std::max(s.bounds.diagonal(), 1e-20f);
}

void PathtracePass::allocate(int width, int height) {
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  for (gl::Texture* t : {&sum_, &compensation_}) {
    *t = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t->id(), 1, GL_RGBA32F, width, height);
  }
  reset();
}

void PathtracePass::reset() {
  samples_ = 0;
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (gl::Texture* t : {&sum_, &compensation_})
    if (*t) glClearTexImage(t->id(), 0, GL_RGBA, GL_FLOAT, zero);
  const uint32_t none = 0;
  glNamedBufferSubData(counter_.id(), 0, sizeof(none), &none);
}

uint64_t PathtracePass::truncatedPaths() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t n = 0;
  glGetNamedBufferSubData(counter_.id(), 0, sizeof(n), &n);
  return n;
}

void PathtracePass::dispatch(gl::FrameContext& ctx, GLuint hdrTexture, int x0, int y0, int w, int h,
                             int firstSample, int samples) {
  const scene::Camera& cam = camera_;
  const float aspect = static_cast<float>(ctx.width) / static_cast<float>(ctx.height);
  const float tanHalf = std::tan(0.5f * cam.yfov);
  const glm::vec3 forward = glm::normalize(cam.forward);
  const glm::vec3 right = glm::normalize(glm::cross(forward, cam.up));
  const glm::vec3 up = glm::cross(right, forward);
  gpu::GpuPtParams p{};
  p.cameraPosition = glm::vec4(cam.position, epsilon_);
  p.cameraRight = glm::vec4(right * (tanHalf * aspect), 0.0f);
  p.cameraUp = glm::vec4(up * tanHalf, 0.0f);
  p.cameraForward = glm::vec4(forward, 0.0f);
  p.image = glm::uvec4(ctx.width, ctx.height, firstSample, samples);
  p.tile = glm::uvec4(x0, y0, settings_.seed,
                      settings_.nextEventEstimation ? gpuBvh_->emissiveTriangles() : 0);
  p.depth = glm::uvec4(settings_.maxDepth, settings_.rrDepth, scene_.lightCount(), 0);
  glNamedBufferSubData(params_.id(), 0, sizeof(p), &p);

  glUseProgram(program_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kPtParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, scene_.materials());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, scene_.lights());
  const GpuBvh& bvh = *gpuBvh_;
  glBindTextureUnit(gpu::kPtNodeTexUnit, bvh.nodeTexels());
  glBindTextureUnit(gpu::kPtTriangleTexUnit, bvh.triangleTexels());
  glBindTextureUnit(gpu::kPtVertexTexUnit, bvh.vertexTexels());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtIndexBinding, bvh.indices());
  if (textured_) {
    glBindTextureUnit(gpu::kPtTexelTexUnit, bvh.textureTexels());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtTextureBinding, bvh.textureTable());
  }
  if (settings_.colors && bvh.colored())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtColorBinding, bvh.colors());
  if (settings_.normalMaps && bvh.textured() && bvh.hasTangents())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtTangentBinding, bvh.tangents());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtEmissiveBinding, bvh.emissive());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtCounterBinding, counter_.id());
  glBindImageTexture(gpu::kPtSumImage, sum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(gpu::kPtCompensationImage, compensation_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                     GL_RGBA32F);
  glBindImageTexture(gpu::kPtOutputImage, hdrTexture, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  const auto groups = [](int n, uint32_t g) {
    return static_cast<GLuint>((static_cast<uint32_t>(n) + g - 1) / g);
  };
  glDispatchCompute(groups(w, gpu::kPtGroupX), groups(h, gpu::kPtGroupY), 1);
  for (GLuint unit :
       {gpu::kPtNodeTexUnit, gpu::kPtTriangleTexUnit, gpu::kPtVertexTexUnit, gpu::kPtTexelTexUnit})
    glBindTextureUnit(unit, 0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_TEXTURE_UPDATE_BARRIER_BIT);
}

void PathtracePass::warmUp(gl::FrameContext& ctx, GLuint hdrTexture) {
  allocate(ctx.width, ctx.height);
  dispatch(ctx, hdrTexture, 0, 0, std::min<int>(ctx.width, gpu::kPtGroupX),
           std::min<int>(ctx.height, gpu::kPtGroupY), 0, 1);
  glFinish();
  reset();
}

void PathtracePass::execute(gl::FrameContext& ctx, int spp, GLuint hdrTexture,
                            const Progress& progress) {
  gl::StageScope stage(ctx.timer, Stage::kPathtrace);
  allocate(ctx.width, ctx.height);
  const int64_t pixels = static_cast<int64_t>(ctx.width) * ctx.height;
  const int64_t budget = std::max<int64_t>(settings_.pixelsPerDispatch, 1);
  // One sample per pixel per pass; large images in bands of whole rows (multiples
  // of the group height).
  int rowsPerTile = ctx.height;
  constexpr int perPass = 1;
  if (pixels > budget) {
    const auto g = static_cast<int>(gpu::kPtGroupY);
    rowsPerTile = std::max<int>(g, static_cast<int>(budget / ctx.width) / g * g);
  }
  const int target = samples_ + spp;
  while (samples_ < target) {
    const int n = std::min(perPass, target - samples_);
    for (int y = 0; y < ctx.height; y += rowsPerTile)
      dispatch(ctx, hdrTexture, 0, y, ctx.width, std::min(rowsPerTile, ctx.height - y), samples_,
               n);
    samples_ += n;
    if (progress) {
      glFinish();
      progress(samples_ - (target - spp), spp);
    }
  }
  glUseProgram(0);
}

}  // namespace voxgi::render

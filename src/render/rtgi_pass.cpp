#include "render/rtgi_pass.h"

#include <algorithm>

#include "core/log.h"
#include "octree_shared.h"
#include "render/raster_pass.h"
#include "scene_shared.h"

namespace voxgi::render {

RtgiPass::RtgiPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      programs_(programs),
      gbuffer_(programs.get(
          {{"render/raster.vert", "render/gbuffer.frag"}, settings.features.defines()})),
      direct_(programs.get({{"render/rtgi_direct.comp"}, settings.features.defines()})),
      accumulate_(programs.get({{"render/rtgi_accumulate.comp"}, settings.features.defines()})) {
  params_ = gl::createBuffer(sizeof(gpu::RtgiParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  buildOptionalStages();
}

void RtgiPass::buildOptionalStages() {
  if (settings_.indirect && !indirect_)
    indirect_ = &programs_.get({{"render/rtgi_indirect.comp"}, {}});
  if (settings_.specular && !specular_)
    specular_ = &programs_.get({{"render/rtgi_specular.comp"}, {}});
}

void RtgiPass::resize(int width, int height) {
  width_ = width;
  height_ = height;
  auto make = [&](gl::Texture& t, GLenum format) {
    t = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, format, width, height);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  make(position_, GL_RGBA32F);
  make(normal_, GL_RGBA16F);
  make(albedo_, GL_RGBA8);
  make(emission_, GL_RGBA16F);
  make(depth_, GL_DEPTH_COMPONENT32F);
  make(directImage_, GL_RGBA16F);
  make(indirectImage_, GL_RGBA16F);
  make(specularImage_, GL_RGBA16F);
  fbo_ = gl::createFramebuffer();
  const GLuint f = fbo_.id();
  glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, position_.id(), 0);
  glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, normal_.id(), 0);
  glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT2, albedo_.id(), 0);
  glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT3, emission_.id(), 0);
  glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  const GLenum buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                             GL_COLOR_ATTACHMENT3};
  glNamedFramebufferDrawBuffers(f, 4, buffers);
  const GLenum status = glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(strf("rtgi G-buffer %dx%d: framebuffer incomplete (0x%x)", width, height, status));
  targetBytes_ =
      static_cast<size_t>(width) * static_cast<size_t>(height) * (16 + 8 + 4 + 8 + 4 + 8 * 3);
}

void RtgiPass::execute(FrameContext& ctx, const GpuScene& gs, const voxel::Octree* octree,
                       const glm::vec3& cameraPosition, int frameIndex, GLuint accum) {
  if (ctx.width != width_ || ctx.height != height_) resize(ctx.width, ctx.height);
  buildOptionalStages();
  const bool specular = settings_.specular;
  // Without shadow rays the direct stage is cheap unshadowed light, run only when
  // there is light to add.
  const bool shadows = settings_.features.shadows;
  const bool direct =
      shadows || gs.lightCount() > 0 || (settings_.features.emission && gs.emitterCount() > 0);
  gpu::RtgiParams p{};
  p.frame = glm::uvec4(static_cast<uint32_t>(frameIndex), settings_.seed,
                       static_cast<uint32_t>(ctx.width), static_cast<uint32_t>(ctx.height));
  const uint32_t flags = (direct ? gpu::kRtgiHasDirect : 0u) |
                         (settings_.indirect ? gpu::kRtgiHasIndirect : 0u) |
                         (specular ? gpu::kRtgiHasSpecular : 0u);
  p.counts = glm::uvec4(
      static_cast<uint32_t>(gs.lightCount()), static_cast<uint32_t>(gs.emitterCount()), flags,
      static_cast<uint32_t>(std::clamp(settings_.exactEmitters, 0, gpu::kMaxExactEmitters)));
  p.camera = glm::vec4(cameraPosition, 1.0f);
  glNamedBufferSubData(params_.id(), 0, sizeof(p), &p);

  {
    gl::StageScope stage(ctx.timer, "gbuffer");
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, ctx.width, ctx.height);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (GLint i = 0; i < 4; ++i) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, i, zero);
    const float one = 1.0f;
    glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glUseProgram(gbuffer_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
    drawSceneGeometry(gs);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  if (octree) octree->bind();
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kRtgiParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, gs.lights());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmitterBinding, gs.emitters());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeLightCdfBinding, gs.emitterCdf());
  glBindTextureUnit(gpu::kGPositionUnit, position_.id());
  glBindTextureUnit(gpu::kGNormalUnit, normal_.id());
  glBindTextureUnit(gpu::kGAlbedoUnit, albedo_.id());
  glBindTextureUnit(gpu::kGEmissionUnit, emission_.id());
  glBindImageTexture(gpu::kDirectImage, directImage_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                     GL_RGBA16F);
  glBindImageTexture(gpu::kIndirectImage, indirectImage_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                     GL_RGBA16F);
  glBindImageTexture(gpu::kSpecularImage, specularImage_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                     GL_RGBA16F);
  glBindImageTexture(gpu::kAccumImage, accum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  const auto gx = static_cast<GLuint>((ctx.width + gpu::kRtgiGroupX - 1) / gpu::kRtgiGroupX);
  const auto gy = static_cast<GLuint>((ctx.height + gpu::kRtgiGroupY - 1) / gpu::kRtgiGroupY);
  auto run = [&](const char* name, const gl::Program& program) {
    gl::StageScope stage(ctx.timer, name);
    glUseProgram(program.id());
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  };
  if (direct) run(shadows ? "shadows" : "direct", direct_);
  if (settings_.indirect) run("indirect", *indirect_);
  if (specular) run("specular", *specular_);
  run("accumulate", accumulate_);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  for (GLuint u = 0; u < 4; ++u) glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  for (GLuint u : {gpu::kGPositionUnit, gpu::kGNormalUnit, gpu::kGAlbedoUnit, gpu::kGEmissionUnit})
    glBindTextureUnit(u, 0);
}

}  // namespace voxgi::render

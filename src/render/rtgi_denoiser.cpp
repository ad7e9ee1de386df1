#include "render/rtgi_denoiser.h"

#include "rtgi_shared.h"

namespace voxgi::render {

void RtgiDenoiser::resize(int width, int height) {
  width_ = width;
  height_ = height;
  for (gl::Texture& t : scratch_) t.reset();
  keys_.reset();
  denoised_.reset();
}

void RtgiDenoiser::execute(gl::FrameContext& ctx, GLuint gx, GLuint gy, GLuint mean, GLuint moments,
                           GLuint directMean) {
  if (!denoised_) {
    for (gl::Texture& t : scratch_) t = gl::createImage2D(GL_RGBA32UI, width_, height_);
    keys_ = gl::createImage2D(GL_RGBA32UI, width_, height_);
    denoised_ = gl::createImage2D(GL_RGBA32F, width_, height_);
  }
  gl::StageScope stage(ctx.timer, Stage::kDenoise);
  glBindTextureUnit(gpu::kHistoryUnit, mean);
  glBindTextureUnit(gpu::kHistoryMomentsUnit, moments);
  glBindTextureUnit(gpu::kHistoryDirectUnit, directMean);
  // Accumulate wrote the mean, moments and direct mean as images.
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  // Both terms of a pixel in one texel of half floats (rtgi_denoise.glsl).
  auto bind = [](GLuint unit, GLuint texture, GLenum access) {
    glBindImageTexture(unit, texture, 0, GL_FALSE, 0, access, GL_RGBA32UI);
  };
  // The terms ping-pong between the two scratch images.
  bind(gpu::kDenoiseKeyImage, keys_.id(), GL_WRITE_ONLY);
  bind(gpu::kDenoiseOutImage, scratch_[0].id(), GL_WRITE_ONLY);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_denoise_prepare.comp"}, {}}).id());
  glDispatchCompute(
      (static_cast<GLuint>(width_) + gpu::kDenoisePrepareGroup - 1) / gpu::kDenoisePrepareGroup,
      (static_cast<GLuint>(height_) + gpu::kDenoisePrepareGroup - 1) / gpu::kDenoisePrepareGroup,
      1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  bind(gpu::kDenoiseKeyImage, keys_.id(), GL_READ_ONLY);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_denoise.comp"}, {}}).id());
  glBindImageTexture(gpu::kDenoisedImage, denoised_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     GL_RGBA32F);
  // The pass's spacing and whether it is the last go in a uniform: updating the
  // parameter block between dispatches stalls a software rasterizer.
  for (int i = 0; i < gpu::kDenoisePasses; ++i) {
    const bool last = i + 1 == gpu::kDenoisePasses;
    const int in = i & 1, out = in ^ 1;
    bind(gpu::kDenoiseInImage, scratch_[in].id(), GL_READ_ONLY);
    bind(gpu::kDenoiseOutImage, scratch_[out].id(), GL_WRITE_ONLY);
    glUniform2f(gpu::kDenoisePassLocation, static_cast<float>(1 << i), last ? 1.0f : 0.0f);
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  for (GLuint u : {gpu::kHistoryUnit, gpu::kHistoryMomentsUnit, gpu::kHistoryDirectUnit})
    glBindTextureUnit(u, 0);
}

}  // namespace voxgi::render

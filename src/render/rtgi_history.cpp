#include "render/rtgi_history.h"

#include "rtgi_shared.h"

namespace voxgi::render {

void RtgiHistory::resize(int width, int height) {
  width_ = width;
  height_ = height;
  mean_ = gl::createImage2D(GL_RGBA32F, width, height);
  for (gl::Texture* t : {&moments_, &reprojectedMoments_, &directMean_, &reprojectedDirect_})
    t->reset();
}

size_t RtgiHistory::makeMoments() {
  if (moments_) return 0;
  for (gl::Texture* t : {&moments_, &reprojectedMoments_, &directMean_, &reprojectedDirect_})
    *t = gl::createImage2D(GL_RGBA32F, width_, height_);
  return static_cast<size_t>(width_) * static_cast<size_t>(height_) * kMomentBytesPerPixel;
}

void RtgiHistory::reproject(gl::FrameContext& ctx, GLuint gx, GLuint gy, GLuint mean,
                            const ReprojectInputs& inputs, GLuint materials, bool moments,
                            std::vector<std::string> defines) {
  gl::StageScope stage(ctx.timer, Stage::kReproject);
  glBindTextureUnit(gpu::kHistoryUnit, mean);
  glBindTextureUnit(gpu::kGPreviousPositionUnit, inputs.previousPosition);
  glBindTextureUnit(gpu::kGPreviousNormalUnit, inputs.previousNormal);
  glBindTextureUnit(gpu::kGMotionUnit, inputs.motion);
  glBindImageTexture(gpu::kReprojectedImage, mean_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, materials);
  if (moments) {
    defines.emplace_back("RTGI_MOMENTS");
    glBindTextureUnit(gpu::kHistoryMomentsUnit, moments_.id());
    glBindTextureUnit(gpu::kHistoryDirectUnit, directMean_.id());
    glBindImageTexture(gpu::kReprojectedMomentsImage, reprojectedMoments_.id(), 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(gpu::kReprojectedDirectImage, reprojectedDirect_.id(), 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA32F);
  }
  glUseProgram(programs_.get({{"render/rtgi/rtgi_reproject.comp"}, defines}).id());
  glDispatchCompute(gx, gy, 1);
  // Accumulate reads the reprojected moments and direct mean as textures.
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  for (GLuint u : {gpu::kHistoryUnit, gpu::kGPreviousPositionUnit, gpu::kGPreviousNormalUnit,
                   gpu::kGMotionUnit, gpu::kHistoryMomentsUnit, gpu::kHistoryDirectUnit})
    glBindTextureUnit(u, 0);
}

}  // namespace voxgi::render

#include "render/rtgi_work_mask.h"

#include <algorithm>

#include "rtgi_shared.h"

namespace voxgi::render {

void RtgiWorkMask::resize(int width, int height) {
  width_ = width;
  height_ = height;
  keys_ = gl::createImage2D(GL_RGBA32UI, width, height);
  edges_ = gl::createImage2D(GL_R16F, width, height);
  image_ = gl::createImage2D(GL_R16F, width, height);
  histogram_ = gl::createBuffer(4 * gpu::kMaskBins, nullptr, GL_DYNAMIC_STORAGE_BIT);
  valid_ = false;
  bins_.clear();
}

void RtgiWorkMask::update(gl::FrameContext& ctx, GLuint gx, GLuint gy, int frameIndex) {
  if (valid_ && !stale_ && frameIndex % kPeriod != 1) return;
  gl::StageScope stage(ctx.timer, Stage::kMask);
  glClearNamedBufferSubData(histogram_.id(), GL_R32UI, 0, 4 * gpu::kMaskBins, GL_RED_INTEGER,
                            GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaskHistogramBinding, histogram_.id());
  glBindImageTexture(gpu::kEdgeImage, edges_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R16F);
  glBindImageTexture(gpu::kMaskImage, image_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
  glBindImageTexture(gpu::kMaskKeyImage, keys_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_mask_key.comp"}, {}}).id());
  glDispatchCompute(gx, gy, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_mask.comp"}, {}}).id());
  glDispatchCompute(gx, gy, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glUseProgram(programs_.get({{"render/rtgi/rtgi_mask_blur.comp"}, {}}).id());
  glDispatchCompute(gx, gy, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT);
  valid_ = true;
  stale_ = false;
  bins_.resize(gpu::kMaskBins);
  glGetNamedBufferSubData(histogram_.id(), 0, 4 * gpu::kMaskBins, bins_.data());
}

float RtgiWorkMask::threshold(uint64_t extra) const {
  uint64_t above = 0;
  for (int b = static_cast<int>(bins_.size()) - 1; b >= 0; --b) {
    if (above + bins_[static_cast<size_t>(b)] > extra)
      return static_cast<float>(b + 1) / static_cast<float>(gpu::kMaskBins);
    above += bins_[static_cast<size_t>(b)];
  }
  return -1.0f;  // every pixel
}

std::vector<float> RtgiWorkMask::read() const {
  std::vector<float> out;
  if (!valid_) return out;
  out.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(image_.id(), 0, GL_RED, GL_FLOAT,
                    static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
  // Bottom-up rows to top-left origin.
  const size_t w = static_cast<size_t>(width_);
  for (size_t y = 0; y < static_cast<size_t>(height_) / 2; ++y)
    std::swap_ranges(
        out.begin() + static_cast<std::ptrdiff_t>(y * w),
        out.begin() + static_cast<std::ptrdiff_t>((y + 1) * w),
        out.begin() + static_cast<std::ptrdiff_t>((static_cast<size_t>(height_) - 1 - y) * w));
  return out;
}

}  // namespace voxgi::render

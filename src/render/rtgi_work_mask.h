// rtgi's work mask (stage "mask"; docs/frame-budget.md): where the image is still
// noisy, per pixel in [0, 1), from the edges of the running mean's luminance between
// neighbours on the same surface, blurred (rtgi_mask_key.comp, rtgi_mask.comp,
// rtgi_mask_blur.comp), and the histogram of its values, from which the select stage
// takes the threshold that lets the budget's share of the pixels trace.
//
// Reads what RtgiPass binds for its compute stages (the parameters, the G-buffer,
// the accumulation target). Made every kPeriod frames: it changes slowly as the image
// converges, and the threshold follows the budget every frame.
#ifndef VOXGI_RENDER_RTGI_WORK_MASK_H
#define VOXGI_RENDER_RTGI_WORK_MASK_H

#include <cstdint>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "render/frame_context.h"

namespace voxgi::render {

class RtgiWorkMask {
 public:
  static constexpr int kPeriod = 4;  // frames between updates

  explicit RtgiWorkMask(gl::ProgramCache& programs) : programs_(programs) {}
  // Its images at width x height; the mask is made again on the next update().
  void resize(int width, int height);
  // Makes the mask when it is out of date: none yet, a period begins (frameIndex %
  // kPeriod == 1), or a period passed while it was not needed (skip). gx, gy: the
  // groups of rtgi's per-pixel stages.
  void update(gl::FrameContext& ctx, GLuint gx, GLuint gy, int frameIndex);
  // A frame that needs no mask: a period that begins now is owed to the next update().
  void skip(int frameIndex) { stale_ = stale_ || frameIndex % kPeriod == 1; }
  // The lowest bin edge with at most `extra` pixels of the last mask above it; -1:
  // every pixel.
  float threshold(uint64_t extra) const;
  bool valid() const { return valid_; }
  GLuint image() const { return image_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  // The last mask, top-left origin (empty before one was made).
  std::vector<float> read() const;

 private:
  gl::ProgramCache& programs_;
  int width_ = 0, height_ = 0;
  gl::Texture keys_, edges_, image_;
  gl::Buffer histogram_;
  std::vector<uint32_t> bins_;
  bool valid_ = false;
  bool stale_ = false;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RTGI_WORK_MASK_H

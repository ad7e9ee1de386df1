// What rtgi keeps of each pixel beside its running mean (the accumulation target,
// which the renderer owns), and the reproject stage that carries it across a camera
// move (rtgi_reproject.comp):
//   - with the denoiser, the moments of the pixel's two terms and the mean of its
//     direct term, which accumulate updates (rtgi_accumulate.comp, RTGI_MOMENTS) and
//     the denoiser reads (RtgiDenoiser);
//   - after a camera move, the mean, and those with it, reprojected from the previous
//     frame's pixels onto the surfaces this frame shows: a pixel follows the surface
//     from where it was, drops what showed another surface and caps its count.
//     Accumulate and the indirect stage read them in place of the pixel's own.
//
// Reads what RtgiPass binds for its compute stages (the parameters, this frame's
// G-buffer: rtgi_common.glsl) and, given to reproject(), the previous frame's
// position and normal and this frame's motion.
#ifndef VOXGI_RENDER_RTGI_HISTORY_H
#define VOXGI_RENDER_RTGI_HISTORY_H

#include <cstddef>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "render/frame_context.h"

namespace voxgi::render {

class RtgiHistory {
 public:
  explicit RtgiHistory(gl::ProgramCache& programs) : programs_(programs) {}
  // Its images at width x height. The moments are made by makeMoments(), on the first
  // frame that denoises: only a pass that denoises pays for them.
  void resize(int width, int height);
  // The moments' images, unless made already. Returns the bytes it added.
  size_t makeMoments();
  bool hasMoments() const { return static_cast<bool>(moments_); }

  // What reproject() reads besides the mean: the previous frame's G-buffer (its
  // positions and normals) and this frame's motion.
  struct ReprojectInputs {
    GLuint previousPosition = 0, previousNormal = 0, motion = 0;
  };
  // The reproject stage: `mean` (the accumulation target, holding the previous
  // frame's image) and, with `moments` (the pass denoises; makeMoments() made them),
  // the moments and direct mean, into their reprojected images. gx, gy: the groups of
  // rtgi's per-pixel stages; `materials`: the scene's (which of them emit);
  // `defines`: the scene's shader features.
  void reproject(gl::FrameContext& ctx, GLuint gx, GLuint gy, GLuint mean,
                 const ReprojectInputs& inputs, GLuint materials, bool moments,
                 std::vector<std::string> defines);

  // The images, 0 where not made: the reprojected mean (rgba32f, the target's
  // layout); the moments of both terms and the direct term's mean (rgba32f), and
  // their reprojections.
  GLuint reprojectedMean() const { return mean_.id(); }
  GLuint moments() const { return moments_.id(); }
  GLuint directMean() const { return directMean_.id(); }
  GLuint reprojectedMoments() const { return reprojectedMoments_.id(); }
  GLuint reprojectedDirect() const { return reprojectedDirect_.id(); }

  // Bytes a pixel: the reprojected mean; with the moments, four rgba32f more.
  static constexpr size_t kBytesPerPixel = 16;
  static constexpr size_t kMomentBytesPerPixel = 4 * 16;

 private:
  gl::ProgramCache& programs_;
  int width_ = 0, height_ = 0;
  gl::Texture mean_;
  gl::Texture moments_, reprojectedMoments_, directMean_, reprojectedDirect_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RTGI_HISTORY_H

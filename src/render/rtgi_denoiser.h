// rtgi's denoise stage: the running mean filtered by a variance-guided, edge-avoiding
// wavelet (Schied et al. 2017, "Spatiotemporal variance-guided filtering"), the
// direct light and the rest each against its own noise (rtgi_denoise_prepare.comp,
// rtgi_denoise.comp, rtgi_denoise.glsl). The mean itself stays as it was.
//
// Reads what RtgiPass binds for its compute stages (the parameters, the G-buffer:
// rtgi_common.glsl) and, given to execute(), the mean, the moments of both terms and
// the direct term's mean. Owns its scratch images, the edge stops' keys and the
// image it writes.
#ifndef VOXGI_RENDER_RTGI_DENOISER_H
#define VOXGI_RENDER_RTGI_DENOISER_H

#include <cstddef>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "render/frame_context.h"

namespace voxgi::render {

class RtgiDenoiser {
 public:
  explicit RtgiDenoiser(gl::ProgramCache& programs) : programs_(programs) {}
  // Its images at width x height, made on the first execute() at that size: only
  // a pass that denoises pays for them.
  void resize(int width, int height);
  // Filters `mean` (the accumulation target, rgba32f: light and sample count) into
  // image(), in the stage "denoise". `moments` and `directMean`: accumulate's
  // (rtgi_accumulate.comp, RTGI_MOMENTS). gx, gy: the groups of rtgi's per-pixel
  // stages (kRtgiGroupX by kRtgiGroupY).
  void execute(gl::FrameContext& ctx, GLuint gx, GLuint gy, GLuint mean, GLuint moments,
               GLuint directMean);
  // The denoised image (rgba32f, the mean's layout; alpha its sample count), 0 before
  // the first execute().
  GLuint image() const { return denoised_.id(); }
  // Bytes a pixel of its images: two scratch images of both terms (rtgi_denoise.glsl,
  // packDenoiseTerms), the keys and the output, 16 each.
  static constexpr size_t kBytesPerPixel = 4 * 16;

 private:
  gl::ProgramCache& programs_;
  int width_ = 0, height_ = 0;
  gl::Texture scratch_[2], keys_, denoised_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RTGI_DENOISER_H

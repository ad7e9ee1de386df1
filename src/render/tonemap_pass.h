// Linear HDR radiance -> 8-bit sRGB for display and PNG. Reads an RGBA32F
// texture; writes RGBA8 (already sRGB-encoded) into the target framebuffer.
#ifndef VOXGI_RENDER_TONEMAP_PASS_H
#define VOXGI_RENDER_TONEMAP_PASS_H

#include <optional>
#include <string>

#include "gl/handles.h"
#include "render/frame_context.h"
#include "render/knob.h"

namespace voxgi::render {

enum class Tonemap { kClamp, kAces };
std::optional<Tonemap> parseTonemap(const std::string& name);
const char* tonemapName(Tonemap t);

class TonemapPass {
 public:
  struct Settings {
    float exposure = 1.0f;  // linear scale applied before the operator
    Tonemap op = Tonemap::kClamp;
  };

  TonemapPass(gl::ProgramCache& programs, const Settings& settings);
  void execute(gl::FrameContext& ctx, GLuint hdrTexture, GLuint framebuffer);
  // A single-channel image in [0, 1] (the rtgi work mask) as grey instead.
  // `scale`: the mask's size over the image's (below 1 under an rtgi render scale).
  void executeMask(gl::FrameContext& ctx, GLuint maskTexture, glm::vec2 scale, GLuint framebuffer);
  // rtgi at a render scale below 1: the radiance shown from the upsampler's history
  // (its sum and count per output pixel, RtgiPass::upsampleHistory()) and rtgi's
  // internal image `shown` (read through `linear`, a bilinear sampler), which weighs
  // as `weight` samples; written to `framebuffer`'s attachment 0 tonemapped and to
  // its attachment 1 (rgba32f) as radiance.
  void executeUpsampled(gl::FrameContext& ctx, GLuint history, GLuint shown, GLuint linear,
                        float weight, GLuint framebuffer);
  Settings& settings() { return settings_; }
  // Exposure and operator, for the viewer's panel.
  void appendKnobs(std::vector<Knob>* knobs);

 private:
  Settings settings_;
  bool masking_ = false;
  glm::vec2 maskScale_{1.0f};
  const gl::Program& program_;
  gl::ProgramCache& programs_;
  gl::VertexArray emptyVao_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_TONEMAP_PASS_H

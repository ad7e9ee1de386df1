#include "render/tonemap_pass.h"

#include "scene_shared.h"

namespace voxgi::render {

std::optional<Tonemap> parseTonemap(const std::string& name) {
  if (name == "clamp") return Tonemap::kClamp;
  if (name == "aces") return Tonemap::kAces;
  return std::nullopt;
}

const char* tonemapName(Tonemap t) {
  return t == Tonemap::kAces ? "aces" : "clamp";
}

TonemapPass::TonemapPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      program_(programs.get({{"render/fullscreen.vert", "render/tonemap.frag"}, {}})),
      programs_(programs),
      emptyVao_(gl::createVertexArray()) {}

void TonemapPass::appendKnobs(std::vector<Knob>* knobs) {
  Knob exposure;
  exposure.label = "exposure";
  exposure.min = 1.0 / 64.0;
  exposure.max = 64.0;
  exposure.logarithmic = true;
  exposure.help = "linear scale applied to radiance before the operator";
  exposure.get = [this] { return static_cast<double>(settings_.exposure); };
  exposure.set = [this](double v) { settings_.exposure = static_cast<float>(v); };
  knobs->push_back(std::move(exposure));
  Knob op;
  op.label = "tonemap";
  op.kind = Knob::Kind::kChoice;
  op.choices = {tonemapName(Tonemap::kClamp), tonemapName(Tonemap::kAces)};
  op.help = "clamp: radiance above 1 clips; aces: Narkowicz's filmic fit";
  op.get = [this] { return settings_.op == Tonemap::kAces ? 1.0 : 0.0; };
  op.set = [this](double v) { settings_.op = v >= 0.5 ? Tonemap::kAces : Tonemap::kClamp; };
  knobs->push_back(std::move(op));
}

void TonemapPass::executeMask(gl::FrameContext& ctx, GLuint maskTexture, glm::vec2 scale,
                              GLuint framebuffer) {
  const Settings saved = settings_;
  masking_ = true;
  maskScale_ = scale;
  execute(ctx, maskTexture, framebuffer);
  masking_ = false;
  settings_ = saved;
}

void TonemapPass::executeUpsampled(gl::FrameContext& ctx, GLuint history, GLuint shown,
                                   GLuint linear, float weight, GLuint framebuffer) {
  gl::StageScope stage(ctx.timer, Stage::kTonemap);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(
      programs_.get({{"render/fullscreen.vert", "render/tonemap.frag"}, {"TONEMAP_UPSAMPLED"}})
          .id());
  glBindTextureUnit(gpu::kUpsampleHistoryUnit, history);
  glBindTextureUnit(gpu::kUpsampleShownUnit, shown);
  glBindSampler(gpu::kUpsampleShownUnit, linear);
  glUniform1f(gpu::kExposureLocation, settings_.exposure);
  glUniform1i(gpu::kTonemapLocation,
              settings_.op == Tonemap::kAces ? gpu::kTonemapAces : gpu::kTonemapClamp);
  glUniform1f(gpu::kUpsampleWeightLocation, weight);
  glBindVertexArray(emptyVao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindSampler(gpu::kUpsampleShownUnit, 0);
  glBindTextureUnit(gpu::kUpsampleHistoryUnit, 0);
  glBindTextureUnit(gpu::kUpsampleShownUnit, 0);
}

void TonemapPass::execute(gl::FrameContext& ctx, GLuint hdrTexture, GLuint framebuffer) {
  gl::StageScope stage(ctx.timer, Stage::kTonemap);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glBindTextureUnit(gpu::kHdrInputUnit, hdrTexture);
  glUniform1f(gpu::kExposureLocation, settings_.exposure);
  glUniform1i(gpu::kTonemapLocation, masking_                         ? gpu::kTonemapMask
                                     : settings_.op == Tonemap::kAces ? gpu::kTonemapAces
                                                                      : gpu::kTonemapClamp);
  glUniform2f(gpu::kTonemapInputScaleLocation, masking_ ? maskScale_.x : 1.0f,
              masking_ ? maskScale_.y : 1.0f);
  glBindVertexArray(emptyVao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindTextureUnit(gpu::kHdrInputUnit, 0);
}

}  // namespace voxgi::render

#include "render/tonemap_pass.h"

#include "scene_shared.h"

namespace voxgi::render {

std::optional<Tonemap> parseTonemap(const std::string& name) {
  if (name == "clamp") return Tonemap::kClamp;
  if (name == "aces") return Tonemap::kAces;
  return std::nullopt;
}

TonemapPass::TonemapPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      program_(programs.get({{"render/fullscreen.vert", "render/tonemap.frag"}, {}})),
      emptyVao_(gl::createVertexArray()) {}

void TonemapPass::execute(FrameContext& ctx, GLuint hdrTexture, GLuint framebuffer) {
  gl::StageScope stage(ctx.timer, "tonemap");
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glBindTextureUnit(gpu::kHdrInputUnit, hdrTexture);
  glUniform1f(gpu::kExposureLocation, settings_.exposure);
  glUniform1i(gpu::kTonemapLocation,
              settings_.op == Tonemap::kAces ? gpu::kTonemapAces : gpu::kTonemapClamp);
  glBindVertexArray(emptyVao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindTextureUnit(gpu::kHdrInputUnit, 0);
}

}  // namespace voxgi::render

#include "render/raster_pass.h"

namespace voxgi::render {

void drawSceneGeometry(const GpuScene& gs) {
  glBindVertexArray(gs.vertexArray());
  gs.setDefaultColor();
  gs.bindSampler();
  const scene::Scene& s = gs.scene();
  for (const scene::Draw& d : s.draws) {
    const scene::Material& m = s.materials[static_cast<size_t>(d.material)];
    if (m.doubleSided) {
      glDisable(GL_CULL_FACE);
    } else {
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
    }
    gs.bindMaterialTextures(m);
    glUniform1i(gpu::kMaterialIndexLocation, d.material);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(d.indexCount), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<uintptr_t>(d.firstIndex) * 4));
  }
  glDisable(GL_CULL_FACE);
  GpuScene::unbindMaterialTextures();
}

RasterPass::RasterPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      program_(programs.get(
          {{"render/raster.vert", "render/raster.frag"}, settings.features.defines()})) {}

void RasterPass::execute(gl::FrameContext& ctx, const GpuScene& gs, GLuint framebuffer) {
  gl::StageScope stage(ctx.timer, Stage::kRaster);
  beginOpaquePass(ctx, framebuffer, settings_.clearColor);
  glUseProgram(program_.id());
  glUniform1f(gpu::kAmbientLocation, settings_.ambient);
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, gs.lights());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmitterBinding, gs.emitters());
  drawSceneGeometry(gs);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace voxgi::render

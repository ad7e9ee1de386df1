#include "render/points_pass.h"

#include "scene_shared.h"
#include "voxel_shared.h"

namespace voxgi::render {

PointsPass::PointsPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      draw_(programs.get({{"render/voxel_points.vert", "render/voxel_points.frag"}, {}})),
      emptyVao_(gl::createVertexArray()) {}

void PointsPass::execute(gl::FrameContext& ctx, const voxel::VoxelizePass& grid,
                         GLuint framebuffer) {
  gl::StageScope stage(ctx.timer, Stage::kPoints);
  beginOpaquePass(ctx, framebuffer, settings_.clearColor);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glUseProgram(draw_.id());
  glBindVertexArray(emptyVao_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kFrameBinding, ctx.frameUniforms);
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, grid.params());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, grid.list());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelAttribBinding, grid.attributes());
  const uint32_t count = grid.stats().occupied;
  if (count > 0) glDrawArraysInstanced(GL_TRIANGLES, 0, 36, static_cast<GLsizei>(count));
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace voxgi::render

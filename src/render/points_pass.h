// `--mode points`: the voxel grid drawn as cubes, one per occupied voxel (the
// debug view of the voxel GI thesis). Reads the resolved grid of a VoxelizePass;
// writes HDR radiance + depth like the raster pass. Shading is for inspection:
// albedo under a head light, plus emission.
#ifndef VOXGI_RENDER_POINTS_PASS_H
#define VOXGI_RENDER_POINTS_PASS_H

#include "gl/frame_context.h"
#include "gl/handles.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::render {

class PointsPass {
 public:
  struct Settings {
    glm::vec4 clearColor{0.0f, 0.0f, 0.0f, 1.0f};
  };

  PointsPass(gl::ProgramCache& programs, const Settings& settings);
  // Rebuilds the list of occupied voxels; call after each voxelization.
  void update(gl::FrameContext& ctx, const voxel::VoxelizePass& grid);
  void execute(gl::FrameContext& ctx, const voxel::VoxelizePass& grid, GLuint framebuffer);
  uint32_t cubes() const { return count_; }

 private:
  Settings settings_;
  const gl::Program& compact_;
  const gl::Program& draw_;
  gl::Buffer list_, stats_;
  gl::VertexArray emptyVao_;
  uint32_t count_ = 0;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_POINTS_PASS_H

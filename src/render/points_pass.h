// `--mode points`: the voxel grid drawn as cubes, one per occupied voxel (the
// debug view of the voxel GI thesis). Reads the resolved grid of a VoxelizePass;
// writes HDR radiance + depth like the raster pass. Shading is for inspection:
// albedo under a head light, plus emission.
#ifndef VOXGI_RENDER_POINTS_PASS_H
#define VOXGI_RENDER_POINTS_PASS_H

#include "gl/handles.h"
#include "render/frame_context.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::render {

class PointsPass {
 public:
  struct Settings {
    glm::vec4 clearColor{0.0f, 0.0f, 0.0f, 1.0f};
  };

  PointsPass(gl::ProgramCache& programs, const Settings& settings);
  // One cube per voxel in the grid's list of occupied voxels.
  void execute(gl::FrameContext& ctx, const voxel::VoxelizePass& grid, GLuint framebuffer);

 private:
  Settings settings_;
  const gl::Program& draw_;
  gl::VertexArray emptyVao_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_POINTS_PASS_H

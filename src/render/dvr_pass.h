// `--mode dvr`: direct volume rendering of the lit octree (shaders/render/dvr.comp).
// Reads a lit Octree; writes linear HDR radiance into the renderer's RGBA32F target.
#ifndef VOXGI_RENDER_DVR_PASS_H
#define VOXGI_RENDER_DVR_PASS_H

#include "gl/handles.h"
#include "render/frame_context.h"
#include "scene/scene.h"
#include "voxel/octree.h"

namespace voxgi::render {

class DvrPass {
 public:
  struct Settings {
    float stopOpacity = 0.99f;  // a ray stops once this opaque
  };
  DvrPass(gl::ProgramCache& programs, const Settings& settings);
  void execute(gl::FrameContext& ctx, const voxel::Octree& octree, const scene::Camera& camera,
               GLuint target);

 private:
  Settings settings_;
  const gl::Program& program_;
  gl::Buffer params_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_DVR_PASS_H

// Raster baseline ("baseline standard render" of the voxel GI thesis).
// Reads: the GpuScene. Writes: linear HDR radiance (RGBA32F) and depth into the
// given target at the frame size. Lighting: emission plus unshadowed direct light
// from punctual lights and emissive surfaces (shaders/include/lighting.glsl), plus
// an optional uniform ambient term scaled by the material's occlusion texture.
// Tested by tests/render/raster_gltest.cpp (backends agree, golden image).
#ifndef VOXGI_RENDER_RASTER_PASS_H
#define VOXGI_RENDER_RASTER_PASS_H

#include "gl/handles.h"
#include "render/frame_context.h"
#include "render/gpu_scene.h"
#include "scene/effects.h"

namespace voxgi::render {

// Draws every draw of the scene with the bound program (material index uniform,
// base-colour texture, culling as the material asks); the frame's uniforms and
// the material SSBO must be bound.
void drawSceneGeometry(const GpuScene& gs);

class RasterPass {
 public:
  struct Settings {
    glm::vec4 clearColor{0.0f, 0.0f, 0.0f, 1.0f};  // the background emits nothing
    scene::ShaderFeatures features;                // effect-plan variant of raster.frag
    // Uniform ambient radiance (grey) times the diffuse albedo and the occlusion
    // texture (glTF occlusionTexture, mixed in by its strength); 0: none.
    float ambient = 0.0f;
  };

  RasterPass(gl::ProgramCache& programs, const Settings& settings);
  // Draws into `framebuffer` (HDR colour + depth of size ctx.width x ctx.height).
  void execute(gl::FrameContext& ctx, const GpuScene& scene, GLuint framebuffer);

 private:
  Settings settings_;
  const gl::Program& program_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RASTER_PASS_H

// `--mode rtgi`: hybrid raster + ray-marched global illumination (the default mode).
//
// Reads: the GpuScene and a lit Octree. Writes: the running mean of linear HDR
// radiance into the renderer's RGBA32F target (which it keeps between frames).
// Stages, each timed:
//   gbuffer     raster primary visibility: position, normal + roughness, base colour
//               + metallic, emission (rtgi_shared.h);
//   shadows     direct light with shadow rays through the octree (rtgi_direct.comp);
//               with the shadows effect off, "direct": the same without shadow rays,
//               and absent when there is no light at all;
//   indirect    one cosine ray per pixel into the lit voxels (rtgi_indirect.comp),
//               with the indirect effect;
//   specular    the reflected ray of mirrors and glossy surfaces (rtgi_specular.comp),
//               with the specular effect (the scene has such materials);
//   accumulate  emission + the three terms, into the mean over still frames.
// Every stage draws its random numbers from a hash of (seed, pixel, frame, stage):
// each frame brings new samples, so accumulation converges.
#ifndef VOXGI_RENDER_RTGI_PASS_H
#define VOXGI_RENDER_RTGI_PASS_H

#include "gl/handles.h"
#include "render/frame_context.h"
#include "render/gpu_scene.h"
#include "rtgi_shared.h"
#include "scene/effects.h"
#include "scene/scene.h"
#include "voxel/octree.h"

namespace voxgi::render {

class RtgiPass {
 public:
  struct Settings {
    // From the effect plan (scene/effects.h): whether the indirect and specular
    // stages run, and the shader variants of the others.
    bool indirect = true;
    bool specular = true;
    scene::ShaderFeatures features;
    int exactEmitters = 4;  // up to this many emitters, each gets a shadow ray
    uint32_t seed = 1;
  };

  RtgiPass(gl::ProgramCache& programs, const Settings& settings);
  // Renders frame `frameIndex` of the accumulation (0 restarts it) into `accum`.
  // `octree` may be null when the settings trace nothing (no shadows, indirect or
  // specular light).
  void execute(FrameContext& ctx, const GpuScene& scene, const voxel::Octree* octree,
               const glm::vec3& cameraPosition, int frameIndex, GLuint accum);
  const Settings& settings() const { return settings_; }
  Settings& settings() { return settings_; }
  size_t targetBytes() const { return targetBytes_; }

 private:
  void resize(int width, int height);

  // The programs of the indirect and specular stages, built only when they run.
  void buildOptionalStages();

  Settings settings_;
  gl::ProgramCache& programs_;
  const gl::Program& gbuffer_;
  const gl::Program& direct_;
  const gl::Program& accumulate_;
  const gl::Program* indirect_ = nullptr;
  const gl::Program* specular_ = nullptr;
  gl::Buffer params_;
  gl::Texture position_, normal_, albedo_, emission_, depth_;
  gl::Texture directImage_, indirectImage_, specularImage_;
  gl::Framebuffer fbo_;
  int width_ = 0, height_ = 0;
  size_t targetBytes_ = 0;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RTGI_PASS_H

// Reference path tracer (`--mode pathtrace`): Monte Carlo path tracing over the
// scene's exact triangles in a compute shader, so it runs on any GL 4.5 device
// (llvmpipe included).
//
// The GL device of the Pathtracer interface (render/pathtrace/pathtracer.h).
// Reads: the scene (triangles, materials, punctual lights, emissive triangles) and a
// BVH built on the CPU (render/gpu_bvh.h: its own at construction, or the one the
// Renderer shares with rtgi; the "bvh" start-up stage).
// Writes: linear radiance, the mean of all samples so far, into the caller's RGBA32F
// texture at the frame size; it keeps the running sum (and its Kahan compensation)
// in two RGBA32F images of its own, so samples accumulate progressively across calls
// to execute() until reset().
//
// Transport (shaders/render/pathtrace.comp): unidirectional path tracing with
// next-event estimation and MIS (Veach 1997, power heuristic) between light and
// BSDF sampling; emissive triangles are area lights chosen in proportion to power
// (area x luminance) through an alias table; punctual lights by NEE only. Depths in
// Mitsuba's convention (1 = emitters seen directly, 2 = direct light), Russian
// roulette from rrDepth. Materials as scenes/reference_scenes.md reads glTF:
// metallic 0 + roughness 1 is Lambert, metallic 1 + roughness 0 a perfect mirror of
// reflectance = base colour (no Fresnel), anything else the glTF metallic-roughness
// BRDF (Lambert + GGX with visible-normal sampling, Heitz 2018). An emissive surface
// emits from its front face (both faces when double-sided) and reflects by its
// material like any other. Textures multiply their factors (base colour; emission,
// also where next-event estimation samples a point; metallic in blue and roughness
// in green of the metallic-roughness texture): corner UVs per triangle and every
// texture's texels live in buffer textures, sampled bilinearly over linear texels
// (colour textures decoded from sRGB) with repeat wrapping, no mipmaps. Without
// textures (Settings::textures off, or no textured material) the kernel is compiled
// without them (VOXGI_NO_TEXTURES). Alpha masks are not read.
// Camera: the scene camera at the image aspect, box pixel filter (uniform jitter).
//
// Tested by tests/render/pathtrace_gltest.cpp: white furnace, a plane under a point
// light against the closed form, energy per bounce, no NaN, seeds, convergence.
#ifndef VOXGI_RENDER_PATHTRACE_PATHTRACE_PASS_H
#define VOXGI_RENDER_PATHTRACE_PATHTRACE_PASS_H

#include <cstdint>
#include <memory>

#include "gl/handles.h"
#include "render/frame_context.h"
#include "render/gpu_bvh.h"
#include "render/gpu_scene.h"
#include "render/pathtrace/pathtracer.h"

namespace voxgi::render {

class PathtracePass final : public Pathtracer {
 public:
  using Settings = PathtraceSettings;

  // `bvh`: the scene's BVH when the caller shares one (the Renderer); null builds one.
  PathtracePass(gl::ProgramCache& programs, const GpuScene& scene, const Settings& settings,
                std::shared_ptr<const GpuBvh> bvh = nullptr);

  void reset() override;
  void setCamera(const scene::Camera& camera) override { camera_ = camera; }
  void execute(gl::FrameContext& ctx, int spp, GLuint hdrTexture,
               const Progress& progress = {}) override;
  // Compiles the kernel and runs one work group, so the driver's JIT is start-up.
  void warmUp(gl::FrameContext& ctx, GLuint hdrTexture) override;

  int samplesSoFar() const override { return samples_; }
  // Waits for the GPU.
  uint64_t truncatedPaths() const override;
  int emissiveTriangles() const override { return gpuBvh_->emissiveTriangles(); }
  double bvhBuildMs() const override { return gpuBvh_->buildMs(); }
  size_t bvhNodes() const override { return gpuBvh_->nodeCount(); }
  PathtraceDevice device() const override { return PathtraceDevice::kGl; }
  Settings& settings() { return settings_; }

 private:
  void allocate(int width, int height);
  void dispatch(gl::FrameContext& ctx, GLuint hdrTexture, int x0, int y0, int w, int h,
                int firstSample, int samples);

  Settings settings_;
  const GpuScene& scene_;
  std::shared_ptr<const GpuBvh> gpuBvh_;  // declared before textured_ and program_
  bool textured_ = false;  // the kernel reads base-colour textures (declared before program_)
  const gl::Program& program_;
  gl::Buffer params_, counter_;
  gl::Texture sum_, compensation_;
  int width_ = 0, height_ = 0;
  int samples_ = 0;
  float epsilon_ = 1e-5f;
  scene::Camera camera_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_PATHTRACE_PATHTRACE_PASS_H

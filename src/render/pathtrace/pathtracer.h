// The reference path tracer's interface, whichever device runs it:
//   gl:  PathtracePass (render/pathtrace/pathtrace_pass.h), a compute shader over a BVH of
//        the exact triangles; any GL 4.5 device, llvmpipe included;
//   cpu: CpuPathtracer (render/pathtrace/pathtrace_cpu.h), Embree 3 ray casting with TBB
//        threads: on a software GL (llvmpipe, softpipe) many times faster.
// Both trace the same paths: materials, light sampling, MIS weights, the alias
// table lookup, texture reads and the random stream come from one source
// (shaders/include/brdf_shared.h, sampling_shared.h, pathtrace_shading.h), so a
// seed and a sample index give the same random numbers on either device; the
// integrator loop around them is written once per device and tested to agree
// (tests/render/pathtrace_gltest.cpp runs its whole suite on both).
// Either writes the mean of all samples since reset() into the caller's RGBA32F
// texture, so tone mapping, screenshots and tests read both alike.
#ifndef VOXGI_RENDER_PATHTRACE_PATHTRACER_H
#define VOXGI_RENDER_PATHTRACE_PATHTRACER_H

#include <cstdint>
#include <functional>
#include <string>

#include "gl/gl.h"
#include "render/frame_context.h"
#include "scene/scene.h"

namespace voxgi::render {

enum class PathtraceDevice { kAuto, kCpu, kGl };

// Whether GL_RENDERER names a software rasterizer (llvmpipe, softpipe, swrast).
bool isSoftwareRenderer(const std::string& glRenderer);

// "auto", "cpu", "gl"; throws Error on anything else.
PathtraceDevice parsePathtraceDevice(const std::string& name);
const char* pathtraceDeviceName(PathtraceDevice device);
// What `auto` means for a GL renderer string: cpu on a software rasterizer
// (llvmpipe, softpipe, swrast), gl on anything else.
PathtraceDevice resolvePathtraceDevice(PathtraceDevice device, const std::string& glRenderer);

struct PathtraceSettings {
  int maxDepth = 8;  // Mitsuba's convention: 8 allows 7 bounces (reference_scenes.md)
  int rrDepth = 5;   // Russian roulette from this depth on (reference_scenes.md)
  uint32_t seed = 0;
  // false: emissive surfaces are found by BSDF sampling alone (no light sampling,
  // no MIS); tests compare the two estimators, which must agree.
  bool nextEventEstimation = true;
  // gl: pixels per dispatch (one path each; see kPtLoopBudget for why one): small
  // enough that a dispatch stays well under a second on llvmpipe, so progress
  // stays live; larger images are cut into bands of whole rows.
  int64_t pixelsPerDispatch = 1 << 18;
  // Textures (base colour, emissive, metallic-roughness; the effect plan's `textures`); off, or
  // with no textured material, none are read (the GL kernel is compiled without them).
  bool textures = true;
  // Alpha masks (the effect plan's `alpha`): rays pass where a MASK material's
  // alpha is below its cutoff.
  bool alpha = true;
  // Vertex colours (the effect plan's `colors`): COLOR_0 multiplies the base colour
  // (and its alpha); off, or in a scene without them, none are read.
  bool colors = true;
  // Normal maps (the effect plan's `normalmaps`): the normal texture bends the
  // shading normal; off, or in a scene without them, the vertex normal shades.
  bool normalMaps = true;
  PathtraceDevice device = PathtraceDevice::kAuto;
  // cpu: worker threads (0: one per core).
  int threads = 0;
};

class Pathtracer {
 public:
  // Called after each pass over the image with the samples per pixel done so far.
  using Progress = std::function<void(int done, int total)>;
  virtual ~Pathtracer() = default;

  // Clears the accumulation (the next execute() starts from sample 0).
  virtual void reset() = 0;
  // The camera of the next samples (default: the scene's); a change needs reset().
  virtual void setCamera(const scene::Camera& camera) = 0;
  // Adds `spp` samples per pixel and writes the mean of all samples so far into
  // `hdrTexture` (RGBA32F, ctx.width x ctx.height).
  virtual void execute(gl::FrameContext& ctx, int spp, GLuint hdrTexture,
                       const Progress& progress = {}) = 0;
  // Work done once before timing starts (the GL kernel's JIT compile).
  virtual void warmUp(gl::FrameContext& ctx, GLuint hdrTexture) = 0;

  virtual int samplesSoFar() const = 0;
  // Paths stopped by a loop budget since reset() (the GL device on llvmpipe; see
  // kPtLoopBudget); should be 0.
  virtual uint64_t truncatedPaths() const = 0;
  virtual int emissiveTriangles() const = 0;
  // The acceleration structure: build time and a size figure for the stats.
  virtual double bvhBuildMs() const = 0;
  virtual size_t bvhNodes() const = 0;
  virtual PathtraceDevice device() const = 0;
  // Texels this device keeps in host memory for its texture reads (the CPU
  // device's copy; 0 on the GL device, whose texels are in the shared GpuBvh).
  virtual size_t hostTextureBytes() const { return 0; }
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_PATHTRACE_PATHTRACER_H

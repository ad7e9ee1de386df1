// Frame order for one render mode, and the targets the passes share:
//   raster:    raster (HDR radiance + depth) -> tonemap (sRGB 8-bit)
//   pathtrace: pathtrace (spp samples per pixel accumulated, the mean into the same
//              HDR target) -> tonemap; its BVH is built once, at construction.
// Output sizes are checked against the driver's limits and a memory budget
// before anything is allocated.
#ifndef VOXGI_RENDER_RENDERER_H
#define VOXGI_RENDER_RENDERER_H

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "gl/stage_timer.h"
#include "render/gpu_scene.h"
#include "render/pathtrace_pass.h"
#include "render/raster_pass.h"
#include "render/tonemap_pass.h"

namespace voxgi::render {

enum class Mode { kRaster, kPathtrace };
std::optional<Mode> parseMode(const std::string& name);
const char* modeName(Mode m);
// The modes this build has, comma separated (for --help and errors).
std::string availableModes();

struct RenderSettings {
  int width = 256;
  int height = 256;
  Mode mode = Mode::kRaster;
  TonemapPass::Settings tonemap;
  PathtracePass::Settings pathtrace;
  int spp = 64;  // pathtrace: samples per pixel of one frame
};

// Throws voxgi::Error when width x height cannot be rendered on this context.
void checkImageSize(int width, int height);

class Renderer {
 public:
  Renderer(gl::ProgramCache& programs, const scene::Scene& scene, const RenderSettings& settings);

  // Renders one frame and waits for it; stage times land in lastStages(). A
  // pathtrace frame is a whole image of `spp` samples per pixel, from sample 0.
  void renderFrame();
  const std::vector<gl::StageTime>& lastStages() const { return stages_; }
  // What the driver compiles at first use, without a whole frame's work.
  void warmUp();
  // Pathtrace: called while a frame runs with samples per pixel done and total.
  void setProgress(PathtracePass::Progress progress) { progress_ = std::move(progress); }
  // Work done once at construction, by stage name and wall-clock ms ("bvh").
  const std::vector<gl::StageTime>& startupStages() const { return startup_; }
  const PathtracePass* pathtrace() const { return pathtrace_.get(); }

  // Top-left origin, RGBA.
  std::vector<float> readLinear() const;
  std::vector<uint8_t> readDisplay() const;

  const RenderSettings& settings() const { return settings_; }
  const GpuScene& gpuScene() const { return gpuScene_; }

 private:
  gl::ProgramCache& programs_;
  const scene::Scene& scene_;
  RenderSettings settings_;
  GpuScene gpuScene_;
  RasterPass raster_;
  TonemapPass tonemap_;
  std::unique_ptr<PathtracePass> pathtrace_;
  PathtracePass::Progress progress_;
  std::vector<gl::StageTime> startup_;
  gl::StageTimer timer_;
  gl::Buffer frameUniforms_;
  gl::Texture hdr_, depth_, ldr_;
  gl::Framebuffer hdrFbo_, ldrFbo_;
  std::vector<gl::StageTime> stages_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RENDERER_H

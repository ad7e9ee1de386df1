// Frame order for one render mode, and the targets the passes share:
//   raster:  raster (HDR radiance + depth) -> tonemap (sRGB 8-bit)
//   points:  [voxelize -> voxel_list, once per scene or every frame with
//            revoxelize] -> points (HDR radiance + depth) -> tonemap
// Only the passes the mode uses are built (their shaders compiled, memory taken).
// Output sizes are checked against the driver's limits and a memory budget
// before anything is allocated.
#ifndef VOXGI_RENDER_RENDERER_H
#define VOXGI_RENDER_RENDERER_H

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "gl/stage_timer.h"
#include "render/gpu_scene.h"
#include "render/points_pass.h"
#include "render/raster_pass.h"
#include "render/tonemap_pass.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::render {

enum class Mode { kRaster, kPoints };
// Whether the mode reads the voxel grid.
bool modeUsesVoxels(Mode m);
std::optional<Mode> parseMode(const std::string& name);
const char* modeName(Mode m);
// The modes this build has, comma separated (for --help and errors).
std::string availableModes();

struct RenderSettings {
  int width = 256;
  int height = 256;
  Mode mode = Mode::kRaster;
  TonemapPass::Settings tonemap;
  int voxels = 128;         // grid resolution N (N^3 voxels) for modes that use voxels
  bool revoxelize = false;  // voxelize every frame (animated scenes) instead of once
};

// Throws voxgi::Error when width x height cannot be rendered on this context.
void checkImageSize(int width, int height);

class Renderer {
 public:
  Renderer(gl::ProgramCache& programs, const scene::Scene& scene, const RenderSettings& settings);

  // Renders one frame and waits for it; stage times land in lastStages().
  void renderFrame();
  const std::vector<gl::StageTime>& lastStages() const { return stages_; }

  // Top-left origin, RGBA.
  std::vector<float> readLinear() const;
  std::vector<uint8_t> readDisplay() const;

  const RenderSettings& settings() const { return settings_; }
  const GpuScene& gpuScene() const { return gpuScene_; }
  // Null unless the mode uses voxels.
  const voxel::VoxelizePass* voxelGrid() const { return voxelize_.get(); }
  // GPU ms of the most recent voxelization (0 if none ran).
  double lastVoxelizeMs() const { return lastVoxelizeMs_; }

 private:
  gl::ProgramCache& programs_;
  const scene::Scene& scene_;
  RenderSettings settings_;
  GpuScene gpuScene_;
  std::unique_ptr<RasterPass> raster_;
  std::unique_ptr<voxel::VoxelizePass> voxelize_;
  std::unique_ptr<PointsPass> points_;
  TonemapPass tonemap_;
  bool voxelized_ = false;
  double lastVoxelizeMs_ = 0.0;
  gl::StageTimer timer_;
  gl::Buffer frameUniforms_;
  gl::Texture hdr_, depth_, ldr_;
  gl::Framebuffer hdrFbo_, ldrFbo_;
  std::vector<gl::StageTime> stages_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_RENDERER_H

// The timed stages of a frame and of scene setup: what StageTimer measures, the
// stats JSON's `stages` and `startup_stages` list, the console table and the
// viewer's plots show. Code names a stage by the enum; its name (below) appears
// only where a stage is written out.
#ifndef VOXGI_CORE_STAGE_H
#define VOXGI_CORE_STAGE_H

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace voxgi {

enum class Stage {
  kVoxelize,  // voxel/voxelize_pass
  kOctree,    // voxel/octree: build
  kInject,    // voxel/octree: direct light into the leaves
  kRefine,    // voxel/octree: bounces between voxels
  kBvh,       // render: BVH build, once at start-up (CPU time)
  kGbuffer,   // render/rtgi_pass and the ones after it
  kSelect,
  kShadows,
  kDirect,
  kIndirect,
  kSpecular,
  kCaustics,
  kAccumulate,
  kReproject,
  kDenoise,
  kMask,
  kUpsample,   // render/rtgi_pass with a render scale below 1
  kRaster,     // render/raster_pass
  kPoints,     // render/points_pass
  kDvr,        // render/dvr_pass
  kPathtrace,  // render/pathtrace/pathtrace_pass, pathtrace_cpu
  kTonemap,    // render/tonemap_pass
  // Start-up only (wall clock, CPU side), before the first frame:
  kContext,  // app: the GL context made
  kUpload,   // gpu_scene: the scene's buffers and textures made on the GPU
  kPasses,   // render/renderer: the passes made, their programs compiled (bvh apart)
  kWarmUp,   // render/renderer: the warm-up frame (the scene stages and first-use JIT)
};

inline constexpr std::array<Stage, 26> kStages = {
    Stage::kVoxelize,  Stage::kOctree,   Stage::kInject,     Stage::kRefine,    Stage::kBvh,
    Stage::kGbuffer,   Stage::kSelect,   Stage::kShadows,    Stage::kDirect,    Stage::kIndirect,
    Stage::kSpecular,  Stage::kCaustics, Stage::kAccumulate, Stage::kReproject, Stage::kDenoise,
    Stage::kMask,      Stage::kUpsample, Stage::kRaster,     Stage::kPoints,    Stage::kDvr,
    Stage::kPathtrace, Stage::kTonemap,  Stage::kContext,    Stage::kUpload,    Stage::kPasses,
    Stage::kWarmUp};

// The stage's name in stats, tables and debug groups ("gbuffer" for kGbuffer).
inline const char* stageName(Stage s) {
  // Indexed by Stage.
  static constexpr std::array<const char*, kStages.size()> kNames = {
      "voxelize", "octree",  "inject",   "refine",   "bvh",      "gbuffer",    "select",
      "shadows",  "direct",  "indirect", "specular", "caustics", "accumulate", "reproject",
      "denoise",  "mask",    "upsample", "raster",   "points",   "dvr",        "pathtrace",
      "tonemap",  "context", "upload",   "passes",   "warmup"};
  return kNames[static_cast<std::size_t>(s)];
}

// The stage of that name; nullopt for any other string.
inline std::optional<Stage> parseStage(std::string_view name) {
  for (Stage s : kStages)
    if (name == stageName(s)) return s;
  return std::nullopt;
}

}  // namespace voxgi

#endif  // VOXGI_CORE_STAGE_H

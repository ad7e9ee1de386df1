// Voxelization: the scene's triangles into a dense N^3 grid of averaged surface
// attributes.
//
// Reads: the GpuScene (scene-space triangles, materials, base-colour textures).
// Writes: three 3D textures of N^3 texels over the cube Scene::scale (gridOrigin,
// gridSize): albedo + opacity (RGBA8, linear), unit normal (RGBA8_SNORM, zero where
// opposite normals cancel), emitted radiance (RGBA16F). Texel (i,j,k) covers
// gridOrigin + [i,i+1)x[j,j+1)x[k,k+1) * voxelSize.
//
// Method (Crassin & Green, OpenGL Insights ch. 22): one raster pass, each triangle
// projected along its dominant axis onto an N x N viewport of a framebuffer with no
// attachments and 4x MSAA (GL_FRAMEBUFFER_DEFAULT_SAMPLES); a fragment runs where
// any sample is covered and writes every voxel its plane crosses in the pixel
// column. Values are summed in fixed point (16 fractional bits, weighted by covered
// samples) with imageAtomicAdd on r32ui images: the grid is bit-identical whatever
// the triangle order; sums saturate, never wrap (see voxel_shared.h for the bound).
// The first fragment to reach a voxel appends it to a list; a compute pass over
// the list resolves the averages (zeroing the sums as it reads them) and checksums
// the grid, so after the first use nothing costs N^3: work follows the surface.
//
// Tested by tests/voxel/voxelize_gltest.cpp (exact counts, determinism, agreement
// with a CPU triangle-box reference, watertightness, scale invariance).
#ifndef VOXGI_VOXEL_VOXELIZE_PASS_H
#define VOXGI_VOXEL_VOXELIZE_PASS_H

#include <cstdint>
#include <vector>

#include "gl/frame_context.h"
#include "gl/handles.h"
#include "scene/effects.h"
#include "scene/gpu_scene.h"
#include "voxel_shared.h"

namespace voxgi::voxel {

constexpr int kMinResolution = 32;
constexpr int kMaxResolution = 512;

// Bytes the grid needs: while voxelizing (sums + resolved) and after (resolved).
struct VoxelMemory {
  uint64_t peakBytes = 0;
  uint64_t residentBytes = 0;
};
VoxelMemory voxelMemory(int resolution);

// Memory available for voxel data on the current context: the driver's report
// where there is one (NVX_gpu_memory_info), half of physical RAM on software
// rasterizers; VOXGI_VOXEL_BUDGET_MB overrides.
uint64_t voxelMemoryBudget(const std::string& renderer);

struct VoxelGridStats {
  int resolution = 0;
  uint32_t occupied = 0;
  uint64_t checksum = 0;
  uint64_t bytes = 0;      // resident (resolved grid)
  uint64_t peakBytes = 0;  // while voxelizing
};

class VoxelizePass {
 public:
  struct Settings {
    int resolution = 128;
    bool keepSums = false;  // keep the r32ui sums allocated between voxelizations
    // Tests: the resolve leaves the sums as they are (readSum() shows them) and each
    // voxelization clears all N^3 of them first instead.
    bool inspectSums = false;
    scene::ShaderFeatures features;  // effect-plan variant of voxelize.frag
  };

  // Throws voxgi::Error if the resolution is out of range or will not fit.
  VoxelizePass(gl::ProgramCache& programs, const std::string& renderer, const Settings& settings);

  // Clears, rasterizes every draw of `scene` and resolves. Stats are read back.
  void execute(gl::FrameContext& ctx, const scene::GpuScene& scene);

  const VoxelGridStats& stats() const { return stats_; }
  int resolution() const { return settings_.resolution; }
  GLuint albedo() const { return albedo_.id(); }
  GLuint normal() const { return normal_.id(); }
  GLuint emission() const { return emission_.id(); }
  GLuint params() const { return params_.id(); }
  // Packed coordinates (10 bits per axis) of the stats().occupied listed voxels.
  GLuint list() const { return list_.id(); }
  // World-space cube of the grid: origin and voxel size.
  glm::vec3 gridOrigin() const { return gridOrigin_; }
  float voxelSize() const { return voxelSize_; }

  // Resolved grid as bytes (tests): rgba8, rgba8 snorm, rgba16f per voxel, x fastest.
  std::vector<uint8_t> readAlbedo() const;
  std::vector<int8_t> readNormal() const;
  std::vector<uint16_t> readEmission() const;
  // One fixed-point sum channel (kSum*), x fastest; only with Settings::inspectSums.
  std::vector<uint32_t> readSum(uint32_t channel) const;

 private:
  void allocateSums();
  void allocateList(uint32_t capacity);
  void raster(const scene::GpuScene& gs);
  void dispatchOverList(const gl::Program& program, uint32_t count);

  Settings settings_;
  const gl::Program& voxelize_;
  const gl::Program& resolve_;
  std::vector<gl::Texture> sums_;
  gl::Texture albedo_, normal_, emission_;
  gl::Framebuffer fbo_;
  gl::Buffer params_, statsBuffer_, list_;
  const gl::Program& unresolve_;
  uint32_t capacity_ = 0;
  uint32_t listed_ = 0;  // voxels listed (and resolved) by the last voxelization
  glm::vec3 gridOrigin_{0.0f};
  float voxelSize_ = 1.0f;
  VoxelGridStats stats_;
};

}  // namespace voxgi::voxel

#endif  // VOXGI_VOXEL_VOXELIZE_PASS_H

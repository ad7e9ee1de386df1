// Voxelization: the scene's triangles into an N^3 grid of averaged surface
// attributes, stored sparsely.
//
// Reads: the GpuScene (scene-space triangles, materials, base-colour textures).
// Writes: the list of occupied voxels (packed coordinates) and, at the same index,
// each one's attributes (voxel_shared.h): albedo + opacity (RGBA8, linear), unit
// normal (RGBA8 snorm, zero where opposite normals cancel), emitted radiance (RGB
// half floats). Voxel (i,j,k) covers gridOrigin + [i,i+1)x[j,j+1)x[k,k+1) * voxelSize
// over the cube Scene::scale (gridOrigin, gridSize). Nothing is stored per empty
// voxel: the octree and the points view read the list.
//
// Method (Crassin & Green, OpenGL Insights ch. 22): one raster pass, each triangle
// projected along its dominant axis onto an N x N viewport of a framebuffer with no
// attachments and 4x MSAA (GL_FRAMEBUFFER_DEFAULT_SAMPLES); a fragment runs where
// any sample is covered and writes every voxel its plane crosses in the pixel
// column. Triangles whose projection spans at most 6 x 6 pixels take a compute path
// instead (Rauwendaal & Bailey, JCGT 2013) that tests the rasterizer's own samples
// and adds what a fragment would: see voxelize_small.comp. It passes the other
// triangles on, compacted per group of 64 triangles: each group of a draw has its
// own range of a second index buffer and one indirect draw command that counts the
// triangles appended there. The raster draws only those (glMultiDrawElementsIndirect
// over each draw's commands), in the same order every run, so no small triangle
// costs the raster's vertex and geometry stages.
// Values are summed in fixed point (16 fractional bits, weighted by covered samples)
// with atomicAdd: the grid is bit-identical whatever the triangle order; sums
// saturate, never wrap (see voxel_shared.h for the bound). The sums are sparse. A
// brick map (one entry per 4^3 voxels) gives each brick a fragment reaches a slot in
// a pool; the pool gives each voxel reached a slot of sums, one uvec4 per slot in
// each of three SSBOs (albedo+weight, normal, emission). Entries carry the
// voxelization's epoch, so nothing is cleared per run. A compute pass over the slots
// resolves the averages (zeroing the sums as it reads them), lists the voxels with
// their attributes, and checksums the grid. After the first use nothing costs N^3:
// work follows the surface.
//
// Tested by tests/voxel/voxelize_gltest.cpp (exact counts, determinism, agreement
// with a CPU triangle-box reference, watertightness, scale invariance).
#ifndef VOXGI_VOXEL_VOXELIZE_PASS_H
#define VOXGI_VOXEL_VOXELIZE_PASS_H

#include <cstdint>
#include <vector>

#include "gl/frame_context.h"
#include "gl/handles.h"
#include "gpu_scene/gpu_scene.h"
#include "scene/effects.h"
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

// The voxel list's first size for scene `s` on an n^3 grid of voxels `voxelSize`
// wide: what its surfaces can occupy, with room to spare (see the .cpp), at most
// initialListCapacity(n). Too few and voxelization takes another round with room for
// what it found.
uint32_t listEntriesFor(const scene::Scene& s, int n, float voxelSize);

// Memory available for voxel data on the current context: the driver's report
// where there is one (NVX_gpu_memory_info), half of physical RAM on software
// rasterizers; `overrideBytes` > 0 overrides (app: VOXGI_VOXEL_BUDGET_MB).
uint64_t voxelMemoryBudget(const std::string& renderer, uint64_t overrideBytes = 0);

struct VoxelGridStats {
  int resolution = 0;
  uint32_t occupied = 0;
  uint64_t checksum = 0;
  uint64_t bytes = 0;            // resident (resolved grid)
  uint64_t peakBytes = 0;        // while voxelizing
  uint32_t smallTriangles = 0;   // taken by the compute path; counted with inspectSums only
  uint32_t rasterTriangles = 0;  // passed on to the raster; counted with inspectSums only
  uint32_t deferred = 0;         // fragments deferred in the last raster (voxel_shared.h)
  int rounds = 0;                // rasters it took: more than 1 when something had to grow
};

class VoxelizePass {
 public:
  struct Settings {
    int resolution = 128;
    bool keepSums = false;  // keep the brick map, pool and sums between voxelizations
    // Tests: the resolve leaves the sums as they are (readSum() shows them) and each
    // voxelization clears all of them first instead.
    bool inspectSums = false;
    scene::ShaderFeatures features;  // effect-plan variant of voxelize.frag
    // Triangles whose projection spans at most kSmallTriangleSpan pixels per axis go to
    // the compute path; false rasterizes every triangle (for comparison).
    bool smallTrianglesInCompute = true;
    // The order-independent checksum of the resolved grid (stats().checksum; 0 when
    // off): a hash per voxel and two atomics on one shared counter pair.
    bool checksum = true;
    // The memory the grid may take, in bytes; 0: voxelMemoryBudget's estimate.
    uint64_t memoryBudgetBytes = 0;
    // Tests: how many times a fragment reads a voxel another thread is claiming
    // before it is deferred (-1: gpu::kClaimSpins; 0 defers every one that meets a
    // claim in progress).
    int claimSpins = -1;
    // Tests: every fragment is deferred (the deferred pass adds them all).
    bool deferAll = false;
    // Tests: the pool's first size in bricks (0: what the grid may need, up to 2^16).
    uint32_t initialBricks = 0;
    // Tests: the voxel list's first size in entries, its slots' too (0: estimated from
    // the scene's surface area, listEntriesFor).
    uint32_t initialListEntries = 0;
  };

  // Throws voxgi::Error if the resolution is out of range or will not fit.
  VoxelizePass(gl::ProgramCache& programs, const std::string& renderer, const Settings& settings);

  // Clears, rasterizes every draw of `scene` and resolves. Stats are read back.
  void execute(gl::FrameContext& ctx, const scene::GpuScene& scene);

  const VoxelGridStats& stats() const { return stats_; }
  int resolution() const { return settings_.resolution; }
  GLuint params() const { return paramsBuffer_.id(); }
  // Packed coordinates (10 bits per axis) of the stats().occupied listed voxels.
  GLuint list() const { return list_.id(); }
  // Their attributes, one uvec4 each at the same index (see voxel_shared.h).
  GLuint attributes() const { return attributes_.id(); }
  // World-space cube of the grid: origin and voxel size.
  glm::vec3 gridOrigin() const { return gridOrigin_; }
  float voxelSize() const { return voxelSize_; }

  // Resolved grid as dense N^3 arrays (tests), gathered from the list: rgba8, rgba8
  // snorm, rgba16f per voxel, x fastest, zero where empty.
  std::vector<uint8_t> readAlbedo() const;
  std::vector<int8_t> readNormal() const;
  std::vector<uint16_t> readEmission() const;
  // One fixed-point sum channel (kSum*) as a dense N^3 array, x fastest (zero where
  // no fragment reached), gathered from the sparse sums; only with inspectSums.
  std::vector<uint32_t> readSum(uint32_t channel) const;

 private:
  void allocateSums();
  void allocateSlots();
  void allocateBricks();
  void allocateLists();
  void allocateDeferred();
  template <typename T>
  std::vector<T> readResolved(uint32_t component) const;
  static void clear(const gl::Buffer& buffer);
  void clearSums();
  void nextEpoch();
  void raster(const scene::GpuScene& gs);
  void rasterSmall(const scene::GpuScene& gs);  // the compute path
  void bindSlots();
  void dispatch(const gl::Program& program, uint64_t invocations);
  // The steps of execute(): rasters, growing the slots, bricks or deferred records
  // and rastering again until every voxel fits; returns the last raster's counters.
  gpu::VoxelStats rasterUntilItFits(const scene::GpuScene& gs);
  // One raster, then the fragments it deferred when everything fit; its counters.
  gpu::VoxelStats rasterOnce(const scene::GpuScene& gs);
  gpu::VoxelStats readCounters() const;
  // stats_ but bytes, from the resolve's counters.
  void recordStats(const gpu::VoxelStats& out);
  // Frees all but the list and its attributes, trimmed to the voxels listed.
  void keepListOnly();

  Settings settings_;
  const gl::Program& voxelize_;
  const gl::Program& voxelizeSmall_;  // the compute path for small triangles
  const gl::Program& resolve_;
  const gl::Program& addDeferred_;  // voxelize_deferred.comp
  // While voxelizing (kept with keepSums): brick map, brick pool, per-slot sums.
  gl::Buffer brickMap_, pool_, sumsA_, sumsN_, sumsE_;
  // The compute path's output for the raster: the triangles it passed on, and one
  // indirect draw command per group of 64 triangles of each draw.
  gl::Buffer largeIndices_, drawCommands_;
  std::vector<uint32_t> firstCommand_;  // per draw of the scene
  size_t largeIndexBytes_ = 0;
  GLsizeiptr drawCommandBytes_ = 0;
  gl::Framebuffer fbo_;
  gl::Buffer paramsBuffer_, statsBuffer_, list_, attributes_;
  gl::Buffer deferred_;  // VoxelDeferred records
  uint32_t deferredCapacity_ = gpu::kInitialDeferred;
  gpu::VoxelParams params_{};
  uint32_t epoch_ = 0;
  uint32_t capacity_ = 0;       // slots, and entries of list_
  bool sized_ = false;          // capacity_ set for the scene (the first execute)
  uint32_t brickCapacity_ = 0;  // pool bricks
  uint32_t listed_ = 0;         // voxels listed (and resolved) by the last voxelization
  glm::vec3 gridOrigin_{0.0f};
  float voxelSize_ = 1.0f;
  VoxelGridStats stats_;
};

}  // namespace voxgi::voxel

#endif  // VOXGI_VOXEL_VOXELIZE_PASS_H

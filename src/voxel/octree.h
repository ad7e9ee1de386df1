// Sparse voxel octree over the voxelized grid, built on the GPU, lit, and filtered
// for cone tracing (layout: shaders/include/octree_shared.h).
//
// Reads: a VoxelizePass (its list of occupied voxels and resolved textures) and the
// GpuScene (lights, emitters). Writes: the node buffer and per-node radiance,
// material and emission buffers that dvr and rtgi trace.
//
// Build, level by level (Crassin & Green, OpenGL Insights ch. 22): for each level
// from the root down, every listed voxel walks to its node at that level and the
// first to reach a node without children allocates a tile of 8 with an atomic
// counter (a compare-and-swap elects it); a last pass over the list marks the leaves
// and copies the voxel's attributes into them. Nothing costs N^3: work follows the
// surface. The first build sizes the node buffer for the worst case, then keeps it
// at the size used plus headroom; an overflowing re-build grows it and runs again.
//
// Light (stage "inject"): every leaf gathers direct light with shadow rays marched
// through the octree, or traced on the exact triangles where rtgi has a BVH
// (Settings::bvhDefines, bounce rays too) (punctual lights; emissive surfaces by their exact
// unshadowed irradiance times the visible fraction of sample points, emitters chosen by power),
// then `bounces - 1` passes each gather one more bounce of diffuse light from the
// leaves the rays hit (ping-pong buffers: the result does not depend on thread
// order). Last, inner nodes are filtered bottom-up.
//
// Refinement (stage "refine", once per frame while the scene is still): a voxel's
// light is a running mean of estimates, as a pixel's is. Each refinement makes one
// more estimate with fresh random numbers (refineRays rays per leaf) for a slice of
// the leaves (one in S by a hash of the voxel, S = leaves / refineLeaves rounded up,
// so a frame's share of this work is bounded whatever the grid) and blends it in
// (weights growing with the rays so far, see refine()), so the voxels' noise falls
// as 1/sqrt(frames) instead of being baked into every frame. With all bounces (the
// default) the estimate gathers its bounce from the running mean itself: each
// refinement adds a bounce, and the mean converges to the solution of the rendering
// equation between the voxels (the fixed point L = Le + albedo x mean incoming L),
// at one bounce pass per frame. The first estimate is a chain of 6 bounces, so
// refinement starts near that answer. A finite --bounces N >= 2 keeps its first
// estimate, the N-bounce chain: a chain's bounce needs the previous bounce of every
// leaf from the same estimate, which a slice does not have (--bounces 1, direct
// light only, refines).
//
// Tested by tests/voxel/octree_gltest.cpp (traversal against a dense DDA, memory,
// leaves equal the grid, filtering, light).
#ifndef VOXGI_VOXEL_OCTREE_H
#define VOXGI_VOXEL_OCTREE_H

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gl/frame_context.h"
#include "gl/handles.h"
#include "gpu_scene/gpu_scene.h"
#include "octree_shared.h"
#include "scene/effects.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::voxel {

struct OctreeStats {
  int depth = 0;
  uint32_t nodes = 0;                // allocated, root included
  uint32_t twoSidedLeaves = 0;       // leaves whose normals cancel, with two light slots
  uint32_t leaves = 0;               // occupied leaves (= occupied voxels)
  uint64_t bytes = 0;                // resident: nodes and per-node data at the buffers' capacity
  uint64_t refineBytes = 0;          // resident beside them: the light's refinement buffers
  uint64_t denseBytes = 0;           // the resolved dense grid the octree replaces for tracing
  uint64_t buildBytes = 0;           // peak while building (worst-case node buffer)
  std::vector<uint32_t> levelNodes;  // nodes per level, root first
};

class Octree {
 public:
  struct Settings {
    // Every bounce: the voxel light feeds back into itself as it refines.
    static constexpr int kAllBounces = 1 << 20;
    int bounces = kAllBounces;  // total diffuse bounces; the voxels hold bounces - 1 of them
    // The first estimate's rays: few, since refinement averages their noise away
    // (docs/octree.md: 4 rays instead of 16 start 3-4x sooner for a FLIP within 0.002).
    int injectRays = 4;       // shadow rays per leaf towards emissive surfaces
    int bounceRays = 4;       // rays per leaf per voxel bounce (all bounces: the first's,
                              // read again by the later ones)
    int refineRays = 1;       // per leaf and refinement, direct and bounce (0: no refinement)
    int refineLeaves = 4096;  // leaves refined per frame at most: the rest wait their turn
    // Keep the voxel bounces apart from the direct light (bounceMean_, 16 bytes a
    // node): rtgi's indirect rays on the triangles light their hit exactly and read
    // only them.
    bool keepBounces = false;
    uint32_t seed = 1;
    scene::ShaderFeatures features;  // effect-plan variant of octree_inject.comp
    // The defines of a BVH of the scene's triangles (rtgi_bvh.glsl) that the caller
    // binds before inject() and refine(): the leaves' shadow and bounce rays run on
    // the exact triangles (a bounce ray reads the leaf that stands for its hit).
    // Empty: they march the octree, whose voxels widen every shadow and stop rays
    // up to a voxel early.
    std::vector<std::string> bvhDefines;
  };

  Octree(gl::ProgramCache& programs, const Settings& settings);

  // Builds the node structure from the grid's occupied voxels (stage "octree").
  void build(gl::FrameContext& ctx, const VoxelizePass& grid);
  // Direct light, voxel bounces and filtering (stage "inject"): the first estimate.
  void inject(gl::FrameContext& ctx, const scene::GpuScene& scene);
  // One more estimate blended into the voxels' light (stage "refine"); nothing with
  // refineRays 0, or with a finite chain of voxel bounces (bounces >= 2), which
  // keeps its first estimate.
  bool refines() const;
  void refine(gl::FrameContext& ctx, const scene::GpuScene& scene);
  // Estimates blended into every leaf since inject(), the first included (a slice
  // refined ahead of the others does not count until all have caught up).
  int estimates() const { return 1 + refinements_ / std::max(slices_, 1); }
  // Refinement slices: a leaf is refined every slices() frames.
  int slices() const { return slices_; }
  bool allBounces() const { return settings_.bounces >= Settings::kAllBounces; }

  const OctreeStats& stats() const { return stats_; }
  const Settings& settings() const { return settings_; }
  int depth() const { return stats_.depth; }
  GLuint params() const { return params_.id(); }
  GLuint nodes() const { return nodes_.id(); }
  GLuint radiance() const { return radiance_.id(); }
  GLuint material() const { return material_.id(); }
  GLuint emission() const { return emission_.id(); }
  // Binds params and the node/data buffers at their octree_shared.h bindings.
  void bind() const;
  // NaN or Inf radiance the octree's passes met and replaced since it was made
  // (nonfinite.glsl); reads back from the GPU.
  uint32_t nonfiniteTerms() const;

  // The first occupied voxel along each ray (xyz; w = 1 on a hit, 0 on a miss),
  // traced by the GLSL traversal (tests, benchmarks).
  std::vector<glm::ivec4> raycast(const std::vector<gpu::OctreeRay>& rays);

  // Tests.
  std::vector<uint32_t> readNodes() const;
  // rgb9e5 per node; slot 1: the - side of two-sided leaves (octree.glsl, leafAxis),
  // 0 for the other nodes.
  std::vector<uint32_t> readRadiance(int slot = 0) const;
  std::vector<glm::vec4> readMean() const;     // the float running mean per node
  std::vector<uint32_t> readMaterial() const;  // two words per node (rgba8, snorm8x4)

 private:
  void allocate(uint32_t capacity);
  void allocateLight(uint32_t backSlots);
  bool buildInto(gl::FrameContext& ctx, const VoxelizePass& grid, uint32_t listed);
  void setPass(uint32_t level, uint32_t first, uint32_t count, uint32_t bounce = 0);
  void dispatch(const gl::Program& p, uint32_t count);
  // The voxels the next passes read: refinement slice `slice`, or (-1) every listed
  // voxel; returns how many.
  uint32_t setSlice(int slice);
  void makeSlices();
  // One estimate of the slice's radiance into estimate_: direct light with `rays`,
  // then the voxel bounces (`feedback`: one, gathered from the running mean).
  // True when it has voxel bounces beside the direct light (in direct_).
  bool estimate(const scene::GpuScene& scene, uint32_t count, int rays, int bounceRays,
                bool feedback);
  // Blends the slice's estimate into the running mean with `weight` and publishes it,
  // and its bounces alone (`bounced`: the estimate less direct_; else none) into
  // bounceMean_.
  void blend(uint32_t count, float weight, bool bounced);
  void filter(const gl::Program& program);

  Settings settings_;
  gl::ProgramCache& programs_;
  const gl::Program& buildLevel_;
  const gl::Program& fill_;
  const gl::Program& filter_;
  const gl::Program& inject_;
  const gl::Program& bounce_;
  const gl::Program& average_;
  const gl::Program& filterRadiance_;
  gl::Buffer params_, counters_, nodes_, radiance_, material_, emission_;
  gl::Buffer bounceMean_;  // vec4: the running mean of the radiance less its direct light
  gl::Buffer nonfinite_;   // uint: values replaced (kNonfiniteCountBinding)
  // Refinement: this estimate, its direct light, the previous bounce, the mean.
  gl::Buffer estimate_, direct_, previous_, mean_;
  gl::Buffer surface_;    // with the BVH: the triangle under each side (kOctreeSurfaceBinding)
  gl::Buffer sliceList_;  // the voxel codes slice by slice
  std::vector<uint32_t> sliceStart_;  // first code of each slice; the last = leaves
  GLuint passList_ = 0;               // the list the next passes read
  int refinements_ = 0;               // refine() calls since inject()
  int slices_ = 1;
  double raysSoFar_ = 0.0;    // per leaf, over the estimates blended in
  double weightSoFar_ = 0.0;  // of those estimates in the running mean
  float cycleWeight_ = 1.0f;  // this cycle's blend weight, the same for every slice
  uint32_t seed_ = 0;         // this estimate's
  gl::Texture nodeTexture_;   // nodes_ as a buffer texture (r32ui)
  uint32_t capacity_ = 0;
  uint32_t lightSlots_ = 0;  // capacity_ + one a leaf (allocateLight)
  GLuint listBuffer_ = 0;    // the grid's voxel list, read again by inject()
  gpu::OctreeParams paramsData_{};
  OctreeStats stats_;
  std::vector<uint32_t> levelStart_;
};

}  // namespace voxgi::voxel

#endif  // VOXGI_VOXEL_OCTREE_H

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
// through the octree (punctual lights; emissive surfaces by their exact unshadowed
// irradiance times the visible fraction of sample points, emitters chosen by power),
// then `bounces - 1` passes each gather one more bounce of diffuse light from the
// leaves the rays hit (ping-pong buffers: the result does not depend on thread
// order). Last, inner nodes are filtered bottom-up.
//
// Tested by tests/voxel/octree_gltest.cpp (traversal against a dense DDA, memory,
// leaves equal the grid, filtering, light).
#ifndef VOXGI_VOXEL_OCTREE_H
#define VOXGI_VOXEL_OCTREE_H

#include <array>
#include <cstdint>
#include <vector>

#include "gl/frame_context.h"
#include "gl/handles.h"
#include "octree_shared.h"
#include "scene/effects.h"
#include "scene/gpu_scene.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::voxel {

struct OctreeStats {
  int depth = 0;
  uint32_t nodes = 0;                // allocated, root included
  uint32_t leaves = 0;               // occupied leaves (= occupied voxels)
  uint64_t bytes = 0;                // resident: nodes and per-node data at the buffers' capacity
  uint64_t denseBytes = 0;           // the resolved dense grid the octree replaces for tracing
  uint64_t buildBytes = 0;           // peak while building (worst-case node buffer)
  std::vector<uint32_t> levelNodes;  // nodes per level, root first
};

class Octree {
 public:
  struct Settings {
    int bounces = 2;      // total diffuse bounces; the voxels hold bounces - 1 of them
    int injectRays = 16;  // shadow rays per leaf towards emissive surfaces
    int bounceRays = 16;  // rays per leaf per voxel bounce
    uint32_t seed = 1;
    scene::ShaderFeatures features;  // effect-plan variant of octree_inject.comp
  };

  Octree(gl::ProgramCache& programs, const Settings& settings);

  // Builds the node structure from the grid's occupied voxels (stage "octree").
  void build(gl::FrameContext& ctx, const VoxelizePass& grid);
  // Direct light, voxel bounces and filtering (stage "inject").
  void inject(gl::FrameContext& ctx, const scene::GpuScene& scene);

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

  // The first occupied voxel along each ray (xyz; w = 1 on a hit, 0 on a miss),
  // traced by the GLSL traversal (tests, benchmarks).
  std::vector<glm::ivec4> raycast(const std::vector<gpu::OctreeRay>& rays);

  // Tests.
  std::vector<uint32_t> readNodes() const;
  std::vector<uint32_t> readRadiance() const;  // rgb9e5 per node
  std::vector<uint32_t> readMaterial() const;  // two words per node (rgba8, snorm8x4)

 private:
  void allocate(uint32_t capacity);
  bool buildInto(gl::FrameContext& ctx, const VoxelizePass& grid, uint32_t listed);
  void setPass(uint32_t level, uint32_t first, uint32_t count, uint32_t bounce = 0);
  void dispatch(const gl::Program& p, uint32_t count);

  Settings settings_;
  gl::ProgramCache& programs_;
  const gl::Program& buildLevel_;
  const gl::Program& fill_;
  const gl::Program& filter_;
  const gl::Program& inject_;
  const gl::Program& bounce_;
  gl::Buffer params_, counters_, nodes_, radiance_, material_, emission_;
  gl::Texture nodeTexture_;  // nodes_ as a buffer texture (r32ui)
  uint32_t capacity_ = 0;
  GLuint listBuffer_ = 0;  // the grid's voxel list, read again by inject()
  gpu::OctreeParams paramsData_{};
  OctreeStats stats_;
  std::vector<uint32_t> levelStart_;
};

}  // namespace voxgi::voxel

#endif  // VOXGI_VOXEL_OCTREE_H

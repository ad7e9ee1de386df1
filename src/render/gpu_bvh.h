// The scene's exact triangles on the GPU for ray tracing: the BVH (render/bvh.h)
// built on the CPU, and what a hit needs to be shaded beyond the scene's own vertex
// and index buffers (GpuScene), which the triangles point into: the material and
// emitter pdf in each triangle's record, and every texture's texels when textured,
// in the layouts of shaders/include/pathtrace_shared.h. Traversed by
// shaders/include/bvh_trace.glsl.
//
// Used by the path tracer (PathtracePass), by rtgi's rays (RtgiPass) and by the
// octree's exact rays: the Renderer builds one and they all read it.
//
// Costs at start-up: the binned SAH build (buildMs(); cornell_room's 3.5k triangles
// take a few ms) and 64 + 48 bytes per triangle of GPU memory (nodes, triangles),
// plus the texels when textured. Normals, texture coordinates, vertex colours and
// tangents are read at a hit from the scene's buffers, through its index buffer: a
// hit costs a few reads more, and the BVH no copy of them (80 bytes a triangle of a
// textured scene, 176 with colours and normal maps).
#ifndef VOXGI_RENDER_GPU_BVH_H
#define VOXGI_RENDER_GPU_BVH_H

#include <cstddef>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gpu_scene/gpu_scene.h"
#include "render/bvh.h"
#include "scene/effects.h"
#include "scene/scene.h"

namespace voxgi::render {

struct PtScene;

class GpuBvh {
 public:
  // `textures`: whether base-colour textures may be read (the effect plan's); the
  // BVH is textured() when so and some drawn material has a texture.
  // Built from gs's scene (its meshes at their current pose); gs must outlive it.
  GpuBvh(const scene::GpuScene& gs, bool textures);

  // The BVH's shape (render::Bvh's; no CPU copy of its arrays is kept).
  size_t triangleCount() const { return triangleCount_; }
  size_t nodeCount() const { return nodeCount_; }
  int depth() const { return depth_; }
  double sahCost() const { return sah_; }
  double buildMs() const { return buildMs_; }
  // The binned SAH build of the tree alone (buildMs() also counts the path tracer's
  // per-triangle arrays it is built from, and the checks of its nodes).
  double treeMs() const { return treeMs_; }
  bool textured() const { return textured_; }
  // The scene has vertex colours: colors() is its colour buffer (vec4 per vertex);
  // 0 otherwise.
  bool colored() const { return colors_ != 0; }
  GLuint colors() const { return colors_; }
  // The scene has normal maps: tangents() is its tangent buffer (vec4 per vertex, xyz
  // and handedness); 0 otherwise.
  bool hasTangents() const { return tangents_ != 0; }
  GLuint tangents() const { return tangents_; }
  int emissiveTriangles() const { return emissiveCount_; }
  size_t gpuBytes() const { return gpuBytes_; }
  // Of gpuBytes(): the textures' texels and their table (0 unless textured()).
  size_t textureBytes() const { return textureBytes_; }

  // Node and triangle texels (RGBA32UI buffer textures), the scene's vertices as
  // RG32F texels (five a vertex) and its index buffer, the emissive triangles
  // (GpuPtEmissive, alias table), and when textured the texel texels and the table
  // of textures (uvec4 per texture).
  GLuint nodeTexels() const { return nodeTexels_.id(); }
  GLuint triangleTexels() const { return triangleTexels_.id(); }
  GLuint vertexTexels() const { return vertexTexels_.id(); }
  GLuint indices() const { return indices_; }
  GLuint emissive() const { return emissive_.id(); }
  GLuint textureTexels() const { return textureTexels_.id(); }
  GLuint textureTable() const { return textureTable_.id(); }

  // Binds what a stage that traces the BVH reads (rtgi_bvh.glsl's bindings): the
  // scene's `materials`, the nodes and triangles, the scene's vertices and indices,
  // the textures when textured(), the vertex colours and tangents when asked for
  // and present.
  // unbind() releases the texture units.
  void bind(GLuint materials, bool colors, bool normalMaps) const;
  static void unbind();
  // The defines of a stage that traces it through rtgi_bvh.glsl, in `scene` (the one
  // it was built from) with the effect plan's `features`: RTGI_BVH, and
  // RTGI_BVH_TEXTURES, _COLORS, _TANGENTS and _ALPHA for what it holds and the
  // plan reads. bind() with the same colours and normal maps serves them.
  std::vector<std::string> traceDefines(const scene::Scene& scene,
                                        const scene::ShaderFeatures& features) const;

 private:
  // A buffer of `bytes` (counted in gpuBytes_).
  gl::Buffer upload(const void* data, size_t bytes);
  // A buffer of `count` T that fill(T*) writes in place through a mapping, so that
  // no CPU copy of it is ever made (counted in gpuBytes_).
  template <typename T, typename Fill>
  gl::Buffer uploadFilled(size_t count, Fill fill);
  // `buffer` as RGBA32UI texels; throws beyond this GL's buffer texture limit.
  gl::Texture bufferTexels(const gl::Buffer& buffer, size_t bytes, GLint maxTexels) const;
  // Every texture's texels and the table of where each starts.
  void uploadTextures(const scene::Scene& s, GLint maxTexels);

  size_t triangleCount_ = 0, nodeCount_ = 0;
  int depth_ = 0;
  double sah_ = 0.0;
  double buildMs_ = 0.0;
  double treeMs_ = 0.0;
  bool textured_ = false;
  int emissiveCount_ = 0;
  size_t gpuBytes_ = 0, textureBytes_ = 0;
  gl::Buffer nodes_, triangles_, emissive_;
  gl::Texture nodeTexels_, triangleTexels_;         // nodes_ and triangles_ as RGBA32UI texels
  gl::Texture vertexTexels_;                        // the scene's vertex buffer as RG32F texels
  GLuint indices_ = 0, colors_ = 0, tangents_ = 0;  // the scene's buffers (not owned)
  gl::Buffer texels_, textureTable_;
  gl::Texture textureTexels_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_GPU_BVH_H

// The scene's exact triangles on the GPU for ray tracing: the BVH (render/bvh.h)
// built on the CPU, and what a hit needs to be shaded (vertex normals, material,
// emitter pdf; corner UVs and every texture's texels when textured), in
// the layouts of shaders/include/pathtrace_shared.h. Traversed by
// shaders/include/bvh_trace.glsl.
//
// Used by the path tracer (PathtracePass) and by rtgi's reflections (RtgiPass, when
// the effect plan has the specular effect): the Renderer builds one and both passes
// read it. A scene without mirrors or glossy surfaces, rendered by rtgi, builds none.
//
// Costs at start-up: the binned SAH build (buildMs(); cornell_room's 3.5k triangles
// take a few ms) and 64 + 48 + 48 bytes per triangle of GPU memory (nodes, triangles,
// shading), plus 32 bytes per triangle and the texels when textured, and 48 bytes per
// triangle when the scene has vertex colours, 48 more when it has normal maps.
#ifndef VOXGI_RENDER_GPU_BVH_H
#define VOXGI_RENDER_GPU_BVH_H

#include <cstddef>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "render/bvh.h"
#include "scene/effects.h"
#include "scene/scene.h"

namespace voxgi::render {

struct PtScene;

class GpuBvh {
 public:
  // `textures`: whether base-colour textures may be read (the effect plan's); the
  // BVH is textured() when so and some drawn material has a texture.
  GpuBvh(const scene::Scene& scene, bool textures);

  // The BVH's shape (render::Bvh's; no CPU copy of its arrays is kept).
  size_t triangleCount() const { return triangleCount_; }
  size_t nodeCount() const { return nodeCount_; }
  int depth() const { return depth_; }
  double sahCost() const { return sah_; }
  double buildMs() const { return buildMs_; }
  bool textured() const { return textured_; }
  // The scene has vertex colours: colors() holds them (vec4 per triangle corner,
  // three a triangle, BVH order; 48 bytes a triangle); 0 otherwise.
  bool colored() const { return colors_.id() != 0; }
  GLuint colors() const { return colors_.id(); }
  // The scene has normal maps: tangents() holds the tangents (vec4 per triangle
  // corner, xyz and handedness, three a triangle, BVH order); 0 otherwise.
  bool tangentsUploaded() const { return tangents_.id() != 0; }
  GLuint tangents() const { return tangents_.id(); }
  int emissiveTriangles() const { return emissiveCount_; }
  size_t gpuBytes() const { return gpuBytes_; }
  // Of gpuBytes(): the textures' texels and their table (0 unless textured()).
  size_t textureBytes() const { return textureBytes_; }

  // Node and triangle texels (RGBA32UI buffer textures), the shading SSBO (one
  // GpuPtShading per triangle, BVH order), the emissive triangles (GpuPtEmissive,
  // alias table), and when textured the UV texels, the texel texels and the table
  // of textures (uvec4 per texture).
  GLuint nodeTexels() const { return nodeTexels_.id(); }
  GLuint triangleTexels() const { return triangleTexels_.id(); }
  GLuint shading() const { return shading_.id(); }
  GLuint emissive() const { return emissive_.id(); }
  GLuint uvTexels() const { return uvTexels_.id(); }
  GLuint textureTexels() const { return textureTexels_.id(); }
  GLuint textureTable() const { return textureTable_.id(); }

  // Binds what a stage that traces the BVH reads (rtgi_bvh.glsl's bindings): the
  // scene's `materials`, the nodes, triangles and shading, the textures when
  // textured(), the vertex colours and tangents when asked for and present.
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
  // Corner UVs, every texture's texels and the table of where each starts.
  void uploadTextures(const scene::Scene& s, const PtScene& pt, const std::vector<uint32_t>& order,
                      GLint maxTexels);

  size_t triangleCount_ = 0, nodeCount_ = 0;
  int depth_ = 0;
  double sah_ = 0.0;
  double buildMs_ = 0.0;
  bool textured_ = false;
  int emissiveCount_ = 0;
  size_t gpuBytes_ = 0, textureBytes_ = 0;
  gl::Buffer nodes_, triangles_, shading_, emissive_;
  gl::Texture nodeTexels_, triangleTexels_;  // nodes_ and triangles_ as RGBA32UI texels
  gl::Buffer uvs_, texels_, textureTable_, colors_, tangents_;
  gl::Texture uvTexels_, textureTexels_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_GPU_BVH_H

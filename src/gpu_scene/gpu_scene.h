// The scene uploaded once: vertex/index buffers and a vertex array, material,
// light and emitter SSBOs, textures (mipmapped; sRGB for colour, linear for data),
// each with a GL sampler of its glTF sampler's wrap modes and filters.
#ifndef VOXGI_GPU_SCENE_GPU_SCENE_H
#define VOXGI_GPU_SCENE_GPU_SCENE_H

#include <vector>

#include "gl/handles.h"
#include "scene/emitters.h"
#include "scene/scene.h"
#include "scene_shared.h"

namespace voxgi::scene {

class GpuScene {
 public:
  explicit GpuScene(const Scene& scene);

  const Scene& scene() const { return scene_; }
  // Re-uploads the animated vertices (and emitters) after Scene::pose().
  void updateGeometry();
  // Animated meshes: after a frame that drew no new pose, the previous positions
  // (vertex attribute 3, for motion vectors) become the current ones again.
  void settleGeometry();
  // Re-uploads the lights after Scene::pose() moved some (a no-op when none moves).
  void updateLights();
  GLuint vertexArray() const { return vao_.id(); }
  // The vertex array's buffers: scene::Vertex per vertex, uint32 indices.
  GLuint vertexBuffer() const { return vertices_.id(); }
  GLuint indexBuffer() const { return indices_.id(); }
  // COLOR_0 as RGBA floats per vertex (std430 vec4[]), 0 when the scene has none;
  // on attribute gpu::kColorAttribute of the vertex array.
  GLuint colorBuffer() const { return colors_.id(); }
  // Where the scene has no colour stream, sets the constant value the vertex array
  // gives gpu::kColorAttribute to white (context state, so set before each draw).
  void setDefaultColor() const;
  // Tangents (vec4 per vertex, xyz and handedness), 0 without normal maps; on
  // attribute gpu::kTangentAttribute.
  GLuint tangentBuffer() const { return tangents_.id(); }
  GLuint materials() const { return materials_.id(); }
  GLuint lights() const { return lights_.id(); }
  GLuint emitters() const { return emitters_.id(); }
  // Emitters chosen for light sampling by power: cumulative distribution, one
  // float per emitter, the last 1 (std430 float[]; empty scene: one 0).
  GLuint emitterCdf() const { return emitterCdf_.id(); }
  // The light tree over the emitters (scene::buildLightTree, light_tree_shared.h);
  // one node of no power when there are none.
  GLuint lightTree() const { return lightTree_.id(); }
  const std::vector<gpu::GpuEmitter>& emitterData() const { return emitterData_; }
  int lightCount() const { return lightCount_; }
  int emitterCount() const { return emitterCount_; }
  // 0 when the material has no texture.
  GLuint texture(int index) const {
    return index >= 0 ? textures_[static_cast<size_t>(index)].id() : 0;
  }
  // Texture `index`'s sampler (the file's wrap modes and filters); the default
  // sampler (repeat, trilinear) for -1.
  GLuint sampler(int index = -1) const {
    return index >= 0 ? samplers_[static_cast<size_t>(index)].id() : sampler_.id();
  }
  // The default sampler on every material texture unit (kBaseColorUnit,
  // kEmissiveUnit, kMetallicRoughnessUnit, and kNormalUnit and kOcclusionUnit where
  // some material has such a texture); m's textures on them with their own samplers
  // (0 and the default where it has none); both undone.
  void bindSampler() const;
  void bindMaterialTextures(const Material& m) const;
  static void unbindMaterialTextures();
  size_t bytes() const { return bytes_; }
  // Wall-clock ms the constructor took (Stage::kUpload).
  double uploadMs() const { return uploadMs_; }
  // Of bytes(): the textures, every mip level (RGBA8 or sRGB8_ALPHA8, 4 bytes a texel).
  size_t textureBytes() const { return textureBytes_; }

  static std::vector<gpu::GpuMaterial> packMaterials(const Scene& s);
  static std::vector<gpu::GpuLight> packLights(const Scene& s);

 private:
  // The constructor's steps, each returning the bytes it uploaded (createTextures:
  // textureBytes_). The vertex and index buffers and the vertex array:
  size_t createGeometry(const Scene& s);
  // The colour and tangent streams of scenes that have them:
  size_t createOptionalStreams(const Scene& s);
  // Materials, lights, emitters and the emitters' power CDF:
  size_t createShadingBuffers(const Scene& s);
  // The textures with their mip chains and the file's samplers:
  void createTextures(const Scene& s);

  const Scene& scene_;
  gl::Buffer vertices_, indices_, colors_, tangents_, materials_, lights_, emitters_, emitterCdf_,
      lightTree_;
  // Animated meshes: the vertices as the last frame drew them (attribute
  // kPreviousPositionAttribute).
  gl::Buffer previousVertices_;
  std::vector<gpu::GpuEmitter> emitterData_;
  gl::VertexArray vao_;
  std::vector<gl::Texture> textures_;
  std::vector<gl::Sampler> samplers_;  // per texture
  gl::Sampler sampler_;
  int lightCount_ = 0, emitterCount_ = 0;
  bool hasOcclusion_ = false;  // some material has an occlusion texture
  size_t bytes_ = 0, textureBytes_ = 0;
  double uploadMs_ = 0.0;
};

}  // namespace voxgi::scene

#endif  // VOXGI_GPU_SCENE_GPU_SCENE_H

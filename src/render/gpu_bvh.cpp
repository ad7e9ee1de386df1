#include "render/gpu_bvh.h"

#include <bit>
#include <chrono>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bindings_shared.h"
#include "core/log.h"
#include "pathtrace_shared.h"
#include "render/pathtrace/pathtrace_scene.h"
#include "scene/emitters.h"

namespace voxgi::render {
namespace {

template <typename Vector>
void freeVector(Vector* v) {
  Vector().swap(*v);
}

}  // namespace

template <typename T, typename Fill>
gl::Buffer GpuBvh::uploadFilled(size_t count, Fill fill) {
  const size_t bytes = count * sizeof(T);
  gpuBytes_ += bytes;
  gl::Buffer b = gl::createBuffer(static_cast<GLsizeiptr>(bytes), nullptr, GL_MAP_WRITE_BIT);
  if (bytes == 0) return b;
  void* p = glMapNamedBufferRange(b.id(), 0, static_cast<GLsizeiptr>(bytes),
                                  GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
  if (!p) throw Error(strf("bvh: could not map a buffer of %zu bytes for writing", bytes));
  fill(static_cast<T*>(p));
  if (!glUnmapNamedBuffer(b.id()))
    throw Error(strf("bvh: a buffer of %zu bytes was lost while being written", bytes));
  return b;
}

GpuBvh::GpuBvh(const scene::GpuScene& gs, bool textures)
    : textured_(ptReadsTextures(gs.scene(), textures)) {
  const scene::Scene& s = gs.scene();
  const auto start = std::chrono::steady_clock::now();
  // No array of the triangles' positions: the build and the records read them from
  // the scene (at 2.44 M triangles 88 MB that were held through the uploads).
  PtScene pt = buildPtScene(s, textured_, false);
  const auto triangle = [&](size_t t) { return sceneTriangle(s, pt.firstIndex[t]); };
  Bvh::Options options;
  options.maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);  // what the kernel tests
  options.keepTriangles = false;  // written into their buffer below, in BVH order
  const auto treeStart = std::chrono::steady_clock::now();
  Bvh bvh(pt.material.size(), triangle, options);
  treeMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - treeStart)
                .count();
  triangleCount_ = bvh.triangleCount();
  depth_ = bvh.depth();
  sah_ = bvh.sahCost();
  Bvh::Arrays a = bvh.release();
  nodeCount_ = a.nodes.size();
  for (const gpu::GpuBvhNode& n : a.nodes) {
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.leftMax.w), gpu::kPtMaxLeafSize);
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.rightMax.w), gpu::kPtMaxLeafSize);
  }
  buildMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  // Each array goes up and its CPU copy is dropped before the next is made, and the
  // per-slot arrays are written straight into their buffers: on a software GL the
  // GPU's copies are host memory too, and the start-up peak is what is held at once.
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  const size_t nodeBytes = a.nodes.size() * sizeof(gpu::GpuBvhNode);
  nodes_ = upload(a.nodes.data(), nodeBytes);
  nodeTexels_ = bufferTexels(nodes_, nodeBytes, maxTexels);
  freeVector(&a.nodes);
  const std::vector<uint32_t>& order = a.order;
  // The emitting triangles that rtgi lights as clusters (scene/emitters.h) carry
  // their pdf negated (pathtrace_shared.h). PtScene's triangles are the draws' in
  // order.
  std::vector<bool> clustered(pt.material.size(), false);
  {
    const std::vector<bool> exact = scene::exactEmitterDraws(s);
    size_t t = 0;
    for (size_t i = 0; i < s.draws.size(); ++i)
      for (uint32_t k = 0; k + 2 < s.draws[i].indexCount; k += 3, ++t) clustered[t] = !exact[i];
    VOXGI_CHECK_EQ(t, clustered.size());
  }
  // Each triangle's record carries its material, emitter pdf and first index; the
  // rest of what a hit reads comes from the scene's own buffers.
  // On every core, as the build: the records read the scene's vertices in BVH
  // order, at random.
  triangles_ = uploadFilled<gpu::GpuPtTriangle>(order.size(), [&](gpu::GpuPtTriangle* out) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 1 << 14),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t slot = r.begin(); slot != r.end(); ++slot) {
                          const uint32_t t = order[slot];
                          gpu::GpuPtTriangle& g = out[slot];
                          g = Bvh::gpuTriangle(triangle(t));
                          g.v0.w = std::bit_cast<float>(static_cast<uint32_t>(pt.material[t]));
                          g.e1.w = clustered[t] ? -pt.emitterAreaPdf[t] : pt.emitterAreaPdf[t];
                          g.e2.w = std::bit_cast<float>(pt.firstIndex[t]);
                        }
                      });
  });
  triangleTexels_ = bufferTexels(triangles_, order.size() * sizeof(gpu::GpuPtTriangle), maxTexels);

  // scene::Vertex as 5 RG32F texels (its 40 bytes are not a whole number of RGBA32F).
  static_assert(sizeof(scene::Vertex) == 5 * sizeof(glm::vec2));
  if (5 * s.vertices.size() > static_cast<size_t>(maxTexels))
    throw Error(
        strf("bvh: the scene's %zu vertices need %zu texels, more than this GL's "
             "buffer texture limit of %d",
             s.vertices.size(), 5 * s.vertices.size(), maxTexels));
  vertexTexels_ = gl::createTexture(GL_TEXTURE_BUFFER);
  if (!s.vertices.empty()) glTextureBuffer(vertexTexels_.id(), GL_RG32F, gs.vertexBuffer());
  indices_ = gs.indexBuffer();
  if (s.hasVertexColors()) colors_ = gs.colorBuffer();
  if (s.hasNormalMaps()) tangents_ = gs.tangentBuffer();
  if (textured_) uploadTextures(s, maxTexels);
  emissiveCount_ = static_cast<int>(pt.emitters.size());
  emissive_ = upload(pt.emitters.data(), pt.emitters.size() * sizeof(gpu::GpuPtEmissive));
  logDebug(
      strf("bvh: %zu triangles, %zu nodes, depth %d, SAH %.1f, %.1f ms (the tree %.1f ms); %d "
           "emissive triangles",
           triangleCount_, nodeCount_, depth_, sah_, buildMs_, treeMs_, emissiveCount_));
}

gl::Buffer GpuBvh::upload(const void* data, size_t bytes) {
  gpuBytes_ += bytes;
  return gl::createBuffer(static_cast<GLsizeiptr>(bytes), bytes ? data : nullptr);
}

gl::Texture GpuBvh::bufferTexels(const gl::Buffer& buffer, size_t bytes, GLint maxTexels) const {
  if (bytes / 16 > static_cast<size_t>(maxTexels))
    throw Error(
        strf("bvh: %zu triangles need a BVH of %zu texels, more than this GL's "
             "buffer texture limit of %d",
             triangleCount_, bytes / 16, maxTexels));
  gl::Texture t = gl::createTexture(GL_TEXTURE_BUFFER);
  if (bytes) glTextureBuffer(t.id(), GL_RGBA32UI, buffer.id());
  return t;
}

void GpuBvh::uploadTextures(const scene::Scene& s, GLint maxTexels) {
  // Every texture's texels in one buffer and where each starts.
  std::vector<glm::uvec4> table;
  std::vector<uint32_t> pixels;
  buildPtTextures(s, &table, &pixels);
  if (pixels.size() > static_cast<size_t>(maxTexels))
    throw Error(
        strf("bvh: the scene's textures hold %zu texels, more than this GL's "
             "buffer texture limit of %d",
             pixels.size(), maxTexels));
  texels_ = upload(pixels.data(), pixels.size() * 4);
  textureTexels_ = gl::createTexture(GL_TEXTURE_BUFFER);
  glTextureBuffer(textureTexels_.id(), GL_R32UI, texels_.id());
  textureTable_ = upload(table.data(), table.size() * sizeof(glm::uvec4));
  textureBytes_ = pixels.size() * 4 + table.size() * sizeof(glm::uvec4);
}

void GpuBvh::bind(GLuint materials, bool colors, bool normalMaps) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, materials);
  glBindTextureUnit(gpu::kRtgiBvhNodeUnit, nodeTexels());
  glBindTextureUnit(gpu::kRtgiBvhTriangleUnit, triangleTexels());
  glBindTextureUnit(gpu::kRtgiBvhVertexUnit, vertexTexels());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhIndexBinding, indices());
  if (textured()) {
    glBindTextureUnit(gpu::kRtgiBvhTexelUnit, textureTexels());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhTextureBinding, textureTable());
  }
  if (colors && colored())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhColorBinding, this->colors());
  if (normalMaps && textured() && hasTangents())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhTangentBinding, tangents());
}

void GpuBvh::unbind() {
  for (GLuint u : {gpu::kRtgiBvhNodeUnit, gpu::kRtgiBvhTriangleUnit, gpu::kRtgiBvhVertexUnit,
                   gpu::kRtgiBvhTexelUnit})
    glBindTextureUnit(u, 0);
}

std::vector<std::string> GpuBvh::traceDefines(const scene::Scene& scene,
                                              const scene::ShaderFeatures& features) const {
  std::vector<std::string> defines{"RTGI_BVH"};
  if (textured_) defines.emplace_back("RTGI_BVH_TEXTURES");
  if (features.colors && colored()) defines.emplace_back("RTGI_BVH_COLORS");
  if (features.normalMaps && textured_ && hasTangents()) defines.emplace_back("RTGI_BVH_TANGENTS");
  if (ptReadsAlphaMasks(scene, features.alpha)) defines.emplace_back("RTGI_BVH_ALPHA");
  return defines;
}

}  // namespace voxgi::render

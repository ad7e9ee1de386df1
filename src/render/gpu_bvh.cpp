#include "render/gpu_bvh.h"

#include <bit>
#include <chrono>
#include <cstring>

#include "bindings_shared.h"
#include "core/log.h"
#include "pathtrace_shared.h"
#include "render/pathtrace_scene.h"

namespace voxgi::render {
namespace {

// Per triangle slot in BVH order: its vertex normals, material and emitter pdf.
void shadingInOrder(const scene::Scene& s, const PtScene& pt, const std::vector<uint32_t>& order,
                    gpu::GpuPtShading* shade) {
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t t = order[slot];
    const uint32_t i = pt.firstIndex[t];
    gpu::GpuPtShading& g = shade[slot];
    g.n0 = glm::vec4(s.vertices[s.indices[i]].normal,
                     std::bit_cast<float>(static_cast<uint32_t>(pt.material[t])));
    g.n1 = glm::vec4(s.vertices[s.indices[i + 1]].normal, pt.emitterAreaPdf[t]);
    g.n2 = glm::vec4(s.vertices[s.indices[i + 2]].normal, 0.0f);
  }
}

// Whether some drawn material reads texture coordinates channel 1.
int uvChannels(const scene::Scene& s) {
  bool second = false;
  for (const scene::Draw& d : s.draws)
    second = second || s.materials[static_cast<size_t>(d.material)].hasUv2;
  return second ? 2 : 1;
}

// The corner UVs of each triangle slot, two vec4 a triangle (a.xy b.xy, c.xy 0 0),
// one block per channel.
void cornerUvs(const scene::Scene& s, const PtScene& pt, const std::vector<uint32_t>& order,
               int channels, glm::vec4* uvs) {
  for (int ch = 0; ch < channels; ++ch) {
    const size_t first = 2 * order.size() * static_cast<size_t>(ch);
    for (size_t slot = 0; slot < order.size(); ++slot) {
      const uint32_t i = pt.firstIndex[order[slot]];
      const glm::vec2 a = scene::channelUv(s.vertices[s.indices[i]], ch),
                      b = scene::channelUv(s.vertices[s.indices[i + 1]], ch),
                      c = scene::channelUv(s.vertices[s.indices[i + 2]], ch);
      uvs[first + 2 * slot] = glm::vec4(a, b);
      uvs[first + 2 * slot + 1] = glm::vec4(c, 0.0f, 0.0f);
    }
  }
}

// A per-vertex attribute at each triangle corner, three a triangle, BVH order.
void cornerValues(const std::vector<glm::vec4>& perVertex, const scene::Scene& s, const PtScene& pt,
                  const std::vector<uint32_t>& order, glm::vec4* values) {
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t i = pt.firstIndex[order[slot]];
    for (uint32_t k = 0; k < 3; ++k) values[3 * slot + k] = perVertex[s.indices[i + k]];
  }
}

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

GpuBvh::GpuBvh(const scene::Scene& s, bool textures) : textured_(ptReadsTextures(s, textures)) {
  const auto start = std::chrono::steady_clock::now();
  PtScene pt = buildPtScene(s, textured_);
  Bvh::Options options;
  options.maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);  // what the kernel tests
  options.keepTriangles = false;  // written into their buffer below, in BVH order
  Bvh bvh(pt.triangles, options);
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
  triangles_ = uploadFilled<gpu::GpuPtTriangle>(order.size(), [&](gpu::GpuPtTriangle* out) {
    for (size_t slot = 0; slot < order.size(); ++slot)
      out[slot] = Bvh::gpuTriangle(pt.triangles[order[slot]]);
  });
  triangleTexels_ = bufferTexels(triangles_, order.size() * sizeof(gpu::GpuPtTriangle), maxTexels);
  freeVector(&pt.triangles);

  shading_ = uploadFilled<gpu::GpuPtShading>(
      order.size(), [&](gpu::GpuPtShading* out) { shadingInOrder(s, pt, order, out); });
  if (textured_) uploadTextures(s, pt, order, maxTexels);
  if (s.hasVertexColors()) {
    colors_ = uploadFilled<glm::vec4>(
        3 * order.size(), [&](glm::vec4* out) { cornerValues(s.colors, s, pt, order, out); });
  }
  if (s.hasNormalMaps()) {
    tangents_ = uploadFilled<glm::vec4>(
        3 * order.size(), [&](glm::vec4* out) { cornerValues(s.tangents, s, pt, order, out); });
  }
  emissiveCount_ = static_cast<int>(pt.emitters.size());
  emissive_ = upload(pt.emitters.data(), pt.emitters.size() * sizeof(gpu::GpuPtEmissive));
  logDebug(strf("bvh: %zu triangles, %zu nodes, depth %d, SAH %.1f, %.1f ms; %d emissive triangles",
                triangleCount_, nodeCount_, depth_, sah_, buildMs_, emissiveCount_));
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

void GpuBvh::uploadTextures(const scene::Scene& s, const PtScene& pt,
                            const std::vector<uint32_t>& order, GLint maxTexels) {
  // Corner UVs in BVH order, then every texture's texels in one buffer and where
  // each starts.
  std::vector<glm::uvec4> table;
  std::vector<uint32_t> pixels;
  buildPtTextures(s, &table, &pixels);
  if (pixels.size() > static_cast<size_t>(maxTexels))
    throw Error(
        strf("bvh: the scene's textures hold %zu texels, more than this GL's "
             "buffer texture limit of %d",
             pixels.size(), maxTexels));
  const int channels = uvChannels(s);
  const size_t uvCount = 2 * order.size() * static_cast<size_t>(channels);
  uvs_ = uploadFilled<glm::vec4>(uvCount,
                                 [&](glm::vec4* out) { cornerUvs(s, pt, order, channels, out); });
  uvTexels_ = bufferTexels(uvs_, uvCount * sizeof(glm::vec4), maxTexels);
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
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhShadingBinding, shading());
  if (textured()) {
    glBindTextureUnit(gpu::kRtgiBvhUvUnit, uvTexels());
    glBindTextureUnit(gpu::kRtgiBvhTexelUnit, textureTexels());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhTextureBinding, textureTable());
  }
  if (colors && colored())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhColorBinding, this->colors());
  if (normalMaps && textured() && tangentsUploaded())
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kRtgiBvhTangentBinding, tangents());
}

void GpuBvh::unbind() {
  for (GLuint u : {gpu::kRtgiBvhNodeUnit, gpu::kRtgiBvhTriangleUnit, gpu::kRtgiBvhUvUnit,
                   gpu::kRtgiBvhTexelUnit})
    glBindTextureUnit(u, 0);
}

std::vector<std::string> GpuBvh::traceDefines(const scene::Scene& scene,
                                              const scene::ShaderFeatures& features) const {
  std::vector<std::string> defines{"RTGI_BVH"};
  if (textured_) defines.emplace_back("RTGI_BVH_TEXTURES");
  if (features.colors && colored()) defines.emplace_back("RTGI_BVH_COLORS");
  if (features.normalMaps && textured_ && tangentsUploaded())
    defines.emplace_back("RTGI_BVH_TANGENTS");
  if (ptReadsAlphaMasks(scene, features.alpha)) defines.emplace_back("RTGI_BVH_ALPHA");
  return defines;
}

}  // namespace voxgi::render

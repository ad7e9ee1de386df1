#include "render/gpu_bvh.h"

#include <bit>
#include <chrono>
#include <cstring>

#include "core/log.h"
#include "pathtrace_shared.h"
#include "render/pathtrace_scene.h"

namespace voxgi::render {
namespace {

// Per-triangle shading data in BVH order: vertex normals, material, emitter pdf.
std::vector<gpu::GpuPtShading> shadingInOrder(const scene::Scene& s, const PtScene& pt,
                                              const std::vector<uint32_t>& order) {
  std::vector<gpu::GpuPtShading> shade(order.size());
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t t = order[slot];
    const uint32_t i = pt.firstIndex[t];
    gpu::GpuPtShading& g = shade[slot];
    g.n0 = glm::vec4(s.vertices[s.indices[i]].normal,
                     std::bit_cast<float>(static_cast<uint32_t>(pt.material[t])));
    g.n1 = glm::vec4(s.vertices[s.indices[i + 1]].normal, pt.emitterAreaPdf[t]);
    g.n2 = glm::vec4(s.vertices[s.indices[i + 2]].normal, 0.0f);
  }
  return shade;
}

// Corner UVs in BVH order: (uv0, uv1) and (uv2, 0, 0) a triangle, texture
// coordinate channel 0 (scene::Vertex::uv); then, where a drawn material reads
// channel 1 (scene::Material::hasUv2), the same for channel 1 (bvh_trace.glsl).
std::vector<glm::vec4> cornerUvs(const scene::Scene& s, const PtScene& pt,
                                 const std::vector<uint32_t>& order) {
  bool second = false;
  for (const scene::Draw& d : s.draws)
    second = second || s.materials[static_cast<size_t>(d.material)].hasUv2;
  const int channels = second ? 2 : 1;
  std::vector<glm::vec4> uvs(2 * order.size() * static_cast<size_t>(channels));
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
  return uvs;
}

// A per-vertex attribute (colours, tangents) at each triangle's three corners, in
// BVH order.
std::vector<glm::vec4> cornerValues(const std::vector<glm::vec4>& perVertex, const scene::Scene& s,
                                    const PtScene& pt, const std::vector<uint32_t>& order) {
  std::vector<glm::vec4> values(3 * order.size());
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t i = pt.firstIndex[order[slot]];
    for (uint32_t k = 0; k < 3; ++k) values[3 * slot + k] = perVertex[s.indices[i + k]];
  }
  return values;
}

}  // namespace

GpuBvh::GpuBvh(const scene::Scene& s, bool textures) : textured_(ptReadsTextures(s, textures)) {
  const auto start = std::chrono::steady_clock::now();
  const PtScene pt = buildPtScene(s, textured_);
  Bvh::Options options;
  options.maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);  // what the kernel tests
  bvh_ = Bvh(pt.triangles, options);
  for (const gpu::GpuBvhNode& n : bvh_.nodes()) {
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.leftMax.w), gpu::kPtMaxLeafSize);
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.rightMax.w), gpu::kPtMaxLeafSize);
  }
  buildMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const std::vector<uint32_t>& order = bvh_.order();
  const std::vector<gpu::GpuPtShading> shade = shadingInOrder(s, pt, order);
  const std::vector<gpu::GpuPtEmissive>& emitters = pt.emitters;
  emissiveCount_ = static_cast<int>(emitters.size());

  const auto& triangles = bvh_.gpuTriangles();
  const auto& nodes = bvh_.nodes();
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  nodes_ = upload(nodes.data(), nodes.size() * sizeof(gpu::GpuBvhNode));
  triangles_ = upload(triangles.data(), triangles.size() * sizeof(gpu::GpuPtTriangle));
  nodeTexels_ = bufferTexels(nodes_, nodes.size() * sizeof(gpu::GpuBvhNode), maxTexels);
  triangleTexels_ =
      bufferTexels(triangles_, triangles.size() * sizeof(gpu::GpuPtTriangle), maxTexels);
  shading_ = upload(shade.data(), shade.size() * sizeof(gpu::GpuPtShading));
  if (textured_) uploadTextures(s, pt, maxTexels);
  if (s.hasVertexColors()) {
    const std::vector<glm::vec4> colors = cornerValues(s.colors, s, pt, order);
    colors_ = upload(colors.data(), colors.size() * sizeof(glm::vec4));
  }
  if (s.hasNormalMaps()) {
    const std::vector<glm::vec4> tangents = cornerValues(s.tangents, s, pt, order);
    tangents_ = upload(tangents.data(), tangents.size() * sizeof(glm::vec4));
  }
  emissive_ = upload(emitters.data(), emitters.size() * sizeof(gpu::GpuPtEmissive));
  logDebug(strf("bvh: %zu triangles, %zu nodes, depth %d, SAH %.1f, %.1f ms; %d emissive triangles",
                bvh_.triangleCount(), nodes.size(), bvh_.depth(), bvh_.sahCost(), buildMs_,
                emissiveCount_));
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
             bvh_.triangleCount(), bytes / 16, maxTexels));
  gl::Texture t = gl::createTexture(GL_TEXTURE_BUFFER);
  if (bytes) glTextureBuffer(t.id(), GL_RGBA32UI, buffer.id());
  return t;
}

void GpuBvh::uploadTextures(const scene::Scene& s, const PtScene& pt, GLint maxTexels) {
  // Corner UVs in BVH order, then every texture's texels in one buffer and where
  // each starts.
  const std::vector<glm::vec4> uvs = cornerUvs(s, pt, bvh_.order());
  std::vector<glm::uvec4> table;
  std::vector<uint32_t> pixels;
  buildPtTextures(s, &table, &pixels);
  if (pixels.size() > static_cast<size_t>(maxTexels))
    throw Error(
        strf("bvh: the scene's textures hold %zu texels, more than this GL's "
             "buffer texture limit of %d",
             pixels.size(), maxTexels));
  uvs_ = upload(uvs.data(), uvs.size() * sizeof(glm::vec4));
  uvTexels_ = bufferTexels(uvs_, uvs.size() * sizeof(glm::vec4), maxTexels);
  texels_ = upload(pixels.data(), pixels.size() * 4);
  textureTexels_ = gl::createTexture(GL_TEXTURE_BUFFER);
  glTextureBuffer(textureTexels_.id(), GL_R32UI, texels_.id());
  textureTable_ = upload(table.data(), table.size() * sizeof(glm::uvec4));
  textureBytes_ = pixels.size() * 4 + table.size() * sizeof(glm::uvec4);
}

}  // namespace voxgi::render

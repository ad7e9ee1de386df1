#include "render/gpu_bvh.h"

#include <bit>
#include <chrono>
#include <cstring>

#include "core/log.h"
#include "pathtrace_shared.h"

namespace voxgi::render {
namespace {

float luminance(const glm::vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// Vose's alias method: prob[i] is the chance of keeping i, alias[i] the other choice.
void buildAliasTable(const std::vector<double>& weights, std::vector<float>* prob,
                     std::vector<uint32_t>* alias) {
  const size_t n = weights.size();
  prob->assign(n, 1.0f);
  alias->resize(n);
  double total = 0.0;
  for (double w : weights) total += w;
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    (*alias)[i] = static_cast<uint32_t>(i);
    scaled[i] = weights[i] / total * static_cast<double>(n);
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t s = small.back(), l = large.back();
    small.pop_back();
    (*prob)[s] = static_cast<float>(scaled[s]);
    (*alias)[s] = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What is left holds (up to rounding) exactly 1.
}

// Whether the kernel reads base-colour textures: the plan allows them and a draw's
// material has one.
bool usesTextures(const scene::Scene& s, bool textures) {
  if (!textures) return false;
  for (const scene::Draw& d : s.draws) {
    const int t = s.materials[static_cast<size_t>(d.material)].baseColorTexture;
    if (t >= 0 && static_cast<size_t>(t) < s.textures.size()) return true;
  }
  return false;
}

}  // namespace

GpuBvh::GpuBvh(const scene::Scene& s, bool textures) : textured_(usesTextures(s, textures)) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BvhTriangle> tris;
  std::vector<int> material;
  tris.reserve(s.triangleCount());
  material.reserve(s.triangleCount());
  for (const scene::Draw& d : s.draws) {
    for (uint32_t i = d.firstIndex; i + 2 < d.firstIndex + d.indexCount; i += 3) {
      tris.push_back({s.vertices[s.indices[i]].position, s.vertices[s.indices[i + 1]].position,
                      s.vertices[s.indices[i + 2]].position});
      material.push_back(d.material);
    }
  }
  Bvh::Options options;
  options.maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);  // what the kernel tests
  bvh_ = Bvh(tris, options);
  for (const gpu::GpuBvhNode& n : bvh_.nodes()) {
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.leftMax.w), gpu::kPtMaxLeafSize);
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.rightMax.w), gpu::kPtMaxLeafSize);
  }
  buildMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  // Emissive triangles, chosen in proportion to their power (area x luminance).
  const std::vector<uint32_t>& order = bvh_.order();
  std::vector<gpu::GpuPtShading> shade(order.size());
  std::vector<gpu::GpuPtEmissive> emitters;
  std::vector<double> power;
  std::vector<size_t> emitterSlot;  // BVH slot of each emitter
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t t = order[slot];
    const scene::Material& m = s.materials[static_cast<size_t>(material[t])];
    gpu::GpuPtShading& g = shade[slot];
    g.n0.w = std::bit_cast<float>(static_cast<uint32_t>(material[t]));
    if (!m.isEmissive()) continue;
    const BvhTriangle& tri = tris[t];
    const glm::vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    const float area = 0.5f * glm::length(glm::cross(e1, e2));
    const double p =
        static_cast<double>(area) * luminance(m.emission) * (m.doubleSided ? 2.0 : 1.0);
    if (!(p > 0.0)) continue;
    gpu::GpuPtEmissive e{};
    e.v0 = glm::vec4(tri.v0, 0.0f);
    e.e1 = glm::vec4(e1, 0.0f);
    e.e2 = glm::vec4(e2, 0.0f);
    e.radiance = glm::vec4(m.emission, m.doubleSided ? 1.0f : 0.0f);
    emitters.push_back(e);
    power.push_back(p);
    emitterSlot.push_back(slot);
  }
  // Triangle t is the t-th triple over the draws: its first index, for the per-corner
  // data (normals, UVs) in BVH order.
  std::vector<uint32_t> firstIndexOf;
  firstIndexOf.reserve(tris.size());
  for (const scene::Draw& d : s.draws)
    for (uint32_t i = d.firstIndex; i + 2 < d.firstIndex + d.indexCount; i += 3)
      firstIndexOf.push_back(i);
  // Vertex normals in BVH order.
  {
    for (size_t slot = 0; slot < order.size(); ++slot) {
      const uint32_t i = firstIndexOf[order[slot]];
      gpu::GpuPtShading& g = shade[slot];
      g.n0 = glm::vec4(s.vertices[s.indices[i]].normal, g.n0.w);
      g.n1 = glm::vec4(s.vertices[s.indices[i + 1]].normal, 0.0f);
      g.n2 = glm::vec4(s.vertices[s.indices[i + 2]].normal, 0.0f);
    }
  }
  if (!emitters.empty()) {
    std::vector<float> prob;
    std::vector<uint32_t> alias;
    buildAliasTable(power, &prob, &alias);
    double total = 0.0;
    for (double p : power) total += p;
    for (size_t i = 0; i < emitters.size(); ++i) {
      const float pmf = static_cast<float>(power[i] / total);
      emitters[i].v0.w = prob[i];
      emitters[i].e1.w = std::bit_cast<float>(alias[i]);
      emitters[i].e2.w = pmf;
      const float area =
          0.5f * glm::length(glm::cross(glm::vec3(emitters[i].e1), glm::vec3(emitters[i].e2)));
      shade[emitterSlot[i]].n1.w = pmf / area;
    }
  }
  emissiveCount_ = static_cast<int>(emitters.size());

  const auto triangles = bvh_.gpuTriangles();
  const auto& nodes = bvh_.nodes();
  auto upload = [this](const void* data, size_t bytes) {
    gpuBytes_ += bytes;
    return gl::createBuffer(static_cast<GLsizeiptr>(bytes), bytes ? data : nullptr);
  };
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  auto texels = [&](const gl::Buffer& buffer, size_t bytes) {
    if (bytes / 16 > static_cast<size_t>(maxTexels))
      throw Error(
          strf("bvh: %zu triangles need a BVH of %zu texels, more than this GL's "
               "buffer texture limit of %d",
               bvh_.triangleCount(), bytes / 16, maxTexels));
    gl::Texture t = gl::createTexture(GL_TEXTURE_BUFFER);
    if (bytes) glTextureBuffer(t.id(), GL_RGBA32UI, buffer.id());
    return t;
  };
  nodes_ = upload(nodes.data(), nodes.size() * sizeof(gpu::GpuBvhNode));
  triangles_ = upload(triangles.data(), triangles.size() * sizeof(gpu::GpuPtTriangle));
  nodeTexels_ = texels(nodes_, nodes.size() * sizeof(gpu::GpuBvhNode));
  triangleTexels_ = texels(triangles_, triangles.size() * sizeof(gpu::GpuPtTriangle));
  shading_ = upload(shade.data(), shade.size() * sizeof(gpu::GpuPtShading));
  if (textured_) {
    // Corner UVs in BVH order, then every texture's texels in one buffer and where
    // each starts.
    std::vector<glm::vec4> uvs(2 * order.size());
    for (size_t slot = 0; slot < order.size(); ++slot) {
      const uint32_t i = firstIndexOf[order[slot]];
      const glm::vec2 a = s.vertices[s.indices[i]].uv, b = s.vertices[s.indices[i + 1]].uv,
                      c = s.vertices[s.indices[i + 2]].uv;
      uvs[2 * slot] = glm::vec4(a, b);
      uvs[2 * slot + 1] = glm::vec4(c, 0.0f, 0.0f);
    }
    std::vector<glm::uvec4> table;
    std::vector<uint32_t> pixels;
    for (const scene::Texture& t : s.textures) {
      table.push_back(glm::uvec4(static_cast<uint32_t>(pixels.size()), t.width, t.height, 0u));
      const size_t n = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
      VOXGI_CHECK_EQ(t.rgba8.size(), n * 4);
      const size_t first = pixels.size();
      pixels.resize(first + n);
      std::memcpy(pixels.data() + first, t.rgba8.data(), n * 4);
    }
    if (pixels.size() > static_cast<size_t>(maxTexels))
      throw Error(
          strf("bvh: the scene's textures hold %zu texels, more than this GL's "
               "buffer texture limit of %d",
               pixels.size(), maxTexels));
    uvs_ = upload(uvs.data(), uvs.size() * sizeof(glm::vec4));
    uvTexels_ = texels(uvs_, uvs.size() * sizeof(glm::vec4));
    texels_ = upload(pixels.data(), pixels.size() * 4);
    textureTexels_ = gl::createTexture(GL_TEXTURE_BUFFER);
    glTextureBuffer(textureTexels_.id(), GL_R32UI, texels_.id());
    textureTable_ = upload(table.data(), table.size() * sizeof(glm::uvec4));
  }
  emissive_ = upload(emitters.data(), emitters.size() * sizeof(gpu::GpuPtEmissive));
  logDebug(strf("bvh: %zu triangles, %zu nodes, depth %d, SAH %.1f, %.1f ms; %d emissive triangles",
                bvh_.triangleCount(), nodes.size(), bvh_.depth(), bvh_.sahCost(), buildMs_,
                emissiveCount_));
}

}  // namespace voxgi::render

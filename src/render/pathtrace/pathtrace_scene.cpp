#include "render/pathtrace/pathtrace_scene.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "core/log.h"
#include "scene/emitters.h"

#include "brdf_shared.h"

namespace voxgi::render {

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

BvhTriangle sceneTriangle(const scene::Scene& s, uint32_t firstIndex) {
  const uint32_t* idx = &s.indices[firstIndex];
  return {s.vertices[idx[0]].position, s.vertices[idx[1]].position, s.vertices[idx[2]].position};
}

PtScene buildPtScene(const scene::Scene& s, bool textured, bool keepTriangles) {
  PtScene pt;
  if (keepTriangles) pt.triangles.reserve(s.triangleCount());
  pt.material.reserve(s.triangleCount());
  pt.firstIndex.reserve(s.triangleCount());
  std::vector<glm::vec3> emission;  // per triangle: mean radiance
  for (const scene::Draw& d : s.draws) {
    for (uint32_t i = d.firstIndex; i + 2 < d.firstIndex + d.indexCount; i += 3) {
      const size_t t = (i - d.firstIndex) / 3;
      emission.push_back(textured ? scene::triangleEmission(s, d, t)
                                  : s.materials[static_cast<size_t>(d.material)].emission);
      if (keepTriangles) pt.triangles.push_back(sceneTriangle(s, i));
      pt.material.push_back(d.material);
      pt.firstIndex.push_back(i);
    }
  }
  pt.emitterAreaPdf.assign(pt.material.size(), 0.0f);
  std::vector<double> power;
  std::vector<size_t> owner;  // triangle of each emitter
  for (size_t t = 0; t < pt.material.size(); ++t) {
    const scene::Material& m = s.materials[static_cast<size_t>(pt.material[t])];
    if (!m.isEmissive()) continue;
    const BvhTriangle tri = sceneTriangle(s, pt.firstIndex[t]);
    const glm::vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    const float area = 0.5f * glm::length(glm::cross(e1, e2));
    const double p =
        static_cast<double>(area) * gpu::luminance(emission[t]) * (m.doubleSided ? 2.0 : 1.0);
    if (!(p > 0.0)) continue;
    gpu::GpuPtEmissive e{};
    e.v0 = glm::vec4(tri.v0, 0.0f);
    e.e1 = glm::vec4(e1, 0.0f);
    e.e2 = glm::vec4(e2, 0.0f);
    e.radiance = glm::vec4(m.emission, m.doubleSided ? 1.0f : 0.0f);
    if (textured && m.emissiveTexture >= 0 &&
        static_cast<size_t>(m.emissiveTexture) < s.textures.size()) {
      const uint32_t* idx = &s.indices[pt.firstIndex[t]];
      // The emissive texture's channel.
      const int ch = m.emissiveChannel;
      const glm::vec2 a = scene::channelUv(s.vertices[idx[0]], ch),
                      b = scene::channelUv(s.vertices[idx[1]], ch),
                      c = scene::channelUv(s.vertices[idx[2]], ch);
      e.uv01 = glm::vec4(a, b);
      e.uv2 =
          glm::vec4(c, std::bit_cast<float>(static_cast<uint32_t>(m.emissiveTexture) + 1u), 0.0f);
    }
    pt.emitters.push_back(e);
    power.push_back(p);
    owner.push_back(t);
  }
  if (!pt.emitters.empty()) {
    std::vector<float> prob;
    std::vector<uint32_t> alias;
    buildAliasTable(power, &prob, &alias);
    double total = 0.0;
    for (double p : power) total += p;
    for (size_t i = 0; i < pt.emitters.size(); ++i) {
      gpu::GpuPtEmissive& e = pt.emitters[i];
      const float pmf = static_cast<float>(power[i] / total);
      e.v0.w = prob[i];
      e.e1.w = std::bit_cast<float>(alias[i]);
      e.e2.w = pmf;
      const float area = 0.5f * glm::length(glm::cross(glm::vec3(e.e1), glm::vec3(e.e2)));
      pt.emitterAreaPdf[owner[i]] = pmf / area;
    }
  }
  pt.epsilon = 1e-5f * std::max(s.bounds.diagonal(), 1e-20f);
  return pt;
}

bool ptReadsTextures(const scene::Scene& s, bool allowed) {
  if (!allowed) return false;
  for (const scene::Draw& d : s.draws) {
    const scene::Material& m = s.materials[static_cast<size_t>(d.material)];
    for (int t :
         {m.baseColorTexture, m.emissiveTexture, m.metallicRoughnessTexture, m.normalTexture})
      if (t >= 0 && static_cast<size_t>(t) < s.textures.size()) return true;
  }
  return false;
}

bool ptReadsAlphaMasks(const scene::Scene& s, bool allowed) {
  if (!allowed) return false;
  for (const scene::Draw& d : s.draws)
    if (s.materials[static_cast<size_t>(d.material)].alphaMode != scene::AlphaMode::kOpaque)
      return true;
  return false;
}

void buildPtTextures(const scene::Scene& s, std::vector<glm::uvec4>* table,
                     std::vector<uint32_t>* texels) {
  table->clear();
  texels->clear();
  for (const scene::Texture& t : s.textures) {
    table->push_back(
        glm::uvec4(static_cast<uint32_t>(texels->size()), t.width, t.height, t.tableFlags()));
    const size_t n = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
    VOXGI_CHECK_EQ(t.rgba8.size(), n * 4);
    const size_t first = texels->size();
    texels->resize(first + n);
    std::memcpy(texels->data() + first, t.rgba8.data(), n * 4);
  }
}

}  // namespace voxgi::render

#include "scene/emitters.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>

#include "core/log.h"
#include "emitter_shared.h"
#include "texture_shared.h"

namespace voxgi::scene {
namespace {

// Normal buckets: the major axis face of the cube (6) times a 3x3 grid over the
// other two components; facets in one bucket are within ~35 degrees of each other.
int normalBucket(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int face = axis * 2 + (n[axis] < 0.0f ? 1 : 0);
  const float u = n[(axis + 1) % 3] / std::max(a[axis], 1e-6f);
  const float v = n[(axis + 2) % 3] / std::max(a[axis], 1e-6f);
  auto bin = [](float x) { return std::clamp(static_cast<int>((x + 1.0f) * 1.5f), 0, 2); };
  return face * 9 + bin(u) * 3 + bin(v);
}

// Any texel index to the texel the sampler reads there (wrapTexel takes [-1, 2n]).
int wrapAny(int i, int extent, uint32_t mode) {
  if (mode != gpu::kTextureClampToEdge) i = ((i % (2 * extent)) + 2 * extent) % (2 * extent);
  return gpu::wrapTexel(i, extent, mode);
}

// An emissive texture as the shared texel reads see it: its texels, table entry and
// wrap modes, and each byte value decoded as the shared texel read decodes it.
struct EmissiveTexels {
  const Texture* tex = nullptr;
  int w = 0, h = 0;
  gpu::PtTables tables;
  glm::uvec4 entry{0u};
  uint32_t wrapS = 0, wrapT = 0;
  std::array<float, 256> decoded{};
};

// `texels` holds the texels that the result's tables point to.
EmissiveTexels emissiveTexels(const Texture& tex, std::vector<uint32_t>* texels) {
  EmissiveTexels e;
  e.tex = &tex;
  e.w = tex.width;
  e.h = tex.height;
  const size_t n = static_cast<size_t>(e.w) * static_cast<size_t>(e.h);
  VOXGI_CHECK_EQ(tex.rgba8.size(), n * 4);
  texels->resize(n);
  std::memcpy(texels->data(), tex.rgba8.data(), n * 4);
  e.tables = gpu::PtTables{nullptr, texels->data(), nullptr};
  e.entry =
      glm::uvec4(0u, static_cast<uint32_t>(e.w), static_cast<uint32_t>(e.h), tex.tableFlags());
  e.wrapS = (e.entry.w >> gpu::kTextureWrapSShift) & 3u;
  e.wrapT = (e.entry.w >> gpu::kTextureWrapTShift) & 3u;
  for (uint32_t v = 0; v < 256; ++v) {
    const gpu::PtTables one{nullptr, &v, nullptr};
    e.decoded[v] = gpu::srgbTexel(one, glm::uvec4(0u, 1u, 1u, e.entry.w), glm::ivec2(0)).r;
  }
  return e;
}

// The mean of the texels whose centres lie in the triangle of texel-space corners q
// (texel (i, j) has its centre at (i, j); wrapped as the sampler wraps them), and
// how many there are (none for a degenerate or huge triangle).
size_t texelCentreMean(const EmissiveTexels& e, const glm::vec2 q[3], glm::dvec3* mean) {
  const glm::vec2 lo = glm::min(q[0], glm::min(q[1], q[2]));
  const glm::vec2 hi = glm::max(q[0], glm::max(q[1], q[2]));
  const float area2 = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
  glm::dvec3 sum(0.0);
  size_t count = 0;
  const double box =
      (std::floor(static_cast<double>(hi.x)) - std::ceil(static_cast<double>(lo.x)) + 1.0) *
      (std::floor(static_cast<double>(hi.y)) - std::ceil(static_cast<double>(lo.y)) + 1.0);
  // Texel coordinates far from the texture (a malformed UV) would overflow int below.
  const bool near = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y)}) <
                    static_cast<float>(1 << 30);
  if (area2 != 0.0f && std::isfinite(area2) && near && box < 16.0 * 1024.0 * 1024.0) {
    const float sign = area2 > 0.0f ? 1.0f : -1.0f;
    for (int y = static_cast<int>(std::ceil(lo.y)); y <= static_cast<int>(std::floor(hi.y)); ++y)
      for (int x = static_cast<int>(std::ceil(lo.x)); x <= static_cast<int>(std::floor(hi.x));
           ++x) {
        const glm::vec2 p(static_cast<float>(x), static_cast<float>(y));
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const glm::vec2 edge = q[(k + 1) % 3] - q[k], r = p - q[k];
          inside = sign * (edge.x * r.y - edge.y * r.x) >= 0.0f;
        }
        if (!inside) continue;
        const int tx = wrapAny(x, e.w, e.wrapS), ty = wrapAny(y, e.h, e.wrapT);
        const uint8_t* c = &e.tex->rgba8[(static_cast<size_t>(ty) * static_cast<size_t>(e.w) +
                                          static_cast<size_t>(tx)) *
                                         4];
        sum += glm::dvec3(e.decoded[c[0]], e.decoded[c[1]], e.decoded[c[2]]);
        ++count;
      }
  }
  if (count > 0) *mean = sum / static_cast<double>(count);
  return count;
}

// The bilinear texture at a grid of 8 x 8 points, spread by the path tracer's
// uniform map from the unit square to the triangle of UVs a, b, c
// (pathtrace_shading.h), averaged.
glm::vec3 sampledMean(const EmissiveTexels& e, const glm::vec2& a, const glm::vec2& b,
                      const glm::vec2& c) {
  constexpr int kGrid = 8;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const float sq = std::sqrt((static_cast<float>(i) + 0.5f) / kGrid);
      const float u2 = (static_cast<float>(j) + 0.5f) / kGrid;
      const glm::vec2 uv = a + (b - a) * (sq * (1.0f - u2)) + (c - a) * (sq * u2);
      sum += glm::dvec3(glm::vec3(gpu::sampleTexture(e.tables, e.entry, uv)));
    }
  return glm::vec3(sum / static_cast<double>(kGrid * kGrid));
}

}  // namespace

void measureEmissiveTextures(Scene* scene) {
  const auto start = std::chrono::steady_clock::now();
  size_t measured = 0;
  std::vector<uint32_t> texels;
  for (Draw& d : scene->draws) {
    d.emissiveMean.clear();
    const Material& m = scene->materials[static_cast<size_t>(d.material)];
    if (m.emissiveTexture < 0 || static_cast<size_t>(m.emissiveTexture) >= scene->textures.size())
      continue;
    const EmissiveTexels e =
        emissiveTexels(scene->textures[static_cast<size_t>(m.emissiveTexture)], &texels);
    const size_t tris = d.indexCount / 3;
    d.emissiveMean.resize(tris);
    for (size_t t = 0; t < tris; ++t) {
      const uint32_t* idx = &scene->indices[d.firstIndex + t * 3];
      // Corners in texel space: texel (i, j) has its centre at (i, j).
      glm::vec2 q[3];
      // The emissive texture's channel at each corner.
      glm::vec2 uv[3];
      for (int k = 0; k < 3; ++k) uv[k] = channelUv(scene->vertices[idx[k]], m.emissiveChannel);
      for (int k = 0; k < 3; ++k) q[k] = uv[k] * glm::vec2(e.w, e.h) - 0.5f;
      glm::dvec3 mean(0.0);
      if (texelCentreMean(e, q, &mean) >= 4) {
        d.emissiveMean[t] = glm::vec3(mean);
        continue;
      }
      // Fewer than four texel centres inside: the texture sampled over the triangle.
      d.emissiveMean[t] = sampledMean(e, uv[0], uv[1], uv[2]);
    }
    measured += tris;
  }
  if (measured)
    logDebug(
        strf("%s: emissive texture averaged over %zu triangles in %.1f ms", scene->path.c_str(),
             measured,
             std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count()));
}

glm::vec3 triangleEmission(const Scene& scene, const Draw& d, size_t t) {
  const glm::vec3 e = scene.materials[static_cast<size_t>(d.material)].emission;
  return t < d.emissiveMean.size() ? e * d.emissiveMean[t] : e;
}

std::vector<bool> exactEmitterDraws(const Scene& scene, const EmitterOptions& options) {
  // Every emitting triangle stays exact when they all fit; else a primitive of more
  // than exactTrianglesPerPrimitive is merged into clusters.
  size_t emissive = 0;
  for (const Draw& d : scene.draws)
    if (scene.materials[static_cast<size_t>(d.material)].isEmissive()) emissive += d.indexCount / 3;
  const bool allExact = emissive <= static_cast<size_t>(options.maxEmitters);
  std::vector<bool> exact(scene.draws.size(), false);
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    const Draw& d = scene.draws[i];
    exact[i] =
        scene.materials[static_cast<size_t>(d.material)].isEmissive() &&
        (allExact || d.indexCount / 3 <= static_cast<size_t>(options.exactTrianglesPerPrimitive));
  }
  return exact;
}

std::vector<Emitter> buildEmitters(const Scene& scene, const EmitterOptions& options) {
  const std::vector<bool> exact = exactEmitterDraws(scene, options);
  std::vector<Emitter> out;
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    const Draw& d = scene.draws[i];
    const Material& m = scene.materials[static_cast<size_t>(d.material)];
    if (!m.isEmissive()) continue;
    const size_t tris = d.indexCount / 3;
    auto corner = [&](size_t t, int k) {
      return scene.vertices[scene.indices[d.firstIndex + t * 3 + static_cast<size_t>(k)]].position;
    };
    if (exact[i]) {
      for (size_t t = 0; t < tris; ++t) {
        const glm::vec3 radiance = triangleEmission(scene, d, t);
        if (!(radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f)) continue;
        Emitter e;
        e.kind = Emitter::Kind::kTriangle;
        e.v0 = corner(t, 0);
        e.v1 = corner(t, 1);
        e.v2 = corner(t, 2);
        const glm::vec3 c = glm::cross(e.v1 - e.v0, e.v2 - e.v0);
        e.area = 0.5f * glm::length(c);
        e.normal = glm::normalize(c);
        e.radiance = radiance;
        e.twoSided = m.doubleSided;
        out.push_back(e);
      }
      continue;
    }
    Bounds b;
    for (size_t t = 0; t < tris; ++t)
      for (int k = 0; k < 3; ++k) b.extend(corner(t, k));
    struct Acc {
      glm::dvec3 weightedNormal{0.0};
      glm::dvec3 weightedCenter{0.0};
      glm::dvec3 weightedRadiance{0.0};
      double area = 0.0;
    };
    std::map<int, Acc> buckets;
    for (size_t t = 0; t < tris; ++t) {
      const glm::vec3 p0 = corner(t, 0), p1 = corner(t, 1), p2 = corner(t, 2);
      const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
      const float len = glm::length(c);
      if (!(len > 0.0f)) continue;
      const glm::vec3 radiance = triangleEmission(scene, d, t);
      if (!(radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f)) continue;
      const glm::vec3 n = c / len;
      const glm::vec3 centroid = (p0 + p1 + p2) / 3.0f;
      const glm::bvec3 upper = glm::greaterThan(centroid, b.center());
      const int octant = (upper.x ? 1 : 0) | (upper.y ? 2 : 0) | (upper.z ? 4 : 0);
      Acc& acc = buckets[normalBucket(n) * 8 + octant];
      const double area = 0.5 * static_cast<double>(len);
      acc.weightedNormal += glm::dvec3(n) * area;
      acc.weightedCenter += glm::dvec3(centroid) * area;
      acc.weightedRadiance += glm::dvec3(radiance) * area;
      acc.area += area;
    }
    for (const auto& [key, acc] : buckets) {
      const double projected = glm::length(acc.weightedNormal);
      if (!(projected > 0.0)) continue;
      Emitter e;
      e.kind = Emitter::Kind::kCluster;
      e.v0 = glm::vec3(acc.weightedCenter / acc.area);
      e.normal = glm::vec3(acc.weightedNormal / projected);
      e.area = static_cast<float>(projected);
      // The facets' mean radiance, by area (all equal without an emissive texture).
      e.radiance = d.emissiveMean.empty() ? m.emission : glm::vec3(acc.weightedRadiance / acc.area);
      e.twoSided = m.doubleSided;
      out.push_back(e);
    }
  }
  if (out.size() > static_cast<size_t>(options.maxEmitters)) {
    std::sort(out.begin(), out.end(), [](const Emitter& a, const Emitter& b) {
      return a.area * (a.radiance.x + a.radiance.y + a.radiance.z) >
             b.area * (b.radiance.x + b.radiance.y + b.radiance.z);
    });
    logWarning(strf("%s: %zu emitter groups; keeping the %d most powerful for direct light",
                    scene.path.c_str(), out.size(), options.maxEmitters));
    out.resize(static_cast<size_t>(options.maxEmitters));
  }
  return out;
}

float emitterIrradianceFactor(const Emitter& e, const glm::vec3& p, const glm::vec3& n) {
  if (e.kind == Emitter::Kind::kCluster)
    return gpu::clusterEmitterFactor(e.v0, e.normal, e.area, e.twoSided, p, n);
  return gpu::triangleEmitterFactor(e.v0, e.v1, e.v2, e.twoSided, p, n);
}

}  // namespace voxgi::scene

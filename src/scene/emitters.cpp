#include "scene/emitters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "core/log.h"

namespace voxgi::scene {
namespace {

constexpr float kPi = 3.14159265358979f;

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

}  // namespace

std::vector<Emitter> buildEmitters(const Scene& scene, const EmitterOptions& options) {
  std::vector<Emitter> out;
  for (const Draw& d : scene.draws) {
    const Material& m = scene.materials[static_cast<size_t>(d.material)];
    if (!m.isEmissive()) continue;
    const size_t tris = d.indexCount / 3;
    auto corner = [&](size_t t, int k) {
      return scene.vertices[scene.indices[d.firstIndex + t * 3 + static_cast<size_t>(k)]].position;
    };
    if (tris <= static_cast<size_t>(options.exactTrianglesPerPrimitive)) {
      for (size_t t = 0; t < tris; ++t) {
        Emitter e;
        e.kind = Emitter::Kind::kTriangle;
        e.v0 = corner(t, 0);
        e.v1 = corner(t, 1);
        e.v2 = corner(t, 2);
        const glm::vec3 c = glm::cross(e.v1 - e.v0, e.v2 - e.v0);
        e.area = 0.5f * glm::length(c);
        e.normal = glm::normalize(c);
        e.radiance = m.emission;
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
      double area = 0.0;
    };
    std::map<int, Acc> buckets;
    for (size_t t = 0; t < tris; ++t) {
      const glm::vec3 p0 = corner(t, 0), p1 = corner(t, 1), p2 = corner(t, 2);
      const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
      const float len = glm::length(c);
      if (!(len > 0.0f)) continue;
      const glm::vec3 n = c / len;
      const glm::vec3 centroid = (p0 + p1 + p2) / 3.0f;
      const glm::bvec3 upper = glm::greaterThan(centroid, b.center());
      const int octant = (upper.x ? 1 : 0) | (upper.y ? 2 : 0) | (upper.z ? 4 : 0);
      Acc& acc = buckets[normalBucket(n) * 8 + octant];
      const double area = 0.5 * static_cast<double>(len);
      acc.weightedNormal += glm::dvec3(n) * area;
      acc.weightedCenter += glm::dvec3(centroid) * area;
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
      e.radiance = m.emission;
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
  if (e.kind == Emitter::Kind::kCluster) {
    const glm::vec3 toC = e.v0 - p;
    const float d2 = glm::dot(toC, toC);
    const glm::vec3 w = toC / std::sqrt(std::max(d2, 1e-30f));
    float cosE = -glm::dot(e.normal, w);
    if (e.twoSided) cosE = std::abs(cosE);
    const float cosR = glm::dot(n, w);
    if (cosE <= 0.0f || cosR <= 0.0f) return 0.0f;
    return e.area * cosE * cosR / (d2 + e.area / kPi);
  }
  // One-sided emitters light only the side their normal faces.
  const float side = glm::dot(e.normal, p - e.v0);
  if (!e.twoSided && side <= 0.0f) return 0.0f;
  // Clip the triangle to the receiver's upper hemisphere (Sutherland-Hodgman).
  std::array<glm::vec3, 3> in = {e.v0 - p, e.v1 - p, e.v2 - p};
  std::array<glm::vec3, 4> poly;
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 a = in[static_cast<size_t>(i)], b = in[static_cast<size_t>((i + 1) % 3)];
    const float da = glm::dot(a, n), db = glm::dot(b, n);
    if (da > 0.0f) poly[static_cast<size_t>(count++)] = a;
    if ((da > 0.0f) != (db > 0.0f))
      poly[static_cast<size_t>(count++)] = a + (b - a) * (da / (da - db));
  }
  if (count < 3) return 0.0f;
  // Lambert: E/L = 1/2 |sum_i theta_i (gamma_i . n)|.
  float sum = 0.0f;
  // A corner at the receiver itself (it sits on the emitter's edge or vertex) has no
  // direction: its edges subtend nothing and are skipped, so the result stays finite.
  for (int i = 0; i < count; ++i) {
    const glm::vec3 pa = poly[static_cast<size_t>(i)];
    const glm::vec3 pb = poly[static_cast<size_t>((i + 1) % count)];
    const float la = glm::length(pa), lb = glm::length(pb);
    if (!(la > 1e-30f) || !(lb > 1e-30f)) continue;
    const glm::vec3 a = pa / la, b = pb / lb;
    const glm::vec3 c = glm::cross(a, b);
    const float s = glm::length(c);
    if (!(s >= 1e-12f)) continue;
    const float theta = std::atan2(s, glm::dot(a, b));
    sum += theta * glm::dot(c / s, n);
  }
  return 0.5f * std::abs(sum);
}

}  // namespace voxgi::scene

#include "support/cpu_voxelizer.h"

#include <algorithm>
#include <cmath>

namespace voxgi::test {
namespace {

// Projects the triangle (relative to the box centre) and the box (half size h)
// onto axis; true if the intervals are disjoint.
bool separated(const glm::dvec3& axis, const glm::dvec3& v0, const glm::dvec3& v1,
               const glm::dvec3& v2, const glm::dvec3& h) {
  const double len2 = glm::dot(axis, axis);
  if (len2 < 1e-30) return false;  // degenerate axis: no information
  const double p0 = glm::dot(axis, v0), p1 = glm::dot(axis, v1), p2 = glm::dot(axis, v2);
  const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
  return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

}  // namespace

bool triangleOverlapsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                         const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 center = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const glm::dvec3 v0 = a - center, v1 = b - center, v2 = c - center;
  const glm::dvec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const glm::dvec3& u : axes)
    if (separated(u, v0, v1, v2, h)) return false;
  if (separated(glm::cross(e[0], e[1]), v0, v1, v2, h)) return false;
  for (const glm::dvec3& edge : e)
    for (const glm::dvec3& u : axes)
      if (separated(glm::cross(edge, u), v0, v1, v2, h)) return false;
  return true;
}

std::vector<uint8_t> cpuVoxelize(const scene::Scene& s, int n) {
  std::vector<uint8_t> grid(static_cast<size_t>(n) * n * n, 0);
  const glm::dvec3 origin(s.scale.gridOrigin);
  const double size = static_cast<double>(s.scale.gridSize) / n;
  for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k)
      p[k] =
          (glm::dvec3(s.vertices[s.indices[t + static_cast<size_t>(k)]].position) - origin) / size;
    const glm::dvec3 lo = glm::min(p[0], glm::min(p[1], p[2]));
    const glm::dvec3 hi = glm::max(p[0], glm::max(p[1], p[2]));
    const glm::ivec3 i0 = glm::clamp(glm::ivec3(glm::floor(lo)), 0, n - 1);
    const glm::ivec3 i1 = glm::clamp(glm::ivec3(glm::floor(hi)), 0, n - 1);
    for (int z = i0.z; z <= i1.z; ++z)
      for (int y = i0.y; y <= i1.y; ++y)
        for (int x = i0.x; x <= i1.x; ++x) {
          const size_t idx =
              static_cast<size_t>(x) +
              static_cast<size_t>(n) *
                  (static_cast<size_t>(y) + static_cast<size_t>(n) * static_cast<size_t>(z));
          if (grid[idx]) continue;
          const glm::dvec3 vlo(x, y, z);
          if (triangleOverlapsBox(p[0], p[1], p[2], vlo, vlo + 1.0)) grid[idx] = 1;
        }
  }
  return grid;
}

std::vector<uint8_t> occupancyFromAlbedo(const std::vector<uint8_t>& rgba) {
  std::vector<uint8_t> out(rgba.size() / 4);
  for (size_t i = 0; i < out.size(); ++i) out[i] = rgba[i * 4 + 3] > 0 ? 1 : 0;
  return out;
}

bool reachableFromOutside(const std::vector<uint8_t>& occupied, int n, glm::ivec3 inside) {
  std::vector<uint8_t> seen(occupied.size(), 0);
  std::vector<glm::ivec3> stack;
  auto index = [n](glm::ivec3 p) {
    return static_cast<size_t>(p.x) +
           static_cast<size_t>(n) *
               (static_cast<size_t>(p.y) + static_cast<size_t>(n) * static_cast<size_t>(p.z));
  };
  auto push = [&](glm::ivec3 p) {
    if (glm::any(glm::lessThan(p, glm::ivec3(0))) ||
        glm::any(glm::greaterThanEqual(p, glm::ivec3(n))))
      return;
    const size_t i = index(p);
    if (seen[i] || occupied[i]) return;
    seen[i] = 1;
    stack.push_back(p);
  };
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      push({a, b, 0});
      push({a, b, n - 1});
      push({a, 0, b});
      push({a, n - 1, b});
      push({0, a, b});
      push({n - 1, a, b});
    }
  const glm::ivec3 steps[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  while (!stack.empty()) {
    const glm::ivec3 p = stack.back();
    stack.pop_back();
    if (p == inside) return true;
    for (const glm::ivec3& d : steps) push(p + d);
  }
  return false;
}

}  // namespace voxgi::test

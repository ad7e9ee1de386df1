#include "scene/tangents.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

namespace voxgi::scene {

namespace {

// Corners pool by exact position, normal and UV (bit for bit) and UV orientation.
struct CornerKey {
  float v[8];
  int orientation;
  bool operator<(const CornerKey& o) const {
    const int c = std::memcmp(v, o.v, sizeof(v));
    return c != 0 ? c < 0 : orientation < o.orientation;
  }
};

glm::vec3 projectOut(const glm::vec3& t, const glm::vec3& n) {
  return t - n * glm::dot(n, t);
}

}  // namespace

glm::vec3 anyPerpendicular(const glm::vec3& n) {
  const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0, 1, 0);
  const glm::vec3 t = projectOut(a, n);
  const float len = glm::length(t);
  return len > 0.0f ? t / len : glm::vec3(1.0f, 0.0f, 0.0f);
}

std::vector<glm::vec4> generateTangents(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& normals,
                                        const std::vector<glm::vec2>& uvs,
                                        const std::vector<uint32_t>& indices) {
  const size_t corners = indices.size() / 3 * 3;
  // Per corner: the face's tangent direction projected into the corner's normal
  // plane, times the corner's angle; the face's UV orientation (+1, -1; 0: none).
  std::vector<glm::vec3> weighted(corners, glm::vec3(0.0f));
  std::vector<float> angle(corners, 0.0f);
  std::vector<int> orientation(corners, 0);
  for (size_t f = 0; f < corners; f += 3) {
    const uint32_t i[3] = {indices[f], indices[f + 1], indices[f + 2]};
    const glm::vec3 d1 = positions[i[1]] - positions[i[0]];
    const glm::vec3 d2 = positions[i[2]] - positions[i[0]];
    const glm::vec2 s1 = uvs[i[1]] - uvs[i[0]];
    const glm::vec2 s2 = uvs[i[2]] - uvs[i[0]];
    // P - P0 = T (u - u0) + B (v - v0) over the triangle: T = (s2.y d1 - s1.y d2) / det,
    // B = (s1.x d2 - s2.x d1) / det. Only directions matter, so scale by sign(det).
    const float det = s1.x * s2.y - s1.y * s2.x;
    if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) continue;
    const float sign = det > 0.0f ? 1.0f : -1.0f;
    const glm::vec3 faceT = sign * (s2.y * d1 - s1.y * d2);
    const glm::vec3 faceB = sign * (s1.x * d2 - s2.x * d1);
    if (!(glm::dot(faceT, faceT) > 0.0f)) continue;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = normals[i[k]];
      const glm::vec3 t = projectOut(faceT, n);
      const float tl = glm::length(t);
      if (!(tl > 0.0f) || !std::isfinite(tl)) continue;
      // The corner's angle, between its two edges as seen along the normal.
      glm::vec3 ea = projectOut(positions[i[(k + 1) % 3]] - positions[i[k]], n);
      glm::vec3 eb = projectOut(positions[i[(k + 2) % 3]] - positions[i[k]], n);
      const float la = glm::length(ea), lb = glm::length(eb);
      float a = 0.0f;
      if (la > 0.0f && lb > 0.0f)
        a = std::acos(std::clamp(glm::dot(ea / la, eb / lb), -1.0f, 1.0f));
      if (!(a > 0.0f)) continue;
      const size_t c = f + static_cast<size_t>(k);
      weighted[c] = t / tl * a;
      angle[c] = a;
      orientation[c] = glm::dot(glm::cross(n, faceT), faceB) >= 0.0f ? 1 : -1;
    }
  }
  // Pool corners that share position, normal, UV and orientation.
  std::map<CornerKey, glm::vec3> pooled;
  auto keyOf = [&](size_t c, int o) {
    const uint32_t v = indices[c];
    CornerKey key{};
    const float raw[8] = {positions[v].x, positions[v].y, positions[v].z, normals[v].x,
                          normals[v].y,   normals[v].z,   uvs[v].x,       uvs[v].y};
    std::memcpy(key.v, raw, sizeof(raw));
    key.orientation = o;
    return key;
  };
  for (size_t c = 0; c < corners; ++c)
    if (orientation[c] != 0) pooled[keyOf(c, orientation[c])] += weighted[c];
  // Per vertex, the orientation with the larger angle sum.
  std::vector<float> plus(positions.size(), 0.0f), minus(positions.size(), 0.0f);
  for (size_t c = 0; c < corners; ++c) {
    if (orientation[c] > 0) plus[indices[c]] += angle[c];
    if (orientation[c] < 0) minus[indices[c]] += angle[c];
  }
  std::vector<glm::vec4> out(positions.size());
  for (size_t v = 0; v < positions.size(); ++v)
    out[v] = glm::vec4(anyPerpendicular(normals[v]), 1.0f);
  for (size_t c = 0; c < corners; ++c) {
    const uint32_t v = indices[c];
    const int o = plus[v] >= minus[v] ? 1 : -1;
    if (orientation[c] != o) continue;
    const glm::vec3 t = projectOut(pooled[keyOf(c, o)], normals[v]);  // Gram-Schmidt
    const float len = glm::length(t);
    if (len > 0.0f && std::isfinite(len)) out[v] = glm::vec4(t / len, static_cast<float>(o));
  }
  return out;
}

}  // namespace voxgi::scene

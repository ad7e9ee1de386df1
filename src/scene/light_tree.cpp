#include "scene/light_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

#include "brdf_shared.h"

namespace voxgi::scene {
namespace {

constexpr float kPi = 3.14159265358979f;

struct NodeBounds {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;
  glm::vec3 axis{0.0f, 0.0f, 1.0f};
  float spread = 0.0f;  // the cone's half-angle
  double power = 0.0;
};

bool isCluster(const gpu::GpuEmitter& e) {
  return e.kind == gpu::kEmitterCluster;
}

// A leaf: a cluster's disk, or a triangle, around a centre on its own plane (so that
// a point in front of the emitter lies within 90 degrees of its axis, as seen from
// that centre).
NodeBounds leafBounds(const gpu::GpuEmitter& e) {
  NodeBounds b;
  b.power = emitterPower(e);
  const bool twoSided = e.twoSided != 0u;
  if (isCluster(e)) {
    b.centre = glm::vec3(e.a);
    b.radius = std::sqrt(std::max(e.area, 0.0f) / kPi);
    b.axis = glm::vec3(e.b);
  } else {
    const glm::vec3 v0(e.a), v1(e.b), v2(e.c);
    b.centre = (v0 + v1 + v2) / 3.0f;
    b.radius = std::max(
        {glm::length(v0 - b.centre), glm::length(v1 - b.centre), glm::length(v2 - b.centre)});
    const glm::vec3 n = glm::cross(v1 - v0, v2 - v0);
    const float len = glm::length(n);
    b.axis = len > 0.0f ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  const float len = glm::length(b.axis);
  if (!(len > 0.0f) || !std::isfinite(len)) {
    b.axis = glm::vec3(0.0f, 0.0f, 1.0f);
    b.spread = kPi;
  } else {
    b.axis /= len;
    b.spread = twoSided ? kPi : 0.0f;
  }
  return b;
}

float angleBetween(glm::vec3 a, glm::vec3 b) {
  return 2.0f * std::asin(std::clamp(0.5f * glm::length(a - b), 0.0f, 1.0f));
}

// The bounds of leaves[order[begin..end)]: the sphere centred in their spheres' box,
// out to the farthest of them; the cone around their mean direction, out to the
// widest of them; their summed power. Computed from the leaves themselves, not
// from the children's bounds, which would widen at every level.
NodeBounds enclose(const std::vector<NodeBounds>& leaves, const std::vector<int>& order,
                   size_t begin, size_t end) {
  glm::vec3 lo(INFINITY), hi(-INFINITY), axis(0.0f);
  NodeBounds out;
  bool everyWay = false;
  for (size_t i = begin; i < end; ++i) {
    const NodeBounds& l = leaves[static_cast<size_t>(order[i])];
    lo = glm::min(lo, l.centre - l.radius);
    hi = glm::max(hi, l.centre + l.radius);
    axis += l.axis;
    everyWay = everyWay || l.spread >= kPi;
    out.power += l.power;
  }
  out.centre = 0.5f * (lo + hi);
  const float len = glm::length(axis);
  everyWay = everyWay || !(len > 1e-4f);
  out.axis = everyWay ? glm::vec3(0.0f, 0.0f, 1.0f) : axis / len;
  out.spread = everyWay ? kPi : 0.0f;
  for (size_t i = begin; i < end; ++i) {
    const NodeBounds& l = leaves[static_cast<size_t>(order[i])];
    out.radius = std::max(out.radius, glm::length(l.centre - out.centre) + l.radius);
    if (!everyWay) out.spread = std::max(out.spread, angleBetween(out.axis, l.axis) + l.spread);
  }
  // Widened a little, so that rounding never leaves a leaf's point or direction out.
  out.radius *= 1.0001f;
  out.spread = std::min(out.spread * 1.0001f + 1e-5f, kPi);
  return out;
}

// info: power, first child (an inner node) or emitter (a leaf), where the node's
// leaves begin in the leaf section, how many there are.
gpu::GpuLightNode pack(const NodeBounds& b, int first, size_t leavesBegin, size_t count) {
  gpu::GpuLightNode n{};
  n.sphere = glm::vec4(b.centre, b.radius);
  n.cone = glm::vec4(b.axis, std::cos(b.spread));
  n.info = glm::vec4(static_cast<float>(b.power), static_cast<float>(first),
                     static_cast<float>(leavesBegin), static_cast<float>(count));
  return n;
}

struct Builder {
  const std::vector<NodeBounds>& leaves;
  std::vector<gpu::GpuLightNode>& nodes;
  size_t leafSection;  // where the leaves, in tree order, begin

  // Fills node `at` with emitters order[begin, end). Each step sorts the range in
  // place, so that a node's emitters are order[begin, end) once the build is done:
  // the leaf section holds them in that order.
  void build(int at, std::vector<int>& order, size_t begin, size_t end) {
    if (end - begin == 1) {
      nodes[at] =
          pack(leaves[static_cast<size_t>(order[begin])], order[begin], leafSection + begin, 1);
      return;
    }
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (size_t i = begin; i < end; ++i) {
      lo = glm::min(lo, leaves[order[i]].centre);
      hi = glm::max(hi, leaves[order[i]].centre);
    }
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                     : extent.y >= extent.z                       ? 1
                                                                  : 2;
    const size_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(begin),
                     order.begin() + static_cast<std::ptrdiff_t>(mid),
                     order.begin() + static_cast<std::ptrdiff_t>(end), [&](int x, int y) {
                       const float cx = leaves[x].centre[axis], cy = leaves[y].centre[axis];
                       return cx < cy || (cx == cy && x < y);
                     });
    const int first = static_cast<int>(nodes.size());
    nodes.resize(nodes.size() + 2);
    build(first, order, begin, mid);
    build(first + 1, order, mid, end);
    nodes[at] = pack(enclose(leaves, order, begin, end), first, leafSection + begin, end - begin);
  }
};

}  // namespace

double emitterPower(const gpu::GpuEmitter& e) {
  const double area = isCluster(e) ? e.area
                                   : 0.5 * glm::length(glm::cross(glm::vec3(e.b) - glm::vec3(e.a),
                                                                  glm::vec3(e.c) - glm::vec3(e.a)));
  const double lum = gpu::luminance(glm::vec3(e.radiance));
  const double p = std::max(0.0, lum * area * (e.twoSided != 0u ? 2.0 : 1.0));
  return std::isfinite(p) ? p : 0.0;
}

std::vector<gpu::GpuLightNode> buildLightTree(const std::vector<gpu::GpuEmitter>& emitters) {
  std::vector<gpu::GpuLightNode> nodes;
  if (emitters.empty()) return nodes;
  std::vector<NodeBounds> leaves;
  leaves.reserve(emitters.size());
  for (const gpu::GpuEmitter& e : emitters) leaves.push_back(leafBounds(e));
  std::vector<int> order(emitters.size());
  std::iota(order.begin(), order.end(), 0);
  const size_t treeSize = 2 * emitters.size() - 1;
  nodes.reserve(treeSize + emitters.size());
  nodes.resize(1);
  Builder{leaves, nodes, treeSize}.build(0, order, 0, order.size());
  for (size_t i = 0; i < order.size(); ++i)
    nodes.push_back(pack(leaves[static_cast<size_t>(order[i])], order[i], treeSize + i, 1));
  return nodes;
}

std::vector<gpu::GpuEmitter> packEmitters(const std::vector<Emitter>& emitters) {
  std::vector<gpu::GpuEmitter> out;
  for (const Emitter& e : emitters) {
    gpu::GpuEmitter g{};
    g.a = e.v0;
    if (e.kind == Emitter::Kind::kCluster) {
      g.kind = gpu::kEmitterCluster;
      g.b = e.normal;
      g.area = e.area;
    } else {
      g.kind = gpu::kEmitterTriangle;
      g.b = e.v1;
      g.c = e.v2;
    }
    g.radiance = e.radiance;
    g.twoSided = e.twoSided ? 1u : 0u;
    out.push_back(g);
  }
  return out;
}

std::vector<float> emitterPowerCdf(const std::vector<gpu::GpuEmitter>& emitters) {
  std::vector<float> cdf;
  double total = 0.0;
  std::vector<double> power;
  for (const gpu::GpuEmitter& e : emitters) {
    power.push_back(emitterPower(e));
    total += power.back();
  }
  double run = 0.0;
  for (size_t i = 0; i < power.size(); ++i) {
    run += power[i];
    // Emitters of no power at all are chosen uniformly.
    cdf.push_back(total > 0.0 ? static_cast<float>(run / total)
                              : static_cast<float>(i + 1) / static_cast<float>(power.size()));
  }
  if (!cdf.empty()) cdf.back() = 1.0f;
  return cdf;
}

}  // namespace voxgi::scene

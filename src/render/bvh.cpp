#include "render/bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/log.h"

namespace voxgi::render {
namespace {

constexpr int kMedianSplitDepth = 24;  // below this depth, split at the median: depth stays bounded
// Ranges above this many triangles bin in parallel chunks, and the build hands the
// subtrees below its frontier (ranges of at most 1/kFrontierShare of the triangles,
// and no fewer than kMinJob) to the worker threads.
constexpr uint32_t kParallelBinning = 1u << 16;
constexpr uint32_t kFrontierShare = 32;
constexpr uint32_t kMinJob = 1u << 12;
// Ranges of at most this many triangles find their split without bins (sweepSmall).
constexpr uint32_t kSmallRange = 16;

// Four floats in one register (GCC and Clang vector extensions, on every target);
// the builder's boxes keep x, y, z in the first three and 0 in the last.
using F4 = float __attribute__((vector_size(16)));
using I4 = int32_t __attribute__((vector_size(16)));
// The operand order of glm::min/max, so that signed zeros come out as they did.
inline F4 vmin(F4 acc, F4 v) {
  return v < acc ? v : acc;
}
inline F4 vmax(F4 acc, F4 v) {
  return acc < v ? v : acc;
}
inline glm::vec3 xyz(F4 v) {
  return {v[0], v[1], v[2]};
}

struct Box {
  F4 lo = {1e30f, 1e30f, 1e30f, 0.0f}, hi = {-1e30f, -1e30f, -1e30f, 0.0f};
  void extend(F4 p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  void extend(const Box& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  bool empty() const { return lo[0] > hi[0]; }
  float area() const {
    if (empty()) return 0.0f;
    const F4 d = hi - lo;
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
};

float bitsToFloat(uint32_t u) {
  return std::bit_cast<float>(u);
}

// One triangle as the build moves it, 32 bytes, so that every pass over a range
// reads memory in order: its bounds, and its input index in the bits of lo's last
// lane (masked off before any arithmetic).
struct Prim {
  F4 lo, hi;
  F4 low() const { return std::bit_cast<F4>(std::bit_cast<I4>(lo) & I4{-1, -1, -1, 0}); }
  uint32_t index() const { return std::bit_cast<uint32_t>(lo[3]); }
  F4 centroid() const { return 0.5f * (low() + hi); }
  Box box() const { return {low(), hi}; }
};

// Per axis and bin: the union of the boxes and the number of triangles whose
// centroid falls in it. Only the first nb bins of each axis are set, so that a
// small range doesn't pay for clearing kMax (no initialisers for that reason).
struct Bins {
  static constexpr int kMax = 64;
  F4 lo[3][kMax], hi[3][kMax];
  uint32_t count[3][kMax];
  explicit Bins(int nb) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < nb; ++b) {
        lo[a][b] = Box{}.lo;
        hi[a][b] = Box{}.hi;
        count[a][b] = 0;
      }
  }
  Box box(int a, int b) const { return {lo[a][b], hi[a][b]}; }
  void add(int a, int b, F4 plo, F4 phi) {
    lo[a][b] = vmin(lo[a][b], plo);
    hi[a][b] = vmax(hi[a][b], phi);
    ++count[a][b];
  }
  void merge(const Bins& o, int nb) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < nb; ++b) {
        lo[a][b] = vmin(lo[a][b], o.lo[a][b]);
        hi[a][b] = vmax(hi[a][b], o.hi[a][b]);
        count[a][b] += o.count[a][b];
      }
  }
};

// A range of prims with its bounds and the bounds of its centroids.
struct Range {
  uint32_t begin = 0, end = 0;
  Box box, cbox;
  uint32_t count() const { return end - begin; }
};

// A child while the build runs: its bounds and what it is: the first of `count`
// prims (a leaf), a node, or above the frontier a job (a subtree built by a worker).
struct ChildRef {
  enum Kind : uint8_t { kLeaf, kInterior, kJob };
  Box box;
  uint32_t index = 0, count = 0;
  Kind kind = kLeaf;
};
// A node above the frontier.
struct TopNode {
  ChildRef left, right;
};

class Builder {
 public:
  Builder(const Bvh::Options& options, std::vector<Prim>* prims)
      : options_(options), prims_(*prims) {}

  // Builds the whole tree into nodes in depth-first order, parent first, as a
  // single-threaded recursive build allocates them; *root is the root's reference
  // (interior: node 0; or a leaf when the range is one).
  BvhNodes build(const Range& range, ChildRef* root) {
    frontier_ = std::max(kMinJob, range.count() / kFrontierShare);
    const ChildRef top = recurseTop(range, 1);
    // Depth-first layout: the top nodes, and for each job a region of count - 1
    // nodes (as many as a subtree of count triangles can have), which its worker
    // fills in place. The output is not initialised: nothing is written twice.
    topIndex_.resize(topNodes_.size());
    uint32_t next = 0;
    layout(top, &next);
    BvhNodes out;
    out.resize(next);
    tbb::parallel_for(
        size_t{0}, jobs_.size(),
        [&](size_t j) {
          Job& job = jobs_[j];
          job.root = recurseJob(job.range, job.level, out.data(), job.base, &job.used);
        },
        tbb::simple_partitioner());
    for (size_t i = 0; i < topNodes_.size(); ++i) {
      const ChildRef l = resolve(topNodes_[i].left), r = resolve(topNodes_[i].right);
      out[topIndex_[i]] = makeNode(l, l.index, r, r.index);
    }
    *root = resolve(top);
    compact(&out);
    return out;
  }

 private:
  struct Job {
    Range range;
    int level = 0;
    uint32_t base = 0, used = 0;  // its region of the output, and how much it filled
    ChildRef root;
    uint32_t reserved() const { return std::max(range.count(), 1u) - 1; }
  };

  // Above the frontier: ranges at most frontier_ large become jobs.
  ChildRef recurseTop(const Range& r, int level) {
    ChildRef ref;
    ref.box = r.box;
    if (r.count() <= frontier_) {
      ref.kind = ChildRef::kJob;
      ref.index = static_cast<uint32_t>(jobs_.size());
      jobs_.push_back({r, level, 0, 0, {}});
      return ref;
    }
    Range left, right;
    if (!split(r, level, true, &left, &right)) {
      ref.index = r.begin;
      ref.count = r.count();
      return ref;
    }
    const auto node = static_cast<uint32_t>(topNodes_.size());
    topNodes_.emplace_back();
    const ChildRef l = recurseTop(left, level + 1);
    const ChildRef rr = recurseTop(right, level + 1);
    topNodes_[node] = {l, rr};
    ref.kind = ChildRef::kInterior;
    ref.index = node;
    return ref;
  }

  // A job's subtree, into out from base on, depth first.
  ChildRef recurseJob(const Range& r, int level, gpu::GpuBvhNode* out, uint32_t base,
                      uint32_t* used) {
    ChildRef ref;
    ref.box = r.box;
    Range left, right;
    if (!split(r, level, false, &left, &right)) {
      ref.index = r.begin;
      ref.count = r.count();
      return ref;
    }
    const uint32_t node = base + (*used)++;
    const ChildRef l = recurseJob(left, level + 1, out, base, used);
    const ChildRef rr = recurseJob(right, level + 1, out, base, used);
    out[node] = makeNode(l, l.index, rr, rr.index);
    ref.kind = ChildRef::kInterior;
    ref.index = node;
    return ref;
  }

  // Splits r into two ranges; false for a leaf.
  bool split(const Range& r, int level, bool parallel, Range* left, Range* right) {
    const uint32_t count = r.count();
    if (count <= 1) return false;
    const Box& cb = r.cbox;
    const F4 extent = cb.hi - cb.lo;
    int axis = 0;
    if (extent[1] > extent[axis]) axis = 1;
    if (extent[2] > extent[axis]) axis = 2;
    const bool big = count > static_cast<uint32_t>(options_.maxLeafSize);
    if (!(extent[axis] > 0.0f)) {  // every centroid in one point: only size forces a split
      if (!big) return false;
      return finish(r, r.begin + count / 2, left, right);
    }
    if (level >= kMedianSplitDepth) return big && median(r, axis, left, right);

    const int nb = std::min(options_.bins, Bins::kMax);
    F4 scale = {};
    for (int a = 0; a < 3; ++a)
      if (extent[a] > 0.0f) scale[a] = static_cast<float>(nb) / extent[a];
    const Best best = count <= kSmallRange ? sweepSmall(r, extent, scale, nb)
                                           : sweepBins(r, extent, scale, nb, parallel);
    if (best.axis < 0) return big && median(r, axis, left, right);
    const float leafCost = static_cast<float>(count);
    const float splitCost = options_.traversalCost + best.cost / std::max(r.box.area(), 1e-30f);
    if (!big && leafCost <= splitCost) return false;
    const float lo = cb.lo[best.axis], s = scale[best.axis];
    const uint32_t m = partition(
        r, [&](const Prim& p) { return binOf(p, best.axis, lo, s, nb) < best.bin; }, left, right);
    // Float rounding put everything on one side.
    if (m == r.begin || m == r.end) return median(r, axis, left, right);
    return true;
  }

  // Moves the prims of r for which goesLeft holds before the others (the swaps of
  // std::partition), and bounds the two sides on the way. Returns where the right
  // side starts.
  template <typename Pred>
  uint32_t partition(const Range& r, Pred goesLeft, Range* left, Range* right) {
    Range lr{r.begin, r.begin, {}, {}}, rr{r.end, r.end, {}, {}};
    auto take = [](Range* side, const Prim& p) {
      side->box.extend(p.box());
      side->cbox.extend(p.centroid());
    };
    uint32_t first = r.begin, last = r.end;
    for (;;) {
      while (first < last && goesLeft(prims_[first])) take(&lr, prims_[first++]);
      while (first < last && !goesLeft(prims_[last - 1])) take(&rr, prims_[--last]);
      if (first == last) break;
      std::swap(prims_[first], prims_[last - 1]);
      take(&lr, prims_[first++]);
      take(&rr, prims_[--last]);
    }
    lr.end = first;
    rr.begin = first;
    *left = lr;
    *right = rr;
    return first;
  }

  // The cheapest split between bins: its SAH cost (un-normalised) and where.
  struct Best {
    float cost = 1e30f;
    int axis = -1, bin = -1;  // left: the triangles whose centroid bin < bin
  };
  static int binOf(const Prim& p, int a, float lo, float scale, int nb) {
    return std::min(nb - 1, static_cast<int>((p.centroid()[a] - lo) * scale));
  }

  // Sweeps the bins of every axis, splitting between bin b-1 and b, first axis and
  // bin on ties.
  Best sweepBins(const Range& r, F4 extent, F4 scale, int nb, bool parallel) const {
    const F4 lo = r.cbox.lo;
    const Bins bins =
        parallel && r.count() > kParallelBinning
            ? tbb::parallel_reduce(
                  tbb::blocked_range<uint32_t>(r.begin, r.end, kParallelBinning / 4), Bins(nb),
                  [&](const tbb::blocked_range<uint32_t>& sub, Bins acc) {
                    bin(sub.begin(), sub.end(), lo, scale, extent, nb, &acc);
                    return acc;
                  },
                  [nb](Bins x, const Bins& y) {
                    x.merge(y, nb);
                    return x;
                  })
            : binRange(r.begin, r.end, lo, scale, extent, nb);
    Best best;
    float rightArea[Bins::kMax];
    uint32_t rightCount[Bins::kMax];
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      Box rb;
      uint32_t rc = 0;
      for (int b = nb - 1; b > 0; --b) {
        rb.extend(bins.box(a, b));
        rc += bins.count[a][b];
        rightArea[b] = rb.area();
        rightCount[b] = rc;
      }
      Box lb;
      uint32_t lc = 0;
      for (int b = 1; b < nb; ++b) {
        lb.extend(bins.box(a, b - 1));
        lc += bins.count[a][b - 1];
        if (lc == 0 || rightCount[b] == 0) continue;
        const float cost =
            lb.area() * static_cast<float>(lc) + rightArea[b] * static_cast<float>(rightCount[b]);
        if (cost < best.cost) best = {cost, a, b};
      }
    }
    return best;
  }

  // The same choice as sweepBins for a few triangles, without the bins: sorted by
  // bin, a split can only change between two occupied bins, and the first bin after
  // an occupied one is where sweepBins meets that split first. The boxes are unions
  // of the same boxes, so the costs are the same floats.
  Best sweepSmall(const Range& r, F4 extent, F4 scale, int nb) const {
    const uint32_t n = r.count();
    Best best;
    // Sort keys: bin x kSmallRange + position in r.
    static_assert(kSmallRange <= 32);
    std::array<uint32_t, kSmallRange> order;
    std::array<Box, kSmallRange> right;  // right[i]: the prims order[i..] hold
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      for (uint32_t i = 0; i < n; ++i) {
        const auto b =
            static_cast<uint32_t>(binOf(prims_[r.begin + i], a, r.cbox.lo[a], scale[a], nb));
        order[i] = b * 32u + i;
      }
      std::sort(order.begin(), order.begin() + n);
      auto prim = [&](uint32_t i) -> const Prim& { return prims_[r.begin + (order[i] & 31u)]; };
      Box rb;
      for (uint32_t i = n; i-- > 0;) {
        rb.extend(prim(i).box());
        right[i] = rb;
      }
      Box lb;
      for (uint32_t i = 0; i + 1 < n; ++i) {
        lb.extend(prim(i).box());
        const uint32_t bin = order[i] >> 5u;
        if (bin == order[i + 1] >> 5u) continue;
        const float cost = lb.area() * static_cast<float>(i + 1) +
                           right[i + 1].area() * static_cast<float>(n - i - 1);
        if (cost < best.cost) best = {cost, a, static_cast<int>(bin) + 1};
      }
    }
    return best;
  }

  void bin(uint32_t begin, uint32_t end, F4 lo, F4 scale, F4 extent, int nb, Bins* bins) const {
    const bool axes[3] = {extent[0] > 0.0f, extent[1] > 0.0f, extent[2] > 0.0f};
    const I4 last = {nb - 1, nb - 1, nb - 1, nb - 1};
    for (uint32_t i = begin; i < end; ++i) {
      const Prim& p = prims_[i];
      const F4 plo = p.low(), phi = p.hi;
      I4 b = __builtin_convertvector((0.5f * (plo + phi) - lo) * scale, I4);  // binOf, 3 lanes
      b = b < last ? b : last;
      for (int a = 0; a < 3; ++a)
        if (axes[a]) bins->add(a, b[a], plo, phi);
    }
  }
  Bins binRange(uint32_t begin, uint32_t end, F4 lo, F4 scale, F4 extent, int nb) const {
    Bins b(nb);
    bin(begin, end, lo, scale, extent, nb, &b);
    return b;
  }

  bool median(const Range& r, int axis, Range* left, Range* right) {
    const uint32_t mid = r.begin + r.count() / 2;
    std::nth_element(
        prims_.begin() + r.begin, prims_.begin() + mid, prims_.begin() + r.end,
        [axis](const Prim& a, const Prim& b) { return a.centroid()[axis] < b.centroid()[axis]; });
    return finish(r, mid, left, right);
  }

  // The two halves of r split at m, with their bounds.
  bool finish(const Range& r, uint32_t m, Range* left, Range* right) const {
    *left = bounded(r.begin, m);
    *right = bounded(m, r.end);
    return true;
  }
  Range bounded(uint32_t begin, uint32_t end) const {
    auto extend = [this](uint32_t b, uint32_t e, Range acc) {
      for (uint32_t i = b; i < e; ++i) {
        acc.box.extend(prims_[i].box());
        acc.cbox.extend(prims_[i].centroid());
      }
      return acc;
    };
    if (end - begin <= kParallelBinning) return extend(begin, end, {begin, end, {}, {}});
    return tbb::parallel_reduce(
        tbb::blocked_range<uint32_t>(begin, end, kParallelBinning / 4), Range{begin, end, {}, {}},
        [&](const tbb::blocked_range<uint32_t>& sub, Range acc) {
          return extend(sub.begin(), sub.end(), acc);
        },
        [](Range x, const Range& y) {
          x.box.extend(y.box);
          x.cbox.extend(y.cbox);
          return x;
        });
  }

  // Numbers the top nodes under c depth first from *next, with each job's region
  // where its subtree goes.
  void layout(const ChildRef& c, uint32_t* next) {
    if (c.kind == ChildRef::kJob) {
      jobs_[c.index].base = *next;
      *next += jobs_[c.index].reserved();
    } else if (c.kind == ChildRef::kInterior) {
      topIndex_[c.index] = (*next)++;
      layout(topNodes_[c.index].left, next);
      layout(topNodes_[c.index].right, next);
    }
  }

  // c as its parent stores it: a job replaced by its subtree's root, a top node by
  // its index in the output.
  ChildRef resolve(const ChildRef& c) const {
    if (c.kind == ChildRef::kJob) return jobs_[c.index].root;
    ChildRef r = c;
    if (c.kind == ChildRef::kInterior) r.index = topIndex_[c.index];
    return r;
  }

  // Closes the gaps jobs left in their regions (leaves of more than one triangle:
  // fewer nodes than reserved), keeping the order; none with one-triangle leaves.
  void compact(BvhNodes* out) const {
    std::vector<uint32_t> start, end,
        shift;  // a gap [start, end); indices past end move down by shift
    uint32_t total = 0;
    for (const Job& j : jobs_) {
      if (j.used == j.reserved()) continue;
      total += j.reserved() - j.used;
      start.push_back(j.base + j.used);
      end.push_back(j.base + j.reserved());
      shift.push_back(total);
    }
    if (total == 0) return;
    auto moved = [&](uint32_t i) {
      const auto k = std::upper_bound(end.begin(), end.end(), i) - end.begin();
      return k == 0 ? i : i - shift[static_cast<size_t>(k - 1)];
    };
    size_t gap = 0;
    for (uint32_t i = 0; i < out->size();) {
      if (gap < start.size() && i == start[gap]) {
        i = end[gap++];
        continue;
      }
      gpu::GpuBvhNode n = (*out)[i];
      if (std::bit_cast<uint32_t>(n.leftMax.w) == 0)
        n.leftMin.w = bitsToFloat(moved(std::bit_cast<uint32_t>(n.leftMin.w)));
      if (std::bit_cast<uint32_t>(n.rightMax.w) == 0)
        n.rightMin.w = bitsToFloat(moved(std::bit_cast<uint32_t>(n.rightMin.w)));
      (*out)[moved(i)] = n;
      ++i;
    }
    out->resize(out->size() - total);
  }

 public:
  static gpu::GpuBvhNode makeNode(const ChildRef& l, uint32_t li, const ChildRef& r, uint32_t ri) {
    gpu::GpuBvhNode n{};
    n.leftMin = glm::vec4(xyz(l.box.lo), bitsToFloat(li));
    n.leftMax = glm::vec4(xyz(l.box.hi), bitsToFloat(l.kind == ChildRef::kLeaf ? l.count : 0u));
    n.rightMin = glm::vec4(xyz(r.box.lo), bitsToFloat(ri));
    n.rightMax = glm::vec4(xyz(r.box.hi), bitsToFloat(r.kind == ChildRef::kLeaf ? r.count : 0u));
    return n;
  }

 private:
  const Bvh::Options& options_;
  std::vector<Prim>& prims_;
  uint32_t frontier_ = 0;
  std::vector<TopNode> topNodes_;
  std::vector<uint32_t> topIndex_;  // of each top node in the output
  std::vector<Job> jobs_;
};

// The depth (root = 1, leaves count) and the un-normalised SAH cost (sum of area x
// cost) of the subtree under interior node i at `level`, depth first, parent first.
void measure(const BvhNodes& nodes, uint32_t i, int level, float traversalCost, int* depth,
             double* sah) {
  *depth = std::max(*depth, level);
  const gpu::GpuBvhNode& n = nodes[i];
  for (int side = 0; side < 2; ++side) {
    const glm::vec4& lo = side ? n.rightMin : n.leftMin;
    const glm::vec4& hi = side ? n.rightMax : n.leftMax;
    const uint32_t count = std::bit_cast<uint32_t>(hi.w);
    const float area = Box{F4{lo.x, lo.y, lo.z, 0.0f}, F4{hi.x, hi.y, hi.z, 0.0f}}.area();
    if (count > 0) {
      *depth = std::max(*depth, level + 1);
      *sah += static_cast<double>(area) * count;
    } else {
      *sah += static_cast<double>(area) * traversalCost;
      measure(nodes, std::bit_cast<uint32_t>(lo.w), level + 1, traversalCost, depth, sah);
    }
  }
}

}  // namespace

bool intersectTriangle(const BvhRay& ray, const glm::vec3& v0, const glm::vec3& e1,
                       const glm::vec3& e2, float* t, float* u, float* v) {
  const glm::vec3 p = glm::cross(ray.direction, e2);
  const float det = glm::dot(e1, p);
  const float inv = 1.0f / det;
  const glm::vec3 s = ray.origin - v0;
  const float uu = glm::dot(s, p) * inv;
  const glm::vec3 q = glm::cross(s, e1);
  const float vv = glm::dot(ray.direction, q) * inv;
  const float tt = glm::dot(e2, q) * inv;
  // Written so that NaN (det == 0) fails every test.
  if (!(uu >= 0.0f && vv >= 0.0f && uu + vv <= 1.0f && tt > ray.tMin && tt < ray.tMax))
    return false;
  *t = tt;
  *u = uu;
  *v = vv;
  return true;
}

Bvh::Bvh(const std::vector<BvhTriangle>& triangles, const Options& options)
    : Bvh(
          triangles.size(), [&triangles](size_t i) { return triangles[i]; }, options) {}

Bvh::Bvh(size_t n, const std::function<BvhTriangle(size_t)>& triangle, const Options& options) {
  if (n > size_t{std::numeric_limits<uint32_t>::max()} / 2)
    throw Error(strf("BVH of %zu triangles: more than a 32-bit index can address", n));
  std::vector<Prim> prims(n);
  Range all{0, static_cast<uint32_t>(n), {}, {}};
  // Bounds of each triangle, and of them all, in parallel chunks.
  struct Bounds {
    Box box, cbox;
  };
  const Bounds b = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 1u << 14), Bounds{},
      [&](const tbb::blocked_range<size_t>& r, Bounds acc) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
          const BvhTriangle t = triangle(i);
          Prim& p = prims[i];
          const glm::vec3 lo = glm::min(glm::min(t.v0, t.v1), t.v2);
          const glm::vec3 hi = glm::max(glm::max(t.v0, t.v1), t.v2);
          p.lo = F4{lo.x, lo.y, lo.z, std::bit_cast<float>(static_cast<uint32_t>(i))};
          p.hi = F4{hi.x, hi.y, hi.z, 0.0f};
          acc.box.extend(p.box());
          acc.cbox.extend(p.centroid());
        }
        return acc;
      },
      [](Bounds x, const Bounds& y) {
        x.box.extend(y.box);
        x.cbox.extend(y.cbox);
        return x;
      });
  all.box = b.box;
  all.cbox = b.cbox;
  ChildRef root;
  if (n > 0) {
    Builder builder(options, &prims);
    nodes_ = builder.build(all, &root);
  }
  if (n == 0 || root.kind == ChildRef::kLeaf) {
    // A single leaf (or nothing): wrap it so traversal always starts at node 0.
    nodes_.insert(nodes_.begin(), Builder::makeNode(root, root.index, ChildRef{}, 0));
    depth_ = 2;
  } else {
    depth_ = 0;
  }
  double sah = static_cast<double>(all.box.area()) * options.traversalCost;
  if (n > 0 && root.kind != ChildRef::kLeaf) {
    measure(nodes_, 0, 1, options.traversalCost, &depth_, &sah);
  } else {
    sah = static_cast<double>(all.box.area()) * static_cast<double>(n);
  }
  if (depth_ > static_cast<int>(gpu::kPtStackSize))
    throw Error(strf("BVH of %zu triangles is %d levels deep, more than the traversal stack (%u)",
                     n, depth_, gpu::kPtStackSize));
  sah_ = all.box.area() > 0.0f ? sah / all.box.area() : 0.0;
  count_ = n;
  order_.resize(n);
  if (options.keepTriangles) triangles_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1u << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i) {
                        order_[i] = prims[i].index();
                        if (options.keepTriangles) triangles_[i] = gpuTriangle(triangle(order_[i]));
                      }
                    });
}

Bvh::Arrays Bvh::release() {
  Arrays a{std::move(nodes_), std::move(order_), std::move(triangles_)};
  nodes_.clear();
  order_.clear();
  triangles_.clear();
  return a;
}

template <bool kAnyHit>
bool Bvh::traverse(const BvhRay& ray, BvhHit* hit) const {
  if (nodes_.empty()) return false;
  const gpu::BvhArrays arrays{nodes_.data(), triangles_.data()};
  float t = 0.0f;
  uint32_t triangle = 0;
  glm::vec2 bary(0.0f);
  if (!gpu::bvhTrace(arrays, ray.origin, ray.direction, ray.tMin, ray.tMax, kAnyHit, t, triangle,
                     bary))
    return false;
  hit->t = t;
  hit->u = bary.x;
  hit->v = bary.y;
  hit->triangle = static_cast<int>(order_[triangle]);
  return true;
}

bool Bvh::intersect(const BvhRay& ray, BvhHit* hit) const {
  return traverse<false>(ray, hit);
}

bool Bvh::occluded(const BvhRay& ray) const {
  BvhHit unused;
  return traverse<true>(ray, &unused);
}

}  // namespace voxgi::render

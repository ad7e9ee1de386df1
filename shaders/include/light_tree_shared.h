// A light tree over the scene's emitters, for drawing one emitter per shading point
// in proportion to a bound on what it may contribute there, written once in the
// common subset of GLSL and C++ (shared_fn.h). After Conty Estevez and Kulla 2018,
// "Importance Sampling of Many Lights with Adaptive Tree Splitting": a binary tree
// whose nodes bound their emitters by a sphere (position) and a cone (the directions
// their light leaves in), with their summed power. From the root, each step picks a
// child with probability proportional to its importance at the point: power x the
// largest cosine at the emitter x the largest cosine at the receiver / distance²,
// the cosines bounded over the node's sphere and cone. An emitter facing away, or
// below the receiver's horizon, has importance 0 and is never drawn; the probability
// of the emitter reached is the product of the steps' probabilities.
//
// GLSL: the including shader defines `GpuLightNode lightTreeNode(int i)`, which reads
// node i (from the buffer bound at kLightTreeBinding), after the include; C++ passes
// the nodes as a pointer. The
// tree is built by scene::buildLightTree (src/scene/light_tree.h), whose tests
// check this traversal against the emitters' exact contributions.
#ifndef VOXGI_LIGHT_TREE_SHARED_H
#define VOXGI_LIGHT_TREE_SHARED_H

#include "sampling_shared.h"
#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// One node, 48 bytes (std430). The tree's 2n - 1 nodes for n emitters come first,
// the root at 0; the children of an inner node are adjacent, `first` and first + 1;
// a leaf holds one emitter, `first` its index in the emitter buffer. Then the leaf
// section: the n leaves again, in the tree's order, so that each node's leaves are
// the `count` nodes from `leaves` on.
struct GpuLightNode {
  vec4 sphere;  // xyz centre, w radius: every point of the node's emitters lies inside
  vec4 cone;    // xyz unit axis, w cos theta_o of its half-angle (-1: light leaves every way)
  vec4 info;    // x summed power, y first (child, or emitter of a leaf), z leaves, w count
};

// Up to this many emitters below a node, the walk stops there and draws among them
// in proportion to each one's own importance, which for a single emitter is close to
// what it contributes: the bounds of a node of many are loose (a sphere lamp's
// hemispheres face every way), those of one emitter tight.
VOXGI_CONST float kLightTreeLeafDraw = 128.0f;

#ifdef __cplusplus
#define VOXGI_LIGHT_NODES_PARAM const GpuLightNode *lightNodes,
#define VOXGI_LIGHT_NODES_ARG lightNodes,
#define VOXGI_LIGHT_NODE(i) lightNodes[i]
#else
#define VOXGI_LIGHT_NODES_PARAM
#define VOXGI_LIGHT_NODES_ARG
#define VOXGI_LIGHT_NODE(i) lightTreeNode(i)
GpuLightNode lightTreeNode(int i);
#endif

// The largest cosine at node n's emitters towards the receivers, which lie in
// directions within theta_u (cosU, sinU) of -w from them: the angle from the cone's
// axis to -w, less the cone's half-angle theta_o and theta_u,
// max(theta - theta_o - theta_u, 0).
VOXGI_FN float lightNodeEmitterCos(GpuLightNode n, vec3 w, float cosU, float sinU) {
  float cosT = -dot(vec3(n.cone), w);
  float sinT = sqrt(max(1.0f - cosT * cosT, 0.0f));
  float cosO = n.cone.w;
  float sinO = sqrt(max(1.0f - cosO * cosO, 0.0f));
  if (!(cosT < cosO)) return 1.0f;
  float cosTO = cosT * cosO + sinT * sinO;  // theta - theta_o, in [0, pi]
  float sinTO = sinT * cosO - cosT * sinO;
  return cosTO > cosU ? 1.0f : cosTO * cosU + sinTO * sinU;
}

// What node `n` may contribute at point p with normal nrm (unit); 0 where none of its
// emitters can send light there: all face away from p, or all lie below p's horizon.
// A point inside the node's sphere excludes no direction, and its distance² counts
// as the sphere's radius² (as pbrt-v4 clamps it to the bounds' size): what a
// receiver gets from emitters around it is at most their radiance x pi, about their
// power / their area, not their whole power. Before, a 16 x 4 m skylight's triangle
// counted its whole power at the floor under it, 50 times the light it sends there,
// so the small lamps nearby were drawn some 20 times too rarely: each draw of one a
// firefly. The angle bounds are worked with as cosines and sines (cos(a - b) =
// cos a cos b + sin a sin b), without inverse trigonometric functions.
VOXGI_FN float lightNodeImportance(GpuLightNode n, vec3 p, vec3 nrm) {
  float power = n.info.x;
  if (!(power > 0.0f)) return 0.0f;
  vec3 toC = vec3(n.sphere) - p;
  float dist2 = dot(toC, toC);
  float r = n.sphere.w;
  if (dist2 <= r * r) return power / max(r * r, 1e-30f);
  float invDist = inversesqrt(dist2);
  vec3 w = toC * invDist;
  // The sphere's half-angle seen from p, theta_u, widened a little against rounding.
  float sinU = min(r * invDist * 1.0001f + 1e-6f, 1.0f);
  float cosU = sqrt(1.0f - sinU * sinU);
  // At the receiver: the angle from its normal to the nearest direction in the
  // sphere, max(theta_i - theta_u, 0).
  float cosI = dot(nrm, w);
  float sinI = sqrt(max(1.0f - cosI * cosI, 0.0f));
  float cosReceiver = cosI > cosU ? 1.0f : cosI * cosU + sinI * sinU;
  if (!(cosReceiver > 0.0f)) return 0.0f;
  float cosEmitter = lightNodeEmitterCos(n, w, cosU, sinU);
  if (!(cosEmitter > 0.0f)) return 0.0f;
  return power * cosEmitter * cosReceiver / dist2;
}

// What node `n` may contribute at any point of a region of receivers: points within
// `radius` of p, normals within `cosN` (a cosine) of the unit axis nrm. It is 0 only
// where no point and normal of the region can take light from the node: seen from
// any receiver point, the node's points lie in the sphere of radius r + radius about
// its centre (the two spheres' Minkowski sum), so the angle bounds of
// lightNodeImportance hold with that radius, the receiver's widened by the normals'
// half-angle as well. The distance counts from the region's nearest point, and a
// region reaching into the node's sphere counts its radius², as there. With radius 0
// and cosN 1 it is lightNodeImportance. The light tiles of rtgi's shadows stage
// (rtgi_light_tiles.comp) weigh each emitter for a tile of pixels by it.
VOXGI_FN float lightNodeRegionImportance(GpuLightNode n, vec3 p, float radius, vec3 nrm,
                                         float cosN) {
  float power = n.info.x;
  if (!(power > 0.0f)) return 0.0f;
  vec3 toC = vec3(n.sphere) - p;
  float dist = sqrt(dot(toC, toC));
  float r = n.sphere.w + radius;
  float near = max(dist - radius, n.sphere.w);
  float near2 = max(near * near, 1e-30f);
  if (dist <= r) return power / near2;
  vec3 w = toC / dist;
  float sinU = min(r / dist * 1.0001f + 1e-6f, 1.0f);
  float cosU = sqrt(1.0f - sinU * sinU);
  // At the receivers: theta_i less theta_u and the normals' half-angle theta_n.
  float sinN = sqrt(max(1.0f - cosN * cosN, 0.0f));
  float cosB = cosU * cosN - sinU * sinN;  // theta_u + theta_n
  float sinB = sinU * cosN + cosU * sinN;
  float cosI = dot(nrm, w);
  float sinI = sqrt(max(1.0f - cosI * cosI, 0.0f));
  float cosReceiver = sinB < 0.0f || cosI > cosB ? 1.0f : cosI * cosB + sinI * sinB;
  if (!(cosReceiver > 0.0f)) return 0.0f;
  float cosEmitter = lightNodeEmitterCos(n, w, cosU, sinU);
  if (!(cosEmitter > 0.0f)) return 0.0f;
  return power * cosEmitter * cosReceiver / near2;
}

// Draws an emitter for point p (normal nrm) with uniform number u (the walk) and
// random bits `seed` (the draw among leaves); returns its index in the emitter buffer
// and its probability in pmf, or -1 (pmf 0) where the walk finds no emitter that can
// contribute. The walk stops at the first node of at most `leafDraw` emitters
// (kLightTreeLeafDraw, or fewer where a draw must cost less than one bound per
// emitter). Nodes must hold a tree of at least one node.
VOXGI_FN int pickLightTree(VOXGI_LIGHT_NODES_PARAM float u, uint seed, vec3 p, vec3 nrm,
                           float leafDraw, VOXGI_OUT(float) pmf) {
  pmf = 1.0f;
  GpuLightNode n = VOXGI_LIGHT_NODE(0);
  // One uniform number for the whole walk: rescaled after each choice, it stays
  // uniform on [0, 1).
  while (n.info.w > leafDraw) {
    int first = int(n.info.y);
    GpuLightNode left = VOXGI_LIGHT_NODE(first);
    GpuLightNode right = VOXGI_LIGHT_NODE(first + 1);
    float il = lightNodeImportance(left, p, nrm);
    float ir = lightNodeImportance(right, p, nrm);
    if (!(il + ir > 0.0f)) {
      pmf = 0.0f;
      return -1;
    }
    float pl = il / (il + ir);
    if (u < pl) {
      pmf *= pl;
      u = u / pl;
      n = left;
    } else {
      pmf *= 1.0f - pl;
      u = (u - pl) / (1.0f - pl);
      n = right;
    }
    u = min(u, 0.99999994f);
  }
  // Among the node's leaves, in one pass (weighted reservoir sampling): leaf k, of
  // weight w_k, replaces the pick when a uniform number of its own (a hash of the seed
  // and k) falls below w_k / (w_0 + ... + w_k), which leaves each picked in
  // proportion to w_k. One number rescaled from leaf to leaf would do as well in
  // exact arithmetic, but its rounding grows with each step.
  int begin = int(n.info.z);
  int count = int(n.info.w);
  int pick = -1;
  float picked = 0.0f, total = 0.0f;
  for (int k = 0; k < count; ++k) {
    GpuLightNode leaf = VOXGI_LIGHT_NODE(begin + k);
    float w = lightNodeImportance(leaf, p, nrm);
    if (!(w > 0.0f)) continue;
    total += w;
    float x = float(pcgHash(seed + uint(k)) >> 8u) * (1.0f / 16777216.0f);
    if (x * total < w) {
      pick = int(leaf.info.y);
      picked = w;
    }
  }
  pmf = pick >= 0 ? pmf * (picked / total) : 0.0f;
  return pick;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_LIGHT_TREE_SHARED_H

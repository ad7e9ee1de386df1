// The light tree rtgi draws emitters from (shaders/include/light_tree_shared.h,
// after Conty Estevez and Kulla 2018): built on the CPU from the packed emitters,
// uploaded by GpuScene beside them.
#ifndef VOXGI_SCENE_LIGHT_TREE_H
#define VOXGI_SCENE_LIGHT_TREE_H

#include <vector>

#include "light_tree_shared.h"
#include "scene/emitters.h"
#include "scene_shared.h"

namespace voxgi::scene {

// The emitters as the shaders read them (gpu::GpuEmitter, std430), in their order.
std::vector<gpu::GpuEmitter> packEmitters(const std::vector<Emitter>& emitters);

// Emitters chosen for light sampling by power: the cumulative distribution, one
// float per emitter, the last 1; emitters of no power at all are chosen uniformly.
std::vector<float> emitterPowerCdf(const std::vector<gpu::GpuEmitter>& emitters);

// The power an emitter sends out, in luminance: radiance x area (both faces of a
// two-sided one). Light sampling by power and the tree's nodes weigh by it; a value
// that is not finite counts as 0.
double emitterPower(const gpu::GpuEmitter& e);

// The tree over `emitters`, root first: 2n - 1 nodes for n emitters, one leaf per
// emitter, then the leaf section: the n leaves again, in the tree's order, so that
// every node's leaves lie side by side there. Empty for none. Splits each node's
// emitters at the median of their centres along the axis where those spread most.
std::vector<gpu::GpuLightNode> buildLightTree(const std::vector<gpu::GpuEmitter>& emitters);

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_LIGHT_TREE_H

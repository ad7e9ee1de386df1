// The uploaded scene lives in scene/ (voxel/ reads it too); the name stays here.
#ifndef VOXGI_RENDER_GPU_SCENE_H
#define VOXGI_RENDER_GPU_SCENE_H

#include "gpu_scene/gpu_scene.h"

namespace voxgi::render {
using GpuScene = scene::GpuScene;
}  // namespace voxgi::render

#endif  // VOXGI_RENDER_GPU_SCENE_H

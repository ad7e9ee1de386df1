#version 450 core
// Raster baseline, vertex stage: world space -> clip space.
#include "scene_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec3 inPreviousPosition;  // the last frame's (animated meshes)

layout(location = 0) out vec3 vPosition;
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec2 vUv;
layout(location = 3) out vec3 vPreviousPosition;

void main() {
  mat4 viewProj = mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]);
  vPosition = inPosition;  // already world space (baked at load)
  vNormal = inNormal;
  vUv = inUv;
  vPreviousPosition = inPreviousPosition;
  gl_Position = viewProj * vec4(inPosition, 1.0);
}

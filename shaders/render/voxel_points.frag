#version 450 core
// Voxel cubes shaded for inspection, not physically: albedo under half a head
// light and half a fixed key light (so the cube faces read apart), plus a floor of
// 15%, and the voxel's emission.
#include "scene_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };

layout(location = 0) flat in vec3 vAlbedo;
layout(location = 1) flat in vec3 vEmission;
layout(location = 2) flat in vec3 vFaceNormal;
layout(location = 3) in vec3 vPosition;

layout(location = 0) out vec4 outRadiance;

void main() {
  vec3 toEye = normalize(frame.cameraPosition.xyz - vPosition);
  const vec3 key = normalize(vec3(0.35, 0.8, 0.5));
  float light =
      0.15 + 0.425 * max(dot(vFaceNormal, toEye), 0.0) + 0.425 * max(dot(vFaceNormal, key), 0.0);
  outRadiance = vec4(vEmission + vAlbedo * light, 1.0);
}

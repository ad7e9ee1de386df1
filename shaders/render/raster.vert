#version 450 core
// Raster baseline (and the rtgi G-buffer), vertex stage: world space -> clip space.
// VOXGI_NO_COLORS and VOXGI_NO_NORMALMAPS compile the vertex colour and the tangent
// out (scene/effects.h), VOXGI_NO_UV2 (or VOXGI_NO_TEXTURES) texture-coordinate
// channel 1.
#include "scene_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
#ifdef VOXGI_UV2
layout(location = kUv2Attribute) in vec2 inUv2;  // texture-coordinate channel 1
#endif
#ifndef VOXGI_NO_COLORS
layout(location = kColorAttribute) in vec4 inColor;
#endif
layout(location = kPreviousPositionAttribute) in vec3
    inPreviousPosition;  // the last frame's (animated meshes)
#ifndef VOXGI_NO_NORMALMAPS
layout(location = kTangentAttribute) in vec4 inTangent;  // xyz, w handedness
#endif

layout(location = 0) out vec3 vPosition;
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec2 vUv;
#ifdef VOXGI_UV2
layout(location = 6) out vec2 vUv2;
#endif
#ifndef VOXGI_NO_COLORS
layout(location = 3) out vec4 vColor;
#endif
layout(location = 4) out vec3 vPreviousPosition;
#ifndef VOXGI_NO_NORMALMAPS
layout(location = 5) out vec4 vTangent;
#endif

void main() {
  mat4 viewProj = mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]);
  vPosition = inPosition;  // already world space (baked at load)
  vNormal = inNormal;
  vUv = inUv;
#ifdef VOXGI_UV2
  vUv2 = inUv2;
#endif
#ifndef VOXGI_NO_COLORS
  // Passed on as the offset from white: where every corner is white (a scene without
  // colours reads the constant white) the interpolated zeros stay exact, and so
  // does the base colour.
  vColor = inColor - 1.0;
#endif
  vPreviousPosition = inPreviousPosition;
#ifndef VOXGI_NO_NORMALMAPS
  vTangent = inTangent;
#endif
  gl_Position = viewProj * vec4(inPosition, 1.0);
}

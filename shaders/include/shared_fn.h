// What a header of *functions* written once in the common subset of GLSL and C++
// needs (octree_march.h, sampling_shared.h, brdf_shared.h, pathtrace_shading.h).
// In C++ it brings GLSL's vector types and built-in functions into voxgi::gpu from
// GLM, and defines the qualifiers GLSL spells differently; in GLSL it defines the
// same macros as GLSL's own words. Rules for such code: float literals carry an f
// (2.0f is valid GLSL and keeps C++ in float), conversions are written as
// constructor casts (float(i), uint(x)), and no function is overloaded.
#ifndef VOXGI_SHARED_FN_H
#define VOXGI_SHARED_FN_H

#include "gpu_types.h"

#ifdef __cplusplus
#include <glm/gtc/packing.hpp>
namespace voxgi::gpu {
using vec2 = glm::vec2;
using ivec2 = glm::ivec2;
using uvec2 = glm::uvec2;
using glm::abs;
using glm::acos;
using glm::atan;
using glm::clamp;
using glm::cos;
using glm::cross;
using glm::dot;
using glm::floatBitsToUint;
using glm::floor;
using glm::fract;
using glm::inversesqrt;
using glm::length;
using glm::max;
using glm::min;
using glm::mix;
using glm::normalize;
using glm::pow;
using glm::reflect;
using glm::sin;
using glm::sqrt;
using glm::uintBitsToFloat;
using glm::unpackUnorm4x8;
}  // namespace voxgi::gpu
#define VOXGI_FN inline
#define VOXGI_INOUT(T) T&
#define VOXGI_OUT(T) T&
#define VOXGI_PRECISE
#else
#define VOXGI_FN
#define VOXGI_INOUT(T) inout T
#define VOXGI_OUT(T) out T
#define VOXGI_PRECISE precise
#endif

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

VOXGI_CONST float kPi = 3.14159265358979f;

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_SHARED_FN_H

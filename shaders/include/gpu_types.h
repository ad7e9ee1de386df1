// What every shared C++/GLSL header needs: in C++, the GLSL type names (vec3,
// vec4, uvec4, uint) inside voxgi::gpu and VOXGI_CONST as constexpr; in GLSL, VOXGI_CONST
// as const. A shared header includes this, then opens voxgi::gpu under __cplusplus.
#ifndef VOXGI_GPU_TYPES_H
#define VOXGI_GPU_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>
namespace voxgi::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = uint32_t;
}  // namespace voxgi::gpu
#define VOXGI_CONST constexpr
#else
#define VOXGI_CONST const
#endif

#endif  // VOXGI_GPU_TYPES_H

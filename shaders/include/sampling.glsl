// Random numbers and direction sampling for the Monte Carlo shaders (pathtrace,
// octree light injection and bounces, rtgi): the shared functions of
// sampling_shared.h, plus one random stream per shader invocation.
#ifndef VOXGI_SAMPLING_GLSL
#define VOXGI_SAMPLING_GLSL

#include "sampling_shared.h"

// This invocation's stream (seeded by the shader from pcgHash).
uint rngState;

float rand01() { return pcgNext01(rngState); }

#endif  // VOXGI_SAMPLING_GLSL

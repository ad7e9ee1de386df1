// A value that is not finite (NaN or Inf) would poison every mean it enters, so the
// passes that could meet one replace it; they count each replacement in one uint,
// which the host binds at kNonfiniteCountBinding, reads back, and reports
// (`--stats` nonfinite_terms). The replacement keeps an image clean; the count keeps
// the bug that made the value visible to the tests, which require it to be 0.
#ifndef VOXGI_NONFINITE_GLSL
#define VOXGI_NONFINITE_GLSL

layout(std430, binding = kNonfiniteCountBinding) coherent buffer NonfiniteCount {
  uint nonfiniteCount;
};

bvec3 notFinite(vec3 c) { return bvec3(uvec3(isnan(c)) | uvec3(isinf(c))); }

// c with its non-finite channels set to 0, counted once per value.
vec3 finiteOrZero(vec3 c) {
  bvec3 bad = notFinite(c);
  if (!any(bad)) return c;
  atomicAdd(nonfiniteCount, 1u);
  return mix(c, vec3(0.0), bad);
}

#endif  // VOXGI_NONFINITE_GLSL

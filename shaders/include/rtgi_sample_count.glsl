// How many samples a pixel's running mean holds before this frame's: the stages
// that spend more rays while it holds few (rtgi_indirect.comp, rtgi_specular.comp)
// read accumulate's count, from the reprojected mean after a camera move.
#ifndef VOXGI_RTGI_SAMPLE_COUNT_GLSL
#define VOXGI_RTGI_SAMPLE_COUNT_GLSL

layout(binding = kAccumImage, rgba32f) uniform readonly image2D accumIn;
layout(binding = kReprojectedImage, rgba32f) uniform readonly image2D reprojectedIn;

float samplesSoFar(ivec2 px) {
  if ((rtgi.flags & kRtgiReprojecting) != 0u) return imageLoad(reprojectedIn, px).a;
  return rtgi.frameIndex > 0u ? imageLoad(accumIn, px).a : 0.0;
}

#endif  // VOXGI_RTGI_SAMPLE_COUNT_GLSL

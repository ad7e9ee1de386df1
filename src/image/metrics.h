// Differences between two images of the same size and channel count.
#ifndef VOXGI_IMAGE_METRICS_H
#define VOXGI_IMAGE_METRICS_H

#include "image/image.h"

namespace voxgi::image {

struct Difference {
  double rmse = 0.0;  // over every channel of every pixel
  double meanAbs = 0.0;
  double maxAbs = 0.0;
  // Fraction of pixels where some channel differs by more than `threshold`.
  double fractionAbove = 0.0;
};

// Throws voxgi::Error if sizes or channel counts differ. Compares the first
// min(channels, 3) channels (colour, not alpha).
Difference compare(const Image& a, const Image& b, double threshold);

}  // namespace voxgi::image

#endif  // VOXGI_IMAGE_METRICS_H

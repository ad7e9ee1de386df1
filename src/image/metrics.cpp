#include "image/metrics.h"

#include <algorithm>
#include <cmath>

#include "core/log.h"

namespace voxgi::image {

Difference compare(const Image& a, const Image& b, double threshold) {
  if (a.width != b.width || a.height != b.height)
    throw Error(
        strf("images differ in size: %dx%d vs %dx%d", a.width, a.height, b.width, b.height));
  if (a.channels != b.channels)
    throw Error(strf("images differ in channel count: %d vs %d", a.channels, b.channels));
  const int channels = std::min(a.channels, 3);
  Difference d;
  double sum2 = 0.0, sum = 0.0;
  size_t above = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      bool over = false;
      for (int c = 0; c < channels; ++c) {
        const double e = std::abs(static_cast<double>(a.at(x, y, c)) - b.at(x, y, c));
        sum += e;
        sum2 += e * e;
        d.maxAbs = std::max(d.maxAbs, e);
        over = over || e > threshold;
      }
      if (over) ++above;
    }
  }
  const double n = static_cast<double>(a.width) * a.height * channels;
  d.rmse = std::sqrt(sum2 / std::max(n, 1.0));
  d.meanAbs = sum / std::max(n, 1.0);
  d.fractionAbove =
      static_cast<double>(above) / std::max(1.0, static_cast<double>(a.width) * a.height);
  return d;
}

}  // namespace voxgi::image

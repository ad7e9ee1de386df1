// Differences between two images of the same size and channel count, and the error
// metrics of `voxgi compare` (tested on known inputs in tests/image/metrics_test.cpp).
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

// Error of a linear image against a reference, over the first min(channels, 3)
// channels. Throws voxgi::Error (one line) if sizes or channel counts differ.
struct ErrorMetrics {
  double rmse = 0.0;
  // Mean of (t - r)^2 / (r^2 + kRelMseEpsilon), the relative MSE of Rousselle et al.
  // 2011: dark regions count as much as bright ones; epsilon keeps black finite.
  double relMse = 0.0;
  // 10 log10(1 / MSE): the peak is display white, 1.0 (the tonemap's clamp point);
  // +inf for identical images.
  double psnr = 0.0;
  // Mean SSIM (Wang et al. 2004) of luminance clamped to [0, 1], dynamic range 1,
  // 11x11 Gaussian window of sigma 1.5, K1 = 0.01, K2 = 0.03; windows that would
  // cross the border are skipped (images under 11 pixels a side use the whole image).
  double ssim = 0.0;
  double meanLuminanceTest = 0.0;  // Rec. 709 luminance; one channel: the channel
  double meanLuminanceReference = 0.0;
  double meanLuminanceRatio = 0.0;  // test / reference (+inf when the reference is black)
};
inline constexpr double kRelMseEpsilon = 0.01;

ErrorMetrics errorMetrics(const Image& test, const Image& reference);

// Mean luminance of the test over the reference's, block by block: the image cut
// into `block` x `block`-pixel squares from the top left (a partial row or column of
// blocks at the right or bottom edge counts too). A block whose reference mean is
// below `floorFraction` of the whole reference's mean is left out (its ratio is noise
// over nearly nothing). The measure of a bias where it lives, and of a leak: a
// region too bright or too dark however well the whole image averages out.
struct BlockRatios {
  int block = 0;
  int blocks = 0;   // measured
  int skipped = 0;  // too dark in the reference to measure
  double min = 1.0, max = 1.0;
  int minX = 0, minY = 0, maxX = 0, maxY = 0;  // the extreme blocks' top-left pixels
  // Share of the measured blocks whose ratio is off 1 by more than 3% and by more
  // than 10%.
  double over3Percent = 0.0, over10Percent = 0.0;
};
BlockRatios blockRatios(const Image& test, const Image& reference, int block,
                        double floorFraction = 0.01);

// Luminance per pixel (Rec. 709 weights on RGB; the channel itself when grey).
std::vector<double> luminance(const Image& image);

}  // namespace voxgi::image

#endif  // VOXGI_IMAGE_METRICS_H

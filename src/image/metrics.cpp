#include "image/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/log.h"

namespace voxgi::image {

namespace {
void checkComparable(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw Error(
        strf("images differ in size: %dx%d vs %dx%d", a.width, a.height, b.width, b.height));
  if (a.channels != b.channels)
    throw Error(strf("images differ in channel count: %d vs %d", a.channels, b.channels));
  if (a.width < 1 || a.height < 1 || a.channels < 1) throw Error("images are empty");
}
}  // namespace

Difference compare(const Image& a, const Image& b, double threshold) {
  checkComparable(a, b);
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

namespace voxgi::image {

std::vector<double> luminance(const Image& img) {
  std::vector<double> out(static_cast<size_t>(img.width) * static_cast<size_t>(img.height));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double l = img.at(x, y, 0);
      if (img.channels >= 3)
        l = 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
      out[static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)] = l;
    }
  return out;
}

namespace {

// Mean SSIM over Gaussian windows (Wang, Bovik, Sheikh and Simoncelli 2004).
double meanSsim(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
  constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;
  const int radius = std::min({5, (w - 1) / 2, (h - 1) / 2});
  std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
  double ksum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    kernel[static_cast<size_t>(i + radius)] = std::exp(-0.5 * i * i / (1.5 * 1.5));
    ksum += kernel[static_cast<size_t>(i + radius)];
  }
  for (double& k : kernel) k /= ksum;
  auto at = [&](const std::vector<double>& v, int x, int y) {
    return std::clamp(v[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)],
                      0.0, 1.0);
  };
  double sum = 0.0;
  int64_t count = 0;
  for (int y = radius; y < h - radius; ++y) {
    for (int x = radius; x < w - radius; ++x) {
      double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
      for (int j = -radius; j <= radius; ++j) {
        for (int i = -radius; i <= radius; ++i) {
          const double k =
              kernel[static_cast<size_t>(i + radius)] * kernel[static_cast<size_t>(j + radius)];
          const double va = at(a, x + i, y + j), vb = at(b, x + i, y + j);
          ma += k * va;
          mb += k * vb;
          saa += k * va * va;
          sbb += k * vb * vb;
          sab += k * va * vb;
        }
      }
      const double va = std::max(saa - ma * ma, 0.0), vb = std::max(sbb - mb * mb, 0.0);
      const double cov = sab - ma * mb;
      sum +=
          ((2 * ma * mb + kC1) * (2 * cov + kC2)) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 1.0;
}

}  // namespace

ErrorMetrics errorMetrics(const Image& test, const Image& ref) {
  checkComparable(test, ref);
  const int channels = std::min(test.channels, 3);
  double se = 0.0, rel = 0.0;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x)
      for (int c = 0; c < channels; ++c) {
        const double t = test.at(x, y, c), r = ref.at(x, y, c);
        se += (t - r) * (t - r);
        rel += (t - r) * (t - r) / (r * r + kRelMseEpsilon);
      }
  const double n = static_cast<double>(test.width) * test.height * channels;
  ErrorMetrics m;
  const double mse = se / n;
  m.rmse = std::sqrt(mse);
  m.relMse = rel / n;
  m.psnr = mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : INFINITY;
  const auto lt = luminance(test), lr = luminance(ref);
  for (double v : lt) m.meanLuminanceTest += v;
  for (double v : lr) m.meanLuminanceReference += v;
  m.meanLuminanceTest /= static_cast<double>(lt.size());
  m.meanLuminanceReference /= static_cast<double>(lr.size());
  m.meanLuminanceRatio = m.meanLuminanceReference != 0.0
                             ? m.meanLuminanceTest / m.meanLuminanceReference
                             : (m.meanLuminanceTest == 0.0 ? 1.0 : INFINITY);
  m.ssim = meanSsim(lt, lr, test.width, test.height);
  return m;
}

BlockRatios blockRatios(const Image& test, const Image& ref, int block, double floorFraction) {
  if (test.width != ref.width || test.height != ref.height || test.channels != ref.channels)
    throw Error(strf("images differ in size or channels (%dx%dx%d vs %dx%dx%d)", test.width,
                     test.height, test.channels, ref.width, ref.height, ref.channels));
  if (block < 1) throw Error(strf("block size %d: must be at least 1", block));
  const auto lt = luminance(test), lr = luminance(ref);
  double refMean = 0.0;
  for (double v : lr) refMean += v;
  refMean /= static_cast<double>(std::max<size_t>(lr.size(), 1));
  BlockRatios out;
  out.block = block;
  int over3 = 0, over10 = 0;
  for (int by = 0; by < ref.height; by += block)
    for (int bx = 0; bx < ref.width; bx += block) {
      double st = 0.0, sr = 0.0;
      int n = 0;
      for (int y = by; y < std::min(by + block, ref.height); ++y)
        for (int x = bx; x < std::min(bx + block, ref.width); ++x) {
          const size_t i = static_cast<size_t>(y) * static_cast<size_t>(ref.width) + x;
          st += lt[i];
          sr += lr[i];
          ++n;
        }
      if (n == 0 || sr / n <= floorFraction * refMean || sr <= 0.0) {
        ++out.skipped;
        continue;
      }
      const double r = st / sr;
      if (out.blocks == 0 || r < out.min) {
        out.min = r;
        out.minX = bx;
        out.minY = by;
      }
      if (out.blocks == 0 || r > out.max) {
        out.max = r;
        out.maxX = bx;
        out.maxY = by;
      }
      ++out.blocks;
      over3 += std::abs(r - 1.0) > 0.03;
      over10 += std::abs(r - 1.0) > 0.10;
    }
  if (out.blocks > 0) {
    out.over3Percent = static_cast<double>(over3) / out.blocks;
    out.over10Percent = static_cast<double>(over10) / out.blocks;
  }
  return out;
}

}  // namespace voxgi::image

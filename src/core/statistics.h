// Small statistics helpers for timings (medians, as the machines are noisy).
#ifndef VOXGI_CORE_STATISTICS_H
#define VOXGI_CORE_STATISTICS_H

#include <algorithm>
#include <vector>

namespace voxgi {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace voxgi

#endif  // VOXGI_CORE_STATISTICS_H

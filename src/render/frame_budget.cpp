#include "render/frame_budget.h"

#include <algorithm>
#include <cmath>

namespace voxgi::render {

FrameBudget::FrameBudget(double targetMs, double minFraction, double maxFraction,
                         double startFraction, Gains gains)
    : targetMs_(targetMs),
      min_(minFraction),
      max_(maxFraction),
      fraction_(std::clamp(startFraction, minFraction, maxFraction)),
      gains_(gains),
      integral_(gains.ki > 0.0 ? fraction_ / gains.ki : 0.0) {}

double FrameBudget::update(double frameMs) {
  if (!std::isfinite(frameMs) || frameMs <= 0.0) return fraction_;
  const double e = std::clamp((targetMs_ - frameMs) / targetMs_, -1.0, 1.0);
  const double d = e - e1_;
  e1_ = e;
  integral_ += e;
  const double rest = gains_.kp * e + gains_.kd * d;
  const double u = rest + gains_.ki * integral_;
  // At a bound, the integral is set back to what puts the output exactly there.
  if (gains_.ki > 0.0 && (u > max_ || u < min_))
    integral_ = ((u > max_ ? max_ : min_) - rest) / gains_.ki;
  fraction_ = std::clamp(u, min_, max_);
  return fraction_;
}

}  // namespace voxgi::render

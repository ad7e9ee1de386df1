// The frame budget's PID controller against a simulated renderer whose frame time
// is linear in the traced fraction, with and without noise.
#include "render/frame_budget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace voxgi::render {
namespace {

// A frame costs a fixed 20 ms plus 200 ms at full work.
double plant(double fraction) {
  return 20.0 + 200.0 * fraction;
}

TEST(FrameBudget, SettlesOnTheTarget) {
  FrameBudget b(50.0, 1.0 / 16.0, 1.0, 1.0 / 16.0, {});
  for (int i = 0; i < 100; ++i) b.update(plant(b.fraction()));
  EXPECT_NEAR(plant(b.fraction()), 50.0, 0.5);
  EXPECT_NEAR(b.fraction(), 0.15, 0.01);
}

TEST(FrameBudget, HoldsTheMedianWithinTenPercentUnderNoise) {
  FrameBudget b(100.0, 1.0 / 16.0, 1.0, 1.0 / 16.0, {});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(1.0, 0.15);  // 15% frame-to-frame scatter
  std::vector<double> times;
  for (int i = 0; i < 400; ++i) {
    const double t = plant(b.fraction()) * noise(rng);
    b.update(t);
    if (i >= 100) times.push_back(t);
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  EXPECT_NEAR(times[times.size() / 2], 100.0, 10.0);
}

TEST(FrameBudget, StaysInItsBoundsWhenTheTargetIsOutOfReach) {
  FrameBudget fast(5.0, 0.1, 1.0, 0.5, {});  // even the least work takes 40 ms
  for (int i = 0; i < 50; ++i) fast.update(plant(fast.fraction()));
  EXPECT_DOUBLE_EQ(fast.fraction(), 0.1);
  FrameBudget slow(1000.0, 0.1, 1.0, 0.5, {});  // all the work fits
  for (int i = 0; i < 50; ++i) slow.update(plant(slow.fraction()));
  EXPECT_DOUBLE_EQ(slow.fraction(), 1.0);
}

// At a bound the integral is held where it puts the output on the bound, so the
// fraction leaves the bound on the first frame whose error changes sign. Without
// that (back-calculation), 50 frames with all the work fitting would wind the sum up
// so far that it takes dozens of frames too slow to come back down.
TEST(FrameBudget, LeavesTheBoundAtOnceWhenThePlantGetsSlower) {
  FrameBudget b(60.0, 0.1, 1.0, 0.5, {});
  auto cheap = [](double fraction) { return 5.0 + 10.0 * fraction; };  // always fits
  for (int i = 0; i < 50; ++i) b.update(cheap(b.fraction()));
  ASSERT_DOUBLE_EQ(b.fraction(), 1.0);
  // Now a frame at full work takes 220 ms against a 60 ms target.
  int framesAtBound = 0;
  for (int i = 0; i < 60; ++i) {
    if (b.fraction() >= 1.0) ++framesAtBound;
    b.update(plant(b.fraction()));
  }
  EXPECT_LE(framesAtBound, 1);
  // And it settles where a controller that never sat at the bound settles.
  FrameBudget fresh(60.0, 0.1, 1.0, 1.0, {});
  for (int i = 0; i < 60; ++i) fresh.update(plant(fresh.fraction()));
  EXPECT_NEAR(b.fraction(), fresh.fraction(), 1e-3);
}

TEST(FrameBudget, IgnoresNonsenseMeasurements) {
  FrameBudget b(50.0, 0.1, 1.0, 0.3, {});
  b.update(-1.0);
  b.update(0.0);
  b.update(std::numeric_limits<double>::quiet_NaN());
  EXPECT_DOUBLE_EQ(b.fraction(), 0.3);
}

}  // namespace
}  // namespace voxgi::render

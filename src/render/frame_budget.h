// Frame budget: a PID controller on the measured frame time that sets how much
// work the next frame does, as the fraction of pixels that trace new rays (after
// the real-time ray tracing thesis's adaptive work mask).
//
// fraction = clamp(Kp e_k + Ki sum(e) + Kd (e_k - e_{k-1}), min, max), with
// e = (target - measured) / target clamped to [-1, 1] (a frame 10 times too slow
// is not a 10 times stronger signal). When the output would leave [min, max], the
// sum is set back to the value that puts it on the bound (back-calculation): no
// wind-up while the fraction sits at a bound, and it leaves the bound as soon as
// the error changes sign. The plant, frame time against
// fraction, is close to linear; the gains were chosen on simulated plants from
// 1x to 8x more work at full fraction than the target allows, with 15% noise per
// frame (tests/render/frame_budget_test.cpp): mostly integral, because single frame
// times on a shared machine scatter by 10-20% and a proportional term would pass
// that scatter straight to the fraction.
#ifndef VOXGI_RENDER_FRAME_BUDGET_H
#define VOXGI_RENDER_FRAME_BUDGET_H

namespace voxgi::render {

class FrameBudget {
 public:
  struct Gains {
    double kp = 0.05;
    double ki = 0.1;
    double kd = 0.0;
  };
  FrameBudget(double targetMs, double minFraction, double maxFraction, double startFraction,
              Gains gains);

  // The frame just measured took frameMs: returns the fraction for the next frame.
  double update(double frameMs);
  double fraction() const { return fraction_; }
  double targetMs() const { return targetMs_; }

 private:
  double targetMs_, min_, max_, fraction_;
  Gains gains_;
  double integral_;  // sum of errors, started so that the first output is startFraction
  double e1_ = 0.0;  // the last error
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_BUDGET_H

// Named per-stage timing: a GL_TIME_ELAPSED query (GPU time) and the CPU clock
// around each stage, inside a debug group of the same name so captures and timing
// plots line up. Stages do not nest (GL allows one TIME_ELAPSED query at a time).
// Where the driver's queries cannot be trusted (see gl/workarounds.h) a stage is
// timed by the wall clock between glFinish calls instead; gpuMs then holds that.
#ifndef VOXGI_GL_STAGE_TIMER_H
#define VOXGI_GL_STAGE_TIMER_H

#include <algorithm>
#include <chrono>
#include <vector>

#include "core/stage.h"
#include "gl/handles.h"

namespace voxgi::gl {

struct StageTime {
  Stage stage;
  double gpuMs = 0.0;  // GL_TIME_ELAPSED
  double cpuMs = 0.0;  // wall clock from begin() to end() on the submitting thread
};

// "gpu-queries" or "synchronous" (what StageTime::gpuMs measured on this context).
const char* stageTimingMethod();

// One entry per stage, in the order first seen, each the sum of that stage's
// entries: a stage may run in more than one timed pass a frame (rtgi's shadows with
// reservoir reuse), and its cost is their sum.
inline std::vector<StageTime> sumByStage(const std::vector<StageTime>& stages) {
  std::vector<StageTime> out;
  for (const StageTime& s : stages) {
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const StageTime& o) { return o.stage == s.stage; });
    if (it == out.end()) {
      out.push_back(s);
    } else {
      it->gpuMs += s.gpuMs;
      it->cpuMs += s.cpuMs;
    }
  }
  return out;
}

class StageTimer {
 public:
  void begin(Stage stage);
  void end();
  // Waits for the queries of this frame and returns the stage times in order, one
  // per stage (sumByStage).
  std::vector<StageTime> resolve();

 private:
  struct Pending {
    Stage stage;
    Query query;
    double cpuMs = 0.0;
  };
  std::vector<Pending> pending_;
  bool open_ = false;
  std::chrono::steady_clock::time_point start_;
};

// RAII helper: StageScope s(timer, Stage::kRaster);
class StageScope {
 public:
  StageScope(StageTimer& timer, Stage stage) : timer_(timer) { timer_.begin(stage); }
  ~StageScope() { timer_.end(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  StageTimer& timer_;
};

}  // namespace voxgi::gl

#endif  // VOXGI_GL_STAGE_TIMER_H

// Named per-stage timing: a GL_TIME_ELAPSED query (GPU time) and the CPU clock
// around each stage, inside a debug group of the same name so captures and timing
// plots line up. Stages do not nest (GL allows one TIME_ELAPSED query at a time).
#ifndef VOXGI_GL_STAGE_TIMER_H
#define VOXGI_GL_STAGE_TIMER_H

#include <chrono>
#include <string>
#include <vector>

#include "gl/handles.h"

namespace voxgi::gl {

struct StageTime {
  std::string name;
  double gpuMs = 0.0;  // GL_TIME_ELAPSED
  double cpuMs = 0.0;  // wall clock from begin() to end() on the submitting thread
};

enum class StageKind { kGraphics, kCompute };

class StageTimer {
 public:
  // Compute stages may be timed by the wall clock (see timeComputeByWallClock()).
  void begin(const std::string& name, StageKind kind = StageKind::kGraphics);
  void end();
  // Waits for the queries of this frame and returns the stage times in order.
  std::vector<StageTime> resolve();

 private:
  struct Pending {
    std::string name;
    Query query;  // none when timed by the wall clock
    double cpuMs = 0.0;
    bool wallClock = false;
  };
  std::vector<Pending> pending_;
  bool open_ = false;
  std::chrono::steady_clock::time_point start_;
};

// RAII helper: StageScope s(timer, "raster");
class StageScope {
 public:
  StageScope(StageTimer& timer, const std::string& name, StageKind kind = StageKind::kGraphics)
      : timer_(timer) {
    timer_.begin(name, kind);
  }
  ~StageScope() { timer_.end(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  StageTimer& timer_;
};

}  // namespace voxgi::gl

#endif  // VOXGI_GL_STAGE_TIMER_H

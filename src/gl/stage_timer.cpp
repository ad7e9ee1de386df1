#include "gl/stage_timer.h"

#include "core/log.h"
#include "gl/workarounds.h"

namespace voxgi::gl {

const char* stageTimingMethod() {
  return stageTimingIsSynchronous() ? "synchronous" : "gpu-queries";
}

void StageTimer::begin(Stage stage) {
  VOXGI_CHECK(!open_);
  open_ = true;
  glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, -1, stageName(stage));
  Pending p{stage, Query(), 0.0};
  if (stageTimingIsSynchronous()) {
    glFinish();  // earlier work is not this stage's
  } else {
    p.query = createQuery(GL_TIME_ELAPSED);
    glBeginQuery(GL_TIME_ELAPSED, p.query.id());
  }
  pending_.push_back(std::move(p));
  start_ = std::chrono::steady_clock::now();
}

void StageTimer::end() {
  VOXGI_CHECK(open_);
  open_ = false;
  if (stageTimingIsSynchronous())
    glFinish();
  else
    glEndQuery(GL_TIME_ELAPSED);
  glPopDebugGroup();
  pending_.back().cpuMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

std::vector<StageTime> StageTimer::resolve() {
  VOXGI_CHECK(!open_);
  std::vector<StageTime> out;
  out.reserve(pending_.size());
  for (Pending& p : pending_) {
    if (!p.query) {  // synchronous: the wall clock is the stage's cost
      out.push_back({p.stage, p.cpuMs, p.cpuMs});
      continue;
    }
    GLuint64 ns = 0;
    glGetQueryObjectui64v(p.query.id(), GL_QUERY_RESULT, &ns);  // waits
    out.push_back({p.stage, static_cast<double>(ns) * 1e-6, p.cpuMs});
  }
  pending_.clear();
  return sumByStage(out);
}

}  // namespace voxgi::gl

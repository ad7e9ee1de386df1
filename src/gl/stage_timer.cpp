#include "gl/stage_timer.h"

#include "core/log.h"
#include "gl/workarounds.h"

namespace voxgi::gl {

void StageTimer::begin(const std::string& name, StageKind kind) {
  VOXGI_CHECK(!open_);
  open_ = true;
  glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, -1, name.c_str());
  Pending p{name, Query(), 0.0, kind == StageKind::kCompute && timeComputeByWallClock()};
  if (p.wallClock) {
    glFinish();  // earlier stages are not this one's time
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
  if (pending_.back().wallClock) {
    glFinish();
    primeTimerQueries();
  } else {
    glEndQuery(GL_TIME_ELAPSED);
  }
  glPopDebugGroup();
  pending_.back().cpuMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

std::vector<StageTime> StageTimer::resolve() {
  VOXGI_CHECK(!open_);
  std::vector<StageTime> out;
  out.reserve(pending_.size());
  for (Pending& p : pending_) {
    if (p.wallClock) {
      out.push_back({p.name, p.cpuMs, p.cpuMs});
      continue;
    }
    GLuint64 ns = 0;
    glGetQueryObjectui64v(p.query.id(), GL_QUERY_RESULT, &ns);  // waits
    out.push_back({p.name, static_cast<double>(ns) * 1e-6, p.cpuMs});
  }
  pending_.clear();
  return out;
}

}  // namespace voxgi::gl

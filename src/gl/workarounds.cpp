#include "gl/workarounds.h"

#include "core/log.h"
#include "gl/handles.h"

namespace voxgi::gl {
namespace {

// llvmpipe (seen on Mesa 22.3.6): the first GL_TIME_ELAPSED query a context ends
// reports the time since the screen was created (minutes) instead of the GPU time
// of its commands; later queries are right. One query around a clear of a tiny
// framebuffer, read back at start, absorbs it (an empty query does not).
}  // namespace

void primeTimerQueries() {
  Texture t = createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, GL_RGBA8, 4, 4);
  Framebuffer f = createFramebuffer();
  glNamedFramebufferTexture(f.id(), GL_COLOR_ATTACHMENT0, t.id(), 0);
  Query q = createQuery(GL_TIME_ELAPSED);
  glBeginQuery(GL_TIME_ELAPSED, q.id());
  const float black[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(f.id(), GL_COLOR, 0, black);
  glEndQuery(GL_TIME_ELAPSED);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
  logDebug(strf("workaround llvmpipe-first-timer-query: primed (%.1f ms)",
                static_cast<double>(ns) * 1e-6));
}

namespace {
bool gComputeByWallClock = false;

}  // namespace

void applyDriverWorkarounds(const std::string& renderer, const std::string& version) {
  (void)version;
  gComputeByWallClock = false;
  if (renderer.find("llvmpipe") != std::string::npos) {
    primeTimerQueries();
    gComputeByWallClock = true;
    logDebug("workaround llvmpipe-compute-timer-query: compute stages timed by wall clock");
  }
}

bool timeComputeByWallClock() {
  return gComputeByWallClock;
}

}  // namespace voxgi::gl

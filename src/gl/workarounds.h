// Driver workarounds, each named, explained and scoped to the drivers it needs.
#ifndef VOXGI_GL_WORKAROUNDS_H
#define VOXGI_GL_WORKAROUNDS_H

#include <string>

namespace voxgi::gl {

// Applies the workarounds the current context's driver needs; called once after
// the context is created and GL is loaded.
void applyDriverWorkarounds(const std::string& renderer, const std::string& version);

// llvmpipe-timer-queries-miss-compute: on llvmpipe, GL_TIME_ELAPSED does not count
// compute dispatches (a compute-only query reads 0) and the query that follows one
// reads the time since the screen was created. Stages are then timed by the wall
// clock between two glFinish calls, which on a CPU rasterizer is exactly what the
// stage costs. True after applyDriverWorkarounds on such a driver.
bool stageTimingIsSynchronous();

}  // namespace voxgi::gl

#endif  // VOXGI_GL_WORKAROUNDS_H

// Driver workarounds, each named, explained and scoped to the drivers it needs.
#ifndef VOXGI_GL_WORKAROUNDS_H
#define VOXGI_GL_WORKAROUNDS_H

#include <string>

namespace voxgi::gl {

// Applies the workarounds the current context's driver needs; called once after
// the context is created and GL is loaded.
void applyDriverWorkarounds(const std::string& renderer, const std::string& version);

// llvmpipe-compute-timer-query: GL_TIME_ELAPSED around compute dispatches reads 0
// on llvmpipe (Mesa 22.3.6), and the next query then reads garbage (thousands of
// seconds). When true, StageTimer times compute stages by the wall clock between
// two glFinish calls instead (on llvmpipe the "GPU" is these CPU threads anyway).
bool timeComputeByWallClock();
// The same driver's next GL_TIME_ELAPSED query after a compute dispatch is garbage
// too, like a context's first one; one primed query absorbs it.
void primeTimerQueries();

}  // namespace voxgi::gl

#endif  // VOXGI_GL_WORKAROUNDS_H

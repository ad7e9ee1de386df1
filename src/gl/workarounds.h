// Driver workarounds, each named, explained and scoped to the drivers it needs.
#ifndef VOXGI_GL_WORKAROUNDS_H
#define VOXGI_GL_WORKAROUNDS_H

#include <string>

namespace voxgi::gl {

// Applies the workarounds the current context's driver needs; called once after
// the context is created and GL is loaded.
void applyDriverWorkarounds(const std::string& renderer, const std::string& version);

}  // namespace voxgi::gl

#endif  // VOXGI_GL_WORKAROUNDS_H

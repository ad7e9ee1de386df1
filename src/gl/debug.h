// KHR_debug output routed to the log. Errors (type GL_DEBUG_TYPE_ERROR or high
// severity) are counted; tests assert the count stays zero.
#ifndef VOXGI_GL_DEBUG_H
#define VOXGI_GL_DEBUG_H

#include <string>

namespace voxgi::gl {

// Enables synchronous debug output on the current context.
void installDebugOutput();

// GL errors and high-severity debug messages seen since start (or the last reset).
int debugErrorCount();
void resetDebugErrorCount();
const std::string& lastDebugError();

// RAII debug group (glPushDebugGroup / glPopDebugGroup), so captures show pass names.
class DebugGroup {
 public:
  explicit DebugGroup(const char* name);
  ~DebugGroup();
  DebugGroup(const DebugGroup&) = delete;
  DebugGroup& operator=(const DebugGroup&) = delete;
};

}  // namespace voxgi::gl

#endif  // VOXGI_GL_DEBUG_H

#include "gl/debug.h"

#include <atomic>
#include <cstring>

#include "core/log.h"
#include "gl/gl.h"

namespace voxgi::gl {
namespace {

std::atomic<int> gErrors{0};
std::string gLastError;

const char* typeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR:
      return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
      return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
      return "undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY:
      return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE:
      return "performance";
    default:
      return "other";
  }
}

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                               GLsizei length, const GLchar* message, const void*) {
  if (type == GL_DEBUG_TYPE_PUSH_GROUP || type == GL_DEBUG_TYPE_POP_GROUP) return;
  std::string msg(message, length >= 0 ? static_cast<size_t>(length) : std::strlen(message));
  // Shader compile errors come back through the program cache, mapped to file:line
  // (a failed hot reload is an expected path, not a GL error).
  if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) {
    logDebug("GL shader compiler: " + msg);
    return;
  }
  const bool error = type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH;
  const std::string line = strf("GL %s (id %u): %s", typeName(type), id, msg.c_str());
  if (error) {
    ++gErrors;
    gLastError = line;
    logError(line);
  } else if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) {
    logDebug(line);
  } else {
    logDebug(line);  // performance/portability hints: visible with --verbose
  }
}

}  // namespace

void installDebugOutput() {
  GLint flags = 0;
  glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(onDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  if (!(flags & GL_CONTEXT_FLAG_DEBUG_BIT))
    logDebug("GL context has no debug flag; output may be sparse");
}

int debugErrorCount() {
  return gErrors.load();
}
void resetDebugErrorCount() {
  gErrors = 0;
  gLastError.clear();
}
const std::string& lastDebugError() {
  return gLastError;
}

DebugGroup::DebugGroup(const char* name) {
  glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, -1, name);
}
DebugGroup::~DebugGroup() {
  glPopDebugGroup();
}

}  // namespace voxgi::gl

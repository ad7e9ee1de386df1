#include "gl/context.h"

#include "core/log.h"
#include "gl/debug.h"
#include "gl/gl.h"
#include "gl/workarounds.h"

#include "bindings_shared.h"

namespace voxgi::gl {

const char* backendName(Backend b) {
  switch (b) {
    case Backend::kEgl:
      return "egl";
    case Backend::kOsMesa:
      return "osmesa";
    case Backend::kGlfw:
      return "glfw";
  }
  return "?";
}

std::optional<Backend> parseBackend(const std::string& name) {
  if (name == "egl") return Backend::kEgl;
  if (name == "osmesa") return Backend::kOsMesa;
  if (name == "glfw") return Backend::kGlfw;
  return std::nullopt;
}

std::unique_ptr<Context> Context::create(const ContextOptions& options) {
  switch (options.backend) {
    case Backend::kEgl:
      return createEglContext(options);
    case Backend::kOsMesa:
      return createOsMesaContext(options);
    case Backend::kGlfw:
      return createGlfwContext(options);
  }
  throw Error("unknown GL backend");
}

void Context::initGl(void* (*load)(const char*), bool debug) {
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(load));
  if (version == 0) throw Error(strf("%s: could not load OpenGL functions", backendName(backend_)));
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  renderer_ = str(GL_RENDERER);
  version_ = str(GL_VERSION);
  vendor_ = str(GL_VENDOR);
  const int major = GLAD_VERSION_MAJOR(version), minor = GLAD_VERSION_MINOR(version);
  if (major < 4 || (major == 4 && minor < 5)) {
    throw Error(strf("%s: OpenGL 4.5 core is required, the driver gives %s (%s)",
                     backendName(backend_), version_.c_str(), renderer_.c_str()));
  }
  checkLimits();
  if (debug) installDebugOutput();
  applyDriverWorkarounds(renderer_, version_);
  logDebug(strf("%s context: %s / %s", backendName(backend_), version_.c_str(), renderer_.c_str()));
}

void Context::checkLimits() const {
  struct Limit {
    GLenum name;
    const char* text;
    GLuint needed;
  };
  for (const Limit& l :
       {Limit{GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS",
              gpu::kRequiredSsboBindings},
        Limit{GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS",
              gpu::kRequiredComputeSsboBlocks},
        Limit{GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, "GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS",
              gpu::kRequiredFragmentSsboBlocks}}) {
    GLint value = 0;
    glGetIntegerv(l.name, &value);
    if (value < static_cast<GLint>(l.needed))
      throw Error(strf("%s: voxgi's shaders need %s >= %u, the driver gives %d (%s)",
                       backendName(backend_), l.text, l.needed, value, renderer_.c_str()));
  }
}

}  // namespace voxgi::gl

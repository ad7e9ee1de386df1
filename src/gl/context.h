// GL 4.5 core contexts: EGL (surfaceless Mesa, or the EGL device platform on
// NVIDIA), OSMesa (loaded at run time: it left Mesa in 25.1) and a GLFW window.
// All three load the same glad function table through their own get-proc-address.
//
// A context renders into framebuffer objects; only the GLFW backend has a default
// framebuffer worth presenting. One context is current per process at a time.
#ifndef VOXGI_GL_CONTEXT_H
#define VOXGI_GL_CONTEXT_H

#include <memory>
#include <optional>
#include <string>

namespace voxgi::gl {

enum class Backend { kEgl, kOsMesa, kGlfw };

const char* backendName(Backend b);
std::optional<Backend> parseBackend(const std::string& name);

struct ContextOptions {
  Backend backend = Backend::kEgl;
  int width = 640;  // window size (GLFW) or OSMesa's 1-pixel buffer is used otherwise
  int height = 360;
  bool debug = true;     // KHR_debug output routed to the log, synchronous
  bool visible = false;  // GLFW only: show the window
  std::string title = "voxgi";
  // EGL: device N of the enumeration (app: VOXGI_EGL_DEVICE); -1 picks the first
  // hardware device.
  int eglDevice = -1;
};

class Context {
 public:
  virtual ~Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Creates the context, makes it current, loads GL and checks for 4.5 core.
  // Throws voxgi::Error with a one-line reason when the backend is unavailable.
  static std::unique_ptr<Context> create(const ContextOptions& options);

  Backend backend() const { return backend_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  const std::string& vendor() const { return vendor_; }

  virtual void makeCurrent() = 0;
  virtual void swapBuffers() {}
  // GLFW only; headless backends never close.
  virtual bool shouldClose() const { return false; }
  virtual void* nativeWindow() const { return nullptr; }

 protected:
  explicit Context(Backend b) : backend_(b) {}
  // Loads the glad table with `load`, reads the strings and checks the version.
  void initGl(void* (*load)(const char*), bool debug);
  // Throws, naming the limit, when the driver offers fewer SSBO bindings or blocks
  // than the shaders use (bindings_shared.h's kRequired*).
  void checkLimits() const;

 private:
  Backend backend_;
  std::string renderer_, version_, vendor_;
};

std::unique_ptr<Context> createEglContext(const ContextOptions& options);
std::unique_ptr<Context> createOsMesaContext(const ContextOptions& options);
std::unique_ptr<Context> createGlfwContext(const ContextOptions& options);

}  // namespace voxgi::gl

#endif  // VOXGI_GL_CONTEXT_H

// A GLFW window with a GL 4.5 core context (the viewer; also usable headless-ish
// for `render --backend glfw` under an X server such as Xvfb).
#include <GLFW/glfw3.h>

#include "core/log.h"
#include "gl/context.h"

namespace voxgi::gl {
namespace {

class GlfwContext final : public Context {
 public:
  explicit GlfwContext(GLFWwindow* w) : Context(Backend::kGlfw), window_(w) {}
  ~GlfwContext() override {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  void makeCurrent() override { glfwMakeContextCurrent(window_); }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  bool shouldClose() const override { return glfwWindowShouldClose(window_); }
  void* nativeWindow() const override { return window_; }
  void init(bool debug) {
    makeCurrent();
    initGl([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); },
           debug);
  }

 private:
  GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<Context> createGlfwContext(const ContextOptions& options) {
  glfwSetErrorCallback([](int, const char* desc) { logDebug(strf("glfw: %s", desc)); });
  if (!glfwInit())
    throw Error(
        "glfw: could not initialise (is there a display? set DISPLAY or use --backend egl)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw Error("glfw: could not open a window with a GL 4.5 core context");
  }
  auto ctx = std::make_unique<GlfwContext>(window);
  ctx->init(options.debug);
  return ctx;
}

}  // namespace voxgi::gl

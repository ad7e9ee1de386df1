// EGL without a window. Order of preference:
//  1. the EGL device platform on a hardware device (NVIDIA servers have no display;
//     EGL_EXT_device_enumeration lists the GPUs, software devices are skipped),
//  2. Mesa's surfaceless platform (llvmpipe on machines without a GPU),
//  3. the default display.
// ContextOptions::eglDevice = N forces device N of the enumeration.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/log.h"
#include "gl/context.h"

namespace voxgi::gl {
namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

const char* eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error";
  }
}

class EglContext final : public Context {
 public:
  EglContext(EGLDisplay display, EGLContext context)
      : Context(Backend::kEgl), display_(display), context_(context) {}
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw Error(strf("egl: eglMakeCurrent failed (%s)", eglErrorName(eglGetError())));
  }
  void init(bool debug) {
    makeCurrent();
    initGl([](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); },
           debug);
  }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

EGLDisplay openDisplay(int forced, std::string* how) {
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  auto queryDevices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));

  if (getPlatformDisplay && queryDevices && queryDeviceString &&
      hasExtension(clientExt, "EGL_EXT_platform_device")) {
    EGLint count = 0;
    queryDevices(0, nullptr, &count);
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    if (count > 0 && queryDevices(count, devices.data(), &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = queryDeviceString(devices[static_cast<size_t>(i)], EGL_EXTENSIONS);
        const bool software = hasExtension(ext, "EGL_MESA_device_software");
        if (forced >= 0 ? i != forced : software) continue;
        EGLDisplay d =
            getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(i)], nullptr);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) {
          *how = strf("device platform, device %d", i);
          return d;
        }
      }
    }
  }
  if (getPlatformDisplay && hasExtension(clientExt, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) {
      *how = "surfaceless platform";
      return d;
    }
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) {
    *how = "default display";
    return d;
  }
  return EGL_NO_DISPLAY;
}

}  // namespace

std::unique_ptr<Context> createEglContext(const ContextOptions& options) {
  std::string how;
  EGLDisplay display = openDisplay(options.eglDevice, &how);
  if (display == EGL_NO_DISPLAY)
    throw Error(
        strf("egl: no usable EGL display (%s); try --backend osmesa", eglErrorName(eglGetError())));
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    throw Error("egl: the EGL implementation has no desktop OpenGL");
  }
  const char* ext = eglQueryString(display, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
    const EGLint want[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                           EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, want, &config, 1, &n) || n < 1) {
      eglTerminate(display);
      throw Error("egl: no EGL config with desktop OpenGL");
    }
  }
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
    eglTerminate(display);
    throw Error("egl: EGL_KHR_surfaceless_context is missing; try --backend osmesa");
  }
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                            4,
                            EGL_CONTEXT_MINOR_VERSION,
                            5,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                            EGL_CONTEXT_OPENGL_DEBUG,
                            options.debug ? EGL_TRUE : EGL_FALSE,
                            EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
  if (context == EGL_NO_CONTEXT) {
    const EGLint err = eglGetError();
    eglTerminate(display);
    throw Error(strf("egl: could not create a GL 4.5 core context on the %s (%s)", how.c_str(),
                     eglErrorName(err)));
  }
  auto ctx = std::make_unique<EglContext>(display, context);
  ctx->init(options.debug);
  logDebug("egl: " + how);
  return ctx;
}

}  // namespace voxgi::gl

// OSMesa, loaded with dlopen so that the binary builds and runs where the
// distribution no longer ships it (Mesa >= 25.1); asking for it there gives a clear
// error. The constants are those of GL/osmesa.h (Mesa 22).
#include <dlfcn.h>

#include <vector>

#include "core/log.h"
#include "gl/context.h"

namespace voxgi::gl {
namespace {

constexpr int kOsMesaFormat = 0x22;
constexpr int kOsMesaRgba = 0x1908;  // GL_RGBA
constexpr int kOsMesaDepthBits = 0x30;
constexpr int kOsMesaStencilBits = 0x31;
constexpr int kOsMesaProfile = 0x33;
constexpr int kOsMesaCoreProfile = 0x34;
constexpr int kOsMesaContextMajor = 0x36;
constexpr int kOsMesaContextMinor = 0x37;
constexpr unsigned kGlUnsignedByte = 0x1401;

using OsMesaContextHandle = void*;
using CreateFn = OsMesaContextHandle (*)(const int*, OsMesaContextHandle);
using DestroyFn = void (*)(OsMesaContextHandle);
using MakeCurrentFn = unsigned char (*)(OsMesaContextHandle, void*, unsigned, int, int);
using GetProcFn = void* (*)(const char*);

struct OsMesaLib {
  void* handle = nullptr;
  CreateFn create = nullptr;
  DestroyFn destroy = nullptr;
  MakeCurrentFn makeCurrent = nullptr;
  GetProcFn getProc = nullptr;
};

// Loaded once per process and kept: unloading Mesa while GL pointers live is unsafe.
const OsMesaLib& library() {
  static OsMesaLib lib = [] {
    OsMesaLib l;
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
      l.handle = dlopen(name, RTLD_NOW | RTLD_LOCAL);
      if (l.handle) break;
    }
    if (!l.handle) return l;
    l.create = reinterpret_cast<CreateFn>(dlsym(l.handle, "OSMesaCreateContextAttribs"));
    l.destroy = reinterpret_cast<DestroyFn>(dlsym(l.handle, "OSMesaDestroyContext"));
    l.makeCurrent = reinterpret_cast<MakeCurrentFn>(dlsym(l.handle, "OSMesaMakeCurrent"));
    l.getProc = reinterpret_cast<GetProcFn>(dlsym(l.handle, "OSMesaGetProcAddress"));
    return l;
  }();
  return lib;
}

const OsMesaLib* gLoaded = nullptr;  // for the get-proc-address trampoline

class OsMesaContext final : public Context {
 public:
  explicit OsMesaContext(OsMesaContextHandle ctx) : Context(Backend::kOsMesa), ctx_(ctx) {
    buffer_.resize(4);  // we draw into FBOs; the context's own buffer is 1x1
  }
  ~OsMesaContext() override { library().destroy(ctx_); }
  void makeCurrent() override {
    if (!library().makeCurrent(ctx_, buffer_.data(), kGlUnsignedByte, 1, 1))
      throw Error("osmesa: OSMesaMakeCurrent failed");
  }
  void init(bool debug) {
    makeCurrent();
    gLoaded = &library();
    initGl([](const char* name) { return gLoaded->getProc(name); }, debug);
  }

 private:
  OsMesaContextHandle ctx_;
  std::vector<unsigned char> buffer_;
};

}  // namespace

std::unique_ptr<Context> createOsMesaContext(const ContextOptions& options) {
  const OsMesaLib& lib = library();
  if (!lib.handle)
    throw Error(
        "osmesa: libOSMesa is not installed (Mesa >= 25.1 no longer ships it); use "
        "--backend egl");
  if (!lib.create || !lib.destroy || !lib.makeCurrent || !lib.getProc)
    throw Error("osmesa: libOSMesa lacks OSMesaCreateContextAttribs (too old)");
  const int attribs[] = {kOsMesaFormat,
                         kOsMesaRgba,
                         kOsMesaDepthBits,
                         24,
                         kOsMesaStencilBits,
                         8,
                         kOsMesaProfile,
                         kOsMesaCoreProfile,
                         kOsMesaContextMajor,
                         4,
                         kOsMesaContextMinor,
                         5,
                         0};
  OsMesaContextHandle ctx = lib.create(attribs, nullptr);
  if (!ctx) throw Error("osmesa: could not create a GL 4.5 core context");
  auto context = std::make_unique<OsMesaContext>(ctx);
  context->init(options.debug);
  return context;
}

}  // namespace voxgi::gl

// The OpenImageIO side of image/image.cpp, built as a module of its own
// (libvoxgi_oiio.so) that image.cpp loads only when a file needs it (EXR, and any
// format but PNG). OpenImageIO brings some 260 shared libraries with it, whose
// loading and relocation took 0.15-0.3 s of every voxgi command's start, a third of
// a small scene's first image, whether it read or wrote an EXR or not. A C
// interface: no C++ type crosses the boundary.
#include <algorithm>
#include <cstring>
#include <string>

#include <OpenImageIO/imageio.h>

#include "image/oiio_module.h"

namespace {

void setError(char* err, int errLen, const std::string& message) {
  if (errLen <= 0) return;
  const size_t n = std::min(message.size(), static_cast<size_t>(errLen - 1));
  std::memcpy(err, message.data(), n);
  err[n] = '\0';
}

}  // namespace

extern "C" {

int voxgiOiioWrite(const char* path, const char* tmp, int width, int height, int isFloat,
                   const void* rgba, char* err, int errLen) {
  const OIIO::TypeDesc type = isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    setError(err, errLen, "no image writer for this format");
    return 1;
  }
  // RGB on disk: alpha carries nothing here, and OIIO would (un)premultiply by it.
  OIIO::ImageSpec spec(width, height, 3, type);
  spec.attribute("oiio:ColorSpace", isFloat ? "linear" : "sRGB");
  spec.attribute("Software", "voxgi");
  if (!out->open(tmp, spec)) {
    setError(err, errLen, "cannot write (" + out->geterror().substr(0, 200) + ")");
    return 1;
  }
  const OIIO::stride_t pixelStride = static_cast<OIIO::stride_t>(4 * type.size());
  const bool ok = out->write_image(type, rgba, pixelStride, pixelStride * width);
  const bool closed = out->close();
  if (!ok || !closed) {
    setError(err, errLen, "write failed (" + out->geterror().substr(0, 200) + ")");
    return 1;
  }
  return 0;
}

int voxgiOiioRead(const char* path, VoxgiOiioAllocate allocate, void* context, char* err,
                  int errLen) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    setError(err, errLen, "cannot read image (" + OIIO::geterror().substr(0, 200) + ")");
    return 1;
  }
  const OIIO::ImageSpec& spec = in->spec();
  float* pixels = allocate(context, spec.width, spec.height, spec.nchannels);
  if (!pixels) {
    setError(err, errLen, "image too large");
    return 1;
  }
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels)) {
    setError(err, errLen, "cannot decode image (" + in->geterror().substr(0, 200) + ")");
    return 1;
  }
  in->close();
  return 0;
}

}  // extern "C"

#include "image/image.h"

#include <dlfcn.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "core/log.h"
#include "image/oiio_module.h"

namespace voxgi::image {
namespace fs = std::filesystem;
namespace {

std::string lowerExtension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  return e;
}

// Same directory (so rename is atomic), same extension (so OIIO picks the format).
std::string tempPathFor(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + ".partial-" + std::to_string(getpid()) +
                             p.extension().string()))
      .string();
}

void commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw Error(path + ": cannot write (" + ec.message() + ")");
  }
}

// The OpenImageIO module (oiio_module.h), loaded on first use: beside the binary,
// or where the build put it.
struct OiioModule {
  VoxgiOiioWriteFn write = nullptr;
  VoxgiOiioReadFn read = nullptr;
  std::string error;  // why it could not be loaded
};

const OiioModule& oiio() {
  static OiioModule module;
  static std::once_flag once;
  std::call_once(once, [] {
    std::vector<std::string> paths;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) paths.push_back((exe.parent_path() / "libvoxgi_oiio.so").string());
#ifdef VOXGI_OIIO_MODULE_PATH
    paths.emplace_back(VOXGI_OIIO_MODULE_PATH);
#endif
    std::string tried;
    for (const std::string& path : paths) {
      if (!fs::exists(path, ec)) {
        tried += (tried.empty() ? "" : ", ") + path;
        continue;
      }
      void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        const char* e = dlerror();
        module.error = path + ": " + (e ? e : "cannot be loaded");
        return;
      }
      module.write = reinterpret_cast<VoxgiOiioWriteFn>(dlsym(handle, "voxgiOiioWrite"));
      module.read = reinterpret_cast<VoxgiOiioReadFn>(dlsym(handle, "voxgiOiioRead"));
      if (!module.write || !module.read) module.error = path + ": not voxgi's OpenImageIO module";
      return;
    }
    module.error =
        "voxgi's OpenImageIO module, libvoxgi_oiio.so, is missing (looked for " + tried + ")";
  });
  return module;
}

// Writes through tmp and renames into place; `write` fills tmp, returning false with
// a message on failure.
template <typename Write>
void writeAtomically(const std::string& path, Write write) {
  checkWritable(path);
  const std::string tmp = tempPathFor(path);
  std::string message;
  if (!write(tmp, &message)) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error(path + ": " + message);
  }
  commit(tmp, path);
}

void writeWithOiio(const std::string& path, int width, int height, bool isFloat, const void* data) {
  const OiioModule& m = oiio();
  if (!m.write) throw Error(path + ": cannot write (" + m.error + ")");
  writeAtomically(path, [&](const std::string& tmp, std::string* message) {
    char err[256] = "";
    if (m.write(path.c_str(), tmp.c_str(), width, height, isFloat ? 1 : 0, data, err, sizeof err) ==
        0)
      return true;
    *message = err;
    return false;
  });
}

}  // namespace

Format formatForPath(const std::string& path) {
  const std::string e = lowerExtension(path);
  if (e == ".png") return Format::kPng;
  if (e == ".exr") return Format::kExr;
  throw Error(path + ": unknown image format '" + e + "' (use .png or .exr)");
}

void checkWritable(const std::string& path) {
  const fs::path p(path);
  std::error_code ec;
  if (p.filename().empty() || fs::is_directory(p, ec))
    throw Error(path + ": is a directory, not a file");
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  if (!fs::is_directory(dir, ec))
    throw Error(path + ": directory " + dir.string() + " does not exist");
  if (access(dir.c_str(), W_OK) != 0)
    throw Error(path + ": cannot write into " + dir.string() + " (" + std::strerror(errno) + ")");
  if (fs::exists(p, ec) && access(p.c_str(), W_OK) != 0)
    throw Error(path + ": exists and is not writable");
}

// PNG through stb_image_write: the common output needs no OpenImageIO.
void writePng(const std::string& path, int width, int height, const uint8_t* rgba) {
  formatForPath(path);
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  for (size_t i = 0, n = rgb.size() / 3; i < n; ++i) std::memcpy(&rgb[3 * i], &rgba[4 * i], 3);
  writeAtomically(path, [&](const std::string& tmp, std::string* message) {
    if (stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), 3 * width) != 0) return true;
    *message = std::string("cannot write (") + std::strerror(errno) + ")";
    return false;
  });
}

void writeExr(const std::string& path, int width, int height, const float* rgba) {
  writeWithOiio(path, width, height, true, rgba);
}

Image readImage(const std::string& path) {
  Image img;
  if (lowerExtension(path) == ".png") {
    // stb_image, as stored: 8- or 16-bit samples to [0, 1], no transfer function.
    int w = 0, h = 0, n = 0;
    const bool wide = stbi_is_16_bit(path.c_str()) != 0;
    void* data = wide ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &n, 0))
                      : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &n, 0));
    if (!data) {
      const char* why = stbi_failure_reason();
      throw Error(path + ": cannot read image (" + (why ? why : "unreadable") + ")");
    }
    img.width = w;
    img.height = h;
    img.channels = n;
    img.pixels.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(n));
    for (size_t i = 0; i < img.pixels.size(); ++i)
      img.pixels[i] = wide ? static_cast<float>(static_cast<const uint16_t*>(data)[i]) / 65535.0f
                           : static_cast<float>(static_cast<const uint8_t*>(data)[i]) / 255.0f;
    stbi_image_free(data);
    return img;
  }
  const OiioModule& m = oiio();
  if (!m.read) throw Error(path + ": cannot read image (" + m.error + ")");
  char err[256] = "";
  const auto allocate = [](void* context, int w, int h, int c) -> float* {
    Image* image = static_cast<Image*>(context);
    if (w <= 0 || h <= 0 || c <= 0) return nullptr;
    image->width = w;
    image->height = h;
    image->channels = c;
    image->pixels.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(c));
    return image->pixels.data();
  };
  if (m.read(path.c_str(), allocate, &img, err, sizeof err) != 0) throw Error(path + ": " + err);
  return img;
}

void writeText(const std::string& path, const std::string& text) {
  checkWritable(path);
  const std::string tmp = tempPathFor(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw Error(path + ": cannot write");
    }
  }
  commit(tmp, path);
}

}  // namespace voxgi::image

#include "image/image.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <OpenImageIO/imageio.h>

#include "core/log.h"

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

void writeWithOiio(const std::string& path, int width, int height, OIIO::TypeDesc type,
                   const void* data, bool srgb) {
  checkWritable(path);
  const std::string tmp = tempPathFor(path);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error(path + ": no image writer for this format");
  // RGB on disk: alpha carries nothing here, and OIIO would (un)premultiply by it.
  OIIO::ImageSpec spec(width, height, 3, type);
  spec.attribute("oiio:ColorSpace", srgb ? "sRGB" : "linear");
  spec.attribute("Software", "voxgi");
  if (!out->open(tmp, spec)) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error(path + ": cannot write (" + out->geterror().substr(0, 200) + ")");
  }
  const OIIO::stride_t pixelStride = static_cast<OIIO::stride_t>(4 * type.size());
  const bool ok = out->write_image(type, data, pixelStride, pixelStride * width);
  const bool closed = out->close();
  if (!ok || !closed) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error(path + ": write failed (" + out->geterror().substr(0, 200) + ")");
  }
  commit(tmp, path);
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

void writePng(const std::string& path, int width, int height, const uint8_t* rgba) {
  writeWithOiio(path, width, height, OIIO::TypeDesc::UINT8, rgba, true);
}

void writeExr(const std::string& path, int width, int height, const float* rgba) {
  writeWithOiio(path, width, height, OIIO::TypeDesc::FLOAT, rgba, false);
}

Image readImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path + ": cannot read image (" + OIIO::geterror().substr(0, 200) + ")");
  const OIIO::ImageSpec& spec = in->spec();
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  img.pixels.resize(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) *
                    static_cast<size_t>(img.channels));
  if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw Error(path + ": cannot decode image (" + in->geterror().substr(0, 200) + ")");
  in->close();
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

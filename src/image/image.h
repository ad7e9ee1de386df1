// Images on disk. PNG holds display-referred sRGB 8-bit, written and read by
// stb_image; EXR linear float radiance (no tonemap), and any other format read,
// through OpenImageIO, in a module loaded on first use (oiio_module.h). Writes go to a temporary
// file beside the target and are renamed into place only when complete, so a failed write never
// leaves a partial file or destroys an earlier one.
#ifndef VOXGI_IMAGE_IMAGE_H
#define VOXGI_IMAGE_IMAGE_H

#include <cstdint>
#include <string>
#include <vector>

namespace voxgi::image {

enum class Format { kPng, kExr };

// From the file name's extension; throws voxgi::Error naming the path otherwise.
Format formatForPath(const std::string& path);

// Throws voxgi::Error (one line, naming the path) if the file cannot be created
// there: missing directory, no permission, or the path is a directory.
void checkWritable(const std::string& path);

// RGBA rows, top-left origin; the files hold RGB (alpha is dropped).
void writePng(const std::string& path, int width, int height, const uint8_t* rgba);
void writeExr(const std::string& path, int width, int height, const float* rgba);

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // as stored: 8-bit files map to [0,1], no transfer function applied
  float at(int x, int y, int c) const {
    return pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)];
  }
};

Image readImage(const std::string& path);

// Atomic write of a text file (stats JSON), same rules as the images.
void writeText(const std::string& path, const std::string& text);

}  // namespace voxgi::image

#endif  // VOXGI_IMAGE_IMAGE_H

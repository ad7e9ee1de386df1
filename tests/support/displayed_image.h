// An RGBA float image as the display shows it, for error measures that should not
// be dominated by a lamp's radiance many times display white.
#ifndef VOXGI_TESTS_DISPLAYED_IMAGE_H
#define VOXGI_TESTS_DISPLAYED_IMAGE_H

#include <algorithm>
#include <vector>

#include "image/image.h"

namespace voxgi::test {

// The RGB channels of `rgba` (width x height), each clamped to [0, 1], as the
// default tonemap clamps them.
inline image::Image displayedImage(const std::vector<float>& rgba, int width, int height) {
  image::Image im;
  im.width = width;
  im.height = height;
  im.channels = 3;
  im.pixels.reserve(rgba.size() / 4 * 3);
  for (size_t i = 0; i + 3 < rgba.size(); i += 4)
    for (size_t c = 0; c < 3; ++c) im.pixels.push_back(std::clamp(rgba[i + c], 0.0f, 1.0f));
  return im;
}

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_DISPLAYED_IMAGE_H

#include "tests/support/png_image.h"

#include <png.h>

#include <cstdlib>
#include <set>

namespace momenta::testing {

PngImage ReadPng(const std::string& path) {
  PngImage img;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    img.error = image.message;
    return img;
  }
  image.format = PNG_FORMAT_RGBA;
  img.width = image.width;
  img.height = image.height;
  img.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, img.rgba.data(), 0, nullptr)) {
    img.error = image.message;
    png_image_free(&image);
    return img;
  }
  img.ok = true;
  return img;
}

size_t PngImage::CountNotBackground() const {
  size_t n = 0;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) {
    for (size_t c = 0; c < 3; ++c) {
      if (std::abs(int(rgba[i + c]) - int(rgba[c])) > 24) {
        ++n;
        break;
      }
    }
  }
  return n;
}

size_t PngImage::CountColours() const {
  std::set<uint32_t> colours;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) {
    colours.insert(uint32_t(rgba[i]) << 16 | uint32_t(rgba[i + 1]) << 8 | rgba[i + 2]);
  }
  return colours.size();
}

}  // namespace momenta::testing

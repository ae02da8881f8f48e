#pragma once
// Decodes a PNG file with libpng (for the tests of screenshots and plots): size and RGBA pixels.

#include <cstdint>
#include <string>
#include <vector>

namespace momenta::testing {

struct PngImage {
  bool ok = false;
  std::string error;  ///< why it could not be decoded
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  ///< width * height * 4 bytes, row by row

  /// Pixels whose colour differs from the top-left pixel's (the background) by more than 24 in a
  /// channel.
  size_t CountNotBackground() const;
  /// Different colours among the pixels (RGB).
  size_t CountColours() const;
};

PngImage ReadPng(const std::string& path);

}  // namespace momenta::testing

// MAT v4 layout (MathWorks, "MAT-File Format", version 4 section): a file is a run of matrices,
// each a header of five int32 (type = 1000 M + 100 O + 10 P + T with M the byte order, 0 little-
// and 1 big-endian, O = 0, P the element type: 0 double, 1 single, 2 int32, 3 int16, 4 uint16,
// 5 uint8, and T the kind: 0 numeric, 1 text, 2 sparse; then rows, columns, imaginary flag and
// the name's length with its NUL), the name, and rows x columns elements (twice for a complex
// matrix). MAT v5 and v7.3 files start with a 128-byte text header ending in a version and "IM".

#include "app/mat_header_check.h"

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "core/base/messages.h"

namespace momenta {

namespace {

constexpr uint64_t kHeaderBytes = 20;
constexpr int64_t kMaxNameBytes = 4096;  ///< a matrix name is a short identifier

/// `n` bytes at `offset`, or fewer when the file ends first.
size_t ReadAt(int fd, uint64_t offset, void* to, size_t n) {
  size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd, static_cast<char*>(to) + got, n - got,
                              static_cast<off_t>(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += static_cast<size_t>(r);
  }
  return got;
}

int32_t Int32(const unsigned char* b, bool big_endian) {
  uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v |= static_cast<uint32_t>(b[big_endian ? 3 - k : k]) << (8 * k);
  return static_cast<int32_t>(v);
}

/// A v4 type's element size in bytes, or 0 when it is not a type momenta reads (VAX and Cray
/// formats, O other than 0, an unknown element type or kind).
uint64_t ElementBytes(int32_t type) {
  if (type < 0 || type > 1052) return 0;
  const int o = type / 100 % 10, p = type / 10 % 10, t = type % 10;
  if (o != 0 || t > 2) return 0;
  static constexpr std::array<uint64_t, 6> kBytes = {8, 4, 4, 2, 2, 1};
  return p < 6 ? kBytes[static_cast<size_t>(p)] : 0;
}

/// The name of the matrix whose name is `bytes` long at `offset`, printable, for a message.
std::string NameAt(int fd, uint64_t offset, int64_t bytes) {
  char buf[64] = {};
  const size_t n = ReadAt(fd, offset, buf, static_cast<size_t>(std::min<int64_t>(bytes, 63)));
  std::string name;
  for (size_t k = 0; k < n && buf[k] != '\0'; ++k) {
    const unsigned char c = static_cast<unsigned char>(buf[k]);
    name += c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?';
  }
  return name;
}

}  // namespace

void CheckMatHeaders(int fd, uint64_t size, const std::string& path) {
  auto invalid = [&](const std::string& why) {
    return std::runtime_error(path + ": not a valid result file: " + why);
  };
  // MAT v5 and v7.3 (HDF5) files: the version word and the "IM" byte-order mark at 124.
  unsigned char v5[4] = {};
  if (size >= 128 && ReadAt(fd, 124, v5, 4) == 4 &&
      ((v5[2] == 'I' && v5[3] == 'M') || (v5[2] == 'M' && v5[3] == 'I'))) {
    throw invalid("it is a MAT v5 or v7.3 file; result files are MAT v4 (as momenta, "
                  "OpenModelica and Dymola write them)");
  }
  uint64_t at = 0;
  for (int k = 1; at < size; ++k) {
    unsigned char h[kHeaderBytes];
    const std::string which = "matrix " + std::to_string(k) + " (at byte " + std::to_string(at) + ")";
    if (ReadAt(fd, at, h, kHeaderBytes) != kHeaderBytes) {
      throw invalid("the header of " + which + " is cut off by the end of the file");
    }
    // The byte order: the type's thousands digit, read as it is stored.
    bool big = false;
    int32_t type = Int32(h, false);
    if (ElementBytes(type) == 0 || type / 1000 != 0) {
      big = true;
      type = Int32(h, true);
    }
    const uint64_t element = ElementBytes(type);
    if (element == 0 || type / 1000 != (big ? 1 : 0)) {
      throw invalid(which + " has no MAT v4 header (type " + std::to_string(Int32(h, false)) + ")");
    }
    const int32_t rows = Int32(h + 4, big), cols = Int32(h + 8, big);
    const int32_t imaginary = Int32(h + 12, big), name_bytes = Int32(h + 16, big);
    const uint64_t left = size - at - kHeaderBytes;
    if (name_bytes < 1 || name_bytes > kMaxNameBytes || static_cast<uint64_t>(name_bytes) > left) {
      throw invalid(which + " has a name of " + std::to_string(name_bytes) + " bytes, where " +
                    std::to_string(left) + " bytes are left in the file");
    }
    const std::string name = NameAt(fd, at + kHeaderBytes, name_bytes);
    const std::string matrix = "matrix '" + name + "' (at byte " + std::to_string(at) + ")";
    if (rows < 0 || cols < 0 || (imaginary != 0 && imaginary != 1)) {
      throw invalid(matrix + " has " + std::to_string(rows) + " rows, " + std::to_string(cols) +
                    " columns and imaginary flag " + std::to_string(imaginary));
    }
    // rows x columns < 2^62; the bytes are compared by division so nothing overflows.
    const uint64_t values = static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols);
    const uint64_t value_bytes = element * (imaginary ? 2 : 1);
    const uint64_t data_left = left - static_cast<uint64_t>(name_bytes);
    if (values > data_left / value_bytes) {
      throw invalid(matrix + " claims " + std::to_string(rows) + " x " + std::to_string(cols) +
                    " values of " + std::to_string(value_bytes) + " bytes (" +
                    ByteText(static_cast<double>(values) * static_cast<double>(value_bytes)) +
                    "), where the file holds " + std::to_string(data_left) + " more bytes");
    }
    at += kHeaderBytes + static_cast<uint64_t>(name_bytes) + values * value_bytes;
  }
}

}  // namespace momenta

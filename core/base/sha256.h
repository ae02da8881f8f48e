#pragma once
/// SHA-256 (FIPS 180-4): the digest the native-code cache records for each object it writes and
/// checks before loading one. Written here from the standard rather than linked from OpenSSL's
/// libcrypto: one function over a file of a few megabytes does not justify a new shared library
/// in every momenta process (libcrypto roughly doubled the start-up of a trivial program on the
/// project's machine) and in every build. tests/core/base/sha256_test.cc checks it against the
/// standard's examples (NIST's test vectors) and against sha256sum.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace momenta {

class Sha256 {
 public:
  Sha256();
  /// Adds `size` bytes at `data` to the message.
  void Update(const void* data, size_t size);
  /// The digest of everything added, as 64 lowercase hex digits. Ends the message: Update may not
  /// follow.
  std::string HexDigest();

 private:
  void Compress(const uint8_t* block);

  std::array<uint32_t, 8> state_;
  std::array<uint8_t, 64> block_{};
  size_t used_ = 0;      ///< bytes waiting in block_
  uint64_t length_ = 0;  ///< bytes added so far
};

/// The SHA-256 of `text` in hex.
std::string Sha256Hex(const std::string& text);

}  // namespace momenta

#pragma once
/// The one way momenta opens a file a user names for reading (a model file, a file in `uses:`, a
/// result file for `report` or `plot`): refused at once unless it is a regular file no larger
/// than the caller's limit. A FIFO would block the read for ever and a device (/dev/zero) never
/// ends; both are told apart from a file before a byte is read, on the open descriptor, so that
/// nothing can be swapped in between the check and the read.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace momenta {

/// A regular file opened for reading; closed when it goes.
class RegularFile {
 public:
  /// Opens `path` without blocking (a FIFO opens at once) and checks what it is. Throws
  /// FileRefused "PATH: is a FIFO (named pipe); a <what> must be a regular file" (for a
  /// directory "PATH: is a directory, not a <what>"), "PATH: cannot open the <what>:
  /// <reason>" or "PATH: the <what> is larger than <max_bytes>..." (`too_large` is appended).
  RegularFile(const std::string& path, const std::string& what, uint64_t max_bytes,
              const std::string& too_large = "");
  ~RegularFile();
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;

  int fd() const { return fd_; }
  uint64_t size() const { return size_; }
  /// The whole file (its size when opened). Throws FileRefused when it cannot be read.
  std::string ReadAll() const;

 private:
  std::string path_, what_;
  int fd_ = -1;
  uint64_t size_ = 0;
};

/// A file refused by RegularFile; the message names the path.
class FileRefused : public std::runtime_error {
 public:
  explicit FileRefused(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace momenta

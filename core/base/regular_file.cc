#include "core/base/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/base/messages.h"

namespace momenta {

namespace {

/// What a file that is not a regular file is, in a user's words.
const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

RegularFile::RegularFile(const std::string& path, const std::string& what, uint64_t max_bytes,
                         const std::string& too_large)
    : path_(path), what_(what) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    throw FileRefused(path + ": cannot open the " + what + ": " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    throw FileRefused(path + ": cannot open the " + what + ": " + std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd_);
    const std::string kind = KindOf(st.st_mode);
    throw FileRefused(path + ": is " + kind +
                      (S_ISDIR(st.st_mode) ? ", not a " + what
                                           : "; a " + what + " must be a regular file"));
  }
  size_ = static_cast<uint64_t>(st.st_size);
  if (size_ > max_bytes) {
    ::close(fd_);
    throw FileRefused(path + ": the " + what + " is " + ByteText(static_cast<double>(size_)) +
                      ", larger than " + ByteText(static_cast<double>(max_bytes)) + too_large);
  }
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::string RegularFile::ReadAll() const {
  std::string text(size_, '\0');
  size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = ::pread(fd_, text.data() + got, text.size() - got, static_cast<off_t>(got));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw FileRefused(path_ + ": cannot read the " + what_ + ": " + std::strerror(errno));
    if (n == 0) break;  // shortened since it was opened: what is there
    got += static_cast<size_t>(n);
  }
  text.resize(got);
  return text;
}

}  // namespace momenta

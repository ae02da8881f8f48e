#include "core/compile/native_cache.h"

#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "core/base/sha256.h"

namespace momenta {

namespace {

/// An entry larger than this is not read (a model's object is a few megabytes at most).
constexpr off_t kMaxObjectBytes = off_t{1} << 30;

std::string Octal(mode_t mode) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04o", static_cast<unsigned>(mode & 07777));
  return buf;
}

/// Why a file or directory with status `st` is not the user's alone ("" when it is).
std::string Exposure(const struct stat& st) {
  if (st.st_uid != ::geteuid())
    return "belongs to another user (uid " + std::to_string(st.st_uid) + ")";
  if (st.st_mode & S_IWOTH) return "is writable by others (mode " + Octal(st.st_mode) + ")";
  if (st.st_mode & S_IWGRP) return "is writable by its group (mode " + Octal(st.st_mode) + ")";
  return "";
}

/// mkdir -p with every directory made 0700; false when some part cannot be made.
bool MakePrivateDirs(const std::string& dir) {
  for (size_t pos = 1; pos <= dir.size(); ++pos) {
    if (pos != dir.size() && dir[pos] != '/') continue;
    const std::string part = dir.substr(0, pos);
    if (::mkdir(part.c_str(), 0700) != 0 && errno != EEXIST) return false;
  }
  return true;
}

/// The whole content of the open file `fd` of `size` bytes; false on a read error.
bool ReadAll(int fd, off_t size, std::vector<char>* bytes) {
  bytes->resize(static_cast<size_t>(size));
  size_t done = 0;
  while (done < bytes->size()) {
    const ssize_t n =
        ::pread(fd, bytes->data() + done, bytes->size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

std::string Digest(const std::vector<char>& bytes) {
  Sha256 h;
  h.Update(bytes.data(), bytes.size());
  return h.HexDigest();
}

/// Opens `name` in directory `dir_fd` without following a symbolic link and checks it is a
/// regular file of the user's that nobody else may write; an invalid fd and why otherwise.
/// `what` names the file in `why` ("it", "its digest").
UniqueFd OpenOwnFile(int dir_fd, const std::string& name, const std::string& what, struct stat* st,
                     std::string* why, bool* refused) {
  UniqueFd fd(::openat(dir_fd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK));
  if (!fd.valid()) {
    *refused = errno == ELOOP;
    *why = errno == ELOOP ? what + " is a symbolic link"
                          : what + " cannot be opened: " + std::strerror(errno);
    return UniqueFd();
  }
  if (::fstat(fd.get(), st) != 0 || !S_ISREG(st->st_mode)) {
    *refused = true;
    *why = what + " is not a regular file";
    return UniqueFd();
  }
  if (std::string exposure = Exposure(*st); !exposure.empty()) {
    *refused = true;
    *why = what + " " + exposure;
    return UniqueFd();
  }
  if (st->st_size > kMaxObjectBytes) {
    *why = what + " is larger than any model's code";
    return UniqueFd();
  }
  return fd;
}

}  // namespace

UniqueFd::~UniqueFd() {
  if (fd_ >= 0) ::close(fd_);
}

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.release();
  }
  return *this;
}

NativeCache::NativeCache(const std::string& path, bool create) : path_(path) {
  if (create && !MakePrivateDirs(path)) {
    refusal_ = "the cache directory " + path + " cannot be made: " + std::strerror(errno);
    return;
  }
  fd_ = UniqueFd(::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (!fd_.valid()) {
    if (errno != ENOENT)
      refusal_ = "the cache directory " + path + " cannot be opened: " + std::strerror(errno);
    return;
  }
  struct stat st {};
  if (::fstat(fd_.get(), &st) != 0) {
    refusal_ = "the cache directory " + path + " cannot be read: " + std::strerror(errno);
  } else if (std::string exposure = Exposure(st); !exposure.empty()) {
    refusal_ = "the cache directory " + path + " " + exposure;
  }
}

bool NativeCache::Has(const std::string& key) const {
  struct stat st {};
  return usable() && ::fstatat(fd_.get(), (key + ".so").c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0;
}

CheckedObject NativeCache::Read(const std::string& key, std::string* why, bool* refused) const {
  *refused = false;
  CheckedObject object;
  // The object, through one descriptor.
  struct stat st {};
  UniqueFd fd = OpenOwnFile(fd_.get(), key + ".so", "it", &st, why, refused);
  if (!fd.valid()) return object;
  if (!ReadAll(fd.get(), st.st_size, &object.bytes)) {
    *why = "it cannot be read";
    return object;
  }
  // The digest momenta recorded when it wrote the object.
  struct stat dst {};
  UniqueFd digest_fd =
      OpenOwnFile(fd_.get(), key + ".sha256", "its digest " + key + ".sha256", &dst, why, refused);
  if (!digest_fd.valid()) {
    if (!*refused) *why = "no digest of it was recorded";
    return object;
  }
  std::vector<char> recorded;
  if (dst.st_size > 200 || !ReadAll(digest_fd.get(), dst.st_size, &recorded)) {
    *why = "its recorded digest cannot be read";
    return object;
  }
  if (std::string(recorded.begin(), recorded.end()).substr(0, 64) != Digest(object.bytes)) {
    *why = "its content is not what momenta wrote (the SHA-256 differs from the one recorded)";
    return object;
  }
  if (!IsWholeElf(object.bytes, why)) return object;
  object.fd = std::move(fd);
  return object;
}

CheckedObject NativeCache::Store(const std::string& key, const std::string& object_path,
                                 std::string* why) const {
  CheckedObject object;
  // The compiler's output, read through the descriptor that will be loaded.
  const std::string build_dir = object_path.substr(0, object_path.find_last_of('/'));
  UniqueFd dir(::open(build_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  struct stat st {};
  bool refused = false;
  UniqueFd fd = dir.valid() ? OpenOwnFile(dir.get(), object_path.substr(build_dir.size() + 1),
                                          "the compiled code", &st, why, &refused)
                            : UniqueFd();
  if (!fd.valid()) {
    if (!dir.valid()) *why = "cannot open " + build_dir;
    return object;
  }
  if (!ReadAll(fd.get(), st.st_size, &object.bytes) || ::fchmod(fd.get(), 0600) != 0) {
    *why = "cannot read the compiled code " + object_path;
    return object;
  }
  if (!IsWholeElf(object.bytes, why)) return object;
  // Its digest beside it, then both into place (each rename is atomic).
  const std::string digest_path = object_path + ".sha256";
  const std::string digest = Digest(object.bytes) + "\n";
  UniqueFd out(
      ::open(digest_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600));
  if (!out.valid() ||
      ::write(out.get(), digest.data(), digest.size()) != static_cast<ssize_t>(digest.size())) {
    *why = "cannot write " + digest_path;
    return object;
  }
  if (::renameat(AT_FDCWD, digest_path.c_str(), fd_.get(), (key + ".sha256").c_str()) != 0 ||
      ::renameat(AT_FDCWD, object_path.c_str(), fd_.get(), (key + ".so").c_str()) != 0) {
    *why = "cannot move the compiled code into " + path_;
    return object;
  }
  object.fd = std::move(fd);
  return object;
}

PrivateBuildDir::PrivateBuildDir() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/momenta-XXXXXX";
  if (::mkdtemp(pattern.data())) path_ = pattern;
}

PrivateBuildDir::~PrivateBuildDir() {
  std::error_code ignored;
  if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
}

bool IsWholeElf(const std::vector<char>& bytes, std::string* why) {
  Elf64_Ehdr eh{};
  const uint64_t size = bytes.size();
  if (size < sizeof eh ||
      (std::memcpy(&eh, bytes.data(), sizeof eh), std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0) ||
      eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_phentsize != sizeof(Elf64_Phdr)) {
    *why = "it is not a 64-bit ELF object";
    return false;
  }
  auto inside = [&](uint64_t offset, uint64_t length) {
    return offset <= size && length <= size - offset;
  };
  bool whole = inside(eh.e_phoff, uint64_t{eh.e_phnum} * eh.e_phentsize) &&
               inside(eh.e_shoff, uint64_t{eh.e_shnum} * eh.e_shentsize);
  for (uint16_t k = 0; whole && k < eh.e_phnum; ++k) {
    Elf64_Phdr ph{};
    std::memcpy(&ph, bytes.data() + eh.e_phoff + uint64_t{k} * sizeof ph, sizeof ph);
    whole = inside(ph.p_offset, ph.p_filesz);
  }
  if (!whole) *why = "it is truncated";
  return whole;
}

}  // namespace momenta

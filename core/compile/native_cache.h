#pragma once
/// The native-code cache on disk, and how an entry comes to be trusted (core/compile/native_code.h
/// uses it; nothing outside core/compile does). A shared object is only loaded when nobody else
/// could have written it:
/// - the cache directory is created 0700 (each directory momenta makes on the way, too) and is used
///   only when it is the user's own and not writable by group or others;
/// - an entry `<key>.so` is the user's own, a regular file (not a symbolic link) and not writable
///   by group or others, and its content has the SHA-256 that momenta recorded in `<key>.sha256`
///   when it wrote the entry;
/// - the checks, the digest and dlopen all work on one open descriptor (dlopen reads
///   /proc/self/fd/N), so the file cannot be swapped between the check and the load.

#include <string>
#include <vector>

namespace momenta {

/// An open file descriptor, closed with its owner.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd();
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_ = -1;
};

/// A shared object read through one descriptor whose content was checked: `fd` stays open for
/// dlopen (/proc/self/fd/N), `bytes` is what was read (and hashed).
struct CheckedObject {
  UniqueFd fd;
  std::vector<char> bytes;
};

/// The cache directory, opened once and checked (its descriptor pins it: entries are opened
/// relative to it).
class NativeCache {
 public:
  /// Opens `path`; with `create`, makes it and any missing parent 0700 first.
  NativeCache(const std::string& path, bool create);

  const std::string& path() const { return path_; }
  /// It exists and may be used.
  bool usable() const { return fd_.valid() && refusal_.empty(); }
  /// Why it may not be used ("" when usable or absent): "/tmp/x is writable by others (mode 1777)".
  const std::string& refusal() const { return refusal_; }
  /// Whether an entry for `key` is present (whatever its state).
  bool Has(const std::string& key) const;

  /// Entry `key` when it passes every check above; else an invalid fd and, in `why`, what failed.
  /// `refused` is set when the entry is someone else's or writable by others (a message the user
  /// should see), as against missing, corrupt or from an older momenta without a digest.
  CheckedObject Read(const std::string& key, std::string* why, bool* refused) const;

  /// Records `object` (a finished shared object in a private build directory) as entry `key`:
  /// reads it through one descriptor, writes its digest next to it and renames both into place.
  /// Returns the object's checked content (still open for dlopen), or an invalid fd and why not.
  CheckedObject Store(const std::string& key, const std::string& object, std::string* why) const;

 private:
  std::string path_;
  UniqueFd fd_;
  std::string refusal_;
};

/// A fresh private (0700) directory for one process's build when the cache may not be used;
/// removed with its contents on destruction.
class PrivateBuildDir {
 public:
  PrivateBuildDir();
  ~PrivateBuildDir();
  PrivateBuildDir(const PrivateBuildDir&) = delete;
  PrivateBuildDir& operator=(const PrivateBuildDir&) = delete;
  /// Empty when none could be made.
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Whether `bytes` are a whole 64-bit ELF file: every part its headers locate lies inside it.
/// dlopen maps a truncated object without complaint and the process dies of SIGBUS on first touch.
bool IsWholeElf(const std::vector<char>& bytes, std::string* why);

}  // namespace momenta

#pragma once
// Helpers for tests that run the real `momenta` binary: a temporary directory that removes itself,
// and a runner that captures the exit code, standard output and standard error.

#include <string>
#include <vector>

namespace momenta::testing {

/// A fresh directory under /tmp (mkdtemp), removed with its contents on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::string& path() const { return path_; }
  /// Writes `text` to path()/name and returns the full path.
  std::string Write(const std::string& name, const std::string& text) const;
  /// path()/name.
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

/// The whole content of a file ("" if it cannot be read).
std::string ReadText(const std::string& path);

struct CliResult {
  int exit_code = -1;  ///< the process's exit status; -1 if it did not exit normally
  std::string out, err;
};

/// Runs MOMENTA_BINARY with `args` (each passed as one word, shell-quoted) in `workdir`, with
/// stdout and stderr captured to files in a private temporary directory.
CliResult RunMomenta(const std::vector<std::string>& args, const std::string& workdir);

}  // namespace momenta::testing

#pragma once
// For the tests of the real `momenta` binary: the binary as a child process (fork/exec) that a
// test can signal, and wait for with a deadline, so a hang fails the test instead of blocking it
// (standard output and standard error go to files in the process's own temporary directory); and
// reading its CSV text.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/cli_runner.h"

namespace momenta::testing {

/// The lines of `text`, without their line ends.
inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  std::string line;
  while (std::getline(s, line)) lines.push_back(line);
  return lines;
}

/// True when `line` is `count` comma-separated numbers.
inline bool IsNumericRow(const std::string& line, size_t count) {
  std::stringstream s(line);
  std::string cell;
  size_t n = 0;
  while (std::getline(s, cell, ',')) {
    size_t used = 0;
    try {
      std::stod(cell, &used);
    } catch (const std::exception&) {
      return false;
    }
    if (used != cell.size()) return false;
    ++n;
  }
  return n == count;
}

class MomentaProcess {
 public:
  /// Starts MOMENTA_BINARY with `args` in `workdir`, through `launcher` when given (its words
  /// come first: `mpirun -n 2`, `sh -c '…; exec "$0" "$@"'`).
  MomentaProcess(const std::vector<std::string>& args, const std::string& workdir,
                 const std::vector<std::string>& launcher = {}) {
    const std::string out = capture_.File("stdout"), err = capture_.File("stderr");
    std::vector<std::string> words = launcher;
    words.push_back(MOMENTA_BINARY);
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      // The child: only async-signal-safe calls until exec.
      int in_fd = open("/dev/null", O_RDONLY);
      int out_fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      int err_fd = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (in_fd < 0 || out_fd < 0 || err_fd < 0 || chdir(workdir.c_str()) != 0) _exit(126);
      dup2(in_fd, 0);
      dup2(out_fd, 1);
      dup2(err_fd, 2);
      execvp(argv[0], argv.data());
      _exit(127);
    }
  }

  ~MomentaProcess() {
    if (pid_ > 0 && !done_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  MomentaProcess(const MomentaProcess&) = delete;
  MomentaProcess& operator=(const MomentaProcess&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  void Signal(int signal_number) { kill(pid_, signal_number); }

  /// Waits at most `seconds` for the process to end. Returns its exit status, -1 when it was
  /// killed by a signal, or -2 when it had not ended by then (it is then killed).
  int Wait(double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (true) {
      int status = 0;
      pid_t r = waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        done_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        done_ = true;
        return -2;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  std::string out() const { return ReadText(capture_.File("stdout")); }
  std::string err() const { return ReadText(capture_.File("stderr")); }

 private:
  TempDir capture_;
  pid_t pid_ = -1;
  bool done_ = false;
};

/// Runs `momenta args` in `workdir`; a run that has not ended after `seconds` is killed and
/// reported as exit status -2.
inline CliResult RunMomentaWithDeadline(const std::vector<std::string>& args, const std::string& workdir,
                                        double seconds, const std::vector<std::string>& launcher = {}) {
  MomentaProcess p(args, workdir, launcher);
  CliResult r;
  r.exit_code = p.Wait(seconds);
  r.out = p.out();
  r.err = p.err();
  return r;
}

}  // namespace momenta::testing

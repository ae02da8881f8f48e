#include "app/plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/result_reader.h"
#include "core/base/messages.h"

extern char** environ;

namespace momenta {

namespace {

/// `text` as one line of the script's text block (see GnuplotScript): a control character is
/// written as visible text (`\x0a`), so the line cannot end early.
std::string TextLine(const std::string& text) {
  std::string line = ":";
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      line += hex;
    } else {
      line += c;
    }
  }
  return line;
}

/// The first control character in `text` as `\xNN` ("" when there is none).
std::string FirstControl(const std::string& text) {
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      return hex;
    }
  }
  return "";
}

/// Throws std::invalid_argument when the result has nothing gnuplot could draw: no rows, or a
/// time that is not finite (an event's line would be drawn at it).
void CheckPlottable(const std::string& path, const ResultTable& r) {
  if (r.time.empty()) throw std::invalid_argument(path + " holds no rows: there is nothing to plot");
  for (size_t i = 0; i < r.time.size(); ++i) {
    if (!std::isfinite(r.time[i])) {
      throw std::invalid_argument(path + ": time is " + NumberText(r.time[i]) + " in row " + std::to_string(i + 1) +
                                  ": a plot needs finite times");
    }
  }
}

bool EndsWith(const std::string& s, const std::string& tail) {
  if (s.size() < tail.size()) return false;
  for (size_t k = 0; k < tail.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + k])) != tail[k])
      return false;
  }
  return true;
}

/// The columns asked for: -y may be given several times and each may hold a comma-separated list.
std::vector<std::string> Names(const std::vector<std::string>& specs) {
  std::vector<std::string> out;
  for (const auto& spec : specs) {
    std::stringstream s(spec);
    std::string name;
    while (std::getline(s, name, ',')) {
      if (!name.empty()) out.push_back(name);
    }
  }
  return out;
}

/// A private file for gnuplot's messages (removed with the object).
class MessageFile {
 public:
  MessageFile() {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::string(tmp && *tmp ? tmp : "/tmp") + "/momenta-gnuplot-XXXXXX";
    fd_ = ::mkstemp(path_.data());
  }
  ~MessageFile() {
    if (fd_ >= 0) {
      ::close(fd_);
      ::unlink(path_.c_str());
    }
  }
  MessageFile(const MessageFile&) = delete;
  MessageFile& operator=(const MessageFile&) = delete;
  int fd() const { return fd_; }
  /// Its first line that says something.
  std::string FirstLine() const {
    std::ifstream in(path_);
    for (std::string line; std::getline(in, line);) {
      if (line.find_first_not_of(" \t^") != std::string::npos && line.rfind("gnuplot>", 0) != 0) return line;
    }
    return "";
  }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace

std::string RunGnuplot(const std::string& script, const std::string& out) {
  const char* env = std::getenv("MOMENTA_GNUPLOT");
  std::string program = env && *env ? env : "gnuplot";
  MessageFile messages;
  const int image = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (image < 0) return "cannot write " + out + ": " + std::strerror(errno);
  int to_gnuplot[2];
  if (messages.fd() < 0 || ::pipe2(to_gnuplot, O_CLOEXEC) != 0) {
    ::close(image);
    return "cannot start gnuplot: " + std::string(std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, to_gnuplot[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, image, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, messages.fd(), STDERR_FILENO);
  char* argv[] = {program.data(), nullptr};
  pid_t pid = -1;
  const int spawned = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(to_gnuplot[0]);
  ::close(image);
  if (spawned != 0) {
    ::close(to_gnuplot[1]);
    ::unlink(out.c_str());
    return spawned == ENOENT ? program + " was not found (install Debian's gnuplot-nox; scripts/setup.sh does)"
                             : "cannot start " + program + ": " + std::strerror(spawned);
  }
  // A gnuplot that stops reading early must not kill momenta with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  bool written = true;
  for (size_t done = 0; done < script.size() && written;) {
    const ssize_t n = ::write(to_gnuplot[1], script.data() + done, script.size() - done);
    written = n > 0 || (n < 0 && errno == EINTR);
    if (n > 0) done += static_cast<size_t>(n);
  }
  ::close(to_gnuplot[1]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (written && WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  ::unlink(out.c_str());
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return program + " could not be run (install Debian's gnuplot-nox; scripts/setup.sh does)";
  const std::string line = messages.FirstLine();
  return "gnuplot failed writing " + out + (line.empty() ? "" : " (" + line + ")");
}

std::string GnuplotTextLine(const std::string& text) { return TextLine(text); }

std::string GnuplotScript(const PlotArgs& args, const std::string& out_path) {
  if (std::string c = FirstControl(args.title); !c.empty()) {
    throw std::invalid_argument("--title holds a control character (" + c + "): a title is one line of text");
  }
  const ResultTable r = ReadResult(args.result);
  CheckPlottable(args.result, r);
  const std::vector<std::string> names = Names(args.columns);
  if (names.empty())
    throw std::invalid_argument("-y names no column (valid: " + JoinNames(r.names, 60) + ")");
  std::vector<size_t> cols;
  for (const auto& n : names) cols.push_back(r.Column(n));

  std::ostringstream g;
  g.precision(17);
  const bool png = EndsWith(out_path, ".png");
  g << "set terminal " << (png ? "pngcairo" : "svg dynamic") << " noenhanced size " << args.width
    << "," << args.width * 5 / 9 << " font 'sans,11'\n";
  // No `set output`: gnuplot writes to its standard output, which momenta opened on the file.
  // The user's text (the title, the series' names) never stands in a command: it is a line of a
  // text block, which gnuplot keeps verbatim (no quotes to close, no backquotes or macros
  // expanded), each line after a ':' so that none is the block's end, and a command reads it
  // back as $momenta_text[k][2:].
  g << "$momenta_text << EOD\n" << TextLine(args.title.empty() ? args.result : args.title) << "\n";
  for (const std::string& name : names) g << TextLine(name) << "\n";
  g << "EOD\nset title $momenta_text[1][2:]\n";
  g << "set xlabel 'time [s]'\nset grid\nset key outside right top\n";
  // Events: two rows at one time.
  for (size_t i = 1; i < r.time.size(); ++i) {
    if (r.time[i] == r.time[i - 1] && (i < 2 || r.time[i - 2] != r.time[i])) {
      g << "set arrow from " << r.time[i] << ", graph 0 to " << r.time[i]
        << ", graph 1 nohead dashtype 2 linecolor rgb '#999999'\n";
    }
  }
  // The data inline, one block: time then the chosen columns.
  g << "$momenta << EOD\n";
  for (size_t i = 0; i < r.time.size(); ++i) {
    g << r.time[i];
    for (size_t c : cols) g << ' ' << r.values[c][i];
    g << '\n';
  }
  g << "EOD\nplot ";
  for (size_t k = 0; k < cols.size(); ++k) {
    g << (k ? ", " : "") << "$momenta using 1:" << k + 2 << " with lines linewidth 1.5 title $momenta_text["
      << k + 2 << "][2:]";
  }
  g << "\n";
  return g.str();
}

int RunPlot(const PlotArgs& args) {
  const std::string out = args.out.empty() ? WithExtension(args.result, ".svg") : args.out;
  if (!EndsWith(out, ".svg") && !EndsWith(out, ".png")) {
    std::cerr << "momenta: -o " << out
              << ": the plot is written as SVG or PNG, chosen by the extension (.svg or .png)\n";
    return kExitUsage;
  }
  std::string script;
  try {
    script = GnuplotScript(args, out);
  } catch (const std::invalid_argument& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::runtime_error& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  // gnuplot reads the program on its standard input and writes the image to its standard output.
  if (std::string failure = RunGnuplot(script, out); !failure.empty()) {
    std::cerr << "momenta: " << failure << "\n";
    return kExitSolver;
  }
  return kExitOk;
}

}  // namespace momenta

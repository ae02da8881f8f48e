#pragma once
/// The one place where the CLI's text reaches the terminal: while a TerminalOutput lives,
/// everything written to std::cout and std::cerr passes through TerminalText
/// (core/base/messages.h), so that no control character from a model, a file name or a value
/// echoed back reaches the terminal raw. Newlines and tabs pass (momenta's multi-line messages);
/// results written to standard output (`-o -`) go through stdio, not through it.

#include <ostream>
#include <streambuf>
#include <string>

namespace momenta {

/// A stream buffer that escapes control characters on their way to `target`.
class TerminalTextBuffer : public std::streambuf {
 public:
  explicit TerminalTextBuffer(std::streambuf* target) : target_(target) {}
  /// Writes a byte held back (a UTF-8 lead byte whose next byte has not come).
  void Finish();

 protected:
  int_type overflow(int_type ch) override;
  std::streamsize xsputn(const char* text, std::streamsize count) override;
  int sync() override;

 private:
  std::streambuf* target_;
  std::string held_;  ///< a trailing 0xC2 (it may begin a C1 control)
};

/// Puts TerminalTextBuffer in front of std::cout and std::cerr; restores them on destruction.
class TerminalOutput {
 public:
  TerminalOutput();
  ~TerminalOutput();
  TerminalOutput(const TerminalOutput&) = delete;
  TerminalOutput& operator=(const TerminalOutput&) = delete;

 private:
  std::streambuf* cout_;
  std::streambuf* cerr_;
  TerminalTextBuffer out_, err_;
};

}  // namespace momenta

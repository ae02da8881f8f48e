#pragma once
/// One way to write numbers, counts and lists of names in a message, whichever stage throws it, so
/// that a user reads "1e-5", "3 equations" and "a, b, c" alike from the loader, the passes and the
/// solver (Drake builds every message with one formatting style for the same reason).

#include <cstddef>
#include <string>
#include <vector>

namespace momenta {

/// `v` as written in a file: a whole number below 1e15 in full (100000), anything else in the
/// shortest text that reads back as v (1e300, 2.5, 1e-5).
std::string NumberText(double v);

/// "1 equation", "2 equations".
std::string Counted(size_t n, const char* noun);

/// A memory size: "512 MiB", "1.3 GiB", "8.7e293 GiB".
std::string ByteText(double bytes);

/// Names as a readable list: "a, b, c" (at most `limit`, then "…").
std::string JoinNames(const std::vector<std::string>& names, size_t limit = 40);

/// `text` made safe to write to a terminal: a control character (C0 but newline and tab, DEL, and
/// C1 as UTF-8, U+0080 to U+009F) becomes visible text, `\x1b` or `\u009b`, so that text from a
/// model or a file name cannot recolour, retitle or erase the user's terminal. The CLI applies it
/// to everything it writes to standard output and standard error (app/terminal_output.h).
std::string TerminalText(const std::string& text);

/// The closest names to `wanted` (edit distance), for "did you mean" hints.
std::vector<std::string> ClosestNames(const std::string& wanted,
                                      const std::vector<std::string>& candidates);

}  // namespace momenta

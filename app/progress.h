#pragma once
/// The progress line of a long command on a terminal: `simulate` shows how far simulated time has
/// come, `sweep` how many runs are done. The line is drawn on standard error only when that is a
/// terminal and the command has run longer than a second, redrawn at most five times a second in
/// place (carriage return, erase to the end of the line), and erased before the command prints its
/// summary: a pipe or a file never sees it.

#include <chrono>
#include <cstddef>
#include <string>

namespace momenta {

/// `simulate`'s progress text: "t = 12.5 / 100 s (12.5%), 3.2 s elapsed, about 22 s left". The
/// estimate assumes the rest goes as fast as the part done so far (simulated seconds per wall
/// second); it is left out until some simulated time has passed. `t` is clamped to [start, stop].
std::string FormatSimulationProgress(double t, double start, double stop, double elapsed_s);

/// `sweep`'s progress text: "sweep: 40/200 runs, 1 failed, 12.3 runs/s, about 13 s left".
std::string FormatSweepProgress(size_t done, size_t runs, size_t failed, double elapsed_s);

/// A duration for a person: "0.4 s", "12 s", "3 min 05 s", "2 h 07 min".
std::string FormatDuration(double seconds);

class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;
  /// `enabled`: the caller's choice (not --quiet); the line is drawn only if standard error is also
  /// a terminal. The second of delay starts now.
  explicit ProgressLine(bool enabled);
  /// Erases the line if it is shown.
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  /// True when Show() would draw now: the line is on, a second has passed since the start, and
  /// 200 ms since the last drawing. Lets a caller skip composing the text.
  bool Due() const;
  /// Draws `text` in place of the last one when Due().
  void Show(const std::string& text);
  /// Erases the line (before the command's own output); Show() may draw it again.
  void Clear();
  /// Seconds since construction.
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  bool enabled_;
  bool shown_ = false;
  Clock::time_point start_, last_;
};

}  // namespace momenta

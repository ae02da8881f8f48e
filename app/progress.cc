#include "app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/csv_writer.h"

namespace momenta {

namespace {

constexpr std::chrono::milliseconds kDelay(1000), kEvery(200);

}  // namespace

std::string FormatDuration(double seconds) {
  char text[64];
  if (!(seconds >= 0) || !std::isfinite(seconds)) seconds = 0;
  if (seconds < 10) {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  } else if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.0f s", std::floor(seconds));
  } else if (seconds < 3600) {
    const long s = static_cast<long>(seconds);
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  } else {
    const double capped = std::min(seconds, 9.99e6 * 3600);  // a silly estimate stays printable
    const long m = static_cast<long>(capped / 60);
    std::snprintf(text, sizeof text, "%ld h %02ld min", m / 60, m % 60);
  }
  return text;
}

std::string FormatSimulationProgress(double t, double start, double stop, double elapsed_s) {
  const double span = stop - start;
  const double done = span > 0 ? std::clamp((t - start) / span, 0.0, 1.0) : 1.0;
  const double shown_t = start + done * span;
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.1f%%", 100 * done);
  // Simulated time with 4 significant digits, the stop time as given.
  char now[32];
  std::snprintf(now, sizeof now, "%.4g", shown_t);
  std::string text = std::string("t = ") + now + " / " + FormatDouble(stop) + " s (" + percent + "), " +
                     FormatDuration(elapsed_s) + " elapsed";
  // The rest at the pace so far.
  if (done > 0 && done < 1) text += ", about " + FormatDuration(elapsed_s * (1 - done) / done) + " left";
  return text;
}

std::string FormatSweepProgress(size_t done, size_t runs, size_t failed, double elapsed_s) {
  char text[160];
  const double rate = elapsed_s > 0 ? static_cast<double>(done) / elapsed_s : 0;
  std::snprintf(text, sizeof text, "sweep: %zu/%zu runs, %zu failed, %.3g runs/s", done, runs, failed, rate);
  std::string line = text;
  // The rest at the pace so far.
  if (done > 0 && done < runs) line += ", about " + FormatDuration(static_cast<double>(runs - done) / rate) + " left";
  return line;
}

ProgressLine::ProgressLine(bool enabled)
    : enabled_(enabled && isatty(STDERR_FILENO)), start_(Clock::now()), last_(start_ - kEvery) {}

ProgressLine::~ProgressLine() { Clear(); }

bool ProgressLine::Due() const {
  if (!enabled_) return false;
  const Clock::time_point now = Clock::now();
  return now - start_ >= kDelay && now - last_ >= kEvery;
}

void ProgressLine::Show(const std::string& text) {
  if (!Due()) return;
  last_ = Clock::now();
  // Back to the line's start, the text, the rest of the old text erased.
  std::fprintf(stderr, "\r%s\033[K", text.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void ProgressLine::Clear() {
  if (!shown_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  shown_ = false;
}

}  // namespace momenta

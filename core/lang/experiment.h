#pragma once
/// A model's `experiment:` section (docs/FORMAT.md): the simulated interval, the tolerance, the
/// output grid and the solver's choices, and the limits that the section and the command line
/// share. The loader checks the section against them; the solver and the app check the values a
/// command line gives.

#include <string>

#include "core/base/error.h"

namespace momenta {

struct ExperimentSpec {
  double start = 0, stop = 1, tolerance = 1e-6;
  double interval = 0;  ///< 0: not given, (stop - start)/500
  std::string linear_solver = "auto";
  /// IDA's maximum BDF order, 1 to 5: a lightly damped model (a long chain of masses) may take
  /// fewer steps at 3 (docs/FORMAT.md; `--max-order` overrides it).
  int max_order = 5;
  SourceLoc loc;
};

/// Limits shared by the experiment section and the command line. A relative tolerance below
/// kMinRelTolerance asks for more than double precision (about 2.2e-16) can deliver; an absolute
/// tolerance below kMinAbsTolerance (the smallest normal double) makes IDA's error weights
/// overflow; an output grid of more than kMaxOutputRows rows cannot be written.
constexpr double kMinRelTolerance = 1e-15;
constexpr double kMinAbsTolerance = 2.2250738585072014e-308;
constexpr double kMaxOutputRows = 1e9;

/// What is wrong with the output grid start, start + interval, …, stop ("" when it is usable):
/// too many rows, or an interval below the time resolution at the ends.
std::string OutputGridProblem(double start, double stop, double interval);

}  // namespace momenta

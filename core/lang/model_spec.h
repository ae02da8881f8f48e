#pragma once
/// A model file as the user wrote it (docs/FORMAT.md), after reading and before flattening.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/lang/component_type.h"

namespace momenta {

struct OutputSpec {
  std::string text;
  AstPtr expr;
  SourceLoc loc;
};

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
inline std::string OutputGridProblem(double start, double stop, double interval) {
  const double rows = (stop - start) / interval;
  char buf[160];
  if (!(rows <= kMaxOutputRows)) {
    std::snprintf(buf, sizeof buf, "from %g to %g s that is %.3g output rows; at most 1e9 can be written",
                  start, stop, rows);
    return buf;
  }
  const double resolution = 1e-13 * std::max(std::fabs(start), std::fabs(stop));
  if (!(interval > resolution)) {
    std::snprintf(buf, sizeof buf, "it is below the time resolution at t = %g (%g s)",
                  std::max(std::fabs(start), std::fabs(stop)), resolution);
    return buf;
  }
  return "";
}

/// A file named in `uses:`, as written (relative to the model's own file).
struct UsesSpec {
  std::string path;
  SourceLoc loc;
};

struct ModelSpec {
  std::string name, doc, file;
  std::vector<UsesSpec> uses;  ///< read by LoadModelFile: their types are in `defines`
  std::vector<ParameterDecl> parameters;
  std::vector<ComponentType> defines;
  std::vector<ComponentSpec> components;
  std::vector<ConnectionSpec> connections;
  std::vector<VariableDecl> variables;
  std::vector<EquationDecl> equations, initial_equations;
  std::vector<WhenDecl> whens;
  ExperimentSpec experiment;
  std::vector<OutputSpec> outputs;
  SourceLoc loc;
};

}  // namespace momenta

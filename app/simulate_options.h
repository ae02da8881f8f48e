#pragma once
/// The options of `momenta simulate`: the model's experiment section with the command line's
/// values put over it, each command-line value checked on its own and the result as a whole.

#include <optional>

#include "core/lang/model_spec.h"
#include "core/compile/native_code.h"
#include "solver/simulator.h"

namespace momenta {

/// The values given on the command line; an empty optional was not given.
struct SimulateOverrides {
  std::optional<double> stop, rtol, atol, interval;
  std::optional<double> max_order;  ///< IDA's maximum BDF order, a whole number from 1 to 5
  std::optional<double> max_steps;  ///< steps allowed between two output rows, a whole number >= 1
  std::string linear_solver;  ///< empty: the experiment's
  std::string error_test;     ///< --error-test: states or all (empty: states)
  /// --codegen: auto, native or interp (empty: auto); see core/compile/native_code.h.
  std::string codegen;
};

/// The --codegen value as a mode; throws UsageError for anything but auto, native or interp.
CodegenMode ResolveCodegenMode(const SimulateOverrides& overrides);

/// The experiment's options with `overrides` over them. Throws UsageError ("--stop inf: …")
/// naming the option and its value when a value is out of range: a stop time that is not a
/// finite number after the start, a tolerance that is not finite and positive or below what
/// double precision resolves, an output interval that is not positive or gives an output grid
/// that cannot be written, a maximum order that is not a whole number from 1 to 5, a step limit that
/// is not a whole number of at least 1.
SimulationOptions ResolveSimulationOptions(const ExperimentSpec& experiment, const SimulateOverrides& overrides);

/// Why the rows of a run with `opt` cannot be kept in `out_path` with `columns` columns besides
/// time, or "" when they can: a CSV file's rows must fit in the free space of its file system, a
/// MAT file's (held in memory until the run ends) in the memory budget. Standard output ("-") is
/// not bounded. The grid's rows are counted (events add a few more, which the estimate's margin
/// covers).
std::string ResultSpaceProblem(const std::string& out_path, const SimulationOptions& opt, size_t columns);

}  // namespace momenta

#include "app/simulate_options.h"

#include <cmath>

#include "app/csv_writer.h"
#include "core/base/error.h"

namespace momenta {

namespace {

[[noreturn]] void Reject(const char* option, double value, const std::string& why) {
  throw UsageError("--" + std::string(option) + " " + FormatDouble(value) + ": " + why);
}

}  // namespace

CodegenMode ResolveCodegenMode(const SimulateOverrides& overrides) {
  CodegenMode mode = CodegenMode::kAuto;
  if (!overrides.codegen.empty() && !ParseCodegenMode(overrides.codegen, &mode)) {
    throw UsageError("--codegen " + overrides.codegen + ": the choices are auto, native and interp");
  }
  return mode;
}

SimulationOptions ResolveSimulationOptions(const ExperimentSpec& experiment, const SimulateOverrides& overrides) {
  SimulationOptions opt = OptionsFromExperiment(experiment);
  // Each value on its own.
  if (overrides.stop) {
    opt.stop = *overrides.stop;
    if (!(std::isfinite(opt.stop) && opt.stop > opt.start)) {
      Reject("stop", opt.stop, "the stop time must be a finite number after the start time " +
                                   FormatDouble(opt.start) + " (experiment.start)");
    }
  }
  if (overrides.rtol) {
    opt.rtol = *overrides.rtol;
    if (!(opt.rtol >= kMinRelTolerance && opt.rtol < 1)) {
      Reject("rtol", opt.rtol, "the relative tolerance must be a number from 1e-15 to below 1 "
                               "(double precision resolves relative differences of about 2.2e-16)");
    }
  }
  if (overrides.atol) {
    opt.atol = *overrides.atol;
    if (!(opt.atol >= kMinAbsTolerance && std::isfinite(opt.atol))) {
      Reject("atol", opt.atol, "the absolute tolerance must be a positive finite number, at least 2.2e-308 "
                               "(the smallest normal double)");
    }
  }
  if (overrides.interval) {
    opt.interval = *overrides.interval;
    if (!(opt.interval > 0 && std::isfinite(opt.interval))) {
      Reject("interval", opt.interval, "the output interval must be a positive finite number");
    }
  }
  if (overrides.max_order) {
    const double k = *overrides.max_order;
    if (!(k >= 1 && k <= 5 && k == std::floor(k))) {
      Reject("max-order", k, "the maximum BDF order must be a whole number from 1 to 5 (IDA's default is 5)");
    }
    opt.max_order = static_cast<int>(k);
  }
  if (overrides.max_steps) {
    const double k = *overrides.max_steps;
    if (!(k >= 1 && k <= 1e15 && k == std::floor(k))) {
      Reject("max-steps", k, "the number of steps allowed between two output rows must be a whole number from 1 to "
                             "1e15 (the default is " + std::to_string(kDefaultMaxSteps) + ")");
    }
    opt.max_steps = static_cast<long>(k);
  }
  if (!overrides.linear_solver.empty()) opt.linear_solver = overrides.linear_solver;
  // The output grid they make together (the experiment's own grid was checked when it was read).
  if (opt.interval > 0) {
    if (std::string grid = OutputGridProblem(opt.start, opt.stop, opt.interval); !grid.empty()) {
      if (overrides.interval) Reject("interval", opt.interval, grid);
      Reject("stop", opt.stop, "with the output interval " + FormatDouble(opt.interval) +
                                   " s (experiment.interval) " + grid + "; choose a larger --interval");
    }
  }
  return opt;
}

}  // namespace momenta

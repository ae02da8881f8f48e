#include "app/simulate_options.h"

#include <sys/statvfs.h>

#include <cmath>

#include "app/csv_writer.h"
#include "app/mat_writer.h"
#include "core/base/error.h"
#include "core/base/memory_budget.h"
#include "core/base/messages.h"

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
  if (!overrides.error_test.empty()) {
    if (overrides.error_test != "states" && overrides.error_test != "all") {
      throw UsageError("--error-test " + overrides.error_test + ": the choices are states and all");
    }
    opt.test_algebraic = overrides.error_test == "all";
  }
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

std::string ResultSpaceProblem(const std::string& out_path, const SimulationOptions& opt, size_t columns) {
  if (out_path == "-" || !(opt.interval > 0)) return "";
  const double rows = std::floor((opt.stop - opt.start) / opt.interval) + 1;
  const double values = rows * static_cast<double>(columns + 1);
  if (IsMatPath(out_path)) {
    // The MAT writer keeps every value (8 bytes) until the run ends, then writes the file.
    const double bytes = 8 * values;
    const MemoryBudget budget = BuildMemoryBudget();
    if (bytes <= budget.bytes) return "";
    return NumberText(rows) + " rows of " + NumberText(static_cast<double>(columns + 1)) +
           " columns take about " + ByteText(bytes) + " of memory until the MAT file is written, more than the " +
           ByteText(budget.bytes) + " available (" + budget.source + ")";
  }
  // A CSV value takes at most 25 bytes (17 significant digits, sign, exponent and separator).
  const double bytes = 25 * values;
  std::string dir = out_path.substr(0, out_path.find_last_of('/') + 1);
  if (dir.empty()) dir = ".";
  struct statvfs fs;
  if (statvfs(dir.c_str(), &fs) != 0) return "";  // opening the file will say what is wrong
  const double free_bytes = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
  if (bytes <= free_bytes) return "";
  return NumberText(rows) + " rows of " + NumberText(static_cast<double>(columns + 1)) + " columns may take up to " +
         ByteText(bytes) + " of CSV, more than the " + ByteText(free_bytes) + " free in " + dir;
}

}  // namespace momenta

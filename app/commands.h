#pragma once
/// The command line's subcommands. Each returns the process exit code: 0 success, 1 the model is
/// wrong, 2 usage, 3 the solver failed or the results could not be written (results so far kept),
/// 128 + the signal number when SIGINT or SIGTERM interrupted a simulation (results so far kept).

#include <string>
#include <vector>

#include <functional>
#include <map>
#include <memory>

#include "app/report_scene.h"
#include "app/simulate_options.h"
#include "core/build.h"
#include "core/compile/native_code.h"
#include "core/compile/compiled_model.h"
#include "core/compile/model_state.h"
#include "core/lang/units.h"

namespace momenta {

constexpr int kExitOk = 0, kExitModel = 1, kExitUsage = 2, kExitSolver = 3;

struct SimulateArgs {
  std::string model;
  std::vector<std::string> params;  ///< NAME=VALUE
  SimulateOverrides options;        ///< --stop, --rtol, --atol, --interval, --linear-solver
  std::string out;  ///< empty: <model file stem>.csv
  bool quiet = false;
  std::string report;          ///< --report: the HTML report to write (empty: none)
  bool scene_columns = false;  ///< --scene-columns: the scene's quantities go into the results file too
};

struct CheckArgs {
  std::string model;
  std::vector<std::string> params;
  bool verbose = false;
};

int RunSimulate(const SimulateArgs& args);
int RunCheck(const CheckArgs& args);
int RunList(const std::string& name);

/// A duration in milliseconds, three significant digits ("3.38 ms"), as the summaries print it.
std::string FormatMs(double seconds);

/// The file name of `path` without its folder and extension: "models/ball.yaml" -> "ball".
std::string FileStem(const std::string& path);

/// `path` with its extension (if any, after the last '/') replaced by `extension` (".html").
std::string WithExtension(const std::string& path, const std::string& extension);

/// The companion file of a CSV result that gives every column's unit: "out.csv" ->
/// "out.units.csv" (docs/FORMAT.md, "Units").
std::string UnitsPath(const std::string& csv_path);
/// Writes `name,unit` rows, `time,s` first; throws CsvWriteError when that fails.
void WriteUnitsFile(const std::string& path, const std::vector<std::string>& names,
                    const std::vector<std::string>& units);

/// Parses NAME=VALUE pairs; throws std::invalid_argument with a usage message. A value with a
/// unit is stored in SI in the result and recorded in `*units` (refused when `units` is null);
/// the build converts it to its parameter's declared unit (BuildOptions::override_units).
ParameterOverrides ParseOverrides(const std::vector<std::string>& pairs, OverrideUnits* units = nullptr);

/// What simulate, check and sweep start from: the built model and its parameter values.
struct LoadedModel {
  std::shared_ptr<const CompiledModel> model;
  std::unique_ptr<ModelState> state;
  BuildReport report;
  ParameterOverrides overrides;
  double load_s = 0, build_s = 0;
  std::string doc;  ///< the model's doc
  /// Set before LoadAndBuild: the model also outputs what its parts' animation draws (`scene`,
  /// app/report_scene.h), after its own outputs.
  bool with_scene = false;
  Scene scene;
  /// Set before LoadAndBuild: how the model's programs run (--codegen); the report says what
  /// was chosen and what it cost.
  NativeCodeOptions codegen;
  NativeCodeReport codegen_report;
  /// Set before LoadAndBuild: adjusts the build's options (a linearisation's held inputs and
  /// outputs, solver/linearization.h).
  std::function<void(BuildOptions*)> configure_build;
};

/// Loads and builds the model with `overrides` and sets its parameters; returns an exit code
/// (kExitOk on success) after printing what went wrong.
int LoadAndBuild(const std::string& path, const ParameterOverrides& overrides, LoadedModel* out,
                 const OverrideUnits& units = {});
/// The same with -p's NAME=VALUE texts, parsed first.
int LoadAndBuild(const std::string& path, const std::vector<std::string>& params, LoadedModel* out);

/// The run's options from the model's experiment and the command line (`*out`), and the build's
/// warnings printed; returns kExitOk, or kExitUsage after printing a bad value's message.
int ResolveRunOptions(const std::string& model_path, const LoadedModel& loaded, const SimulateOverrides& overrides,
                      SimulationOptions* out);

}  // namespace momenta

#pragma once
/// The Python module's model (`momenta.load`): a model file loaded and built once, then run any
/// number of times with other parameter values, each run on its own ModelState (as `momenta
/// sweep` runs them), several at once on threads. Plain C++ over the app's public face
/// (docs/ARCHITECTURE.md); python/module.cc binds it to Python and converts the rows to numpy.

#include <functional>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "app/simulate_options.h"
#include "core/build.h"
#include "core/compile/compiled_model.h"
#include "core/compile/native_code.h"
#include "solver/linearization.h"
#include "solver/simulation_options.h"

namespace momenta::python {

/// One run's rows and what the solver reported.
struct RunRecord {
  std::vector<double> time;
  std::vector<double> values;  ///< row-major: time.size() rows of the model's outputs
  SolverStats stats;
  /// 0: finished; 1: the model refused a parameter value; 2: an option the solver refused;
  /// 3: the solver failed (the rows before the failure are kept).
  int status = 0;
  std::string message;  ///< why the run did not finish ("" when it did)
};

/// One parameter of the built model, as `-p` names it ("eC", "A.m").
struct ParameterInfo {
  std::string name;
  double value = 0;  ///< in `unit`, with the overrides the model was loaded with
  std::string unit, description;
  bool structural = false;  ///< shaped the structure: a run cannot change it
};

/// A stop request polled while runs are under way (Python's signals: Ctrl-C).
using StopPoll = std::function<bool()>;

class PythonModel {
 public:
  /// Loads the file and builds it with `overrides` (structural parameters too); `codegen` is
  /// auto, native or interp (core/compile/native_code.h). Throws ModelError (file:line:col) for
  /// a wrong model and UsageError for an unknown parameter name or codegen mode.
  PythonModel(const std::string& path, const ParameterOverrides& overrides, const std::string& codegen);

  const std::string& path() const { return path_; }
  const std::string& model_name() const { return model_->flat->model_name; }
  const std::vector<std::string>& output_names() const { return model_->output_names; }
  std::vector<std::string> output_units() const;
  std::vector<ParameterInfo> Parameters() const;
  /// What the build and native code had to say (warnings, notes), one line each.
  const std::vector<std::string>& warnings() const { return warnings_; }
  std::string codegen_summary() const { return codegen_report_.Summary(); }
  /// The experiment section's options (what a run without options uses).
  SimulationOptions experiment_options() const;

  /// The options of a run: the experiment's with `overrides` over them. Throws UsageError naming
  /// the argument as Python spells it ("stop=-1: …").
  SimulationOptions ResolveOptions(const SimulateOverrides& overrides) const;
  /// Every run's overrides on top of the load's, checked: an unknown name or a structural
  /// parameter given another value than the model was built with is a UsageError naming it
  /// (with the closest names).
  std::vector<ParameterOverrides> RunOverrides(const std::vector<ParameterOverrides>& runs) const;

  /// With codegen auto, native code if `runs` runs repay it (as `momenta sweep` decides); the
  /// model stays as built when they do not.
  void PrepareForRuns(size_t runs);
  /// Model.linearize: the model built again as `momenta linearize` builds it (`spec`'s free inputs
  /// held, its outputs added) with the load's parameters and `params` over them, brought to `at`
  /// (the start, after the initialisation, when empty; else where a run to it ends) and
  /// linearised. Throws UsageError for an unknown name or a time outside the experiment,
  /// ModelError, and SolverError when the run or the linearisation fails.
  Linearization Linearize(const ParameterOverrides& params, std::optional<double> at,
                          const LinearizationSpec& spec) const;

  /// The built model, for RunAll (each caller keeps its own reference: PrepareForRuns may replace it).
  std::shared_ptr<const CompiledModel> compiled() const { return model_; }

 private:
  std::string path_;
  std::shared_ptr<const CompiledModel> model_;
  ParameterOverrides built_with_;  ///< the load's overrides, in the parameters' units
  NativeCodeOptions codegen_;
  NativeCodeReport codegen_report_;
  std::vector<std::string> warnings_;
};

/// Runs `model` once per overrides on `jobs` threads (at most one per run), each run on a fresh
/// ModelState; `keep_rows` false keeps only each run's last row. The calling thread waits and
/// calls `poll` about every 50 ms: true stops the runs under way between steps (their records
/// say so in SolverStats::interrupted) and starts no more. Records come in the runs' order.
std::vector<RunRecord> RunAll(const std::shared_ptr<const CompiledModel>& model, const std::string& path,
                              const std::vector<ParameterOverrides>& runs, const SimulationOptions& options,
                              unsigned jobs, bool keep_rows, const StopPoll& poll);

/// A message from the core as the Python module shows it: the command line's `-p NAME` and
/// `--stop VALUE:` become `parameter NAME` and `stop=VALUE:`.
std::string PythonText(const std::string& message);

}  // namespace momenta::python

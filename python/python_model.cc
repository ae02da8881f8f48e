// The Python module's model: load and build once (python_model.h), then runs on threads, each on
// its own ModelState, as app/sweep.cc runs a sweep's.

#include "python/python_model.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/compile/model_state.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "solver/simulator.h"

namespace momenta::python {

namespace {

/// The component library is read lazily and shared: one build at a time in a process.
std::mutex& BuildMutex() {
  static std::mutex m;
  return m;
}

/// "--max-order 7: …" -> "max_order=7: …"; every later "--name" -> "name".
std::string OptionText(std::string message) {
  if (message.rfind("--", 0) == 0) {
    const size_t space = message.find(' ');
    if (space != std::string::npos) {
      std::string name = message.substr(2, space - 2);
      std::replace(name.begin(), name.end(), '-', '_');
      message = name + "=" + message.substr(space + 1);
    }
  }
  for (size_t at = message.find(" --"); at != std::string::npos; at = message.find(" --", at + 1)) {
    if (at + 3 < message.size() && std::islower(static_cast<unsigned char>(message[at + 3]))) message.erase(at + 1, 2);
  }
  return message;
}

/// One run on a fresh state: nothing of one run reaches the next, whichever thread runs it.
RunRecord RunOne(const std::shared_ptr<const CompiledModel>& model, const std::string& path,
                 const ParameterOverrides& overrides, const SimulationOptions& options, bool keep_rows) {
  RunRecord r;
  ModelState state(model);
  try {
    state.SetParameters(overrides);
  } catch (const ModelError& e) {
    r.status = 1;
    r.message = PythonText(e.what());
    return r;
  }
  // The rows as they come (only the last one when the trajectory is not kept).
  const size_t width = model->output_names.size();
  try {
    Simulate(&state, options, [&](double t, const std::vector<double>& v) {
      if (!keep_rows && !r.time.empty()) {
        r.time.back() = t;
        std::copy(v.begin(), v.end(), r.values.end() - static_cast<std::ptrdiff_t>(width));
        return;
      }
      r.time.push_back(t);
      r.values.insert(r.values.end(), v.begin(), v.end());
    }, &r.stats);
  } catch (const SolverError& e) {
    r.status = 3;
    r.message = path + ": simulation failed " + e.what();
  } catch (const ModelError& e) {
    r.status = 1;
    r.message = PythonText(e.what());
  } catch (const std::invalid_argument& e) {
    r.status = 2;
    r.message = OptionText(e.what());
  } catch (const std::exception& e) {
    // Nothing may leave a worker thread (it would end the Python process): the run fails.
    r.status = 3;
    r.message = path + ": simulation failed: " + e.what();
  }
  return r;
}

}  // namespace

std::string PythonText(const std::string& message) {
  std::string text = OptionText(message);
  for (size_t at = text.find(": -p "); at != std::string::npos; at = text.find(": -p ", at)) {
    text.replace(at + 2, 3, "parameter ");
  }
  return text;
}

PythonModel::PythonModel(const std::string& path, const ParameterOverrides& overrides, const std::string& codegen)
    : path_(path) {
  if (!ParseCodegenMode(codegen, &codegen_.mode)) {
    throw UsageError("codegen=" + codegen + ": the choices are auto, native and interp");
  }
  // Load and build (one build at a time), then native code where it pays for one run.
  BuildReport report;
  {
    std::lock_guard<std::mutex> lock(BuildMutex());
    model_ = BuildModel(LoadModelFile(path), BuiltinLibrary(), BuildOptions(overrides), &report);
  }
  built_with_ = report.overrides;
  model_ = AttachNativeCode(std::move(model_), codegen_, &codegen_report_);
  // What the command line would print beside the run.
  for (const auto& w : report.warnings) warnings_.push_back(path + ": warning: " + w);
  for (const auto& n : report.notes) warnings_.push_back(path + ": note: " + n);
  if (!codegen_report_.note.empty()) warnings_.push_back(path + ": note: " + codegen_report_.note);
}

std::vector<std::string> PythonModel::output_units() const { return OutputUnits(*model_->flat, model_->output_names); }

std::vector<ParameterInfo> PythonModel::Parameters() const {
  // The values as a run without overrides sets them.
  ModelState state(model_);
  state.SetParameters(built_with_);
  const FlatSystem& flat = *model_->flat;
  std::vector<ParameterInfo> out;
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    const ParamId p(static_cast<uint32_t>(k));
    ParameterInfo info;
    info.name = flat.ParameterName(p);
    info.value = state.parameter_values()[k];
    info.unit = flat.ParameterUnit(p);
    info.description = flat.ParameterDoc(p);
    info.structural = flat.structural.Find(p) != nullptr;
    out.push_back(std::move(info));
  }
  return out;
}

SimulationOptions PythonModel::experiment_options() const { return OptionsFromExperiment(model_->experiment); }

SimulationOptions PythonModel::ResolveOptions(const SimulateOverrides& overrides) const {
  if (!overrides.linear_solver.empty() && overrides.linear_solver != "auto" && overrides.linear_solver != "dense" &&
      overrides.linear_solver != "klu") {
    throw UsageError("linear_solver=" + overrides.linear_solver + ": the choices are auto, dense and klu");
  }
  try {
    return ResolveSimulationOptions(model_->experiment, overrides);
  } catch (const UsageError& e) {
    throw UsageError(OptionText(e.what()));
  }
}

std::vector<ParameterOverrides> PythonModel::RunOverrides(const std::vector<ParameterOverrides>& runs) const {
  const FlatSystem& flat = *model_->flat;
  std::vector<ParameterOverrides> out;
  out.reserve(runs.size());
  for (const ParameterOverrides& run : runs) {
    ParameterOverrides merged = built_with_;
    for (const auto& [name, value] : run) {
      // An unknown name, with the closest ones.
      const std::optional<ParamId> id = flat.FindParameter(name);
      if (!id) {
        std::vector<std::string> all;
        for (uint32_t k = 0; k < flat.parameters.size(); ++k) all.push_back(flat.ParameterName(ParamId(k)));
        const std::vector<std::string> close = ClosestNames(name, all);
        throw UsageError(path_ + ": parameter " + name + ": no parameter of that name in " + flat.model_name +
                         (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                         "; Model.parameters lists them");
      }
      // A structural parameter keeps the value the model was built with.
      if (const double* built = flat.structural.Find(*id); built != nullptr && *built != value) {
        throw UsageError(path_ + ": parameter " + name + "=" + NumberText(value) + ": " + name +
                         " shapes the model's structure (a count, a connection index or a Boolean or Integer "
                         "if-condition) and the model was built with " + name + " = " + NumberText(*built) +
                         "; load the model again with params={\"" + name + "\": " + NumberText(value) + "}");
      }
      merged[name] = value;
    }
    out.push_back(std::move(merged));
  }
  return out;
}

Linearization PythonModel::Linearize(const ParameterOverrides& params, std::optional<double> at,
                                     const LinearizationSpec& spec) const {
  ParameterOverrides overrides = built_with_;
  for (const auto& [name, value] : params) overrides[name] = value;
  BuildOptions options(overrides);
  PrepareLinearizationBuild(spec, &options);
  BuildReport report;
  std::shared_ptr<const CompiledModel> model;
  {
    std::lock_guard<std::mutex> lock(BuildMutex());
    model = BuildModel(LoadModelFile(path_), BuiltinLibrary(), options, &report);
  }
  ModelState state(model);
  state.SetParameters(report.overrides);
  const SimulationOptions run = OptionsFromExperiment(model->experiment);
  const double t = at.value_or(run.start);
  if (!(std::isfinite(t) && t >= run.start && t <= run.stop)) {
    throw UsageError("at=" + NumberText(t) + ": linearise at a time from " + NumberText(run.start) + " to " +
                     NumberText(run.stop) + " s (the experiment's start and stop)");
  }
  SolverStats stats;
  const RunPoint point = SimulateTo(&state, run, t, [](double, const std::vector<double>&) {}, &stats);
  return momenta::Linearize(state, point.t, point.y, point.yp, ResolveLinearizationColumns(*model, report, spec));
}

void PythonModel::PrepareForRuns(size_t runs) {
  if (codegen_.mode != CodegenMode::kAuto || model_->native || runs <= 1) return;
  NativeCodeOptions options = codegen_;
  options.expected_runs = static_cast<double>(runs);
  NativeCodeReport report;
  model_ = AttachNativeCode(model_, options, &report);
  if (model_->native) codegen_report_ = report;
}

std::vector<RunRecord> RunAll(const std::shared_ptr<const CompiledModel>& model, const std::string& path,
                              const std::vector<ParameterOverrides>& runs, const SimulationOptions& options,
                              unsigned jobs, bool keep_rows, const StopPoll& poll) {
  std::vector<RunRecord> records(runs.size());
  std::atomic<bool> stop{false};
  SimulationOptions run_options = options;
  run_options.interrupt = &stop;
  // Threads take the next run until none is left or a stop is asked for.
  std::atomic<size_t> next{0};
  std::mutex mutex;
  std::condition_variable finished;
  unsigned active = static_cast<unsigned>(std::clamp<size_t>(jobs, 1, std::max<size_t>(runs.size(), 1)));
  std::vector<std::thread> threads;
  for (unsigned w = 0, n = active; w < n; ++w) {
    threads.emplace_back([&] {
      while (!stop.load(std::memory_order_relaxed)) {
        const size_t k = next.fetch_add(1);
        if (k >= runs.size()) break;
        records[k] = RunOne(model, path, runs[k], run_options, keep_rows);
      }
      std::lock_guard<std::mutex> lock(mutex);
      --active;
      finished.notify_one();
    });
  }
  // The calling thread polls for a stop while they run.
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (active > 0) {
      if (finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return active == 0; })) break;
      lock.unlock();
      if (poll && poll()) stop = true;
      lock.lock();
    }
  }
  for (auto& t : threads) t.join();
  return records;
}

}  // namespace momenta::python

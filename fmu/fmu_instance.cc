// One FMU instance (fmu_instance.h): the model built from the FMU's resources, and the two kinds
// of run over the solver's phases.

#include "fmu/fmu_instance.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/base/messages.h"
#include "core/build.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "fmu/fmu_resources.h"
#include "solver/crossing_search.h"
#include "solver/event_iteration.h"
#include "solver/ida_session.h"
#include "solver/initializer.h"
#include "solver/simulator.h"

namespace momenta::fmu {

FmuInstance::FmuInstance(const std::string& resources, const std::string& guid, bool co_simulation)
    : resources_(resources), co_simulation_(co_simulation) {
  const ResourceManifest manifest = ReadManifest(resources_);
  model_file_ = resources_ + "/" + manifest.model_file;
  built_with_ = manifest.overrides;
  BuildReport report;
  model_ =
      BuildModel(LoadModelFile(model_file_), BuiltinLibrary(), BuildOptions(built_with_), &report);
  built_with_ = report.overrides;
  ModelState defaults(model_);
  defaults.SetParameters(built_with_);
  parameters_ = defaults.parameter_values();
  layout_ = MakeLayout(*model_, parameters_);
  if (layout_.guid != guid) {
    throw std::runtime_error("the GUID " + guid + " is not that of the model in " + model_file_ +
                             " (" + layout_.guid +
                             "): the FMU's modelDescription.xml and its resources disagree");
  }
  options_ = OptionsFromExperiment(model_->experiment);
  row_ = [](double, const std::vector<double>&) {};
  t_ = options_.start;
}

FmuInstance::~FmuInstance() = default;

void FmuInstance::SetupExperiment(bool tolerance_defined, double tolerance, double start,
                                  bool stop_defined, double stop) {
  if (tolerance_defined && tolerance > 0) options_.rtol = tolerance;
  options_.start = start;
  if (stop_defined) options_.stop = stop;
  if (!(options_.stop > options_.start)) options_.stop = options_.start + 1;
  t_ = start;
}

void FmuInstance::CheckParameterValue(const FmuVariable& v, double value) const {
  if (v.structural && value != v.start) {
    throw std::runtime_error("parameter " + v.name + "=" + NumberText(value) + ": " + v.name +
                             " shapes the model's structure and the FMU was exported with " +
                             v.name + " = " + NumberText(v.start) + "; export it again with -p " +
                             v.name + "=" + NumberText(value));
  }
}

void FmuInstance::SetReal(uint32_t vr, double value) {
  if (vr >= layout_.variables.size())
    throw std::runtime_error("no variable with value reference " + std::to_string(vr));
  const FmuVariable& v = layout_.variables[vr];
  if (v.kind != VariableKind::kParameter) {
    throw std::runtime_error(v.name +
                             " is not a parameter: only parameters can be set (value reference " +
                             std::to_string(vr) + ")");
  }
  CheckParameterValue(v, value);
  parameters_[v.index] = value;
  built_with_[v.name] = value;
  if (!initialized_) return;
  // A tunable parameter set during the run: from now on (Co-Simulation: from the next step's
  // start, where the run restarts; Model Exchange: at once, the importer being in event mode).
  state_->SetParameters(built_with_);
  parameters_ = state_->parameter_values();
  if (co_simulation_) {
    changes_.emplace_back(t_, built_with_);
    parameters_changed_ = true;
  } else {
    solved_ = false;
  }
}

const std::vector<double>& FmuInstance::y() const { return co_simulation_ || !run_ ? y_ : run_->y; }
const std::vector<double>& FmuInstance::yp() const {
  return co_simulation_ || !run_ ? yp_ : run_->yp;
}

double FmuInstance::GetReal(uint32_t vr) {
  if (vr >= layout_.variables.size())
    throw std::runtime_error("no variable with value reference " + std::to_string(vr));
  const FmuVariable& v = layout_.variables[vr];
  if (v.kind == VariableKind::kParameter) return parameters_[v.index];
  if (!initialized_ && !initializing_) {
    throw std::runtime_error(v.name + ": no value before fmi2EnterInitializationMode");
  }
  if (!initialized_) ExitInitialization();
  if (!co_simulation_) Solve();
  const size_t yk = v.state >= 0 ? model_->state_y[static_cast<size_t>(v.state)] : 0;
  switch (v.kind) {
    case VariableKind::kState:
      return y()[yk];
    case VariableKind::kDerivative:
      return yp()[yk];
    default:
      break;
  }
  outputs_.resize(model_->output_names.size());
  state_->Outputs(t_, y().data(), yp().data(), outputs_.data());
  return outputs_[v.index];
}

void FmuInstance::ExitInitialization() {
  initializing_ = false;
  if (initialized_) return;
  state_ = std::make_unique<ModelState>(model_);
  state_->SetParameters(built_with_);
  parameters_ = state_->parameter_values();
  initial_parameters_ = built_with_;
  initialized_ = true;
  if (co_simulation_) {
    const RunPoint at = SimulateTo(state_.get(), options_, options_.start, row_, &stats_);
    t_ = at.t;
    y_ = at.y;
    yp_ = at.yp;
    return;
  }
  StartModelExchange();
}

void FmuInstance::StartModelExchange() {
  const CompiledModel& model = *model_;
  run_ = std::make_unique<IntegrationState>(options_, row_, &stats_);
  IntegrationState& run = *run_;
  // As the simulator prepares a run (simulator.cc), with no output grid to speak of.
  run.num_unknowns = model.num_unknowns();
  run.num_conditions = model.conditions.size();
  run.interval = (options_.stop - options_.start) / 500.0;
  run.outputs.resize(model.output_names.size());
  run.has_events = run.num_conditions > 0 || !model.whens.empty() || !model.impacts.empty();
  run.sparse = run.num_unknowns > kDenseLimit;
  run.crossing_values.resize(run.num_conditions);
  run.crossing_scale.assign(run.num_conditions, 1.0);
  InitializeRun(model, state_.get(), &run);
  if (run.num_unknowns > 0) {
    PolishConsistentValues(model, state_.get(), &run, options_.start);
    StartIda(model, state_.get(), &run);
  }
  run.t = options_.start;
  t_ = options_.start;
  solved_ = true;
  first_event_ = true;
  next_time_event_ = HUGE_VAL;
}

void FmuInstance::Reset() {
  state_.reset();
  run_.reset();
  initialized_ = initializing_ = false;
  ModelState defaults(model_);
  defaults.SetParameters(built_with_);
  parameters_ = defaults.parameter_values();
  options_ = OptionsFromExperiment(model_->experiment);
  t_ = options_.start;
}

// ---- Model Exchange -------------------------------------------------------------------------

void FmuInstance::SetTime(double t) {
  if (t != t_) solved_ = false;
  t_ = t;
}

void FmuInstance::SetContinuousStates(const double* x, size_t n) {
  if (!run_ || n != model_->num_states())
    throw std::runtime_error("fmi2SetContinuousStates: expected " +
                             std::to_string(model_->num_states()) + " states");
  for (size_t j = 0; j < n; ++j) run_->y[model_->state_y[j]] = x[j];
  solved_ = false;
}

void FmuInstance::GetContinuousStates(double* x, size_t n) const {
  if (!run_ || n != model_->num_states())
    throw std::runtime_error("fmi2GetContinuousStates: expected " +
                             std::to_string(model_->num_states()) + " states");
  for (size_t j = 0; j < n; ++j) x[j] = run_->y[model_->state_y[j]];
}

void FmuInstance::GetNominals(double* nominal, size_t n) const {
  for (size_t j = 0; j < n && j < model_->num_states(); ++j)
    nominal[j] = model_->nominal[model_->state_y[j]];
}

void FmuInstance::Solve() {
  if (solved_ || !run_ || run_->num_unknowns == 0) return;
  // The solver's polish, repeated until the residual stops falling: a Newton iteration on
  // F(t, y, y') = 0 for the rates of the states and the algebraic unknowns, the states held.
  IntegrationState& run = *run_;
  std::vector<double> f(run.num_unknowns);
  double last = HUGE_VAL;
  for (int round = 0; round < 8; ++round) {
    PolishConsistentValues(*model_, state_.get(), &run, t_);
    state_->Residual(t_, run.y.data(), run.yp.data(), f.data());
    double worst = 0;
    for (double r : f) worst = std::max(worst, std::fabs(r));
    if (worst == 0 || worst >= 0.5 * last) break;
    last = worst;
  }
  run.t = t_;
  solved_ = true;
}

void FmuInstance::GetDerivatives(double* dx, size_t n) {
  if (!run_ || n != model_->num_states())
    throw std::runtime_error("fmi2GetDerivatives: expected " +
                             std::to_string(model_->num_states()) + " states");
  Solve();
  for (size_t j = 0; j < n; ++j) dx[j] = run_->yp[model_->state_y[j]];
}

void FmuInstance::GetEventIndicators(double* z, size_t n) {
  if (!run_ || n != layout_.num_event_indicators) {
    throw std::runtime_error("fmi2GetEventIndicators: expected " +
                             std::to_string(layout_.num_event_indicators) + " event indicators");
  }
  Solve();
  const size_t nc = model_->conditions.size();
  if (nc > 0) state_->ZeroCrossings(t_, run_->y.data(), run_->yp.data(), z);
  // A relation of time alone, affine in it, is a time event (nextEventTime), not a crossing.
  for (size_t i = 0; i < nc && i < run_->affine_in_time.size(); ++i) {
    if (model_->conditions[i].time_only && run_->affine_in_time[i]) z[i] = 1.0;
  }
  if (model_->impacts.empty()) return;
  // An open contact's gap (it closes where the gap reaches zero); a closed one is no crossing.
  run_->contacts.Evaluate(state_.get(), t_, run_->y.data(), run_->yp.data());
  const double* discrete = state_->discrete();
  for (size_t k = 0; k < model_->impacts.size(); ++k) {
    z[nc + k] = discrete[model_->impacts[k].contact] != 0 ? 1.0 : run_->contacts.gap(k);
  }
}

bool FmuInstance::EventUpdate(double* next_event) {
  *next_event = HUGE_VAL;
  if (!run_) return false;
  Solve();
  const CompiledModel& model = *model_;
  IntegrationState& run = *run_;
  std::vector<double> before(model.num_states());
  GetContinuousStates(before.data(), before.size());
  run.t = t_;
  if (first_event_) {
    if (TimeRelationSwitchesAtStart(model, state_.get(), &run))
      DoEvent(model, state_.get(), &run, t_, true);
  } else {
    // A time event when the time is the one the last event update gave (or past it).
    DoEvent(model, state_.get(), &run, t_, t_ >= next_time_event_);
  }
  first_event_ = false;
  run.t = t_;
  solved_ = true;
  next_time_event_ = NextTimeEvent(model, state_.get(), &run);
  *next_event = next_time_event_;
  std::vector<double> after(model.num_states());
  GetContinuousStates(after.data(), after.size());
  return after != before;
}

// ---- Co-Simulation --------------------------------------------------------------------------

void FmuInstance::DoStep(double t, double h) {
  if (!initialized_) throw std::runtime_error("fmi2DoStep before fmi2ExitInitializationMode");
  if (!(h > 0))
    throw std::runtime_error("fmi2DoStep: the step size " + NumberText(h) + " is not positive");
  // One run carries on from step to step (solver/simulator.h, Simulation): its events located
  // and its impacts resolved by the solver, each step's end point consistent. A step that does
  // not start where the last one ended, or that goes past the run's stop time (the experiment's
  // when the importer gives none), starts a run from the start time again, to twice as far: the
  // cost stays linear in the number of steps.
  // Parameters set between steps take effect at the step's start: the run restarts there. A run
  // made again replays them at the times they were set.
  const double end_time = t + h;
  // (An importer that counts its time as k*h rather than adding h differs from ours by rounding.)
  const bool goes_on = std::fabs(t - t_) <= 1e-12 * std::max(1.0, std::fabs(t));
  if (!simulation_ || !goes_on || end_time > simulation_->stop()) {
    simulation_.reset();
    state_ = std::make_unique<ModelState>(model_);
    state_->SetParameters(initial_parameters_);
    SimulationOptions options = options_;
    options.interval = 0;
    if (end_time > options.stop) options.stop = options.start + 2 * (end_time - options.start);
    simulation_ = std::make_unique<Simulation>(state_.get(), options, row_, &stats_);
    for (const auto& [at, values] : changes_) {
      if (at > t) break;
      if (at > options.start) simulation_->AdvanceTo(at);
      state_->SetParameters(values);
      simulation_->ParametersChanged();
    }
    if (t > options.start) simulation_->AdvanceTo(t);
  } else if (parameters_changed_) {
    simulation_->ParametersChanged();
  }
  parameters_changed_ = false;
  const RunPoint end = simulation_->AdvanceTo(end_time);
  t_ = end.t;
  y_ = end.y;
  yp_ = end.yp;
}

}  // namespace momenta::fmu

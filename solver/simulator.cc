// The run (see the pseudocode in simulator.h): the options checked and the IntegrationState set
// up, then the loop that fits the model: with or without events, with or without unknowns. The
// phases the loops call live in their own files and share only the IntegrationState.

#include "solver/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/base/messages.h"
#include "solver/crossing_search.h"
#include "solver/event_iteration.h"
#include "solver/ida_session.h"
#include "solver/initializer.h"
#include "solver/integration_state.h"
#include "solver/output_rows.h"
#include "solver/stiffness_report.h"

namespace momenta {

namespace {

/// Sizes, the linear solver and the output grid from the options. Throws std::invalid_argument
/// for options that give no finite output grid or a BDF order IDA does not have.
void PrepareRun(const CompiledModel& model, IntegrationState* run) {
  const SimulationOptions& opt = run->options;
  run->num_unknowns = model.num_unknowns();
  run->num_conditions = model.conditions.size();
  run->interval = opt.interval == 0 ? (opt.stop - opt.start) / 500.0 : opt.interval;
  run->outputs.resize(model.output_names.size());
  run->has_events = run->num_conditions > 0 || !model.whens.empty() || !model.impacts.empty();
  run->sparse = opt.linear_solver == "klu" || (opt.linear_solver == "auto" && run->num_unknowns > kDenseLimit);
  run->stats->linear_solver = run->sparse ? "klu" : "dense";
  // The grid must be finite before its size is cast (an infinite stop would never end).
  if (!(std::isfinite(opt.start) && std::isfinite(opt.stop) && opt.stop > opt.start)) {
    throw std::invalid_argument("the stop time " + NumberText(opt.stop) + " is not a finite time after the start time " +
                                NumberText(opt.start));
  }
  if (!(run->interval > 0 && std::isfinite(run->interval))) {
    throw std::invalid_argument("the output interval " + NumberText(run->interval) + " is not a positive finite number");
  }
  if (std::string grid = OutputGridProblem(opt.start, opt.stop, run->interval); !grid.empty()) {
    throw std::invalid_argument("the output interval " + NumberText(run->interval) + ": " + grid);
  }
  if (opt.max_order < 1 || opt.max_order > 5) {
    throw std::invalid_argument("the maximum BDF order " + std::to_string(opt.max_order) + " is not one of 1 to 5");
  }
  run->num_intervals = static_cast<long>(std::ceil((opt.stop - opt.start) / run->interval - 1e-9));
  run->crossing_values.resize(run->num_conditions);
  run->crossing_scale.assign(run->num_conditions, 1.0);
}

/// The `tout` for IDASolve's next step from run.t (the step itself stops at IDASetStopTime's
/// `tstop`). IDA_ONE_STEP reads tout on the first step after a start or restart only, to size
/// that step: 0.001 of the distance to tout, less where 0.5 / |y'| is smaller (IDA's own
/// default). Aimed at one output interval ahead, as IDA_NORMAL aims at the first output row,
/// the first step follows the time scale the user asked to see rather than the length of the
/// run (a 1000 s run would otherwise start with a 1 s step, whatever the model's dynamics).
double StepTarget(const IntegrationState& run, double tstop) { return std::min(run.t + run.interval, tstop); }

/// One step at a time to `until` (the steps IDA_NORMAL would take to each output time), the
/// output rows interpolated within each step, so an interrupt is seen after every step.
void RunWithoutEvents(const CompiledModel& model, ModelState* state, IntegrationState* run, double until) {
  const double stop = until;
  SetStopTime(run, stop);
  long steps_since_row = 0;
  while (run->t < stop && !Interrupted(run, run->t)) {
    const IdaStepEnd step = StepIda(model, run, StepTarget(*run, stop));
    // IDA_NORMAL's guard: this many steps without reaching the next output time is too many.
    const long before = run->next_grid_row;
    EmitGrid(state, run, step.t, /*inclusive=*/true);
    steps_since_row = run->next_grid_row != before ? 0 : steps_since_row + 1;
    if (steps_since_row >= run->options.max_steps) FailTooMuchWork(model, run);
    run->t = step.t;
  }
}

/// Quiet crossings passed within one step before the next crossing is handled as an event (a
/// relation that keeps switching back and forth is then reported as chattering).
constexpr int kQuietPerStep = 100;

/// What a run with events does once, before its first step.
void BeginWithEvents(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  PrepareQuietCrossings(model, run);
  if (TimeRelationSwitchesAtStart(model, state, run)) DoEvent(model, state, run, run->t, true);
}

/// IDA's steps one at a time to `until`, each searched for crossings; time events as IDA stop
/// times.
void RunWithEvents(const CompiledModel& model, ModelState* state, IntegrationState* run, double until) {
  const double stop = until;
  long steps_since_row = 0;
  while (run->t < stop && !Interrupted(run, run->t)) {
    const double t_event = NextTimeEvent(model, state, run);
    const double tstop = std::min(stop, t_event);
    SetStopTime(run, tstop);
    const double t_old = run->t;
    // The same guard as without events, counted over the steps between rows (events write rows).
    if (++steps_since_row > run->options.max_steps) FailTooMuchWork(model, run);
    const long rows_before = run->next_grid_row;
    const IdaStepEnd step = StepIda(model, run, StepTarget(*run, tstop));
    // A state event inside (t_old, step.t]? Quiet crossings (they change nothing IDA's equations
    // read) are passed in the same step; at most kQuietPerStep of them, then it is an event.
    double from = t_old;
    bool restarted = false;
    for (int quiet = 0;; ++quiet) {
      const double t_cross = FirstCrossing(model, state, run, from, step.t);
      if (t_cross > step.t) break;
      EmitGrid(state, run, t_cross, /*inclusive=*/false);
      Interpolate(run, t_cross);
      if (quiet < kQuietPerStep && QuietCrossing(model, state, run, t_cross)) {
        from = t_cross;
        continue;
      }
      DoEvent(model, state, run, t_cross, false);
      restarted = true;
      break;
    }
    if (restarted) {
      steps_since_row = 0;
      continue;
    }
    const bool at_time_event = step.at_stop_time && step.t == t_event;
    EmitGrid(state, run, step.t, !at_time_event);  // an event's own rows cover its time
    if (run->next_grid_row != rows_before || at_time_event) steps_since_row = 0;
    run->t = step.t;
    if (at_time_event) {  // (one exactly at the stop time gives the run's last row)
      ReadIdaValues(run);
      DoEvent(model, state, run, step.t, true);
      EmitGridAtEvent(state, run, step.t);
    }
  }
}

/// Models without unknowns: time advances to `until` in sub-steps of the output interval, each
/// checked for crossings like an IDA step (everything is a function of time and the discrete
/// values).
void RunStateless(const CompiledModel& model, ModelState* state, IntegrationState* run, double until) {
  const double stop = until;
  const double h = run->interval / 8;
  while (run->t < stop && !Interrupted(run, run->t)) {
    const double t_event = NextTimeEvent(model, state, run);
    const double t_next = std::min({stop, t_event, run->t + h});
    const double t_cross = FirstCrossing(model, state, run, run->t, t_next);
    if (t_cross <= t_next) {
      EmitGrid(state, run, t_cross, false);
      DoEvent(model, state, run, t_cross, false);
      continue;
    }
    const bool at_time_event = t_next == t_event && t_event < HUGE_VAL;
    EmitGrid(state, run, t_next, !at_time_event);
    run->t = t_next;
    if (at_time_event) {
      DoEvent(model, state, run, t_next, true);
      EmitGridAtEvent(state, run, t_next);
    }
  }
}

/// Nothing to integrate, to `until`: the outputs are functions of time and of the discrete values.
void RunWithoutUnknowns(const CompiledModel& model, ModelState* state, IntegrationState* run, double until) {
  if (run->has_events) {
    RunStateless(model, state, run, until);
    return;
  }
  for (long& k = run->next_grid_row; k <= run->num_intervals && GridTime(*run, k) <= until &&
                                     !Interrupted(run, GridTime(*run, k - 1));
       ++k) {
    Emit(state, run, GridTime(*run, k), nullptr, nullptr);
  }
  run->t = std::max(run->t, until);
}

}  // namespace

SimulationOptions OptionsFromExperiment(const ExperimentSpec& e) {
  SimulationOptions o;
  o.start = e.start;
  o.stop = e.stop;
  o.interval = e.interval;
  o.rtol = e.tolerance;
  o.linear_solver = e.linear_solver;
  o.max_order = e.max_order;
  return o;
}

namespace {

/// A run in pieces: Start once, then Advance to later and later times, then Finish.
class RunInPieces {
 public:
  RunInPieces(ModelState* state, const SimulationOptions& options, const RowCallback& row, SolverStats* stats)
      : model_(state->model()), state_(state), options_(options), row_(row), run_(options_, row_, stats) {}

  /// The initialisation, the first row and IDA's start (with the initial event).
  void Start() {
    PrepareRun(model_, &run_);
    InitializeRun(model_, state_, &run_);
    if (run_.num_unknowns > 0) {
      PolishConsistentValues(model_, state_, &run_, options_.start);
      StartIda(model_, state_, &run_);
    }
    run_.t = options_.start;
    run_.next_grid_row = 1;
    run_.integration_started = std::chrono::steady_clock::now();
    if (run_.has_events) {
      if (run_.num_unknowns == 0) {
        if (TimeRelationSwitchesAtStart(model_, state_, &run_)) DoEvent(model_, state_, &run_, run_.t, true);
      } else {
        BeginWithEvents(model_, state_, &run_);
      }
    }
  }

  /// On to `until` (at most the options' stop time).
  void Advance(double until) {
    until = std::min(until, options_.stop);
    if (run_.num_unknowns == 0) {
      RunWithoutUnknowns(model_, state_, &run_, until);
    } else if (!run_.has_events) {
      RunWithoutEvents(model_, state_, &run_, until);
    } else {
      RunWithEvents(model_, state_, &run_, until);
    }
  }

  /// New parameter values where the run stands: a restart, as after an event, and the time
  /// events sought again.
  void ParametersChanged() {
    run_.time_events_stale = true;
    if (run_.num_unknowns == 0) return;
    run_.restarted_at = NAN;  // (a restart at the same time and values is otherwise skipped)
    Restart(model_, state_, &run_, run_.t);
  }

  /// The statistics and, at the stop time, the cost note.
  void Finish() {
    SolverStats* stats = run_.stats;
    if (run_.num_unknowns > 0) CollectIdaStats(&run_);
    stats->integrate_seconds = SecondsSince(run_.integration_started);
    if (run_.num_unknowns > 0 && !stats->interrupted) {
      stats->cost_note = StepCostNote(*state_, run_.t, run_.y, run_.yp, run_.interval, stats->steps, run_.num_intervals);
    }
  }

  /// Where the run stands, its rates and algebraic unknowns made consistent with the states (the
  /// last row's values are IDA's interpolant).
  RunPoint Point() {
    if (run_.num_unknowns == 0) return {run_.t, {}, {}};
    PolishConsistentValues(model_, state_, &run_, run_.t);
    return {run_.t, run_.y, run_.yp};
  }

 private:
  const CompiledModel& model_;
  ModelState* state_;
  SimulationOptions options_;
  RowCallback row_;
  IntegrationState run_;
};

/// The run itself; `end`, when given, receives where it stands at its end.
void Run(ModelState* state, const SimulationOptions& options, const RowCallback& row, SolverStats* stats,
         RunPoint* end) {
  RunInPieces run(state, options, row, stats);
  run.Start();
  run.Advance(options.stop);
  run.Finish();
  if (end) *end = run.Point();
}

}  // namespace

void Simulate(ModelState* state, const SimulationOptions& options, const RowCallback& row,
              SolverStats* stats) {
  Run(state, options, row, stats, nullptr);
}

struct Simulation::Pieces : RunInPieces {
  using RunInPieces::RunInPieces;
};

Simulation::Simulation(ModelState* state, const SimulationOptions& options, const RowCallback& row,
                       SolverStats* stats)
    : pieces_(std::make_unique<Pieces>(state, options, row, stats)), stop_(options.stop) {
  pieces_->Start();
}

Simulation::~Simulation() = default;

RunPoint Simulation::AdvanceTo(double t) {
  if (!(t <= stop_)) {
    throw std::invalid_argument("the time " + NumberText(t) + " is past the run's stop time " + NumberText(stop_));
  }
  pieces_->Advance(t);
  pieces_->Finish();
  return pieces_->Point();
}

void Simulation::ParametersChanged() { pieces_->ParametersChanged(); }

RunPoint SimulateTo(ModelState* state, SimulationOptions options, double t, const RowCallback& row,
                    SolverStats* stats) {
  if (!(std::isfinite(t) && t >= options.start)) {
    throw std::invalid_argument("the time " + NumberText(t) + " is not a finite time from the start time " +
                                NumberText(options.start) + " on");
  }
  RunPoint end;
  if (t > options.start) {
    options.stop = t;
    Run(state, options, row, stats, &end);
    return end;
  }
  // At the start: the initialisation alone.
  const CompiledModel& model = state->model();
  IntegrationState run(options, row, stats);
  PrepareRun(model, &run);
  InitializeRun(model, state, &run);
  if (run.num_unknowns > 0) PolishConsistentValues(model, state, &run, options.start);
  return {options.start, run.y, run.yp};
}

}  // namespace momenta

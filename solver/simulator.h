#pragma once
/// Integration of a compiled model with SUNDIALS IDA (BDF, variable order 1-5), from consistent
/// initial values, with output at a fixed interval. The linear solver is dense LU for small
/// systems and KLU (sparse LU) for large ones unless chosen.

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/compile/model_state.h"

namespace momenta {

struct SimulationOptions {
  double start = 0, stop = 1;
  double interval = 0;      ///< 0: (stop - start)/500; otherwise positive
  double rtol = 1e-6;
  double atol = -1;         ///< < 0: rtol; each variable's is atol*nominal
  std::string linear_solver = "auto";  ///< auto, dense or klu
  /// IDA's highest BDF order, 1..5 (IDASetMaxOrd). Orders 3 and above are not A-stable: on lightly
  /// damped oscillations IDA's order choice can wander into 4 and 5 and pay for it in steps
  /// (bench/RESULTS.md, "The chain's extra steps"), where 3 takes fewer and is as accurate.
  int max_order = 5;
  /// Left- and right-limit rows at every event, also one that changes no output (as Dymola's
  /// events=true output, which the MSL reference results use); otherwise only at events that
  /// change an output.
  bool rows_at_every_event = false;
  /// When set and raised (by a signal handler), the run stops before the next step or output row:
  /// the rows so far have been given out, SolverStats::interrupted says so, no error is thrown.
  const std::atomic<bool>* interrupt = nullptr;
};

/// Systems with at most this many unknowns use dense LU under "auto".
constexpr size_t kDenseLimit = 40;

struct SolverStats {
  std::string linear_solver;
  long steps = 0, residual_evals = 0, jacobian_evals = 0, error_test_failures = 0,
       nonlinear_failures = 0, init_iterations = 0;
  long events = 0, time_events = 0, impacts = 0, restarts = 0;
  std::vector<double> impact_times;  ///< when each impact happened (for tests and summaries)
  double init_seconds = 0, integrate_seconds = 0;
  double final_time = 0;
  bool interrupted = false;   ///< SimulationOptions::interrupt stopped the run
  double interrupted_at = 0;  ///< how far the integration had come then
};

/// Called for every output row: time and the outputs in CompiledModel::output_names order.
using RowCallback = std::function<void(double t, const std::vector<double>& outputs)>;

/// Events (docs/FORMAT.md, "Events"): between events every relation outside noEvent() keeps the
/// value it had after the last event; its zero-crossing function is watched on IDA's interpolant at
/// the end of each step and at interior points, so a sign change inside a step is not missed
/// however large the step; between samples it is modelled by the cubic through its values and time
/// derivatives, and sampled again where that cubic dips more than halfway to zero, so a crossing
/// there and back between samples is found too (README, "Events and impacts", says when). The event is located by the Illinois method on the interpolant;
/// relations of time alone that are affine in it (Step, Ramp, startTime) are hit exactly as IDA
/// stop times. At an event: a left-limit output row; impacts are resolved one contact at a time
/// (the fastest approaching first) until none approaches; the event iteration updates conditions
/// (right-limit values: a relation whose function is within rounding of zero takes the value its
/// derivative points to), discrete equations, when-clauses and releases until nothing changes;
/// IDA restarts from consistent values (IDACalcIC); a right-limit row follows. More than
/// kChatterLimit events in a row less than kChatterSpacing apart stop the run as chattering.
constexpr int kChatterLimit = 200;

/// Runs the simulation. Rows reach `row` as they are computed, so a failure keeps what came
/// before it; the failure is then thrown as SolverError ("at t = …: …") after `stats` is filled.
/// Options that give no finite output grid (stop not finite or not after start, an interval that
/// is not positive or gives more than kMaxOutputRows rows) throw std::invalid_argument.
void Simulate(ModelState* state, const SimulationOptions& options, const RowCallback& row,
              SolverStats* stats);

/// The options a model's experiment section asks for.
SimulationOptions OptionsFromExperiment(const ExperimentSpec& e);

}  // namespace momenta

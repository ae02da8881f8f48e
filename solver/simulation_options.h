#pragma once
/// What a simulation is asked to do and what it reports back: the options of one run, the
/// statistics it fills and the callback that takes its rows. Apart from simulator.h, so that
/// whoever fills options or reads statistics sees no more of the solver (Drake's
/// simulator_config.h beside simulator.h).

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace momenta {

/// SimulationOptions::max_steps unless the user sets it (--max-steps).
constexpr long kDefaultMaxSteps = 500000;

struct SimulationOptions {
  double start = 0, stop = 1;
  double interval = 0;      ///< 0: (stop - start)/500; otherwise positive
  double rtol = 1e-6;
  double atol = -1;         ///< < 0: rtol; each variable's is atol*nominal
  std::string linear_solver = "auto";  ///< auto, dense or klu
  /// IDA's highest BDF order, 1..5 (IDASetMaxOrd). Orders 3 and above are not A-stable: on lightly
  /// damped oscillations IDA's order choice can wander into 4 and 5 and pay for it in steps, where
  /// 3 is as accurate (bench/RESULTS.md, "The chain's extra steps", measures it).
  int max_order = 5;
  /// At most this many steps between two output rows (IDASetMaxNumSteps' meaning for a run that
  /// steps one at a time); more stop the run with a message that names the model's fastest modes.
  long max_steps = kDefaultMaxSteps;
  /// Whether IDA's local error test covers every unknown (IDA's own default) or, when false, the
  /// states only, leaving out the algebraic unknowns that follow from them (forces, accelerations,
  /// currents), as an ODE solver on the model's state-space form does (DASSL in Dymola's ODE form);
  /// a kink in such an unknown (a friction force's |v|) then costs no steps (--error-test). A
  /// model that index reduction differentiated keeps every unknown tested.
  bool test_algebraic = false;
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

/// More than this many events in a row, each within 1e-10 s (relative to t) of the one before,
/// stop the run as chattering.
constexpr int kChatterLimit = 200;

struct SolverStats {
  std::string linear_solver;
  long steps = 0, residual_evals = 0, jacobian_evals = 0, error_test_failures = 0,
       nonlinear_failures = 0, init_iterations = 0;
  /// Event instants (state and time events) that changed what the equations read; a relation's
  /// crossing that changed nothing else (a threshold only a discrete equation reads, whose value
  /// stays) is counted as a quiet crossing instead, and IDA goes on without a restart.
  long events = 0, time_events = 0, impacts = 0, restarts = 0, quiet_crossings = 0;
  std::vector<double> impact_times;  ///< when each impact happened (for tests and summaries)
  double init_seconds = 0, integrate_seconds = 0;
  double final_time = 0;
  std::vector<double> event_times;  ///< when each event happened (time events and impacts too)
  /// Set when the run took far more steps per output interval than a smooth solution needs: how
  /// many, the model's fastest modes and what helps (solver/stiffness_report.h, StepCostNote).
  std::string cost_note;
  bool interrupted = false;   ///< SimulationOptions::interrupt stopped the run
  double interrupted_at = 0;  ///< how far the integration had come then
};

/// Called for every output row: time and the outputs in CompiledModel::output_names order.
using RowCallback = std::function<void(double t, const std::vector<double>& outputs)>;

}  // namespace momenta

#pragma once
/// Integration of a compiled model with SUNDIALS IDA (BDF, variable order 1-5), from consistent
/// initial values, with output at a fixed interval and events. The linear solver is dense LU for
/// small systems and KLU (sparse LU) for large ones unless chosen.
///
/// A run, as the phases carry it out over one IntegrationState (integration_state.h):
///
///   InitializeRun: discrete and continuous start values until they agree, the first row,
///                  the initial event (initializer.cc)
///   no unknowns:   RunStateless, sub-steps of the output interval searched for crossings like
///                  IDA steps; without events only the grid rows
///   otherwise:     PolishConsistentValues, StartIda (ida_session.cc)
///     if a relation of time alone switches at the start: DoEvent(start)
///     while t < stop and not interrupted:
///       tstop := min(stop, the next time event)               (crossing_search.cc)
///       one IDA step from t to t1 <= tstop
///       tc := FirstCrossing(t, t1)                             (crossing_search.cc)
///       if tc <= t1:  the grid rows before tc (output_rows.cc); y, y' := the interpolant at tc;
///                     DoEvent(tc)                              (event_iteration.cc, impacts.cc)
///       else:         the grid rows up to t1; t := t1;
///                     at the time event: DoEvent(t1), then its grid row if no event row stood for it
///
/// Without events, RunWithoutEvents takes IDA's steps one at a time to the stop time and writes
/// the grid rows within each.

#include <memory>
#include <string>
#include <vector>

#include "core/compile/model_state.h"
#include "solver/simulation_options.h"

namespace momenta {

/// Runs the simulation. Rows reach `row` as they are computed, so a failure keeps what came
/// before it; the failure is then thrown as SolverError ("at t = …: …") after `stats` is filled.
/// Options that give no finite output grid (stop not finite or not after start, an interval that
/// is not positive or gives more than kMaxOutputRows rows) throw std::invalid_argument.
void Simulate(ModelState* state, const SimulationOptions& options, const RowCallback& row,
              SolverStats* stats);

/// Where a run stands: the time and the unknowns y, y' there, consistent (F(t, y, y') = 0 with
/// the rates and algebraic unknowns polished for the states: PolishConsistentValues).
struct RunPoint {
  double t = 0;
  std::vector<double> y, yp;
};

/// The model's values at `t`, for what looks at the model where it stands (linearisation): at
/// options.start, those of the initialisation (after the initial event); later, where a run from
/// options.start to t (options.stop := t, its rows to `row`) ends. Throws as Simulate does, and
/// std::invalid_argument for a t before the start or not finite.
RunPoint SimulateTo(ModelState* state, SimulationOptions options, double t, const RowCallback& row,
                    SolverStats* stats);

/// A run that goes on in pieces (Co-Simulation's steps, fmu/): initialised and IDA started when
/// made; AdvanceTo(t) integrates on from where the last piece ended to t, with the events and
/// impacts on the way, its rows to `row` and `stats` updated, and gives the values there,
/// consistent. One run in one piece is Simulate's. Throws as Simulate does, and
/// std::invalid_argument for a t past options.stop.
class Simulation {
 public:
  Simulation(ModelState* state, const SimulationOptions& options, const RowCallback& row, SolverStats* stats);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  RunPoint AdvanceTo(double t);
  /// The state's parameters were set anew (ModelState::SetParameters) where the run stands: IDA
  /// restarts there from values made consistent with them (the states kept), as after an event.
  void ParametersChanged();
  double stop() const { return stop_; }

 private:
  struct Pieces;
  std::unique_ptr<Pieces> pieces_;
  double stop_;
};

/// The options a model's experiment section asks for.
SimulationOptions OptionsFromExperiment(const ExperimentSpec& e);

/// What the solver was built with, for --version and run summaries.
struct SolverBuild {
  std::string sundials_version;     ///< "6.4.1"
  bool sundials_optimized = false;  ///< the optimised SUNDIALS (built from source with -O2)
};
SolverBuild SolverBuildInfo();

}  // namespace momenta

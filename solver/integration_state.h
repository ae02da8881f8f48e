#pragma once
/// The record that every phase of a run shares: what was asked, the solution at the current time,
/// the output grid's position, the zero-crossing functions and their samples, the event
/// bookkeeping and the IDA session. The phases are free functions over
/// (const CompiledModel&, ModelState*, IntegrationState*), one file each (SUNDIALS' IDAMemRec in
/// ida_impl.h, which ida.c, ida_ic.c and ida_ls.c share): ida_session.cc, crossing_search.cc,
/// event_iteration.cc, impacts.cc, output_rows.cc, initializer.cc, and the run loops in
/// simulator.cc. Each group below says which phases write it.

#include <chrono>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/compile/model_state.h"
#include "solver/simulation_options.h"

namespace momenta {

/// SUNDIALS' objects for the run (ida_session.cc): IDA's memory, its vectors, the linear solver.
class IdaSession;
/// Frees an IdaSession (defined where it is complete, so that this header needs no SUNDIALS).
struct IdaSessionDeleter {
  void operator()(IdaSession* session) const;
};

/// The zero-crossing functions and their time derivatives at one time (crossing_search.cc).
struct CrossingSample {
  double t = 0;
  std::vector<double> z, dz;      ///< per condition
  std::vector<double> gap, rate;  ///< per impact: its gap and velocity (the gap's rate)
};

/// ModelState::ImpactValues' output, five values per impact, with their names.
struct ImpactValues {
  std::vector<double> values;

  /// Evaluates every impact's values at (t, y, y').
  void Evaluate(ModelState* state, double t, const double* y, const double* yp) {
    values.resize(5 * state->model().impacts.size());
    state->ImpactValues(t, y, yp, values.data());
  }
  double gap(size_t k) const { return values[5 * k]; }
  double velocity(size_t k) const { return values[5 * k + 1]; }  ///< the gap's rate
  double restitution(size_t k) const { return values[5 * k + 2]; }
  double small_velocity(size_t k) const { return values[5 * k + 3]; }  ///< slower: it closes
  bool release(size_t k) const { return values[5 * k + 4] != 0; }     ///< closed: it opens
};

struct IntegrationState {
  IntegrationState(const SimulationOptions& run_options, const RowCallback& row_callback,
                   SolverStats* run_stats)
      : options(run_options), row(row_callback), stats(run_stats) {}

  // ---- What was asked, fixed before the run starts (simulator.cc) ----------------------------
  const SimulationOptions& options;
  const RowCallback& row;
  SolverStats* stats;
  size_t num_unknowns = 0;
  size_t num_conditions = 0;
  double interval = 0;     ///< between output rows
  long num_intervals = 0;  ///< of the output grid; the last one may be shorter
  bool has_events = false;  ///< conditions, when-clauses or impacts
  bool sparse = false;      ///< KLU, not dense LU

  // ---- The solution: y, y' at t (every phase) ----------------------------------------------
  double t = 0;
  std::vector<double> y, yp;
  std::chrono::steady_clock::time_point integration_started;  ///< after the initialisation

  // ---- The output grid (output_rows.cc) ------------------------------------------------------
  long next_grid_row = 1;       ///< the grid index of the next row to write
  std::vector<double> outputs;  ///< the last row's outputs

  // ---- The conditions' zero-crossing functions (crossing_search.cc, event_iteration.cc) -------
  std::vector<double> crossing_values;  ///< z per condition, as last evaluated
  std::vector<double> crossing_scale;   ///< per condition, the largest |z| so far (at least 1)
  /// Per condition: at zero with a nonzero rate in the first round of the last event, so set by
  /// its rate; it stays set while its function creeps across zero there.
  std::vector<bool> moving_at_zero;
  ImpactValues contacts;  ///< as last evaluated (OverlappingContact reads ContactCloses' values)

  // ---- The crossing search between and inside steps (crossing_search.cc) ---------------------
  std::vector<size_t> cubic_watched;  ///< conditions watched with a cubic model
  CrossingSample sample;              ///< at the end of the last step
  CrossingSample next_sample;         ///< at the next sample time (kept to reuse its storage)
  bool sample_valid = false;          ///< `sample` is at the current step's start
  int refinements_left = 0;           ///< extra samples the current step may still take

  // ---- Time events (crossing_search.cc) ------------------------------------------------------
  double next_time_event = HUGE_VAL;
  bool time_events_stale = true;    ///< an event has happened since next_time_event was computed
  std::vector<bool> affine_in_time;  ///< per condition: of time alone and affine in it (scheduled)

  // ---- Event bookkeeping (event_iteration.cc) ------------------------------------------------
  double last_event_time = -HUGE_VAL;  ///< of the last event that wrote rows
  int close_events = 0;  ///< events in a row within 1e-10 s (relative) of last_event_time
  std::vector<bool> when_true;         ///< per when-clause: its condition when last evaluated
  /// Per condition: the residual or its Jacobian reads it (a crossing of one that is not read
  /// changes IDA's equations only through discrete values). Empty when no crossing may be quiet
  /// (impacts, or equations that read pre-values of y).
  std::vector<bool> residual_reads_condition;

  // ---- The last restart (ida_session.cc): a restart from the same values at the same time is
  // not repeated ----------------------------------------------------------------------------------
  double restarted_at = HUGE_VAL;
  std::vector<double> restarted_y, restarted_event_values;

  // ---- IDA (ida_session.cc); null for a model without unknowns -------------------------------
  std::unique_ptr<IdaSession, IdaSessionDeleter> ida;
};

/// Seconds since `since` by the steady clock.
inline double SecondsSince(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace momenta

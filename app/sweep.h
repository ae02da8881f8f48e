#pragma once
/// `momenta sweep`: one model built once, simulated for many parameter values on several threads,
/// and under mpirun on several processes (app/sweep_cluster.h).
///
/// The runs (app/sweep_plan.h) share one CompiledModel, each with its own ModelState, so the table
/// is the same for any --jobs and any number of MPI ranks (app/sweep_cluster.h).
///
/// Fixed values are applied when the model is built (so a fixed value may be a structural
/// parameter: a count, a connection index, a Boolean or Integer `if` condition); swept parameters
/// must not be structural (a usage error naming them).

#include <cstdint>
#include <string>
#include <vector>

#include "app/simulate_options.h"
#include "app/sweep_plan.h"

namespace momenta {

struct SweepArgs {
  std::string model;
  std::vector<std::string> params;  ///< NAME=SPEC
  SimulateOverrides options;        ///< --stop, --rtol, --atol, --interval, --max-order, --linear-solver
  unsigned jobs = 0;                ///< threads per process; 0: the cores / the ranks on this machine
  std::string out;                  ///< summary CSV; empty: <model file stem>_sweep.csv; "-": stdout
  std::string trajectories;         ///< directory for run-<k>.csv; empty: none written
  uint64_t seed = 0;
  size_t samples = 0;               ///< Monte Carlo draws (needs a distribution)
  bool quiet = false;
};

/// Runs the sweep and writes the summary: one row per run in run order, columns `run`, each -p
/// parameter, each output's final value, `steps`, `events`, `status` (0, or the exit code the run
/// alone would have had: 1 a parameter value the model refuses, 3 the solver failed) and
/// `message`. Returns 0 when every run succeeded, 3 when some failed (their rows say why), 2 for
/// usage errors, 1 for a wrong model, 128 + signal when interrupted (the finished rows kept). Under
/// mpirun, rank 0 writes the summary and returns that code; the other ranks return 0, or their own
/// code when they could not prepare the sweep.
int RunSweep(const SweepArgs& args);

}  // namespace momenta

#pragma once
/// Consistent initial values for IDA: Newton's method (KINSOL, with line search and an exact
/// sparse Jacobian every iteration) on the initialisation system [F(t0, y, y') = 0; G = 0], whose
/// unknowns are y and the states' y' and whose G holds the fixed start values and initial
/// equations. Start values of the other variables are the first guess; where KINSOL's LU meets a
/// singular system that holds (some unknowns left free), Newton steps of least norm (Eigen's
/// complete orthogonal decomposition) pick the solution nearest the guesses. InitializeRun starts a
/// run from it: discrete and continuous values iterate until they agree.

#include <string>
#include <vector>

#include "core/compile/model_state.h"
#include "solver/integration_state.h"

namespace momenta {

struct InitialValues {
  std::vector<double> y, yp;
  long iterations = 0;
  double max_residual = 0;
};

/// Throws SolverError naming the equation with the largest residual when Newton fails, and
/// ModelError naming them when initial conditions left out as redundant do not hold at the
/// solution (inconsistent fixed start values).
InitialValues SolveInitialization(ModelState* state, double t0, bool sparse);

/// The start of a run, at options.start: the discrete values and the continuous ones (by
/// SolveInitialization) until they agree, the when-clauses at the start, the first row, and the
/// initial event with a second row when it changes something. Leaves run->y, run->y' consistent.
void InitializeRun(const CompiledModel& model, ModelState* state, IntegrationState* run);

}  // namespace momenta

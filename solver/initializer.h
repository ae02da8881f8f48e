#pragma once
/// Consistent initial values for IDA: Newton's method (KINSOL, with line search and an exact
/// sparse Jacobian every iteration) on the initialisation system [F(t0, y, y') = 0; G = 0], whose
/// unknowns are y and the states' y' and whose G holds the fixed start values and initial
/// equations. Start values of the other variables are the first guess.

#include <string>
#include <vector>

#include "core/compile/model_state.h"

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

}  // namespace momenta

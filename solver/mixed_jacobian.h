#pragma once
/// The matrix of the DAE F(t, y, y') = 0 taken over an instant, in which the states jump and the
/// algebraic unknowns take new values:
///     M = [dF/dy' over the states | dF/dy over the algebraic unknowns],
/// the matrix of IDACalcIC's YA_YDP_INIT step. An impact solves M [Δx; Λ] = b for the states'
/// jumps and the impulses (impacts.cc); the polish after a start or restart solves with it for the
/// states' rates and the algebraic unknowns (ida_session.cc).

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <vector>

#include "core/compile/model_state.h"

namespace momenta {

class MixedJacobian {
 public:
  /// Evaluates dF/dy and dF/dy' at (t, y, y') in the Jacobian's pattern.
  MixedJacobian(ModelState* state, double t, const double* y, const double* yp);

  /// Factors M; false when it is singular.
  bool Factor();
  /// M⁻¹ b, once factored.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const { return lu_.solve(b); }

  /// dF/dy in the Jacobian's pattern (CompiledModel::jacobian_pattern).
  const std::vector<double>& dfdy() const { return dfdy_; }

 private:
  const CompiledModel& model_;
  std::vector<double> dfdy_, dfdyp_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
};

}  // namespace momenta

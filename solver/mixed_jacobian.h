#pragma once
/// The matrix of the DAE F(t, y, y') = 0 taken over an instant, in which the states jump and the
/// algebraic unknowns take new values:
///     M = [dF/dy' over the states | dF/dy over the algebraic unknowns],
/// the matrix of IDACalcIC's YA_YDP_INIT step. An impact solves M [Δx; Λ] = b for the states'
/// jumps and the impulses (impacts.cc); the polish after a start or restart solves with it for the
/// states' rates and the algebraic unknowns (ida_session.cc), and so does a restart whose matrix
/// is singular, by steps of least norm (SolveMixedByMinimumNormSteps).

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <vector>

#include "core/compile/model_state.h"

namespace momenta {

class MixedJacobian {
 public:
  /// Evaluates dF/dy and dF/dy' at (t, y, y') in the Jacobian's pattern.
  MixedJacobian(ModelState* state, double t, const double* y, const double* yp);
  /// Evaluates them again at another (t, y, y'), to be factored anew (Factor).
  void Evaluate(ModelState* state, double t, const double* y, const double* yp);

  /// M as a dense matrix into *dense (n x n, zero outside the pattern).
  void FillDense(Eigen::MatrixXd* dense) const;

  /// Factors M; false when it is singular. The ordering of the columns (Eigen's analyzePattern)
  /// depends on the nonzero pattern alone and is kept while that holds, and the factors are kept
  /// while every value does: the same factors as computed afresh.
  bool Factor();
  /// M⁻¹ b, once factored.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const {
    Eigen::VectorXd x;
    Solve(b, &x);
    return x;
  }
  /// M⁻¹ b into *x, reusing its storage.
  void Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
    if (dense_) {
      *x = dense_lu_.solve(b);
    } else {
      *x = lu_.solve(b);
    }
  }

  /// dF/dy in the Jacobian's pattern (CompiledModel::jacobian_pattern).
  const std::vector<double>& dfdy() const { return dfdy_; }

 private:
  bool FactorDense(int n);
  bool FactorSparse(int n);

  const CompiledModel& model_;
  std::vector<double> dfdy_, dfdyp_;
  /// Up to kDenseUpTo unknowns M is factored as a dense matrix (dense_): small models solve with
  /// it at every sample of the crossing search, and for the carrier collision's 14 unknowns
  /// Eigen's sparse LU took 37 k instructions a factorisation and 2.8 k a solve, the dense one
  /// 1.4 k a solve (callgrind; bench/RESULTS.md, "Read this first").
  static constexpr int kDenseUpTo = 32;
  const bool dense_;
  Eigen::PartialPivLU<Eigen::MatrixXd> dense_lu_;
  Eigen::MatrixXd dense_matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  /// The nonzero pattern lu_ was analysed for (empty before the first Factor).
  std::vector<int> analysed_outer_, analysed_inner_;
  /// M's values in the Jacobian's pattern (zeros included), and those lu_ holds the factors of
  /// when the last Factor succeeded (factored_).
  std::vector<double> mixed_, factored_values_;
  bool factored_ = false;
};

/// The states' rates and the algebraic unknowns in *y, *yp (the states held) such that
/// F(t, y, y') = 0, by Newton steps of least norm from the values given (minimum_norm_newton.h):
/// where M is singular because the equations leave a split open (two stuck friction elements in
/// series share the load in any split), the values nearest the given ones. False, with *y and *yp
/// as given, when that finds no solution.
bool SolveMixedByMinimumNormSteps(ModelState* state, double t, std::vector<double>* y, std::vector<double>* yp);

}  // namespace momenta

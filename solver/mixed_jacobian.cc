// The mixed Jacobian of mixed_jacobian.h, assembled from the IDA Jacobian's two parts in its
// sparse pattern and factored by a dense LU (up to MixedJacobian::kDenseUpTo unknowns) or Eigen's
// sparse LU: IDA's own linear solver holds a different matrix, dF/dy + cj dF/dy'.

#include "solver/mixed_jacobian.h"

#include <algorithm>

#include "solver/minimum_norm_newton.h"

namespace momenta {

MixedJacobian::MixedJacobian(ModelState* state, double t, const double* y, const double* yp)
    : model_(state->model()), dense_(model_.num_unknowns() <= static_cast<size_t>(kDenseUpTo)) {
  Evaluate(state, t, y, yp);
}

void MixedJacobian::Evaluate(ModelState* state, double t, const double* y, const double* yp) {
  dfdy_.resize(model_.jacobian_pattern.nnz());
  dfdyp_.resize(model_.jacobian_pattern.nnz());
  state->JacobianParts(t, y, yp, dfdy_.data(), dfdyp_.data());
}

void MixedJacobian::FillDense(Eigen::MatrixXd* dense) const {
  const SparsePattern& pattern = model_.jacobian_pattern;
  for (int32_t c = 0; c < pattern.cols; ++c) {
    for (int32_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) {
      (*dense)(pattern.row_index[k], c) = model_.is_state[c] ? dfdyp_[k] : dfdy_[k];
    }
  }
}

bool MixedJacobian::Factor() {
  const SparsePattern& pattern = model_.jacobian_pattern;
  mixed_.resize(dfdy_.size());
  for (int32_t c = 0; c < pattern.cols; ++c) {
    const std::vector<double>& part = model_.is_state[c] ? dfdyp_ : dfdy_;
    std::copy(part.begin() + pattern.col_start[c], part.begin() + pattern.col_start[c + 1],
              mixed_.begin() + pattern.col_start[c]);
  }
  // The same matrix, value for value, as the one factored last: its factors stand (a linear
  // model's matrix at every step of a mode; Eigen's factorisation of a small matrix costs more
  // than the rest of a step).
  if (factored_ && mixed_ == factored_values_) return true;
  const auto n = static_cast<int>(model_.num_unknowns());
  factored_ = dense_ ? FactorDense(n) : FactorSparse(n);
  if (factored_) {
    factored_values_ = mixed_;
  } else {
    factored_values_.clear();
  }
  return factored_;
}

bool MixedJacobian::FactorDense(int n) {
  dense_matrix_.setZero(n, n);
  FillDense(&dense_matrix_);
  dense_lu_.compute(dense_matrix_);
  // Singular as the sparse LU finds it: a pivot that is exactly zero (partial pivoting takes the
  // largest of its column, so the whole column below it was zero).
  return (dense_lu_.matrixLU().diagonal().array() != 0).all();
}

bool MixedJacobian::FactorSparse(int n) {
  const SparsePattern& pattern = model_.jacobian_pattern;
  std::vector<Eigen::Triplet<double>> triplets;
  for (int32_t c = 0; c < pattern.cols; ++c) {
    for (int32_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) {
      if (mixed_[k] != 0) triplets.emplace_back(pattern.row_index[k], c, mixed_[k]);
    }
  }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  matrix.makeCompressed();
  const int* outer = matrix.outerIndexPtr();
  const int* inner = matrix.innerIndexPtr();
  if (!std::equal(analysed_outer_.begin(), analysed_outer_.end(), outer, outer + n + 1) ||
      !std::equal(analysed_inner_.begin(), analysed_inner_.end(), inner, inner + matrix.nonZeros())) {
    lu_.analyzePattern(matrix);
    analysed_outer_.assign(outer, outer + n + 1);
    analysed_inner_.assign(inner, inner + matrix.nonZeros());
  }
  lu_.factorize(matrix);
  return lu_.info() == Eigen::Success;
}

bool SolveMixedByMinimumNormSteps(ModelState* state, double t, std::vector<double>* y, std::vector<double>* yp) {
  const std::vector<bool>& is_state = state->model().is_state;
  const size_t n = y->size();
  // The unknowns of the instant: a state's rate, an algebraic unknown's value.
  std::vector<double> y_at = *y, yp_at = *yp;
  const auto place = [&](const Eigen::VectorXd& x) {
    for (size_t c = 0; c < n; ++c) (is_state[c] ? yp_at[c] : y_at[c]) = x[static_cast<Eigen::Index>(c)];
  };
  Eigen::VectorXd x(static_cast<Eigen::Index>(n));
  for (size_t c = 0; c < n; ++c) x[static_cast<Eigen::Index>(c)] = is_state[c] ? (*yp)[c] : (*y)[c];
  const auto residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd* f) {
    place(at);
    try {
      state->Residual(t, y_at.data(), yp_at.data(), f->data());
    } catch (const std::exception&) {
      return false;
    }
    return true;
  };
  const auto jacobian = [&](const Eigen::VectorXd& at, Eigen::MatrixXd* J) {
    place(at);
    try {
      MixedJacobian(state, t, y_at.data(), yp_at.data()).FillDense(J);
    } catch (const std::exception&) {
      return false;
    }
    return true;
  };
  if (SolveByMinimumNormSteps(residual, jacobian, &x) < 0) return false;
  place(x);
  *y = y_at;
  *yp = yp_at;
  return true;
}

}  // namespace momenta

// The mixed Jacobian of mixed_jacobian.h, assembled from the IDA Jacobian's two parts in its
// sparse pattern and factored by Eigen's sparse LU: IDA's own linear solver holds a different
// matrix, dF/dy + cj dF/dy'.

#include "solver/mixed_jacobian.h"

namespace momenta {

MixedJacobian::MixedJacobian(ModelState* state, double t, const double* y, const double* yp)
    : model_(state->model()) {
  dfdy_.resize(model_.jacobian_pattern.nnz());
  dfdyp_.resize(model_.jacobian_pattern.nnz());
  state->JacobianParts(t, y, yp, dfdy_.data(), dfdyp_.data());
}

bool MixedJacobian::Factor() {
  const SparsePattern& pattern = model_.jacobian_pattern;
  std::vector<Eigen::Triplet<double>> triplets;
  for (int32_t c = 0; c < pattern.cols; ++c) {
    for (int32_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) {
      double v = model_.is_state[c] ? dfdyp_[k] : dfdy_[k];
      if (v != 0) triplets.emplace_back(pattern.row_index[k], c, v);
    }
  }
  const auto n = static_cast<int>(model_.num_unknowns());
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  matrix.makeCompressed();
  lu_.compute(matrix);
  return lu_.info() == Eigen::Success;
}

}  // namespace momenta

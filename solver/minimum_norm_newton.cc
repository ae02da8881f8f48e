// Newton's method with minimum-norm steps (minimum_norm_newton.h):
//     z_{k+1} = z_k + λ dz,  dz = argmin { |dz| : |J(z_k) dz + F(z_k)| minimal },
// λ = 1, 1/2, 1/4, … down to 1e-4 until |F(z_{k+1})| < |F(z_k)|; a residual that cannot be
// evaluated or is not finite counts as infinitely large.

#include "solver/minimum_norm_newton.h"

#include <cmath>

namespace momenta {

int SolveByMinimumNormSteps(const MinimumNormResidual& residual, const MinimumNormJacobian& jacobian,
                            Eigen::VectorXd* z) {
  if (z->size() > kMaxMinimumNormUnknowns) return -1;
  Eigen::VectorXd f(z->size()), trial_f(z->size());
  Eigen::MatrixXd J(z->size(), z->size());
  auto norm_at = [&](const Eigen::VectorXd& at, Eigen::VectorXd* r) {
    return residual(at, r) && r->allFinite() ? r->norm() : HUGE_VAL;
  };
  double norm = norm_at(*z, &f);
  if (norm == HUGE_VAL) return -1;
  for (int iter = 0; iter < 50; ++iter) {
    const double scale = std::max(1.0, z->cwiseAbs().maxCoeff());
    if (f.cwiseAbs().maxCoeff() <= 1e-10 * scale) return iter;
    J.setZero();
    if (!jacobian(*z, &J)) return -1;
    const Eigen::VectorXd step = J.completeOrthogonalDecomposition().solve(-f);
    // Backtracking: halve the step until the residual's norm falls.
    double lambda = 1;
    for (; lambda > 1e-4; lambda /= 2) {
      const double trial = norm_at(*z + lambda * step, &trial_f);
      if (trial < norm) {
        *z += lambda * step;
        f = trial_f;
        norm = trial;
        break;
      }
    }
    if (lambda <= 1e-4) return -1;
  }
  return -1;
}

}  // namespace momenta

#pragma once
/// Newton's method with minimum-norm steps, for a square system F(z) = 0 that holds but leaves
/// some unknowns free: where an LU factorisation stops at a zero pivot (two stuck friction
/// elements in series carry the load between them in any split), each step is the least-norm
/// solution of J dz = -F (Eigen's complete orthogonal decomposition of the dense Jacobian), so the
/// solution nearest the starting point picks one. The start (SolveInitialization) and the restart
/// after an event (Restart) fall back on it when SUNDIALS' Newton iterations fail.

#include <Eigen/Dense>

#include <functional>

namespace momenta {

/// The largest system solved (the dense decomposition's memory and time grow as the square and
/// the cube of the unknowns: 2 MB and about 0.1 s at 500).
inline constexpr Eigen::Index kMaxMinimumNormUnknowns = 500;

/// F(z) into *f; false when it cannot be evaluated.
using MinimumNormResidual = std::function<bool(const Eigen::VectorXd& z, Eigen::VectorXd* f)>;
/// dF/dz at z into *J (zeroed before the call); false when it cannot be evaluated.
using MinimumNormJacobian = std::function<bool(const Eigen::VectorXd& z, Eigen::MatrixXd* J)>;

/// Solves F(z) = 0 from *z by at most 50 minimum-norm Newton steps, each halved until the
/// residual's norm falls. Returns the number of steps taken when every residual is within 1e-10
/// of the largest unknown (at least 1e-10), with *z the solution; -1 otherwise (no solution, a
/// system of more than kMaxMinimumNormUnknowns, a residual that is not finite at the start), *z
/// then where the iteration stopped.
int SolveByMinimumNormSteps(const MinimumNormResidual& residual, const MinimumNormJacobian& jacobian,
                            Eigen::VectorXd* z);

}  // namespace momenta

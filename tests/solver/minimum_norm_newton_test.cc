// Newton's method with minimum-norm steps on systems whose Jacobian is singular everywhere: a
// consistent system reaches the solution nearest the start (closed form), an inconsistent one and
// one past the size limit are refused.

#include <gtest/gtest.h>

#include <cmath>

#include "solver/minimum_norm_newton.h"

namespace momenta {
namespace {

// Two torques in series carrying a 10 N.m load: z0 + z1 = 10 (written twice, so J has rank 1).
bool SplitResidual(const Eigen::VectorXd& z, Eigen::VectorXd* f) {
  (*f)[0] = z[0] + z[1] - 10;
  (*f)[1] = 2 * (z[0] + z[1] - 10);
  return true;
}
bool SplitJacobian(const Eigen::VectorXd&, Eigen::MatrixXd* J) {
  *J << 1, 1, 2, 2;
  return true;
}

TEST(MinimumNormNewton, ASplitTheEquationsLeaveOpenIsTheOneNearestTheStart) {
  // From (1, 3) the nearest point of z0 + z1 = 10 is (1, 3) + 3 (1, 1) = (4, 6): one step.
  Eigen::VectorXd z(2);
  z << 1, 3;
  EXPECT_EQ(SolveByMinimumNormSteps(SplitResidual, SplitJacobian, &z), 1);
  EXPECT_NEAR(z[0], 4, 1e-12);
  EXPECT_NEAR(z[1], 6, 1e-12);
}

TEST(MinimumNormNewton, ANonlinearSingularSystemConvergesToItsNearestSolution) {
  // (z0 + z1)^2 = 4 and z0 + z1 = 2: rank 1 everywhere; from (0, 0.5) the solution stays on
  // the line z1 - z0 = 0.5 that the minimum-norm steps keep: (0.75, 1.25).
  const auto residual = [](const Eigen::VectorXd& z, Eigen::VectorXd* f) {
    const double s = z[0] + z[1];
    (*f)[0] = s * s - 4;
    (*f)[1] = s - 2;
    return true;
  };
  const auto jacobian = [](const Eigen::VectorXd& z, Eigen::MatrixXd* J) {
    const double s = z[0] + z[1];
    *J << 2 * s, 2 * s, 1, 1;
    return true;
  };
  Eigen::VectorXd z(2);
  z << 0, 0.5;
  EXPECT_GT(SolveByMinimumNormSteps(residual, jacobian, &z), 1);
  EXPECT_NEAR(z[0], 0.75, 1e-9);
  EXPECT_NEAR(z[1], 1.25, 1e-9);
}

TEST(MinimumNormNewton, AnInconsistentSystemIsRefused) {
  // z0 + z1 = 1 and z0 + z1 = 2: the least-squares step lands at 1.5 and can go no lower.
  const auto residual = [](const Eigen::VectorXd& z, Eigen::VectorXd* f) {
    (*f)[0] = z[0] + z[1] - 1;
    (*f)[1] = z[0] + z[1] - 2;
    return true;
  };
  const auto jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd* J) {
    *J << 1, 1, 1, 1;
    return true;
  };
  Eigen::VectorXd z = Eigen::VectorXd::Zero(2);
  EXPECT_EQ(SolveByMinimumNormSteps(residual, jacobian, &z), -1);
}

TEST(MinimumNormNewton, AResidualThatCannotBeEvaluatedAtTheStartIsRefused) {
  Eigen::VectorXd z = Eigen::VectorXd::Zero(2);
  const auto residual = [](const Eigen::VectorXd&, Eigen::VectorXd* f) {
    (*f)[0] = NAN;
    (*f)[1] = 0;
    return true;
  };
  EXPECT_EQ(SolveByMinimumNormSteps(residual, SplitJacobian, &z), -1);
  EXPECT_EQ(SolveByMinimumNormSteps([](const Eigen::VectorXd&, Eigen::VectorXd*) { return false; }, SplitJacobian, &z),
            -1);
}

TEST(MinimumNormNewton, ASystemPastTheSizeLimitIsRefusedUnevaluated) {
  Eigen::VectorXd z = Eigen::VectorXd::Zero(kMaxMinimumNormUnknowns + 1);
  bool evaluated = false;
  const auto residual = [&](const Eigen::VectorXd&, Eigen::VectorXd* f) {
    evaluated = true;
    f->setZero();
    return true;
  };
  EXPECT_EQ(SolveByMinimumNormSteps(residual, SplitJacobian, &z), -1);
  EXPECT_FALSE(evaluated);
}

}  // namespace
}  // namespace momenta

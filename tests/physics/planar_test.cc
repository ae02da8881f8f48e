// The planar library's elementary closed forms: a pendulum of a Revolute, a FixedTranslation cord
// and a PointMass against the small-angle period 2π√(L/g) and the exact large-amplitude period
// (4√(L/g) K(sin(θ0/2)), K the complete elliptic integral of the first kind); a free Body thrown
// in gravity against the parabola; a Prismatic joint driven by a constant force.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

std::string Pendulum(double theta0) {
  return R"(model: Pendulum
parameters: {L: 2, theta0: )" + std::to_string(theta0) + R"(}
components:
  pivot: {type: Planar.Fixed, r: [0, 0]}
  joint: {type: Revolute, phi: {start: theta0, fixed: true}, w: {start: 0, fixed: true}}
  cord: {type: FixedTranslation, r: [0, -L]}
  bob: {type: PointMass, m: 0.7}
connections:
  - [pivot.frame, joint.frame_a]
  - [joint.frame_b, cord.frame_a]
  - [cord.frame_b, bob.frame_a]
experiment: {stop: 12, tolerance: 1e-10, interval: 0.001}
outputs: [joint.phi, joint.w, bob.r, bob.v]
)";
}

/// Times at which w crosses zero from above (the swing's turning points at +θ0), interpolated.
std::vector<double> TurningPoints(const Trajectory& tr) {
  std::vector<double> out;
  const size_t w = tr.Index("joint.w");
  for (size_t k = 1; k < tr.t.size(); ++k) {
    const double a = tr.values[k - 1][w], b = tr.values[k][w];
    if (a < 0 && b >= 0) out.push_back(tr.t[k - 1] + (tr.t[k] - tr.t[k - 1]) * a / (a - b));
  }
  return out;
}

/// K(k) by the arithmetic-geometric mean: K = π / (2 agm(1, √(1 - k²))).
double EllipticK(double k) {
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 40; ++i) {
    const double m = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = m;
  }
  return kPi / (2 * a);
}

TEST(PlanarPendulum, PeriodsAgainstTheClosedForms) {
  const double L = 2, g = 9.81;
  for (double theta0 : {0.01, 1.0, 2.5}) {
    Built b = testing::BuildYaml(Pendulum(theta0));
    Trajectory tr = testing::RunDefault(b);
    const std::vector<double> turns = TurningPoints(tr);
    ASSERT_GE(turns.size(), 2u) << theta0;
    const double period = (turns.back() - turns.front()) / static_cast<double>(turns.size() - 1);
    const double exact = 4 * std::sqrt(L / g) * EllipticK(std::sin(theta0 / 2));
    // Turning points are interpolated linearly between 1 ms output rows where w is ~θ0 ω² dt·t:
    // error O(dt²·w''/w') ≈ 1e-7 s; rtol 1e-10 adds nothing visible.
    EXPECT_NEAR(period, exact, 1e-6) << "theta0 = " << theta0;
    if (theta0 < 0.02) EXPECT_NEAR(period, 2 * kPi * std::sqrt(L / g), 2e-5 * period);
    // The bob stays on its circle and the energy is kept.
    for (size_t k = 0; k < tr.t.size(); k += 100) {
      const double x = tr.Column("bob.r[1]", k), y = tr.Column("bob.r[2]", k);
      EXPECT_NEAR(std::hypot(x, y), L, 1e-12);
      const double vx = tr.Column("bob.v[1]", k), vy = tr.Column("bob.v[2]", k);
      EXPECT_NEAR(0.5 * (vx * vx + vy * vy) + g * y, -g * L * std::cos(theta0), 1e-7 * g * L);
    }
  }
}

TEST(PlanarBody, ThrownBodyFollowsTheParabolaAndSpinsFreely) {
  Built b = testing::BuildYaml(R"(model: Throw
components:
  ball: {type: Body, m: 2, I: 0.3, r: {start: [1, 2], fixed: true}, v: {start: [3, 4], fixed: true}, phi: {start: 0, fixed: true}, w: {start: 5, fixed: true}}
experiment: {stop: 1, tolerance: 1e-8, interval: 0.01}
outputs: [ball.r, ball.v, ball.phi]
)");
  Trajectory tr = testing::RunDefault(b);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    // Polynomials of degree ≤ 2: IDA's BDF integrates them exactly up to rounding.
    EXPECT_NEAR(tr.Column("ball.r[1]", k), 1 + 3 * t, 1e-10);
    EXPECT_NEAR(tr.Column("ball.r[2]", k), 2 + 4 * t - 0.5 * 9.81 * t * t, 1e-10);
    EXPECT_NEAR(tr.Column("ball.v[2]", k), 4 - 9.81 * t, 1e-10);
    EXPECT_NEAR(tr.Column("ball.phi", k), 5 * t, 1e-10);
  }
}

TEST(PlanarPrismatic, ConstantForceAlongATiltedAxisAgainstGravity) {
  // A body of mass m on a prismatic joint along (cos 30°, sin 30°), pushed along the axis by F:
  // s'' = F/m - g sin 30°.
  Built b = testing::BuildYaml(R"(model: Slide
parameters: {m: 2, F: 30}
components:
  ground: {type: Planar.Fixed}
  slider: {type: Prismatic, r: [0.8660254037844386, 0.5], s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  body: {type: Body, m: m, I: 0.1}
  push: {type: ConstantForce, f_constant: F}
connections:
  - [ground.frame, slider.frame_a]
  - [slider.frame_b, body.frame_a]
  - [push.flange, slider.flange_a]
experiment: {stop: 1, tolerance: 1e-8, interval: 0.01}
outputs: [slider.s, slider.v, body.r, body.phi]
)");
  Trajectory tr = testing::RunDefault(b);
  const double acc = 30.0 / 2 - 9.81 * 0.5;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    EXPECT_NEAR(tr.Column("slider.s", k), 0.5 * acc * t * t, 1e-9);
    EXPECT_NEAR(tr.Column("body.r[2]", k), 0.25 * acc * t * t, 1e-9);
    EXPECT_NEAR(tr.Column("body.phi", k), 0, 1e-12);
  }
}

}  // namespace
}  // namespace momenta

// Index reduction on physics with closed forms: a pendulum written in Cartesian coordinates,
//   der(x) = vx, der(y) = vy, m der(vx) = -x F/L, m der(vy) = -y F/L - m g, x^2 + y^2 = L^2,
// an index-3 DAE that Pantelides' algorithm and dummy derivatives reduce to index 1. Released at
// rest from the angle theta0, its period is T = 4 sqrt(L/g) K(sin(theta0/2)) with K the complete
// elliptic integral of the first kind (2 pi sqrt(L/g) for small theta0), its energy is constant
// and the constraint must hold along the whole run. And a second-order equation written with
// der(der(x)), which the first-order form turns into two states.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

/// K(k) by the arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(1 - k^2))).
double EllipticK(double k) {
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 40 && std::fabs(a - b) > 1e-16 * a; ++i) {
    double an = (a + b) / 2;
    b = std::sqrt(a * b);
    a = an;
  }
  return kPi / (2 * a);
}

std::string PendulumYaml(double theta0, double stop, double v0 = 0) {
  std::ostringstream y;
  y.precision(17);
  y << R"(model: CartesianPendulum
parameters: {L: 1.5, g: 9.81, m: 2, theta0: )" << theta0 << ", v0: " << v0 << R"(}
define:
  Pendulum:
    parameters: {L: 1, g: 9.81, m: 1, theta0: 0.1, v0: 0}
    variables:
      x: {start: L*sin(theta0), fixed: true}
      y: {start: -L*cos(theta0)}
      vx: {start: v0*cos(theta0), fixed: true}
      vy: {start: v0*sin(theta0)}
      F: {start: m*g}
    equations:
      - der(x) = vx
      - der(y) = vy
      - m*der(vx) = -x*F/L
      - m*der(vy) = -y*F/L - m*g
      - x^2 + y^2 = L^2
components:
  p: {type: Pendulum, L: L, g: g, m: m, theta0: theta0, v0: v0}
experiment: {stop: )" << stop << R"(, tolerance: 1e-10, interval: 1e-3}
outputs: [p.x, p.y, p.vx, p.vy, p.F]
)";
  return y.str();
}

/// Times at which vx changes sign from + to - (the pendulum at its right turning point),
/// interpolated linearly between rows.
std::vector<double> TurningPoints(const Trajectory& tr) {
  std::vector<double> ts;
  const size_t ivx = tr.Index("p.vx");
  for (size_t k = 1; k < tr.t.size(); ++k) {
    double a = tr.values[k - 1][ivx], b = tr.values[k][ivx];
    if (a > 0 && b <= 0) ts.push_back(tr.t[k - 1] + (tr.t[k] - tr.t[k - 1]) * a / (a - b));
  }
  return ts;
}

struct PendulumRun {
  Trajectory tr;
  BuildReport report;
};

PendulumRun RunPendulum(double theta0, double stop, double v0 = 0) {
  Built b = testing::BuildYaml(PendulumYaml(theta0, stop, v0));
  return {testing::RunDefault(b), b.report};
}

TEST(CartesianPendulum, IndexReductionReportsIndexThreeAndTwoStates) {
  Built b = testing::BuildYaml(PendulumYaml(0.1, 1));
  EXPECT_EQ(b.report.structural_index, 3u);
  // The constraint twice, der(x) = vx and der(y) = vy once.
  EXPECT_EQ(b.report.differentiated.size(), 4u);
  // Every candidate is a dummy derivative: the two degrees of freedom are carried by state sets
  // whose selection follows the motion, starting with x and vx near the bottom.
  EXPECT_EQ(b.report.dummy_derivatives.size(), 6u);
  EXPECT_EQ(b.report.states, (std::vector<std::string>{"stateSet1.x", "stateSet2.x"}));
  ASSERT_EQ(b.report.state_choices.size(), 2u);
  EXPECT_NE(b.report.state_choices[0].find("one of {der(p.x), der(p.y), p.vx, p.vy} is a state"), std::string::npos)
      << b.report.state_choices[0];
  EXPECT_NE(b.report.state_choices[0].find("(at the start: p.vx)"), std::string::npos) << b.report.state_choices[0];
  EXPECT_NE(b.report.state_choices[1].find("one of {p.x, p.y} is a state"), std::string::npos) << b.report.state_choices[1];
  EXPECT_NE(b.report.state_choices[1].find("(at the start: p.x)"), std::string::npos) << b.report.state_choices[1];
}

TEST(CartesianPendulum, SmallAmplitudePeriod) {
  const double L = 1.5, g = 9.81, theta0 = 0.05;
  PendulumRun r = RunPendulum(theta0, 10);
  std::vector<double> ts = TurningPoints(r.tr);
  ASSERT_GE(ts.size(), 4u);
  const double period = (ts.back() - ts.front()) / static_cast<double>(ts.size() - 1);
  const double exact = 4 * std::sqrt(L / g) * EllipticK(std::sin(theta0 / 2));
  // The turning points come from rows 1 ms apart; vx is nearly linear there, so the period is
  // good to about 1e-8 s at rtol 1e-10.
  EXPECT_NEAR(period, exact, 1e-7);
  // Against the small-angle law: theta0 = 0.05 lengthens the period by theta0^2/16 = 1.6e-4.
  EXPECT_NEAR(period / (2 * kPi * std::sqrt(L / g)), 1.0, 2e-4);
}

/// Times at which the pendulum passes the bottom (x from - to +, y < 0).
std::vector<double> BottomPassages(const Trajectory& tr) {
  std::vector<double> ts;
  const size_t ix = tr.Index("p.x"), iy = tr.Index("p.y");
  for (size_t k = 1; k < tr.t.size(); ++k) {
    double a = tr.values[k - 1][ix], b = tr.values[k][ix];
    if (a < 0 && b >= 0 && tr.values[k][iy] < 0 && tr.t[k] > tr.t[k - 1]) {
      ts.push_back(tr.t[k - 1] + (tr.t[k] - tr.t[k - 1]) * -a / (b - a));
    }
  }
  return ts;
}

// 2.5 rad (143 degrees, above the horizontal): no fixed choice of states stays regular over the
// swing (solving the constraint for y fails at the horizontal, for x at the bottom), so the state
// sets switch during the run; the period is 1.62 times the small-angle law.
TEST(CartesianPendulum, LargeAmplitudePeriodEnergyAndConstraint) {
  const double L = 1.5, g = 9.81, m = 2, theta0 = 2.5;
  PendulumRun r = RunPendulum(theta0, 12);
  EXPECT_GE(r.tr.stats.events, 8);  // the selection changes several times per swing
  std::vector<double> ts = BottomPassages(r.tr);
  ASSERT_GE(ts.size(), 3u);
  const double period = (ts.back() - ts.front()) / static_cast<double>(ts.size() - 1);
  const double exact = 4 * std::sqrt(L / g) * EllipticK(std::sin(theta0 / 2));
  EXPECT_NEAR(period, exact, 1e-6 * exact);
  // Energy E = m/2 (vx^2 + vy^2) + m g y, and the constraint, along the whole run.
  const Trajectory& tr = r.tr;
  const size_t ix = tr.Index("p.x"), iy = tr.Index("p.y"), ivx = tr.Index("p.vx"), ivy = tr.Index("p.vy");
  const double e0 = m * g * (-L * std::cos(theta0));
  double worst_energy = 0, worst_constraint = 0;
  for (const auto& row : tr.values) {
    double e = m / 2 * (row[ivx] * row[ivx] + row[ivy] * row[ivy]) + m * g * row[iy];
    worst_energy = std::max(worst_energy, std::fabs(e - e0));
    worst_constraint = std::max(worst_constraint, std::fabs(std::hypot(row[ix], row[iy]) - L));
  }
  // |E0| = 23.6 J; rtol 1e-10 keeps the drift over 12 s (about 5 periods) within 1e-6 of it.
  EXPECT_LT(worst_energy, 1e-6 * std::fabs(e0));
  // The position constraint is one of the equations IDA solves: at the end of the run (a step of
  // IDA's, stop time) it holds to the Newton tolerance; rows between steps come from IDA's
  // interpolating polynomial, which keeps it to the local error.
  const auto& last = tr.values.back();
  EXPECT_LT(std::fabs(std::hypot(last[ix], last[iy]) - L), 1e-9 * L);
  EXPECT_LT(worst_constraint, 1e-8 * L);
}

// Given more than 2 sqrt(g L) at the bottom, the pendulum goes over the top: x and y each pass
// through zero twice a turn. The time for a turn is T = integral over 2 pi of L dtheta / v(theta)
// with v^2 = v0^2 - 2 g L (1 - cos theta), computed here by Simpson's rule.
TEST(CartesianPendulum, OverTheTopTenTurns) {
  const double L = 1.5, g = 9.81, m = 2, v0 = 8.5;
  const int kPoints = 20000;
  double turn = 0;
  for (int k = 0; k <= kPoints; ++k) {
    double th = 2 * kPi * k / kPoints;
    double f = L / std::sqrt(v0 * v0 - 2 * g * L * (1 - std::cos(th)));
    turn += f * (k == 0 || k == kPoints ? 1 : (k % 2 ? 4 : 2));
  }
  turn *= 2 * kPi / kPoints / 3;
  PendulumRun r = RunPendulum(0, 10.5 * turn, v0);
  const Trajectory& tr = r.tr;
  std::vector<double> ts = BottomPassages(tr);
  // It starts at the bottom (x = 0, not counted); the tenth passage ends the tenth turn.
  ASSERT_GE(ts.size(), 10u);
  EXPECT_NEAR(ts[9], 10 * turn, 1e-6 * 10 * turn) << "turn " << turn;
  const size_t iy = tr.Index("p.y"), ivx = tr.Index("p.vx"), ivy = tr.Index("p.vy");
  const double e0 = m / 2 * v0 * v0 - m * g * L;
  double worst = 0;
  for (const auto& row : tr.values) {
    worst = std::max(worst, std::fabs(m / 2 * (row[ivx] * row[ivx] + row[ivy] * row[ivy]) + m * g * row[iy] - e0));
  }
  // E0 = 42.8 J; over ten turns at rtol 1e-10 the energy stays within 1e-6 of it.
  EXPECT_LT(worst, 1e-6 * e0);
  // Four switches a turn at the least (the positions' set twice, the velocities' twice).
  EXPECT_GE(tr.stats.events, 40);
}

// One degree of freedom fixed (vx) of two: the position's start value is taken, with a warning
// naming the variable the user would fix (x), not the internal state set.
TEST(CartesianPendulum, MissingFixedPositionTakesItsStartValue) {
  std::string yaml = PendulumYaml(0.3, 2);
  const std::string fixed_x = "x: {start: L*sin(theta0), fixed: true}";
  yaml.replace(yaml.find(fixed_x), fixed_x.size(), "x: {start: L*sin(theta0)}");
  Built b = testing::BuildYaml(yaml);
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_EQ(b.report.warnings[0],
            "initial conditions: the model has 2 degrees of freedom and its fixed start values and initial equations "
            "determine 1; the start value of p.x is used as well (add fixed: true to say so)");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_NEAR(tr.values[0][tr.Index("p.x")], 1.5 * std::sin(0.3), 1e-12);
  EXPECT_NEAR(tr.values[0][tr.Index("p.y")], -1.5 * std::cos(0.3), 1e-9);
}

TEST(SecondDerivatives, HarmonicOscillatorInSecondOrderForm) {
  // der(der(x)) = -w^2 x becomes der(x) = der(x)_state, der(der(x)_state) = -w^2 x.
  const double w = 3;
  Built b = testing::BuildYaml(R"(model: SecondOrder
parameters: {w: 3}
variables:
  x: {start: 1, fixed: true}
initial_equations:
  - der(x) = 0
equations:
  - der(der(x)) = -w^2*x
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [x, der(x)]
)");
  EXPECT_EQ(b.report.states, (std::vector<std::string>{"x", "der(x)"}));
  Trajectory tr = testing::RunDefault(b);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    EXPECT_NEAR(tr.values[k][0], std::cos(w * tr.t[k]), 1e-7) << "t = " << tr.t[k];
    EXPECT_NEAR(tr.values[k][1], -w * std::sin(w * tr.t[k]), 3e-7) << "t = " << tr.t[k];
  }
}

}  // namespace
}  // namespace momenta

// MultiBody point gravity against the closed-form Kepler orbit: two free bodies of the MSL's
// Examples.Elementary.PointGravity (world.mu = 1 m3/s2, gravity -mu/|r|^2 r/|r|), body1 from
// r = (0, 0.6, 0) with v = (1, 0, 0), body2 from (0.6, 0.6, 0) with (0.6, 0, 0). Each moves on a
// Kepler ellipse: a = -mu/(2E), E = v^2/2 - mu/r, period T = 2 pi sqrt(a^3/mu), the position
// at t from Kepler's equation M = E_a - e sin(E_a), M = n t + M0, n = 2 pi/T; energy and angular
// momentum h = x vy - y vx are constant. body2's orbit (a = 0.5007 m, e = 0.861) passes its
// pericentre at 0.070 m from the origin at 5.2 m/s: the published reference (Dymola, tolerance
// 1e-6) loses 3e-4 of its energy at each passage and is 0.18 m/s off the closed form at
// t = 3.75 s, 22 times the tube's height at the same time (within CSV-compare's tube, whose 0.01 s
// width in time covers the phase the reference lost, the example passes in tests/msl/); this test
// holds the model to the closed form.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Position and velocity (x, y, vx, vy) at time t on the Kepler orbit through (r0, v0) at t = 0,
/// mu = 1, elliptic (E < 0).
struct Planar {
  double x, y, vx, vy;
};
Planar Kepler(Planar s, double t) {
  const double r = std::hypot(s.x, s.y), v2 = s.vx * s.vx + s.vy * s.vy, rv = s.x * s.vx + s.y * s.vy;
  const double a = -1 / (2 * (v2 / 2 - 1 / r)), n = std::sqrt(1 / (a * a * a));
  const double h = s.x * s.vy - s.y * s.vx;
  // Eccentricity vector, pericentre direction p and the direction q a quarter turn on.
  const double ex = (v2 - 1 / r) * s.x - rv * s.vx, ey = (v2 - 1 / r) * s.y - rv * s.vy;
  const double e = std::hypot(ex, ey), px = ex / e, py = ey / e;
  const double qx = h > 0 ? -py : py, qy = h > 0 ? px : -px;
  // Eccentric anomaly now, then Kepler's equation by Newton.
  const double e0 = std::atan2(rv / (e * std::sqrt(a)), (1 - r / a) / e);
  const double m = e0 - e * std::sin(e0) + n * t;
  double ea = m;
  for (int i = 0; i < 50; ++i) ea -= (ea - e * std::sin(ea) - m) / (1 - e * std::cos(ea));
  const double b = a * std::sqrt(1 - e * e), rr = a * (1 - e * std::cos(ea));
  const double X = a * (std::cos(ea) - e), Y = b * std::sin(ea);
  const double VX = -std::sqrt(a) / rr * std::sin(ea), VY = std::sqrt(a) / rr * (b / a) * std::cos(ea);
  return {X * px + Y * qx, X * py + Y * qy, VX * px + VY * qx, VX * py + VY * qy};
}

constexpr char kPointGravity[] = R"(
model: PointGravity
components:
  world: {type: MultiBody.World, mu: 1, gravityType: 3}
  body1: {type: MultiBody.Parts.Body, m: 1, I_11: 0.1, I_22: 0.1, I_33: 0.1, r_0: {start: [0, 0.6, 0], fixed: true}, v_0: {start: [1, 0, 0], fixed: true}, angles_fixed: true, w_0_fixed: true, r_CM: [0, 0, 0]}
  body2: {type: MultiBody.Parts.Body, m: 1, I_11: 0.1, I_22: 0.1, I_33: 0.1, r_0: {start: [0.6, 0.6, 0], fixed: true}, v_0: {start: [0.6, 0, 0], fixed: true}, angles_fixed: true, w_0_fixed: true, r_CM: [0, 0, 0]}
experiment: {start: 0, stop: 5, tolerance: 1e-10, interval: 0.001}
outputs: ["body1.frame_a.r_0[1]", "body1.frame_a.r_0[2]", "body1.frame_a.r_0[3]", "body1.v_0[1]", "body1.v_0[2]", "body2.frame_a.r_0[1]", "body2.frame_a.r_0[2]", "body2.frame_a.r_0[3]", "body2.v_0[1]", "body2.v_0[2]"]
)";

TEST(PointGravityTest, BodiesFollowTheKeplerOrbits) {
  testing::Built b = testing::BuildYaml(kPointGravity);
  ASSERT_TRUE(b.report.warnings.empty()) << b.report.warnings.front();
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_NEAR(tr.t.back(), 5, 1e-12);
  const Planar start[2] = {{0, 0.6, 1, 0}, {0.6, 0.6, 0.6, 0}};
  for (int k = 0; k < 2; ++k) {
    const std::string body = k == 0 ? "body1" : "body2";
    const Planar s = start[k];
    const double e0 = (s.vx * s.vx + s.vy * s.vy) / 2 - 1 / std::hypot(s.x, s.y), h0 = s.x * s.vy - s.y * s.vx;
    double worst_r = 0, worst_v = 0, worst_energy = 0, worst_h = 0;
    for (size_t row = 0; row < tr.t.size(); ++row) {
      const double x = tr.Column(body + ".frame_a.r_0[1]", row), y = tr.Column(body + ".frame_a.r_0[2]", row);
      const double vx = tr.Column(body + ".v_0[1]", row), vy = tr.Column(body + ".v_0[2]", row);
      EXPECT_EQ(tr.Column(body + ".frame_a.r_0[3]", row), 0) << body << " leaves the orbit's plane";
      const Planar want = Kepler(s, tr.t[row]);
      worst_r = std::max(worst_r, std::hypot(x - want.x, y - want.y));
      worst_v = std::max(worst_v, std::hypot(vx - want.vx, vy - want.vy));
      worst_energy = std::max(worst_energy, std::fabs((vx * vx + vy * vy) / 2 - 1 / std::hypot(x, y) - e0));
      worst_h = std::max(worst_h, std::fabs(x * vy - y * vx - h0));
    }
    // At tolerance 1e-10 the run meets the closed form to 1.3e-5 m/s (body2's velocity at its
    // second pericentre, 2.2 m/s there) and 2e-6 m; the bounds leave 5x for other platforms and
    // stay 1/16 of the MSL tube (2e-3 of body2's 5.2 m/s), where the reference misses by 0.18 m/s.
    EXPECT_LT(worst_r, 1e-5) << body;
    EXPECT_LT(worst_v, 1e-4) << body;
    EXPECT_LT(worst_energy, 1e-5) << body;
    EXPECT_LT(worst_h, 1e-5) << body;
  }
}

TEST(PointGravityTest, Body2ReturnsAfterItsKeplerPeriod) {
  // T = 2 pi a^(3/2), a = -1/(2E), E = 0.6^2/2 - 1/(0.6 sqrt(2)).
  const double a = -1 / (2 * (0.18 - 1 / (0.6 * std::sqrt(2.0)))), period = 2 * kPi * std::pow(a, 1.5);
  testing::Built b = testing::BuildYaml(kPointGravity);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  opt.stop = period;
  opt.interval = period / 4;
  testing::Trajectory tr = testing::Run(b, opt);
  ASSERT_NEAR(tr.t.back(), period, 1e-12);
  EXPECT_NEAR(tr.Column("body2.frame_a.r_0[1]", tr.t.size() - 1), 0.6, 1e-5);
  EXPECT_NEAR(tr.Column("body2.frame_a.r_0[2]", tr.t.size() - 1), 0.6, 1e-5);
  EXPECT_NEAR(tr.Column("body2.v_0[1]", tr.t.size() - 1), 0.6, 1e-5);
  EXPECT_NEAR(tr.Column("body2.v_0[2]", tr.t.size() - 1), 0, 1e-5);
  // A quarter period earlier it is nowhere near its start (the check above is not vacuous).
  EXPECT_GT(std::hypot(tr.Column("body2.frame_a.r_0[1]", 3) - 0.6, tr.Column("body2.frame_a.r_0[2]", 3) - 0.6), 0.1);
}

}  // namespace
}  // namespace momenta

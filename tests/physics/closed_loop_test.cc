// A closed kinematic loop: a four-bar linkage in joint angles, the crank th1 driven at a constant
// rate w, the coupler th2 and the rocker th3 tied by the two loop-closure equations
//   L1 cos th1 + L2 cos th2 - L3 cos th3 = L0,   L1 sin th1 + L2 sin th2 - L3 sin th3 = 0,
// with w2 = der(th2) and w3 = der(th3): the closure constrains th2 and th3, so index reduction
// must differentiate it. Reference, computed independently here: the coupler-rocker joint B is an
// intersection of the circles of radius L2 about the crank pin A = L1 (cos th1, sin th1) and of
// radius L3 about the ground pivot D = (L0, 0) (the one above the line AD, the assembly the start
// values pick), and the rates solve the closure's time derivative, a 2x2 linear system.
// L1 + L0 = 5 <= L2 + L3 = 6: a crank-rocker, the crank turns fully.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

constexpr double L0 = 4, L1 = 1, L2 = 3.5, L3 = 2.5, kW = 2;

const char* kFourBar = R"(model: FourBar
define:
  FourBarLoop:
    parameters: {L0: 4, L1: 1, L2: 3.5, L3: 2.5, w: 2}
    variables:
      th1: {start: 0}
      th2: {start: 0.7}
      th3: {start: 1.8}
      w2: {start: 0}
      w3: {start: 0}
    equations:
      - th1 = w*time
      - w2 = der(th2)
      - w3 = der(th3)
      - L1*cos(th1) + L2*cos(th2) - L3*cos(th3) - L0 = 0
      - L1*sin(th1) + L2*sin(th2) - L3*sin(th3) = 0
components:
  loop: {type: FourBarLoop}
experiment: {stop: 6.5, tolerance: 1e-10, interval: 0.01}
outputs: [loop.th1, loop.th2, loop.th3, loop.w2, loop.w3]
)";

struct Pose {
  double th2, th3, w2, w3;
};

Pose Reference(double th1) {
  const double ax = L1 * std::cos(th1), ay = L1 * std::sin(th1);
  const double dx = L0 - ax, dy = -ay, d = std::hypot(dx, dy);
  // Along AD from A: a = (L2^2 - L3^2 + d^2) / (2 d); h above the line.
  const double a = (L2 * L2 - L3 * L3 + d * d) / (2 * d), h = std::sqrt(L2 * L2 - a * a);
  const double bx = ax + a * dx / d - h * dy / d, by = ay + a * dy / d + h * dx / d;
  Pose p;
  p.th2 = std::atan2(by - ay, bx - ax);
  p.th3 = std::atan2(by, bx - L0);
  // d/dt of the closure: [-L2 sin th2, L3 sin th3; L2 cos th2, -L3 cos th3] [w2; w3] = L1 w [sin th1; -cos th1].
  const double a11 = -L2 * std::sin(p.th2), a12 = L3 * std::sin(p.th3);
  const double a21 = L2 * std::cos(p.th2), a22 = -L3 * std::cos(p.th3);
  const double b1 = L1 * kW * std::sin(th1), b2 = -L1 * kW * std::cos(th1);
  const double det = a11 * a22 - a12 * a21;
  p.w2 = (b1 * a22 - a12 * b2) / det;
  p.w3 = (a11 * b2 - a21 * b1) / det;
  return p;
}

TEST(ClosedLoop, FourBarAnglesAndRatesAgainstGeometry) {
  testing::Built b = testing::BuildYaml(kFourBar);
  EXPECT_EQ(b.report.structural_index, 2u);
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_GT(tr.t.size(), 600u);  // two full turns of the crank
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double th1 = tr.values[k][0];
    ASSERT_NEAR(th1, kW * tr.t[k], 1e-12);
    Pose ref = Reference(th1);
    // The angles are solved from the closure at every step (to its Newton tolerance); the rates
    // from its derivative.
    EXPECT_NEAR(std::remainder(tr.values[k][1] - ref.th2, 2 * M_PI), 0.0, 1e-8) << "t = " << tr.t[k];
    EXPECT_NEAR(std::remainder(tr.values[k][2] - ref.th3, 2 * M_PI), 0.0, 1e-8) << "t = " << tr.t[k];
    EXPECT_NEAR(tr.values[k][3], ref.w2, 1e-7) << "t = " << tr.t[k];
    EXPECT_NEAR(tr.values[k][4], ref.w3, 1e-7) << "t = " << tr.t[k];
  }
}

}  // namespace
}  // namespace momenta

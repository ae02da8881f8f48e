// The event iteration (solver/event_iteration.cc): left/right rows, when-clauses with reinit and
// discrete assignments, pre(), discrete equations iterated until settled, `when initial()`, and
// chattering reported rather than looping forever.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/solver/event_rows.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;
using testing::EventRows;

TEST(EventIterationTest, WhenClauseWithReinitBouncesLikeTheImpactComponent) {
  // The classic Modelica bouncing ball, written with reinit(): same impact times as the exact
  // Impact component (models/bouncing_ball.yaml) while the bounces are large.
  Built b = testing::BuildYaml(R"yaml(
model: ReinitBall
parameters: {e: 0.8, g: 9.81}
variables:
  h: {start: 1, fixed: true}
  v: {start: 0, fixed: true}
  n: {type: Integer, start: 0}
equations:
  - der(h) = v
  - der(v) = -g
when:
  - when: h < 0
    then: ["reinit(v, -e*pre(v))", "n = pre(n) + 1"]
experiment: {stop: 3, tolerance: 1e-10, interval: 0.01}
outputs: [h, v, n]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  const double g = 9.81, e = 0.8, v0 = std::sqrt(2 * g), t1 = std::sqrt(2 / g);
  auto rows = EventRows(tr);
  ASSERT_GE(rows.size(), 4u);
  double tk = t1, vk = v0;
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(tr.t[rows[k]], tk, 1e-9) << "bounce " << k + 1;
    EXPECT_NEAR(tr.Column("v", rows[k] + 1), e * vk, 1e-8);
    EXPECT_EQ(tr.Column("n", rows[k] + 1), static_cast<double>(k + 1));
    vk *= e;
    tk += 2 * vk / g;
  }
}

TEST(EventIterationTest, DiscreteEquationsWithPreIterateUntilSettled) {
  // A Boolean that latches: on becomes true when x passes 1 and stays true (pre() feedback).
  Built b = testing::BuildYaml(R"yaml(
model: Latch
variables:
  x: {start: 0, fixed: true}
  on: {type: Boolean, start: false}
  y: {}
equations:
  - der(x) = if on then -1 else 1
  - on = pre(on) or x > 1
  - y = if on then 10 else 0
experiment: {stop: 3, tolerance: 1e-10, interval: 0.01}
outputs: [x, on, y]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  size_t last = tr.t.size() - 1;
  EXPECT_EQ(tr.Column("on", last), 1.0);
  EXPECT_EQ(tr.Column("y", last), 10.0);
  // x rises to 1 at t = 1 and then falls at unit rate: x(3) = 1 - 2 = -1 (to rtol).
  EXPECT_NEAR(tr.Column("x", last), -1.0, 1e-8);
}

TEST(EventIterationTest, ChatteringIsReportedNotLoopedForever) {
  // der(x) = -sign-like switching around x = 0: a sliding mode with events ever closer together.
  Built b = testing::BuildYaml(R"yaml(
model: Chatter
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = if x > 0 then -1 else 1
experiment: {stop: 2, tolerance: 1e-8, interval: 0.01}
outputs: [x]
)yaml");
  try {
    testing::RunDefault(b);
    FAIL() << "expected a chattering error";
  } catch (const SolverError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("chattering"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at t = 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("x > 0"), std::string::npos) << msg;
  }
}

TEST(EventIterationTest, WhenInitialFiresAtTheStartOnly) {
  // `when initial()` runs once at the start; a clause whose condition is already true at the
  // start (x >= 0) waits for an edge and never fires here.
  Built b = testing::BuildYaml(R"yaml(
model: InitialWhen
parameters: {k: 3}
variables:
  x: {start: 0, fixed: true}
  a: {start: -1}
  b: {start: -1}
equations:
  - der(x) = 1
when:
  - when: initial()
    then: ["a = 2*k"]
  - when: x >= 0
    then: ["b = 5"]
experiment: {stop: 1, tolerance: 1e-8, interval: 0.5}
outputs: [a, b]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("a", 0), 6.0);
  EXPECT_EQ(tr.Column("a", tr.t.size() - 1), 6.0);
  EXPECT_EQ(tr.Column("b", tr.t.size() - 1), -1.0);
}

TEST(EventIterationTest, ABranchThatCeasesToExistGivesWayToTheOneThatDoes) {
  // A Schmitt trigger: an amplifier limited to +-Vps with positive feedback through R2/R1, its
  // input u ramped from 5 V down to -5 V. It starts saturated high; when u passes
  // u* = (Vps/V0*(R1 + R2) - Vps*R1)/R2 (about -1 V) the high solution ceases to exist. The
  // iteration's first guesses flip between the high branch (whose solution has V0*x < Vps) and
  // the linear one (whose solution has V0*x > Vps): only the low branch, which neither visits,
  // is consistent, and it must be found rather than reported as chattering.
  Built b = testing::BuildYaml(R"yaml(
model: SchmittLoop
parameters: {V0: 15000, Vps: 15, R1: 1000, R2: 15000}
variables:
  u: {}
  x: {}
  v: {}
equations:
  - u = 5 - 10*time
  - x = (u*R2 + v*R1)/(R1 + R2)
  - v = if V0*x > Vps then Vps elseif V0*x < -Vps then -Vps else V0*x
experiment: {stop: 1, tolerance: 1e-8, interval: 0.01}
outputs: [u, x, v]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  const double V0 = 15000, Vps = 15, R1 = 1000, R2 = 15000;
  const double u_switch = (Vps / V0 * (R1 + R2) - Vps * R1) / R2, t_switch = (5 - u_switch) / 10;
  auto rows = EventRows(tr);
  ASSERT_EQ(rows.size(), 1u);
  // The crossing is located to its search's precision (1e-12 s here), far inside 1e-9 s.
  EXPECT_NEAR(tr.t[rows[0]], t_switch, 1e-9);
  EXPECT_EQ(tr.Column("v", rows[0]), Vps);
  EXPECT_EQ(tr.Column("v", rows[0] + 1), -Vps);
  // Low for the rest of the run, the input where the divider puts it: x = (u*R2 - Vps*R1)/(R1 + R2).
  const size_t last = tr.t.size() - 1;
  EXPECT_EQ(tr.Column("v", last), -Vps);
  EXPECT_NEAR(tr.Column("x", last), (-5 * R2 - Vps * R1) / (R1 + R2), 1e-9);
}

}  // namespace
}  // namespace momenta

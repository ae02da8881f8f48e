// The crossing search (solver/crossing_search.cc): time events hit exactly, state events located
// on the interpolant, noEvent() relations left alone, and crossings there and back within a
// fraction of a step found by the cubic models between samples.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/solver/event_rows.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;
using testing::EventRows;
using testing::EventTimes;

TEST(CrossingSearchTest, StepIsATimeEventHitExactly) {
  // startTime 0.123 is not on the 0.01 output grid: the event rows appear at exactly 0.123.
  Built b = testing::BuildYaml(R"yaml(
model: StepEvent
components:
  step: {type: Step, height: 2, offset: 1, startTime: 0.123}
  integrator: {type: Integrator}
connections:
  - [step.y, integrator.u]
experiment: {stop: 0.3, tolerance: 1e-10, interval: 0.01}
outputs: [step.y, integrator.y]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  auto rows = EventRows(tr);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(tr.t[rows[0]], 0.123);
  EXPECT_EQ(tr.Column("step.y", rows[0]), 1.0);      // left limit: offset
  EXPECT_EQ(tr.Column("step.y", rows[0] + 1), 3.0);  // right limit: offset + height
  EXPECT_EQ(tr.stats.time_events, 1);
  // The integral is exact for a piecewise-constant input (BDF integrates it exactly): 1e-10.
  EXPECT_NEAR(tr.Column("integrator.y", tr.t.size() - 1), 0.3 + 2 * (0.3 - 0.123), 1e-10);
}

TEST(CrossingSearchTest, TimeRelationAtZeroAtTheStartSwitchesThere) {
  // `time > 0` from t = 0 is false at the start and true at every later time: an event at the
  // start time switches it (it cannot be scheduled later), so the integral is exactly t.
  Built b = testing::BuildYaml(R"yaml(
model: StartSwitch
variables:
  x: {start: 0, fixed: true}
  u: {}
equations:
  - u = if time > 0 then 1 else 0
  - der(x) = u
experiment: {stop: 1, tolerance: 1e-10, interval: 0.25}
outputs: [u, x]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("u", 0), 0.0);  // at the start: time > 0 is false
  EXPECT_EQ(tr.Column("u", tr.t.size() - 1), 1.0);
  EXPECT_NEAR(tr.Column("x", tr.t.size() - 1), 1.0, 1e-10);
  EXPECT_EQ(tr.stats.time_events, 1);
}

TEST(CrossingSearchTest, StateEventIsLocatedOnTheInterpolant) {
  // x = t^2 crosses 0.5 at t = sqrt(0.5); a when-clause records the time it happened.
  Built b = testing::BuildYaml(R"yaml(
model: StateEvent
variables:
  x: {start: 0, fixed: true}
  v: {start: 0, fixed: true}
  t_cross: {start: -1}
equations:
  - der(x) = v
  - der(v) = 2
when:
  - when: x > 0.5
    then: ["t_cross = time"]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.1}
outputs: [x, t_cross]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  // Located to the solver's time resolution (~1e-15 relative); 1e-12 allows for the
  // interpolant's error at rtol 1e-10.
  EXPECT_NEAR(tr.Column("t_cross", tr.t.size() - 1), std::sqrt(0.5), 1e-12);
  ASSERT_EQ(EventRows(tr).size(), 1u);
  EXPECT_EQ(tr.Column("t_cross", EventRows(tr)[0]), -1.0);
}

TEST(CrossingSearchTest, NoEventRelationsMakeNoEvents) {
  Built b = testing::BuildYaml(R"yaml(
model: Smooth
variables:
  x: {start: -1, fixed: true}
  y: {}
equations:
  - der(x) = 1
  - y = noEvent(if x > 0 then x^2 else 0)
experiment: {stop: 2, tolerance: 1e-10, interval: 0.1}
outputs: [y]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_TRUE(EventRows(tr).empty());
  EXPECT_NEAR(tr.Column("y", tr.t.size() - 1), 1.0, 1e-9);
}

// Zero crossings that last a tiny fraction of a step: the crossing function goes through zero and
// back between two of the samples taken in each IDA step. The cubic model of each crossing function
// between samples (from its values and time derivatives) finds them; with only the samples they
// were missed.

TEST(CrossingSearchTest, ParabolaAboveZeroForATinyFractionOfAStepIsSeen) {
  // x = 1e-8 - (t - 1)^2 is above 0 for |t - 1| < 1e-4 only; IDA integrates the quadratic exactly
  // and takes large steps. The when-clause counts the upward crossing.
  Built b = testing::BuildYaml(R"yaml(
model: TouchingParabola
variables:
  x: {start: -0.99999999, fixed: true}
  v: {start: 2, fixed: true}
  n: {start: 0}
equations:
  - der(x) = v
  - der(v) = -2
when:
  - when: x > 0
    then: ["n = pre(n) + 1"]
experiment: {stop: 3, interval: 0.5, tolerance: 1e-8}
outputs: [x, n, "if x > 0 then 1 else 0"]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("n", tr.t.size() - 1), 1.0) << tr.stats.steps << " steps";
  // Both crossings, at 1 -/+ 1e-4. An event is placed where |x| has passed 1e-12 of its scale
  // (here 1), which at |x'| = 2e-4 is 5e-9 s after the crossing: 1e-8.
  std::vector<double> events = EventTimes(tr);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_NEAR(events[0], 1 - 1e-4, 1e-8);
  EXPECT_NEAR(events[1], 1 + 1e-4, 1e-8);
}

TEST(CrossingSearchTest, SinePeakJustAboveTheThresholdIsSeenEveryPeriod) {
  // A slow sine (period 20 s) whose peaks exceed a GreaterThreshold by 1e-6 of its amplitude: above
  // it for 9 ms around t = 5, 25, 45, 65, 85. An integrator gives IDA something to integrate (its
  // steps are set by the integral, not by the threshold). The when-clause counts the peaks.
  Built b = testing::BuildYaml(R"yaml(
model: ThinSinePeaks
variables:
  n: {start: 0}
components:
  sine: {type: Sine, amplitude: 1, f: 0.05}
  above: {type: GreaterThreshold, threshold: 0.999999}
  integrator: {type: Integrator}
connections:
  - [sine.y, above.u]
  - [sine.y, integrator.u]
when:
  - when: above.y
    then: ["n = pre(n) + 1"]
experiment: {stop: 100, interval: 0.5}
outputs: [integrator.y, n, above.y]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("n", tr.t.size() - 1), 5.0) << tr.stats.steps << " steps";
  // Each crossing at 5 + 20k -/+ acos(0.999999)/(2 pi 0.05) = 4.5e-3 s. An event is placed where
  // |u - threshold| has passed 1e-12 of its scale (2), at |du/dt| = 4.4e-4 that is 4.5e-9 s late: 1e-8.
  const double half_width = std::acos(0.999999) / (2 * M_PI * 0.05);
  std::vector<double> events = EventTimes(tr);
  ASSERT_EQ(events.size(), 10u);
  for (size_t k = 0; k < 10; ++k) {
    const double peak = 5 + 20 * (k / 2);
    EXPECT_NEAR(events[k], k % 2 ? peak + half_width : peak - half_width, 1e-8) << k;
  }
}

TEST(CrossingSearchTest, OscillatorTouchingAThresholdIsSeenEveryPeriod) {
  // x = sin(t) from states (rtol 1e-9 keeps the amplitude well within 1e-6); x > 1 - 1e-6 for 2.8 ms
  // around each peak at pi/2 + 2 pi k: 4 peaks before t = 25.
  Built b = testing::BuildYaml(R"yaml(
model: ThinOscillatorPeaks
variables:
  x: {start: 0, fixed: true}
  v: {start: 1, fixed: true}
  n: {start: 0}
equations:
  - der(x) = v
  - der(v) = -x
when:
  - when: x > 1 - 1e-6
    then: ["n = pre(n) + 1"]
experiment: {stop: 25, interval: 0.5, tolerance: 1e-9}
outputs: [x, n]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("n", tr.t.size() - 1), 4.0) << tr.stats.steps << " steps";
}

TEST(CrossingSearchTest, ConditionOnADiscreteVariableIsModelledWithItsValueConstant) {
  // x = t crosses n + 0.5 at t = 0.5, 1.5, …; n (discrete) is constant between events, so dz/dt = 1
  // (its der() would have been an unknown's y' that does not exist: an internal error before).
  Built b = testing::BuildYaml(R"yaml(
model: Staircase
variables:
  x: {start: 0, fixed: true}
  n: {start: 0}
equations:
  - der(x) = 1
when:
  - when: x > n + 0.5
    then: ["n = pre(n) + 1"]
experiment: {stop: 5, interval: 0.5}
outputs: [x, n]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  EXPECT_EQ(tr.Column("n", tr.t.size() - 1), 5.0);
  std::vector<double> events = EventTimes(tr);
  ASSERT_EQ(events.size(), 5u);
  for (size_t k = 0; k < 5; ++k) EXPECT_NEAR(events[k], k + 0.5, 1e-9) << k;
}

}  // namespace
}  // namespace momenta

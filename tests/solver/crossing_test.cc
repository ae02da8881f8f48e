// Zero crossings that last a tiny fraction of a step: the crossing function goes through zero and
// back between two of the samples taken in each IDA step. The cubic model of each crossing function
// between samples (from its values and time derivatives) finds them; with only the samples they
// were missed.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

/// Times of rows that repeat (an event's left and right limits).
std::vector<double> EventTimes(const Trajectory& tr) {
  std::vector<double> times;
  for (size_t k = 0; k + 1 < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k + 1]) times.push_back(tr.t[k]);
  }
  return times;
}

TEST(CrossingTest, ParabolaAboveZeroForATinyFractionOfAStepIsSeen) {
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

TEST(CrossingTest, SinePeakJustAboveTheThresholdIsSeenEveryPeriod) {
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

TEST(CrossingTest, OscillatorTouchingAThresholdIsSeenEveryPeriod) {
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

TEST(CrossingTest, ConditionOnADiscreteVariableIsModelledWithItsValueConstant) {
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

// The blocks of components/blocks_*.yaml after MSL Blocks against their closed forms, for what
// the MSL reference results do not pin:
// - FirstOrder, k/(T s + 1), after a unit step at t0 from steady state: y = k (1 - e^{-(t-t0)/T});
// - an Integrator closing a loop y' = k (r - y) with initType SteadyState starts at y = r;
// - SlewRateLimiter after a unit step at t0: y = Rising (t - t0) while u - y > Rising Td;
// - Filter, Butterworth low pass of order 2 (w = 2 pi f_cut, zeta = 1/sqrt(2)), unit step at t0
//   from steady state: y = 1 - e^{-zeta w s} (cos(wd s) + zeta/sqrt(1 - zeta^2) sin(wd s)),
//   s = t - t0, wd = w sqrt(1 - zeta^2); as a high pass, s^2/(s^2 + 2 zeta w s + w^2):
//   y = e^{-zeta w s} (cos(wd s) - zeta/sqrt(1 - zeta^2) sin(wd s));
// - CriticalDamping of order 2, w = 2 pi f/alpha, alpha = sqrt(2^(1/2) - 1):
//   y = 1 - (1 + w s) e^{-w s};
// - SampleTrigger, BooleanPulse and Pulse switch at exactly startTime + k period (time events);
// - Mean of u = 1 + sin(2 pi f t) over each period 1/f is 1 from the first period's end;
// - KinematicPTP2 from 0 to 1 with qd_max 1, qdd_max 2 from t0: accelerates at 2 for 0.5 s,
//   moves at 1 for 0.5 s, decelerates for 0.5 s: q = (t-t0)^2 for t-t0 < 0.5, then
//   0.25 + (t-t0-0.5), then 1 - (t0+1.5-t)^2, and 1 from t0 + 1.5 on.
// Tolerances: the runs use rtol 1e-8, so the states are within about 1e-6 of the closed forms.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

Trajectory RunModel(const std::string& yaml) {
  Built b = testing::BuildYaml(yaml);
  for (const auto& w : b.report.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  return testing::RunDefault(b);
}

/// The value of `name` at the last row at or before t (rows at an event: the right limit).
double At(const Trajectory& tr, const std::string& name, double t) {
  size_t row = 0;
  for (size_t k = 0; k < tr.t.size() && tr.t[k] <= t + 1e-12; ++k) row = k;
  return tr.Column(name, row);
}

TEST(BlocksLibraryTest, FirstOrderStepResponseFromSteadyState) {
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  step: {type: Step, startTime: 0.5, height: 1}
  fo: {type: FirstOrder, k: 2, T: 0.3, initType: 2}
connections: [[step.y, fo.u]]
experiment: {stop: 2, interval: 0.01, tolerance: 1e-8}
outputs: [fo.y]
)yaml");
  for (double t : {0.25, 0.6, 0.8, 1.1, 2.0}) {
    const double expected = t < 0.5 ? 0 : 2 * (1 - std::exp(-(t - 0.5) / 0.3));
    EXPECT_NEAR(At(tr, "fo.y", t), expected, 1e-6) << "t = " << t;
  }
}

TEST(BlocksLibraryTest, IntegratorSteadyStateInitialisationInALoop) {
  // y' = 4 (r - y): steady state means y = r = 3 at the start, and y stays there.
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  r: {type: Constant, k: 3}
  fb: {type: Feedback}
  integ: {type: Integrator, k: 4, initType: 2, y_start: -7}
connections: [[r.y, fb.u1], [integ.y, fb.u2], [fb.y, integ.u]]
experiment: {stop: 1, interval: 0.1, tolerance: 1e-8}
outputs: [integ.y]
)yaml");
  EXPECT_NEAR(At(tr, "integ.y", 0), 3, 1e-9);
  EXPECT_NEAR(At(tr, "integ.y", 1), 3, 1e-9);
}

TEST(BlocksLibraryTest, IntegratorInitialStateIsTheDefault) {
  // The existing default: y = y_start at the start, then y' = k u.
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  c: {type: Constant, k: 2}
  integ: {type: Integrator, k: 0.5, y_start: 1}
connections: [[c.y, integ.u]]
experiment: {stop: 1, interval: 0.1, tolerance: 1e-8}
outputs: [integ.y]
)yaml");
  EXPECT_NEAR(At(tr, "integ.y", 0), 1, 1e-12);
  EXPECT_NEAR(At(tr, "integ.y", 1), 2, 1e-7);
}

TEST(BlocksLibraryTest, SlewRateLimiterRampsAtItsRisingRate) {
  // Rising = 2/s, Td = 1 ms: the ramp holds until u - y < Rising*Td = 2e-3, about t = 0.999.
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  step: {type: Step, startTime: 0.5, height: 1}
  srl: {type: SlewRateLimiter, Rising: 2}
connections: [[step.y, srl.u]]
experiment: {stop: 1.5, interval: 0.01, tolerance: 1e-8}
outputs: [srl.y]
)yaml");
  EXPECT_NEAR(At(tr, "srl.y", 0.4), 0, 1e-9);  // initType SteadyState: y = u = 0
  for (double t : {0.6, 0.75, 0.9}) EXPECT_NEAR(At(tr, "srl.y", t), 2 * (t - 0.5), 1e-6) << "t = " << t;
  EXPECT_NEAR(At(tr, "srl.y", 1.5), 1, 1e-6);
}

/// The step responses of the second-order Butterworth low pass (high_pass false) and high pass.
double Butterworth2Step(double f_cut, double s, bool high_pass) {
  const double w = 2 * kPi * f_cut, zeta = 1 / std::sqrt(2.0), wd = w * std::sqrt(1 - zeta * zeta);
  const double decay = std::exp(-zeta * w * s), ratio = zeta / std::sqrt(1 - zeta * zeta);
  if (high_pass) return decay * (std::cos(wd * s) - ratio * std::sin(wd * s));
  return 1 - decay * (std::cos(wd * s) + ratio * std::sin(wd * s));
}

TEST(BlocksLibraryTest, ButterworthLowAndHighPassStepResponses) {
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  step: {type: Step, startTime: 0.1}
  lp: {type: Filter, analogFilter: 3, order: 2, f_cut: 3}
  hp: {type: Filter, analogFilter: 3, filterType: 2, order: 2, f_cut: 3}
connections: [[step.y, lp.u], [step.y, hp.u]]
experiment: {stop: 0.6, interval: 0.005, tolerance: 1e-8}
outputs: [lp.y, hp.y]
)yaml");
  for (double t : {0.12, 0.15, 0.2, 0.3, 0.6}) {
    EXPECT_NEAR(At(tr, "lp.y", t), Butterworth2Step(3, t - 0.1, false), 1e-6) << "t = " << t;
    EXPECT_NEAR(At(tr, "hp.y", t), Butterworth2Step(3, t - 0.1, true), 1e-6) << "t = " << t;
  }
}

TEST(BlocksLibraryTest, CriticalDampingStepResponse) {
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  step: {type: Step, startTime: 0.1}
  cd: {type: CriticalDamping, n: 2, f: 2, initType: 2}
  filter: {type: Filter, analogFilter: 1, order: 2, f_cut: 2}
connections: [[step.y, cd.u], [step.y, filter.u]]
experiment: {stop: 1, interval: 0.005, tolerance: 1e-8}
outputs: [cd.y, filter.y]
)yaml");
  // CriticalDamping normalises with sqrt(2^(1/n) - 1), Filter with sqrt(10^(3/10/n) - 1) (MSL).
  const double w_block = 2 * kPi * 2 / std::sqrt(std::pow(2.0, 0.5) - 1);
  const double w_filter = 2 * kPi * 2 / std::sqrt(std::pow(10.0, 0.15) - 1);
  for (double t : {0.15, 0.2, 0.4, 1.0}) {
    const double s = t - 0.1;
    EXPECT_NEAR(At(tr, "cd.y", t), 1 - (1 + w_block * s) * std::exp(-w_block * s), 1e-6) << "t = " << t;
    EXPECT_NEAR(At(tr, "filter.y", t), 1 - (1 + w_filter * s) * std::exp(-w_filter * s), 1e-6) << "t = " << t;
  }
}

TEST(BlocksLibraryTest, PeriodicSourcesSwitchAtExactTimes) {
  // A counter of the sample instants, a Boolean pulse and a Real pulse: every switch is a time
  // event, so an event row stands at exactly startTime + k*period.
  Trajectory tr = RunModel(R"yaml(
model: M
define:
  Counter:
    connectors: {u: BooleanInput}
    variables:
      count: {type: Integer, start: 0}
    initial_equations:
      - pre(count) = 0
    when:
      - when: u
        then: ["count = pre(count) + 1"]
components:
  sample: {type: SampleTrigger, period: 0.1, startTime: 0.05}
  counter: {type: Counter}
  bp: {type: BooleanPulse, period: 0.3, width: 40}
  p: {type: Pulse, amplitude: 2, period: 0.25, width: 20, startTime: 0.1}
connections: [[sample.y, counter.u]]
experiment: {stop: 1, interval: 0.5, tolerance: 1e-6}
outputs: [counter.count, bp.y, p.y]
)yaml");
  // Samples at 0.05, 0.15, …, 0.95: ten of them.
  EXPECT_EQ(At(tr, "counter.count", 1.0), 10);
  EXPECT_EQ(At(tr, "counter.count", 0.5), 5);
  EXPECT_EQ(tr.stats.events - tr.stats.time_events, 0) << "every switch is a time event";
  // Every row time is a grid time or an exact switching instant k*0.1 + 0.05, k*0.3 (+ 0.12),
  // 0.1 + k*0.25 (+ 0.05), to the last bits.
  for (double t : tr.t) {
    bool exact = false;
    for (int k = 0; k <= 20 && !exact; ++k) {
      for (double candidate : {0.5 * k, 0.05 + 0.1 * k, 0.3 * k, 0.3 * k + 0.12, 0.1 + 0.25 * k, 0.15 + 0.25 * k}) {
        exact = exact || std::fabs(t - candidate) <= 1e-14;
      }
    }
    EXPECT_TRUE(exact) << "a row at t = " << t;
  }
  EXPECT_EQ(At(tr, "bp.y", 0.61), 1);
  EXPECT_EQ(At(tr, "bp.y", 0.73), 0);
  EXPECT_EQ(At(tr, "p.y", 0.36), 2);
  EXPECT_EQ(At(tr, "p.y", 0.41), 0);
}

// Pulse and Trapezoid count their periods as the MSL's: whole periods since startTime from the
// start (negative before a late start: events every period before it too, at startTime - k*period)
// and nperiod periods only, then the offset.
TEST(BlocksLibraryTest, PulseAndTrapezoidCountPeriodsAsTheMslAndStopAfterNperiod) {
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  p: {type: Pulse, amplitude: 2, period: 0.25, width: 20, startTime: 0.3, nperiod: 2, offset: 1}
  z: {type: Trapezoid, amplitude: 1, rising: 0.1, width: 0.1, falling: 0.1, period: 0.4, startTime: 0.3, nperiod: 1}
experiment: {stop: 1.2, interval: 0.01, tolerance: 1e-6}
outputs: [p.y, p.count, z.y, z.count]
)yaml");
  EXPECT_EQ(tr.Column("p.count", 0), -2);  // integer((0 - 0.3)/0.25) rounded down, as floor
  EXPECT_EQ(tr.Column("z.count", 0), -1);
  EXPECT_EQ(At(tr, "p.count", 0.1), -1);    // the event at 0.05 = 0.3 - 0.25
  EXPECT_EQ(At(tr, "p.y", 0.2), 1);         // before startTime: the offset
  EXPECT_EQ(At(tr, "p.y", 0.32), 3);        // first pulse [0.3, 0.35)
  EXPECT_EQ(At(tr, "p.y", 0.4), 1);
  EXPECT_EQ(At(tr, "p.y", 0.57), 3);        // second pulse [0.55, 0.6)
  EXPECT_EQ(At(tr, "p.y", 0.82), 1);        // nperiod = 2: no third
  EXPECT_EQ(At(tr, "p.y", 1.07), 1);
  EXPECT_NEAR(At(tr, "z.y", 0.35), 0.5, 1e-12);  // rising
  EXPECT_EQ(At(tr, "z.y", 0.45), 1);
  EXPECT_NEAR(At(tr, "z.y", 0.55), 0.5, 1e-12);  // falling
  EXPECT_EQ(At(tr, "z.y", 0.8), 0);              // nperiod = 1: no second
}

TEST(BlocksLibraryTest, MeanOverEachPeriod) {
  // u = 1 + sin(2 pi 5 t): its mean over each 0.2 s period is 1, available from t = 0.2 on.
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  s: {type: Sine, f: 5, offset: 1}
  mean: {type: Mean, f: 5, y0: -1}
connections: [[s.y, mean.u]]
experiment: {stop: 0.7, interval: 0.05, tolerance: 1e-8}
outputs: [mean.y]
)yaml");
  EXPECT_EQ(At(tr, "mean.y", 0.15), -1);
  for (double t : {0.2, 0.45, 0.7}) EXPECT_NEAR(At(tr, "mean.y", t), 1, 1e-6) << "t = " << t;
}

TEST(BlocksLibraryTest, KinematicPTP2TrapezoidalSpeedProfile) {
  Trajectory tr = RunModel(R"yaml(
model: M
components:
  ptp: {type: KinematicPTP2, q_end: [1], qd_max: [1], qdd_max: [2], startTime: 0.1}
experiment: {stop: 2, interval: 0.05, tolerance: 1e-8}
outputs: [ptp.q, ptp.qd, ptp.qdd, ptp.moving]
)yaml");
  auto q = [](double s) { return s < 0.5 ? s * s : s < 1 ? 0.25 + (s - 0.5) : s < 1.5 ? 1 - (1.5 - s) * (1.5 - s) : 1.0; };
  auto qd = [](double s) { return s < 0.5 ? 2 * s : s < 1 ? 1.0 : s < 1.5 ? 2 * (1.5 - s) : 0.0; };
  for (double t : {0.05, 0.35, 0.85, 1.35, 1.95}) {
    const double s = std::max(0.0, t - 0.1);
    EXPECT_NEAR(At(tr, "ptp.q[1]", t), q(s), 1e-9) << "t = " << t;
    EXPECT_NEAR(At(tr, "ptp.qd[1]", t), qd(s), 1e-9) << "t = " << t;
  }
  EXPECT_NEAR(At(tr, "ptp.qdd[1]", 0.35), 2, 1e-9);
  EXPECT_NEAR(At(tr, "ptp.qdd[1]", 1.35), -2, 1e-9);
  EXPECT_EQ(At(tr, "ptp.moving[1]", 1.55), 1);
  EXPECT_EQ(At(tr, "ptp.moving[1]", 1.65), 0);
}

TEST(BlocksLibraryTest, FilterRefusesOrdersAndKindsItDoesNotHave) {
  // The Filter holds six states, low and high pass: a larger order or a band filter is an error
  // at the entry, naming the component, the value and the limit.
  const std::string base = R"yaml(
model: M
components:
  step: {type: Step}
  f: {type: Filter, f_cut: 2, )yaml";
  const std::string tail = "}\nconnections: [[step.y, f.u]]\n";
  std::string error = testing::BuildError(base + "order: 7" + tail);
  EXPECT_NE(error.find("f.order"), std::string::npos) << error;
  EXPECT_NE(error.find("= 7 is above its maximum 6"), std::string::npos) << error;
  error = testing::BuildError(base + "filterType: 3" + tail);
  EXPECT_NE(error.find("f.filterType"), std::string::npos) << error;
  EXPECT_NE(error.find("= 3 is above its maximum 2"), std::string::npos) << error;
  EXPECT_NE(error.find("BandPass"), std::string::npos) << error;
}

}  // namespace
}  // namespace momenta

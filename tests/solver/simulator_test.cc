// Simulate()'s contract at its edges: options that give no finite output grid are refused before
// anything runs; an interrupt stops the run between steps and between rows with no gap in the rows;
// a solver failure's advice points the right way; how long the run is does not change its start.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;

// x' = -x, x(0) = 1 (no events).
constexpr const char* kDecay = R"yaml(model: Decay
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = -x
experiment: {stop: 10, interval: 0.01}
outputs: [x]
)yaml";

// The same with a state event at x = 0.5 (t = ln 2) counted by a when-clause.
constexpr const char* kDecayWithEvent = R"yaml(model: DecayWithEvent
variables:
  x: {start: 1, fixed: true}
  n: {start: 0}
equations:
  - der(x) = -x
when:
  - when: x < 0.5
    then: ["n = pre(n) + 1"]
experiment: {stop: 10, interval: 0.01}
outputs: [x, n]
)yaml";

std::string RunError(const Built& b, const SimulationOptions& opt) {
  try {
    testing::Run(b, opt);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(SimulatorTest, OptionsWithoutAFiniteOutputGridAreRefused) {
  Built b = testing::BuildYaml(kDecay);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  struct Case {
    double stop, interval;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           {inf, 0, "the stop time inf is not a finite time after the start time 0"},
           {nan, 0, "the stop time NaN is not a finite time after the start time 0"},
           {0, 0, "the stop time 0 is not a finite time after the start time 0"},
           {1, -1, "the output interval -1 is not a positive finite number"},
           {1, nan, "the output interval NaN is not a positive finite number"},
           {1, 1e-300, "the output interval 1e-300: from 0 to 1 s that is 1e+300 output rows; at most 1e9 can be written"},
       }) {
    SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
    opt.stop = c.stop;
    opt.interval = c.interval;
    const std::string msg = RunError(b, opt);
    EXPECT_NE(msg.find(c.message), std::string::npos) << "stop " << c.stop << ", interval " << c.interval << ": " << msg;
  }
}

/// Runs `yaml`, raising the interrupt flag when row `at_row` arrives; returns the trajectory.
testing::Trajectory RunInterrupted(const char* yaml, size_t at_row) {
  Built b = testing::BuildYaml(yaml);
  std::atomic<bool> flag{false};
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  opt.interrupt = &flag;
  ModelState state(b.model);
  testing::Trajectory tr;
  Simulate(&state, opt, [&](double t, const std::vector<double>& v) {
    tr.t.push_back(t);
    tr.values.push_back(v);
    if (tr.t.size() == at_row) flag = true;
  }, &tr.stats);
  return tr;
}

TEST(SimulatorTest, InterruptStopsBetweenRowsWithoutAGap) {
  for (const char* yaml : {kDecay, kDecayWithEvent}) {
    // Raised at the 5th row (t = 0.04): no row follows it, and the run says where it stopped.
    testing::Trajectory tr = RunInterrupted(yaml, 5);
    ASSERT_EQ(tr.t.size(), 5u) << yaml;
    for (size_t k = 0; k < tr.t.size(); ++k) EXPECT_NEAR(tr.t[k], 0.01 * k, 1e-15) << yaml;
    EXPECT_TRUE(tr.stats.interrupted) << yaml;
    EXPECT_GE(tr.stats.interrupted_at, 0.04) << yaml;
    EXPECT_LT(tr.stats.interrupted_at, 10) << yaml;
    EXPECT_EQ(tr.stats.final_time, tr.t.back()) << yaml;
    // Raised at the first row (the initial values): nothing more.
    EXPECT_EQ(RunInterrupted(yaml, 1).t.size(), 1u) << yaml;
    // Never raised: the whole run, not marked interrupted.
    testing::Trajectory whole = RunInterrupted(yaml, 0);
    EXPECT_FALSE(whole.stats.interrupted) << yaml;
    EXPECT_EQ(whole.t.back(), 10) << yaml;
  }
}

// A driven oscillator starting at rest: y'(0) = 0, so nothing in the state sizes IDA's first step;
// the same with a when-clause counting the crossings of x = 0.005 (the event loop's path).
constexpr const char* kDrivenAtRest = R"yaml(model: DrivenAtRest
variables:
  x: {start: 0, fixed: true}
  v: {start: 0, fixed: true}
equations:
  - der(x) = v
  - der(v) = sin(10*time) - 4*x - 0.2*v
experiment: {stop: 2, interval: 0.01}
outputs: [x, v]
)yaml";
constexpr const char* kDrivenAtRestWithEvent = R"yaml(model: DrivenAtRestWithEvent
variables:
  x: {start: 0, fixed: true}
  v: {start: 0, fixed: true}
  n: {start: 0}
equations:
  - der(x) = v
  - der(v) = sin(10*time) - 4*x - 0.2*v
when:
  - when: x > 0.005
    then: ["n = pre(n) + 1"]
experiment: {stop: 2, interval: 0.01}
outputs: [x, v, n]
)yaml";

// IDA's first step follows the output interval, not the length of the run (IDA_ONE_STEP aimed at
// the stop time would start 100x larger here): so a run to 200 s repeats the rows of a run to 2 s
// to the bit, up to where the shorter run's steps are cut at its stop time.
TEST(SimulatorTest, ALongerRunRepeatsAShorterOnesRows) {
  for (const char* yaml : {kDrivenAtRest, kDrivenAtRestWithEvent}) {
    Built b = testing::BuildYaml(yaml);
    SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
    const testing::Trajectory shorter = testing::Run(b, opt);
    opt.stop = 200;
    const testing::Trajectory longer = testing::Run(b, opt);
    ASSERT_EQ(shorter.t.back(), 2) << yaml;
    ASSERT_EQ(longer.t.back(), 200) << yaml;
    size_t compared = 0;
    for (size_t k = 0; k < shorter.t.size() && shorter.t[k] <= 1.0; ++k, ++compared) {
      ASSERT_EQ(shorter.t[k], longer.t[k]) << yaml;
      EXPECT_EQ(shorter.values[k], longer.values[k]) << yaml << " at t = " << shorter.t[k];
    }
    // 101 grid rows, and with the when-clause a left- and a right-limit row at each event.
    const bool counts = yaml == kDrivenAtRestWithEvent;
    EXPECT_EQ(compared, counts ? 103u : 101u) << yaml;
    if (counts) EXPECT_EQ(longer.values[compared - 1][2], 1.0);
  }
}

TEST(SimulatorTest, MaxOrderOutsideOneToFiveIsRefused) {
  Built b = testing::BuildYaml(kDecay);
  for (int q : {0, 6, -1}) {
    SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
    opt.max_order = q;
    const std::string msg = RunError(b, opt);
    EXPECT_NE(msg.find("the maximum BDF order " + std::to_string(q) + " is not one of 1 to 5"), std::string::npos)
        << msg;
  }
}

// x' = -x with IDA's BDF order capped at 1 (backward Euler) to 5: every cap follows exp(-t) (the
// local error test at rtol 1e-6 leaves backward Euler a global error of 2e-4 over ten time
// constants, order 2 2e-5, the higher orders a few 1e-6), and each higher cap takes fewer steps,
// so the cap reaches IDA.
TEST(SimulatorTest, EveryMaxOrderFollowsTheDecay) {
  Built b = testing::BuildYaml(kDecay);
  long steps[6] = {};
  for (int q = 1; q <= 5; ++q) {
    SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
    opt.max_order = q;
    const testing::Trajectory tr = testing::Run(b, opt);
    ASSERT_EQ(tr.t.back(), 10) << "order " << q;
    double worst = 0;
    for (size_t k = 0; k < tr.t.size(); ++k) worst = std::max(worst, std::fabs(tr.values[k][0] - std::exp(-tr.t[k])));
    EXPECT_LT(worst, q == 1 ? 5e-4 : q == 2 ? 5e-5 : 1e-5) << "order " << q;
    steps[q] = tr.stats.steps;
    if (q > 1) EXPECT_LT(steps[q], steps[q - 1]) << "order " << q;
  }
  EXPECT_GT(steps[1], 10 * steps[5]) << steps[1] << " steps at order 1, " << steps[5] << " at order 5";
}

TEST(SimulatorTest, SolverFailureAdviceFitsTheFailure) {
  Built b = testing::BuildYaml(kDecay);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  // Below what double precision resolves (the CLI refuses it up front): loosen, not tighten.
  opt.rtol = 1e-17;
  opt.atol = 1e-30;
  std::string msg = RunError(b, opt);
  EXPECT_NE(msg.find("IDA_TOO_MUCH_ACC"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Loosen the tolerance (a larger --rtol or --atol)"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("tighter"), std::string::npos) << msg;
  // A tolerance so small that IDA's step vanishes: IDA itself blames the stop time ("tstop is
  // behind current t"); the message names the tolerance.
  opt.rtol = 1e-300;
  opt.atol = 1e-300;
  msg = RunError(b, opt);
  EXPECT_NE(msg.find("IDA rejected its input (IDA_ILL_INPUT): the relative tolerance 1e-300 is below what double "
                     "precision resolves (use at least 1e-15)"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find("tstop"), std::string::npos) << msg;
}

// A run in pieces (Co-Simulation's steps) carries IDA on across each piece's end: the carrier
// collision advanced in 37 pieces of 13.5 ms (one ends 2 ms after the first impact) writes the
// same output grid, finds both impacts and ends at the seed's closed form, vB = 31.95/11 m/s, to
// rounding (the impacts are linear solves); each piece's end point is consistent.
TEST(SimulatorTest, ARunInPiecesGoesOnWhereTheLastPieceEnded) {
  Built b = testing::BuildFile("models/carrier_collision.yaml");
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  ModelState state(b.model);
  state.SetParameters({});
  testing::Trajectory tr;
  Simulation run(&state, opt, [&](double t, const std::vector<double>& v) {
    tr.t.push_back(t);
    tr.values.push_back(v);
  }, &tr.stats);
  RunPoint end;
  const double kPiece = 0.0135;
  for (double t = opt.start + kPiece; t < opt.stop; t += kPiece) {
    end = run.AdvanceTo(t);
    EXPECT_DOUBLE_EQ(end.t, t);
  }
  end = run.AdvanceTo(opt.stop);
  EXPECT_EQ(end.t, opt.stop);
  EXPECT_EQ(tr.stats.impacts, 2);
  const auto& names = b.model->output_names;
  const size_t bv = static_cast<size_t>(std::find(names.begin(), names.end(), "B.v") - names.begin());
  ASSERT_LT(bv, names.size());
  EXPECT_NEAR(tr.values.back()[bv], 31.95 / 11, 1e-9);
  ModelState whole(b.model);
  whole.SetParameters({});
  testing::Trajectory one;
  Simulate(&whole, opt, [&](double t, const std::vector<double>& v) {
    one.t.push_back(t);
    one.values.push_back(v);
  }, &one.stats);
  ASSERT_EQ(tr.t.size(), one.t.size());
  for (size_t k = 0; k < tr.t.size(); ++k) EXPECT_NEAR(tr.t[k], one.t[k], 1e-12) << k;
  EXPECT_THROW(run.AdvanceTo(opt.stop + 1), std::invalid_argument);
}

}  // namespace
}  // namespace momenta

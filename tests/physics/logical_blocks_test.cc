// The Boolean blocks of components/blocks.yaml after MSL Blocks.Logical, against their closed
// forms: truth tables (Xor, Nor, Nand, LogicalSwitch, RSFlipFlop), instants (Pre, Change,
// FallingEdge, ZeroCrossing are true only at an event instant, so a when-clause counts them),
// switching times (OnOffController, Greater…), Timer's elapsed time and TriggeredTrapezoid's
// ramps. Inputs are time pulses (time events, hit exactly), so the expected values are exact.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

/// Library types every model below uses: a Boolean pulse true on [on, off) and, if given, on
/// [on2, off2), and a counter of the instants where its input becomes true.
constexpr const char* kPulseAndCounter = R"yaml(
define:
  TimePulse:
    parameters: {on: 1, off: 2, on2: -1, off2: -1}
    connectors: {y: BooleanOutput}
    equations:
      - y = (time >= on and time < off) or (time >= on2 and time < off2)
  Counter:
    connectors: {u: BooleanInput}
    variables:
      count: {type: Integer, start: 0}
    initial_equations:
      - pre(count) = 0
    when:
      - when: u
        then: ["count = pre(count) + 1"]
)yaml";

Trajectory RunModel(const std::string& body, const ParameterOverrides& overrides = {}) {
  Built b = testing::BuildYaml(std::string(kPulseAndCounter) + body, overrides);
  for (const auto& w : b.report.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  return testing::RunDefault(b, overrides);
}

/// Our value of `name` at time t, read at the last row at or before t (rows at an event: the right
/// limit).
double At(const Trajectory& tr, const std::string& name, double t) {
  size_t row = 0;
  for (size_t k = 0; k < tr.t.size() && tr.t[k] <= t + 1e-12; ++k) row = k;
  return tr.Column(name, row);
}

// u1 is true on [1, 3) and u2 on [2, 4): the four input pairs FF, TF, TT, FT, FF on the unit
// intervals from 0 to 5, read at their midpoints.
TEST(LogicalBlocksTest, TruthTablesOfXorNorNandAndLogicalSwitch) {
  Trajectory tr = RunModel(R"yaml(
model: Gates
components:
  u1: {type: TimePulse, on: 1, off: 3}
  u2: {type: TimePulse, on: 2, off: 4}
  sel: {type: TimePulse, on: 0, off: 2.5}
  xor: {type: Xor}
  nor: {type: Nor}
  nand: {type: Nand}
  logicalSwitch: {type: LogicalSwitch}
connections:
  - [u1.y, xor.u1]
  - [u2.y, xor.u2]
  - [u1.y, nor.u1]
  - [u2.y, nor.u2]
  - [u1.y, nand.u1]
  - [u2.y, nand.u2]
  - [u1.y, logicalSwitch.u1]
  - [sel.y, logicalSwitch.u2]
  - [u2.y, logicalSwitch.u3]
experiment: {stop: 5, interval: 0.25}
outputs: [xor.y, nor.y, nand.y, logicalSwitch.y]
)yaml");
  const bool u1[] = {false, true, true, false, false}, u2[] = {false, false, true, true, false};
  for (int k = 0; k < 5; ++k) {
    const double t = k + 0.5;
    EXPECT_EQ(At(tr, "xor.y", t), u1[k] != u2[k] ? 1.0 : 0.0) << "t = " << t;
    EXPECT_EQ(At(tr, "nor.y", t), !(u1[k] || u2[k]) ? 1.0 : 0.0) << "t = " << t;
    EXPECT_EQ(At(tr, "nand.y", t), !(u1[k] && u2[k]) ? 1.0 : 0.0) << "t = " << t;
    // The switch passes u1 while sel is true (t < 2.5), then u2.
    EXPECT_EQ(At(tr, "logicalSwitch.y", t), (t < 2.5 ? u1[k] : u2[k]) ? 1.0 : 0.0) << "t = " << t;
  }
}

// S is true on [1, 2), R on [3, 4), both on [5, 6). Q follows the set-reset truth table: set by
// S, kept, reset by R, kept; with S and R both true both outputs are false (the two Nor gates).
// When both fall at once (6), the Nor that makes Q reads QI through the Pre, i.e. its value
// before the event (false): Q turns true first, and the latch settles set (Q = 1, QI = 0).
TEST(LogicalBlocksTest, RSFlipFlopTruthTable) {
  const std::string model = R"yaml(
model: FlipFlop
components:
  s: {type: TimePulse, on: 1, off: 2, on2: 5, off2: 6}
  r: {type: TimePulse, on: 3, off: 4, on2: 5, off2: 6}
  rSFlipFlop: {type: RSFlipFlop}
connections:
  - [s.y, rSFlipFlop.S]
  - [r.y, rSFlipFlop.R]
experiment: {stop: 7, interval: 0.25}
outputs: [rSFlipFlop.Q, rSFlipFlop.QI, rSFlipFlop.pre.u]
)yaml";
  Trajectory tr = RunModel(model);
  const double q[] = {0, 1, 1, 0, 0, 0, 1}, qi[] = {1, 0, 0, 1, 1, 0, 0};
  for (int k = 0; k < 7; ++k) {
    const double t = k + 0.5;
    EXPECT_EQ(At(tr, "rSFlipFlop.Q", t), q[k]) << "t = " << t;
    EXPECT_EQ(At(tr, "rSFlipFlop.QI", t), qi[k]) << "t = " << t;
  }
  // Qini = true starts set: Q(0) = 1 until R resets it at 3.
  Trajectory set = RunModel(model, {{"rSFlipFlop.Qini", 1.0}});
  EXPECT_EQ(At(set, "rSFlipFlop.Q", 0), 1.0);
  EXPECT_EQ(At(set, "rSFlipFlop.QI", 0), 0.0);
  EXPECT_EQ(At(set, "rSFlipFlop.Q", 2.5), 1.0);
  EXPECT_EQ(At(set, "rSFlipFlop.Q", 3.5), 0.0);
}

// u is true on [1, 3) and [5, 7): two rising and two falling edges. Edge, FallingEdge and Change
// are true only at those instants, so counters of their outputs count 2, 2 and 4; Pre delays u
// by one event iteration, so its output equals u again once the instant has settled.
TEST(LogicalBlocksTest, PreChangeEdgeAndFallingEdgeFireAtTheirInstants) {
  Trajectory tr = RunModel(R"yaml(
model: Instants
components:
  u: {type: TimePulse, on: 1, off: 3, on2: 5, off2: 7}
  pre1: {type: Pre}
  change1: {type: Change}
  edge1: {type: Edge}
  fallingEdge: {type: FallingEdge}
  changes: {type: Counter}
  rises: {type: Counter}
  falls: {type: Counter}
connections:
  - [u.y, pre1.u]
  - [u.y, change1.u]
  - [u.y, edge1.u]
  - [u.y, fallingEdge.u]
  - [change1.y, changes.u]
  - [edge1.y, rises.u]
  - [fallingEdge.y, falls.u]
experiment: {stop: 8, interval: 0.5}
outputs: [u.y, pre1.y, changes.count, rises.count, falls.count, fallingEdge.not_u]
)yaml");
  EXPECT_EQ(At(tr, "changes.count", 8), 4.0);
  EXPECT_EQ(At(tr, "rises.count", 8), 2.0);
  EXPECT_EQ(At(tr, "falls.count", 8), 2.0);
  // Counted at the right instants: after the first rise, after the first fall.
  EXPECT_EQ(At(tr, "changes.count", 2), 1.0);
  EXPECT_EQ(At(tr, "falls.count", 4), 1.0);
  EXPECT_EQ(At(tr, "rises.count", 4), 1.0);
  for (double t : {0.5, 2.0, 4.0, 6.0, 7.5}) {
    EXPECT_EQ(At(tr, "pre1.y", t), At(tr, "u.y", t)) << "t = " << t;
    EXPECT_EQ(At(tr, "fallingEdge.not_u", t), 1.0 - At(tr, "u.y", t)) << "t = " << t;
  }
}

// u = sin(2 pi t) crosses zero at 0.5, 1, 1.5 and 2 while enable is true on [0.25, 2.25); enable
// rises and falls while u != 0, which must not count: four crossings.
TEST(LogicalBlocksTest, ZeroCrossingCountsCrossingsWhileEnabled) {
  Trajectory tr = RunModel(R"yaml(
model: Crossings
components:
  sine: {type: Sine, f: 1}
  enable: {type: TimePulse, on: 0.25, off: 2.25}
  zeroCrossing: {type: ZeroCrossing}
  crossings: {type: Counter}
connections:
  - [sine.y, zeroCrossing.u]
  - [enable.y, zeroCrossing.enable]
  - [zeroCrossing.y, crossings.u]
experiment: {stop: 3, interval: 0.05}
outputs: [crossings.count, zeroCrossing.u_pos, zeroCrossing.disable]
)yaml");
  EXPECT_EQ(At(tr, "crossings.count", 3), 4.0);
  EXPECT_EQ(At(tr, "crossings.count", 0.75), 1.0);
  EXPECT_EQ(At(tr, "zeroCrossing.u_pos", 0.3), 1.0);   // enabled and u > 0
  EXPECT_EQ(At(tr, "zeroCrossing.u_pos", 0.75), 0.0);  // u < 0
  EXPECT_EQ(At(tr, "zeroCrossing.disable", 0.1), 1.0);
  EXPECT_EQ(At(tr, "zeroCrossing.disable", 1.0), 0.0);
}

// reference = 1, bandwidth 0.5, u = 1 + sin(pi t/2): y(0) = false (u = 1 is inside the band),
// on where u falls below 0.75 (t = 2 + 2 asin(0.25)/pi), off where it rises above 1.25
// (t = 4 + 2 asin(0.25)/pi). The two-input relations switch where u crosses 1 (t = 0, 2, 4).
TEST(LogicalBlocksTest, OnOffControllerAndRelationsSwitchAtTheirCrossings) {
  Trajectory tr = RunModel(R"yaml(
model: OnOff
components:
  reference: {type: Constant, k: 1}
  u: {type: Sine, amplitude: 1, f: 0.25, offset: 1}
  onOffController: {type: OnOffController, bandwidth: 0.5}
  greater: {type: Greater}
  greaterEqual: {type: GreaterEqual}
  less: {type: Less}
  lessEqual: {type: LessEqual}
connections:
  - [reference.y, onOffController.reference]
  - [u.y, onOffController.u]
  - [u.y, greater.u1]
  - [reference.y, greater.u2]
  - [u.y, greaterEqual.u1]
  - [reference.y, greaterEqual.u2]
  - [u.y, less.u1]
  - [reference.y, less.u2]
  - [u.y, lessEqual.u1]
  - [reference.y, lessEqual.u2]
experiment: {stop: 5, tolerance: 1e-10, interval: 0.1}
outputs: [onOffController.y, greater.y, greaterEqual.y, less.y, lessEqual.y]
)yaml");
  const double shift = 2 * std::asin(0.25) / M_PI;
  // Where the controller switches: rows whose value differs from the previous row's.
  std::vector<double> switches;
  for (size_t k = 1; k < tr.t.size(); ++k) {
    if (tr.Column("onOffController.y", k) != tr.Column("onOffController.y", k - 1)) switches.push_back(tr.t[k]);
  }
  ASSERT_EQ(switches.size(), 2u);
  // Located on the interpolant at rtol 1e-10: 1e-9 s.
  EXPECT_NEAR(switches[0], 2 + shift, 1e-9);
  EXPECT_NEAR(switches[1], 4 + shift, 1e-9);
  EXPECT_EQ(At(tr, "onOffController.y", 0), 0.0);
  EXPECT_EQ(At(tr, "onOffController.y", 3), 1.0);
  // u > 1 on (0, 2), u < 1 on (2, 4).
  for (double t : {1.0, 3.0}) {
    const double above = t < 2 ? 1.0 : 0.0;
    EXPECT_EQ(At(tr, "greater.y", t), above) << "t = " << t;
    EXPECT_EQ(At(tr, "greaterEqual.y", t), above) << "t = " << t;
    EXPECT_EQ(At(tr, "less.y", t), 1 - above) << "t = " << t;
    EXPECT_EQ(At(tr, "lessEqual.y", t), 1 - above) << "t = " << t;
  }
}

// u is true on [1, 3) and [5, 7): y = t - 1 on [1, 3), 0 on [3, 5), t - 5 on [5, 7), and
// entryTime holds the last rising instant.
TEST(LogicalBlocksTest, TimerMeasuresTheTimeSinceTheInputBecameTrue) {
  Trajectory tr = RunModel(R"yaml(
model: Timing
components:
  u: {type: TimePulse, on: 1, off: 3, on2: 5, off2: 7}
  timer: {type: Timer}
connections:
  - [u.y, timer.u]
experiment: {stop: 8, interval: 0.25}
outputs: [timer.y, timer.entryTime]
)yaml");
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    double expected = 0;
    if (t > 1 && t < 3) expected = t - 1;
    if (t > 5 && t < 7) expected = t - 5;
    // The rising instants are time events, hit exactly; y = time - entryTime to rounding.
    if (std::fabs(t - 1) > 1e-12 && std::fabs(t - 3) > 1e-12 && std::fabs(t - 5) > 1e-12 && std::fabs(t - 7) > 1e-12) {
      EXPECT_NEAR(tr.Column("timer.y", k), expected, 1e-12) << "t = " << t;
    }
  }
  EXPECT_EQ(At(tr, "timer.entryTime", 0.5), 0.0);
  EXPECT_EQ(At(tr, "timer.entryTime", 4), 1.0);
  EXPECT_EQ(At(tr, "timer.entryTime", 8), 5.0);
}

// amplitude 2, offset 0.5, rising 1 s and falling 0.5 s for the full amplitude (slopes +2 and
// -4 per s). u on [1, 1.5): y rises from 0.5 to 1.5 and falls back by 1.75. u on [3, 5): y
// reaches 2.5 at 4, holds, and falls to 0.5 by 5.5.
TEST(LogicalBlocksTest, TriggeredTrapezoidRampsFromWhereItIs) {
  Trajectory tr = RunModel(R"yaml(
model: Trapezoid
components:
  u: {type: TimePulse, on: 1, off: 1.5, on2: 3, off2: 5}
  triggeredTrapezoid: {type: TriggeredTrapezoid, amplitude: 2, offset: 0.5, rising: 1, falling: 0.5}
connections:
  - [u.y, triggeredTrapezoid.u]
experiment: {stop: 6, interval: 0.05}
outputs: [triggeredTrapezoid.y, triggeredTrapezoid.T, triggeredTrapezoid.rate, triggeredTrapezoid.endValue]
)yaml");
  auto closed_form = [](double t) {
    if (t < 1) return 0.5;
    if (t < 1.5) return 0.5 + 2 * (t - 1);
    if (t < 1.75) return 1.5 - 4 * (t - 1.5);
    if (t < 3) return 0.5;
    if (t < 4) return 0.5 + 2 * (t - 3);
    if (t < 5) return 2.5;
    if (t < 5.5) return 2.5 - 4 * (t - 5);
    return 0.5;
  };
  for (size_t k = 0; k < tr.t.size(); ++k) {
    // y is piecewise linear in time. The changes of u are time events, hit exactly; the corners
    // where a ramp ends (time = T) are state events, located to ~1.5e-12 s, and the left-limit
    // row there reads the ramp that far on: 1e-11 for slopes up to 4 per s.
    EXPECT_NEAR(tr.Column("triggeredTrapezoid.y", k), closed_form(tr.t[k]), 1e-11) << "t = " << tr.t[k];
  }
  // After the fall at 1.5 the ramp ends at T = 1.75 with slope -4 towards 0.5.
  EXPECT_NEAR(At(tr, "triggeredTrapezoid.T", 1.6), 1.75, 1e-12);
  EXPECT_EQ(At(tr, "triggeredTrapezoid.rate", 1.6), -4.0);
  EXPECT_EQ(At(tr, "triggeredTrapezoid.endValue", 3.5), 2.5);
  EXPECT_NEAR(At(tr, "triggeredTrapezoid.T", 3.5), 4.0, 1e-12);
}

}  // namespace
}  // namespace momenta

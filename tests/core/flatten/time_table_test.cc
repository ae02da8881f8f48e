// The blocks that read a table in time (components/blocks.yaml): CombiTimeTable and BooleanTable,
// through timeTable() and booleanTable() (docs/FORMAT.md, "Tables"). Each table point is a time
// event: the integrator stops there, so an integral across a kink or a jump is exact to the
// solver's tolerance, and the output has the left and the right limit at a jump.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

/// The rows of `tr` at time t (two at an event that changed an output: left, then right limit).
std::vector<size_t> RowsAt(const testing::Trajectory& tr, double t) {
  std::vector<size_t> rows;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    if (std::fabs(tr.t[k] - t) < 1e-12) rows.push_back(k);
  }
  return rows;
}

// lin: a ramp to 2 at t = 1, a jump to 4 there (the time given twice), down to 0 at t = 3, held
// after (HoldLastPoint) and before (from 0). step: the same rows with ConstantSegments.
// shifted: column 3 from startTime 0.5 (offset 1 before), on a time axis scaled by 2.
// The integrator of lin has the closed form 1 + 4 = 5 from t = 3 on.
const char* kTables = R"(
model: Tables
components:
  lin: {type: CombiTimeTable, table: [[0, 0, 0], [1, 2, 5], [1, 4, 5], [3, 0, 7]], extrapolation: 1}
  step: {type: CombiTimeTable, table: [[0, 0], [1, 2], [3, 0]], smoothness: 3}
  shifted: {type: CombiTimeTable, table: [[0, 0, 0], [1, 2, 5], [3, 0, 7]], column: 3, startTime: 0.5,
            offset: 1, timeScale: 2}
  switch: {type: BooleanTable, table: [0.5, 1.5, 2.5]}
  switchOn: {type: BooleanTable, table: [1.25], startValue: true}
  area: {type: Integrator}
variables:
  slope: {}
equations:
  - slope = der(shifted.y)
connections:
  - [lin.y, area.u]
outputs: [lin.y, step.y, shifted.y, switch.y, switchOn.y, area.y, slope]
experiment: {stop: 4, interval: 0.25}
)";

double Lin(double t) { return t < 1 ? 2 * t : (t < 3 ? 4 - 2 * (t - 1) : 0); }
double Step(double t) { return t < 1 ? 0 : (t < 3 ? 2 : 0); }
/// Column 3 at x = (t - 0.5)/2 with LastTwoPoints extrapolation, plus the offset 1.
double Shifted(double t) {
  if (t < 0.5) return 1;
  const double x = (t - 0.5) / 2;
  return 1 + (x < 1 ? 5 * x : 5 + (x - 1));
}

TEST(TimeTableTest, ValuesBetweenAndAtTheTablePoints) {
  testing::Built b = testing::BuildYaml(kTables);
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    const std::vector<size_t> rows = RowsAt(tr, t);
    // At an event the first row is the left limit, the last the right limit.
    const bool left = rows.size() > 1 && k == rows.front();
    const double tl = left ? std::nextafter(t, 0.0) : t;
    // The table arithmetic in doubles: 1e-12.
    EXPECT_NEAR(tr.Column("lin.y", k), Lin(tl), 1e-12) << "t = " << t << (left ? " (left)" : "");
    EXPECT_NEAR(tr.Column("step.y", k), Step(tl), 1e-12) << "t = " << t;
    EXPECT_NEAR(tr.Column("shifted.y", k), Shifted(tl), 1e-12) << "t = " << t;
    EXPECT_EQ(tr.Column("switch.y", k), (tl >= 0.5) != (tl >= 1.5) != (tl >= 2.5) ? 1.0 : 0.0) << "t = " << t;
    EXPECT_EQ(tr.Column("switchOn.y", k), tl >= 1.25 ? 0.0 : 1.0) << "t = " << t;
    // der(shifted.y): 0 before startTime, 5/2 on the first segment, 1/2 after x = 1 (t = 2.5).
    const double slope = tl < 0.5 ? 0 : (tl < 2.5 ? 2.5 : 0.5);
    EXPECT_NEAR(tr.Column("slope", k), slope, 1e-9) << "t = " << t;
  }
  // The jump of lin at t = 1 shows as two rows: 2 then 4.
  const std::vector<size_t> at1 = RowsAt(tr, 1.0);
  ASSERT_EQ(at1.size(), 2u);
  EXPECT_EQ(tr.Column("lin.y", at1[0]), 2.0);
  EXPECT_EQ(tr.Column("lin.y", at1[1]), 4.0);
  // Time events at the points where an output kinks or jumps: 0.5 (startTime, switch), 1 (lin,
  // step), 1.25 (switchOn), 1.5 (switch), 2.5 (shifted's x = 1, switch) and 3 (lin, step).
  EXPECT_EQ(tr.stats.time_events, 6) << tr.stats.events;
}

TEST(TimeTableTest, TheIntegratorStopsAtEveryPoint) {
  testing::Built b = testing::BuildYaml(kTables);
  testing::Trajectory tr = testing::RunDefault(b);
  // The integral of lin: t^2 on [0, 1], then 1 + 4(t-1) - (t-1)^2 to 5 at t = 3, constant after.
  // IDA never steps across the kinks, so the error is the tolerance's (rtol 1e-6 by default, the
  // first step's start error included): 1e-5.
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    const double area = t < 1 ? t * t : (t < 3 ? 1 + 4 * (t - 1) - (t - 1) * (t - 1) : 5);
    EXPECT_NEAR(tr.Column("area.y", k), area, 1e-5) << "t = " << t;
  }
}

TEST(TimeTableTest, ParametersChangeOrdinatesButNotTheJumps) {
  testing::Built b = testing::BuildYaml(kTables);
  // An ordinate: the jump at t = 1 now reaches 6 (the same compiled model).
  testing::Trajectory tr = testing::RunDefault(b, {{"lin.table[3,2]", 6}});
  const std::vector<size_t> at1 = RowsAt(tr, 1.0);
  ASSERT_EQ(at1.size(), 2u);
  EXPECT_EQ(tr.Column("lin.y", at1[1]), 6.0);
  // A repeated time is a jump built into the equations: moving it needs a rebuild.
  std::string e = testing::BuildError(kTables, {{"lin.table[3,1]", 2}});
  EXPECT_EQ(e, "");  // a -p given at the build builds that table
  testing::Built b2 = testing::BuildYaml(kTables);
  EXPECT_THROW(testing::RunDefault(b2, {{"lin.table[3,1]", 2}}), ModelError);
  // Options outside LinearSegments/ConstantSegments and HoldLastPoint/LastTwoPoints are refused.
  e = testing::BuildError(R"(
model: Bad
components:
  t: {type: CombiTimeTable, table: [[0, 0], [1, 1]], extrapolation: 3}
)");
  EXPECT_NE(e.find("the extrapolation of a table is 3; valid: 1 (HoldLastPoint), 2 (LastTwoPoints)"), std::string::npos)
      << e;
}

}  // namespace
}  // namespace momenta

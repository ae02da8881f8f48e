// Tables (docs/FORMAT.md, "Tables"): a parameter whose size its value gives, read through
// interpolate(table, x[, column]) with MSL's semantics (Modelica.Math.Vectors.interpolate,
// tempInterpol1): linear between rows, linear extrapolation through the outer two rows, a one-row
// table constant. The derivative reaches index reduction, the values come from the parameter
// storage (so -p changes them without a rebuild), and a bad table is reported by name and row.

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

// y reads column 2 at time, z column 3 at time - 1; w = der(y) makes index reduction
// differentiate y = interpolate(f, time), so w is the slope of the segment time lies in.
const char* kCurve = R"(
model: TableDemo
define:
  Curve:
    parameters:
      f: {shape: [":", 3], value: [[0, 1, 2]], doc: "rows {x, y, z}"}
    variables:
      y: {}
      z: {}
      w: {}
    equations:
      - y = interpolate(f, time)
      - z = interpolate(f, time - 1, 3)
      - w = der(y)
components:
  c: {type: Curve, f: [[0, 0, 10], [1, 2, 10], [3, 0, 40]]}
  d: {type: Curve}
outputs: [c.y, c.z, c.w, d.y, d.w]
experiment: {stop: 5, interval: 0.25}
)";

/// The closed form of column 2 of c.f: 2t on [0, 1], 2 - (t - 1) on [1, 3], and the outer
/// segments extended: 2t before 0, 2 - (t - 1) after 3.
double CurveY(double t) { return t < 1 ? 2 * t : 2 - (t - 1); }
double CurveSlope(double t) { return t < 1 ? 2 : -1; }
/// Column 3 at x: 10 up to 1, then 10 + 15 (x - 1).
double CurveZ(double x) { return x < 1 ? 10 : 10 + 15 * (x - 1); }

TEST(TableTest, InterpolatesBetweenRowsAndExtrapolatesTheEnds) {
  testing::Built b = testing::BuildYaml(kCurve);
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_GT(tr.t.size(), 10u);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    const double t = tr.t[row];
    // The values are the table's arithmetic evaluated in doubles: 1e-12 covers rounding.
    EXPECT_NEAR(tr.Column("c.y", row), CurveY(t), 1e-12) << "t = " << t;
    // z at time - 1: before the table (x < 0) the first segment [0, 1] extends, constant 10.
    EXPECT_NEAR(tr.Column("c.z", row), CurveZ(t - 1), 1e-12) << "t = " << t;
    // The one-row default table is constant, with slope 0.
    EXPECT_EQ(tr.Column("d.y", row), 1.0);
    EXPECT_EQ(tr.Column("d.w", row), 0.0);
  }
  // The derivative by index reduction: exactly the segment's slope away from the kinks (at a kink
  // the output row may be either side's; IDA does not stop there in this model).
  for (size_t row = 0; row < tr.t.size(); ++row) {
    const double t = tr.t[row];
    if (std::fabs(t - 1) < 1e-9 || std::fabs(t - 3) < 1e-9) continue;
    EXPECT_NEAR(tr.Column("c.w", row), CurveSlope(t), 1e-9) << "t = " << t;
  }
}

TEST(TableTest, ParameterOverridesChangeTheTableWithoutARebuild) {
  testing::Built b = testing::BuildYaml(kCurve);
  // The same compiled model, run with the middle row's y raised from 2 to 6: the program reads
  // the table from the parameter storage, so the new value takes effect.
  testing::Trajectory tr = testing::RunDefault(b, {{"c.f[2,2]", 6}});
  for (size_t row = 0; row < tr.t.size(); ++row) {
    const double t = tr.t[row];
    const double expected = t < 1 ? 6 * t : 6 - 3 * (t - 1);
    EXPECT_NEAR(tr.Column("c.y", row), expected, 1e-12) << "t = " << t;
  }
  // An abscissa moved past its neighbour is refused by name and row, at run time too.
  std::string error = testing::BuildError(kCurve, {{"c.f[2,1]", 4}});
  EXPECT_NE(error.find("c.f (Curve): row 3 has abscissa 3, not greater than row 2's 4"), std::string::npos) << error;
}

TEST(TableTest, JacobianOfAStateReadThroughATable) {
  // der(x) = -k(x) with k(x) = x from a two-row table: the Newton iterations need
  // d/dx interpolate(), and the solution is the exponential decay x = 2 exp(-t).
  testing::Built b = testing::BuildYaml(R"(
model: Decay
define:
  Rate:
    parameters:
      k: {shape: [":", 2], value: [[0, 0], [4, 4]]}
    variables:
      x: {start: 2, fixed: true}
    equations:
      - der(x) = -interpolate(k, x)
components:
  r: {type: Rate}
outputs: [r.x]
experiment: {stop: 1, interval: 0.1}
)");
  testing::Trajectory tr = testing::RunDefault(b);
  // k(x) = x: der(x) = -x, x = 2 exp(-t); the solver's tolerance bounds the error (rtol 1e-6
  // by default, accumulated over 1 s).
  for (size_t row = 0; row < tr.t.size(); ++row) {
    EXPECT_NEAR(tr.Column("r.x", row), 2 * std::exp(-tr.t[row]), 1e-4) << "t = " << tr.t[row];
  }
}

TEST(TableTest, BadTablesAreReportedByComponentParameterAndRow) {
  const std::string base = R"yaml(
model: Bad
define:
  Curve:
    parameters:
      f: {shape: [":", 2], value: [[0, 1]]}
    variables: {y: {}}
    equations: ["y = interpolate(f, time)"]
components:
)yaml";
  std::string e = testing::BuildError(base + "  c: {type: Curve, f: [[0, 1], [2, 3], [2, 4]]}\n");
  EXPECT_NE(e.find("c.f (Curve): row 3 has abscissa 2, not greater than row 2's 2; the first column of a table must "
                   "increase strictly"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(":10:"), std::string::npos) << e;  // the line of c's value
  e = testing::BuildError(base + "  c: {type: Curve, f: [[0, 1], [2]]}\n");
  EXPECT_NE(e.find("the value of c.f (shape [:, 2]) must be a list of rows of one length, e.g. [[0, 1], [1, 2]]; "
                   "row 2 has 1 elements, row 1 has 2"),
            std::string::npos)
      << e;
  e = testing::BuildError(base + "  c: {type: Curve, f: [[0, 1, 2]]}\n");
  EXPECT_NE(e.find("the value of c.f has shape [1, 3], but it is declared with shape [:, 2]"), std::string::npos) << e;
  e = testing::BuildError(base + "  c: {type: Curve, f: [0, 1]}\n");
  EXPECT_NE(e.find("must be a list of rows"), std::string::npos) << e;
}

TEST(TableTest, InterpolateNeedsATableAndAColumnInRange) {
  auto model = [](const std::string& equation) {
    return R"(
model: Bad
define:
  Curve:
    parameters:
      f: {shape: [":", 2], value: [[0, 1]]}
      g: 2
    variables: {y: {}}
    equations: [")" + equation + R"("]
components:
  c: {type: Curve}
)";
  };
  std::string e = testing::BuildError(model("y = interpolate(g, time)"));
  EXPECT_NE(e.find("the first argument of interpolate() must name a table, found 'g'"), std::string::npos) << e;
  EXPECT_NE(e.find("(tables of Curve: f)"), std::string::npos) << e;
  e = testing::BuildError(model("y = interpolate(f, time, 3)"));
  EXPECT_NE(e.find("the column of interpolate() must be a whole number from 1 to the table's columns (2), found '3'"),
            std::string::npos)
      << e;
  e = testing::BuildError(model("y = f"));
  EXPECT_NE(e.find("'f' is a table of Curve; read it with interpolate(f, x)"), std::string::npos) << e;
  e = testing::BuildError(R"yaml(
model: Bad
variables: {y: {}}
equations: ["y = interpolate(g, time)"]
)yaml");
  EXPECT_NE(e.find("interpolate() reads a table of a component type, in its equations; the model's own equations cannot"),
            std::string::npos)
      << e;
  e = testing::BuildError(model("y = interpolate(f)"));
  EXPECT_NE(e.find("interpolate() takes 2 or 3 arguments, found 1"), std::string::npos) << e;
}

TEST(TableTest, ATableHasAtMost65535Columns) {
  // A table leaf keeps its column count in 16 bits (core/expr/expr.h, kMaxTableColumns).
  std::string row;
  for (int k = 0; k < 65536; ++k) row += k == 0 ? "0" : ", 0";
  const std::string e = testing::BuildError(R"yaml(
model: Wide
define:
  Wide:
    parameters:
      f: {shape: [":", 65536], value: [[)yaml" + row + R"yaml(]]}
    variables: {y: {}}
    equations: ["y = interpolate(f, time)"]
components:
  w: {type: Wide}
)yaml");
  EXPECT_NE(e.find("w: interpolate() reads a table with 65536 columns, more than the 65535 a table may have, in "
                   "'y = interpolate(f, time)'"),
            std::string::npos)
      << e;
}

}  // namespace
}  // namespace momenta

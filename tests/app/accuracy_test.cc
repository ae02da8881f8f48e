// `momenta accuracy`: the error falls as the tolerance tightens on a model with a closed form (a
// reference CSV written from it); the table's columns on the terminal and in its CSV; the computed
// reference when none is given; the plot; the error measure itself; and the errors by their
// messages.

#include "app/accuracy_command.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/base/error.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::ReadCsv;
using testing::ReadText;
using testing::RunMomenta;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A 1 kg mass on a 4 N/m spring released from s = 1 m: s = cos(2 t), v = -2 sin(2 t).
const char* kOscillator = R"(model: Oscillator
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: 4}
  mass: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
outputs: [mass.s, mass.v]
experiment: {stop: 2, interval: 0.01}
)";

/// The closed form every 1e-4 s: linear interpolation between its rows errs by at most
/// h^2/8 max|s''| = 5e-9, below the errors the test compares.
std::string WriteClosedForm(const TempDir& dir) {
  const std::string path = dir.File("exact.csv");
  std::ofstream f(path);
  f << "time,mass.s,mass.v\n";
  char line[96];
  for (int k = 0; k <= 20000; ++k) {
    const double t = 1e-4 * k;
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g\n", t, std::cos(2 * t), -2 * std::sin(2 * t));
    f << line;
  }
  return path;
}

class AccuracyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
      GTEST_SKIP() << "gnuplot is not installed (Debian package gnuplot-nox; scripts/setup.sh installs it)";
    }
    model_ = dir_.Write("oscillator.yaml", kOscillator);
  }
  TempDir dir_;
  std::string model_;
};

// Against the closed form, from rtol 1e-3 to 1e-8: each decade's error is at most 3 times the
// looser one's (BDF's error is not strictly monotone in the tolerance, but does not grow by
// more than that), and over the five decades it falls by more than 1000.
TEST_F(AccuracyTest, ErrorFallsAsTheToleranceTightensAgainstTheClosedForm) {
  const std::string table = dir_.File("table.csv");
  const CliResult r = RunMomenta({"accuracy", model_, "--rtol", "1e-3:1e-8", "--reference", WriteClosedForm(dir_),
                                  "--table", table, "-o", dir_.File("wp.svg")},
                                 dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "reference: the result file")) << r.out;
  const testing::Csv csv = ReadCsv(table);
  ASSERT_EQ(csv.rows.size(), 6u);
  const size_t rtol = csv.Index("rtol"), error = csv.Index("error");
  for (size_t k = 0; k < csv.rows.size(); ++k) {
    EXPECT_NEAR(csv.rows[k][rtol], std::pow(10.0, -3.0 - static_cast<double>(k)), 1e-20);
    EXPECT_GT(csv.rows[k][error], 0);
    if (k > 0) {
      EXPECT_LE(csv.rows[k][error], 3 * csv.rows[k - 1][error]) << "rtol " << csv.rows[k][rtol];
    }
  }
  EXPECT_LT(csv.rows.back()[error], csv.rows.front()[error] / 1000);
}

// The table's columns, on the terminal and in the CSV; the computed reference is said; the plot
// is an SVG document.
TEST_F(AccuracyTest, TableColumnsAndTheComputedReference) {
  const std::string table = dir_.File("table.csv"), svg = dir_.File("wp.svg");
  const CliResult r = RunMomenta({"accuracy", model_, "--rtol", "1e-4:1e-6", "--table", table, "-o", svg}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "reference: a run at rtol 1e-08 (no --reference given)")) << r.out;
  for (const char* column : {"rtol", "error", "time [ms]", "steps", "residuals"}) {
    EXPECT_TRUE(Contains(r.out, column)) << column << "\n" << r.out;
  }
  EXPECT_TRUE(Contains(ReadText(table).substr(0, 80), "rtol,error,wall_time_s,steps,residual_evals,jacobian_evals"));
  EXPECT_EQ(ReadCsv(table).rows.size(), 3u);
  const std::string text = ReadText(svg);
  EXPECT_TRUE(Contains(text, "<svg")) << text.substr(0, 200);
  EXPECT_TRUE(Contains(text, "residual evaluations"));
}

TEST_F(AccuracyTest, WithReportWritesThePage) {
  const std::string html = dir_.File("acc.html");
  const CliResult r =
      RunMomenta({"accuracy", model_, "--rtol", "1e-4:1e-5", "-o", dir_.File("wp.svg"), "--report", html}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = ReadText(html);
  EXPECT_TRUE(Contains(page, "work-precision")) << page.size();
  EXPECT_TRUE(Contains(page, "rtol 0.0001"));
}

TEST_F(AccuracyTest, BadRangeIsAUsageError) {
  const CliResult r = RunMomenta({"accuracy", model_, "--rtol", "1e-3:abc"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "--rtol 1e-3:abc: 'abc' is not a tolerance from 1e-14 to below 1")) << r.err;
}

TEST_F(AccuracyTest, ReferenceWithoutTheOutputsIsAUsageError) {
  const std::string ref = dir_.Write("other.csv", "time,x.y\n0,1\n1,2\n");
  const CliResult r = RunMomenta({"accuracy", model_, "--reference", ref}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "has none of the model's outputs (its columns: x.y; the model's outputs: mass.s, mass.v)"))
      << r.err;
}

TEST_F(AccuracyTest, PlotNeedsSvgOrPng) {
  const CliResult r = RunMomenta({"accuracy", model_, "-o", dir_.File("wp.pdf")}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "wp.pdf: the plot is written as SVG or PNG")) << r.err;
}

// ---- the pieces ---------------------------------------------------------------------------------

TEST(ToleranceRangeTest, DecadesFromTheLooseToTheTight) {
  const std::vector<double> range = ToleranceRange("1e-6:1e-3");
  ASSERT_EQ(range.size(), 4u);
  EXPECT_DOUBLE_EQ(range.front(), 1e-3);
  EXPECT_NEAR(range.back(), 1e-6, 1e-21);
  EXPECT_EQ(ToleranceRange("1e-4").size(), 1u);
  EXPECT_THROW(ToleranceRange("1e-16:1e-3"), UsageError);
  EXPECT_THROW(ToleranceRange("2"), UsageError);
}

// The error skips event rows and interpolates the reference: a run that matches the reference
// at every row but an event's has error 0; a shifted value shows relative to the column's scale.
TEST(ResultErrorTest, InterpolatesTheReferenceAndSkipsEventRows) {
  ResultTable ref{{"x"}, {0, 1, 1, 2}, {{0, 10, -10, -20}}};
  ResultTable run{{"x"}, {0.5, 1, 1, 1.5}, {{5, 999, 999, -15}}};
  EXPECT_DOUBLE_EQ(ResultError(run, {0}, ref, {0}), 0.0);
  run.values[0][3] = -14;  // 1 off; the column's largest |ref| is 20
  EXPECT_DOUBLE_EQ(ResultError(run, {0}, ref, {0}), 1.0 / 20);
}

}  // namespace
}  // namespace momenta

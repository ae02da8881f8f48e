// Initialisation of a constrained system: the Cartesian pendulum x^2 + y^2 = L^2 (index 3) has
// two degrees of freedom, so two fixed start values (a position and a velocity) determine it.
// More fixed values are redundant: consistent ones (x and y on the circle; vx and vy with
// x vx + y vy = 0) are left out with a note and the motion is the same; inconsistent ones are an
// error naming them and the constraint. Fewer are completed by start values, with a warning
// giving the degrees of freedom and naming the variables.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/base/error.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kL = 1.5, kTheta0 = 0.4, kSpeed = 0.7;

/// Released at angle theta0 with speed kSpeed along the circle; `fixed` lists the variables
/// whose start values are fixed; `y0`/`vy0` override the start values of y and vy.
std::string Pendulum(const std::string& fixed, const std::string& y0 = "-L*cos(theta0)",
                     const std::string& vy0 = "v0*sin(theta0)") {
  auto var = [&](const std::string& name, const std::string& start) {
    const bool f = (" " + fixed + " ").find(" " + name + " ") != std::string::npos;
    return "      " + name + ": {start: " + start + (f ? ", fixed: true" : "") + "}\n";
  };
  std::ostringstream y;
  y.precision(17);
  y << "model: Pendulum\nparameters: {L: " << kL << ", theta0: " << kTheta0 << ", v0: " << kSpeed << "}\n";
  y << "define:\n  Pendulum:\n    parameters: {L: 1, g: 9.81, m: 1, theta0: 0.1, v0: 0}\n    variables:\n";
  y << var("x", "L*sin(theta0)") << var("y", y0) << var("vx", "v0*cos(theta0)") << var("vy", vy0);
  y << "      F: {start: m*g}\n";
  y << "    equations:\n      - der(x) = vx\n      - der(y) = vy\n      - m*der(vx) = -x*F/L\n"
       "      - m*der(vy) = -y*F/L - m*g\n      - x^2 + y^2 = L^2\n";
  y << "components:\n  p: {type: Pendulum, L: L, theta0: theta0, v0: v0}\n"
       "experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}\noutputs: [p.x, p.y, p.vx, p.vy, p.F]\n";
  return y.str();
}

/// The error of initialising (and running) a model that builds; empty when it runs.
std::string RunError(const Built& b) {
  try {
    testing::RunDefault(b);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

double WorstDifference(const Trajectory& a, const Trajectory& b) {
  EXPECT_EQ(a.t.size(), b.t.size());
  double worst = 0;
  for (size_t k = 0; k < a.t.size() && k < b.t.size(); ++k) {
    for (size_t j = 0; j < a.names.size(); ++j) worst = std::max(worst, std::fabs(a.values[k][j] - b.values[k][j]));
  }
  return worst;
}

const char* const kConstraint = "    p (Pendulum, test.yaml:19:6): 'x^2 + y^2 = L^2'\n";

TEST(ConstrainedInit, TwoFixedValuesDetermineThePendulum) {
  Built b = testing::BuildYaml(Pendulum("x vx"));
  EXPECT_TRUE(b.report.notes.empty());
  EXPECT_TRUE(b.report.warnings.empty()) << ::testing::PrintToString(b.report.warnings);
  Trajectory tr = testing::RunDefault(b);
  // y and vy follow from the constraint and its derivative (y on the lower branch, its guess).
  EXPECT_NEAR(tr.Column("p.y", 0), -kL * std::cos(kTheta0), 1e-12);
  EXPECT_NEAR(tr.Column("p.vy", 0), kSpeed * std::sin(kTheta0), 1e-12);
}

TEST(ConstrainedInit, ConsistentRedundantPositionIsANoteAndChangesNothing) {
  Built reference = testing::BuildYaml(Pendulum("x vx"));
  Built b = testing::BuildYaml(Pendulum("x y vx"));
  ASSERT_EQ(b.report.notes.size(), 1u);
  EXPECT_EQ(b.report.notes[0], std::string("initial conditions: the fixed start value of p.y (test.yaml:19:6) is "
                                           "redundant: it follows from\n"
                                           "    fixed start value of p.x (test.yaml:19:6)\n") +
                                   kConstraint +
                                   "  It is left out of the initial system; initialisation checks that it holds.");
  EXPECT_TRUE(b.report.warnings.empty()) << ::testing::PrintToString(b.report.warnings);
  EXPECT_LT(WorstDifference(testing::RunDefault(reference), testing::RunDefault(b)), 1e-9);
}

TEST(ConstrainedInit, ConsistentRedundantVelocityIsANoteAndChangesNothing) {
  // vx and vy both fixed, with x vx + y vy = 0 (the constraint's derivative).
  Built reference = testing::BuildYaml(Pendulum("x vx"));
  Built b = testing::BuildYaml(Pendulum("x vx vy"));
  ASSERT_EQ(b.report.notes.size(), 1u);
  EXPECT_EQ(b.report.notes[0].rfind("initial conditions: the fixed start value of p.vy (test.yaml:19:6) is redundant: "
                                    "it follows from\n"
                                    "    fixed start value of p.x (test.yaml:19:6)\n"
                                    "    fixed start value of p.vx (test.yaml:19:6)\n",
                                    0),
            0u)
      << b.report.notes[0];
  EXPECT_NE(b.report.notes[0].find("'x^2 + y^2 = L^2', differentiated once\n"), std::string::npos) << b.report.notes[0];
  EXPECT_LT(WorstDifference(testing::RunDefault(reference), testing::RunDefault(b)), 1e-9);
}

TEST(ConstrainedInit, InconsistentPositionIsAnErrorNamingTheConstraint) {
  // y = -1.2 is not on the circle through x = L sin(theta0): y = -L cos(theta0) = -1.3816…
  Built b = testing::BuildYaml(Pendulum("x y vx", "-1.2"));
  std::ostringstream off;
  off << -kL * std::cos(kTheta0) - (-1.2);
  EXPECT_EQ(RunError(b), "at initialisation: the initial conditions contradict each other: the fixed start value of "
                         "p.y (test.yaml:19:6) is off by " +
                             off.str() +
                             " at the solution of the others; it follows from\n"
                             "    fixed start value of p.x (test.yaml:19:6)\n" +
                             kConstraint + "  Make the fixed start values consistent, or set fixed: false on it.");
}

TEST(ConstrainedInit, InconsistentVelocityIsAnError) {
  // vy = 0 while the pendulum moves along the circle: x vx + y vy = 0 does not hold.
  Built b = testing::BuildYaml(Pendulum("x vx vy", "-L*cos(theta0)", "0"));
  std::string err = RunError(b);
  std::ostringstream off;
  off << kSpeed * std::sin(kTheta0) - 0;
  EXPECT_EQ(err.rfind("at initialisation: the initial conditions contradict each other: the fixed start value of "
                      "p.vy (test.yaml:19:6) is off by " + off.str() + " at the solution of the others",
                      0),
            0u)
      << err;
  EXPECT_NE(err.find("'x^2 + y^2 = L^2', differentiated once\n"), std::string::npos) << err;
}

TEST(ConstrainedInit, NothingFixedTakesPositionAndVelocityWithAWarning) {
  Built b = testing::BuildYaml(Pendulum(""));
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_EQ(b.report.warnings[0],
            "initial conditions: the model has 2 degrees of freedom and its fixed start values and initial equations "
            "determine 0; the start values of p.x, p.vx are used as well (add fixed: true to say so)");
  EXPECT_EQ(b.model->defaulted_starts, (std::vector<std::string>{"p.x", "p.vx"}));
  EXPECT_LT(WorstDifference(testing::RunDefault(testing::BuildYaml(Pendulum("x vx"))), testing::RunDefault(b)), 1e-9);
}

TEST(ConstrainedInit, CliPrintsTheNoteAndExitsWithOneOnAContradiction) {
  testing::TempDir dir;
  dir.Write("ok.yaml", Pendulum("x y vx"));
  dir.Write("bad.yaml", Pendulum("x y vx", "-1.2"));
  testing::CliResult check = testing::RunMomenta({"check", "ok.yaml"}, dir.path());
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("note: initial conditions: the fixed start value of p.y (ok.yaml:19:6) is redundant"),
            std::string::npos)
      << check.out;
  testing::CliResult ok = testing::RunMomenta({"simulate", "ok.yaml", "-o", "-", "-q"}, dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.err.find("ok.yaml: note: initial conditions: the fixed start value of p.y"), std::string::npos) << ok.err;
  testing::CliResult bad = testing::RunMomenta({"simulate", "bad.yaml", "-o", "-"}, dir.path());
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_NE(bad.err.find("bad.yaml: simulation failed at initialisation: the initial conditions contradict each "
                         "other: the fixed start value of p.y (bad.yaml:19:6)"),
            std::string::npos)
      << bad.err;
  EXPECT_EQ(bad.err.find("note:"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace momenta

// Linearisation (solver/linearization.h, `momenta linearize`): A, B, C, D against closed forms
// (a mass-spring-damper; the Cartesian pendulum at rest, index 3 reduced; a nonlinear pendulum at
// a time after a simulation), B, C and D of a model with inputs and outputs, and against finite
// differences of simulations of a nonlinear model; the JSON and MAT files; the errors by their
// messages.

#include "solver/linearization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "app/mat_file.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::ReadText;
using testing::RunMomenta;
using testing::SourcePath;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Builds `yaml` for `spec` with `overrides`, brings it to t and linearises it there.
Linearization LinearizeYaml(const std::string& yaml, const LinearizationSpec& spec, double t = 0,
                            const ParameterOverrides& overrides = {}) {
  ModelSpec model = LoadModelString(yaml, "test.yaml");
  BuildOptions options(overrides);
  PrepareLinearizationBuild(spec, &options);
  BuildReport report;
  auto built = BuildModel(model, BuiltinLibrary(), options, &report);
  ModelState state(built);
  state.SetParameters(report.overrides);
  SimulationOptions opt = OptionsFromExperiment(built->experiment);
  SolverStats stats;
  const RunPoint point = SimulateTo(&state, opt, t, [](double, const std::vector<double>&) {}, &stats);
  return Linearize(state, point.t, point.y, point.yp, ResolveLinearizationColumns(*built, report, spec));
}

size_t IndexOf(const std::vector<std::string>& names, const std::string& name) {
  for (size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return k;
  }
  ADD_FAILURE() << "no " << name << " among " << ::testing::PrintToString(names);
  return 0;
}

/// A mass on a spring and a damper to a wall, pushed by a force whose signal input f is left
/// open; a gain whose input u is left open too. m = 2 kg, c = 8 N/m, d = 0.4 N.s/m, k = 3.
const char* kDrivenOscillator = R"(model: DrivenOscillator
parameters: {m: 2, c: 8, d: 0.4, k: 3}
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: c}
  damper: {type: Damper, d: d}
  mass: {type: Mass, m: m, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  force: {type: Force}
  gain: {type: Gain, k: k}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [wall.flange, damper.flange_a]
  - [damper.flange_b, mass.flange_a]
  - [force.flange, mass.flange_b]
outputs: [mass.s, mass.v, gain.y]
)";

/// The state that is the position (mass.s or damper.s_rel, equal here: the wall is at 0) and the
/// one that is the velocity.
std::pair<size_t, size_t> PositionAndVelocity(const Linearization& lin) {
  EXPECT_EQ(lin.states.size(), 2u) << ::testing::PrintToString(lin.states);
  const bool s_first = lin.states[0] == "mass.s" || lin.states[0] == "damper.s_rel";
  return s_first ? std::pair<size_t, size_t>{0, 1} : std::pair<size_t, size_t>{1, 0};
}

// A and the eigenvalues are exact up to rounding (one LU of a 2 x 2 system's matrices): 1e-12.
TEST(LinearizeTest, MassSpringDamperAIsTheClosedForm) {
  const Linearization lin = LinearizeYaml(kDrivenOscillator, {});
  const auto [s, v] = PositionAndVelocity(lin);
  EXPECT_NEAR(lin.A(s, s), 0.0, 1e-12);
  EXPECT_NEAR(lin.A(s, v), 1.0, 1e-12);
  EXPECT_NEAR(lin.A(v, s), -8.0 / 2, 1e-12);  // -c/m
  EXPECT_NEAR(lin.A(v, v), -0.4 / 2, 1e-12);  // -d/m
  // lambda = -d/2m ± i sqrt(c/m - (d/2m)^2)
  ASSERT_EQ(lin.eigenvalues.size(), 2u);
  for (const auto& lambda : lin.eigenvalues) {
    EXPECT_NEAR(lambda.real(), -0.1, 1e-12);
    EXPECT_NEAR(std::fabs(lambda.imag()), std::sqrt(4 - 0.01), 1e-12);
  }
}

// B, C and D: dv/dt = ... + f/m; the outputs s and v are states (C rows e_s, e_v; central
// differences of linear outputs: 1e-9); gain.y = k u (D = k), with no path from f.
TEST(LinearizeTest, InputsAndOutputsGiveBCAndD) {
  const Linearization lin = LinearizeYaml(kDrivenOscillator, {});
  const auto [s, v] = PositionAndVelocity(lin);
  ASSERT_EQ(lin.inputs, (std::vector<std::string>{"force.f", "gain.u"}));
  ASSERT_EQ(lin.outputs, (std::vector<std::string>{"mass.s", "mass.v", "gain.y"}));
  EXPECT_NEAR(lin.B(s, 0), 0.0, 1e-12);
  EXPECT_NEAR(lin.B(v, 0), 1 / 2.0, 1e-12);
  EXPECT_NEAR(lin.B(v, 1), 0.0, 1e-12);
  EXPECT_NEAR(lin.C(0, s), 1.0, 1e-9);
  EXPECT_NEAR(lin.C(0, v), 0.0, 1e-9);
  EXPECT_NEAR(lin.C(1, v), 1.0, 1e-9);
  EXPECT_NEAR(lin.C(2, s), 0.0, 1e-9);
  EXPECT_NEAR(lin.D(2, 1), 3.0, 1e-9);
  EXPECT_NEAR(lin.D(2, 0), 0.0, 1e-9);
  EXPECT_NEAR(lin.D(0, 0), 0.0, 1e-9);
}

// -u chooses the inputs and their order and sets the operating value; -y chooses the outputs.
TEST(LinearizeTest, ChosenInputsAndOutputsInTheirOrder) {
  LinearizationSpec spec;
  spec.inputs = {{"gain.u", 2.0}};
  spec.outputs = {"gain.y", "spring.f"};
  const Linearization lin = LinearizeYaml(kDrivenOscillator, spec);
  const auto [s, v] = PositionAndVelocity(lin);
  ASSERT_EQ(lin.inputs, std::vector<std::string>{"gain.u"});
  ASSERT_EQ(lin.outputs, (std::vector<std::string>{"gain.y", "spring.f"}));
  EXPECT_DOUBLE_EQ(lin.u[0], 2.0);
  EXPECT_NEAR(lin.y[0], 6.0, 1e-12);    // k u
  EXPECT_NEAR(lin.D(0, 0), 3.0, 1e-9);  // d(gain.y)/d(gain.u)
  EXPECT_NEAR(lin.C(1, s), 8.0, 1e-7);  // spring.f = c s
  EXPECT_NEAR(lin.C(1, v), 0.0, 1e-9);
}

// The Cartesian pendulum (index 3: the constraint differentiated twice, dummy derivatives) at
// rest at the bottom: eigenvalues ±i sqrt(g/L) (L = 2 m: 2.2147 rad/s), exact up to rounding.
TEST(LinearizeTest, CartesianPendulumAtRestHasEigenvaluesOfTheSmallOscillation) {
  const Linearization lin = LinearizeYaml(ReadText(SourcePath("models/pendulum_cartesian.yaml")), {}, 0,
                                          {{"theta0", 0.0}, {"L", 2.0}});
  ASSERT_EQ(lin.states.size(), 2u) << ::testing::PrintToString(lin.states);
  ASSERT_EQ(lin.eigenvalues.size(), 2u);
  for (const auto& lambda : lin.eigenvalues) {
    EXPECT_NEAR(lambda.real(), 0.0, 1e-9);
    EXPECT_NEAR(std::fabs(lambda.imag()), std::sqrt(9.81 / 2), 1e-9);
  }
}

/// A pendulum in its angle, J der(w) = -m g L sin(phi) - d w + tau, with its torque input tau
/// open (`tau: {}` leaves it; the `Driven` model drives it with a constant for simulations).
const char* kAnglePendulumTypes = R"(define:
  AnglePendulum:
    parameters:
      J: {value: 0.5}
      m: {value: 1}
      L: {value: 0.5}
      g: {value: 9.81}
      d: {value: 0.3}
      phi0: {value: 1.2}
      w0: {value: 0}
    connectors:
      tau: {type: RealInput}
    variables:
      phi: {start: phi0, fixed: true}
      w: {start: w0, fixed: true}
    equations:
      - der(phi) = w
      - J*der(w) = -m*g*L*sin(phi) - d*w + tau
)";

std::string OpenPendulum() {
  return std::string("model: Open\n") + kAnglePendulumTypes +
         "components:\n  p: {type: AnglePendulum}\noutputs: [p.phi, p.w]\nexperiment: {stop: 2, tolerance: 1e-10}\n";
}

std::string DrivenPendulum() {
  return std::string("model: Driven\nparameters: {phi0: 1.2, w0: 0, tau: 0}\n") + kAnglePendulumTypes +
         "components:\n  p: {type: AnglePendulum, phi0: phi0, w0: w0}\n  torque: {type: Constant, k: tau}\n"
         "connections:\n  - [torque.y, p.tau]\noutputs: [p.phi, p.w]\n";
}

// After a simulation to t = 0.7 s the pendulum is where the run left it: A is the closed form at
// that angle, [[0, 1], [-(m g L / J) cos(phi), -d / J]].
TEST(LinearizeTest, AfterASimulationAIsTheClosedFormWhereTheRunEnds) {
  const Linearization lin = LinearizeYaml(OpenPendulum(), {}, 0.7);
  EXPECT_DOUBLE_EQ(lin.t, 0.7);
  const size_t phi = IndexOf(lin.states, "p.phi"), w = IndexOf(lin.states, "p.w");
  const double angle = lin.x[phi];
  EXPECT_GT(std::fabs(angle - 1.2), 0.1);  // it has moved
  EXPECT_NEAR(lin.A(phi, w), 1.0, 1e-12);
  EXPECT_NEAR(lin.A(w, phi), -(9.81 * 0.5 / 0.5) * std::cos(angle), 1e-10);
  EXPECT_NEAR(lin.A(w, w), -0.3 / 0.5, 1e-12);
  EXPECT_NEAR(lin.B(w, 0), 1 / 0.5, 1e-12);
}

/// State at time tau of the driven pendulum started at (phi0, w0) with torque u.
std::vector<double> StateAt(const testing::Built& b, double tau, double phi0, double w0, double u) {
  SimulationOptions opt;
  opt.stop = tau;
  opt.interval = tau;
  opt.rtol = 1e-11;
  const testing::Trajectory run = testing::Run(b, opt, {{"phi0", phi0}, {"w0", w0}, {"tau", u}});
  return {run.values.back()[run.Index("p.phi")], run.values.back()[run.Index("p.w")]};
}

// Against simulations of the nonlinear model: a state (or input) perturbed by ±delta moves the
// state at tau by Phi(tau) e_j (by the input: Gamma(tau)), with Phi = I + A tau + A^2 tau^2 / 2 +
// O(tau^3) (A is constant to first order here: w0 = 0, so dA/dt = 0 at the start) and
// Gamma = B tau + A B tau^2 / 2 + O(tau^3). tau = 1e-3 s, delta = 1e-4, rtol 1e-11: the
// neglected terms are about |A|^3 tau^3 / 6 ~ 1e-7, the runs' error over 2 delta about 1e-7.
TEST(LinearizeTest, AgreesWithFiniteDifferencesOfSimulations) {
  const Linearization lin = LinearizeYaml(OpenPendulum(), {});
  const size_t phi = IndexOf(lin.states, "p.phi"), w = IndexOf(lin.states, "p.w");
  const testing::Built b = testing::BuildYaml(DrivenPendulum());
  const double tau = 1e-3, delta = 1e-4;
  const double a[2][2] = {{lin.A(phi, phi), lin.A(phi, w)}, {lin.A(w, phi), lin.A(w, w)}};
  auto times_a = [&a](const std::vector<double>& col) {
    return std::vector<double>{a[0][0] * col[0] + a[0][1] * col[1], a[1][0] * col[0] + a[1][1] * col[1]};
  };
  // tau M col + tau^2/2 A M col: the first two terms of the perturbation's move.
  auto move = [&](const std::vector<double>& m_col) {
    const std::vector<double> a_col = times_a(m_col);
    return std::vector<double>{tau * m_col[0] + tau * tau / 2 * a_col[0], tau * m_col[1] + tau * tau / 2 * a_col[1]};
  };
  // The states' columns: (Phi - I) e_j = tau A e_j + tau^2/2 A^2 e_j.
  for (int j = 0; j < 2; ++j) {
    const std::vector<double> e = {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0};
    const std::vector<double> plus = StateAt(b, tau, 1.2 + delta * e[0], delta * e[1], 0);
    const std::vector<double> minus = StateAt(b, tau, 1.2 - delta * e[0], -delta * e[1], 0);
    const std::vector<double> expected = move(times_a(e));
    for (int r = 0; r < 2; ++r) {
      EXPECT_NEAR((plus[r] - minus[r]) / (2 * delta) - e[r], expected[r], 1e-6) << "row " << r << ", column " << j;
    }
  }
  // The input's column: Gamma = tau B + tau^2/2 A B.
  const std::vector<double> plus = StateAt(b, tau, 1.2, 0, delta), minus = StateAt(b, tau, 1.2, 0, -delta);
  const std::vector<double> expected = move({lin.B(phi, 0), lin.B(w, 0)});
  for (int r = 0; r < 2; ++r) {
    EXPECT_NEAR((plus[r] - minus[r]) / (2 * delta), expected[r], 1e-6) << "row " << r;
  }
}

// ---- the command ----------------------------------------------------------------------------------

class LinearizeCliTest : public ::testing::Test {
 protected:
  std::string Model() const { return dir_.Write("oscillator.yaml", kDrivenOscillator); }
  TempDir dir_;
};

TEST_F(LinearizeCliTest, JsonHasTheNamesAndMatrices) {
  const CliResult r = RunMomenta({"linearize", Model()}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* key : {"\"states\": [", "\"inputs\": [\"force.f\", \"gain.u\"]",
                          "\"outputs\": [\"mass.s\", \"mass.v\", \"gain.y\"]", "\"A\": [", "\"B\": [", "\"C\": [",
                          "\"D\": [", "\"eigenvalues\": ["}) {
    EXPECT_TRUE(Contains(r.out, key)) << key << "\n" << r.out;
  }
  EXPECT_TRUE(Contains(r.out, "-4")) << r.out;  // -c/m in A
}

TEST_F(LinearizeCliTest, MatFileHoldsDslinsMatrices) {
  std::string why;
  if (!HaveMat(&why)) GTEST_SKIP() << why;
  const std::string mat = dir_.File("lin.mat");
  const CliResult r = RunMomenta({"linearize", Model(), "-y", "gain.y", "-o", mat}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "2 states, 2 inputs, 1 output")) << r.out;
  MatFile file(mat);
  ASSERT_TRUE(file.ok());
  const auto abcd = file.Read("ABCD");
  ASSERT_NE(abcd, nullptr);
  EXPECT_EQ(abcd->rows, 3u);  // nx + ny
  EXPECT_EQ(abcd->cols, 4u);  // nx + nu
  // D = [0, k] in the last row, stored column by column.
  const auto* v = static_cast<const double*>(abcd->data);
  EXPECT_NEAR(v[3 * 3 + 2], 3.0, 1e-9);
  const auto names = file.Read("xuyName");
  ASSERT_NE(names, nullptr);
  EXPECT_EQ(names->rows, 5u);
  const auto nx = file.Read("nx");
  ASSERT_NE(nx, nullptr);
  EXPECT_EQ(static_cast<const double*>(nx->data)[0], 2.0);
}

TEST_F(LinearizeCliTest, UnknownInputIsAUsageErrorListingTheInputs) {
  const CliResult r = RunMomenta({"linearize", Model(), "-u", "force.x"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "-u force.x")) << r.err;
  EXPECT_TRUE(Contains(r.err, "its unconnected inputs: force.f, gain.u")) << r.err;
}

TEST_F(LinearizeCliTest, UnknownOutputIsAUsageErrorWithASuggestion) {
  const CliResult r = RunMomenta({"linearize", Model(), "-y", "mass.vv"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "-y mass.vv: DrivenOscillator has no variable mass.vv")) << r.err;
  EXPECT_TRUE(Contains(r.err, "did you mean")) << r.err;
  EXPECT_TRUE(Contains(r.err, "mass.v")) << r.err;
}

TEST_F(LinearizeCliTest, TimeBeyondTheStopIsAUsageError) {
  const CliResult r = RunMomenta({"linearize", Model(), "--at", "20"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "--at 20: beyond the stop time 1 s of the experiment")) << r.err;
}

TEST_F(LinearizeCliTest, BadInputValueIsAUsageError) {
  const CliResult r = RunMomenta({"linearize", Model(), "-u", "gain.u=abc"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "-u gain.u=abc: 'abc' is not a number")) << r.err;
}

// Without linearize, an open input stays an error (the build holds inputs only when asked).
TEST_F(LinearizeCliTest, SimulateStillRefusesAnOpenInput) {
  const CliResult r = RunMomenta({"simulate", Model(), "-q"}, dir_.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, "force.f")) << r.err;
}

}  // namespace
}  // namespace momenta

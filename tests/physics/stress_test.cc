// The numerical stress suite's outcomes (bench/stress/stress.py, bench/RESULTS.md), the fast ones:
// a 1e12 N/m spring-damper, a 1e-9 mass ratio, a sliding mode, simultaneous impacts, and the
// message when the cost explodes (a fast undamped oscillation, a mechanism at its singular
// configuration). Each runs the real CLI.

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

/// A 1 kg mass on a spring c [N/m] to ground, pushed by F = c * 1 mm from rest at s = 0: its
/// static deflection is 1 mm whatever c. `damper` gives a SpringDamper with d [N.s/m].
std::string PushedSpring(const std::string& c, const std::string& damper) {
  const std::string spring = damper.empty() ? "{type: Spring, c: c}" : "{type: SpringDamper, c: c, d: " + damper + "}";
  return R"(model: PushedSpring
parameters:
  c: {value: )" + c + R"(, unit: N/m}
components:
  ground: {type: Fixed}
  spring: )" + spring + R"(
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  push: {type: ConstantForce, f_constant: c*1e-3}
connections:
  - [ground.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [push.flange, mass.flange_b]
experiment: {start: 0, stop: 0.1, interval: 1e-3}
outputs: [mass.s]
)";
}

/// "N steps" from the run's summary; -1 when absent.
long Steps(const std::string& summary) {
  std::smatch m;
  if (!std::regex_search(summary, m, std::regex(R"((\d+) steps, )"))) return -1;
  return std::stol(m[1]);
}

class StressTest : public ::testing::Test {
 protected:
  CliResult Simulate(const std::string& name, const std::string& yaml, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"simulate", dir_.Write(name, yaml), "-o", dir_.File("out.csv")};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunMomenta(args, dir_.path());
  }
  testing::Csv Rows() { return testing::ReadCsv(dir_.File("out.csv")); }
  TempDir dir_;
};

// A 1e12 N/m spring with damping ratio 0.5 (d = 2 * 0.5 * sqrt(c m) = 1e6 N.s/m): its mode decays
// at 5e5 1/s, so after 1e-4 s (e^-50) the mass rests at F/c = 1 mm. BDF steps over the decayed
// mode: a few hundred steps for the run (the bench measured 308), where following an undamped
// 1e6 rad/s oscillation for 0.1 s takes a million.
TEST_F(StressTest, StiffSpringDamperFinishesAtTheStaticDeflectionCheaply) {
  CliResult r = Simulate("stiff.yaml", PushedSpring("1e12", "1e6"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const testing::Csv csv = Rows();
  ASSERT_EQ(csv.rows.size(), 101u);
  for (const auto& row : csv.rows) {
    if (row[0] < 1e-4) continue;
    // rtol 1e-6 (the default) of the deflection.
    EXPECT_NEAR(row[1], 1e-3, 1e-9) << "t = " << row[0];
  }
  const long steps = Steps(r.out);
  EXPECT_GT(steps, 0) << r.out;
  EXPECT_LT(steps, 2000) << r.out;
}

// A 1e-9 kg mass on a 1 N/m spring (its own mode at 3.2e4 rad/s) riding a 1 kg mass on a 1 Hz
// spring released from 1 m: the heavy mass moves as cos(2 pi t) up to O(1e-9) m, and the light
// one follows it within m a / c = 1e-9 * 40 / 1 = 4e-8 m. The error bound 1e-4 m is the global
// error of two periods at rtol 1e-6 with margin (the bench measured 4.5e-6 undamped, 1.9e-5
// damped); the light mass's mode neither breaks the run nor makes it dear.
TEST_F(StressTest, MassRatioOfOneInABillionFollowsTheHeavyMass) {
  for (const char* d : {"0", "6.32e-5"}) {  // undamped; critically damped, 2 sqrt(c m)
    CliResult r = Simulate("ratio.yaml", std::string(R"(model: MassRatio
components:
  ground: {type: Fixed}
  spring: {type: Spring, c: 39.47841760435743}
  heavy: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  link: {type: SpringDamper, c: 1, d: )") + d + R"(}
  light: {type: Mass, m: 1e-9, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [ground.flange, spring.flange_a]
  - [spring.flange_b, heavy.flange_a]
  - [heavy.flange_b, link.flange_a]
  - [link.flange_b, light.flange_a]
experiment: {start: 0, stop: 2, interval: 0.01}
outputs: [heavy.s, light.s]
)");
    ASSERT_EQ(r.exit_code, 0) << "d = " << d << ": " << r.err;
    const testing::Csv csv = Rows();
    ASSERT_EQ(csv.rows.size(), 201u);
    for (const auto& row : csv.rows) {
      EXPECT_NEAR(row[1], std::cos(2 * M_PI * row[0]), 1e-4) << "d = " << d << ", t = " << row[0];
      EXPECT_NEAR(row[2], row[1], 1e-6) << "d = " << d << ", t = " << row[0];
    }
    EXPECT_LT(Steps(r.out), 50000) << r.out;
  }
}

// Coulomb friction as a sign: a mass sliding at 1 m/s against 1 N stops at t = 1 s, where each
// branch pushes the velocity back across zero. The run ends there with a named chattering error
// (exit 3), not a hang, and keeps the rows up to t = 1 s and the left limit there.
TEST_F(StressTest, SlidingModeEndsWithTheChatteringMessage) {
  CliResult r = Simulate("slide.yaml", R"(model: SignFriction
define:
  Coulomb:
    connectors: {flange: Flange}
    parameters: {F: {value: 1, unit: N}}
    variables: {v: {unit: m/s}}
    equations:
      - v = der(flange.s)
      - flange.f = if v > 0 then F else -F
components:
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  friction: {type: Coulomb, F: 1}
connections:
  - [friction.flange, mass.flange_a]
experiment: {start: 0, stop: 2, interval: 0.01}
outputs: [mass.s, mass.v]
)");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("simulation failed at t = 1.0000000000"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("chattering"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mass.v > 0"), std::string::npos) << r.err;
  const testing::Csv csv = Rows();
  // The grid's rows to t = 1, then the left-limit row at the instant the iteration gave up
  // (1 + 1e-12: the crossing's location), kept as every failed event keeps it.
  ASSERT_EQ(csv.rows.size(), 102u);
  EXPECT_DOUBLE_EQ(csv.rows[100][0], 1.0);
  EXPECT_NEAR(csv.rows.back()[0], 1.0, 1e-9);
  EXPECT_NEAR(csv.rows.back()[1], 0.5, 1e-8);  // s = v0 t - t^2/2 at t = 1
}

/// A row of n touching balls (0.1 kg, elastic contacts); ball 1 arrives at 1 m/s, and with `both`
/// ball n at -1 m/s from the same distance, so that both ends strike at the same instant.
std::string Cradle(int n, bool both) {
  std::string outputs;
  for (int k = 1; k <= n; ++k) outputs += std::string(k > 1 ? ", " : "") + "\"ball[" + std::to_string(k) + "].v\"";
  const std::string gap = both ? "(if i == 1 then -gap else 0) + (if i == n then gap else 0)" : "(if i == 1 then -gap else 0)";
  const std::string v = both ? "if i == 1 then v0 else (if i == n then -v0 else 0)" : "if i == 1 then v0 else 0";
  return R"(model: Cradle
parameters:
  n: {value: )" + std::to_string(n) + R"(, type: Integer}
  m: {value: 0.1, unit: kg}
  r: {value: 0.02, unit: m}
  v0: {value: 1, unit: m/s}
  gap: {value: 0.05, unit: m}
components:
  ball: {type: Mass, count: n, m: m, L: 2*r, s: {start: "2*r*(i - 1) + )" + gap + R"(", fixed: true},
         v: {start: ")" + v + R"(", fixed: true}}
  contact: {type: Impact, count: n - 1, e: 1}
connections:
  - for: i in 1:n-1
    connect: ["ball[i].flange_b", "contact[i].flange_a"]
  - for: i in 1:n-1
    connect: ["contact[i].flange_b", "ball[i+1].flange_a"]
experiment: {start: 0, stop: 0.2, tolerance: 1e-8, interval: 0.001}
outputs: [)" + outputs + R"(]
)";
}

// Twenty balls struck at both ends at once: 19 contacts close at the same instant from both
// sides. Elastic impacts conserve momentum (0) and energy (2 * m v0^2 / 2), and the end balls
// leave at -v0 and +v0 while the others stay at rest; from one end only, the last ball leaves at
// v0. The impulses are solved exactly, so the sums hold to rounding (1e-12).
TEST_F(StressTest, SimultaneousImpactsOfTwentyBallsConserveMomentumAndEnergy) {
  for (bool both : {false, true}) {
    CliResult r = Simulate("cradle.yaml", Cradle(20, both), {"-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const testing::Csv csv = Rows();
    const std::vector<double> v(csv.rows.back().begin() + 1, csv.rows.back().end());
    ASSERT_EQ(v.size(), 20u);
    double momentum = 0, energy = 0;
    for (double x : v) {
      momentum += x;
      energy += x * x;
    }
    EXPECT_NEAR(momentum, both ? 0.0 : 1.0, 1e-12) << "both = " << both;
    EXPECT_NEAR(energy, both ? 2.0 : 1.0, 1e-12) << "both = " << both;
    EXPECT_NEAR(v.front(), both ? -1.0 : 0.0, 1e-12) << "both = " << both;
    EXPECT_NEAR(v.back(), 1.0, 1e-12) << "both = " << both;
  }
}

// An undamped 1e12 N/m spring on 1 kg oscillates at 1e6 rad/s (1.59e5 Hz): IDA must follow every
// period, 159 of them per 1 ms output interval (the whole run takes 1e6 steps, 1e4 an interval).
// With --max-steps 5000 the run stops, and the
// message names the mode, its frequency and the parameters that set it (|lambda| = sqrt(c/m):
// exponents 0.5 and -0.5), says that a tighter tolerance makes it worse, and what helps.
TEST_F(StressTest, CostExplosionNamesTheFastestModeAndItsParameters) {
  CliResult r = Simulate("stiff.yaml", PushedSpring("1e12", ""), {"--max-steps", "5000"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  for (const char* part :
       {"IDA stopped (IDA_TOO_MUCH_WORK): 5000 steps (--max-steps) without reaching the next output time",
        "is an oscillation at 1e6 rad/s (1.59e5 Hz, period 6.28e-6 s), damping ratio 0",
        "spring.c = 1e12 N/m (|lambda| ~ spring.c^0.5)", "mass.m = 1 kg (|lambda| ~ mass.m^-0.5)",
        "159 periods per output interval", "a tighter tolerance makes the run dearer",
        "reduce spring.c", "increase mass.m", "or damp it"}) {
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.err;
  }
  EXPECT_EQ(r.err.find("Try a tighter tolerance"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("results up to t = "), std::string::npos) << r.err;
}

// The slider-crank with its rod as long as the crank (l = R) reaches a configuration where the
// constraints lose rank as the crank passes -pi/2. The steps pile up there (every unknown is in
// IDA's error test: an index-reduced model's are by default, and --error-test all says so for any);
// its modes are slow (3.3 rad/s): the message says that they do not explain the steps and points
// at the constraints.
TEST_F(StressTest, CostExplosionAtASingularConfigurationPointsAtTheConstraints) {
  CliResult r = RunMomenta({"simulate", testing::SourcePath("models/slider_crank.yaml"), "-p", "l=0.1",
                            "--max-steps", "5000", "--error-test", "all", "-o", dir_.File("out.csv")},
                           dir_.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("IDA_TOO_MUCH_WORK"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("so the steps go elsewhere: look for a configuration where the constraints lose rank"),
            std::string::npos)
      << r.err;
}

// The same spring with a time event: the loop that searches every step for crossings counts its
// steps between rows as well (it had no limit), and stops with the same message.
TEST_F(StressTest, CostExplosionIsCaughtInRunsWithEvents) {
  std::string yaml = PushedSpring("1e12", "");
  yaml.replace(yaml.find("components:"), 11, R"(define:
  Clock:
    variables: {ticks: {type: Integer, start: 0}}
    when:
      - when: time > 0.05
        then: ["ticks = pre(ticks) + 1"]
components:
  clock: {type: Clock})");
  CliResult r = Simulate("stiff_events.yaml", yaml, {"--max-steps", "5000"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("IDA stopped (IDA_TOO_MUCH_WORK): 5000 steps (--max-steps)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is an oscillation at 1e6 rad/s"), std::string::npos) << r.err;
}

// A run that finishes with far more steps per output interval than a smooth solution needs (10 ms
// of the undamped 1e12 N/m spring: 1590 periods, about 1e5 steps, 1e4 per row) gets the analysis
// as a note in its summary, with the advice for a run that finished (no --max-steps).
TEST_F(StressTest, DearRunThatFinishesGetsTheFastestModeAsANote) {
  CliResult r = Simulate("stiff.yaml", PushedSpring("1e12", ""), {"--stop", "0.01"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const size_t note = r.out.find("  note: ");
  ASSERT_NE(note, std::string::npos) << r.out;
  const std::string text = r.out.substr(note, r.out.find('\n', note) - note);
  EXPECT_NE(text.find(" per output interval. The fastest mode at t = 0.01 s is an oscillation at 1e6 rad/s"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("spring.c = 1e12 N/m"), std::string::npos) << text;
  EXPECT_NE(text.find("159 periods per output interval, more than the rows resolve"), std::string::npos) << text;
  EXPECT_EQ(text.find("--max-steps"), std::string::npos) << text;
  // A cheap run has no note.
  CliResult cheap = Simulate("soft.yaml", PushedSpring("1e3", ""));
  ASSERT_EQ(cheap.exit_code, 0) << cheap.err;
  EXPECT_EQ(cheap.out.find("note:"), std::string::npos) << cheap.out;
}

TEST_F(StressTest, MaxStepsMustBeAWholeNumberOfAtLeastOne) {
  for (const char* bad : {"0", "2.5", "-3", "1e16"}) {
    CliResult r = Simulate("stiff.yaml", PushedSpring("1e3", ""), {"--max-steps", bad});
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--max-steps "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("must be a whole number from 1 to 1e15"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace momenta

// stateSelect (MSL's StateSelect: never, avoid, default, prefer, always) on a pendulum written
// with both Cartesian coordinates and the angle: the priorities change which variables index
// reduction keeps as states, without changing the motion; the promises `always` and `never` are
// reported, by message, where the equations cannot keep them.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;

/// Pendulum of length 1 released from theta0 = 0.5; `select` maps variables (x, y, phi, vx, vy,
/// w, F) to their stateSelect. With `angle` the angle phi and its rate w are unknowns too,
/// tied to x and y by x = L sin(phi), y = -L cos(phi), instead of the constraint x^2 + y^2 = L^2.
std::string Pendulum(const std::map<std::string, std::string>& select, bool angle) {
  auto var = [&](const std::string& name, const std::string& rest) {
    auto it = select.find(name);
    std::string s = "      " + name + ": {" + rest;
    if (it != select.end()) s += ", stateSelect: " + it->second;
    return s + "}\n";
  };
  std::ostringstream y;
  y << "model: Pendulum\ndefine:\n  Pendulum:\n    parameters: {L: 1, g: 9.81, m: 1, theta0: 0.5}\n    variables:\n";
  y << var("x", std::string("start: L*sin(theta0)") + (angle ? "" : ", fixed: true"));
  y << var("y", "start: -L*cos(theta0)");
  y << var("vx", std::string("start: 0") + (angle ? "" : ", fixed: true"));
  y << var("vy", "start: 0");
  y << var("F", "start: m*g");
  if (angle) {
    y << var("phi", "start: theta0, fixed: true");
    y << var("w", "start: 0, fixed: true");
  }
  y << "    equations:\n      - der(x) = vx\n      - der(y) = vy\n      - m*der(vx) = -x*F/L\n"
       "      - m*der(vy) = -y*F/L - m*g\n";
  if (angle) {
    y << "      - x = L*sin(phi)\n      - y = -L*cos(phi)\n      - w = der(phi)\n";
  } else {
    y << "      - x^2 + y^2 = L^2\n";
  }
  y << "components:\n  p: {type: Pendulum}\nexperiment: {stop: 1, tolerance: 1e-10, interval: 0.01}\n"
       "outputs: [p.x, p.y, p.vx, p.vy]\n";
  return y.str();
}

using States = std::vector<std::string>;

TEST(StateSelectTest, AngleByDefaultCartesianWhenAlways) {
  // By default the angle and its rate are the states (x = L sin(phi) is solved for x by the
  // linear fast path); `always` on x and vx keeps them instead (Pantelides differentiates the
  // angle equations), and the motion is the same.
  Built by_angle = testing::BuildYaml(Pendulum({}, true));
  EXPECT_EQ(by_angle.report.states, (States{"p.phi", "p.w"}));
  Built cartesian = testing::BuildYaml(Pendulum({{"x", "always"}, {"vx", "always"}}, true));
  EXPECT_EQ(cartesian.report.states, (States{"p.x", "p.vx"}));
  testing::Trajectory a = testing::RunDefault(by_angle), b = testing::RunDefault(cartesian);
  ASSERT_EQ(a.t.size(), b.t.size());
  double worst = 0;
  for (size_t k = 0; k < a.t.size(); ++k) {
    for (const char* name : {"p.x", "p.y", "p.vx", "p.vy"}) {
      worst = std::max(worst, std::fabs(a.Column(name, k) - b.Column(name, k)));
    }
  }
  EXPECT_LT(worst, 1e-7);
}

TEST(StateSelectTest, PreferAndNeverChooseAmongConstrainedCandidates) {
  // x^2 + y^2 = L^2: by default one of {x, y} is chosen during the run (a state set).
  Built dynamic = testing::BuildYaml(Pendulum({}, false));
  EXPECT_EQ(dynamic.report.states, (States{"stateSet1.x", "stateSet2.x"}));
  // `prefer` on x alone (or `always`) makes it the position state throughout, with der(x)
  // (rather than vx, which has no preference) for the velocity.
  for (const char* choice : {"prefer", "always"}) {
    Built b = testing::BuildYaml(Pendulum({{"x", choice}}, false));
    EXPECT_EQ(b.report.states, (States{"p.x", "der(p.x)"})) << choice;
  }
  // `never` on x and vx leaves y (and a velocity chosen during the run among vy and der(y)).
  Built never = testing::BuildYaml(Pendulum({{"x", "never"}, {"vx", "never"}}, false));
  EXPECT_EQ(never.report.states, (States{"p.y", "stateSet1.x"}));
  ASSERT_EQ(never.report.state_choices.size(), 2u);
  EXPECT_NE(never.report.state_choices[0].find("one of {der(p.y), p.vy} is a state"), std::string::npos)
      << never.report.state_choices[0];
  EXPECT_EQ(never.report.state_choices[1], "of {der(p.x), der(p.y)} 1 made dummy: der(p.x) (static: stateSelect)");
  // Equal priorities still choose during the run.
  Built both = testing::BuildYaml(Pendulum({{"x", "prefer"}, {"y", "prefer"}}, false));
  EXPECT_EQ(both.report.states, (States{"stateSet1.x", "stateSet2.x"}));
}

TEST(StateSelectTest, AlwaysThatTheConstraintForbidsIsAnError) {
  std::string err = testing::BuildError(Pendulum({{"x", "always"}, {"y", "always"}}, false));
  EXPECT_NE(err.find("test.yaml:18:6: stateSelect: always on p.y cannot be honoured: the other states determine p.y "
                     "through\n"
                     "    p (Pendulum, test.yaml:18:6): 'x^2 + y^2 = L^2', differentiated once\n"
                     "  (index reduction must make der(p.y) a dummy derivative). Use stateSelect: prefer on p.y, "
                     "or always on fewer variables."),
            std::string::npos)
      << err;
}

TEST(StateSelectTest, AlwaysOnAVariableNeverDifferentiatedIsAnError) {
  std::string err = testing::BuildError(Pendulum({{"F", "always"}}, false));
  EXPECT_NE(err.find("stateSelect: always on p.F cannot be honoured: der(p.F) appears in no equation (states are "
                     "chosen among the variables that appear differentiated). Use stateSelect: prefer (or "
                     "default) on p.F."),
            std::string::npos)
      << err;
  // With the angle, x and y are both determined by phi: they cannot both be states.
  err = testing::BuildError(Pendulum({{"x", "always"}, {"y", "always"}}, true));
  EXPECT_NE(err.find("stateSelect: always on p.y cannot be honoured"), std::string::npos) << err;
}

TEST(StateSelectTest, NeverOnEveryCandidateIsAWarning) {
  Built b = testing::BuildYaml(Pendulum({{"x", "never"}, {"y", "never"}}, false));
  EXPECT_EQ(b.report.states, (States{"stateSet1.x", "stateSet2.x"}));
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_EQ(b.report.warnings[0],
            "stateSelect: never on each of {p.x, p.y}, but one of them must be a state (a state set selects it "
            "during the run)");
  // An ordinary ODE state marked never.
  Built ode = testing::BuildYaml(R"yaml(
model: Decay
variables:
  x: {start: 1, fixed: true, stateSelect: never}
equations:
  - der(x) = -x
)yaml");
  ASSERT_EQ(ode.report.warnings.size(), 1u);
  EXPECT_EQ(ode.report.warnings[0],
            "test.yaml:4:6: stateSelect: never on x, but it is a state: no other variable can carry its degree of freedom");
}

TEST(StateSelectTest, ComponentModifierAndBadValue) {
  // Two masses joined by a rod: one position and one velocity are states; the modifier picks
  // which mass carries them.
  auto rod = [](const std::string& m1, const std::string& m2) {
    return R"yaml(
model: TwoMasses
components:
  m1: {type: Mass, m: 1)yaml" + m1 + R"yaml(}
  rod: {type: Rod, L: 1}
  m2: {type: Mass, m: 2)yaml" + m2 + R"yaml(}
connections:
  - [m1.flange_b, rod.flange_a]
  - [rod.flange_b, m2.flange_a]
)yaml";
  };
  Built first = testing::BuildYaml(rod(", s: {stateSelect: prefer}, v: {stateSelect: prefer}", ""));
  EXPECT_EQ(first.report.states, (States{"m1.s", "m1.v"}));
  Built second = testing::BuildYaml(rod("", ", s: {stateSelect: prefer}, v: {stateSelect: prefer}"));
  EXPECT_EQ(second.report.states, (States{"m2.s", "m2.v"}));
  // The same as a part's modifier inside a composite type.
  Built inside = testing::BuildYaml(R"yaml(
model: Composite
define:
  Dumbbell:
    components:
      m1: {type: Mass, m: 1}
      rod: {type: Rod, L: 1}
      m2: {type: Mass, m: 2, s: {stateSelect: prefer}, v: {stateSelect: prefer}}
    connections:
      - [m1.flange_b, rod.flange_a]
      - [rod.flange_b, m2.flange_a]
components:
  bell: {type: Dumbbell}
)yaml");
  EXPECT_EQ(inside.report.states, (States{"bell.m2.s", "bell.m2.v"}));
  EXPECT_EQ(testing::BuildError(rod(", s: {stateSelect: sometimes}", "")),
            "test.yaml:4:43: unknown stateSelect 'sometimes' for m1.s (valid choices: never, avoid, default, prefer, "
            "always)");
}

}  // namespace
}  // namespace momenta

// Conditional parts (core/passes/conditional_connectors.h, docs/FORMAT.md "Conditional parts"): a
// part of a composite type declared with `condition: use_d` exists only when that condition on the
// type's parameters holds, as Modelica's `Der derv[3] if use_v`. Absent, it and every connection to
// it vanish; present, it is an ordinary part. Errors name the file:line, the component and why.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/base/error.h"
#include "core/compile/model_state.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::Trajectory;

/// The 1-based line of `yaml` that first holds `needle`, as ":N:" (a message's file:line:col).
std::string LineOf(const std::string& yaml, const std::string& needle) {
  const size_t at = yaml.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  int line = 1;
  for (size_t k = 0; k < at; ++k) line += yaml[k] == '\n';
  return ":" + std::to_string(line) + ":";
}

/// Whether `msg` reads FILE:LINE:COL: `text`, LINE being that of `needle` in `yaml`.
bool AtLine(const std::string& msg, const std::string& yaml, const std::string& needle, const std::string& text) {
  const size_t at = msg.find(LineOf(yaml, needle));
  if (at == std::string::npos) return false;
  const size_t colon = msg.find(": ", at + 1);
  return colon != std::string::npos && msg.compare(colon + 2, text.size(), text) == 0;
}

/// y = k*sin(2t) from the type's own equation; dy = der(y) and ddy = der(dy) from two Der parts,
/// each there only with its condition. `der1` is der1's condition, `more` extends the type's
/// equations, `entry` the keys of s's entry, `outputs` the model's outputs.
std::string Shaper(const std::string& der1, const std::string& entry, const std::string& outputs,
                   const std::string& more_variables = "", const std::string& more_equations = "") {
  return R"(model: Shaping
define:
  Shaper:
    parameters:
      use_d: {value: false, type: Boolean}
      use_dd: {value: false, type: Boolean}
      has_dd: {value: use_d and use_dd, type: Boolean}
      k: {value: 1}
      gain: {value: 2}
    connectors:
      y: RealOutput
      dy: {type: RealOutput, condition: use_d}
      ddy: {type: RealOutput, condition: has_dd}
    components:
      der1: {type: Der, condition: )" + der1 + R"(}
      der2: {type: Der, condition: use_d and use_dd}
    connections:
      - [y, der1.u]
      - [der1.y, dy]
      - [der1.y, der2.u]
      - [der2.y, ddy]
    variables: {)" + more_variables + R"(}
    equations:
      - y = k*sin(2*time)
)" + more_equations + R"(components:
  s: {type: Shaper)" + entry + R"(}
experiment: {stop: 1, tolerance: 1e-8, interval: 0.01}
outputs: )" + outputs + "\n";
}

// Present, the parts are ordinary Der blocks: dy = 2k cos 2t and ddy = -4k sin 2t exactly (the
// derivatives are taken of the equations, not integrated: 1e-9 is rounding with room).
TEST(ConditionalPartsTest, PresentPartsWork) {
  Trajectory tr = testing::RunDefault(testing::BuildYaml(
      Shaper("use_d", ", use_d: true, use_dd: true, k: 3", "[s.y, s.dy, s.ddy, s.der2.u, s.der1.u]")));
  ASSERT_GT(tr.t.size(), 50u);
  for (size_t r = 0; r < tr.t.size(); ++r) {
    const double t = tr.t[r];
    EXPECT_NEAR(tr.Column("s.dy", r), 6 * std::cos(2 * t), 1e-9) << "t = " << t;
    EXPECT_NEAR(tr.Column("s.ddy", r), -12 * std::sin(2 * t), 1e-9) << "t = " << t;
    EXPECT_EQ(tr.Column("s.der2.u", r), tr.Column("s.dy", r));
    EXPECT_EQ(tr.Column("s.der1.u", r), tr.Column("s.y", r));
  }
}

// Absent, a part has no variables: an output that names one is an error at the output naming the
// part and why, and the build has the unknowns of the type written without it. The other part,
// present, still works (only der2 is absent: dy is there, ddy is not).
TEST(ConditionalPartsTest, AnAbsentPartHasNoVariables) {
  Trajectory tr = testing::RunDefault(testing::BuildYaml(Shaper("use_d", ", use_d: true", "[s.dy]")));
  for (size_t r = 0; r < tr.t.size(); ++r) EXPECT_NEAR(tr.Column("s.dy", r), 2 * std::cos(2 * tr.t[r]), 1e-9);

  const std::string yaml = Shaper("use_d", ", use_d: true", "[s.dy, s.der2.y]");
  const std::string msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "outputs:", "the output 's.der2.y' names s.der2.y, but s has no part der2 (its "
                                                "condition use_d and use_dd is false)")) << msg;

  // The build's unknowns are those of the type written without der2 and ddy at all.
  auto unknowns_after_aliases = [](const std::string& text) {
    const testing::Built b = testing::BuildYaml(text);
    for (const PassReport& pass : b.report.passes) {
      if (pass.name == "alias elimination") return pass.variables;
    }
    ADD_FAILURE() << "no alias elimination pass";
    return size_t{0};
  };
  std::string without = Shaper("use_d", ", use_d: true", "[s.dy]");
  for (const char* line : {"      ddy: {type: RealOutput, condition: has_dd}\n", "      der2: {type: Der, condition: use_d and use_dd}\n",
                           "      - [der1.y, der2.u]\n", "      - [der2.y, ddy]\n"}) {
    without.erase(without.find(line), std::string(line).size());
  }
  EXPECT_EQ(unknowns_after_aliases(Shaper("use_d", ", use_d: true", "[s.dy]")), unknowns_after_aliases(without));
}

// A condition may read Real parameters; they are fixed when the model is built, as the Boolean
// ones are: -p on them is refused on the built model.
TEST(ConditionalPartsTest, TheConditionFixesTheStructure) {
  testing::Built b = testing::BuildYaml(Shaper("use_d and gain > 1", ", use_d: true", "[s.dy]"));
  Trajectory tr = testing::RunDefault(b);
  EXPECT_NEAR(tr.Column("s.dy", 0), 2, 1e-9);
  for (const char* name : {"s.gain", "s.use_d"}) {
    ModelState state(b.model);
    try {
      state.SetParameters({{name, 0}});
      FAIL() << "expected an error for " << name;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(name) + " shapes the model's structure"), std::string::npos)
          << e.what();
    }
  }
}

TEST(ConditionalPartsTest, TheConditionIsABooleanOfParameters) {
  std::string yaml = Shaper("k", "", "[s.y]");
  std::string msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "der1: {type: Der, condition: k}", "the condition of part der1 in Shaper must be a Boolean: a Boolean parameter, a comparison or "
                     "and/or/not of them (e.g. use_v, m > 0), found 'k' (a Real parameter)")) << msg;
  yaml = Shaper("y > 0", "", "[s.y]");
  msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "der1: {type: Der",
                     "the condition of part der1 in Shaper reads the variable y, in 'y > 0'; a part's condition may "
                     "read parameters only"))
      << msg;
  yaml = Shaper("missing", "", "[s.y]");
  msg = BuildError(yaml);
  EXPECT_NE(msg.find("unknown name 'missing'"), std::string::npos) << msg;
  // A model's own components take none.
  yaml = "model: M\ncomponents:\n  c: {type: Constant, condition: true}\noutputs: [c.y]\n";
  msg = BuildError(yaml);
  EXPECT_NE(msg.find(":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("component c of the model has a condition; condition: is taken by the parts of a component type"),
            std::string::npos)
      << msg;
}

// What an absent part leaves must still be determined: a connector that exists without it and was
// driven by it is an error at the connection; so is an equation of the type that names it.
TEST(ConditionalPartsTest, WhatAnAbsentPartLeavesMustBeDetermined) {
  std::string yaml = Shaper("use_d and gain > 1", ", use_d: true, gain: 0.5", "[s.y]");
  std::string msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "- [der1.y, dy]",
                     "the connection 's.dy = s.der1.y (connection)' joins s.dy to s.der1.y, but s has no part der1 "
                     "(its condition use_d and gain > 1 is false); s.dy exists without it"))
      << msg;
  yaml = Shaper("use_d", "", "[s.y]", "z: {}", "      - z = der1.u\n");
  msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "- z = der1.u", "the equation 'z = der1.u' names s.der1.u, but s has no part der1 "
                                                       "(its condition use_d is false)")) << msg;
}

/// A mass on a spring (c = 100, m = 1) from the cell's flange, with a damper beside the spring
/// that is there only when `damped`; `joints` are the damper's connections.
std::string Cell(const std::string& damped, const std::string& joints) {
  return R"(model: Cells
define:
  Cell:
    parameters: {damped: {value: false, type: Boolean}}
    connectors: {flange: Flange}
    components:
      mass: {type: Mass, m: 1, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
      spring: {type: Spring, c: 100}
      damper: {type: Damper, d: 2, condition: damped}
    connections:
      - [flange, spring.flange_a]
      - [spring.flange_b, mass.flange_a]
)" + joints + R"(components:
  wall: {type: Fixed}
  cell: {type: Cell)" + damped + R"(}
connections:
  - [wall.flange, cell.flange]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [cell.mass.s]
)";
}

// Physical connectors: an absent part's flows leave the flow sums, so the cell is a plain
// oscillator, s = 0.1 cos 10t; present, the damper damps it: s = 0.1 e^(-t)(cos wt + sin(wt)/w),
// w = sqrt(99) (1e-6: the integration at 1e-10 with room).
TEST(ConditionalPartsTest, FlowsOfAnAbsentPartLeaveTheirSets) {
  const std::string joints = "      - [flange, damper.flange_a]\n      - [damper.flange_b, mass.flange_a]\n";
  Trajectory plain = testing::RunDefault(testing::BuildYaml(Cell("", joints)));
  Trajectory damped = testing::RunDefault(testing::BuildYaml(Cell(", damped: true", joints)));
  const double w = std::sqrt(99.0);
  for (size_t r = 0; r < plain.t.size(); ++r) {
    const double t = plain.t[r];
    EXPECT_NEAR(plain.Column("cell.mass.s", r), 0.1 * std::cos(10 * t), 1e-6) << "t = " << t;
  }
  for (size_t r = 0; r < damped.t.size(); ++r) {
    const double t = damped.t[r];
    EXPECT_NEAR(damped.Column("cell.mass.s", r), 0.1 * std::exp(-t) * (std::cos(w * t) + std::sin(w * t) / w), 1e-6)
        << "t = " << t;
  }
  // Connectors that always exist joined only through the conditional part: refused where the
  // type is laid out (absent, Modelica would leave them apart).
  const std::string yaml = Cell("", "      - [spring.flange_b, damper.flange_a]\n      - [damper.flange_a, mass.flange_b]\n");
  const std::string msg = BuildError(yaml);
  EXPECT_TRUE(AtLine(msg, yaml, "- [spring.flange_b, damper.flange_a]", "mass.flange_a and mass.flange_b in Cell are connected only through damper.flange_a, which is "
                     "conditional")) << msg;
}

}  // namespace
}  // namespace momenta

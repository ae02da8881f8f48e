// Bad models, each written inline: the CLI must exit with 1 and BuildError() must return a
// message that names the place (file:line:col, or the file), the user's component or connector
// path, and the valid alternatives where there are any. Each case lists the fragments the
// message must contain; '@' stands for the file name ("test.yaml" for BuildError, "<case>.yaml"
// for the CLI).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/commands.h"
#include "core/lang/yaml_document.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

struct BadModel {
  std::string name;
  std::string yaml;
  std::vector<std::string> params;  ///< -p NAME=VALUE
  std::vector<std::string> must_contain;
};

std::ostream& operator<<(std::ostream& o, const BadModel& b) { return o << b.name; }

std::string WithFile(const std::string& fragment, const std::string& file) {
  std::string out;
  for (char c : fragment) {
    if (c == '@') {
      out += file;
    } else {
      out += c;
    }
  }
  return out;
}

const std::vector<BadModel>& Cases() {
  static const std::vector<BadModel> cases = {
      // YAML syntax: the extra '}' is at 3:24.
      {"yaml_syntax",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}}\n",
       {},
       {"@:3:24: ", "YAML"}},

      // An equation that does not parse, in a define: type; the column of the second '*'.
      {"equation_syntax",
       R"(model: Bad
define:
  Thing:
    variables:
      x: {start: 0}
    equations:
      - der(x) = -2 * * x
components:
  T: {type: Thing}
)",
       {},
       {"@:7:23: ", "'*'", "der(x) = -2 * * x"}},

      // A misspelt library type: the closest ones and the list (its first 80 names, alphabetical).
      {"unknown_type",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mas, m: 1}\n",
       {},
       {"@:3:13: ", "'Mas'", "A", "did you mean Mass", "valid types: ", "Accelerate", "Add"}},

      // A connector the component does not have.
      {"unknown_connector",
       R"(model: Bad
components:
  A: {type: Mass, m: 1}
  W: {type: Fixed}
connections:
  - [A.flange_c, W.flange]
)",
       {},
       {"@:6:", "A (Mass)", "'flange_c'", "valid connectors: flange_a, flange_b"}},

      // A component that does not exist in a connection.
      {"unknown_component_in_connection",
       R"(model: Bad
components:
  A: {type: Mass}
  W: {type: Fixed}
connections:
  - [Wall.flange, A.flange_a]
)",
       {},
       {"@:6:", "'Wall'", "valid components: A, W"}},

      // A Flange joined to a Pin: both ends and their kinds.
      {"mismatched_connectors",
       R"(model: Bad
components:
  A: {type: Mass, m: 1}
  R: {type: Resistor}
  G: {type: Ground}
connections:
  - [A.flange_a, R.p]
  - [R.n, G.p]
)",
       {},
       {"@:7:", "A.flange_a (Flange)", "R.p (Pin)"}},

      // Too few equations: y is never determined.
      {"too_few_equations",
       R"(model: Bad
define:
  Two:
    variables:
      x: {start: 0, fixed: true}
      y: {start: 0}
    equations:
      - der(x) = -x
components:
  T: {type: Two}
)",
       {},
       {"@:10:", "T (Two)", "not balanced", "1 equation for 2 unknowns", "add an equation"}},

      // Too many equations: x is both integrated and prescribed.
      {"too_many_equations",
       R"(model: Bad
define:
  Over:
    variables:
      x: {start: 1}
    equations:
      - der(x) = -x
      - x = 2*time
components:
  T: {type: Over}
)",
       {},
       {"@:10:", "T (Over)", "not balanced", "2 equations for 1 unknown", "remove the extra equation"}},

      // Two walls joined: the flange is at 0 and at 1, and nothing determines its force.
      {"two_fixed_flanges",
       R"(model: Bad
components:
  W1: {type: Fixed, s0: 0}
  W2: {type: Fixed, s0: 1}
connections:
  - [W1.flange, W2.flange]
)",
       {},
       {"@", "contradicts", "W2.flange.s = W1.flange.s", "@:6:", "two sources fixing one position"}},

      // Two masses joined by two rods in a loop: B.s = A.s + 1 twice, and only the sum of the
      // rods' forces is determined. The message must point at the loop, i.e. at both rods.
      {"rod_loop",
       R"(model: Bad
components:
  A: {type: Mass, m: 1, L: 0, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  B: {type: Mass, m: 1, L: 0}
  R1: {type: Rod, L: 1}
  R2: {type: Rod, L: 1}
connections:
  - [A.flange_b, R1.flange_a]
  - [R1.flange_b, B.flange_a]
  - [A.flange_a, R2.flange_a]
  - [R2.flange_b, B.flange_b]
)",
       {},
       {"@", "redundant", "R2.flange_b.s = B.flange_b.s", "closed loop of rigid connections"}},

      // A model parameter declared without a value.
      {"parameter_without_value",
       R"(model: Bad
parameters:
  mA: {unit: kg, doc: the mass}
components:
  A: {type: Mass, m: mA}
)",
       {},
       {"@:3:", "mA", "value"}},

      // The experiment section: each value is checked where it is written, with its text.
      {"experiment_interval_zero",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {stop: 1, interval: 0}\n",
       {},
       {"@:4:33: experiment.interval must be positive, found '0'"}},
      {"experiment_interval_too_many_rows",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {stop: 1, interval: 1e-300}\n",
       {},
       {"@:4:33: experiment.interval '1e-300': from 0 to 1 s that is 1e+300 output rows; at most 1e9 can be written"}},
      {"experiment_interval_below_time_resolution",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {start: 1e9, stop: 1.000000001e9, interval: 1e-7}\n",
       {},
       {"@:4:57: experiment.interval '1e-7': it is below the time resolution at t = 1e+09 (0.0001 s)"}},
      {"experiment_tolerance_below_double_precision",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {tolerance: 1e-300}\n",
       {},
       {"@:4:25: experiment.tolerance must lie between 1e-15 and 1", "found '1e-300'"}},
      {"experiment_max_order_above_five",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {max_order: 6}\n",
       {},
       {"@:4:25: experiment.max_order must be a whole number from 1 to 5 (IDA's maximum BDF order; the default "
        "is 5), found '6'"}},
      {"experiment_max_order_not_whole",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {max_order: 2.5}\n",
       {},
       {"@:4:25: experiment.max_order must be a whole number from 1 to 5", "found '2.5'"}},
      {"experiment_stop_before_start",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 1}\n"
       "experiment: {start: 2}\n",
       {},
       {"@:4:13: experiment.stop must be after experiment.start ('2'), found 1 (the default)"}},

      // min violated: the parameter, its value and the bound.
      {"negative_mass",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: -2}\n",
       {},
       {"@:3:22: ", "A.m", "-2", "minimum 0"}},

      // min violated through -p.
      {"negative_mass_override",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: 2}\n",
       {"A.m=-2"},
       {"@", "-p A.m", "-2", "minimum 0"}},

      // NaN in the file.
      {"nan_value",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, m: .nan}\n",
       {},
       {"@:3:22: ", "A.m", "finite"}},

      // An unknown key in a component entry: points at the key, lists the valid ones.
      {"unknown_component_key",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, mass: 1}\n",
       {},
       {"@:3:19: ", "'mass'", "A (Mass)", "m, L", "type, count, condition, doc"}},

      // An unknown key at the top level.
      {"unknown_top_level_key",
       R"(model: Bad
components:
  A: {type: Mass}
connection:
  - [A.flange_a, A.flange_b]
)",
       {},
       {"@:4:1: ", "'connection'", "connections", "components", "experiment", "outputs"}},

      // An unknown name in an equation of a define: type.
      {"unknown_name_in_equation",
       R"(model: Bad
define:
  Decay:
    parameters:
      k: {value: 2}
    variables:
      x: {start: 1, fixed: true}
    equations:
      - der(x) = -kk*x
components:
  D: {type: Decay}
)",
       {},
       {"@:9:19: ", "'kk'", "Decay", "did you mean k", "x, k, time, pi"}},

      // A variable given a plain number instead of {start:}.
      {"variable_as_plain_value",
       "model: Bad\n"
       "components:\n"
       "  A: {type: Mass, s: 1.5}\n",
       {},
       {"@:3:", "A.s", "variable", "{start: 1.5"}},

      // An array index past the end.
      {"index_out_of_range",
       R"(model: Bad
parameters: {n: 3}
components:
  R: {type: Resistor, count: n}
  G: {type: Ground}
connections:
  - ["R[4].p", G.p]
)",
       {},
       {"@:7:", "R[4]", "1..3"}},

      // R = 0: the resistor's law cannot be solved for its current.
      {"zero_divisor",
       R"(model: Bad
components:
  source: {type: ConstantVoltage, V: 1}
  R: {type: Resistor, R: 0}
  C: {type: Capacitor, C: 1, v: {start: 0, fixed: true}}
  ground: {type: Ground}
connections:
  - [source.p, R.p]
  - [R.n, C.p]
  - [C.n, source.n]
  - [source.n, ground.p]
outputs: [C.v]
)",
       {},
       {"@", "R.R * (1 + R.alpha * (R.T - R.T_ref)) = 0", "'v = R_actual*i'", "R (Resistor"}},

      // Two signal outputs joined.
      {"two_outputs_connected",
       R"(model: Bad
components:
  c1: {type: Constant}
  c2: {type: Constant}
connections:
  - [c1.y, c2.y]
)",
       {},
       {"@:6:", "c1.y", "c2.y"}},

      // A signal input left unconnected.
      {"unconnected_input",
       R"(model: Bad
components:
  g: {type: Gain}
outputs: [g.y]
)",
       {},
       {"@", "g.u", "connect it to an output"}},

      // An output naming a variable the component does not have.
      {"unknown_output",
       R"(model: Bad
components:
  A: {type: Mass, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
outputs: [A.vel]
)",
       {},
       {"@:4:", "'vel'", "A (Mass)", "s, v, a"}},

      // Planar multibody: a joint whose two frames are one body's frame fixes nothing new but
      // states the body's position twice; the message names the joint's equations.
      {"planar_joint_on_one_body",
       "model: Bad\n"
       "components:\n"
       "  body: {type: Body, m: 1, I: 0.1}\n"
       "  joint: {type: Revolute}\n"
       "connections:\n"
       "  - [body.frame_a, joint.frame_a]\n"
       "  - [body.frame_a, joint.frame_b]\n",
       {},
       {"redundant", "joint.frame_b.x = body.frame_a.x (connection)", "@:6:6"}},

      // A body with a negative moment of inertia.
      {"planar_negative_inertia",
       "model: Bad\n"
       "components:\n"
       "  body: {type: Body, m: 1, I: -1}\n",
       {},
       {"@:3:31: body.I", "= -1 is below its minimum 0"}},
  };
  return cases;
}

class BadModelTest : public ::testing::TestWithParam<BadModel> {};

TEST_P(BadModelTest, BuildErrorNamesTheProblem) {
  const BadModel& c = GetParam();
  ParameterOverrides overrides;
  if (!c.params.empty()) overrides = ParseOverrides(c.params);
  const std::string message = testing::BuildError(c.yaml, overrides);
  ASSERT_FALSE(message.empty()) << c.name << " built without an error";
  for (const auto& fragment : c.must_contain) {
    const std::string want = WithFile(fragment, "test.yaml");
    EXPECT_NE(message.find(want), std::string::npos) << c.name << ": no '" << want << "' in:\n" << message;
  }
}

// The faster readers (the subset reader and libyaml, core/lang/yaml_document.h) give the same
// message, at the same place, as yaml-cpp's.
TEST_P(BadModelTest, FasterReadersGiveTheSameMessage) {
  const BadModel& c = GetParam();
  ParameterOverrides overrides;
  if (!c.params.empty()) overrides = ParseOverrides(c.params);
  SetDefaultYamlReader(YamlReader::kYamlCpp);
  const std::string by_yaml_cpp = testing::BuildError(c.yaml, overrides);
  SetDefaultYamlReader(YamlReader::kLibyaml);
  const std::string by_libyaml = testing::BuildError(c.yaml, overrides);
  SetDefaultYamlReader(YamlReader::kSubset);
  const std::string by_subset = testing::BuildError(c.yaml, overrides);
  SetDefaultYamlReader(YamlReader::kAuto);
  EXPECT_EQ(by_libyaml, by_yaml_cpp) << c.name;
  EXPECT_EQ(by_subset, by_yaml_cpp) << c.name;
}

TEST_P(BadModelTest, CliExitsWithOneAndPrintsTheMessage) {
  const BadModel& c = GetParam();
  testing::TempDir dir;
  const std::string file = c.name + ".yaml";
  dir.Write(file, c.yaml);
  std::vector<std::string> args = {"simulate", file, "-o", "out.csv"};
  for (const auto& p : c.params) {
    args.push_back("-p");
    args.push_back(p);
  }
  testing::CliResult r = testing::RunMomenta(args, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel) << c.name << ":\n" << r.err;
  EXPECT_EQ(r.out, "") << c.name;
  // The message starts with the file (and where known the line and column).
  EXPECT_EQ(r.err.rfind(file, 0), 0u) << c.name << ": stderr does not start with the file:\n" << r.err;
  for (const auto& fragment : c.must_contain) {
    const std::string want = WithFile(fragment, file);
    EXPECT_NE(r.err.find(want), std::string::npos) << c.name << ": no '" << want << "' in:\n" << r.err;
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, BadModelTest, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<BadModel>& info) { return info.param.name; });

}  // namespace
}  // namespace momenta

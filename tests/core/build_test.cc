// The build pipeline: the report lists the passes in order with sizes that only shrink, the
// default outputs are the states, start values that have to stand in for initial conditions are
// warned about, and redundant initial conditions are left out with a note and checked; -p values
// with units are converted to the declared units, and outputs added once the model is flattened
// (the report's scene) follow the model's own.

#include "core/build.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/lang/parser.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

const char* kOscillator = R"(
model: Osc
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: 4}
  damper: {type: Damper, d: 0.5}
  m: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  sensor: {type: PositionSensor}
connections:
  - [wall.flange, spring.flange_a]
  - [wall.flange, damper.flange_a]
  - [spring.flange_b, m.flange_a]
  - [damper.flange_b, m.flange_a]
  - [m.flange_b, sensor.flange]
experiment: {stop: 2, interval: 0.5}
)";

TEST(BuildTest, ReportListsThePassesInOrder) {
  testing::Built b = testing::BuildYaml(kOscillator);
  // The pipeline's passes in order; a pass that reports on a separate system (the
  // initialisation), only on models with events (the discrete partition) or only on models with
  // structural parameters or conditional connectors (a Damper's absent heat port) may come in
  // between.
  const std::vector<std::string> pipeline = {"flatten",         "alias elimination",
                                             "index reduction", "structural analysis",
                                             "pruning",         "causalisation",
                                             "compilation"};
  std::vector<std::string> names, core;
  for (const auto& p : b.report.passes) {
    names.push_back(p.name);
    if (std::count(pipeline.begin(), pipeline.end(), p.name)) {
      core.push_back(p.name);
    } else {
      EXPECT_TRUE(p.name == "initialisation" || p.name == "discrete partition" || p.name == "structural parameters")
          << p.name;
    }
  }
  EXPECT_EQ(core, pipeline) << ::testing::PrintToString(names);
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "flatten");
  EXPECT_EQ(names.back(), "compilation");
  EXPECT_EQ(b.report.num_components, 5u);
  EXPECT_GE(b.report.num_parameters, 6u);
  for (const auto& p : b.report.passes) {
    EXPECT_GE(p.seconds, 0.0) << p.name;
    EXPECT_FALSE(p.note.empty()) << p.name;
  }
}

TEST(BuildTest, UnknownsOnlyShrink) {
  for (const std::string& file : {"models/rc_ladder.yaml", "models/spring_damper_chain.yaml",
                                  "models/msl/Sensors.yaml"}) {
    testing::Built b = testing::BuildFile(file);
    const auto& passes = b.report.passes;
    ASSERT_GE(passes.size(), 7u);
    size_t previous = passes[0].variables;
    EXPECT_EQ(passes[0].variables, b.model->flat->variables.size()) << file;
    EXPECT_EQ(passes[0].equations, b.model->flat->equations.size()) << file;
    for (const auto& p : passes) {
      if (p.name == "initialisation") {
        // A different system: y and the states' y'.
        EXPECT_EQ(p.variables, b.model->num_unknowns() + b.model->num_states()) << file;
        continue;
      }
      EXPECT_LE(p.variables, previous) << file << ": " << p.name;
      previous = p.variables;
      // Balanced from the structural analysis on.
      if (p.name == "structural analysis" || p.name == "pruning" || p.name == "causalisation" ||
          p.name == "compilation") {
        EXPECT_EQ(p.equations, p.variables) << file << ": " << p.name;
      }
    }
    EXPECT_EQ(passes.back().variables, b.model->num_unknowns()) << file;
    EXPECT_LT(b.model->num_unknowns(), b.model->flat->variables.size()) << file;
  }
}

TEST(BuildTest, WithoutOutputsEveryStateIsAnOutput) {
  testing::Built b = testing::BuildYaml(kOscillator);
  EXPECT_EQ(b.model->output_names, b.report.states);
  std::vector<std::string> states = b.report.states;
  std::sort(states.begin(), states.end());
  // The damper's relative quantities (stateSelect prefer) win over the mass's (default).
  EXPECT_EQ(states, (std::vector<std::string>{"damper.s_rel", "damper.v_rel"}));
  // What the states do not need: the wall's reaction force and the damper's heat.
  std::vector<std::string> pruned = b.report.pruned;
  std::sort(pruned.begin(), pruned.end());
  EXPECT_EQ(pruned, (std::vector<std::string>{"damper.lossPower", "wall.flange.f"}));
  // The outputs are the states' values: the damped oscillator x'' + 0.5x' + 4x = 0 with
  // x(0) = 1 (s_rel = m.s - wall), x'(0) = 0.
  testing::Trajectory tr = testing::RunDefault(b);
  const double w0 = 2, zeta = 0.5 / (2 * w0), wd = w0 * std::sqrt(1 - zeta * zeta);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row];
    double x = std::exp(-zeta * w0 * t) * (std::cos(wd * t) + zeta * w0 / wd * std::sin(wd * t));
    EXPECT_NEAR(tr.Column("damper.s_rel", row), x, 1e-4) << t;
  }
}

const char* kGrams = R"(
model: Grams
parameters:
  m: {value: 500, unit: g}
variables:
  x: {start: 0, fixed: true}
  y: {}
equations: [der(x) = m, y = 2*x]
experiment: {stop: 1, interval: 0.5}
)";

TEST(BuildTest, ValuesWithUnitsAreConvertedToTheDeclaredUnit) {
  BuildOptions options;
  options.overrides["m"] = 2.0;  // 2 kg in SI, as -p m=2kg gives it
  options.override_units["m"] = Quantity{2.0, "kg"};
  BuildReport report;
  BuildModel(LoadModelString(kGrams, "grams.yaml"), BuiltinLibrary(), options, &report);
  EXPECT_EQ(report.overrides.at("m"), 2000.0);
  // A unit of another dimension is the user's mistake, named with both units.
  options.override_units["m"] = Quantity{2.0, "m"};
  BuildReport failed;
  try {
    BuildModel(LoadModelString(kGrams, "grams.yaml"), BuiltinLibrary(), options, &failed);
    ADD_FAILURE() << "a length for a mass was taken";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("-p m=2 m: m is in g: "), std::string::npos) << e.what();
  }
}

TEST(BuildTest, AddedOutputsFollowTheStatesOfAModelWithoutOutputs) {
  BuildOptions options;
  size_t instances_seen = 99;
  options.add_outputs = [&](const FlatSystem& flat, ModelSpec* spec) {
    instances_seen = flat.instances.size();
    OutputSpec o;
    o.text = "y";
    o.loc = spec->loc;
    o.expr = ParseName("y", spec->loc);
    spec->outputs.push_back(std::move(o));
  };
  BuildReport report;
  auto model = BuildModel(LoadModelString(kGrams, "grams.yaml"), BuiltinLibrary(), options, &report);
  EXPECT_EQ(instances_seen, 0u);
  EXPECT_EQ(model->output_names, (std::vector<std::string>{"x", "y"}));
  EXPECT_TRUE(report.pruned.empty());  // y is needed now
}

TEST(BuildTest, StartValuesStandingInForInitialConditionsAreWarnedAbout) {
  testing::Built b = testing::BuildYaml(R"(
model: Loose
components:
  m: {type: Mass, s: {start: 2, fixed: true}, v: {start: 3}}
experiment: {stop: 1, interval: 0.5}
outputs: [m.s]
)");
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_NE(b.report.warnings[0].find("m.v"), std::string::npos) << b.report.warnings[0];
  EXPECT_NE(b.report.warnings[0].find("add fixed: true"), std::string::npos);
  EXPECT_EQ(b.model->defaulted_starts, std::vector<std::string>{"m.v"});
  testing::Trajectory tr = testing::RunDefault(b);
  EXPECT_NEAR(tr.Column("m.s", tr.t.size() - 1), 5.0, 1e-6);
  // Fully specified: no warning.
  testing::Built fixed = testing::BuildYaml(R"(
model: Tight
components:
  m: {type: Mass, s: {start: 2, fixed: true}, v: {start: 3, fixed: true}}
outputs: [m.s]
)");
  EXPECT_TRUE(fixed.report.warnings.empty()) << ::testing::PrintToString(fixed.report.warnings);
}

TEST(BuildTest, RedundantInitialConditionsAreCheckedForConsistency) {
  // m2.s is tied to m1.s and the spring's stretch: fixing all three is one too many. The last
  // is left out with a note, and initialisation checks it: 1.5 contradicts 0 + 1, 1 does not.
  auto model = [](const std::string& m2_s) {
    return R"(
model: TooFixed
components:
  m1: {type: Mass, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  sd: {type: SpringDamper, s_rel: {start: 1, fixed: true}}
  m2: {type: Mass, s: {start: )" + m2_s + R"(, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [m1.flange_b, sd.flange_a]
  - [sd.flange_b, m2.flange_a]
outputs: [m2.s]
)";
  };
  testing::Built consistent = testing::BuildYaml(model("1"));
  ASSERT_EQ(consistent.report.notes.size(), 1u);
  EXPECT_EQ(consistent.report.notes[0],
            "initial conditions: the fixed start value of m2.s (test.yaml:6:20) is redundant: it follows from\n"
            "    fixed start value of m1.s (test.yaml:4:20)\n"
            "    fixed start value of sd.s_rel (test.yaml:5:28)\n"
            "  It is left out of the initial system; initialisation checks that it holds.");
  EXPECT_TRUE(consistent.report.warnings.empty()) << ::testing::PrintToString(consistent.report.warnings);
  testing::Trajectory tr = testing::RunDefault(consistent);
  EXPECT_EQ(tr.Column("m2.s", 0), 1.0);

  testing::Built inconsistent = testing::BuildYaml(model("1.5"));
  std::string msg;
  try {
    testing::RunDefault(inconsistent);
  } catch (const ModelError& e) {
    msg = e.what();
  }
  EXPECT_EQ(msg,
            "at initialisation: the initial conditions contradict each other: the fixed start value of m2.s "
            "(test.yaml:6:20) is off by -0.5 at the solution of the others; it follows from\n"
            "    fixed start value of m1.s (test.yaml:4:20)\n"
            "    fixed start value of sd.s_rel (test.yaml:5:28)\n"
            "  Make the fixed start values consistent, or set fixed: false on it.");
}

TEST(BuildTest, CompiledModelIsConsistent) {
  testing::Built b = testing::BuildFile("models/spring_damper_chain.yaml", {{"n", 3}});
  const CompiledModel& m = *b.model;
  const size_t n = m.num_unknowns();
  EXPECT_EQ(m.is_state.size(), n);
  EXPECT_EQ(m.residual_exprs.size(), n);
  EXPECT_EQ(m.residual_equations.size(), n);
  EXPECT_EQ(m.nominal.size(), n);
  EXPECT_EQ(m.jacobian_pattern.rows, static_cast<int32_t>(n));
  EXPECT_EQ(m.jacobian_pattern.cols, static_cast<int32_t>(n));
  EXPECT_EQ(m.jacobian_pattern.col_start.back(), static_cast<int32_t>(m.jacobian_pattern.nnz()));
  EXPECT_EQ(m.init_pattern.rows, static_cast<int32_t>(n + m.num_states()));
  EXPECT_EQ(m.initial_exprs.size(), m.initial_origin.size());
  // Square initialisation system.
  EXPECT_EQ(n + m.initial_exprs.size(), n + m.num_states());
  for (uint32_t s = 0; s < m.num_states(); ++s) EXPECT_TRUE(m.is_state[m.state_y[s]]);
  // Every state named in the report, in y order.
  ASSERT_EQ(b.report.states.size(), m.num_states());
  for (uint32_t s = 0; s < m.num_states(); ++s) {
    EXPECT_EQ(b.report.states[s], m.flat->VariableName(VarId(m.unknowns[m.state_y[s]].value())));
  }
}

}  // namespace
}  // namespace momenta

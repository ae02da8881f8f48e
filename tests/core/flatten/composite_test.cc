// Composite component types: parts and connections inside a type, three levels deep, with
// parameters flowing down as expressions; full dotted paths in outputs, -p and messages; a model
// reused as a component through `uses:`; a library file in `uses:`; type cycles; and the errors of
// connections inside a type.
//
// The physics reference is the damped oscillator: a mass m on a spring-damper (k, d) from a wall,
// released from x0 at rest, has x(t) = e^{-ζωt} (x0 cos ω_d t + ζω x0/ω_d sin ω_d t) and
// v(t) = -x0 ω²/ω_d e^{-ζωt} sin ω_d t, with ω² = k/m, ζ = d/(2√(km)), ω_d = ω√(1-ζ²).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "core/base/error.h"
#include "core/flatten/flat_system.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

struct Damped {
  double m, k, d, x0;
  double X(double t) const {
    const double w = std::sqrt(k / m), z = d / (2 * std::sqrt(k * m)), wd = w * std::sqrt(1 - z * z);
    return std::exp(-z * w * t) * (x0 * std::cos(wd * t) + z * w * x0 / wd * std::sin(wd * t));
  }
  double V(double t) const {
    const double w = std::sqrt(k / m), z = d / (2 * std::sqrt(k * m)), wd = w * std::sqrt(1 - z * z);
    return -x0 * w * w / wd * std::exp(-z * w * t) * std::sin(wd * t);
  }
  double Force(double t) const { return k * X(t) + d * V(t); }
};

// Model -> Rig -> Pair -> Cell -> Mass: the masses are five names deep.
const char* kNested = R"(model: Nested
define:
  Cell:
    doc: a mass held by a spring-damper from the cell's flange
    parameters: {m: 1, k: 100, d: 0.5, x0: 0.1}
    connectors: {flange: Flange}
    components:
      mass: {type: Mass, m: m, s: {start: x0, fixed: true}, v: {start: 0, fixed: true}}
      spring: {type: SpringDamper, c: k, d: d}
    connections:
      - [flange, spring.flange_a]
      - [spring.flange_b, mass.flange_a]
  Pair:
    parameters: {k: 100}
    connectors: {flange: Flange}
    components:
      a: {type: Cell, k: k}
      b: {type: Cell, k: 2*k, m: 2}
    connections:
      - [flange, a.flange]
      - [flange, b.flange]
  Rig:
    parameters: {k: 50}
    components:
      wall: {type: Fixed}
      pair: {type: Pair, k: k}
    connections:
      - [wall.flange, pair.flange]
components:
  rig: {type: Rig}
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [rig.pair.a.mass.s, rig.pair.b.mass.s, rig.pair.b.mass.v, rig.wall.flange.f]
)";

// rtol 1e-10 on motions of amplitude 0.1 and forces of amplitude 15: 1e-8 and 1e-6 leave room for
// the global error accumulated over about three periods.
constexpr double kPositionTol = 1e-8, kSpeedTol = 1e-7, kForceTol = 1e-6;

void ExpectCells(const testing::Trajectory& tr, const Damped& a, const Damped& b) {
  ASSERT_EQ(tr.t.size(), 201u);
  for (size_t r = 0; r < tr.t.size(); ++r) {
    const double t = tr.t[r];
    EXPECT_NEAR(tr.Column("rig.pair.a.mass.s", r), a.X(t), kPositionTol) << "t = " << t;
    EXPECT_NEAR(tr.Column("rig.pair.b.mass.s", r), b.X(t), kPositionTol) << "t = " << t;
    EXPECT_NEAR(tr.Column("rig.pair.b.mass.v", r), b.V(t), kSpeedTol) << "t = " << t;
    // The wall holds both spring-dampers: its flange force is the sum of theirs.
    EXPECT_NEAR(tr.Column("rig.wall.flange.f", r), a.Force(t) + b.Force(t), kForceTol) << "t = " << t;
  }
}

TEST(CompositeTest, ThreeLevelsDeepAgainstTheDampedOscillator) {
  testing::Built b = testing::BuildYaml(kNested);
  // Rig.k = 50 flows down: cell a has k = 50, cell b 2*50 and m = 2.
  ExpectCells(testing::RunDefault(b), {1, 50, 0.5, 0.1}, {2, 100, 0.5, 0.1});
}

TEST(CompositeTest, OverridesReachEveryLevel) {
  testing::Built b = testing::BuildYaml(kNested);
  // A parameter of the model's component, and one four names down.
  ExpectCells(testing::RunDefault(b, {{"rig.k", 80}, {"rig.pair.a.mass.m", 3}}), {3, 80, 0.5, 0.1},
              {2, 160, 0.5, 0.1});
  // A part's own default when nothing above sets it.
  ExpectCells(testing::RunDefault(b, {{"rig.pair.b.x0", 0.05}, {"rig.pair.a.d", 2}}), {1, 50, 2, 0.1},
              {2, 100, 0.5, 0.05});
}

TEST(CompositeTest, NamesAreFullPaths) {
  testing::Built b = testing::BuildYaml(kNested);
  const FlatSystem& flat = *b.model->flat;
  std::set<std::string> vars, params, instances;
  for (uint32_t k = 0; k < flat.variables.size(); ++k) vars.insert(flat.VariableName(VarId(k)));
  for (uint32_t k = 0; k < flat.parameters.size(); ++k) params.insert(flat.ParameterName(ParamId(k)));
  for (uint32_t k = 0; k < flat.instances.size(); ++k) {
    instances.insert(flat.InstancePath(InstanceId(k)) + " " + flat.instances[k].type->name);
  }
  EXPECT_TRUE(vars.count("rig.pair.a.spring.flange_b.f"));
  EXPECT_TRUE(vars.count("rig.pair.flange.s"));
  EXPECT_TRUE(params.count("rig.pair.b.spring.c"));
  EXPECT_TRUE(instances.count("rig.pair.b.mass Mass"));
  EXPECT_TRUE(instances.count("rig.pair.a Cell"));
  EXPECT_EQ(instances.size(), 9u);  // rig, rig.wall, rig.pair, rig.pair.a and its mass and spring, b alike
}

// Names and texts are made on demand from each type's names (FlatSystem::VariableName, ...): the
// parts' names carry their paths at every depth, every parameter is found by its name, and the
// inner connections of a part name the part's connectors from the model's component down.
TEST(CompositeTest, NamesMadeOnDemandCarryEveryPath) {
  testing::Built b = testing::BuildYaml(kNested);
  const FlatSystem& flat = *b.model->flat;
  std::set<std::string> vars;
  for (uint32_t k = 0; k < flat.variables.size(); ++k) vars.insert(flat.VariableName(VarId(k)));
  EXPECT_EQ(vars.size(), flat.variables.size());  // no two alike
  for (uint32_t k = 0; k < flat.parameters.size(); ++k) {
    EXPECT_EQ(flat.FindParameter(flat.ParameterName(ParamId(k))), ParamId(k)) << flat.ParameterName(ParamId(k));
  }
  for (const char* none : {"rig.pair.a.mass", "rig.pair.a.mass.mm", "rig", "rig.", "pair.a.mass.m", ""}) {
    EXPECT_FALSE(flat.FindParameter(none)) << none;
  }
  const ParamId m = *flat.FindParameter("rig.pair.a.mass.m");
  EXPECT_EQ(flat.ParameterUnit(m), "kg");
  EXPECT_EQ(flat.ParameterDoc(m), "mass of the sliding mass");
  std::set<std::string> texts;
  for (const FlatEquation& eq : flat.equations) texts.insert(flat.EquationText(eq));
  EXPECT_TRUE(texts.count("rig.pair.a.spring.flange_b.s = rig.pair.a.mass.flange_a.s (connection)"));
  EXPECT_TRUE(texts.count("rig.pair.b.mass.flange_b.f = 0 (unconnected)"));
}

std::string BuildError(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  try {
    testing::Built b = testing::BuildYaml(yaml, overrides);
    testing::RunDefault(b, overrides);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(CompositeTest, MessagesNameTheFullPath) {
  EXPECT_EQ(BuildError(kNested, {{"rig.pair.a.mass.m", -1}}),
            "test.yaml: -p rig.pair.a.mass.m: rig.pair.a.mass.m (Mass.m: mass of the sliding mass [kg]) = -1 is "
            "below its minimum 0");
  std::string unknown = BuildError(kNested, {{"rig.pair.a.mass.mm", 1}});
  EXPECT_NE(unknown.find("-p rig.pair.a.mass.mm: no parameter of that name in Nested"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("did you mean rig.pair.a.mass.m"), std::string::npos) << unknown;
  // An output of a name the part does not have.
  std::string yaml = kNested;
  yaml.replace(yaml.find("rig.pair.b.mass.v,"), 18, "rig.pair.b.mass.w,");
  std::string out = BuildError(yaml);
  EXPECT_NE(out.find("rig (Rig) has no variable or parameter 'pair.b.mass.w'"), std::string::npos) << out;
}

TEST(CompositeTest, ATypeThatContainsItselfIsACycle) {
  const char* yaml = R"(model: Loop
define:
  A:
    components:
      b: {type: B}
  B:
    components:
      c: {type: C}
  C:
    components:
      a: {type: A}
components:
  top: {type: A}
)";
  EXPECT_EQ(BuildError(yaml), "test.yaml:11:17: type A contains itself: A -> B -> C -> A; a type cannot be a part of itself");
  const char* direct = R"(model: Self
define:
  A:
    components:
      again: {type: A}
components:
  top: {type: A}
)";
  EXPECT_EQ(BuildError(direct), "test.yaml:5:21: type A contains itself: A -> A; a type cannot be a part of itself");
}

TEST(CompositeTest, ConnectionErrorsInsideAType) {
  auto with = [](const std::string& connections) {
    return "model: M\n"
           "define:\n"
           "  Box:\n"
           "    connectors: {flange: Flange}\n"
           "    components:\n"
           "      mass: {type: Mass}\n"
           "      gain: {type: Gain}\n"
           "      source: {type: Constant}\n"
           "    connections:\n" + connections +
           "components:\n"
           "  box: {type: Box}\n"
           "  wall: {type: Fixed}\n"
           "connections:\n"
           "  - [wall.flange, box.flange]\n";
  };
  EXPECT_EQ(BuildError(with("      - [flange, mass.flange_c]\n      - [source.y, gain.u]\n")),
            "test.yaml:10:18: unknown connector 'mass.flange_c' in connection end 'mass.flange_c' of Box (did "
            "you mean mass.flange_a, mass.flange_b?) (its own connectors are named alone, its parts' like "
            "mass.flange_a; valid: flange, mass.flange_a, mass.flange_b, gain.u, gain.y, source.y)");
  EXPECT_EQ(BuildError(with("      - [flange, mass.flange_a]\n")),
            "test.yaml:7:13: the signal input gain.u inside Box is connected to nothing; connect it to an output "
            "or to an input of Box");
  EXPECT_EQ(BuildError(with("      - [flange, gain.u]\n      - [source.y, gain.u]\n")),
            "test.yaml:10:10: cannot connect flange (Flange) to gain.u (RealInput) in Box: connectors of "
            "different kinds");
}

TEST(CompositeTest, ArraysOfPartsAndTheirIndex) {
  // A chain of n masses inside a type, each a spring from the one before; the first on the
  // type's flange. Modifiers may use the element index i.
  const char* yaml = R"(model: Chain
define:
  Chain3:
    parameters: {k: 10}
    connectors: {flange: Flange}
    components:
      m: {type: Mass, count: 3, m: i}
      s: {type: Spring, count: 3, c: k*i}
    connections:
      - [flange, "s[1].flange_a"]
      - for: j in 1:3
        connect: ["s[j].flange_b", "m[j].flange_a"]
      - for: j in 1:2
        connect: ["m[j].flange_b", "s[j+1].flange_a"]
components:
  wall: {type: Fixed}
  chain: {type: Chain3}
connections:
  - [wall.flange, chain.flange]
outputs: ["chain.m[3].s", "chain.s[2].c"]
)";
  testing::Built b = testing::BuildYaml(yaml);
  const FlatSystem& flat = *b.model->flat;
  std::vector<double> values = EvaluateParameters(flat, {});
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    if (flat.ParameterName(ParamId(k)) == "chain.m[2].m") EXPECT_EQ(values[k], 2);
    if (flat.ParameterName(ParamId(k)) == "chain.s[3].c") EXPECT_EQ(values[k], 30);
  }
  EXPECT_EQ(b.model->num_states(), 6u);
  const char* bad = R"(model: Bad
define:
  Many:
    parameters: {n: 3}
    components:
      m: {type: Mass, count: n}
components:
  x: {type: Many}
)";
  EXPECT_EQ(BuildError(bad),
            "test.yaml:6:10: count of m in Many must be a number: a type's structure is fixed, so its parameters "
            "cannot size its parts, found 'n'");
}

TEST(CompositeTest, AnArrayOfCompositesInTheModel) {
  // Three cells on one wall, each element reached by index in connections, outputs and -p; the
  // elements' stiffness 50*i makes each its own damped oscillator.
  const char* yaml = R"(model: Cells
define:
  Cell:
    parameters: {m: 1, k: 100, d: 0.5, x0: 0.1}
    connectors: {flange: Flange}
    components:
      mass: {type: Mass, m: m, s: {start: x0, fixed: true}, v: {start: 0, fixed: true}}
      spring: {type: SpringDamper, c: k, d: d}
    connections:
      - [flange, spring.flange_a]
      - [spring.flange_b, mass.flange_a]
components:
  wall: {type: Fixed}
  cells: {type: Cell, count: 3, k: 50*i}
connections:
  - for: j in 1:3
    connect: [wall.flange, "cells[j].flange"]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: ["cells[1].mass.s", "cells[2].mass.s", "cells[3].mass.s"]
)";
  testing::Built b = testing::BuildYaml(yaml);
  testing::Trajectory tr = testing::RunDefault(b, {{"cells[3].mass.m", 2}});
  const Damped cells[] = {{1, 50, 0.5, 0.1}, {1, 100, 0.5, 0.1}, {2, 150, 0.5, 0.1}};
  ASSERT_EQ(tr.t.size(), 101u);
  for (size_t r = 0; r < tr.t.size(); ++r) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(tr.values[r][k], cells[k].X(tr.t[r]), kPositionTol) << "cell " << k + 1 << ", t = " << tr.t[r];
    }
  }
}

TEST(CompositeTest, HierarchiesThatCannotBeBuiltAreRefusedAtOnce) {
  // Types nested 70 deep, one part each.
  std::string deep = "model: Deep\ndefine:\n  T0: {components: {m: {type: Mass}}}\n";
  for (int k = 1; k < 70; ++k) {
    deep += "  T" + std::to_string(k) + ": {components: {p: {type: T" + std::to_string(k - 1) + "}}}\n";
  }
  deep += "components:\n  top: {type: T69}\n";
  std::string message = BuildError(deep);
  EXPECT_NE(message.find("types nested deeper than 64 levels: T69 -> T68 -> "), std::string::npos) << message;
  // Twenty levels of two parts each: a million masses from a few lines.
  std::string bomb = "model: Bomb\ndefine:\n  T0: {components: {m: {type: Mass}}}\n";
  for (int k = 1; k <= 20; ++k) {
    const std::string below = "T" + std::to_string(k - 1);
    bomb += "  T" + std::to_string(k) + ": {components: {a: {type: " + below + "}, b: {type: " + below + "}}}\n";
  }
  bomb += "components:\n  top: {type: T20}\n";
  message = BuildError(bomb);
  EXPECT_NE(message.find("has more than 250000 variables; parts of parts multiply"), std::string::npos) << message;
  // A range inside a type beyond what doubles count.
  const char* range = R"(model: Range
define:
  Two:
    components:
      a: {type: Mass}
      b: {type: Mass}
    connections:
      - for: k in 1e17:1e17
        connect: [a.flange_b, b.flange_a]
components:
  t: {type: Two}
)";
  EXPECT_EQ(BuildError(range),
            "test.yaml:8:14: the range of 'for: k in 1e17:1e17' inside Two must have whole-number bounds below "
            "2^53 (a type's structure is fixed)");
}

TEST(CompositeTest, AModelConnectsToAPartOnlyThroughTheTypesConnectors) {
  const char* yaml = R"(model: Reach
define:
  Box:
    components:
      m: {type: Mass}
components:
  wall: {type: Fixed}
  box: {type: Box}
connections:
  - [wall.flange, box.m.flange_a]
)";
  EXPECT_EQ(BuildError(yaml),
            "test.yaml:10:19: 'box.m.flange_a' reaches into box; a model connects to a component's own connectors "
            "only (a composite type exposes a part's connector by connecting it to one of its own)");
}

/// A directory with the given files, removed at the end of the test.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("momenta-composite-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

TEST(CompositeTest, AModelFromAUsesFileIsAComponent) {
  TempDir dir;
  // An ordinary model file: simulated alone, it is one oscillator.
  dir.Write("oscillator.yaml", R"(model: Oscillator
parameters: {k: 100, m: 1}
components:
  wall: {type: Fixed}
  spring: {type: SpringDamper, c: k, d: 0.5}
  mass: {type: Mass, m: m, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
experiment: {stop: 1}
outputs: [mass.s]
)");
  // A library file of the user's, in a subdirectory.
  std::filesystem::create_directories(dir.path / "lib");
  dir.Write("lib/parts.yaml", R"(Doubled:
  parameters: {k: 1}
  components:
    inner: {type: Oscillator, k: 2*k}
)");
  std::string main = dir.Write("main.yaml", R"(model: Two
uses: [oscillator.yaml, lib/parts.yaml]
components:
  one: {type: Oscillator, k: 50}
  two: {type: Doubled, k: 50}
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [one.mass.s, two.inner.mass.s]
)");
  testing::Built b;
  ModelSpec spec = LoadModelFile(main);
  b.model = BuildModel(spec, BuiltinLibrary(), {}, &b.report);
  testing::Trajectory tr = testing::RunDefault(b);
  Damped one{1, 50, 0.5, 0.1}, two{1, 100, 0.5, 0.1};
  ASSERT_EQ(tr.t.size(), 201u);
  for (size_t r = 0; r < tr.t.size(); ++r) {
    EXPECT_NEAR(tr.Column("one.mass.s", r), one.X(tr.t[r]), kPositionTol);
    EXPECT_NEAR(tr.Column("two.inner.mass.s", r), two.X(tr.t[r]), kPositionTol);
  }
  // A file that is not there, and a type defined twice.
  std::string twice = dir.Write("twice.yaml", "model: T\nuses: [oscillator.yaml]\ndefine:\n  Oscillator:\n    doc: mine\n");
  try {
    ModelSpec t = LoadModelFile(twice);
    BuildReport report;
    BuildModel(t, BuiltinLibrary(), {}, &report);
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("twice.yaml:5:5: type Oscillator is defined twice (also at "),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("oscillator.yaml:1:1)"), std::string::npos) << e.what();
  }
  std::string missing = dir.Write("missing.yaml", "model: M\nuses: [nowhere.yaml]\n");
  try {
    LoadModelFile(missing);
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.yaml:2:8: uses: no file 'nowhere.yaml' (looked for "),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace momenta

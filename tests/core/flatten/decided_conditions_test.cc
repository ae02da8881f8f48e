// Conditional connectors decided when the instances are made (core/flatten/decided_conditions.h):
// an MSL heat port left off by default is not made into equations the passes would remove, and
// the model builds and runs as when the passes decide it; whatever can change the condition (a
// modifier, an element's modifier of an array, a -p) leaves it to the passes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/flatten/equation_template.h"
#include "core/flatten/flat_system.h"
#include "core/flatten/flatten.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

FlatSystem FlattenYaml(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  ModelSpec spec = LoadModelString(yaml, "test.yaml");
  return Flatten(spec, BuiltinLibrary(), overrides);
}

/// A sine source driving R1 and an array R of three resistors in series to ground; `r1` and
/// `r` add keys to their entries, `more` adds components and connections.
std::string Circuit(const std::string& r1 = "", const std::string& r = "", const std::string& more_components = "",
                    const std::string& more_connections = "") {
  return R"(model: Heated
components:
  ground: {type: Ground}
  source: {type: SineVoltage, V: 2, f: 5}
  R1: {type: Resistor, R: 2)" + r1 + R"(}
  R: {type: Resistor, count: 3, R: "i")" + r + R"(}
  C: {type: Capacitor, C: 0.01, v: {start: 0, fixed: true}}
)" + more_components + R"(connections:
  - [source.n, ground.p]
  - [source.p, R1.p]
  - [R1.n, "R[1].p"]
  - for: i in 1:2
    connect: ["R[i].n", "R[i+1].p"]
  - ["R[3].n", C.p]
  - [C.n, ground.p]
)" + more_connections + R"(experiment: {stop: 0.5, tolerance: 1e-9, interval: 0.01}
outputs: [C.v, R1.i]
)";
}

/// Whether a template holds an if-expression.
bool HoldsIf(const Template& t) {
  return std::any_of(t.nodes.begin(), t.nodes.end(), [](const TNode& n) { return n.kind == TNode::kOp && n.op == Op::kIf; });
}

/// The decided values of the model's conditional connectors, in their order.
std::string Decided(const FlatSystem& flat) {
  std::string s;
  for (const FlatConditionalConnector& cc : flat.conditional_connectors) s += std::to_string(cc.decided) + " ";
  return s;
}

size_t EquationsNaming(const FlatSystem& flat, const std::string& what) {
  size_t n = 0;
  for (const FlatEquation& e : flat.equations) n += flat.EquationText(e).find(what) != std::string::npos;
  return n;
}

TEST(DecidedConditionsTest, AHeatPortLeftOffIsNotMade) {
  const FlatSystem flat = FlattenYaml(Circuit());
  EXPECT_EQ(Decided(flat), "0 0 0 0 ");
  // Neither the equation that holds only with the port nor its unconnected flow's is made...
  EXPECT_EQ(EquationsNaming(flat, "heatPort.Q_flow"), 0u);
  // ...and the device temperature is T, folded when the instances are made: no if-expression and
  // no heat port variable is left in it.
  size_t folded = 0;
  for (const FlatEquation& e : flat.equations) {
    if (flat.EquationText(e).find("T_heatPort = if useHeatPort") == std::string::npos) continue;
    ++folded;
    ASSERT_TRUE(e.residual.valid());
    EXPECT_FALSE(flat.pool->HasIf(e.residual));
    const std::string text = ToString(*flat.pool, e.residual, flat.Namer());
    EXPECT_EQ(text.find("heatPort."), std::string::npos) << text;
    EXPECT_EQ(text.substr(text.size() - 2), ".T") << text;
  }
  EXPECT_EQ(folded, 4u);
  EXPECT_EQ(flat.conditions_decided, 4u);
}

TEST(DecidedConditionsTest, WhatCanChangeTheConditionLeavesItToThePasses) {
  // A modifier of the component, a modifier of an array's elements, and a -p.
  EXPECT_EQ(Decided(FlattenYaml(Circuit(", useHeatPort: false"))), "-1 0 0 0 ");
  EXPECT_EQ(Decided(FlattenYaml(Circuit("", ", useHeatPort: \"i == 2\""))), "0 -1 -1 -1 ");
  // A -p of a parameter of that name, of any component: every instance of a type that has one
  // (the overrides are read per type layout, not per instance).
  EXPECT_EQ(Decided(FlattenYaml(Circuit(), {{"R1.useHeatPort", 0}})), "-1 -1 -1 -1 ");
  EXPECT_EQ(Decided(FlattenYaml(Circuit(), {{"R[2].useHeatPort", 0}})), "-1 -1 -1 -1 ");
}

// Decided when made or by the passes, the model is the same: its report and its results, to the
// bit (the same operations), and a heated element among decided ones takes its loss power.
TEST(DecidedConditionsTest, DecidedOrLeftToThePassesTheResultsAreTheSame) {
  const testing::Built made = testing::BuildYaml(Circuit());
  const testing::Built passes = testing::BuildYaml(Circuit(", useHeatPort: false", ", useHeatPort: false"));
  ASSERT_EQ(made.report.passes.size(), passes.report.passes.size());
  for (size_t k = 1; k < made.report.passes.size(); ++k) {  // after flattening, which makes fewer equations
    EXPECT_EQ(made.report.passes[k].note, passes.report.passes[k].note) << made.report.passes[k].name;
    EXPECT_EQ(made.report.passes[k].variables, passes.report.passes[k].variables) << made.report.passes[k].name;
    EXPECT_EQ(made.report.passes[k].equations, passes.report.passes[k].equations) << made.report.passes[k].name;
  }
  EXPECT_NE(made.report.passes[1].note.find("4 conditions on Boolean or Integer parameters fixed, 4 conditional "
                                            "connectors absent"),
            std::string::npos)
      << made.report.passes[1].note;
  const testing::Trajectory a = testing::RunDefault(made), b = testing::RunDefault(passes);
  ASSERT_EQ(a.t.size(), b.t.size());
  for (size_t k = 0; k < a.t.size(); ++k) {
    EXPECT_EQ(a.t[k], b.t[k]);
    EXPECT_EQ(a.values[k], b.values[k]) << "row " << k;
  }

  // R[2] heated into a heat capacitor, the others decided: the capacitor takes the loss power
  // R i^2 of R[2] (R = 2), and the circuit's current is unchanged (alpha = 0).
  const std::string heated = Circuit("", ", useHeatPort: \"i == 2\"",
                                     "  heat: {type: HeatCapacitor, C: 1, T: {start: 300, fixed: true}}\n",
                                     "  - [\"R[2].heatPort\", heat.port]\n");
  std::string with_outputs = heated;
  with_outputs.replace(with_outputs.find("outputs: [C.v, R1.i]"), 20, "outputs: [C.v, R1.i, heat.T, \"R[2].LossPower\"]");
  const testing::Trajectory h = testing::RunDefault(testing::BuildYaml(with_outputs));
  ASSERT_EQ(h.t.size(), a.t.size());
  double energy = 0;  // the trapezoidal integral of R i^2, at the output rows
  for (size_t k = 0; k < h.t.size(); ++k) {
    // The current is the same to the integration tolerance (1e-9 of amplitudes of about 0.1 A).
    EXPECT_NEAR(h.Column("R1.i", k), a.Column("R1.i", k), 1e-7) << "t = " << h.t[k];
    const double i = h.Column("R1.i", k);
    EXPECT_NEAR(h.Column("R[2].LossPower", k), 2 * i * i, 1e-7);
    if (k > 0) {
      const double i0 = h.Column("R1.i", k - 1);
      energy += 0.5 * (h.t[k] - h.t[k - 1]) * 2 * (i * i + i0 * i0);
    }
  }
  // The heat capacitor's temperature rise is the energy in J (C = 1 J/K). The trapezoid over
  // 50 rows of a 5 Hz current squared: its error is below 1 % of the energy.
  const double rise = h.Column("heat.T", h.t.size() - 1) - 300;
  EXPECT_GT(energy, 0.01);
  EXPECT_NEAR(rise, energy, 0.01 * energy);
}

// A connection to a heat port decided absent is the passes' error, with the same words.
TEST(DecidedConditionsTest, ConnectingADecidedAbsentPortIsTheSameError) {
  const std::string msg = testing::BuildError(Circuit("", "", "  hot: {type: FixedTemperature, T: 350}\n",
                                                      "  - [R1.heatPort, hot.port]\n"));
  EXPECT_NE(msg.find("test.yaml:17:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot connect R1.heatPort: R1 (Resistor) has the connector heatPort only when useHeatPort "
                     "is true, and R1.useHeatPort is false; set useHeatPort: true in R1's entry"),
            std::string::npos)
      << msg;
}

/// A model of one `Heater` (a resistor of 2 Ohm on a 1 V source, with a heat port that is off by
/// default) whose type adds `equations` (over v, i, y and T_port) and `impact`; `entry` adds keys to
/// its component entry.
std::string Heater(const std::string& equations, const std::string& entry = "") {
  return R"(model: Heating
define:
  Heater:
    parameters:
      R: {value: 2}
      useHeatPort: {value: false, type: Boolean}
      useOther: {value: true, type: Boolean}
    connectors:
      p: Pin
      n: Pin
      heatPort: {type: Thermal.HeatPort, condition: useHeatPort}
    variables: {v: {}, i: {}, y: {}, T_port: {}}
    equations:
      - v = p.v - n.v
      - 0 = p.i + n.i
      - i = p.i
      - v = R*i
      - heatPort.Q_flow = -v*i
)" + equations + R"(components:
  ground: {type: Ground}
  source: {type: ConstantVoltage, V: 1}
  h: {type: Heater)" + entry + R"(}
connections:
  - [source.n, ground.p]
  - [source.p, h.p]
  - [h.n, ground.p]
experiment: {stop: 0.1, interval: 0.05}
outputs: [h.i, h.y, h.T_port]
)";
}

// What the pool folds, or only the passes fold, decides as the passes decide: a guard that reads
// another parameter too (`useHeatPort and useOther`), a condition folded through a product
// (`0*heatPort.T` names nothing), a condition read outside an if (`useHeatPort*...`). Each builds
// and runs as when the component entry sets useHeatPort (the passes decide), to the bit.
TEST(DecidedConditionsTest, WhatOnlyThePassesFoldIsLeftToThem) {
  const std::vector<std::string> cases = {
      // A conditional block whose guard reads another Boolean parameter: its false branch only.
      "      - if: useHeatPort and useOther\n        then: [y = 1, T_port = heatPort.T]\n"
      "        else: [y = 2, T_port = 300]\n",
      // A condition folded into a factor: the port's temperature is multiplied away.
      "      - T_port = 300 + (if useHeatPort then 1 else 0)*(heatPort.T - 300)\n      - y = 2\n",
      // The condition read as a number.
      "      - y = 2 + (if useHeatPort then 1 else 0)\n      - T_port = 300\n",
  };
  for (const std::string& eqs : cases) {
    const std::string& text = eqs;
    const testing::Built decided = testing::BuildYaml(Heater(text));
    const testing::Built passes = testing::BuildYaml(Heater(text, ", useHeatPort: false"));
    ASSERT_EQ(decided.report.passes.size(), passes.report.passes.size()) << text;
    for (size_t k = 1; k < decided.report.passes.size(); ++k) {
      EXPECT_EQ(decided.report.passes[k].equations, passes.report.passes[k].equations) << text;
    }
    const testing::Trajectory a = testing::RunDefault(decided), b = testing::RunDefault(passes);
    ASSERT_EQ(a.t.size(), b.t.size()) << text;
    for (size_t k = 0; k < a.t.size(); ++k) EXPECT_EQ(a.values[k], b.values[k]) << text;
    EXPECT_EQ(a.Column("h.i", 0), 0.5) << text;
    EXPECT_EQ(a.Column("h.y", 0), 2) << text;
    EXPECT_EQ(a.Column("h.T_port", 0), 300) << text;
  }
}

// An impact's contact law is made outside the type's templates: an impact that names the
// connector leaves it to the passes.
TEST(DecidedConditionsTest, AnImpactThatNamesTheConnectorLeavesItToThePasses) {
  const std::string stop = R"(model: Stopped
define:
  Stop:
    parameters: {useSupport: {value: false, type: Boolean}, e: {value: 0.5}}
    connectors: {flange_a: Flange, support: {type: Flange, condition: useSupport}}
    variables: {v_rel: {}, f: {}, contact: {type: Boolean, start: false}}
    equations:
      - v_rel = der(flange_a.s)
      - flange_a.f = f
      - support.f = -f
    impact: {gap: GAP, velocity: v_rel, force: f, restitution: e, contact: contact, release: f > 0, v_small: 1e-3}
components:
  stop: {type: Stop}
)";
  std::string named = stop, unnamed = stop;
  named.replace(named.find("GAP"), 3, "flange_a.s - support.s");
  unnamed.replace(unnamed.find("GAP"), 3, "flange_a.s");
  EXPECT_EQ(Decided(FlattenYaml(named)), "-1 ");
  EXPECT_EQ(Decided(FlattenYaml(unnamed)), "0 ");
}

// FixLocalParameters folds what a fixed parameter decides, as the pool folds its copies, and
// keeps only what the root reaches, the root last.
TEST(DecidedConditionsTest, FixLocalParametersFoldsTheIfAndDropsWhatIsNotReached) {
  // T_heatPort - (if not useHeatPort then T else heatPort.T): local variables 0 (T_heatPort) and
  // 1 (heatPort.T), parameters 0 (useHeatPort) and 1 (T).
  Template t;
  auto add = [&](TNode n) {
    t.nodes.push_back(n);
    return static_cast<int32_t>(t.nodes.size() - 1);
  };
  auto leaf = [&](TNode::Kind kind, uint32_t local) {
    TNode n;
    n.kind = kind;
    n.local = local;
    return add(n);
  };
  auto op = [&](Op o, int32_t a, int32_t b = -1, int32_t c = -1) {
    TNode n;
    n.kind = TNode::kOp;
    n.op = o;
    n.a = a;
    n.b = b;
    n.c = c;
    return add(n);
  };
  const int32_t x = leaf(TNode::kLocalVar, 0), use = leaf(TNode::kLocalParam, 0);
  const int32_t cond = op(Op::kNot, use);
  const int32_t iff = op(Op::kIf, cond, leaf(TNode::kLocalParam, 1), leaf(TNode::kLocalVar, 1));
  t.root = op(Op::kSub, x, iff);

  std::vector<int32_t> folded;
  const Template off = FixLocalParameters(t, {0.0, std::nan("")}, &folded);
  ASSERT_EQ(off.nodes.size(), 3u);  // T_heatPort, T, their difference
  EXPECT_EQ(off.root, 2);
  EXPECT_EQ(off.nodes[1].kind, TNode::kLocalParam);
  EXPECT_EQ(off.nodes[1].local, 1u);
  EXPECT_EQ(off.nodes[2].a, 0);
  EXPECT_EQ(off.nodes[2].b, 1);
  EXPECT_EQ(folded, std::vector<int32_t>{cond});
  EXPECT_FALSE(NamesLocalVariables(off, 1, 1));
  EXPECT_FALSE(HoldsIf(off));

  const Template on = FixLocalParameters(t, {1.0, std::nan("")}, nullptr);
  ASSERT_EQ(on.nodes.size(), 3u);  // T_heatPort, heatPort.T, their difference
  EXPECT_TRUE(NamesLocalVariables(on, 1, 1));
  // Nothing fixed: the template as it was.
  const Template same = FixLocalParameters(t, {std::nan(""), std::nan("")}, nullptr);
  EXPECT_EQ(same.nodes.size(), t.nodes.size());
  EXPECT_TRUE(HoldsIf(same));
}

}  // namespace
}  // namespace momenta

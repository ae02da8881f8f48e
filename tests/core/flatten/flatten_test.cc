// Flattening: connection sets (potentials equal, flows sum to zero), unconnected flows, signal
// connections, arrays with count and `for:` connections, the index `i` in parameter expressions,
// model parameters that reference each other, and the errors for parameter cycles.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "core/expr/expr_eval.h"
#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

FlatSystem FlattenYaml(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  ModelSpec spec = LoadModelString(yaml, "test.yaml");
  return Flatten(spec, BuiltinLibrary(), overrides);
}

std::string FlattenError(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  try {
    FlatSystem flat = FlattenYaml(yaml, overrides);
    EvaluateParameters(flat, overrides);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

VarId FindVar(const FlatSystem& flat, const std::string& name) {
  for (size_t k = 0; k < flat.variables.size(); ++k) {
    if (flat.VariableName(VarId(k)) == name) return VarId(k);
  }
  ADD_FAILURE() << "no variable " << name;
  return VarId();
}

ParamId FindParam(const FlatSystem& flat, const std::string& name) {
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    if (flat.ParameterName(ParamId(k)) == name) return ParamId(k);
  }
  ADD_FAILURE() << "no parameter " << name;
  return ParamId();
}

std::vector<const FlatEquation*> WithOrigin(const FlatSystem& flat, EquationOrigin origin) {
  std::vector<const FlatEquation*> out;
  for (const auto& e : flat.equations) {
    if (e.origin == origin) out.push_back(&e);
  }
  return out;
}

/// The residual as {variable name: coefficient}, for affine residuals.
std::map<std::string, double> Terms(const FlatSystem& flat, ExprId residual) {
  AffineForm form;
  EXPECT_TRUE(DecomposeAffine(flat.pool.get(), residual, 1000, &form));
  EXPECT_EQ(form.offset, flat.pool->Zero());
  std::map<std::string, double> out;
  for (auto& [leaf, c] : form.terms) out[flat.VariableName(VarId(flat.pool->node(leaf).a))] = c;
  return out;
}

TEST(FlattenTest, ThreeFlangesInOneSet) {
  // B.flange_a joins A.flange_b and C.flange_a: two potential equalities and one flow sum.
  FlatSystem flat = FlattenYaml(R"(
model: Three
components:
  A: {type: Mass}
  B: {type: Mass}
  C: {type: Mass}
connections:
  - [A.flange_b, B.flange_a]
  - [B.flange_a, C.flange_a]
)");
  auto conn = WithOrigin(flat, EquationOrigin::kConnection);
  ASSERT_EQ(conn.size(), 3u);
  int potentials = 0, flows = 0;
  std::set<std::string> potential_vars;
  for (const FlatEquation* e : conn) {
    auto terms = Terms(flat, e->residual);
    if (terms.size() == 2) {
      // x - y = 0 between two positions of the set.
      ++potentials;
      std::vector<double> coefs;
      for (auto& [name, c] : terms) {
        EXPECT_TRUE(name == "A.flange_b.s" || name == "B.flange_a.s" || name == "C.flange_a.s") << name;
        potential_vars.insert(name);
        coefs.push_back(c);
      }
      EXPECT_EQ(coefs[0] * coefs[1], -1.0);
      EXPECT_NE(flat.EquationText(*e).find("(connection)"), std::string::npos);
    } else {
      ++flows;
      EXPECT_EQ(terms, (std::map<std::string, double>{
                           {"A.flange_b.f", 1}, {"B.flange_a.f", 1}, {"C.flange_a.f", 1}}));
      EXPECT_NE(flat.EquationText(*e).find("sum of f"), std::string::npos) << flat.EquationText(*e);
    }
  }
  EXPECT_EQ(potentials, 2);
  EXPECT_EQ(flows, 1);
  EXPECT_EQ(potential_vars.size(), 3u);
  // The connection equations point at the connection in the file.
  EXPECT_EQ(conn[0]->loc.file(), "test.yaml");
  EXPECT_EQ(conn[0]->loc.line, 8);
}

TEST(FlattenTest, RepeatedConnectionsJoinOneSet) {
  // The same pair twice, and a loop A-B, B-C, C-A: one set each, no duplicate equations.
  FlatSystem once = FlattenYaml(R"(
model: Once
components:
  A: {type: Mass}
  B: {type: Mass}
connections:
  - [A.flange_b, B.flange_a]
)");
  FlatSystem twice = FlattenYaml(R"(
model: Twice
components:
  A: {type: Mass}
  B: {type: Mass}
connections:
  - [A.flange_b, B.flange_a]
  - [B.flange_a, A.flange_b]
)");
  EXPECT_EQ(WithOrigin(twice, EquationOrigin::kConnection).size(),
            WithOrigin(once, EquationOrigin::kConnection).size());
  EXPECT_EQ(twice.equations.size(), once.equations.size());
  FlatSystem loop = FlattenYaml(R"(
model: Loop
components:
  A: {type: Mass}
  B: {type: Mass}
  C: {type: Mass}
connections:
  - [A.flange_b, B.flange_a]
  - [B.flange_a, C.flange_a]
  - [C.flange_a, A.flange_b]
)");
  EXPECT_EQ(WithOrigin(loop, EquationOrigin::kConnection).size(), 3u);  // 2 potentials, 1 flow sum
  EXPECT_NE(FlattenError(R"(
model: Self
components:
  A: {type: Mass}
connections:
  - [A.flange_b, A.flange_b]
)").find("connection of A.flange_b to itself"), std::string::npos);
}

TEST(FlattenTest, UnconnectedFlowsAreZero) {
  FlatSystem flat = FlattenYaml(R"(
model: Lonely
components:
  A: {type: Mass}
  S: {type: Spring}
connections:
  - [A.flange_b, S.flange_a]
)");
  // A.flange_a and S.flange_b are left open.
  auto open = WithOrigin(flat, EquationOrigin::kUnconnectedFlow);
  std::set<std::string> zero;
  for (const FlatEquation* e : open) {
    ASSERT_EQ(flat.pool->op(e->residual), Op::kVar) << flat.EquationText(*e);
    zero.insert(flat.VariableName(VarId(flat.pool->node(e->residual).a)));
    EXPECT_NE(flat.EquationText(*e).find("= 0 (unconnected)"), std::string::npos) << flat.EquationText(*e);
  }
  EXPECT_EQ(zero, (std::set<std::string>{"A.flange_a.f", "S.flange_b.f"}));
  // Every variable counted: Mass 3 + 2*2 connector, Spring 2 + 2*2 connector.
  EXPECT_EQ(flat.variables.size(), 7u + 6u);
  // 5 + 4 component equations, 2 connection equations, 2 unconnected flows: balanced.
  EXPECT_EQ(flat.equations.size(), 13u);
}

TEST(FlattenTest, SignalConnectionsEquateInputAndOutput) {
  FlatSystem flat = FlattenYaml(R"(
model: Signals
components:
  k: {type: Constant, k: 3}
  g1: {type: Gain, k: 2}
  g2: {type: Gain, k: -1}
connections:
  - [k.y, g1.u]
  - [g2.u, k.y]
)");
  auto conn = WithOrigin(flat, EquationOrigin::kConnection);
  ASSERT_EQ(conn.size(), 2u);
  std::set<std::string> texts;
  for (const FlatEquation* e : conn) {
    texts.insert(flat.EquationText(*e));
    auto terms = Terms(flat, e->residual);
    ASSERT_EQ(terms.size(), 2u);
    EXPECT_EQ(terms.at("k.y"), -1.0);
  }
  EXPECT_EQ(texts, (std::set<std::string>{"g1.u = k.y (connection)", "g2.u = k.y (connection)"}));
  // Signal connectors have no unconnected-flow equations; g1.y and g2.y stay free.
  EXPECT_TRUE(WithOrigin(flat, EquationOrigin::kUnconnectedFlow).empty());
  EXPECT_TRUE(flat.variables[FindVar(flat, "g1.u").value()].is_input);
  EXPECT_FALSE(flat.variables[FindVar(flat, "k.y").value()].is_input);
}

TEST(FlattenTest, SignalErrors) {
  std::string msg = FlattenError(R"(
model: TwoOutputs
components:
  a: {type: Constant}
  b: {type: Constant}
connections:
  - [a.y, b.y]
)");
  EXPECT_NE(msg.find("a.y and b.y are connected to each other"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: NoOutput
components:
  a: {type: Gain}
  b: {type: Gain}
connections:
  - [a.u, b.u]
)");
  EXPECT_NE(msg.find("no output drives them"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: Mixed
components:
  a: {type: Constant}
  m: {type: Mass}
connections:
  - [a.y, m.flange_a]
)");
  EXPECT_NE(msg.find("connectors of different kinds"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a.y (RealOutput)"), std::string::npos) << msg;
}

TEST(FlattenTest, ArraysWithCountAndForConnections) {
  FlatSystem flat = FlattenYaml(R"(
model: Ladder
parameters:
  n: 4
components:
  R: {type: Resistor, count: n, R: "10*i + 1"}
  g: {type: Ground}
connections:
  - for: i in 1:n-1
    connect: ["R[i].n", "R[i+1].p"]
  - ["R[n].n", g.p]
)");
  std::vector<std::string> paths;
  for (uint32_t k = 0; k < flat.instances.size(); ++k) paths.push_back(flat.InstancePath(InstanceId(k)));
  EXPECT_EQ(paths, (std::vector<std::string>{"R[1]", "R[2]", "R[3]", "R[4]", "g"}));
  // R[k].R = 10*k + 1, folded to a number at flatten time.
  for (int k = 1; k <= 4; ++k) {
    ParamId id = FindParam(flat, "R[" + std::to_string(k) + "].R");
    EXPECT_TRUE(flat.pool->IsConst(flat.parameters[id.value()].binding, 10.0 * k + 1)) << k;
  }
  // R[i].n -- R[i+1].p for i = 1..3, and R[4].n -- g.p: 4 sets of 2 pins, one equation each for
  // v and for i.
  auto conn = WithOrigin(flat, EquationOrigin::kConnection);
  EXPECT_EQ(conn.size(), 8u);
  std::set<std::map<std::string, double>> all;
  for (const FlatEquation* e : conn) all.insert(Terms(flat, e->residual));
  EXPECT_TRUE(all.count({{"R[2].n.i", 1}, {"R[3].p.i", 1}}));
  EXPECT_TRUE(all.count({{"R[4].n.i", 1}, {"g.p.i", 1}}));
  EXPECT_TRUE(all.count({{"R[1].n.v", -1}, {"R[2].p.v", 1}}) || all.count({{"R[1].n.v", 1}, {"R[2].p.v", -1}}));
  // R[1].p is open (and so is each resistor's heat port, which useHeatPort = false removes later).
  std::vector<std::string> open;
  for (const FlatEquation* e : WithOrigin(flat, EquationOrigin::kUnconnectedFlow)) {
    std::string name = flat.VariableName(VarId(flat.pool->node(e->residual).a));
    if (name.find(".heatPort.") == std::string::npos) open.push_back(name);
  }
  EXPECT_EQ(open, std::vector<std::string>{"R[1].p.i"});
  // The count follows an override of n (a structural parameter).
  FlatSystem six = FlattenYaml(R"(
model: Ladder
parameters:
  n: 4
components:
  R: {type: Resistor, count: n}
)", {{"n", 6}});
  EXPECT_EQ(six.instances.size(), 6u);
  EXPECT_EQ(six.InstancePath(InstanceId(5)), "R[6]");
}

TEST(FlattenTest, BlocksNameTheirElementsOnDemand) {
  // A count: array of a composite type is one block: its elements' paths, their variables'
  // and equations' numbers and their locations follow from the block's record alone.
  FlatSystem flat = FlattenYaml(R"(model: Cells
define:
  Cell:
    parameters: {m: 1, k: 100}
    connectors: {flange: Flange}
    components:
      mass: {type: Mass, m: m}
      spring: {type: Spring, c: k}
    connections:
      - [flange, spring.flange_a]
      - [spring.flange_b, mass.flange_a]
components:
  wall: {type: Fixed}
  cells: {type: Cell, count: 3, k: 50*i, mass.s: {start: i}}
connections:
  - for: j in 1:3
    connect: [wall.flange, "cells[j].flange"]
)");
  ASSERT_EQ(flat.blocks.size(), 1u);
  const FlatBlock& b = flat.blocks[0];
  EXPECT_EQ(b.name, "cells");
  EXPECT_EQ(b.type->name, "Cell");
  EXPECT_EQ(b.count, 3u);
  EXPECT_EQ(b.stride, 3u);  // the cell, its mass and its spring
  EXPECT_EQ(b.part_paths, (std::vector<std::string>{"mass", "spring"}));
  std::vector<std::string> paths;
  for (uint32_t k = 0; k < flat.instances.size(); ++k) paths.push_back(flat.InstancePath(InstanceId(k)));
  EXPECT_EQ(paths, (std::vector<std::string>{"wall", "cells[1]", "cells[1].mass", "cells[1].spring", "cells[2]",
                                             "cells[2].mass", "cells[2].spring", "cells[3]", "cells[3].mass",
                                             "cells[3].spring"}));
  // Element k's variables, parameters and equations are numbered from the block's firsts with its
  // strides, and name themselves after the element.
  EXPECT_EQ(b.first_var.value() + b.vars_per * b.count, flat.variables.size());
  EXPECT_EQ(b.first_param.value() + b.params_per * b.count, flat.parameters.size());
  for (uint32_t k = 0; k < b.count; ++k) {
    const std::string element = "cells[" + std::to_string(k + 1) + "]";
    for (uint32_t local = 0; local < b.vars_per; ++local) {
      const VarId v(b.first_var.value() + b.vars_per * k + local);
      const std::string name = flat.VariableName(v);
      EXPECT_EQ(name.rfind(element + ".", 0), 0u) << name;
      const InstanceId owner = flat.variables[v.value()].instance;
      EXPECT_EQ((owner.value() - b.first_instance.value()) / b.stride, k) << name;
      EXPECT_EQ(name.rfind(flat.InstancePath(owner) + ".", 0), 0u) << name;
      EXPECT_EQ(FindVar(flat, name), v);
    }
    for (uint32_t local = 0; local < b.params_per; ++local) {
      const ParamId p(b.first_param.value() + b.params_per * k + local);
      EXPECT_EQ(flat.FindParameter(flat.ParameterName(p)), std::optional<ParamId>(p));
    }
    for (uint32_t local = 0; local < b.equations_per; ++local) {
      const FlatEquation& eq = flat.equations[b.first_equation + b.equations_per * k + local];
      const std::string text = flat.DescribeEquation(eq);
      EXPECT_NE(text.find(element), std::string::npos) << text;
    }
  }
  // Names compared in place: a wrong index, a missing part or extra text match nothing.
  EXPECT_TRUE(flat.FindParameter("cells[2].k"));
  EXPECT_TRUE(flat.FindParameter("cells[3].mass.m"));
  for (const char* wrong : {"cells[4].k", "cells[02].k", "cells[2]k", "cells[2].", "cells.k", "cells[2].mass",
                            "cells[2].spring.m", "cell[2].k", "cells[2"}) {
    EXPECT_FALSE(flat.FindParameter(wrong)) << wrong;
  }
  // Locations: a variable is located at its component entry, or at the modifier that sets it,
  // for every element alike.
  for (uint32_t k = 0; k < b.count; ++k) {
    const std::string element = "cells[" + std::to_string(k + 1) + "]";
    const FlatVariable& s = flat.variables[FindVar(flat, element + ".mass.s").value()];
    const FlatVariable& v = flat.variables[FindVar(flat, element + ".mass.v").value()];
    EXPECT_EQ(s.loc.ToString(), flat.variables[FindVar(flat, "cells[1].mass.s").value()].loc.ToString());
    EXPECT_NE(s.loc.ToString(), b.loc.ToString());  // set by the modifier mass.s
    EXPECT_EQ(flat.DescribeVariable(FindVar(flat, element + ".mass.v")),
              element + ".mass.v (Mass, " + flat.instances[v.instance.value()].loc.ToString() + ")");
  }
}

TEST(FlattenTest, ArrayIndexErrors) {
  std::string msg = FlattenError(R"(
model: Out
components:
  R: {type: Resistor, count: 3}
  g: {type: Ground}
connections:
  - ["R[4].n", g.p]
)");
  EXPECT_NE(msg.find("R[4] is out of range 1..3"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: NoIndex
components:
  R: {type: Resistor, count: 3}
  g: {type: Ground}
connections:
  - [R.n, g.p]
)");
  EXPECT_NE(msg.find("R is an array of 3 components"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: BadCount
parameters:
  n: 2.5
components:
  R: {type: Resistor, count: n}
)");
  EXPECT_NE(msg.find("count of R must be a whole number"), std::string::npos) << msg;
  // Subscripts of a for: connection: sums of the loop index and whole numbers are added up
  // directly, the rest is evaluated as a structural value; both report the same way.
  auto loop_error = [](const std::string& end) {
    return FlattenError(R"(
model: Loop
components:
  R: {type: Resistor, count: 3}
  g: {type: Ground}
connections:
  - for: i in 1:3
    connect: [")" + end + R"(", g.p]
)");
  };
  msg = loop_error("R[i - 1 + 2].n");
  EXPECT_NE(msg.find("R[4] is out of range 1..3 in 'R[i - 1 + 2].n'"), std::string::npos) << msg;
  msg = loop_error("R[i + 0.5].n");
  EXPECT_NE(msg.find("an index must be a whole number, found 1.5"), std::string::npos) << msg;
  msg = loop_error("R[2*i].n");
  EXPECT_NE(msg.find("R[4] is out of range 1..3 in 'R[2*i].n'"), std::string::npos) << msg;
}

TEST(FlattenTest, IndexInParameterAndStartExpressions) {
  FlatSystem flat = FlattenYaml(R"(
model: Caps
parameters:
  C0: 2
components:
  C: {type: Capacitor, count: 3, C: "C0/i^2", v: {start: "i + C0", fixed: true}}
)");
  std::vector<double> values = EvaluateParameters(flat, {});
  LeafValues lv;
  lv.params = values.data();
  for (int k = 1; k <= 3; ++k) {
    std::string path = "C[" + std::to_string(k) + "]";
    ParamId c = FindParam(flat, path + ".C");
    EXPECT_DOUBLE_EQ(values[c.value()], 2.0 / (k * k)) << path;
    const FlatVariable& v = flat.variables[FindVar(flat, path + ".v").value()];
    EXPECT_TRUE(v.fixed);
    ASSERT_TRUE(v.start.valid());
    EXPECT_DOUBLE_EQ(Evaluate(*flat.pool, v.start, lv), k + 2.0) << path;
  }
  // An override of the model parameter reaches every element's binding.
  values = EvaluateParameters(flat, {{"C0", 8}});
  EXPECT_DOUBLE_EQ(values[FindParam(flat, "C[2].C").value()], 2.0);
}

TEST(FlattenTest, ModelParametersReferenceEachOther) {
  // Declared in any order; the bindings are evaluated dependencies first.
  FlatSystem flat = FlattenYaml(R"(
model: Params
parameters:
  c: "a*b + 1"
  a: 2
  b: {value: "a + 1", unit: m}
components:
  m: {type: Mass, m: "c/7", L: "b"}
)");
  std::vector<double> v = EvaluateParameters(flat, {});
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "a").value()], 2);
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "b").value()], 3);
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "c").value()], 7);
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "m.m").value()], 1);
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "m.L").value()], 3);
  // parameter_order puts every binding's parameters first.
  std::vector<int> position(flat.parameters.size(), -1);
  for (size_t k = 0; k < flat.parameter_order.size(); ++k) position[flat.parameter_order[k].value()] = static_cast<int>(k);
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    ASSERT_GE(position[k], 0) << flat.ParameterName(ParamId(k));
    for (ExprId leaf : CollectLeaves(*flat.pool, flat.parameters[k].binding, kHasParam)) {
      EXPECT_LT(position[flat.pool->node(leaf).a], position[k]) << flat.ParameterName(ParamId(k));
    }
  }
  // Overriding a parameter changes those that depend on it, not the override itself.
  v = EvaluateParameters(flat, {{"a", 4}});
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "b").value()], 5);
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "c").value()], 21);
  v = EvaluateParameters(flat, {{"b", 10}});
  EXPECT_DOUBLE_EQ(v[FindParam(flat, "c").value()], 21);
  // Component parameter defaults that reference other parameters of the type.
  FlatSystem dflt = FlattenYaml(R"(
model: Defaults
define:
  Box:
    parameters:
      w: 2
      area: "w*w"
components:
  b: {type: Box, w: 3}
)");
  v = EvaluateParameters(dflt, {});
  EXPECT_DOUBLE_EQ(v[FindParam(dflt, "b.area").value()], 9);
}

TEST(FlattenTest, DefinedTypesOutliveTheFlattener) {
  // FlatInstance::type of a define: type must stay valid after Flatten() returns: the
  // parameter check and every message (DescribeVariable, DescribeEquation) read its name.
  FlatSystem flat = FlattenYaml(R"(
model: Defined
define:
  AComponentTypeWithAFairlyLongName:
    parameters: {gain: {value: 2, min: 0, doc: a gain}}
    variables: {x: {}}
    equations:
      - x = gain*time
components:
  c: {type: AComponentTypeWithAFairlyLongName}
)");
  // Churn the heap a little, as the passes after flattening do.
  std::vector<std::string> churn;
  for (int k = 0; k < 1000; ++k) churn.push_back(std::string(40 + k % 50, 'z'));
  churn.clear();
  ASSERT_EQ(flat.instances.size(), 1u);
  ASSERT_NE(flat.instances[0].type, nullptr);
  EXPECT_EQ(flat.instances[0].type->name, "AComponentTypeWithAFairlyLongName");
  EXPECT_NE(flat.DescribeVariable(FindVar(flat, "c.x")).find("(AComponentTypeWithAFairlyLongName, test.yaml:"),
            std::string::npos);
  // A parameter out of range names the type in its message.
  try {
    EvaluateParameters(flat, {{"c.gain", -1}});
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("c.gain (AComponentTypeWithAFairlyLongName.gain: a gain)"),
              std::string::npos)
        << e.what();
  }
}

TEST(FlattenTest, ParameterCycleIsAnError) {
  std::string msg = FlattenError(R"(
model: Cycle
parameters:
  a: "b + 1"
  b: "2*c"
  c: "a"
)");
  EXPECT_NE(msg.find("the parameters' bindings form a cycle through"), std::string::npos) << msg;
  EXPECT_EQ(msg.rfind("test.yaml:", 0), 0u) << msg;
  // A self-reference, and a cycle through a component's parameters.
  msg = FlattenError(R"(
model: Self
parameters:
  a: "a + 1"
)");
  EXPECT_NE(msg.find("cycle through a"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: Loop
define:
  Box:
    parameters:
      u: "v"
      v: "u"
components:
  b: {type: Box}
)");
  EXPECT_NE(msg.find("cycle through b."), std::string::npos) << msg;
  // A structural use of a cyclic parameter.
  msg = FlattenError(R"(
model: Count
parameters:
  n: "m"
  m: "n"
components:
  R: {type: Resistor, count: n}
)");
  EXPECT_NE(msg.find("cycle"), std::string::npos) << msg;
}

TEST(FlattenTest, LongParameterChainIsNotACycle) {
  // 150 model parameters, each the previous plus one, the last one used as a count.
  std::string yaml = "model: Chain\nparameters:\n  p0: 1\n";
  for (int k = 1; k < 150; ++k) yaml += "  p" + std::to_string(k) + ": \"p" + std::to_string(k - 1) + " + 0\"\n";
  yaml += "components:\n  R: {type: Resistor, count: p149}\n";
  EXPECT_EQ(FlattenError(yaml), "");
}

TEST(FlattenTest, ParameterValuesAreChecked) {
  std::string msg = FlattenError(R"(
model: Negative
components:
  m: {type: Mass, m: -1}
)");
  EXPECT_NE(msg.find("m.m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("below its minimum 0"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: M
components:
  m: {type: Mass}
)", {{"m.mm", 2}});
  EXPECT_NE(msg.find("-p m.mm: no parameter of that name"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean m.m"), std::string::npos) << msg;
}

TEST(FlattenTest, NamesAreResolvedWithHelpfulErrors) {
  std::string msg = FlattenError(R"(
model: Typo
components:
  A: {type: Mas}
)");
  EXPECT_NE(msg.find("unknown component type 'Mas' for A"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean Mass"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: BadKey
components:
  A: {type: Mass, mass: 2}
)");
  EXPECT_NE(msg.find("unknown key 'mass' for A (Mass)"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: BadConnector
components:
  A: {type: Mass}
  B: {type: Mass}
connections:
  - [A.flange, B.flange_a]
)");
  EXPECT_NE(msg.find("A (Mass) has no connector 'flange'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("valid connectors: flange_a, flange_b"), std::string::npos) << msg;
  msg = FlattenError(R"(
model: BadOutput
components:
  A: {type: Mass}
outputs: [A.w]
)");
  EXPECT_NE(msg.find("A (Mass) has no variable or parameter 'w'"), std::string::npos) << msg;
  EXPECT_EQ(msg.rfind("test.yaml:5:", 0), 0u) << msg;
}

TEST(FlattenTest, EquationsOfComponentsAndModel) {
  FlatSystem flat = FlattenYaml(R"(
model: Own
parameters:
  k: 2
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = -k*x + A.v
components:
  A: {type: Mass}
initial_equations:
  - A.v = 3
)");
  // The model's equation: der(x) + k*x - A.v.
  auto model = WithOrigin(flat, EquationOrigin::kModel);
  ASSERT_EQ(model.size(), 1u);
  const ExprPool& pool = *flat.pool;
  std::vector<double> params = EvaluateParameters(flat, {});
  std::vector<double> vars(flat.variables.size(), 0.0), ders(flat.variables.size(), 0.0);
  vars[FindVar(flat, "x").value()] = 0.5;
  vars[FindVar(flat, "A.v").value()] = 4;
  ders[FindVar(flat, "x").value()] = 10;
  LeafValues lv;
  lv.params = params.data();
  lv.vars = vars.data();
  lv.ders = ders.data();
  EXPECT_DOUBLE_EQ(Evaluate(pool, model[0]->residual, lv), 10 - (-2 * 0.5 + 4));
  ASSERT_EQ(flat.initial_equations.size(), 1u);
  EXPECT_EQ(flat.initial_equations[0].origin, EquationOrigin::kInitial);
  EXPECT_TRUE(flat.variables[FindVar(flat, "x").value()].fixed);
  // Mass's `v = der(s)` belongs to A.
  int of_a = 0;
  for (const auto& e : flat.equations) {
    if (e.origin == EquationOrigin::kComponent) {
      EXPECT_EQ(flat.InstancePath(e.instance), "A");
      ++of_a;
    }
  }
  EXPECT_EQ(of_a, 5);
  EXPECT_NE(flat.DescribeEquation(*model[0]).find("der(x) = -k*x + A.v"), std::string::npos);
}

TEST(FlattenTest, WrittenOutComponentsAreReservedAtTheirSize) {
  // Components written one by one: their records, connection equations included, take their
  // memory once (ReserveComponents), and are the same as made one after the other.
  FlatSystem flat = FlattenYaml(R"(
model: WrittenOut
components:
  wall: {type: Fixed}
  sd1: {type: SpringDamper, c: 1e4, d: 10}
  mass1: {type: Mass, m: 1, s: {start: 1, fixed: true}}
  sd2: {type: SpringDamper, c: 1e4, d: 10}
  mass2: {type: Mass, m: 2, s: {start: 2, fixed: true}}
connections:
  - [wall.flange, sd1.flange_a]
  - [sd1.flange_b, mass1.flange_a]
  - [mass1.flange_b, sd2.flange_a]
  - [sd2.flange_b, mass2.flange_a]
)");
  EXPECT_EQ(flat.variables.capacity(), flat.variables.size());
  EXPECT_EQ(flat.equations.capacity(), flat.equations.size());
  EXPECT_EQ(flat.instances.capacity(), flat.instances.size());
  // mass2.flange_b is connected to nothing: its force is zero.
  std::set<std::string> unconnected;
  for (const FlatEquation* e : WithOrigin(flat, EquationOrigin::kUnconnectedFlow)) unconnected.insert(flat.EquationText(*e));
  EXPECT_TRUE(unconnected.count("mass2.flange_b.f = 0 (unconnected)"));
  const std::vector<double> v = EvaluateParameters(flat, {});
  EXPECT_EQ(v[FindParam(flat, "mass2.m").value()], 2);
  EXPECT_EQ(flat.pool->ConstValue(flat.variables[FindVar(flat, "mass2.s").value()].start), 2);
}

TEST(FlattenTest, ATypeThatCannotBeLaidOutIsReportedInTheModelsOrder) {
  // The types are laid out before the components are made (to reserve their records); a type
  // that fails there is reported where its component is, after the errors of those before it.
  const std::string broken = R"(
model: Order
parameters: {p: 1}
define:
  Broken:
    connectors: {a: {type: NoSuchConnector}}
components:
)";
  EXPECT_NE(FlattenError(broken + "  p: {type: Mass}\n  q: {type: Broken}\n").find("the name p is used twice"),
            std::string::npos);
  EXPECT_NE(FlattenError(broken + "  q: {type: Broken}\n").find("unknown connector type 'NoSuchConnector' for Broken.a"),
            std::string::npos);
}

TEST(FlattenTest, ConnectionEndsHeldAsTextResolveAsTheirTrees) {
  // A plain end (sd1.flange_b) is resolved from its text; anything it cannot resolve is left to
  // the end's tree, which gives the message.
  const std::string model = R"(
model: Ends
components:
  A: {type: Mass, m: 1}
  R: {type: Resistor, count: 2}
connections:
)";
  EXPECT_NE(FlattenError(model + "  - [A.flange_c, A.flange_b]\n").find("A (Mass) has no connector 'flange_c'"),
            std::string::npos);
  EXPECT_NE(FlattenError(model + "  - [B.flange_a, A.flange_b]\n").find("unknown component 'B'"), std::string::npos);
  EXPECT_NE(FlattenError(model + "  - [R.p, R.n]\n").find("R is an array of 2 components; name one element"),
            std::string::npos);
}

}  // namespace
}  // namespace momenta

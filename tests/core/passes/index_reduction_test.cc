// Index reduction: derivative aliases (a speed sensor on a mass measures the mass's velocity, as
// an alias), constrained states (a spring-damper between two masses; a lever between two masses),
// the stateSelect: prefer / avoid choice, and the run-time check of a parameter coefficient.

#include "core/passes/index_reduction.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/passes/alias_elimination.h"
#include "tests/support/reduced_system.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

using Reduced = testing::ReducedSystem;
using testing::Reduce;

const char* kSpeedSensor = R"(
model: Speed
components:
  m: {type: Mass, m: 2, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  push: {type: ConstantForce, f_constant: 4}
  sensor: {type: SpeedSensor}
connections:
  - [push.flange, m.flange_b]
  - [m.flange_a, sensor.flange]
experiment: {stop: 1, interval: 0.25}
outputs: [sensor.v]
)";

TEST(IndexReductionTest, SpeedSensorIsADerivativeAlias) {
  Reduced r = Reduce(kSpeedSensor);
  EXPECT_GE(r.index.derivative_aliases, 1u);
  EXPECT_EQ(r.index.constrained_states, 0u);
  EXPECT_EQ(r.role("sensor.v"), VarRole::kAlias);
  EXPECT_EQ(r.role("m.v"), VarRole::kUnknown);
  ExprPool& P = *r.sys.pool;
  EXPECT_EQ(r.sys.eliminated->Apply(P.Var(VarId(r.Var("sensor.v")))), P.Var(VarId(r.Var("m.v"))));
  EXPECT_EQ(r.sys.outputs[0], P.Var(VarId(r.Var("m.v"))));
  // der(m.s) is left in exactly one equation (its definition), so m.s is one state, not two.
  size_t holders = 0;
  for (const auto& e : r.sys.equations) holders += ContainsLeaf(P, e.residual, P.Der(VarId(r.Var("m.s"))));
  EXPECT_EQ(holders, 1u);
  // Simulated: v = 1 + (4/2) t.
  testing::Built b = testing::BuildYaml(kSpeedSensor);
  EXPECT_TRUE(b.report.warnings.empty());
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    EXPECT_NEAR(tr.Column("sensor.v", row), 1 + 2 * tr.t[row], 1e-6) << tr.t[row];
  }
}

TEST(IndexReductionTest, NothingToDoForASingleMass) {
  Reduced r = Reduce(R"(
model: One
components:
  m: {type: Mass, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
)");
  EXPECT_EQ(r.index.derivative_aliases, 0u);
  EXPECT_EQ(r.index.constrained_states, 0u);
}

const char* kTwoMasses = R"(
model: TwoMasses
components:
  m1: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  sd: {type: SpringDamper, c: 100, d: 2, s_rel0: 1}
  m2: {type: Mass, m: 1, s: {start: 1.5, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [m1.flange_b, sd.flange_a]
  - [sd.flange_b, m2.flange_a]
experiment: {stop: 1, interval: 0.05, tolerance: 1e-8}
outputs: [m1.s, m2.s, sd.s_rel, m1.v, m2.v]
)";

TEST(IndexReductionTest, SpringDamperBetweenTwoMassesConstrainsAState) {
  // s_rel = m2.s - m1.s relates three differentiated variables; s_rel is `stateSelect: prefer`, so the
  // position of the mass declared last becomes m1.s + s_rel.
  Reduced r = Reduce(kTwoMasses);
  EXPECT_GE(r.index.constrained_states, 1u);
  EXPECT_EQ(r.role("m2.s"), VarRole::kConstrained);
  EXPECT_EQ(r.role("m1.s"), VarRole::kUnknown);
  EXPECT_EQ(r.role("sd.s_rel"), VarRole::kUnknown);
  ExprPool& P = *r.sys.pool;
  ExprId m2s = r.sys.eliminated->Apply(P.Var(VarId(r.Var("m2.s"))));
  AffineForm form;
  ASSERT_TRUE(DecomposeAffine(&P, m2s, 4, &form));
  std::map<std::string, double> terms;
  for (auto& [leaf, c] : form.terms) terms[r.flat->VariableName(VarId(P.node(leaf).a))] = c;
  EXPECT_EQ(terms, (std::map<std::string, double>{{"m1.s", 1}, {"sd.s_rel", 1}}));
  // Built: four states (m1.s, m1.v, s_rel and one velocity), no more.
  testing::Built b = testing::BuildYaml(kTwoMasses);
  EXPECT_EQ(b.model->num_states(), 4u);
  EXPECT_EQ(std::count(b.report.states.begin(), b.report.states.end(), "m2.s"), 0);
  EXPECT_EQ(std::count(b.report.states.begin(), b.report.states.end(), "sd.s_rel"), 1);
  EXPECT_TRUE(b.report.warnings.empty());
  // Physics: momentum is conserved (it starts at 0) and the stretch x = s_rel - 1 is a damped
  // oscillation of the reduced mass 0.5: x'' + 4x' + 200x = 0, x(0) = 0.5, x'(0) = 0.
  testing::Trajectory tr = testing::RunDefault(b);
  const double w0 = std::sqrt(200.0), zeta = 2.0 / (2 * std::sqrt(100.0 * 0.5));
  const double wd = w0 * std::sqrt(1 - zeta * zeta);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row];
    double x = 0.5 * std::exp(-zeta * w0 * t) * (std::cos(wd * t) + zeta * w0 / wd * std::sin(wd * t));
    EXPECT_NEAR(tr.Column("sd.s_rel", row), 1 + x, 1e-5) << t;
    EXPECT_NEAR(tr.Column("m2.s", row) - tr.Column("m1.s", row), tr.Column("sd.s_rel", row), 1e-9) << t;
    EXPECT_NEAR(tr.Column("m1.s", row) + tr.Column("m2.s", row), 1.5, 1e-6) << t;
    EXPECT_NEAR(tr.Column("m1.v", row) + tr.Column("m2.v", row), 0.0, 1e-6) << t;
  }
}

/// Two masses on a lever (flange_b moves `ratio` times as far as flange_a); a constant force of
/// 3 N pushes m1. With x = m1.s: (m1 + ratio^2 m2) x'' = F.
std::string LeverModel(const std::string& m1_type) {
  return R"(
model: Lever
define:
  Lever:
    parameters: {ratio: 2}
    connectors: {flange_a: Flange, flange_b: Flange}
    equations:
      - flange_b.s = ratio*flange_a.s
      - 0 = flange_a.f + ratio*flange_b.f
  AvoidMass:
    parameters: {m: 1}
    connectors: {flange_a: Flange, flange_b: Flange}
    variables:
      s: {start: 0, stateSelect: avoid}
      v: {start: 0, stateSelect: avoid}
      a: {}
    equations:
      - flange_a.s = s
      - flange_b.s = s
      - v = der(s)
      - a = der(v)
      - m*a = flange_a.f + flange_b.f
components:
  push: {type: ConstantForce, f_constant: 3}
  m1: {type: )" + m1_type + R"(, m: 1, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
  lever: {type: Lever}
  m2: {type: Mass, m: 1}
connections:
  - [push.flange, m1.flange_a]
  - [m1.flange_b, lever.flange_a]
  - [lever.flange_b, m2.flange_a]
experiment: {stop: 1, interval: 0.25}
outputs: [m1.s, m2.s, m2.v]
)";
}

TEST(IndexReductionTest, TheLaterDeclaredStateIsConstrained) {
  Reduced r = Reduce(LeverModel("Mass"));
  EXPECT_EQ(r.role("m2.s"), VarRole::kConstrained);
  EXPECT_EQ(r.role("m2.v"), VarRole::kConstrained);
  EXPECT_EQ(r.role("m1.s"), VarRole::kUnknown);
  EXPECT_EQ(r.role("m1.v"), VarRole::kUnknown);
  EXPECT_EQ(r.index.constrained_states, 2u);
  EXPECT_TRUE(r.sys.guards.empty());  // m2.s = ratio*m1.s: coefficient 1 in m2.s
}

TEST(IndexReductionTest, StateAvoidIsConstrainedFirst) {
  Reduced r = Reduce(LeverModel("AvoidMass"));
  EXPECT_EQ(r.role("m1.s"), VarRole::kConstrained);
  EXPECT_EQ(r.role("m1.v"), VarRole::kConstrained);
  EXPECT_EQ(r.role("m2.s"), VarRole::kUnknown);
  EXPECT_EQ(r.role("m2.v"), VarRole::kUnknown);
  // m1.s = m2.s/ratio: the parameter divides, so it is guarded.
  EXPECT_FALSE(r.sys.guards.empty());
}

TEST(IndexReductionTest, BothChoicesSimulateTheSameMotion) {
  for (const char* type : {"Mass", "AvoidMass"}) {
    testing::Built b = testing::BuildYaml(LeverModel(type));
    EXPECT_EQ(b.model->num_states(), 2u) << type;
    testing::Trajectory tr = testing::RunDefault(b);
    for (size_t row = 0; row < tr.t.size(); ++row) {
      double t = tr.t[row];
      // x'' = 3/(1 + 4) = 0.6
      EXPECT_NEAR(tr.Column("m1.s", row), 0.3 * t * t, 1e-6) << type << " at " << t;
      EXPECT_NEAR(tr.Column("m2.s", row), 0.6 * t * t, 1e-6) << type << " at " << t;
      EXPECT_NEAR(tr.Column("m2.v", row), 1.2 * t, 1e-6) << type << " at " << t;
    }
    // A different ratio, without rebuilding: (1 + 9) x'' = 3.
    testing::Trajectory tr3 = testing::RunDefault(b, {{"lever.ratio", 3}});
    EXPECT_NEAR(tr3.Column("m2.s", tr3.t.size() - 1), 3 * 0.15 * 1.0, 1e-6) << type;
  }
}

TEST(IndexReductionTest, AZeroCoefficientIsReportedWhenParametersAreSet) {
  // With ratio = 0, m1.s = m2.s/ratio cannot be computed: the message names the equation, the
  // variable and the parameter expression.
  std::string msg = testing::BuildError(LeverModel("AvoidMass"), {{"lever.ratio", 0}});
  EXPECT_NE(msg.find("cannot be solved for m1."), std::string::npos) << msg;
  EXPECT_NE(msg.find("lever.ratio"), std::string::npos) << msg;
  EXPECT_NE(msg.find("flange_b.s = ratio*flange_a.s"), std::string::npos) << msg;
  EXPECT_EQ(testing::BuildError(LeverModel("AvoidMass"), {{"lever.ratio", 0.5}}), "");
}

}  // namespace
}  // namespace momenta

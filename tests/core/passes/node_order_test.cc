// What the build decides does not follow the order in which the expression pool's nodes were
// made: each model is built twice, the second time with every pool first given nodes of its own
// (the leaves of variables and parameters in reverse order, sums and products of neighbouring
// variables), so that the model's nodes get other ids and the pool orders the operands of + and *
// the other way round. Ties in alias elimination, index reduction, matching, state selection and
// causalisation are broken by variable and equation index, so both builds must make the same
// structure (the same states, dummy derivatives, rows in the same order, the same Jacobian
// pattern) and, since + and * give the same bits in either operand order, the same results to
// the bit.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/expr/expr.h"
#include "core/expr/expr_testing.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

/// Nodes made in every new pool before the model's: leaves in reverse order of their index, and
/// sums, differences and products of neighbours, which models make too (a connection's x - y).
void MakeNodesFirst(ExprPool* p) {
  constexpr uint32_t kLeaves = 4096, kPairs = 512;
  for (uint32_t k = kLeaves; k-- > 0;) {
    p->Param(ParamId(k));
    p->Var(VarId(k));
  }
  for (uint32_t k = kPairs; k-- > 0;) {
    const ExprId x = p->Var(VarId(k)), y = p->Var(VarId(k + 1));
    p->Add(x, y);
    p->Sub(x, y);
    p->Sub(y, x);
    p->Mul(p->Param(ParamId(k)), x);
  }
  for (double c : {0.5, 2.0, 3.0, 0.25, 1e-3}) p->Const(c);
}

/// Sets the hook for the scope of one build.
class PerturbedPools {
 public:
  PerturbedPools() { pool_made_for_testing = MakeNodesFirst; }
  ~PerturbedPools() { pool_made_for_testing = nullptr; }
};

/// What the build decided, in words: the passes' counts and notes, and the compiled model's
/// unknowns, states, rows and patterns.
std::vector<std::string> Structure(const testing::Built& b) {
  std::vector<std::string> s;
  const BuildReport& r = b.report;
  for (const PassReport& pass : r.passes) {
    s.push_back(pass.name + ": " + std::to_string(pass.variables) + " unknowns, " + std::to_string(pass.equations) +
                " equations; " + pass.note);
  }
  for (const auto* list : {&r.warnings, &r.notes, &r.pruned, &r.states, &r.differentiated, &r.dummy_derivatives,
                           &r.state_choices}) {
    s.insert(s.end(), list->begin(), list->end());
  }
  const CompiledModel& m = *b.model;
  for (size_t y = 0; y < m.num_unknowns(); ++y) {
    s.push_back("y" + std::to_string(y) + " " + m.flat->VariableName(m.unknowns[y]) + (m.is_state[y] ? " (state)" : "") +
                ": " + m.residual_origin(y));
  }
  for (const SparsePattern* pattern : {&m.jacobian_pattern, &m.init_pattern}) {
    std::string cols = "pattern:";
    for (int32_t k : pattern->col_start) cols += " " + std::to_string(k);
    cols += " |";
    for (int32_t k : pattern->row_index) cols += " " + std::to_string(k);
    s.push_back(cols);
  }
  for (const auto& c : m.conditions) s.push_back("condition " + std::string(OpName(c.op)) + (c.time_only ? " (time)" : ""));
  s.insert(s.end(), m.initial_origin.begin(), m.initial_origin.end());
  return s;
}

class NodeOrderTest : public ::testing::TestWithParam<const char*> {};

TEST_P(NodeOrderTest, SameStructureAndResultsWhateverTheNodeIds) {
  const std::string path = GetParam();
  const testing::Built plain = testing::BuildFile(path);
  testing::Built perturbed;
  {
    PerturbedPools hook;
    perturbed = testing::BuildFile(path);
  }
  // The perturbation took: the model's nodes have other ids (else the test proves nothing).
  ASSERT_NE(plain.model->pool->size(), perturbed.model->pool->size());
  EXPECT_EQ(Structure(plain), Structure(perturbed));
  const testing::Trajectory a = testing::RunDefault(plain), b = testing::RunDefault(perturbed);
  ASSERT_EQ(a.t, b.t);
  ASSERT_EQ(a.values.size(), b.values.size());
  for (size_t row = 0; row < a.values.size(); ++row) {
    ASSERT_EQ(a.values[row], b.values[row]) << "row " << row << ", t = " << a.t[row];
  }
}

// Models with choices to make: index reduction with state sets (the Cartesian pendulum), closed
// kinematic loops (the slider-crank), algebraic loops, events and friction modes.
INSTANTIATE_TEST_SUITE_P(Models, NodeOrderTest,
                         ::testing::Values("models/pendulum_cartesian.yaml", "models/double_pendulum.yaml",
                                           "models/slider_crank.yaml", "models/bouncing_ball.yaml",
                                           "models/suspension_rig.yaml", "models/msl/DoublePendulum.yaml",
                                           "models/msl/Mechanics/Rotational/Examples/CoupledClutches.yaml",
                                           "models/msl/Friction.yaml"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           name = name.substr(7, name.size() - 12);  // models/ ... .yaml
                           for (char& c : name) {
                             if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace momenta

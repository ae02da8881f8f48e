#include "core/passes/causalization.h"

#include <algorithm>

#include "core/base/graph.h"

namespace momenta {

EquationSystem Causalize(EquationSystem sys, Structure* st, CausalStats* stats) {
  ExprPool& p = *sys.pool;
  const size_t ne = sys.equations.size();
  // Dependency graph among equations that determine algebraic unknowns.
  std::vector<uint32_t> start{0}, adj;
  std::vector<bool> algebraic_eq(ne, false);
  // The variables of each algebraic equation, kept for weighing its solution below (the
  // equations do not change until the end): equation k's are vars[var_start[k] ..
  // var_start[k+1]).
  std::vector<uint32_t> var_start{0}, vars;
  std::vector<ExprId> leaves;  // scratch
  for (size_t k = 0; k < ne; ++k) {
    uint32_t v = static_cast<uint32_t>(st->var_of_equation[k]);
    algebraic_eq[k] = !st->is_state[v];
    if (algebraic_eq[k]) {
      CollectLeaves(p, sys.equations[k].residual, kHasVar, &leaves);
      for (ExprId leaf : leaves) {
        uint32_t w = p.node(leaf).a;
        vars.push_back(w);
        if (w == v || sys.role[w] != VarRole::kUnknown || st->is_state[w] || st->equation_of_var[w] < 0) {
          continue;  // known here: states, discrete values
        }
        adj.push_back(static_cast<uint32_t>(st->equation_of_var[w]));
      }
    }
    start.push_back(static_cast<uint32_t>(adj.size()));
    var_start.push_back(static_cast<uint32_t>(vars.size()));
  }
  auto components = StronglyConnectedComponents(static_cast<uint32_t>(ne), start, adj);
  std::vector<bool> keep(sys.role.size(), false);
  for (const auto& im : sys.impacts) keep[im.force.value()] = true;
  // Solve singletons explicitly, dependencies first.
  Substitution& s = *sys.eliminated;
  std::vector<bool> removed(ne, false);
  // Inlining a chain of solutions, each referring to the previous one (the frames of a pendulum
  // chain, x_k = x_(k-1) + L*cos(phi_k)), would make the k-th solution hold k unknowns (states,
  // loop variables) k levels deep, and the Jacobian, which differentiates every equation by each
  // of its unknowns with a walk over the expression, cubic in the chain's length. So each inlined
  // variable carries its `weight`, the unknowns of its fully substituted solution counted with
  // repetition (1 for an unknown), and its `depth`, how far solutions nest below it; one whose
  // weight × depth would pass kMaxInlineCost stays an unknown instead, and the chain restarts
  // from it. A deep chain without unknowns (gains of an input) costs nothing and is inlined
  // however long; the largest cost in the models of models/ is 370.
  constexpr uint64_t kMaxInlineCost = 1024;
  std::vector<uint64_t> weight(sys.role.size(), 1);
  std::vector<uint32_t> depth(sys.role.size(), 0);
  for (const auto& comp : components) {
    if (comp.size() > 1) {
      ++stats->algebraic_loops;
      stats->loop_variables += comp.size();
      continue;
    }
    uint32_t k = comp[0];
    if (!algebraic_eq[k]) continue;
    uint32_t v = static_cast<uint32_t>(st->var_of_equation[k]);
    if (sys.flat->variables[v].type != ValueType::kReal || keep[v]) continue;
    uint64_t v_weight = 0;
    uint32_t v_depth = 0;
    for (uint32_t j = var_start[k]; j < var_start[k + 1]; ++j) {
      const uint32_t w = vars[j];
      if (w == v) continue;
      v_weight = std::min<uint64_t>(v_weight + weight[w], kMaxInlineCost + 1);
      v_depth = std::max(v_depth, depth[w]);
    }
    ++v_depth;
    if (v_weight * v_depth > kMaxInlineCost) continue;
    // Solved as written, the earlier solutions left in place for the final substitution to
    // resolve: substituting first would copy a chain of n equations, each referring to the
    // previous one, n times (quadratic). Only when the coefficient of v involves variables solved
    // earlier (it may then become a number or a parameter) is the substituted form needed.
    ExprId coefficient;
    ExprId value = SolveFor(&p, sys.equations[k].residual, p.Var(VarId(v)), true, &coefficient);
    if (!value.valid()) {
      value = SolveFor(&p, s.Apply(sys.equations[k].residual), p.Var(VarId(v)), true, &coefficient);
    }
    if (!value.valid()) continue;
    s.Set(p.Var(VarId(v)), value);
    ExprId pre = p.FindLeaf(Op::kPre, v);
    if (pre.valid()) s.Set(pre, value);
    if (!p.IsConst(coefficient)) {
      sys.guards.push_back({coefficient, sys.equations[k].origin, VarId(v)});
    }
    weight[v] = v_weight;
    depth[v] = v_depth;
    sys.role[v] = VarRole::kInlined;
    removed[k] = true;
    ++stats->inlined;
  }
  std::vector<SystemEquation> kept;
  std::vector<int32_t> var_of_eq;
  for (size_t k = 0; k < ne; ++k) {
    if (removed[k]) continue;
    kept.push_back(sys.equations[k]);
    var_of_eq.push_back(st->var_of_equation[k]);
  }
  sys.equations.swap(kept);
  st->var_of_equation.swap(var_of_eq);
  std::fill(st->equation_of_var.begin(), st->equation_of_var.end(), -1);
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    st->equation_of_var[st->var_of_equation[k]] = static_cast<int32_t>(k);
  }
  sys.ApplyEliminations();
  return sys;
}

}  // namespace momenta

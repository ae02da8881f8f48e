#include "core/passes/causalization.h"

#include "core/expr/expr_leaves.h"

#include <algorithm>

#include "core/base/graph.h"

namespace momenta {

namespace {

/// The dependency graph among the equations that determine algebraic unknowns (an edge from
/// equation k to the equation of each algebraic unknown it reads), and each such equation's
/// variables, kept for weighing its solution (the equations do not change until the end):
/// equation k's are vars[var_start[k] .. var_start[k+1]).
struct AlgebraicDependencies {
  std::vector<uint32_t> start{0}, adj;
  std::vector<bool> algebraic_eq;
  std::vector<uint32_t> var_start{0}, vars;
};

AlgebraicDependencies FindAlgebraicDependencies(const EquationSystem& sys,
                                                const Structure& structure) {
  const ExprPool& p = *sys.pool;
  const size_t ne = sys.equations.size();
  AlgebraicDependencies deps;
  deps.algebraic_eq.assign(ne, false);
  std::vector<ExprId> leaves;  // scratch
  for (size_t k = 0; k < ne; ++k) {
    uint32_t v = static_cast<uint32_t>(structure.var_of_equation[k]);
    deps.algebraic_eq[k] = !structure.is_state[v];
    if (deps.algebraic_eq[k]) {
      CollectLeaves(p, sys.equations[k].residual, kHasVar, &leaves);
      for (ExprId leaf : leaves) {
        uint32_t w = p.node(leaf).a;
        deps.vars.push_back(w);
        if (w == v || sys.role[w] != VarRole::kUnknown || structure.is_state[w] ||
            structure.equation_of_var[w] < 0) {
          continue;  // known here: states, discrete values
        }
        deps.adj.push_back(static_cast<uint32_t>(structure.equation_of_var[w]));
      }
    }
    deps.start.push_back(static_cast<uint32_t>(deps.adj.size()));
    deps.var_start.push_back(static_cast<uint32_t>(deps.vars.size()));
  }
  return deps;
}

/// Inlining a chain of solutions, each referring to the previous one (the frames of a pendulum
/// chain, x_k = x_(k-1) + L*cos(phi_k)), would make the k-th solution hold k unknowns (states,
/// loop variables) k levels deep, and the Jacobian, which differentiates every equation by each
/// of its unknowns with a walk over the expression, cubic in the chain's length. So each inlined
/// variable carries its `weight`, the unknowns of its fully substituted solution counted with
/// repetition (1 for an unknown), and its `depth`, how far solutions nest below it; one whose
/// weight × depth would pass kMaxInlineCost stays an unknown instead, and the chain restarts
/// from it. A deep chain without unknowns (gains of an input) costs nothing and is inlined
/// however long; the largest cost in the models of models/ is 370.
class InlineCost {
 public:
  static constexpr uint64_t kMaxInlineCost = 1024;

  explicit InlineCost(size_t num_variables) : weight_(num_variables, 1), depth_(num_variables, 0) {}

  /// The weight and depth of v's solution from equation k; false when too costly to inline.
  bool Weigh(uint32_t v, uint32_t k, const AlgebraicDependencies& deps, uint64_t* weight,
             uint32_t* depth) const {
    uint64_t v_weight = 0;
    uint32_t v_depth = 0;
    for (uint32_t j = deps.var_start[k]; j < deps.var_start[k + 1]; ++j) {
      const uint32_t w = deps.vars[j];
      if (w == v) continue;
      v_weight = std::min<uint64_t>(v_weight + weight_[w], kMaxInlineCost + 1);
      v_depth = std::max(v_depth, depth_[w]);
    }
    ++v_depth;
    *weight = v_weight;
    *depth = v_depth;
    return v_weight * v_depth <= kMaxInlineCost;
  }

  void Inlined(uint32_t v, uint64_t weight, uint32_t depth) {
    weight_[v] = weight;
    depth_[v] = depth;
  }

 private:
  std::vector<uint64_t> weight_;
  std::vector<uint32_t> depth_;
};

/// Solves equation k for its variable v and records v's solution in sys->eliminated; false
/// when the equation is not linear in v with a numeric or parameter coefficient.
bool InlineSolution(EquationSystem* sys, uint32_t k, uint32_t v) {
  ExprPool& p = *sys->pool;
  Substitution& s = *sys->eliminated;
  // Solved as written, the earlier solutions left in place for the final substitution to
  // resolve: substituting first would copy a chain of n equations, each referring to the
  // previous one, n times (quadratic). Only when the coefficient of v involves variables solved
  // earlier (it may then become a number or a parameter) is the substituted form needed.
  ExprId coefficient;
  ExprId value = SolveFor(&p, sys->equations[k].residual, p.Var(VarId(v)), true, &coefficient);
  if (!value.valid()) {
    value = SolveFor(&p, s.Apply(sys->equations[k].residual), p.Var(VarId(v)), true, &coefficient);
  }
  if (!value.valid()) return false;
  ExprId pre = p.FindLeaf(Op::kPre, v);
  // v defined by its own left limit (y = if b then 4 else pre(y)): pre(v) is replaced by v's
  // solution below, which would then hold itself. Such a v is kept an unknown.
  if (pre.valid() && ContainsLeaf(p, value, pre)) return false;
  s.Set(p.Var(VarId(v)), value);
  if (pre.valid()) s.Set(pre, value);
  if (!p.IsConst(coefficient)) {
    sys->guards.push_back({coefficient, sys->equations[k].origin, VarId(v)});
  }
  return true;
}

}  // namespace

EquationSystem Causalize(EquationSystem sys, Structure* structure, CausalStats* stats) {
  const size_t ne = sys.equations.size();
  const AlgebraicDependencies deps = FindAlgebraicDependencies(sys, *structure);
  auto components = StronglyConnectedComponents(static_cast<uint32_t>(ne), deps.start, deps.adj);
  std::vector<bool> keep(sys.role.size(), false);
  for (const auto& im : sys.impacts) keep[im.force.value()] = true;
  // Solve singletons explicitly, dependencies first.
  std::vector<bool> kept_eq(ne, true);
  InlineCost cost(sys.role.size());
  for (const auto& comp : components) {
    if (comp.size() > 1) {
      ++stats->algebraic_loops;
      stats->loop_variables += comp.size();
      continue;
    }
    uint32_t k = comp[0];
    if (!deps.algebraic_eq[k]) continue;
    uint32_t v = static_cast<uint32_t>(structure->var_of_equation[k]);
    if (sys.flat->variables[v].type != ValueType::kReal || keep[v]) continue;
    uint64_t weight;
    uint32_t depth;
    if (!cost.Weigh(v, k, deps, &weight, &depth)) continue;
    if (!InlineSolution(&sys, k, v)) continue;
    cost.Inlined(v, weight, depth);
    sys.role[v] = VarRole::kInlined;
    kept_eq[k] = false;
    ++stats->inlined;
  }
  KeepMatchedEquations(&sys, structure, kept_eq);
  sys.ApplyEliminations();
  return sys;
}

}  // namespace momenta

#include "core/passes/structural_conditions.h"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "core/expr/expr_eval.h"

namespace momenta {

namespace {

/// True when every parameter `e` depends on, through the parameters' bindings, is Boolean or
/// Integer, or with `any_type` of any type; `depends` collects them. Called once per condition:
/// the parameters seen are a set of the few reached, not a flag per parameter of the model (that
/// made the pass quadratic in an array's size: one condition and one parameter per element).
bool OnlyDiscreteParameters(const FlatSystem& flat, ExprId e, std::vector<uint32_t>* depends,
                            bool any_type = false) {
  const ExprPool& p = *flat.pool;
  std::vector<ExprId> todo = CollectLeaves(p, e, kHasParam);
  std::unordered_set<uint32_t> seen;
  while (!todo.empty()) {
    uint32_t q = p.node(todo.back()).a;
    todo.pop_back();
    if (!seen.insert(q).second) continue;
    const FlatParameter& fp = flat.parameters[q];
    if (fp.type == ValueType::kReal && !any_type) return false;
    depends->push_back(q);
    if (fp.binding.valid() && (p.mask(fp.binding) & kHasParam)) {
      for (ExprId leaf : CollectLeaves(p, fp.binding, kHasParam)) todo.push_back(leaf);
    }
  }
  return true;
}

/// The guard of a conditional block's equation, `0 = if guard then lhs - rhs else 0`: the
/// condition of the first if-node below the residual's negations, or an invalid id.
ExprId BlockGuard(const ExprPool& p, ExprId residual) {
  for (ExprId e = residual;;) {
    const Node& n = p.node(e);
    if (n.op == Op::kIf) return ExprId(n.a);
    if (n.op == Op::kNeg) {
      e = ExprId(n.a);
    } else if ((n.op == Op::kSub || n.op == Op::kAdd || n.op == Op::kMul) && p.IsConst(ExprId(n.a))) {
      e = ExprId(n.b);
    } else if ((n.op == Op::kSub || n.op == Op::kAdd || n.op == Op::kMul) && p.IsConst(ExprId(n.b))) {
      e = ExprId(n.a);
    } else {
      return ExprId();
    }
  }
}

/// The parameters that conditional blocks' guards read, through bindings, where a guard reads a
/// Real one (MSL's LineForceWithTwoMasses, `if m_a > 0 or m_b > 0`): a block chooses its
/// equations when the model is built, as Modelica evaluates an if-equation's parameter condition,
/// so these are evaluated as `evaluate: true` ones are. (Kept an if-expression, both branches
/// would be equations.) A guard of Boolean and Integer parameters alone is folded as any
/// structural condition is.
std::vector<bool> RealBlockGuardParameters(const FlatSystem& flat, const EquationSystem& sys) {
  const ExprPool& p = *flat.pool;
  std::vector<bool> also(flat.parameters.size(), false);
  std::vector<uint32_t> depends;
  for (const auto& e : sys.equations) {
    if (e.kind != SystemEquation::Kind::kDynamic || !flat.equations[e.origin].guarded) continue;
    const ExprId guard = BlockGuard(p, e.residual);
    if (!guard.valid() || !p.IsParamOnly(guard)) continue;
    depends.clear();
    if (OnlyDiscreteParameters(flat, guard, &depends)) continue;
    depends.clear();
    OnlyDiscreteParameters(flat, guard, &depends, true);
    for (uint32_t q : depends) also[q] = true;
  }
  return also;
}

/// The parameters fixed when the model is built, as Modelica evaluates a parameter with
/// `Evaluate = true` and those bound to it: the ones declared `evaluate: true` or in `also`, and the ones whose
/// binding is an expression of such parameters alone (`C: CapVal`; a binding without parameters is
/// an ordinary value). Each leaf maps to its value in `fixed`; `structural` collects them.
size_t EvaluatedParameters(const FlatSystem& flat, ExprPool* pool, const std::vector<double>& params,
                           const std::vector<bool>& also, std::unordered_map<uint32_t, ExprId>* fixed,
                           std::vector<uint32_t>* structural) {
  const auto& all = flat.parameters;
  if (std::none_of(all.begin(), all.end(), [](const FlatParameter& fp) { return fp.evaluate; }) &&
      std::none_of(also.begin(), also.end(), [](bool b) { return b; })) {
    return 0;
  }
  // In the parameters' evaluation order (a binding's parameters before it), so one pass decides.
  std::vector<bool> evaluated(all.size(), false);
  size_t count = 0;
  for (ParamId id : flat.parameter_order) {
    const uint32_t q = id.value();
    const FlatParameter& fp = all[q];
    bool yes = fp.evaluate || also[q];
    if (!yes && fp.binding.valid() && (pool->mask(fp.binding) & kHasParam)) {
      yes = true;
      for (ExprId leaf : CollectLeaves(*pool, fp.binding, kHasParam)) yes = yes && evaluated[pool->node(leaf).a];
    }
    if (!yes) continue;
    evaluated[q] = true;
    fixed->emplace(pool->Param(id).value(), pool->Const(params[q]));
    structural->push_back(q);
    ++count;
  }
  return count;
}

}  // namespace

size_t FoldStructuralConditions(EquationSystem* sys, const std::vector<double>& params) {
  ExprPool& p = *sys->pool;
  const FlatSystem& flat = *sys->flat;
  // The conditions to fix: parameter-only conditions of if-nodes, found once over the shared DAG.
  std::unordered_map<uint32_t, ExprId> fixed;
  std::vector<uint32_t> structural;
  std::vector<uint8_t> visited(p.size(), 0);
  // Only subtrees that hold an if-expression over parameters are walked (the RC ladder's
  // resistors at 10^6: most equations hold none).
  auto scan = [&](ExprId root) {
    if (!root.valid() || !(p.mask(root) & kHasParam) || !p.HasIf(root)) return;  // invalid: deferred (no if)
    std::vector<uint32_t> stack{root.value()};
    while (!stack.empty()) {
      uint32_t id = stack.back();
      stack.pop_back();
      if (id < visited.size() && visited[id]) continue;
      if (id < visited.size()) visited[id] = 1;
      const Node& n = p.node(ExprId(id));
      if (!(n.mask & kHasParam) || !(n.traits & kHasIf) || IsLeaf(n.op)) continue;
      if (n.op == Op::kIf && p.IsParamOnly(ExprId(n.a)) && !fixed.count(n.a) &&
          OnlyDiscreteParameters(flat, ExprId(n.a), &structural)) {
        LeafValues lv;
        lv.params = params.data();
        fixed.emplace(n.a, p.Const(Evaluate(p, ExprId(n.a), lv) != 0 ? 1.0 : 0.0));
      }
      int arity = Arity(n.op);
      if (arity >= 1) stack.push_back(n.a);
      if (arity >= 2) stack.push_back(n.b);
      if (arity >= 3) stack.push_back(n.c);
    }
  };
  for (const auto& e : sys->equations) scan(e.residual);
  for (const auto& e : sys->initial) scan(e.residual);
  for (ExprId o : sys->outputs) scan(o);
  const size_t conditions = fixed.size();
  const size_t evaluated =
      EvaluatedParameters(flat, &p, params, RealBlockGuardParameters(flat, *sys), &fixed, &structural);
  if (fixed.empty()) return 0;

  // Rewrite (an if on a constant condition is its branch), dropping initial equations that are
  // now 0 = 0.
  auto fold = [&](ExprId e) { return e.valid() && (p.mask(e) & kHasParam) ? ReplaceNodes(&p, e, fixed, kHasParam) : e; };
  // An equation of a conditional block whose guard is false is no equation (docs/FORMAT.md,
  // "Conditional equation blocks").
  std::vector<SystemEquation> equations;
  equations.reserve(sys->equations.size());
  for (auto e : sys->equations) {
    e.residual = fold(e.residual);
    if (e.kind == SystemEquation::Kind::kDynamic && flat.equations[e.origin].guarded && p.IsConst(e.residual, 0.0)) continue;
    equations.push_back(e);
  }
  sys->equations.swap(equations);
  std::vector<SystemEquation> initial;
  for (auto e : sys->initial) {
    e.residual = fold(e.residual);
    if (!p.IsConst(e.residual, 0.0)) initial.push_back(e);
  }
  sys->initial.swap(initial);
  for (auto& o : sys->outputs) o = fold(o);
  FlatSystem& f = sys->MutableFlat();
  for (uint32_t q : structural) f.structural.Set(ParamId(q), params[q]);
  return conditions + evaluated;
}

}  // namespace momenta

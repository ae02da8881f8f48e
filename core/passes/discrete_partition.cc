#include "core/passes/discrete_partition.h"

#include <sstream>

#include "core/base/graph.h"

namespace momenta {

namespace {

/// A discrete variable is constant between events and has no derivative: der() of one (written,
/// or through der(expr)) is the model's mistake, reported with its equation.
void CheckNoDerivativeOfDiscrete(const EquationSystem& sys) {
  const ExprPool& p = *sys.pool;
  const FlatSystem& flat = *sys.flat;
  auto check = [&](const SystemEquation& eq, const FlatEquation& origin) {
    if (!(p.mask(eq.residual) & kHasDer)) return;
    for (ExprId leaf : CollectLeaves(p, eq.residual, kHasDer)) {
      const VarId v(p.node(leaf).a);
      if (!flat.variables[v.value()].discrete) continue;
      const std::string name = flat.VariableName(v);
      throw ModelError(origin.loc, "der(" + name + ") in " + sys.Describe(eq) + ": " + name +
                                       " is a discrete variable (Integer, Boolean, or set by a "
                                       "when-clause), constant between events, so it has no "
                                       "derivative; der() applies to continuous Real variables");
    }
  };
  for (const auto& eq : sys.equations) check(eq, flat.equations[eq.origin]);
  for (const auto& eq : sys.initial) {
    if (eq.kind == SystemEquation::Kind::kInitial) check(eq, flat.initial_equations[eq.origin]);
  }
}

}  // namespace

EquationSystem PartitionDiscrete(EquationSystem sys, DiscreteStats* stats) {
  ExprPool& p = *sys.pool;
  const FlatSystem& flat = *sys.flat;
  const size_t nv = sys.role.size();
  CheckNoDerivativeOfDiscrete(sys);
  // The discrete unknowns: discrete, still unknown, not set by a when-clause or an impact.
  std::vector<bool> assigned(nv, false);
  for (const auto& w : sys.whens) {
    for (const auto& a : w.assigns) assigned[a.first.value()] = true;
  }
  for (const auto& im : sys.impacts) assigned[im.contact.value()] = true;
  std::vector<int32_t> col_of(nv, -1);
  std::vector<uint32_t> var_of_col;
  for (uint32_t v = 0; v < nv; ++v) {
    if (sys.role[v] == VarRole::kUnknown && flat.variables[v].discrete && !assigned[v]) {
      col_of[v] = static_cast<int32_t>(var_of_col.size());
      var_of_col.push_back(v);
    }
    if (flat.variables[v].discrete) ++stats->variables;
  }
  if (var_of_col.empty()) return sys;
  // Edges: equation k can define discrete variable d when it is explicitly solvable for d.
  BipartiteGraph g;
  g.num_cols = static_cast<uint32_t>(var_of_col.size());
  std::vector<std::vector<std::pair<uint32_t, ExprId>>> solutions(sys.equations.size());
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    std::vector<uint32_t> row;
    ExprId r = sys.equations[k].residual;
    for (ExprId leaf : CollectLeaves(p, r, kHasVar)) {
      uint32_t v = p.node(leaf).a;
      if (col_of[v] < 0) continue;
      ExprId coefficient;
      ExprId value = SolveFor(&p, r, leaf, false, &coefficient);
      if (!value.valid() || ContainsLeaf(p, value, leaf)) continue;
      row.push_back(static_cast<uint32_t>(col_of[v]));
      solutions[k].emplace_back(v, value);
    }
    g.AddRow(row);
  }
  Matching m = MaximumMatching(g);
  // Every discrete unknown needs its equation.
  std::vector<std::string> missing;
  for (uint32_t c = 0; c < g.num_cols; ++c) {
    if (m.col_to_row[c] < 0) missing.push_back(sys.flat->DescribeVariable(VarId(var_of_col[c])));
  }
  if (!missing.empty()) {
    std::ostringstream msg;
    msg << flat.file << ": these discrete variables of " << flat.model_name
        << " are set by no equation of the form 'x = expression' and by no when-clause:";
    for (const auto& s : missing) msg << "\n    " << s;
    throw ModelError(msg.str());
  }
  // Take the matched equations out, in dependency order (a discrete value may use others).
  std::vector<int32_t> eq_of_col(g.num_cols, -1);
  std::vector<DiscreteEquation> defs(g.num_cols);
  for (uint32_t k = 0; k < sys.equations.size(); ++k) {
    int32_t c = m.row_to_col[k];
    if (c < 0) continue;
    eq_of_col[c] = static_cast<int32_t>(k);
    for (const auto& [v, value] : solutions[k]) {
      if (col_of[v] == c) defs[c] = {VarId(v), value, sys.equations[k].origin};
    }
  }
  std::vector<uint32_t> start{0}, adj;
  for (uint32_t c = 0; c < g.num_cols; ++c) {
    for (ExprId leaf : CollectLeaves(p, defs[c].value, kHasVar)) {
      int32_t d = col_of[p.node(leaf).a];
      if (d >= 0) adj.push_back(static_cast<uint32_t>(d));
    }
    start.push_back(static_cast<uint32_t>(adj.size()));
  }
  for (const auto& comp : StronglyConnectedComponents(g.num_cols, start, adj)) {
    if (comp.size() > 1) {
      std::ostringstream msg;
      msg << flat.file << ": the discrete variables";
      for (uint32_t c : comp) msg << " " << flat.VariableName(VarId(var_of_col[c]));
      msg << " depend on each other at the same event; break the loop with pre()";
      throw ModelError(msg.str());
    }
    sys.discrete.push_back(defs[comp[0]]);
  }
  std::vector<SystemEquation> kept;
  for (uint32_t k = 0; k < sys.equations.size(); ++k) {
    if (m.row_to_col[k] < 0) kept.push_back(sys.equations[k]);
  }
  stats->equations = sys.equations.size() - kept.size();
  sys.equations.swap(kept);
  return sys;
}

}  // namespace momenta

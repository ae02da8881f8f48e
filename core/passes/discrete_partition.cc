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

/// The discrete unknowns: discrete, still unknown, not set by a when-clause or an impact, as the
/// columns of the matching; counts the discrete variables into `stats`.
struct DiscreteUnknowns {
  std::vector<int32_t> col_of;     ///< by flat variable: its column, or -1
  std::vector<uint32_t> var_of_col;
};

DiscreteUnknowns FindDiscreteUnknowns(const EquationSystem& sys, DiscreteStats* stats) {
  const FlatSystem& flat = *sys.flat;
  const size_t nv = sys.role.size();
  std::vector<bool> assigned(nv, false);
  for (const auto& w : sys.whens) {
    for (const auto& a : w.assigns) assigned[a.first.value()] = true;
  }
  for (const auto& im : sys.impacts) assigned[im.contact.value()] = true;
  DiscreteUnknowns unknowns;
  unknowns.col_of.assign(nv, -1);
  for (uint32_t v = 0; v < nv; ++v) {
    if (sys.role[v] == VarRole::kUnknown && flat.variables[v].discrete && !assigned[v]) {
      unknowns.col_of[v] = static_cast<int32_t>(unknowns.var_of_col.size());
      unknowns.var_of_col.push_back(v);
    }
    if (flat.variables[v].discrete) ++stats->variables;
  }
  return unknowns;
}

/// Which equation can define which discrete unknown: an edge where the equation is explicitly
/// solvable for it, with that solution (by equation: variable and value).
struct DefiningEquations {
  BipartiteGraph graph;
  std::vector<std::vector<std::pair<uint32_t, ExprId>>> solutions;
};

DefiningEquations FindDefiningEquations(const EquationSystem& sys,
                                        const DiscreteUnknowns& unknowns) {
  ExprPool& p = *sys.pool;
  DefiningEquations defining;
  BipartiteGraph& g = defining.graph;
  g.num_cols = static_cast<uint32_t>(unknowns.var_of_col.size());
  defining.solutions.resize(sys.equations.size());
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    std::vector<uint32_t> row;
    ExprId r = sys.equations[k].residual;
    for (ExprId leaf : CollectLeaves(p, r, kHasVar)) {
      uint32_t v = p.node(leaf).a;
      if (unknowns.col_of[v] < 0) continue;
      ExprId coefficient;
      ExprId value = SolveFor(&p, r, leaf, false, &coefficient);
      if (!value.valid() || ContainsLeaf(p, value, leaf)) continue;
      row.push_back(static_cast<uint32_t>(unknowns.col_of[v]));
      defining.solutions[k].emplace_back(v, value);
    }
    g.AddRow(row);
  }
  return defining;
}

/// Every discrete unknown needs its equation: throws ModelError naming those without one.
void CheckAllDefined(const EquationSystem& sys, const DiscreteUnknowns& unknowns,
                     const BipartiteGraph& g, const Matching& m) {
  std::vector<std::string> missing;
  for (uint32_t c = 0; c < g.num_cols; ++c) {
    if (m.col_to_row[c] < 0) {
      missing.push_back(sys.flat->DescribeVariable(VarId(unknowns.var_of_col[c])));
    }
  }
  if (missing.empty()) return;
  std::ostringstream msg;
  msg << sys.flat->file << ": these discrete variables of " << sys.flat->model_name
      << " are set by no equation of the form 'x = expression' and by no when-clause:";
  for (const auto& s : missing) msg << "\n    " << s;
  throw ModelError(msg.str());
}

/// The matched equations as discrete equations in sys->discrete, in dependency order (a discrete
/// value may use others); throws ModelError for discrete variables that depend on each other.
void OrderDiscreteEquations(EquationSystem* sys, const DiscreteUnknowns& unknowns,
                            const DefiningEquations& defining, const Matching& m) {
  const ExprPool& p = *sys->pool;
  const uint32_t num_cols = defining.graph.num_cols;
  std::vector<DiscreteEquation> defs(num_cols);
  for (uint32_t k = 0; k < sys->equations.size(); ++k) {
    int32_t c = m.row_to_col[k];
    if (c < 0) continue;
    for (const auto& [v, value] : defining.solutions[k]) {
      if (unknowns.col_of[v] == c) defs[c] = {VarId(v), value, sys->equations[k].origin};
    }
  }
  std::vector<uint32_t> start{0}, adj;
  for (uint32_t c = 0; c < num_cols; ++c) {
    for (ExprId leaf : CollectLeaves(p, defs[c].value, kHasVar)) {
      int32_t d = unknowns.col_of[p.node(leaf).a];
      if (d >= 0) adj.push_back(static_cast<uint32_t>(d));
    }
    start.push_back(static_cast<uint32_t>(adj.size()));
  }
  for (const auto& comp : StronglyConnectedComponents(num_cols, start, adj)) {
    if (comp.size() > 1) {
      std::ostringstream msg;
      msg << sys->flat->file << ": the discrete variables";
      for (uint32_t c : comp) msg << " " << sys->flat->VariableName(VarId(unknowns.var_of_col[c]));
      msg << " depend on each other at the same event; break the loop with pre()";
      throw ModelError(msg.str());
    }
    sys->discrete.push_back(defs[comp[0]]);
  }
}

}  // namespace

EquationSystem PartitionDiscrete(EquationSystem sys, DiscreteStats* stats) {
  CheckNoDerivativeOfDiscrete(sys);
  const DiscreteUnknowns unknowns = FindDiscreteUnknowns(sys, stats);
  if (unknowns.var_of_col.empty()) return sys;
  const DefiningEquations defining = FindDefiningEquations(sys, unknowns);
  const Matching m = MaximumMatching(defining.graph);
  CheckAllDefined(sys, unknowns, defining.graph, m);
  OrderDiscreteEquations(&sys, unknowns, defining, m);
  // The matched equations leave the continuous ones.
  std::vector<SystemEquation> kept;
  for (uint32_t k = 0; k < sys.equations.size(); ++k) {
    if (m.row_to_col[k] < 0) kept.push_back(sys.equations[k]);
  }
  stats->equations = sys.equations.size() - kept.size();
  sys.equations.swap(kept);
  return sys;
}

}  // namespace momenta

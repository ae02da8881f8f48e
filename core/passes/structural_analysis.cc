// The unknowns of the equations are, for each variable still unknown, its derivative if it is a
// state (der(x) appears) and the variable itself otherwise. A perfect matching of equations to
// those unknowns means the system is structurally regular with index at most 1; IDA then solves
// for (der(x), y) given x.

#include "core/passes/structural_analysis.h"

#include <algorithm>
#include <sstream>
#include <unordered_map>

#include "core/base/graph.h"
#include "core/base/messages.h"

namespace momenta {

namespace {

constexpr size_t kListLimit = 12;

std::string ListVariables(const EquationSystem& sys, const std::vector<uint32_t>& vars) {
  std::ostringstream s;
  for (size_t k = 0; k < vars.size() && k < kListLimit; ++k) {
    s << "\n    " << sys.flat->DescribeVariable(VarId(vars[k]));
    const FlatVariable& v = sys.flat->variables[vars[k]];
    if (v.is_input) s << " — a signal input: connect it to an output";
  }
  if (vars.size() > kListLimit) s << "\n    … and " << vars.size() - kListLimit << " more";
  return s.str();
}

std::string ListEquations(const EquationSystem& sys, const std::vector<uint32_t>& rows) {
  std::ostringstream s;
  for (size_t k = 0; k < rows.size() && k < kListLimit; ++k) {
    s << "\n    " << sys.Describe(sys.equations[rows[k]]);
  }
  if (rows.size() > kListLimit) s << "\n    … and " << rows.size() - kListLimit << " more";
  return s.str();
}


/// The matching graph of the equations and the unknowns (columns: the unknown variables; each
/// row: a state's derivative or an algebraic unknown), and the pencil graph, where a state counts
/// by itself as well (for telling a higher index from a singular system).
struct Incidence {
  BipartiteGraph graph, pencil;
  std::vector<uint32_t> var_of_col;
};

/// The incidence of `sys`'s equations; sets the states of `structure`.
Incidence FindIncidence(const EquationSystem& sys, Structure* structure) {
  const ExprPool& p = *sys.pool;
  const size_t nv = sys.role.size();
  Incidence incidence;
  structure->is_state = DifferentiatedVariables(sys);
  // Columns: the unknown variables.
  std::vector<int32_t> col_of_var(nv, -1);
  std::vector<uint32_t>& var_of_col = incidence.var_of_col;
  for (uint32_t v = 0; v < nv; ++v) {
    if (sys.role[v] != VarRole::kUnknown || sys.flat->variables[v].discrete) {
      structure->is_state[v] = false;
      continue;
    }
    col_of_var[v] = static_cast<int32_t>(var_of_col.size());
    var_of_col.push_back(v);
    structure->num_states += structure->is_state[v];
  }
  // Rows: each equation's unknowns.
  BipartiteGraph& g = incidence.graph;
  BipartiteGraph& pencil = incidence.pencil;
  g.num_cols = pencil.num_cols = static_cast<uint32_t>(var_of_col.size());
  std::vector<uint32_t> row, prow;
  std::vector<ExprId> leaves;  // scratch
  for (const SystemEquation& eq : sys.equations) {
    row.clear();
    prow.clear();
    CollectLeaves(p, eq.residual, kHasVar | kHasDer, &leaves);
    for (ExprId leaf : leaves) {
      uint32_t v = p.node(leaf).a;
      int32_t c = col_of_var[v];
      if (c < 0) continue;
      bool der = p.op(leaf) == Op::kDer;
      if (der == static_cast<bool>(structure->is_state[v])) row.push_back(static_cast<uint32_t>(c));
      prow.push_back(static_cast<uint32_t>(c));
    }
    std::sort(prow.begin(), prow.end());
    prow.erase(std::unique(prow.begin(), prow.end()), prow.end());
    g.AddRow(row);
    pencil.AddRow(prow);
  }
  return incidence;
}

/// An equation left without unknowns (after eliminations) is redundant or contradicts others:
/// typically a closed loop of rigid parts, whose second constraint repeats the first. Throws
/// ModelError naming them when the system is otherwise balanced.
void CheckNoEmptyEquations(const EquationSystem& sys, const Incidence& incidence) {
  const BipartiteGraph& g = incidence.graph;
  const BipartiteGraph& pencil = incidence.pencil;
  std::vector<uint32_t> empty;
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    if (g.row_start[r] == g.row_start[r + 1] && pencil.row_start[r] == pencil.row_start[r + 1]) empty.push_back(r);
  }
  if (empty.empty() || sys.equations.size() != incidence.var_of_col.size()) return;
  std::ostringstream msg;
  msg << sys.flat->file << ": " << sys.flat->model_name << " has "
      << (empty.size() == 1 ? "an equation that no longer involves"
                            : std::to_string(empty.size()) + " equations that no longer involve")
      << " any unknown once the others are used, so it is redundant or contradicts them (a "
         "closed loop of rigid connections, two sources fixing one position, or a constraint "
         "stated twice):"
      << ListEquations(sys, empty);
  throw ModelError(msg.str());
}

/// The message for a balanced system whose pencil has a perfect matching: a constraint among
/// states that index reduction left (`over_rows`, the over-determined equations).
std::string HigherIndexMessage(const EquationSystem& sys, const Incidence& incidence,
                               const std::vector<uint32_t>& over_rows) {
  // The states a constraint involves count only through their derivatives in the matching
  // graph; name every variable of those equations instead.
  const BipartiteGraph& pencil = incidence.pencil;
  std::vector<uint32_t> over_vars;
  for (uint32_t r : over_rows) {
    for (uint32_t k = pencil.row_start[r]; k < pencil.row_start[r + 1]; ++k) {
      over_vars.push_back(incidence.var_of_col[pencil.cols[k]]);
    }
  }
  std::sort(over_vars.begin(), over_vars.end());
  over_vars.erase(std::unique(over_vars.begin(), over_vars.end()), over_vars.end());
  std::ostringstream msg;
  msg << sys.flat->file << ": " << sys.flat->model_name
      << " has structural index above 1: these equations constrain states that are also "
         "integrated, so the derivatives of the states are over-determined:"
      << ListEquations(sys, over_rows) << "\n  involving" << ListVariables(sys, over_vars)
      << "\n  Index reduction (Pantelides' algorithm and dummy derivatives) did not resolve "
         "it. Consider relating the states through a compliant element (a stiff spring) or "
         "making one of the variables a non-state.";
  return msg.str();
}

/// Throws ModelError for a system without a perfect matching `m`: of index above 1, unbalanced
/// or structurally singular, with its over- and under-determined parts in the user's names.
[[noreturn]] void ReportUnmatched(const EquationSystem& sys, const Incidence& incidence,
                                  const Matching& m) {
  const BipartiteGraph& g = incidence.graph;
  const size_t ne = sys.equations.size(), nu = incidence.var_of_col.size();
  std::vector<uint32_t> over_rows, over_cols, under_rows, under_cols;
  OverDeterminedPart(g, m, &over_rows, &over_cols);
  UnderDeterminedPart(g, m, &under_rows, &under_cols);
  if (ne == nu && FastMaximumMatching(incidence.pencil).size == ne) {  // its size only
    throw ModelError(HigherIndexMessage(sys, incidence, over_rows));
  }
  std::vector<uint32_t> over_vars, under_vars;
  for (uint32_t c : over_cols) over_vars.push_back(incidence.var_of_col[c]);
  for (uint32_t c : under_cols) under_vars.push_back(incidence.var_of_col[c]);
  std::ostringstream msg;
  const std::string& file = sys.flat->file;
  if (ne != nu) {
    msg << file << ": " << sys.flat->model_name << " is unbalanced: " << Counted(ne, "equation")
        << " for " << Counted(nu, "unknown") << ".";
  } else {
    msg << file << ": " << sys.flat->model_name
        << " is structurally singular: the equations cannot be solved for all unknowns.";
  }
  if (!over_rows.empty()) {
    msg << "\n  Over-determined: " << Counted(over_rows.size(), "equation") << " for only "
        << Counted(over_cols.size(), "unknown") << ":" << ListEquations(sys, over_rows);
    if (!over_vars.empty()) msg << "\n  which involve" << ListVariables(sys, over_vars);
  }
  if (!under_cols.empty()) {
    msg << "\n  Under-determined: " << Counted(under_cols.size(), "unknown") << " with only "
        << Counted(under_rows.size(), "equation") << ":" << ListVariables(sys, under_vars);
    if (!under_rows.empty()) msg << "\n  which occur in" << ListEquations(sys, under_rows);
  }
  throw ModelError(msg.str());
}

}  // namespace

Structure AnalyseStructure(const EquationSystem& sys) {
  Structure structure;
  const Incidence incidence = FindIncidence(sys, &structure);
  const Matching m = MaximumMatching(incidence.graph);
  const size_t ne = sys.equations.size(), nu = incidence.var_of_col.size();
  CheckNoEmptyEquations(sys, incidence);
  if (m.size < ne || m.size < nu) ReportUnmatched(sys, incidence, m);
  structure.equation_of_var.assign(sys.role.size(), -1);
  structure.var_of_equation.assign(ne, -1);
  for (uint32_t r = 0; r < ne; ++r) {
    uint32_t v = incidence.var_of_col[m.row_to_col[r]];
    structure.var_of_equation[r] = static_cast<int32_t>(v);
    structure.equation_of_var[v] = static_cast<int32_t>(r);
  }
  return structure;
}

size_t KeepMatchedEquations(EquationSystem* sys, Structure* structure,
                            const std::vector<bool>& keep) {
  std::vector<SystemEquation> kept;
  std::vector<int32_t> var_of_eq;
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (!keep[k]) continue;
    var_of_eq.push_back(structure->var_of_equation[k]);
    kept.push_back(sys->equations[k]);
  }
  const size_t dropped = sys->equations.size() - kept.size();
  sys->equations.swap(kept);
  structure->var_of_equation.swap(var_of_eq);
  std::fill(structure->equation_of_var.begin(), structure->equation_of_var.end(), -1);
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    structure->equation_of_var[structure->var_of_equation[k]] = static_cast<int32_t>(k);
  }
  return dropped;
}

}  // namespace momenta

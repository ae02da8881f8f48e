#include "core/build.h"

#include <algorithm>
#include <chrono>
#include <sstream>

#include "core/alias_elimination.h"
#include "core/causalization.h"
#include "core/graph.h"
#include "core/index_reduction.h"
#include "core/pruning.h"
#include "core/structural_analysis.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// Columns of a residual: Var(v) -> y index; Der(v) -> y index (Jacobian) or n + state slot
/// (initialisation), via the maps given.
struct Columns {
  std::vector<int32_t> y_of_var;      ///< flat variable -> y index
  std::vector<int32_t> slot_of_y;     ///< y index -> state slot
};

/// The initialisation system's structure: which states had no initial condition (their start
/// values become fixed), and an error when the conditions over-determine the model.
std::vector<uint32_t> CompleteInitialConditions(const EquationSystem& sys, const CompiledModel& m,
                                                const Columns& cols) {
  const ExprPool& p = *sys.pool;
  const uint32_t n = static_cast<uint32_t>(m.unknowns.size());
  BipartiteGraph g;
  g.num_cols = n + static_cast<uint32_t>(m.state_y.size());
  auto row_of = [&](ExprId e) {
    std::vector<uint32_t> row;
    for (ExprId leaf : CollectLeaves(p, e, kHasVar | kHasDer | kHasPre)) {
      const Node& nd = p.node(leaf);
      int32_t y = cols.y_of_var[nd.a];
      if (y < 0) continue;
      if (nd.op == Op::kDer) {
        int32_t s = cols.slot_of_y[y];
        if (s >= 0) row.push_back(n + static_cast<uint32_t>(s));
      } else {
        row.push_back(static_cast<uint32_t>(y));
      }
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    return row;
  };
  for (ExprId r : m.residual_exprs) g.AddRow(row_of(r));
  for (ExprId r : m.initial_exprs) g.AddRow(row_of(r));
  Matching match = MaximumMatching(g);
  if (match.size < g.num_rows()) {
    std::vector<uint32_t> rows, over_cols;
    OverDeterminedPart(g, match, &rows, &over_cols);
    std::ostringstream msg;
    msg << sys.flat->file << ": the initial conditions of " << sys.flat->model_name
        << " over-determine it: these equations fix more than the " << over_cols.size()
        << " unknowns they involve:";
    size_t shown = 0;
    for (uint32_t r : rows) {
      if (shown++ == 12) break;
      msg << "\n    " << (r < n ? m.residual_origin[r] : m.initial_origin[r - n]);
    }
    msg << "\n  Remove one of the fixed start values (or set fixed: false).";
    throw ModelError(msg.str());
  }
  // Columns left free: reach a state's position through alternating paths and fix its start.
  std::vector<uint32_t> under_rows, under_cols;
  UnderDeterminedPart(g, match, &under_rows, &under_cols);
  std::vector<uint32_t> defaulted;
  for (uint32_t c : under_cols) {
    if (c < n && m.is_state[c]) defaulted.push_back(c);
  }
  // Check that fixing those completes the system.
  BipartiteGraph g2 = g;
  for (uint32_t c : defaulted) g2.AddRow({c});
  Matching m2 = MaximumMatching(g2);
  if (m2.size < g2.num_cols) {
    std::ostringstream msg;
    msg << sys.flat->file << ": the initial conditions of " << sys.flat->model_name
        << " leave unknowns undetermined:";
    size_t shown = 0;
    for (uint32_t c = 0; c < g2.num_cols; ++c) {
      if (m2.col_to_row[c] >= 0) continue;
      if (shown++ == 12) break;
      uint32_t y = c < n ? c : m.state_y[c - n];
      msg << "\n    " << (c < n ? "" : "der of ") << sys.flat->DescribeVariable(m.unknowns[y]);
    }
    throw ModelError(msg.str());
  }
  return defaulted;
}

/// Entries (row, col, value expression) of a sparse Jacobian, sorted into compressed columns.
struct Entry {
  int32_t row, col;
  ExprId value;
};

void SortToPattern(std::vector<Entry>* entries, int32_t rows, int32_t cols, SparsePattern* pattern,
                   std::vector<ExprId>* values) {
  std::sort(entries->begin(), entries->end(), [](const Entry& a, const Entry& b) {
    return a.col != b.col ? a.col < b.col : a.row < b.row;
  });
  pattern->rows = rows;
  pattern->cols = cols;
  pattern->col_start.assign(cols + 1, 0);
  pattern->row_index.clear();
  values->clear();
  for (const Entry& e : *entries) {
    ++pattern->col_start[e.col + 1];
    pattern->row_index.push_back(e.row);
    values->push_back(e.value);
  }
  for (int32_t c = 0; c < cols; ++c) pattern->col_start[c + 1] += pattern->col_start[c];
}

}  // namespace

std::shared_ptr<const CompiledModel> BuildModel(const ModelSpec& spec, const Library& library,
                                                const ParameterOverrides& overrides,
                                                BuildReport* report) {
  auto pass_start = Clock::now();
  auto record = [&](const std::string& name, size_t vars, size_t eqs, const std::string& note) {
    report->passes.push_back({name, Seconds(pass_start), vars, eqs, note});
    pass_start = Clock::now();
  };

  // Flatten.
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, library, overrides));
  report->num_components = flat->instances.size();
  report->num_parameters = flat->parameters.size();
  {
    std::ostringstream note;
    note << flat->instances.size() << " components, " << flat->parameters.size() << " parameters";
    record("flatten", flat->variables.size(), flat->equations.size(), note.str());
  }
  // Parameters are evaluated now too, so a bad value is reported before any solving.
  EvaluateParameters(*flat, overrides);
  ExprPool& p = *flat->pool;
  EquationSystem sys = MakeEquationSystem(flat);

  // Simplify: aliases, derivative aliases and constrained states, until nothing changes.
  AliasStats alias;
  IndexStats index;
  for (int round = 0; round < 20; ++round) {
    size_t before = sys.num_unknowns();
    sys = EliminateAliases(std::move(sys), &alias);
    size_t der_before = index.derivative_aliases;
    sys = ReduceIndex(std::move(sys), &index);
    if (sys.num_unknowns() == before && index.derivative_aliases == der_before) break;
  }
  {
    std::ostringstream note;
    note << alias.aliases << " aliases, " << alias.constants << " constants";
    record("alias elimination", sys.num_unknowns() + index.constrained_states, sys.equations.size() + index.constrained_states, note.str());
    std::ostringstream note2;
    note2 << index.derivative_aliases << " derivative aliases, " << index.constrained_states
          << " constrained states";
    record("index reduction", sys.num_unknowns(), sys.equations.size(), note2.str());
  }

  // Outputs default to every state.
  std::vector<std::string> output_names;
  for (const auto& o : flat->outputs) output_names.push_back(o.text);

  Structure st = AnalyseStructure(sys);
  {
    std::ostringstream note;
    note << st.num_states << " states, structurally regular, index <= 1";
    record("structural analysis", sys.num_unknowns(), sys.equations.size(), note.str());
  }
  if (output_names.empty()) {
    for (uint32_t v = 0; v < st.is_state.size(); ++v) {
      if (!st.is_state[v]) continue;
      output_names.push_back(flat->variables[v].name);
      sys.outputs.push_back(p.Var(VarId(v)));
    }
  }

  PruneStats pruned;
  sys = Prune(std::move(sys), &st, &pruned);
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] == VarRole::kPruned) report->pruned.push_back(flat->variables[v].name);
  }
  {
    std::ostringstream note;
    note << pruned.variables << " variables and " << pruned.equations << " equations not needed by the outputs";
    record("pruning", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  CausalStats causal;
  sys = Causalize(std::move(sys), &st, &causal);
  {
    std::ostringstream note;
    note << causal.inlined << " solved explicitly, " << causal.algebraic_loops << " algebraic loops ("
         << causal.loop_variables << " unknowns)";
    record("causalisation", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  // Assemble the DAE: unknowns in declaration order, each with its matched equation.
  auto m = std::make_shared<CompiledModel>();
  m->flat = flat;
  m->pool = flat->pool;
  m->experiment = flat->experiment;
  Columns cols;
  cols.y_of_var.assign(sys.role.size(), -1);
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] != VarRole::kUnknown) continue;
    cols.y_of_var[v] = static_cast<int32_t>(m->unknowns.size());
    m->unknowns.push_back(VarId(v));
    m->is_state.push_back(st.is_state[v]);
    m->nominal.push_back(flat->variables[v].nominal);
    m->residual_exprs.push_back(sys.equations[st.equation_of_var[v]].residual);
    m->residual_origin.push_back(sys.Describe(sys.equations[st.equation_of_var[v]]));
    if (st.is_state[v]) report->states.push_back(flat->variables[v].name);
  }
  const uint32_t n = static_cast<uint32_t>(m->unknowns.size());
  cols.slot_of_y.assign(n, -1);
  for (uint32_t y = 0; y < n; ++y) {
    if (!m->is_state[y]) continue;
    cols.slot_of_y[y] = static_cast<int32_t>(m->state_y.size());
    m->state_y.push_back(y);
  }
  m->output_names = output_names;
  m->output_exprs = sys.outputs;
  for (const auto& e : sys.initial) {
    m->initial_exprs.push_back(e.residual);
    m->initial_origin.push_back(sys.Describe(e));
  }
  m->guards = sys.guards;
  for (const auto& g : sys.guards) m->guard_text.push_back(ToString(p, g.divisor, flat->Namer()));

  // Initial conditions: states without one take their start value (as Modelica tools do).
  std::vector<uint32_t> defaulted = CompleteInitialConditions(sys, *m, cols);
  for (uint32_t y : defaulted) {
    VarId v = m->unknowns[y];
    m->initial_exprs.push_back(p.Sub(p.Var(v), sys.guess[v.value()]));
    m->initial_origin.push_back("start value of " + flat->variables[v.value()].name + " (not fixed; taken as initial condition)");
    m->defaulted_starts.push_back(flat->variables[v.value()].name);
  }
  if (!m->defaulted_starts.empty()) {
    std::ostringstream w;
    w << "initial conditions: no fixed start value determines ";
    for (size_t k = 0; k < m->defaulted_starts.size() && k < 10; ++k) w << (k ? ", " : "") << m->defaulted_starts[k];
    if (m->defaulted_starts.size() > 10) w << " and " << m->defaulted_starts.size() - 10 << " more";
    w << "; their start values are used (add fixed: true to say so)";
    report->warnings.push_back(w.str());
  }
  record("initialisation", n + m->state_y.size(), n + m->initial_exprs.size(),
         std::to_string(m->initial_exprs.size()) + " initial equations, " + std::to_string(defaulted.size()) + " start values taken");

  // Compile.
  ProgramCompiler compiler(p, static_cast<uint32_t>(flat->parameters.size()), cols.y_of_var);
  m->residual = compiler.Compile(m->residual_exprs);
  // Jacobian entries dF_i/dy_j + cj dF_i/dy'_j, and the same partials for the initialisation
  // system, whose columns are y and then the states' y'.
  std::vector<Entry> entries, init_entries;
  for (uint32_t i = 0; i < n; ++i) {
    ExprId r = m->residual_exprs[i];
    for (ExprId leaf : CollectLeaves(p, r, kHasVar | kHasDer)) {
      const Node& nd = p.node(leaf);
      int32_t y = cols.y_of_var[nd.a];
      if (y < 0) continue;
      ExprId d = PartialDerivative(&p, r, leaf);
      if (p.IsConst(d, 0)) continue;
      bool der = nd.op == Op::kDer;
      entries.push_back({static_cast<int32_t>(i), y, der ? p.Mul(p.Cj(), d) : d});
      if (!der) {
        init_entries.push_back({static_cast<int32_t>(i), y, d});
      } else if (cols.slot_of_y[y] >= 0) {
        init_entries.push_back({static_cast<int32_t>(i), static_cast<int32_t>(n) + cols.slot_of_y[y], d});
      }
    }
  }
  {
    // Merge the y and y' parts of each (row, col).
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
      return a.col != b.col ? a.col < b.col : a.row < b.row;
    });
    std::vector<Entry> merged;
    for (const Entry& e : entries) {
      if (!merged.empty() && merged.back().row == e.row && merged.back().col == e.col) {
        merged.back().value = p.Add(merged.back().value, e.value);
      } else {
        merged.push_back(e);
      }
    }
    std::vector<ExprId> values;
    SortToPattern(&merged, static_cast<int32_t>(n), static_cast<int32_t>(n), &m->jacobian_pattern, &values);
    m->jacobian = compiler.Compile(values);
  }
  // Initialisation residual and Jacobian: rows [F; G], columns [y; y' of states].
  {
    std::vector<ExprId> roots = m->residual_exprs;
    roots.insert(roots.end(), m->initial_exprs.begin(), m->initial_exprs.end());
    m->init_residual = compiler.Compile(roots);
    for (size_t gi = 0; gi < m->initial_exprs.size(); ++gi) {
      ExprId r = m->initial_exprs[gi];
      int32_t row = static_cast<int32_t>(n + gi);
      for (ExprId leaf : CollectLeaves(p, r, kHasVar | kHasDer)) {
        const Node& nd = p.node(leaf);
        int32_t y = cols.y_of_var[nd.a];
        if (y < 0) continue;
        bool der = nd.op == Op::kDer;
        if (der && cols.slot_of_y[y] < 0) continue;
        ExprId d = PartialDerivative(&p, r, leaf);
        if (p.IsConst(d, 0)) continue;
        int32_t col = der ? static_cast<int32_t>(n) + cols.slot_of_y[y] : y;
        init_entries.push_back({row, col, d});
      }
    }
    std::vector<ExprId> values;
    int32_t size = static_cast<int32_t>(n + m->state_y.size());
    SortToPattern(&init_entries, size, size, &m->init_pattern, &values);
    m->init_jacobian = compiler.Compile(values);
  }
  m->outputs = compiler.Compile(m->output_exprs);
  {
    std::vector<ExprId> starts;
    for (VarId v : m->unknowns) starts.push_back(sys.guess[v.value()]);
    m->start_values = compiler.Compile(starts);
  }
  {
    std::vector<ExprId> divisors;
    for (const auto& g : m->guards) divisors.push_back(g.divisor);
    m->guard_values = compiler.Compile(divisors);
  }
  compiler.Finish({&m->residual, &m->jacobian, &m->outputs, &m->start_values, &m->init_residual,
                   &m->init_jacobian, &m->guard_values, &compiler.parameter_program()});
  m->parameters = compiler.parameter_program();
  m->layout = compiler.layout();
  m->constants = compiler.constants();
  {
    std::ostringstream note;
    note << m->residual.size() << " residual, " << m->jacobian.size() << " Jacobian ("
         << m->jacobian_pattern.nnz() << " nonzeros), " << m->parameters.size()
         << " parameter instructions";
    record("compilation", n, n, note.str());
  }
  return m;
}

}  // namespace momenta

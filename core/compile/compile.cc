#include "core/compile/compile.h"

#include <algorithm>
#include <unordered_map>

#include "core/compile/compile_stages.h"
#include "core/compile/initial_conditions.h"

namespace momenta {

namespace {

bool ColumnMajor(const JacobianEntry& a, const JacobianEntry& b) {
  if (a.col != b.col) return a.col < b.col;
  if (a.row != b.row) return a.row < b.row;
  return a.der < b.der;
}

/// Sorts `entries` (columns below `cols`) by ColumnMajor. They are made row by row, so a stable
/// counting sort by column orders them by (column, row) in linear time, and leaves only a y and
/// a y' partial of one (row, column) to put in order (std::sort, a call per comparison, was a
/// tenth of compilation on a large model). Entries in neither order are sorted the general way.
void SortColumnMajor(std::vector<JacobianEntry>* entries, int32_t cols) {
  std::vector<JacobianEntry>& in = *entries;
  auto column_major = [](const JacobianEntry& a, const JacobianEntry& b) {
    return ColumnMajor(a, b);
  };
  if (std::is_sorted(in.begin(), in.end(), column_major)) return;
  for (size_t k = 1; k < in.size(); ++k) {
    if (in[k].row < in[k - 1].row) {
      std::sort(in.begin(), in.end(), column_major);
      return;
    }
  }
  std::vector<uint32_t> next(static_cast<size_t>(cols) + 1, 0);  // per column: its next place
  for (const JacobianEntry& e : in) ++next[e.col + 1];
  for (int32_t c = 0; c < cols; ++c) next[c + 1] += next[c];
  std::vector<JacobianEntry> sorted(in.size());
  for (const JacobianEntry& e : in) sorted[next[e.col]++] = e;
  for (size_t k = 1; k < sorted.size(); ++k) {
    if (ColumnMajor(sorted[k], sorted[k - 1])) std::swap(sorted[k], sorted[k - 1]);
  }
  in.swap(sorted);
}

/// The pattern and values of `entries`, sorted by ColumnMajor.
void SortToPattern(std::vector<JacobianEntry>* entries, int32_t rows, int32_t cols,
                   SparsePattern* pattern, std::vector<ExprId>* values) {
  SortColumnMajor(entries, cols);
  pattern->rows = rows;
  pattern->cols = cols;
  pattern->col_start.assign(cols + 1, 0);
  pattern->row_index.clear();
  pattern->row_index.reserve(entries->size());
  values->clear();
  values->reserve(entries->size());
  for (const JacobianEntry& e : *entries) {
    ++pattern->col_start[e.col + 1];
    pattern->row_index.push_back(e.row);
    values->push_back(e.value);
  }
  for (int32_t c = 0; c < cols; ++c) pattern->col_start[c + 1] += pattern->col_start[c];
}

/// The rows of the initialisation system [F; G] that may give a start guess, with their unknowns,
/// and each unknown's rows: flat lists with offsets, where a vector per row and per unknown made
/// hundreds of thousands.
struct GuessRows {
  std::vector<ExprId> rows;
  std::vector<uint32_t> row_start{0}, row_ys;  ///< row r's unknowns: row_ys[row_start[r] ..]
  std::vector<uint32_t> y_start, y_rows;        ///< unknown y's rows: y_rows[y_start[y] ..]
  std::vector<uint32_t> missing;                ///< per row: its unknowns not guessed yet
  std::vector<uint32_t> ready;                  ///< rows with one unknown left (a queue)
};

/// The rows of variables, parameters and constants alone (none is guessed yet).
GuessRows FindGuessRows(const ExprPool& p, const CompiledModel& m, const VariableSlots& slots) {
  constexpr uint8_t kOther = kHasDer | kHasTime | kHasPre | kHasRelation | kHasInitial | kHasCond;
  GuessRows g;
  std::vector<ExprId> leaves;  // scratch
  auto add_row = [&](ExprId e) {
    if (p.node(e).mask & kOther) return;
    CollectLeaves(p, e, kHasVar, &leaves);
    const size_t first = g.row_ys.size();
    for (ExprId leaf : leaves) {
      const int32_t y = slots.y_of_var[p.node(leaf).a];
      if (y < 0) {  // a discrete value: not known before the start values
        g.row_ys.resize(first);
        return;
      }
      g.row_ys.push_back(static_cast<uint32_t>(y));
    }
    const uint32_t r = static_cast<uint32_t>(g.rows.size());
    const uint32_t count = static_cast<uint32_t>(g.row_ys.size() - first);
    g.rows.push_back(e);
    g.row_start.push_back(static_cast<uint32_t>(g.row_ys.size()));
    g.missing.push_back(count);
    if (count == 1) g.ready.push_back(r);
  };
  for (ExprId e : m.residual_exprs) add_row(e);
  for (ExprId e : m.initial_exprs) add_row(e);
  const uint32_t n = static_cast<uint32_t>(m.unknowns.size());
  g.y_start.assign(n + 1, 0);
  g.y_rows.resize(g.row_ys.size());
  for (uint32_t y : g.row_ys) ++g.y_start[y + 1];
  for (uint32_t y = 0; y < n; ++y) g.y_start[y + 1] += g.y_start[y];
  std::vector<uint32_t> next(g.y_start.begin(), g.y_start.end() - 1);
  for (uint32_t r = 0; r < g.rows.size(); ++r) {
    for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) {
      g.y_rows[next[g.row_ys[k]]++] = r;
    }
  }
  return g;
}

/// Start guesses for y. A start value that is not fixed is only a guess, and the components'
/// defaults (a body's position starts at 0) are poor ones where the fixed conditions determine the
/// variable: a pendulum chain's bodies would all start at the pivot while the joint angles put them
/// radians away. So the guesses are found as the initialisation system [F; G] would determine
/// them, in dependency (block-lower-triangular) order: an equation with one unknown not yet
/// guessed that is linear in it with a numeric coefficient gives its guess, from the guesses of
/// the others (first from the fixed start values and the parameters); when none is left, the
/// start value of a variable still open (algebraic loops) is taken, one the model gives before a
/// default 0, and the search goes on.
/// Only equations of variables, parameters and constants are used; the guesses stay
/// parameter-only (each refers to the earlier ones' expressions, shared, so linear in size).
std::vector<ExprId> PropagatedStartGuesses(ExprPool* pool, const EquationSystem& sys,
                                           const CompiledModel& m, const VariableSlots& slots) {
  ExprPool& p = *pool;
  const uint32_t n = static_cast<uint32_t>(m.unknowns.size());
  std::vector<ExprId> starts(n);
  std::vector<bool> known(n, false);
  for (uint32_t y = 0; y < n; ++y) starts[y] = sys.guess[m.unknowns[y].value()];
  GuessRows g = FindGuessRows(p, m, slots);
  // Row r2 has one unknown fewer to find now that y is known.
  auto now_known = [&](uint32_t y) {
    known[y] = true;
    for (uint32_t k = g.y_start[y]; k < g.y_start[y + 1]; ++k) {
      const uint32_t r2 = g.y_rows[k];
      if (--g.missing[r2] == 1) g.ready.push_back(r2);
    }
  };
  std::unordered_map<uint32_t, ExprId> map;  // known unknowns -> their guesses, for one row
  for (size_t k = 0, next_open = 0, next_given = 0;; ++k) {
    if (k == g.ready.size()) {
      // No explicit equation left: a variable still open takes its start value, first one whose
      // start the model gives (not the default 0), so that a body's quaternions (start
      // {0, 0, 0, 1}) give the orientation matrix rather than the matrix's zeros giving them.
      while (next_given < n && (known[next_given] || p.IsConst(starts[next_given], 0))) ++next_given;
      while (next_open < n && known[next_open]) ++next_open;
      if (next_open == n) break;
      now_known(static_cast<uint32_t>(next_given < n ? next_given : next_open));
      --k;
      continue;
    }
    const uint32_t r = g.ready[k];
    if (g.missing[r] != 1) continue;
    uint32_t target = n;
    map.clear();
    for (uint32_t j = g.row_start[r]; j < g.row_start[r + 1]; ++j) {
      const uint32_t y = g.row_ys[j];
      if (!known[y]) {
        target = y;
      } else {
        map[p.Var(m.unknowns[y]).value()] = starts[y];
      }
    }
    if (target == n) continue;
    ExprId e = map.empty() ? g.rows[r] : ReplaceNodes(&p, g.rows[r], map, kHasVar);
    ExprId coefficient;
    ExprId value = SolveFor(&p, e, p.Var(m.unknowns[target]), false, &coefficient);
    if (!value.valid() || !p.IsParamOnly(value)) continue;
    starts[target] = value;
    now_known(target);
  }
  return starts;
}

/// Left out of the initial equations G as redundant (`plan`), kept with what they follow from.
void LeaveOutRedundant(const InitialConditionPlan& plan, CompiledModel* m) {
  for (size_t k = plan.redundant.size(); k-- > 0;) {
    const uint32_t g = plan.redundant[k];
    m->redundant_exprs.insert(m->redundant_exprs.begin(), m->initial_exprs[g]);
    m->redundant_origin.insert(m->redundant_origin.begin(), m->initial_origin[g]);
    m->redundant_from.insert(m->redundant_from.begin(), plan.redundant_from[k]);
    m->initial_exprs.erase(m->initial_exprs.begin() + g);
    m->initial_origin.erase(m->initial_origin.begin() + g);
  }
}

}  // namespace

// ---- the stages ---------------------------------------------------------------------------------

void CompileUnknowns(const EquationSystem& sys, const Structure& structure, CompileContext* ctx,
                     CompiledModel* m) {
  const FlatSystem& flat = *sys.flat;
  VariableSlots& slots = ctx->slots;
  slots.y_of_var.assign(sys.role.size(), -1);
  slots.disc_of_var.assign(sys.role.size(), -1);
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] != VarRole::kUnknown) continue;
    if (flat.variables[v].discrete) {
      slots.disc_of_var[v] = static_cast<int32_t>(m->discrete_vars.size());
      m->discrete_vars.push_back(VarId(v));
      continue;
    }
    slots.y_of_var[v] = static_cast<int32_t>(m->unknowns.size());
    m->unknowns.push_back(VarId(v));
    m->is_state.push_back(structure.is_state[v]);
    m->nominal.push_back(flat.variables[v].nominal);
    const SystemEquation& eq = sys.equations[structure.equation_of_var[v]];
    m->residual_exprs.push_back(eq.residual);
    m->residual_equations.push_back(eq);
    ctx->residual_source.push_back(eq.origin);
  }
  const uint32_t n = static_cast<uint32_t>(m->unknowns.size());
  slots.state_of_y.assign(n, -1);
  for (uint32_t y = 0; y < n; ++y) {
    if (!m->is_state[y]) continue;
    slots.state_of_y[y] = static_cast<int32_t>(m->state_y.size());
    m->state_y.push_back(y);
  }
}

std::string CompiledModel::guard_text(size_t k) const { return ToString(*pool, guards[k].divisor, flat->Namer()); }

void CompileInitialSystem(const EquationSystem& sys, CompileContext* ctx, CompiledModel* m) {
  ExprPool& p = *sys.pool;
  const VariableSlots& slots = ctx->slots;
  // Discrete start values; initial equations `pre(d) = expr` set them instead.
  ctx->discrete_start.resize(m->discrete_vars.size());
  for (size_t k = 0; k < m->discrete_vars.size(); ++k) {
    ctx->discrete_start[k] = sys.guess[m->discrete_vars[k].value()];
  }
  std::vector<ExprId> pres, vars;  // scratch
  for (const auto& e : sys.initial) {
    CollectLeaves(p, e.residual, kHasPre, &pres);
    CollectLeaves(p, e.residual, kHasVar | kHasDer, &vars);
    if (pres.size() == 1 && vars.empty() && slots.disc_of_var[p.node(pres[0]).a] >= 0) {
      ExprId value = SolveFor(&p, e.residual, pres[0], true, nullptr);
      if (value.valid() && p.IsParamOnly(value)) {
        ctx->discrete_start[slots.disc_of_var[p.node(pres[0]).a]] = value;
        continue;
      }
    }
    m->initial_exprs.push_back(e.residual);
    m->initial_origin.push_back(sys.Describe(e));
  }
  m->guards = sys.guards;

  // Redundant initial conditions are left out (and checked at the solution); states without an
  // initial condition take their start value (as Modelica tools do).
  const InitialConditionPlan plan =
      PlanInitialConditions(sys, *m, slots.y_of_var, slots.state_of_y);
  LeaveOutRedundant(plan, m);
  for (uint32_t y : plan.defaulted) {
    VarId v = m->unknowns[y];
    m->initial_exprs.push_back(p.Sub(p.Var(v), sys.guess[v.value()]));
    m->initial_origin.push_back("start value of " + sys.flat->VariableName(v) +
                                " (not fixed; taken as initial condition)");
    m->defaulted_starts.push_back(sys.flat->VariableName(v));
  }
}

void CompileResidualAndJacobian(CompileContext* ctx, ProgramCompiler* compiler, CompiledModel* m) {
  ExprPool& p = *m->pool;
  const VariableSlots& slots = ctx->slots;
  const uint32_t n = static_cast<uint32_t>(m->unknowns.size());
  m->residual = compiler->Compile(m->residual_exprs);
  // The partials of each row; a y' partial is the DAE Jacobian's cj dF/dy' and, for a state, the
  // initialisation Jacobian's column of its y'.
  std::vector<JacobianEntry> entries;
  PartialDerivatives partials(&p);
  // cj * d: most y' partials are the same number (the -1 of v - der(x)), so the last is kept
  // (the same node; only the lookup in the pool is spared).
  ExprId last_d, last_cj_d;
  auto times_cj = [&](ExprId d) {
    if (d != last_d) {
      last_d = d;
      last_cj_d = p.Mul(p.Cj(), d);
    }
    return last_cj_d;
  };
  for (uint32_t i = 0; i < n; ++i) {
    partials.Reset(m->residual_exprs[i], kHasVar | kHasDer);
    for (ExprId leaf : partials.Leaves()) {
      const Node leaf_node = p.node(leaf);  // a copy: new nodes may move the pool
      int32_t y = slots.y_of_var[leaf_node.a];
      if (y < 0) continue;
      ExprId d = partials.Of(leaf);
      if (p.IsConst(d, 0)) continue;
      bool der = leaf_node.op == Op::kDer;
      entries.push_back({static_cast<int32_t>(i), y, der ? times_cj(d) : d, der});
      if (!der) {
        ctx->init_entries.push_back({static_cast<int32_t>(i), y, d});
      } else if (slots.state_of_y[y] >= 0) {
        ctx->init_entries.push_back(
            {static_cast<int32_t>(i), static_cast<int32_t>(n) + slots.state_of_y[y], d});
      }
    }
  }
  SortColumnMajor(&entries, static_cast<int32_t>(n));
  // A y and a y' partial of one (row, column), now next to each other, make one entry.
  size_t merged = 0;
  for (const JacobianEntry& e : entries) {
    if (merged > 0 && entries[merged - 1].row == e.row && entries[merged - 1].col == e.col) {
      entries[merged - 1].value = p.Add(entries[merged - 1].value, e.value);
    } else {
      entries[merged++] = e;
    }
  }
  entries.resize(merged);
  std::vector<ExprId> values;
  SortToPattern(&entries, static_cast<int32_t>(n), static_cast<int32_t>(n), &m->jacobian_pattern, &values);
  std::vector<JacobianEntry>().swap(entries);  // given back before the programs that follow
  m->jacobian = compiler->Compile(values);
}

void CompileInitialization(CompileContext* ctx, ProgramCompiler* compiler, CompiledModel* m) {
  ExprPool& p = *m->pool;
  const VariableSlots& slots = ctx->slots;
  const uint32_t n = static_cast<uint32_t>(m->unknowns.size());
  std::vector<ExprId> roots = m->residual_exprs;
  roots.insert(roots.end(), m->initial_exprs.begin(), m->initial_exprs.end());
  m->init_residual = compiler->Compile(roots);
  m->redundant_residual = compiler->Compile(m->redundant_exprs);
  // The rows G (after the rows F, from CompileResidualAndJacobian): columns y, then the states' y'.
  std::vector<JacobianEntry>& entries = ctx->init_entries;
  PartialDerivatives partials(&p);
  for (size_t gi = 0; gi < m->initial_exprs.size(); ++gi) {
    int32_t row = static_cast<int32_t>(n + gi);
    partials.Reset(m->initial_exprs[gi], kHasVar | kHasDer);
    for (ExprId leaf : partials.Leaves()) {
      const Node leaf_node = p.node(leaf);  // a copy: new nodes may move the pool
      int32_t y = slots.y_of_var[leaf_node.a];
      if (y < 0) continue;
      bool der = leaf_node.op == Op::kDer;
      if (der && slots.state_of_y[y] < 0) continue;
      ExprId d = partials.Of(leaf);
      if (p.IsConst(d, 0)) continue;
      int32_t col = der ? static_cast<int32_t>(n) + slots.state_of_y[y] : y;
      entries.push_back({row, col, d});
    }
  }
  std::vector<ExprId> values;
  int32_t size = static_cast<int32_t>(n + m->state_y.size());
  SortToPattern(&entries, size, size, &m->init_pattern, &values);
  std::vector<JacobianEntry>().swap(entries);
  m->init_jacobian = compiler->Compile(values);
}

void CompileOutputs(ProgramCompiler* compiler, CompiledModel* m) {
  m->outputs = compiler->Compile(m->output_exprs);
}

void CompileStartValues(const EquationSystem& sys, const CompileContext& ctx,
                        ProgramCompiler* compiler, CompiledModel* m) {
  std::vector<ExprId> starts;
  for (VarId v : m->unknowns) starts.push_back(sys.guess[v.value()]);
  m->start_values = compiler->Compile(starts);
  m->start_guesses = compiler->Compile(PropagatedStartGuesses(m->pool.get(), sys, *m, ctx.slots));
}

void CompileGuards(ProgramCompiler* compiler, CompiledModel* m) {
  std::vector<ExprId> divisors;
  for (const auto& g : m->guards) divisors.push_back(g.divisor);
  m->guard_values = compiler->Compile(divisors);
}

// ---- the model ----------------------------------------------------------------------------------

std::shared_ptr<CompiledModel> CompileModel(EquationSystem sys, const Structure& structure,
                                            const std::vector<std::string>& output_names) {
  // The eliminations are applied: their memo (8 bytes per pool node) is not needed here.
  sys.eliminated->ReleaseMemo();
  auto m = std::make_shared<CompiledModel>();
  m->flat = sys.flat;
  m->pool = sys.pool;
  m->experiment = sys.flat->experiment;

  // The layout and the expressions to compile, events' relations frozen into conditions.
  CompileContext ctx;
  CompileUnknowns(sys, structure, &ctx, m.get());
  m->output_names = output_names;
  m->output_exprs = sys.outputs;
  CompileInitialSystem(sys, &ctx, m.get());
  CollectConditions(&sys, &ctx, m.get());

  // The programs, in the order that numbers their registers.
  ProgramCompiler compiler(*m->pool, static_cast<uint32_t>(m->flat->parameters.size()),
                           ctx.slots.y_of_var, ctx.slots.disc_of_var,
                           static_cast<uint32_t>(m->conditions.size()));
  CompileResidualAndJacobian(&ctx, &compiler, m.get());
  CompileInitialization(&ctx, &compiler, m.get());
  CompileOutputs(&compiler, m.get());
  CompileStartValues(sys, ctx, &compiler, m.get());
  CompileGuards(&compiler, m.get());
  CompileDiscrete(sys, ctx, &compiler, m.get());
  CompileZeroCrossings(ctx, &compiler, m.get());
  CompileWhens(sys, ctx, &compiler, m.get());
  CompileImpacts(sys, ctx, &compiler, m.get());

  compiler.Finish({&m->residual, &m->jacobian, &m->outputs, &m->start_values, &m->start_guesses,
                   &m->init_residual, &m->redundant_residual, &m->init_jacobian, &m->guard_values,
                   &m->discrete_starts, &m->discrete_update, &m->zero_crossings,
                   &m->zero_crossing_rates, &m->when_conditions, &m->when_values, &m->impact_values,
                   &compiler.parameter_program()});
  m->parameters = std::move(compiler.parameter_program());
  m->layout = compiler.layout();
  m->constants = compiler.constants();
  return m;
}

}  // namespace momenta

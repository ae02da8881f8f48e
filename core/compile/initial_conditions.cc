#include "core/compile/initial_conditions.h"

#include <algorithm>
#include <sstream>

#include "core/base/graph.h"

namespace momenta {

namespace {

/// The initialisation system's incidence: rows [F; G], columns [y; y' of the states].
class InitGraph {
 public:
  InitGraph(const EquationSystem& sys, const CompiledModel& m, const std::vector<int32_t>& y_of_var,
            const std::vector<int32_t>& state_of_y)
      : n_(static_cast<uint32_t>(m.unknowns.size())), num_cols_(n_ + static_cast<uint32_t>(m.state_y.size())) {
    const ExprPool& p = *sys.pool;
    std::vector<ExprId> leaves;  // scratch: one buffer for every row
    auto row_of = [&](ExprId e) {
      std::vector<uint32_t> row;
      CollectLeaves(p, e, kHasVar | kHasDer, &leaves);
      for (ExprId leaf : leaves) {
        const Node& nd = p.node(leaf);
        int32_t y = y_of_var[nd.a];
        if (y < 0) continue;
        if (nd.op == Op::kDer) {
          int32_t s = state_of_y[y];
          if (s >= 0) row.push_back(n_ + static_cast<uint32_t>(s));
        } else {
          row.push_back(static_cast<uint32_t>(y));
        }
      }
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      return row;
    };
    rows_.reserve(m.residual_exprs.size() + m.initial_exprs.size());
    for (ExprId r : m.residual_exprs) rows_.push_back(row_of(r));
    for (ExprId r : m.initial_exprs) rows_.push_back(row_of(r));
  }

  uint32_t n() const { return n_; }
  uint32_t num_rows() const { return static_cast<uint32_t>(rows_.size()); }
  uint32_t num_cols() const { return num_cols_; }
  const std::vector<uint32_t>& row(uint32_t r) const { return rows_[r]; }

  /// The graph of `rows` (indices into [F; G]).
  BipartiteGraph Graph(const std::vector<uint32_t>& rows) const {
    BipartiteGraph g;
    g.num_cols = num_cols_;
    for (uint32_t r : rows) g.AddRow(rows_[r]);
    return g;
  }

 private:
  uint32_t n_, num_cols_;
  std::vector<std::vector<uint32_t>> rows_;
};

std::string RowOrigin(const CompiledModel& m, uint32_t row) {
  const size_t n = m.unknowns.size();
  return row < n ? m.residual_origin(row) : m.initial_origin[row - n];
}

/// "a\nb\n…": what a redundant condition follows from, the other conditions first.
std::string Sources(const CompiledModel& m, std::vector<uint32_t> rows) {
  const size_t n = m.unknowns.size();
  std::stable_sort(rows.begin(), rows.end(), [&](uint32_t a, uint32_t b) { return (a >= n) > (b >= n); });
  std::ostringstream from;
  for (size_t k = 0; k < rows.size(); ++k) {
    if (k == 12) {
      from << "\n… and " << rows.size() - 12 << " more";
      break;
    }
    from << (k ? "\n" : "") << RowOrigin(m, rows[k]);
  }
  return from.str();
}

/// The start values that may complete the kept rows `ids` of [F; G], in the order they are
/// tried: the states in the under-determined part, those whose derivatives index reduction made
/// dummy (the positions and velocities of a constrained mechanism, what the user would have
/// fixed) first.
std::vector<uint32_t> StartValueOrder(const EquationSystem& sys, const CompiledModel& m,
                                      const InitGraph& ig, const std::vector<uint32_t>& ids,
                                      const std::vector<int32_t>& y_of_var) {
  const uint32_t n = ig.n();
  std::vector<uint32_t> kept = ids;
  std::sort(kept.begin(), kept.end());
  BipartiteGraph gk = ig.Graph(kept);
  Matching mk = MaximumMatching(gk);
  std::vector<uint32_t> under_rows, under_cols;
  UnderDeterminedPart(gk, mk, &under_rows, &under_cols);
  std::sort(under_cols.begin(), under_cols.end());
  std::vector<bool> has_dummy_derivative(n, false);
  for (const FlatVariable& fv : sys.flat->variables) {
    if (fv.derivative_order != 1 || !fv.derivative_of.valid()) continue;
    int32_t y = y_of_var[fv.derivative_of.value()];
    if (y >= 0) has_dummy_derivative[y] = true;
  }
  std::vector<uint32_t> order;
  for (uint32_t c : under_cols) {
    if (c < n && has_dummy_derivative[c]) order.push_back(c);
  }
  for (uint32_t c : under_cols) {
    if (c < n && m.is_state[c] && !has_dummy_derivative[c]) order.push_back(c);
  }
  return order;
}

/// Throws ModelError naming the unknowns that no row of the completed system determines.
void CheckAllDetermined(const EquationSystem& sys, const CompiledModel& m, const InitGraph& ig,
                        const IncrementalMatching& im) {
  const uint32_t n = ig.n();
  std::vector<uint32_t> free_cols;
  for (uint32_t c = 0; c < ig.num_cols(); ++c) {
    if (!im.ColumnMatched(c)) free_cols.push_back(c);
  }
  if (free_cols.empty()) return;
  std::ostringstream msg;
  msg << sys.flat->file << ": the initial conditions of " << sys.flat->model_name << " leave unknowns undetermined:";
  for (size_t k = 0; k < free_cols.size() && k < 12; ++k) {
    const uint32_t c = free_cols[k];
    uint32_t y = c < n ? c : m.state_y[c - n];
    msg << "\n    " << (c < n ? "" : "der of ") << sys.flat->DescribeVariable(m.unknowns[y]);
  }
  throw ModelError(msg.str());
}

}  // namespace

InitialConditionPlan PlanInitialConditions(const EquationSystem& sys, const CompiledModel& m,
                                           const std::vector<int32_t>& y_of_var,
                                           const std::vector<int32_t>& state_of_y) {
  InitialConditionPlan plan;
  InitGraph ig(sys, m, y_of_var, state_of_y);
  const uint32_t n = ig.n();

  // Too many: the conditions in the over-determined part are taken in declaration order while
  // each can still be matched; the others are redundant.
  std::vector<uint32_t> base(ig.num_rows()), over;
  for (uint32_t r = 0; r < ig.num_rows(); ++r) base[r] = r;
  BipartiteGraph g = ig.Graph(base);
  Matching match = MaximumMatching(g);
  if (match.size < g.num_rows()) {
    std::vector<uint32_t> over_rows, over_cols;
    OverDeterminedPart(g, match, &over_rows, &over_cols);
    std::vector<bool> in_over(ig.num_rows(), false);
    for (uint32_t r : over_rows) in_over[r] = r >= n;
    base.clear();
    for (uint32_t r = 0; r < ig.num_rows(); ++r) (in_over[r] ? over : base).push_back(r);
    g = ig.Graph(base);
    match = MaximumMatching(g);
  }
  MOMENTA_CHECK(match.size == g.num_rows());
  IncrementalMatching im(g, match);
  std::vector<uint32_t> ids = base;  // im's rows -> rows of [F; G]
  std::vector<uint32_t> redundant;
  for (uint32_t r : over) {
    if (im.TryAdd(ig.row(r))) {
      ids.push_back(r);
    } else {
      redundant.push_back(r);
    }
  }
  for (uint32_t r : redundant) {
    std::vector<uint32_t> from;
    for (uint32_t k : im.Reach(ig.row(r))) from.push_back(ids[k]);
    std::sort(from.begin(), from.end());
    plan.redundant.push_back(r - n);
    plan.redundant_from.push_back(Sources(m, from));
  }

  // Too few: the start values of states in the under-determined part, one at a time while each
  // still adds one.
  if (ids.size() < ig.num_cols()) {
    for (uint32_t c : StartValueOrder(sys, m, ig, ids, y_of_var)) {
      if (im.TryAdd({c})) plan.defaulted.push_back(c);
    }
  }
  CheckAllDetermined(sys, m, ig, im);
  return plan;
}

}  // namespace momenta

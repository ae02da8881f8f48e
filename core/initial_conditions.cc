#include "core/initial_conditions.h"

#include <algorithm>
#include <sstream>

#include "core/graph.h"

namespace momenta {

namespace {

/// The initialisation system's incidence: rows [F; G], columns [y; y' of the states].
class InitGraph {
 public:
  InitGraph(const EquationSystem& sys, const CompiledModel& m, const std::vector<int32_t>& y_of_var,
            const std::vector<int32_t>& state_of_y)
      : n_(static_cast<uint32_t>(m.unknowns.size())), num_cols_(n_ + static_cast<uint32_t>(m.state_y.size())) {
    const ExprPool& p = *sys.pool;
    auto row_of = [&](ExprId e) {
      std::vector<uint32_t> row;
      for (ExprId leaf : CollectLeaves(p, e, kHasVar | kHasDer)) {
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
    for (ExprId r : m.residual_exprs) rows_.push_back(row_of(r));
    for (ExprId r : m.initial_exprs) rows_.push_back(row_of(r));
  }

  uint32_t n() const { return n_; }
  uint32_t num_rows() const { return static_cast<uint32_t>(rows_.size()); }

  /// The graph of `rows` (indices into [F; G]) followed by one-column rows `extra`.
  BipartiteGraph Graph(const std::vector<uint32_t>& rows, const std::vector<uint32_t>& extra = {}) const {
    BipartiteGraph g;
    g.num_cols = num_cols_;
    for (uint32_t r : rows) g.AddRow(rows_[r]);
    for (uint32_t c : extra) g.AddRow({c});
    return g;
  }

 private:
  uint32_t n_, num_cols_;
  std::vector<std::vector<uint32_t>> rows_;
};

std::string RowOrigin(const CompiledModel& m, uint32_t row) {
  const size_t n = m.unknowns.size();
  return row < n ? m.residual_origin[row] : m.initial_origin[row - n];
}

/// Splits the over-determined initial conditions into kept and redundant ones.
void FindRedundant(const InitGraph& ig, const CompiledModel& m, std::vector<uint32_t>* kept, InitialConditionPlan* plan) {
  const uint32_t n = ig.n();
  std::vector<uint32_t> all(ig.num_rows());
  for (uint32_t r = 0; r < ig.num_rows(); ++r) all[r] = r;
  BipartiteGraph g = ig.Graph(all);
  Matching match = MaximumMatching(g);
  *kept = all;
  if (match.size == g.num_rows()) return;
  std::vector<uint32_t> over_rows, over_cols;
  OverDeterminedPart(g, match, &over_rows, &over_cols);
  // Conditions outside the over-determined part are matched regardless; those inside are taken
  // in declaration order while each still adds to the matching.
  std::vector<bool> in_over(ig.num_rows(), false);
  for (uint32_t r : over_rows) in_over[r] = r >= n;
  std::vector<uint32_t> trial_rows;
  for (uint32_t r = 0; r < ig.num_rows(); ++r) {
    if (!in_over[r]) trial_rows.push_back(r);
  }
  std::vector<uint32_t> redundant;
  for (uint32_t r = n; r < ig.num_rows(); ++r) {
    if (!in_over[r]) continue;
    trial_rows.push_back(r);
    BipartiteGraph trial = ig.Graph(trial_rows);
    if (MaximumMatching(trial).size < trial.num_rows()) {
      trial_rows.pop_back();
      redundant.push_back(r);
    }
  }
  std::sort(trial_rows.begin(), trial_rows.end());
  *kept = trial_rows;
  // What each redundant condition follows from: the over-determined part it makes with the rest.
  for (uint32_t r : redundant) {
    std::vector<uint32_t> with = trial_rows;
    with.push_back(r);
    BipartiteGraph tg = ig.Graph(with);
    Matching tm = MaximumMatching(tg);
    std::vector<uint32_t> part_rows, part_cols;
    OverDeterminedPart(tg, tm, &part_rows, &part_cols);
    std::vector<uint32_t> sources;
    for (uint32_t local : part_rows) {
      if (with[local] != r) sources.push_back(with[local]);
    }
    // The other conditions first, then the model's equations.
    std::stable_sort(sources.begin(), sources.end(), [&](uint32_t a, uint32_t b) { return (a >= n) > (b >= n); });
    std::ostringstream from;
    size_t shown = 0;
    for (uint32_t s : sources) {
      if (shown++ == 12) {
        from << "\n… and " << sources.size() - 12 << " more";
        break;
      }
      from << (shown > 1 ? "\n" : "") << RowOrigin(m, s);
    }
    plan->redundant.push_back(r - n);
    plan->redundant_from.push_back(from.str());
  }
}

}  // namespace

InitialConditionPlan PlanInitialConditions(const EquationSystem& sys, const CompiledModel& m,
                                           const std::vector<int32_t>& y_of_var,
                                           const std::vector<int32_t>& state_of_y) {
  InitialConditionPlan plan;
  InitGraph ig(sys, m, y_of_var, state_of_y);
  const uint32_t n = ig.n();
  std::vector<uint32_t> kept;
  FindRedundant(ig, m, &kept, &plan);

  // Columns left free: fix the start values of the states their alternating paths reach.
  BipartiteGraph g = ig.Graph(kept);
  Matching match = MaximumMatching(g);
  MOMENTA_CHECK(match.size == g.num_rows());
  std::vector<uint32_t> under_rows, under_cols;
  UnderDeterminedPart(g, match, &under_rows, &under_cols);
  std::vector<uint32_t> defaulted;
  for (uint32_t c : under_cols) {
    if (c < n && m.is_state[c]) defaulted.push_back(c);
  }
  // Variables whose derivatives index reduction made dummy (the positions and velocities of a
  // constrained mechanism) are what the user would have fixed: when there are such, or when the
  // free states are more than the degrees of freedom, take the start values one at a time,
  // those first, while each still adds one.
  std::vector<bool> has_dummy_derivative(n, false);
  bool any_dummy = false;
  for (const FlatVariable& fv : sys.flat->variables) {
    if (fv.derivative_order != 1 || !fv.derivative_of.valid()) continue;
    int32_t y = y_of_var[fv.derivative_of.value()];
    if (y >= 0) has_dummy_derivative[y] = any_dummy = true;
  }
  Matching m2 = MaximumMatching(ig.Graph(kept, defaulted));
  if (!defaulted.empty() && (any_dummy || m2.size < kept.size() + defaulted.size())) {
    std::vector<uint32_t> order;
    for (uint32_t c : under_cols) {
      if (c < n && has_dummy_derivative[c]) order.push_back(c);
    }
    order.insert(order.end(), defaulted.begin(), defaulted.end());
    std::vector<uint32_t> taken;
    for (uint32_t c : order) {
      if (std::find(taken.begin(), taken.end(), c) != taken.end()) continue;
      taken.push_back(c);
      if (MaximumMatching(ig.Graph(kept, taken)).size < kept.size() + taken.size()) taken.pop_back();
    }
    defaulted.swap(taken);
    m2 = MaximumMatching(ig.Graph(kept, defaulted));
  }
  if (m2.size < g.num_cols) {
    std::ostringstream msg;
    msg << sys.flat->file << ": the initial conditions of " << sys.flat->model_name << " leave unknowns undetermined:";
    size_t shown = 0;
    for (uint32_t c = 0; c < g.num_cols; ++c) {
      if (m2.col_to_row[c] >= 0) continue;
      if (shown++ == 12) break;
      uint32_t y = c < n ? c : m.state_y[c - n];
      msg << "\n    " << (c < n ? "" : "der of ") << sys.flat->DescribeVariable(m.unknowns[y]);
    }
    throw ModelError(msg.str());
  }
  plan.defaulted = defaulted;
  return plan;
}

}  // namespace momenta

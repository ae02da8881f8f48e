#include "core/passes/pantelides.h"

#include <algorithm>
#include <span>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "core/base/graph.h"
#include "core/base/limits.h"

namespace momenta {

namespace {

/// The bipartite graph of equations and derivatives (v, k) that Pantelides' algorithm grows.
class DerivativeGraph {
 public:
  explicit DerivativeGraph(EquationSystem* sys) : sys_(*sys), p_(*sys->pool) {}

  /// Column of der^k(v), created (with the lower orders it implies) on first use.
  uint32_t Column(uint32_t v, uint32_t k) {
    if (const int32_t known = Find(v, k); known >= 0) return static_cast<uint32_t>(known);
    int32_t lower = k > 0 ? static_cast<int32_t>(Column(v, k - 1)) : -1;
    uint32_t c = static_cast<uint32_t>(var_.size());
    var_.push_back(v);
    order_.push_back(k);
    derivative_.push_back(-1);
    assign_.push_back(-1);
    colour_col_.push_back(0);
    if (lower >= 0) derivative_[lower] = static_cast<int32_t>(c);
    if (k <= 1) {
      std::vector<int32_t>& by_var = k == 0 ? value_column_ : derivative_column_;
      if (by_var.size() <= v) by_var.resize(sys_.role.size() > v ? sys_.role.size() : v + 1, -1);
      by_var[v] = static_cast<int32_t>(c);
    } else {
      higher_column_.emplace(Key(v, k), c);
    }
    return c;
  }

  /// Adds the columns of equation `e` (sys.equations index) as its row. Rows come in the order
  /// of the equations (those of the system, then each differentiated one as it is added), so
  /// they are stored one after the other in one array.
  void AddRow(uint32_t e) {
    if (e != num_rows()) throw std::logic_error("DerivativeGraph::AddRow: rows must come in order");
    CollectLeaves(p_, sys_.equations[e].residual, kHasVar | kHasDer, &leaves_);
    for (ExprId leaf : leaves_) {
      const Node& n = p_.node(leaf);
      if (!IsContinuousUnknown(n.a)) continue;
      row_cols_.push_back(Column(n.a, n.op == Op::kDer ? n.b + 1 : 0));
    }
    row_start_.push_back(static_cast<uint32_t>(row_cols_.size()));
    colour_eq_.resize(num_rows(), 0);
  }
  uint32_t num_rows() const { return static_cast<uint32_t>(row_start_.size() - 1); }

  bool IsContinuousUnknown(uint32_t v) const {
    return sys_.role[v] == VarRole::kUnknown && !sys_.flat->variables[v].discrete;
  }
  bool Active(uint32_t c) const { return derivative_[c] < 0; }

  /// Seeks an augmenting path from equation `root` over the highest derivatives (explicit stack,
  /// no recursion); colours what it visits. On success the matching is extended.
  bool Augment(uint32_t root) {
    ++colour_;
    std::vector<Frame>& stack = stack_;
    stack.assign(1, {root, 0});
    std::vector<uint32_t>& path = path_;  // column taken from each frame to the next
    path.clear();
    colour_eq_[root] = colour_;
    visited_eqs_.assign(1, root);
    visited_cols_.clear();
    while (!stack.empty()) {
      const size_t top = stack.size() - 1;
      const uint32_t eq = stack[top].eq;
      const std::span<const uint32_t> cols = row(eq);
      // A free highest derivative ends the path: flip the matching along it.
      if (stack[top].pos == 0) {
        for (uint32_t c : cols) {
          if (!Active(c) || assign_[c] >= 0) continue;
          assign_[c] = static_cast<int32_t>(eq);
          for (size_t k = 0; k < path.size(); ++k) assign_[path[k]] = static_cast<int32_t>(stack[k].eq);
          return true;
        }
      }
      bool descended = false;
      while (stack[top].pos < cols.size()) {
        uint32_t c = cols[stack[top].pos++];
        if (!Active(c) || colour_col_[c] == colour_) continue;
        colour_col_[c] = colour_;
        visited_cols_.push_back(c);
        uint32_t next = static_cast<uint32_t>(assign_[c]);
        if (colour_eq_[next] == colour_) continue;
        colour_eq_[next] = colour_;
        visited_eqs_.push_back(next);
        path.push_back(c);
        stack.push_back({next, 0});
        descended = true;
        break;
      }
      if (!descended) {
        stack.pop_back();
        if (!path.empty()) path.pop_back();
      }
    }
    return false;
  }

  const std::vector<uint32_t>& visited_eqs() const { return visited_eqs_; }
  const std::vector<uint32_t>& visited_cols() const { return visited_cols_; }
  std::span<const uint32_t> row(uint32_t e) const {
    return {row_cols_.data() + row_start_[e], row_start_[e + 1] - row_start_[e]};
  }
  size_t num_columns() const { return var_.size(); }
  uint32_t var(uint32_t c) const { return var_[c]; }
  uint32_t order(uint32_t c) const { return order_[c]; }
  int32_t derivative(uint32_t c) const { return derivative_[c]; }
  int32_t assigned(uint32_t c) const { return assign_[c]; }
  void Assign(uint32_t c, int32_t e) { assign_[c] = e; }

 private:
  struct Frame {
    uint32_t eq, pos;
  };
  static uint64_t Key(uint32_t v, uint32_t k) { return (static_cast<uint64_t>(v) << 32) | k; }
  /// The column of der^k(v), or -1.
  int32_t Find(uint32_t v, uint32_t k) const {
    if (k <= 1) {
      const std::vector<int32_t>& by_var = k == 0 ? value_column_ : derivative_column_;
      return v < by_var.size() ? by_var[v] : -1;
    }
    auto it = higher_column_.find(Key(v, k));
    return it != higher_column_.end() ? static_cast<int32_t>(it->second) : -1;
  }

  EquationSystem& sys_;
  const ExprPool& p_;
  // Columns by variable for v and der(v) (nearly all of them: flat arrays), in a map above.
  std::vector<int32_t> value_column_, derivative_column_;
  std::unordered_map<uint64_t, uint32_t> higher_column_;
  std::vector<ExprId> leaves_;  // AddRow's scratch
  std::vector<Frame> stack_;    // Augment's scratch
  std::vector<uint32_t> path_;
  std::vector<uint32_t> var_, order_;
  std::vector<int32_t> derivative_, assign_;
  std::vector<uint32_t> row_start_{0}, row_cols_;  ///< row e: row_cols_[row_start_[e] .. row_start_[e+1])
  std::vector<uint32_t> colour_eq_, colour_col_;
  uint32_t colour_ = 0;
  std::vector<uint32_t> visited_eqs_, visited_cols_;
};

/// True when the equations can be matched to distinct variables at all (any derivative order):
/// the condition under which Pantelides' algorithm terminates.
bool StructurallyRegular(EquationSystem* sys, DerivativeGraph* g, uint32_t ne) {
  // Columns numbered by first occurrence.
  constexpr uint32_t kNone = ~0u;
  std::vector<uint32_t> col_of_var(sys->role.size(), kNone);
  uint32_t num_cols = 0;
  BipartiteGraph pencil;
  std::vector<uint32_t> row;
  for (uint32_t e = 0; e < ne; ++e) {
    row.clear();
    for (uint32_t c : g->row(e)) {
      uint32_t& col = col_of_var[g->var(c)];
      if (col == kNone) col = num_cols++;
      row.push_back(col);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    pencil.AddRow(row);
  }
  pencil.num_cols = num_cols;
  // Only the matching's size is asked, which every maximum matching has: the fast one (the
  // classic search spent its whole budget on the RC ladder's pencil, 13 % of its build).
  return pencil.num_cols == ne && FastMaximumMatching(pencil).size == ne;
}

}  // namespace

DifferentiatedSystem Pantelides(EquationSystem* sys) {
  ExprPool& p = *sys->pool;
  const uint32_t ne = static_cast<uint32_t>(sys->equations.size());
  DifferentiatedSystem out;
  DerivativeGraph g(sys);
  for (uint32_t e = 0; e < ne; ++e) g.AddRow(e);
  out.derivative.assign(ne, -1);
  out.antiderivative.assign(ne, -1);
  auto finish = [&]() {
    out.max_order.assign(sys->role.size(), 0);
    for (uint32_t c = 0; c < g.num_columns(); ++c) {
      out.max_order[g.var(c)] = std::max(out.max_order[g.var(c)], g.order(c));
    }
    return out;
  };
  if (!StructurallyRegular(sys, &g, ne)) return finish();

  // A maximum matching of the highest derivatives as it stands; most models end here.
  BipartiteGraph highest;
  std::vector<uint32_t> row;
  for (uint32_t e = 0; e < ne; ++e) {
    row.clear();
    for (uint32_t c : g.row(e)) {
      if (g.Active(c)) row.push_back(c);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    highest.AddRow(row);
  }
  highest.num_cols = static_cast<uint32_t>(g.num_columns());
  Matching m = MaximumMatching(highest);
  for (uint32_t c = 0; c < highest.num_cols; ++c) g.Assign(c, m.col_to_row[c]);
  if (m.size == ne) return finish();

  // Pantelides' loop for each equation left unmatched.
  std::vector<uint32_t> differentiations(ne, 0);
  for (uint32_t e0 = 0; e0 < ne; ++e0) {
    if (m.row_to_col[e0] >= 0) continue;
    uint32_t e = e0;
    while (!g.Augment(e)) {
      // Differentiate every visited unknown and equation once.
      const std::vector<uint32_t>& cols = g.visited_cols();
      const std::vector<uint32_t>& eqs = g.visited_eqs();
      std::vector<uint32_t> new_col(cols.size());
      for (size_t k = 0; k < cols.size(); ++k) new_col[k] = g.Column(g.var(cols[k]), g.order(cols[k]) + 1);
      for (uint32_t l : eqs) {
        const SystemEquation& eq = sys->equations[l];
        FlatEquation fe = sys->flat->equations[eq.origin];
        if (fe.differentiations + 1u > kMaxDifferentiations) {
          std::ostringstream msg;
          msg << sys->flat->file << ": " << sys->flat->model_name
              << ": index reduction does not terminate: this equation would be differentiated more than "
              << kMaxDifferentiations << " times (the model is structurally singular):\n    "
              << sys->flat->DescribeEquation(fe);
          throw ModelError(msg.str());
        }
        fe.residual = TimeDerivative(&p, eq.residual);
        fe.differentiated_from = static_cast<int32_t>(eq.origin);
        fe.differentiations += 1;
        uint32_t d = sys->AddEquation(std::move(fe));
        out.derivative.push_back(-1);
        out.antiderivative.push_back(static_cast<int32_t>(l));
        out.derivative[l] = static_cast<int32_t>(d);
        g.AddRow(d);
        out.structural_index = std::max<uint32_t>(out.structural_index, sys->flat->equations.back().differentiations + 1u);
        ++out.num_differentiated;
      }
      // The derivative of each visited unknown is matched to the derivative of its equation.
      for (size_t k = 0; k < cols.size(); ++k) {
        g.Assign(new_col[k], out.derivative[static_cast<uint32_t>(g.assigned(cols[k]))]);
      }
      e = static_cast<uint32_t>(out.derivative[e]);
    }
  }
  return finish();
}

}  // namespace momenta

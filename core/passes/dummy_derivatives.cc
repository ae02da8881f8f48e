#include "core/passes/dummy_derivatives.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "core/expr/expr_affine.h"
#include "core/expr/expr_eval.h"
#include "core/base/graph.h"

namespace momenta {

namespace {

/// Components with more equations than this are chosen structurally (by a matching that
/// follows the preferences) instead of by dense elimination.
constexpr size_t kDenseLimit = 200;
/// A pivot must be at least this fraction of its row's largest entry (`stateSelect: never`
/// candidates: kNeverPivotFraction, so they become dummy whenever the block allows it).
constexpr double kPivotFraction = 0.1;
constexpr double kNeverPivotFraction = 1e-8;

/// A state set switches when its current choice's pivot falls below this fraction of the best.
constexpr double kSwitchFraction = 0.5;
/// A state set with one state is made for a block of at most this many equations (its pivots are
/// symbolic determinants; a set with one dummy has one equation), and any set only with at most
/// kDynamicMaxChoices ways of choosing its states (one pivot expression each).
constexpr size_t kDynamicMaxRows = 3;
constexpr size_t kDynamicMaxChoices = 10;

struct Candidate {
  uint32_t var, order;
  bool operator==(const Candidate& o) const { return var == o.var && order == o.order; }
};

/// A block whose best choice of dummy derivatives depends on where the motion is: all its
/// candidates become dummy derivatives, and new states, equal to the lower derivatives of the
/// candidates currently selected, carry the block's degrees of freedom (one for a pendulum's
/// {x, y}; three for a free body's quaternion, "3 states selected from body.Q[]").
struct DynamicSet {
  std::vector<uint32_t> rows;    ///< indices into sys.equations
  std::vector<Candidate> cands;  ///< derivatives der^k(v), all made dummy
  /// The candidates (indices into cands) whose der^(k-1)(v) the set's states may be: those of the
  /// highest stateSelect priority in the block.
  std::vector<uint32_t> selectable;
  /// The ways of choosing the states: each a list of indices into cands, as many as the block
  /// has degrees of freedom, taken from `selectable` in order (lexicographically).
  std::vector<std::vector<uint32_t>> choices;
  uint32_t start_choice = 0;     ///< index into choices: the states at the start values
};

/// Every way of taking `k` of `items`, in lexicographic order of positions.
std::vector<std::vector<uint32_t>> Combinations(const std::vector<uint32_t>& items, size_t k) {
  std::vector<std::vector<uint32_t>> out;
  if (k == 0 || k > items.size()) return out;
  std::vector<size_t> pos(k);
  for (size_t i = 0; i < k; ++i) pos[i] = i;
  while (true) {
    std::vector<uint32_t> c;
    for (size_t i : pos) c.push_back(items[i]);
    out.push_back(std::move(c));
    size_t i = k;
    while (i > 0 && pos[i - 1] == items.size() - k + i - 1) --i;
    if (i == 0) return out;
    ++pos[i - 1];
    for (size_t j = i; j < k; ++j) pos[j] = pos[j - 1] + 1;
  }
}

uint64_t Key(uint32_t v, uint32_t k) { return (static_cast<uint64_t>(v) << 32) | k; }

std::string DerName(const std::string& name, uint32_t order) {
  std::string s;
  for (uint32_t k = 0; k < order; ++k) s += "der(";
  s += name;
  s.append(order, ')');
  return s;
}

/// One level of the selection: equations `rows` and the derivatives they may be solved for.
class LevelChoice {
 public:
  LevelChoice(EquationSystem* sys, const DifferentiatedSystem& differentiated, const std::vector<double>& params,
              const std::vector<double>& start)
      : sys_(*sys), p_(*sys->pool), params_(params), start_(start), appears_differentiated_(sys->role.size(), false) {
    // The variables whose derivative the model's own equations hold (not only their derivatives),
    // and those an equation of the model defines as a derivative, v = c*der(x) + offset (der(v)
    // is der(der(x)): a pendulum's w = der(phi)).
    AffineForm form;
    for (uint32_t e = 0; e < sys->equations.size(); ++e) {
      if (e < differentiated.antiderivative.size() && differentiated.antiderivative[e] >= 0) continue;
      const ExprId res = sys->equations[e].residual;
      if (!res.valid() || !(p_.mask(res) & kHasDer)) continue;
      for (ExprId leaf : CollectLeaves(p_, res, kHasDer)) MarkDifferentiated(p_.node(leaf).a);
      if (DecomposeAffine(&p_, res, 2, &form) && form.terms.size() == 2 &&
          (p_.op(form.terms[0].first) == Op::kDer) != (p_.op(form.terms[1].first) == Op::kDer)) {
        for (const auto& [leaf, c] : form.terms) MarkDifferentiated(p_.node(leaf).a);
      }
    }
    MergeAliasPriorities();
  }

  /// Chooses |rows| candidates; returns them. `choices` gets a line where there was a choice.
  std::vector<Candidate> Choose(const std::vector<uint32_t>& rows, const std::vector<Candidate>& cands,
                                std::vector<std::string>* choices, std::vector<DynamicSet>* sets) {
    rows_ = &rows;
    // Each row's candidate columns.
    std::unordered_map<uint64_t, uint32_t> col_of;
    for (uint32_t c = 0; c < cands.size(); ++c) col_of.emplace(Key(cands[c].var, cands[c].order), c);
    std::vector<std::vector<std::pair<uint32_t, ExprId>>> row_cols(rows.size());
    for (size_t r = 0; r < rows.size(); ++r) {
      ExprId res = sys_.equations[rows[r]].residual;
      for (ExprId leaf : CollectLeaves(p_, res, kHasDer)) {
        const Node& n = p_.node(leaf);
        auto it = col_of.find(Key(n.a, n.b + 1));
        if (it != col_of.end()) row_cols[r].push_back({it->second, leaf});
      }
    }
    // Connected components of rows and columns (union-find over rows, joined through columns).
    DisjointSets row_sets(rows.size());
    std::vector<int32_t> first_row_of_col(cands.size(), -1);
    for (uint32_t r = 0; r < rows.size(); ++r) {
      for (auto [c, leaf] : row_cols[r]) {
        if (first_row_of_col[c] < 0) {
          first_row_of_col[c] = static_cast<int32_t>(r);
        } else {
          row_sets.Join(r, static_cast<uint32_t>(first_row_of_col[c]));
        }
      }
    }
    std::unordered_map<uint32_t, std::vector<uint32_t>> components;
    for (uint32_t r = 0; r < rows.size(); ++r) components[row_sets.Find(r)].push_back(r);
    std::vector<uint32_t> roots;
    for (auto& [root, members] : components) roots.push_back(root);
    std::sort(roots.begin(), roots.end());

    std::vector<Candidate> selected;
    for (uint32_t root : roots) {
      const std::vector<uint32_t>& comp_rows = components[root];
      std::vector<uint32_t> comp_cols;
      for (uint32_t r : comp_rows) {
        for (auto [c, leaf] : row_cols[r]) comp_cols.push_back(c);
      }
      std::sort(comp_cols.begin(), comp_cols.end());
      comp_cols.erase(std::unique(comp_cols.begin(), comp_cols.end()), comp_cols.end());
      std::vector<uint32_t> chosen;
      if (comp_rows.size() <= kDenseLimit) chosen = ChooseByPivoting(comp_rows, comp_cols, row_cols, cands);
      if (chosen.size() < comp_rows.size()) chosen = ChooseByStructure(comp_rows, comp_cols, row_cols, cands);
      if (chosen.size() < comp_rows.size()) Fail(rows, comp_rows, comp_cols, cands);
      CheckAlways(rows, comp_rows, comp_cols, chosen, cands);
      if (IsDynamic(comp_rows, comp_cols, row_cols)) {
        // Every candidate becomes a dummy; the set's state follows the best pivot during the run,
        // among the candidates of the highest stateSelect priority. One such candidate alone is
        // the state throughout (the static choice made above).
        DynamicSet set;
        int top = Rank(cands[comp_cols[0]]);
        for (uint32_t c : comp_cols) top = std::max(top, Rank(cands[c]));
        std::vector<uint32_t> kept;  // the static choice's states, as indices into set.cands
        for (uint32_t c : comp_cols) {
          if (std::find(chosen.begin(), chosen.end(), c) == chosen.end()) kept.push_back(static_cast<uint32_t>(set.cands.size()));
          if (Rank(cands[c]) == top) set.selectable.push_back(static_cast<uint32_t>(set.cands.size()));
          set.cands.push_back(cands[c]);
        }
        if (set.selectable.size() > kept.size()) set.choices = Combinations(set.selectable, kept.size());
        const auto start = std::find(set.choices.begin(), set.choices.end(), kept);
        if (set.choices.size() <= kDynamicMaxChoices && start != set.choices.end()) {
          set.start_choice = static_cast<uint32_t>(start - set.choices.begin());
          for (uint32_t r : comp_rows) set.rows.push_back(rows[r]);
          for (const Candidate& c : set.cands) selected.push_back(c);
          choices->push_back(DescribeDynamic(set));
          if (Priority(set.cands[set.selectable[0]]) == kStateNever && set.cands[set.selectable[0]].order == 1) {
            warnings_.push_back("stateSelect: never on each of " + SelectableNames(set) +
                                ", but one of them must be a state (a state set selects it during the run)");
          }
          sets->push_back(std::move(set));
          continue;
        }
        choices->push_back(DescribeChoice(comp_cols, chosen, cands) + " (static: stateSelect)");
        for (uint32_t c : chosen) selected.push_back(cands[c]);
        continue;
      }
      if (comp_cols.size() > comp_rows.size()) choices->push_back(DescribeChoice(comp_cols, chosen, cands));
      for (uint32_t c : chosen) selected.push_back(cands[c]);
    }
    return selected;
  }

 private:
  /// The candidate's variable's stateSelect priority (its derivatives of every order share it).
  int Priority(const Candidate& c) const { return priority_[c.var]; }

  void MarkDifferentiated(uint32_t v) {
    if (v < appears_differentiated_.size()) appears_differentiated_[v] = true;
  }

  /// The priority of each variable as its alias set has it: a variable left with the default
  /// takes the stateSelect its aliases declare (the highest where they differ), as a body's r_0
  /// (avoid) gives it to its frame's r_0, the variable that stays.
  void MergeAliasPriorities() {
    const FlatSystem& flat = *sys_.flat;
    priority_.resize(sys_.role.size());
    for (uint32_t v = 0; v < priority_.size(); ++v) priority_[v] = flat.variables[v].state_priority;
    std::vector<bool> merged(priority_.size(), false);
    for (uint32_t v = 0; v < priority_.size(); ++v) {
      const int prio = flat.variables[v].state_priority;
      if (sys_.role[v] != VarRole::kAlias || prio == kStateDefault) continue;
      AffineForm form;
      if (!DecomposeAffine(&p_, sys_.eliminated->Apply(p_.Var(VarId(v))), 1, &form) || form.terms.size() != 1 ||
          p_.op(form.terms[0].first) != Op::kVar) {
        continue;
      }
      const uint32_t root = p_.node(form.terms[0].first).a;
      if (flat.variables[root].state_priority != kStateDefault) continue;
      priority_[root] = merged[root] ? std::max(priority_[root], prio) : prio;
      merged[root] = true;
    }
  }

  /// The order in which candidates stay states, finer than the priority as the MSL's StateSelect
  /// reads: `default` and `avoid` are states only if the variable appears differentiated in the
  /// model, so one that appears differentiated only through index reduction ranks with `avoid`
  /// below an `avoid` that does (a body's quaternions, whose der(Q) the body's equations hold,
  /// stay states where its frame's transformation matrix is made dummy, as Dymola chooses).
  int Rank(const Candidate& c) const {
    const int prio = Priority(c);
    if (prio >= kStatePrefer || appears_differentiated_[c.var]) return 2 * prio + 1;
    return 2 * std::min(prio, kStateDefault - 1);
  }

  /// Smaller is made dummy first: `never` before `avoid` before `default` before `prefer`
  /// before `always` (see Rank), higher derivatives first.
  std::tuple<int, int> Preference(const Candidate& c) const { return {Rank(c), -static_cast<int>(c.order)}; }

  /// Gaussian elimination with a pivot search that honours the preferences; returns the chosen
  /// columns, or fewer than the rows when the start values make the block singular.
  std::vector<uint32_t> ChooseByPivoting(const std::vector<uint32_t>& comp_rows, const std::vector<uint32_t>& comp_cols,
                                         const std::vector<std::vector<std::pair<uint32_t, ExprId>>>& row_cols,
                                         const std::vector<Candidate>& cands) {
    const size_t nr = comp_rows.size(), nc = comp_cols.size();
    std::unordered_map<uint32_t, size_t> local;
    for (size_t j = 0; j < nc; ++j) local.emplace(comp_cols[j], j);
    std::vector<double> a(nr * nc, 0.0);
    LeafValues lv;
    lv.params = params_.data();
    lv.vars = start_.data();
    for (size_t i = 0; i < nr; ++i) {
      ExprId res = sys_.equations[(*rows_)[comp_rows[i]]].residual;
      for (auto [c, leaf] : row_cols[comp_rows[i]]) {
        a[i * nc + local.at(c)] = Evaluate(p_, PartialDerivative(&p_, res, leaf), lv);
      }
    }
    std::vector<bool> row_done(nr, false), col_done(nc, false);
    std::vector<uint32_t> chosen;
    for (size_t step = 0; step < nr; ++step) {
      // Candidates to avoid (or never to choose) that one remaining row alone can still give are
      // taken there first within their priority, or that row's pivot could be spent on a column
      // other rows also have (a contact's der(v_n) = der(der(d)) must give der(v_n), not
      // der(der(d)), or v_n becomes a state).
      std::vector<uint32_t> col_rows(nc, 0);
      for (size_t i = 0; i < nr; ++i) {
        if (row_done[i]) continue;
        for (size_t j = 0; j < nc; ++j) col_rows[j] += !col_done[j] && a[i * nc + j] != 0;
      }
      int64_t bi = -1, bj = -1;
      std::tuple<int, int, int, double, double> best{0, 0, 0, 0.0, 0.0};
      for (size_t i = 0; i < nr; ++i) {
        if (row_done[i]) continue;
        // The row's largest entry among the candidates that may be made dummy (`always` ones
        // only when nothing else can).
        double row_max = 0, row_max_all = 0;
        for (size_t j = 0; j < nc; ++j) {
          if (col_done[j]) continue;
          const double v = std::fabs(a[i * nc + j]);
          row_max_all = std::max(row_max_all, v);
          if (Priority(cands[comp_cols[j]]) != kStateAlways) row_max = std::max(row_max, v);
        }
        const bool forced = !(row_max > 0);
        if (forced) row_max = row_max_all;
        if (!(row_max > 0) || !std::isfinite(row_max)) continue;
        for (size_t j = 0; j < nc; ++j) {
          const double v = std::fabs(a[i * nc + j]);
          const int prio = Priority(cands[comp_cols[j]]);
          const double fraction = prio == kStateNever ? kNeverPivotFraction : kPivotFraction;
          if (col_done[j] || v < fraction * row_max || (prio == kStateAlways && !forced) || !(v > 0)) continue;
          std::tuple<int, int, int, double, double> key{Rank(cands[comp_cols[j]]), prio < kStateDefault && col_rows[j] == 1 ? 0 : 1,
                                                        -static_cast<int>(cands[comp_cols[j]].order), -v / row_max, -v};
          if (bi < 0 || key < best) {
            best = key;
            bi = static_cast<int64_t>(i);
            bj = static_cast<int64_t>(j);
          }
        }
      }
      if (bi < 0) return chosen;  // singular at the start values
      row_done[bi] = col_done[bj] = true;
      chosen.push_back(comp_cols[bj]);
      const double pivot = a[bi * nc + bj];
      for (size_t i = 0; i < nr; ++i) {
        if (row_done[i] || a[i * nc + bj] == 0) continue;
        const double f = a[i * nc + bj] / pivot;
        for (size_t j = 0; j < nc; ++j) a[i * nc + j] -= f * a[bi * nc + j];
      }
    }
    return chosen;
  }

  /// A maximum matching in which each row tries its candidates in order of preference.
  std::vector<uint32_t> ChooseByStructure(const std::vector<uint32_t>& comp_rows, const std::vector<uint32_t>& comp_cols,
                                          const std::vector<std::vector<std::pair<uint32_t, ExprId>>>& row_cols,
                                          const std::vector<Candidate>& cands) {
    std::unordered_map<uint32_t, uint32_t> local;
    for (uint32_t j = 0; j < comp_cols.size(); ++j) local.emplace(comp_cols[j], j);
    BipartiteGraph g;
    g.num_cols = static_cast<uint32_t>(comp_cols.size());
    for (uint32_t r : comp_rows) {
      std::vector<uint32_t> cols;
      for (auto [c, leaf] : row_cols[r]) cols.push_back(c);
      // Equal preferences in candidate order (by variable), not in the order of the equation's leaves.
      std::sort(cols.begin(), cols.end(), [&](uint32_t x, uint32_t y) {
        return std::make_tuple(Preference(cands[x]), x) < std::make_tuple(Preference(cands[y]), y);
      });
      std::vector<uint32_t> row;
      for (uint32_t c : cols) row.push_back(local.at(c));
      g.AddRow(row);
    }
    Matching m = MaximumMatching(g);
    std::vector<uint32_t> chosen;
    for (int32_t j : m.row_to_col) {
      if (j >= 0) chosen.push_back(comp_cols[j]);
    }
    // A maximum matching may trade a row's preferred column for another along an augmenting
    // path, leaving a `default` position as the state where a `prefer` joint angle could be (a
    // 3-D chain of seven links and more, whose block passes the dense limit). The matching that
    // takes the columns in order of preference keeps the best states; it is used only when it
    // keeps better ones, so a choice that already honours the priorities stays as it was.
    std::vector<uint32_t> greedy = ChooseByPreferenceOrder(comp_rows, comp_cols, row_cols, cands);
    if (greedy.size() == chosen.size() &&
        StatePriorities(comp_cols, chosen, cands) < StatePriorities(comp_cols, greedy, cands)) {
      return greedy;
    }
    return chosen;
  }

  /// The columns made dummy by matching them one at a time in order of preference (smallest
  /// first), each kept when an augmenting path lets it in: the greedy basis of the transversal
  /// matroid, so the columns left as states have the highest priorities a matching allows.
  std::vector<uint32_t> ChooseByPreferenceOrder(const std::vector<uint32_t>& comp_rows,
                                                const std::vector<uint32_t>& comp_cols,
                                                const std::vector<std::vector<std::pair<uint32_t, ExprId>>>& row_cols,
                                                const std::vector<Candidate>& cands) {
    // The graph transposed: each candidate column lists the block's rows it occurs in.
    std::unordered_map<uint32_t, uint32_t> local;
    for (uint32_t j = 0; j < comp_cols.size(); ++j) local.emplace(comp_cols[j], j);
    std::vector<std::vector<uint32_t>> rows_of(comp_cols.size());
    for (uint32_t i = 0; i < comp_rows.size(); ++i) {
      for (auto [c, leaf] : row_cols[comp_rows[i]]) rows_of[local.at(c)].push_back(i);
    }
    std::vector<uint32_t> order(comp_cols.size());
    for (uint32_t j = 0; j < order.size(); ++j) order[j] = j;
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
      return std::make_tuple(Preference(cands[comp_cols[x]]), comp_cols[x]) <
             std::make_tuple(Preference(cands[comp_cols[y]]), comp_cols[y]);
    });
    BipartiteGraph none;
    none.num_cols = static_cast<uint32_t>(comp_rows.size());
    Matching empty;
    empty.col_to_row.assign(comp_rows.size(), -1);
    IncrementalMatching matching(none, empty);
    std::vector<uint32_t> chosen;
    for (uint32_t j : order) {
      if (chosen.size() == comp_rows.size()) break;  // every row has its column: the rest are states
      std::sort(rows_of[j].begin(), rows_of[j].end());
      rows_of[j].erase(std::unique(rows_of[j].begin(), rows_of[j].end()), rows_of[j].end());
      if (matching.TryAdd(rows_of[j])) chosen.push_back(comp_cols[j]);
    }
    return chosen;
  }

  /// The priorities of the columns not made dummy (the states), highest first.
  std::vector<int> StatePriorities(const std::vector<uint32_t>& comp_cols, const std::vector<uint32_t>& chosen,
                                   const std::vector<Candidate>& cands) const {
    std::unordered_set<uint32_t> dummy(chosen.begin(), chosen.end());
    std::vector<int> priorities;
    for (uint32_t c : comp_cols) {
      if (!dummy.count(c)) priorities.push_back(Rank(cands[c]));
    }
    std::sort(priorities.rbegin(), priorities.rend());
    return priorities;
  }

  std::string Name(const Candidate& c) const { return DerName(sys_.flat->VariableName(VarId(c.var)), c.order); }

  /// One state among the candidates of a small block whose pivots depend on the motion.
  bool IsDynamic(const std::vector<uint32_t>& comp_rows, const std::vector<uint32_t>& comp_cols,
                 const std::vector<std::vector<std::pair<uint32_t, ExprId>>>& row_cols) const {
    // One state among rows + 1 candidates (a pendulum's {x, y}), or all but one of a single
    // equation's candidates (a free body's Q*der(Q) = 0: three of the four elements of Q).
    const bool one_state = comp_cols.size() == comp_rows.size() + 1 && comp_rows.size() <= kDynamicMaxRows;
    const bool one_dummy = comp_rows.size() == 1 && comp_cols.size() > 2;
    if (!one_state && !one_dummy) return false;
    for (uint32_t r : comp_rows) {
      ExprId res = sys_.equations[(*rows_)[r]].residual;
      for (auto [c, leaf] : row_cols[r]) {
        if (!p_.IsParamOnly(PartialDerivative(&p_, res, leaf))) return true;
      }
    }
    return false;
  }

  /// "{x, y}": the variables a state set may select.
  std::string SelectableNames(const DynamicSet& set) const {
    std::string s = "{";
    for (size_t k = 0; k < set.selectable.size(); ++k) {
      const Candidate& c = set.cands[set.selectable[k]];
      s += (k ? ", " : "") + DerName(sys_.flat->VariableName(VarId(c.var)), c.order - 1);
    }
    return s + "}";
  }

  std::string DescribeDynamic(const DynamicSet& set) const {
    std::ostringstream s;
    const std::vector<uint32_t>& start = set.choices[set.start_choice];
    if (start.size() == 1) {
      s << "dynamic: one of " << SelectableNames(set) << " is a state";
    } else {
      s << "dynamic: " << start.size() << " of " << SelectableNames(set) << " are states";
    }
    s << ", chosen during the run by the largest pivot (at the start: ";
    for (size_t i = 0; i < start.size(); ++i) {
      const Candidate& c = set.cands[start[i]];
      s << (i ? ", " : "") << DerName(sys_.flat->VariableName(VarId(c.var)), c.order - 1);
    }
    s << ")";
    return s.str();
  }

  std::string DescribeChoice(const std::vector<uint32_t>& comp_cols, const std::vector<uint32_t>& chosen,
                             const std::vector<Candidate>& cands) const {
    std::ostringstream s;
    s << "of {";
    for (size_t k = 0; k < comp_cols.size(); ++k) s << (k ? ", " : "") << Name(cands[comp_cols[k]]);
    s << "} " << chosen.size() << " made dummy: ";
    for (size_t k = 0; k < chosen.size(); ++k) s << (k ? ", " : "") << Name(cands[chosen[k]]);
    return s.str();
  }

  /// A variable with `stateSelect: always` whose first derivative was made dummy cannot be a
  /// state: the block's equations determine it from the other candidates.
  void CheckAlways(const std::vector<uint32_t>& rows, const std::vector<uint32_t>& comp_rows,
                   const std::vector<uint32_t>& comp_cols, const std::vector<uint32_t>& chosen,
                   const std::vector<Candidate>& cands) const {
    for (uint32_t c : chosen) {
      if (Priority(cands[c]) != kStateAlways || cands[c].order != 1) continue;
      const FlatVariable& v = sys_.flat->variables[cands[c].var];
      const std::string name = sys_.flat->VariableName(VarId(cands[c].var));
      std::ostringstream msg;
      msg << "stateSelect: always on " << name << " cannot be honoured: the other states determine "
          << name << " through";
      for (uint32_t r : comp_rows) msg << "\n    " << sys_.Describe(sys_.equations[rows[r]]);
      msg << "\n  (index reduction must make " << DerName(name, 1) << " a dummy derivative). Use stateSelect: prefer on "
          << name << ", or always on fewer variables.";
      throw ModelError(v.loc, msg.str());
    }
  }

  [[noreturn]] void Fail(const std::vector<uint32_t>& rows, const std::vector<uint32_t>& comp_rows,
                         const std::vector<uint32_t>& comp_cols, const std::vector<Candidate>& cands) const {
    std::ostringstream msg;
    msg << sys_.flat->file << ": " << sys_.flat->model_name
        << ": index reduction failed: these differentiated equations cannot be solved for distinct "
           "derivatives (their constraints are redundant or contradict each other):";
    for (uint32_t r : comp_rows) msg << "\n    " << sys_.Describe(sys_.equations[rows[r]]);
    msg << "\n  candidate derivatives:";
    for (uint32_t c : comp_cols) msg << " " << Name(cands[c]);
    throw ModelError(msg.str());
  }

 public:
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::vector<std::string> warnings_;  ///< `stateSelect: never` that could not be honoured
  EquationSystem& sys_;
  ExprPool& p_;
  const std::vector<double>& params_;
  const std::vector<double>& start_;
  const std::vector<uint32_t>* rows_ = nullptr;  ///< the level's equations (indices into sys_.equations)
  std::vector<bool> appears_differentiated_;     ///< by variable: der of it is in an equation of the model
  std::vector<int> priority_;                    ///< by variable: stateSelect, merged over its alias set
};

/// Adds an equation index reduction made, described as belonging to `instance`.
void AddMadeEquation(EquationSystem* sys, ExprId residual, InstanceId instance, const std::string& text,
                     const SourceLoc& loc) {
  FlatEquation fe;
  fe.residual = residual;
  fe.origin = EquationOrigin::kModel;
  fe.instance = instance;
  fe.text = sys->MutableFlat().Own(text);
  fe.loc = loc;
  sys->AddEquation(std::move(fe));
}

/// if sel == 1 then values[0] else if sel == 2 then values[1] … else values[n-1].
ExprId Choice(ExprPool* pool, ExprId sel, const std::vector<ExprId>& values) {
  ExprPool& p = *pool;
  ExprId e = values.back();
  for (size_t k = values.size() - 1; k-- > 0;) {
    e = p.If(p.NoEvent(p.Binary(Op::kEq, sel, p.Const(static_cast<double>(k + 1)))), values[k], e);
  }
  return e;
}

/// Determinant of a small square matrix of expressions, by cofactors.
ExprId Determinant(ExprPool* pool, const std::vector<std::vector<ExprId>>& a) {
  ExprPool& p = *pool;
  const size_t n = a.size();
  if (n == 1) return a[0][0];
  ExprId det = p.Zero();
  for (size_t j = 0; j < n; ++j) {
    std::vector<std::vector<ExprId>> minor;
    for (size_t i = 1; i < n; ++i) {
      std::vector<ExprId> row;
      for (size_t c = 0; c < n; ++c) {
        if (c != j) row.push_back(a[i][c]);
      }
      minor.push_back(row);
    }
    ExprId term = p.Mul(a[0][j], Determinant(pool, minor));
    det = (j % 2 == 0) ? p.Add(det, term) : p.Sub(det, term);
  }
  return det;
}

/// The pivot of each of the set's choices: |det| of the block's Jacobian in the candidates'
/// derivatives without the choice's columns (those stay states; the rest are solved for).
std::vector<ExprId> ChoicePivots(EquationSystem* sys, const DynamicSet& set, const std::vector<ExprId>& der) {
  ExprPool& p = *sys->pool;
  std::vector<std::vector<ExprId>> jac;
  for (uint32_t r : set.rows) {
    std::vector<ExprId> row;
    for (ExprId d : der) row.push_back(PartialDerivative(&p, sys->equations[r].residual, d));
    jac.push_back(row);
  }
  std::vector<ExprId> pivot;
  for (const std::vector<uint32_t>& choice : set.choices) {
    std::vector<std::vector<ExprId>> rest;
    for (const auto& row : jac) {
      std::vector<ExprId> r;
      for (uint32_t c = 0; c < row.size(); ++c) {
        if (std::find(choice.begin(), choice.end(), c) == choice.end()) r.push_back(row[c]);
      }
      rest.push_back(r);
    }
    pivot.push_back(p.Unary(Op::kAbs, Determinant(&p, rest)));
  }
  return pivot;
}

/// Makes a state set: the states `stateSetK.x` (`x[1]`, `x[2]`, ... where the block has several
/// degrees of freedom) = the lower derivatives of the selected candidates, their derivatives =
/// the selected candidates, and a when-clause that switches the selection (and reinitialises the
/// states) when the current choice's pivot |det| falls below kSwitchFraction of the best one's.
/// Expressions are in the candidates' derivative leaves; the dummy-derivative substitution that
/// follows rewrites them.
void AddStateSet(EquationSystem* sys, const DynamicSet& set, size_t number) {
  ExprPool& p = *sys->pool;
  const std::string prefix = "stateSet" + std::to_string(number);
  const std::vector<uint32_t>& start = set.choices[set.start_choice];
  const FlatVariable first = sys->flat->variables[set.cands[set.selectable[0]].var];  // a copy: AddVariable grows the vector
  const InstanceId instance = first.instance;
  const SourceLoc loc = first.loc;
  const size_t n = set.choices.size(), k = start.size();
  // The candidates, the selectable ones' lower derivatives and the pivot of each choice.
  std::vector<ExprId> der, lower(set.cands.size());
  for (const Candidate& c : set.cands) der.push_back(p.Der(VarId(c.var), c.order));
  for (uint32_t s : set.selectable) {
    const Candidate& c = set.cands[s];
    lower[s] = c.order == 1 ? p.Var(VarId(c.var)) : p.Der(VarId(c.var), c.order - 1);
  }
  const std::vector<ExprId> pivot = ChoicePivots(sys, set, der);
  // The selection (Integer, 1-based) and the states.
  FlatVariable sel_var;
  sel_var.name = sys->MutableFlat().Own(prefix + ".select");
  sel_var.type = ValueType::kInteger;
  sel_var.discrete = true;
  sel_var.start = p.Const(static_cast<double>(set.start_choice + 1));
  sel_var.instance = instance;
  sel_var.loc = loc;
  VarId sel = sys->AddVariable(std::move(sel_var), p.Const(static_cast<double>(set.start_choice + 1)));
  std::string candidates;
  for (size_t j = 0; j < set.selectable.size(); ++j) {
    const Candidate& c = set.cands[set.selectable[j]];
    candidates += (j ? ", " : "") + DerName(sys->flat->VariableName(VarId(c.var)), c.order - 1);
  }
  auto equation = [&](ExprId residual, const std::string& text) { AddMadeEquation(sys, residual, instance, text, loc); };
  const ExprId sel_now = p.Var(sel);
  std::vector<VarId> states;
  std::vector<std::vector<ExprId>> lowers(k);  // by state: its lower derivative in each choice
  for (size_t i = 0; i < k; ++i) {
    const std::string x = k == 1 ? prefix + ".x" : prefix + ".x[" + std::to_string(i + 1) + "]";
    const std::string which = k == 1 ? "the selected one" : "selected " + std::to_string(i + 1);
    FlatVariable state_var;
    state_var.name = sys->MutableFlat().Own(x);
    state_var.nominal = first.nominal;
    state_var.instance = instance;
    state_var.loc = loc;
    const VarId state = sys->AddVariable(std::move(state_var), sys->guess[set.cands[start[i]].var]);
    states.push_back(state);
    std::vector<ExprId> ders;
    for (const std::vector<uint32_t>& choice : set.choices) {
      lowers[i].push_back(lower[choice[i]]);
      ders.push_back(der[choice[i]]);
    }
    equation(p.Sub(p.Var(state), Choice(&p, sel_now, lowers[i])), x + " = " + which + " of " + candidates);
    equation(p.Sub(p.Der(state), Choice(&p, sel_now, ders)), "der(" + x + ") = der(" + which + " of " + candidates + ")");
  }
  // Switch to the best pivot when the current one is much worse.
  ExprId best = pivot[0];
  for (size_t j = 1; j < n; ++j) best = p.Binary(Op::kMax, best, pivot[j]);
  ExprId argmax = p.Const(static_cast<double>(n));
  for (size_t j = n - 1; j-- > 0;) {
    ExprId others = p.Zero();
    for (size_t m = j + 1; m < n; ++m) others = p.Binary(Op::kMax, others, pivot[m]);
    argmax = p.If(p.NoEvent(p.Binary(Op::kGe, pivot[j], others)), p.Const(static_cast<double>(j + 1)), argmax);
  }
  FlatWhen w;
  w.condition = p.Binary(Op::kLt, Choice(&p, p.Pre(sel), pivot), p.Mul(p.Const(kSwitchFraction), best));
  w.assigns.push_back({sel, argmax});
  for (size_t i = 0; i < k; ++i) w.reinits.push_back({states[i], Choice(&p, argmax, lowers[i])});
  w.instance = instance;
  FlatSystem& flat = sys->MutableFlat();
  w.text = flat.Own("the pivot of " + prefix + "'s choice among " + candidates + " falls below half the best");
  w.loc = loc;
  flat.whens.push_back(w);
  sys->whens.push_back({w.condition, w.assigns, w.reinits, static_cast<uint32_t>(flat.whens.size() - 1)});
}

/// Chooses the dummy derivatives level by level, from the differentiated equations at the top
/// of their chains down, with the highest derivatives of every variable as the first
/// candidates; returns by variable the lowest derivative order made dummy (UINT32_MAX: none),
/// with the dynamic state sets in `*sets` and the choices and warnings in `*out`.
std::vector<uint32_t> ChooseLevels(EquationSystem* sys, const DifferentiatedSystem& differentiated,
                                   const std::vector<double>& params, std::vector<DynamicSet>* sets,
                                   StateSelection* out) {
  ExprPool& p = *sys->pool;
  const size_t nv = sys->role.size();
  // The start point the pivots are chosen at.
  std::vector<double> start(nv, 0.0);
  {
    LeafValues lv;
    lv.params = params.data();
    for (size_t v = 0; v < nv; ++v) start[v] = sys->guess[v].valid() ? Evaluate(p, sys->guess[v], lv) : 0.0;
  }
  std::vector<uint32_t> rows;
  for (uint32_t e = 0; e < differentiated.derivative.size(); ++e) {
    if (differentiated.derivative[e] < 0 && differentiated.antiderivative[e] >= 0) {
      rows.push_back(e);
    }
  }
  std::vector<Candidate> cands;
  for (uint32_t v = 0; v < differentiated.max_order.size(); ++v) {
    if (differentiated.max_order[v] >= 1) cands.push_back({v, differentiated.max_order[v]});
  }
  std::vector<uint32_t> lowest_dummy(nv, UINT32_MAX);
  LevelChoice chooser(sys, differentiated, params, start);
  while (!rows.empty()) {
    std::vector<Candidate> chosen = chooser.Choose(rows, cands, &out->choices, sets);
    cands.clear();
    for (const Candidate& c : chosen) {
      lowest_dummy[c.var] = std::min(lowest_dummy[c.var], c.order);
      if (c.order >= 2) cands.push_back({c.var, c.order - 1});
    }
    std::vector<uint32_t> next;
    for (uint32_t r : rows) {
      int32_t a = differentiated.antiderivative[r];
      if (a >= 0 && differentiated.antiderivative[a] >= 0) next.push_back(static_cast<uint32_t>(a));
    }
    rows.swap(next);
  }
  out->warnings = chooser.warnings();
  return lowest_dummy;
}

/// Rewrites `sys` in the choice: dummy derivatives become algebraic variables; derivatives of
/// order two or more that stay derivatives go through new states (first-order form).
void RewriteInDummyDerivatives(EquationSystem* sys, const DifferentiatedSystem& differentiated,
                               const std::vector<uint32_t>& lowest_dummy,
                               const std::vector<DynamicSet>& sets, StateSelection* out) {
  ExprPool& p = *sys->pool;
  Substitution s(&p);
  std::vector<std::pair<ExprId, ExprId>> links;  // der(prev) = w, added after the substitution
  for (uint32_t v = 0; v < differentiated.max_order.size(); ++v) {
    const uint32_t top = differentiated.max_order[v];
    if (top == 0) continue;
    const FlatVariable base = sys->flat->variables[v];
    const std::string base_name = sys->flat->VariableName(VarId(v));
    auto make = [&](uint32_t order) {
      FlatVariable fv;
      fv.name = sys->MutableFlat().Own(DerName(base_name, order));
      fv.nominal = base.nominal;
      fv.instance = base.instance;
      fv.loc = base.loc;
      fv.derivative_of = VarId(v);
      fv.derivative_order = order;
      return sys->AddVariable(std::move(fv), p.Zero());
    };
    const uint32_t first_dummy = std::min(lowest_dummy[v], top + 1);
    for (uint32_t k = first_dummy; k <= top; ++k) {
      VarId w = make(k);
      s.Set(p.Der(VarId(v), k), p.Var(w));
      out->dummy_derivatives.push_back(DerName(base_name, k));
    }
    const uint32_t highest_kept = first_dummy - 1;
    if (highest_kept >= 2) {
      VarId prev(v);
      for (uint32_t j = 1; j < highest_kept; ++j) {
        VarId w = make(j);
        s.Set(p.Der(VarId(v), j), p.Var(w));
        links.push_back({p.Der(prev), p.Var(w)});
        out->new_states.push_back(DerName(base_name, j));
        prev = w;
      }
      s.Set(p.Der(VarId(v), highest_kept), p.Der(prev));
    }
  }
  for (size_t k = 0; k < sets.size(); ++k) AddStateSet(sys, sets[k], k + 1);
  if (s.size() == 0) return;
  sys->ApplySubstitution(&s);
  for (auto [der_prev, w] : links) {
    const VarId wid(p.node(w).a);
    const FlatVariable wv = sys->flat->variables[wid.value()];
    AddMadeEquation(sys, p.Sub(der_prev, w), wv.instance,
                    sys->flat->VariableName(wid) + " = " + DerName(sys->flat->VariableName(wv.derivative_of), wv.derivative_order),
                    wv.loc);
  }
}

}  // namespace

StateSelection SelectDummyDerivatives(EquationSystem* sys,
                                      const DifferentiatedSystem& differentiated,
                                      const std::vector<double>& params) {
  StateSelection out;
  std::vector<DynamicSet> sets;
  const std::vector<uint32_t> lowest_dummy = ChooseLevels(sys, differentiated, params, &sets, &out);
  RewriteInDummyDerivatives(sys, differentiated, lowest_dummy, sets, &out);
  return out;
}

}  // namespace momenta

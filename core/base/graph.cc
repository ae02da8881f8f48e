#include "core/base/graph.h"

#include <algorithm>

namespace momenta {

void BipartiteGraph::AddRow(const std::vector<uint32_t>& row_cols) {
  cols.insert(cols.end(), row_cols.begin(), row_cols.end());
  row_start.push_back(static_cast<uint32_t>(cols.size()));
}

IncrementalMatching::IncrementalMatching(const BipartiteGraph& g, const Matching& m)
    : col_to_row_(m.col_to_row), seen_(g.num_cols, 0) {
  rows_.reserve(g.num_rows());
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    rows_.emplace_back(g.cols.begin() + g.row_start[r], g.cols.begin() + g.row_start[r + 1]);
  }
}

bool IncrementalMatching::TryAdd(const std::vector<uint32_t>& cols) {
  const uint32_t root = static_cast<uint32_t>(rows_.size());
  rows_.push_back(cols);
  ++stamp_;
  struct Frame {
    uint32_t row;
    size_t pos;
  };
  std::vector<Frame> stack{{root, 0}};
  std::vector<uint32_t> via;  // via[k]: the column from frame k to frame k+1
  while (!stack.empty()) {
    const uint32_t row = stack.back().row;
    if (stack.back().pos == rows_[row].size()) {
      stack.pop_back();
      if (!via.empty()) via.pop_back();
      continue;
    }
    const uint32_t c = rows_[row][stack.back().pos++];
    if (seen_[c] == stamp_) continue;
    seen_[c] = stamp_;
    via.push_back(c);
    const int32_t next = col_to_row_[c];
    if (next >= 0) {
      stack.push_back({static_cast<uint32_t>(next), 0});
      continue;
    }
    // A free column: each row on the path takes the column after it.
    for (size_t k = 0; k < stack.size(); ++k) col_to_row_[via[k]] = static_cast<int32_t>(stack[k].row);
    return true;
  }
  rows_.pop_back();
  return false;
}

std::vector<uint32_t> IncrementalMatching::Reach(const std::vector<uint32_t>& cols) {
  ++stamp_;
  std::vector<uint32_t> rows;
  row_stamp_.resize(rows_.size(), 0);
  auto visit = [&](uint32_t c) {
    if (seen_[c] == stamp_) return;
    seen_[c] = stamp_;
    const int32_t r = col_to_row_[c];
    if (r >= 0 && row_stamp_[r] != stamp_) {
      row_stamp_[r] = stamp_;
      rows.push_back(static_cast<uint32_t>(r));
    }
  };
  for (uint32_t c : cols) visit(c);
  for (size_t k = 0; k < rows.size(); ++k) {
    for (uint32_t c : rows_[rows[k]]) visit(c);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

namespace {

/// Cheap assignment: each unmatched row takes its first free column.
void GreedyAssign(const BipartiteGraph& g, Matching* out) {
  Matching& m = *out;
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    if (m.row_to_col[r] >= 0) continue;
    for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) {
      uint32_t c = g.cols[k];
      if (m.col_to_row[c] < 0) {
        m.col_to_row[c] = static_cast<int32_t>(r);
        m.row_to_col[r] = static_cast<int32_t>(c);
        ++m.size;
        break;
      }
    }
  }
}

/// Depth-first search for augmenting paths (MC21 with look-ahead), shared by both matchings.
/// Columns marked with the current stamp are not entered again: a new stamp per search gives the
/// classic method, one stamp per phase Pothen and Fan's.
class AugmentingSearch {
 public:
  explicit AugmentingSearch(const BipartiteGraph& g)
      : g_(g), visited_(g.num_cols, 0), lookahead_(g.row_start.begin(), g.row_start.end() - 1) {}

  void NewStamp() { ++stamp_; }

  /// Searches from the unmatched row r0 and augments `m` along the path found: 1 when it did, 0
  /// when there is no path from r0, -1 when `budget` (search steps, decremented) ran out.
  int Augment(uint32_t r0, Matching* m, uint64_t* budget) {
    stack_.clear();
    stack_.push_back({r0, g_.row_start[r0], -1});
    int32_t found = -1;
    while (!stack_.empty() && found < 0) {
      if ((*budget)-- == 0) return -1;
      Frame& f = stack_.back();
      // Look ahead for a free column first.
      uint32_t& la = lookahead_[f.row];
      for (; la < g_.row_start[f.row + 1]; ++la) {
        uint32_t c = g_.cols[la];
        if (m->col_to_row[c] < 0) {
          found = static_cast<int32_t>(c);
          break;
        }
      }
      if (found >= 0) break;
      bool pushed = false;
      while (f.next < g_.row_start[f.row + 1]) {
        uint32_t c = g_.cols[f.next++];
        if (visited_[c] == stamp_) continue;
        visited_[c] = stamp_;
        const auto row = static_cast<uint32_t>(m->col_to_row[c]);
        stack_.push_back({row, g_.row_start[row], static_cast<int32_t>(c)});
        pushed = true;
        break;
      }
      if (!pushed) stack_.pop_back();
    }
    if (found < 0) return 0;
    // Augment: the top row takes the free column, each row below takes the column freed above it.
    int32_t c = found;
    for (size_t k = stack_.size(); k-- > 0;) {
      uint32_t row = stack_[k].row;
      int32_t freed = stack_[k].via_col;
      m->row_to_col[row] = c;
      m->col_to_row[c] = static_cast<int32_t>(row);
      c = freed;
    }
    ++m->size;
    return 1;
  }

 private:
  struct Frame {
    uint32_t row, next;
    int32_t via_col;  ///< the column whose matched row this frame is
  };
  const BipartiteGraph& g_;
  std::vector<uint32_t> visited_, lookahead_;
  uint32_t stamp_ = 0;
  std::vector<Frame> stack_;
};

/// Duff's MC21: a greedy start, then a depth-first search for an augmenting path from each
/// unmatched row, each with its own marks. Fast on most systems, but a long chain is walked once
/// per row (quadratic): past `budget` search steps it gives up (false).
bool ClassicMatching(const BipartiteGraph& g, uint64_t budget, Matching* out) {
  Matching& m = *out;
  const uint32_t nr = g.num_rows();
  m.row_to_col.assign(nr, -1);
  m.col_to_row.assign(g.num_cols, -1);
  GreedyAssign(g, &m);
  // Augmenting paths by depth-first search from each unmatched row, each with its own marks.
  AugmentingSearch search(g);
  for (uint32_t r0 = 0; r0 < nr; ++r0) {
    if (m.row_to_col[r0] >= 0) continue;
    search.NewStamp();
    if (search.Augment(r0, &m, &budget) < 0) return false;
  }
  return true;
}

}  // namespace

Matching MaximumMatching(const BipartiteGraph& g) {
  // The classic search first: the matching it finds is the one every model was analysed with
  // (state selection and dummy derivatives follow it), so models it handles quickly keep it; one
  // that would take more than a few passes over the graph (a pendulum chain of thousands of links:
  // 186 M steps at n = 3 000) is matched the fast way instead.
  Matching m;
  const uint64_t budget = (uint64_t{1} << 20) + 16 * (uint64_t{g.cols.size()} + g.num_rows());
  if (ClassicMatching(g, budget, &m)) return m;
  return FastMaximumMatching(g);
}

/// Linear in practice: Karp–Sipser's degree-one rules, a greedy start, then augmenting paths in
/// phases.
Matching FastMaximumMatching(const BipartiteGraph& g) {
  const uint32_t nr = g.num_rows();
  Matching m;
  m.row_to_col.assign(nr, -1);
  m.col_to_row.assign(g.num_cols, -1);
  // Karp–Sipser's degree-one rules first: a column that only one row holds, or a row with only
  // one column left, can be matched so without losing maximality; each match lowers the degrees
  // of its neighbours, so a chain (a pendulum chain's frames, an RC ladder) is matched whole in
  // linear time, where augmenting paths from a greedy start would walk it once per row.
  {
    std::vector<uint32_t> col_start(g.num_cols + 1, 0);
    for (uint32_t c : g.cols) ++col_start[c + 1];
    for (uint32_t c = 0; c < g.num_cols; ++c) col_start[c + 1] += col_start[c];
    std::vector<uint32_t> col_rows(g.cols.size());
    {
      std::vector<uint32_t> fill(col_start.begin(), col_start.end() - 1);
      for (uint32_t r = 0; r < nr; ++r) {
        for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) col_rows[fill[g.cols[k]]++] = r;
      }
    }
    std::vector<uint32_t> row_deg(nr), col_deg(g.num_cols);
    for (uint32_t r = 0; r < nr; ++r) row_deg[r] = g.row_start[r + 1] - g.row_start[r];
    for (uint32_t c = 0; c < g.num_cols; ++c) col_deg[c] = col_start[c + 1] - col_start[c];
    // Entries: row r as 2r, column c as 2c+1, queued when their degree becomes 1.
    std::vector<uint32_t> queue;
    for (uint32_t c = 0; c < g.num_cols; ++c) {
      if (col_deg[c] == 1) queue.push_back(2 * c + 1);
    }
    for (uint32_t r = 0; r < nr; ++r) {
      if (row_deg[r] == 1) queue.push_back(2 * r);
    }
    auto match = [&](uint32_t r, uint32_t c) {
      m.row_to_col[r] = static_cast<int32_t>(c);
      m.col_to_row[c] = static_cast<int32_t>(r);
      ++m.size;
      for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) {
        const uint32_t c2 = g.cols[k];
        if (m.col_to_row[c2] < 0 && --col_deg[c2] == 1) queue.push_back(2 * c2 + 1);
      }
      for (uint32_t k = col_start[c]; k < col_start[c + 1]; ++k) {
        const uint32_t r2 = col_rows[k];
        if (m.row_to_col[r2] < 0 && --row_deg[r2] == 1) queue.push_back(2 * r2);
      }
    };
    for (size_t q = 0; q < queue.size(); ++q) {
      const uint32_t x = queue[q] >> 1;
      if (queue[q] & 1) {
        if (m.col_to_row[x] >= 0 || col_deg[x] != 1) continue;
        for (uint32_t k = col_start[x]; k < col_start[x + 1]; ++k) {
          if (m.row_to_col[col_rows[k]] < 0) {
            match(col_rows[k], x);
            break;
          }
        }
      } else {
        if (m.row_to_col[x] >= 0 || row_deg[x] != 1) continue;
        for (uint32_t k = g.row_start[x]; k < g.row_start[x + 1]; ++k) {
          if (m.col_to_row[g.cols[k]] < 0) {
            match(x, g.cols[k]);
            break;
          }
        }
      }
    }
  }
  GreedyAssign(g, &m);
  // Augmenting paths by depth-first search from each unmatched row, in phases (Pothen and Fan):
  // a column visited in a phase stays visited for the phase's later searches, so a phase costs
  // O(entries) however many rows it starts from (separate marks per search walked a chain once per
  // row: quadratic); phases repeat until one augments nothing, and then no augmenting path exists.
  AugmentingSearch search(g);
  uint64_t unbounded = UINT64_MAX;
  std::vector<uint32_t> open;
  for (uint32_t r = 0; r < nr; ++r) {
    if (m.row_to_col[r] < 0) open.push_back(r);
  }
  for (bool augmented = true; augmented && !open.empty();) {
    augmented = false;
    search.NewStamp();
    size_t still_open = 0;
    for (uint32_t r0 : open) {
      if (search.Augment(r0, &m, &unbounded) > 0) {
        augmented = true;
      } else {
        open[still_open++] = r0;
      }
    }
    open.resize(still_open);
  }
  return m;
}

void OverDeterminedPart(const BipartiteGraph& g, const Matching& m, std::vector<uint32_t>* rows,
                        std::vector<uint32_t>* cols) {
  std::vector<bool> row_seen(g.num_rows(), false), col_seen(g.num_cols, false);
  std::vector<uint32_t> queue;
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    if (m.row_to_col[r] < 0) {
      row_seen[r] = true;
      queue.push_back(r);
    }
  }
  while (!queue.empty()) {
    uint32_t r = queue.back();
    queue.pop_back();
    rows->push_back(r);
    for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) {
      uint32_t c = g.cols[k];
      if (col_seen[c]) continue;
      col_seen[c] = true;
      cols->push_back(c);
      int32_t r2 = m.col_to_row[c];
      if (r2 >= 0 && !row_seen[r2]) {
        row_seen[r2] = true;
        queue.push_back(static_cast<uint32_t>(r2));
      }
    }
  }
  std::sort(rows->begin(), rows->end());
  std::sort(cols->begin(), cols->end());
}

void UnderDeterminedPart(const BipartiteGraph& g, const Matching& m, std::vector<uint32_t>* rows,
                         std::vector<uint32_t>* cols) {
  // Column -> rows incidence.
  std::vector<uint32_t> start(g.num_cols + 1, 0);
  for (uint32_t c : g.cols) ++start[c + 1];
  for (uint32_t c = 0; c < g.num_cols; ++c) start[c + 1] += start[c];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1), by_col(g.cols.size());
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) by_col[fill[g.cols[k]]++] = r;
  }
  std::vector<bool> row_seen(g.num_rows(), false), col_seen(g.num_cols, false);
  std::vector<uint32_t> queue;
  for (uint32_t c = 0; c < g.num_cols; ++c) {
    if (m.col_to_row[c] < 0) {
      col_seen[c] = true;
      queue.push_back(c);
    }
  }
  while (!queue.empty()) {
    uint32_t c = queue.back();
    queue.pop_back();
    cols->push_back(c);
    for (uint32_t k = start[c]; k < start[c + 1]; ++k) {
      uint32_t r = by_col[k];
      if (row_seen[r]) continue;
      row_seen[r] = true;
      rows->push_back(r);
      int32_t c2 = m.row_to_col[r];
      if (c2 >= 0 && !col_seen[c2]) {
        col_seen[c2] = true;
        queue.push_back(static_cast<uint32_t>(c2));
      }
    }
  }
  std::sort(rows->begin(), rows->end());
  std::sort(cols->begin(), cols->end());
}

std::vector<std::vector<uint32_t>> StronglyConnectedComponents(uint32_t n,
                                                               const std::vector<uint32_t>& start,
                                                               const std::vector<uint32_t>& adj) {
  std::vector<std::vector<uint32_t>> out;
  std::vector<int32_t> index(n, -1), low(n, 0);
  std::vector<bool> on_stack(n, false);
  std::vector<uint32_t> stack;
  struct Frame {
    uint32_t node, next;
  };
  std::vector<Frame> call;
  int32_t counter = 0;
  for (uint32_t s = 0; s < n; ++s) {
    if (index[s] >= 0) continue;
    call.push_back({s, start[s]});
    index[s] = low[s] = counter++;
    stack.push_back(s);
    on_stack[s] = true;
    while (!call.empty()) {
      Frame& f = call.back();
      if (f.next < start[f.node + 1]) {
        uint32_t w = adj[f.next++];
        if (index[w] < 0) {
          index[w] = low[w] = counter++;
          stack.push_back(w);
          on_stack[w] = true;
          call.push_back({w, start[w]});
        } else if (on_stack[w]) {
          low[f.node] = std::min(low[f.node], index[w]);
        }
        continue;
      }
      uint32_t v = f.node;
      if (low[v] == index[v]) {
        std::vector<uint32_t> comp;
        uint32_t w;
        do {
          w = stack.back();
          stack.pop_back();
          on_stack[w] = false;
          comp.push_back(w);
        } while (w != v);
        out.push_back(std::move(comp));
      }
      call.pop_back();
      if (!call.empty()) low[call.back().node] = std::min(low[call.back().node], low[v]);
    }
  }
  return out;
}

DisjointSets::DisjointSets(size_t num_elements) : parent_(num_elements) {
  for (uint32_t k = 0; k < parent_.size(); ++k) parent_[k] = k;
}

uint32_t DisjointSets::Find(uint32_t x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];
    x = parent_[x];
  }
  return x;
}

void DisjointSets::Join(uint32_t x, uint32_t y) { parent_[Find(x)] = Find(y); }

std::vector<std::vector<uint32_t>> DisjointSets::Sets() {
  std::vector<std::vector<uint32_t>> sets;
  std::vector<int32_t> set_of_root(parent_.size(), -1);
  for (uint32_t k = 0; k < parent_.size(); ++k) {
    const uint32_t root = Find(k);
    if (set_of_root[root] < 0) {
      set_of_root[root] = static_cast<int32_t>(sets.size());
      sets.emplace_back();
    }
    sets[set_of_root[root]].push_back(k);
  }
  return sets;
}

}  // namespace momenta

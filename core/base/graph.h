#pragma once
/// Graph algorithms for structural analysis: maximum bipartite matching (augmenting paths in the
/// manner of Duff's MC21), alternating-path reachability (the Dulmage–Mendelsohn over- and
/// under-determined parts), strongly connected components (Tarjan) and disjoint sets (connection
/// sets). All iterative, so a model of a million equations cannot overflow the call stack.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace momenta {

/// Rows (equations) to columns (unknowns), compressed: row r's columns are
/// cols[row_start[r] .. row_start[r+1]).
struct BipartiteGraph {
  uint32_t num_cols = 0;
  std::vector<uint32_t> row_start{0};
  std::vector<uint32_t> cols;

  uint32_t num_rows() const { return static_cast<uint32_t>(row_start.size() - 1); }
  void AddRow(const std::vector<uint32_t>& row_cols);
};

struct Matching {
  std::vector<int32_t> row_to_col, col_to_row;  ///< -1 when unmatched
  size_t size = 0;
};

/// A maximum matching: Duff's MC21 (greedy start, a depth-first search from each unmatched row),
/// or FastMaximumMatching when that would take more than a few passes over the graph.
Matching MaximumMatching(const BipartiteGraph& g);
/// A maximum matching in time linear in practice (Karp–Sipser's degree-one rules, a greedy
/// start, augmenting paths in Pothen–Fan phases); it may differ from MC21's.
Matching FastMaximumMatching(const BipartiteGraph& g);

/// A maximum matching that grows one row at a time: each row added is kept when an augmenting
/// path from it exists (so the matching stays perfect on the rows kept), found by a depth-first
/// search over what the row reaches only — cheap when the rows are local (one pendulum's initial
/// conditions among a thousand).
class IncrementalMatching {
 public:
  /// Starts from `g` and a matching `m` of it in which every row is matched.
  IncrementalMatching(const BipartiteGraph& g, const Matching& m);
  /// Adds the row `cols` when it can be matched too; returns whether it was.
  bool TryAdd(const std::vector<uint32_t>& cols);
  /// Rows (in order of addition, those of `g` first) reachable from `cols` by alternating paths:
  /// the rows a row with these columns would compete with.
  std::vector<uint32_t> Reach(const std::vector<uint32_t>& cols);
  bool ColumnMatched(uint32_t c) const { return col_to_row_[c] >= 0; }

 private:
  std::vector<std::vector<uint32_t>> rows_;
  std::vector<int32_t> col_to_row_;
  std::vector<uint32_t> seen_;
  std::vector<uint32_t> row_stamp_;  ///< Reach: rows met in the current call (== stamp_)
  uint32_t stamp_ = 0;
};

/// Rows and columns reachable by alternating paths from the unmatched rows: the part of the
/// system with more equations than unknowns.
void OverDeterminedPart(const BipartiteGraph& g, const Matching& m, std::vector<uint32_t>* rows,
                        std::vector<uint32_t>* cols);
/// Rows and columns reachable by alternating paths from the unmatched columns: the part with
/// more unknowns than equations.
void UnderDeterminedPart(const BipartiteGraph& g, const Matching& m, std::vector<uint32_t>* rows,
                         std::vector<uint32_t>* cols);

/// Strongly connected components of a directed graph (adjacency compressed as above). Components
/// come out dependencies first: if u -> v (u depends on v), v's component precedes u's.
std::vector<std::vector<uint32_t>> StronglyConnectedComponents(uint32_t num_nodes,
                                                               const std::vector<uint32_t>& start,
                                                               const std::vector<uint32_t>& adj);

/// Disjoint sets over the elements 0 … n-1 (union-find with path halving), such as the connectors
/// joined by connections into connection sets.
class DisjointSets {
 public:
  explicit DisjointSets(size_t num_elements);
  size_t size() const { return parent_.size(); }
  /// The root of x's set (halving the path to it on the way).
  uint32_t Find(uint32_t x);
  /// Joins the sets of x and y: x's root is hung under y's.
  void Join(uint32_t x, uint32_t y);
  /// The sets, each in element order, ordered by their first element (whatever the roots are).
  std::vector<std::vector<uint32_t>> Sets();

 private:
  std::vector<uint32_t> parent_;
};

}  // namespace momenta

#pragma once
/// Graph algorithms for structural analysis: maximum bipartite matching (augmenting paths in the
/// manner of Duff's MC21), alternating-path reachability (the Dulmage–Mendelsohn over- and
/// under-determined parts) and strongly connected components (Tarjan). All iterative, so a model
/// of a million equations cannot overflow the call stack.

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

Matching MaximumMatching(const BipartiteGraph& g);

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

}  // namespace momenta

// Maximum bipartite matching, the over- and under-determined parts, strongly connected components
// and disjoint sets, on small graphs with known answers and on 100 000-long chains and cycles (the
// algorithms are iterative: no stack overflow).

#include "core/base/graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace momenta {
namespace {

BipartiteGraph Graph(uint32_t num_cols, const std::vector<std::vector<uint32_t>>& rows) {
  BipartiteGraph g;
  g.num_cols = num_cols;
  for (const auto& r : rows) g.AddRow(r);
  return g;
}

/// A matching is consistent: row_to_col and col_to_row agree, every pair is an edge, size counts.
void ExpectValid(const BipartiteGraph& g, const Matching& m) {
  ASSERT_EQ(m.row_to_col.size(), g.num_rows());
  ASSERT_EQ(m.col_to_row.size(), g.num_cols);
  size_t matched = 0;
  for (uint32_t r = 0; r < g.num_rows(); ++r) {
    int32_t c = m.row_to_col[r];
    if (c < 0) continue;
    ++matched;
    EXPECT_EQ(m.col_to_row[c], static_cast<int32_t>(r));
    bool edge = false;
    for (uint32_t k = g.row_start[r]; k < g.row_start[r + 1]; ++k) edge = edge || g.cols[k] == static_cast<uint32_t>(c);
    EXPECT_TRUE(edge) << "row " << r << " matched to column " << c << " without an edge";
  }
  size_t cols_matched = 0;
  for (int32_t r : m.col_to_row) cols_matched += r >= 0;
  EXPECT_EQ(matched, cols_matched);
  EXPECT_EQ(m.size, matched);
}

/// The size of a maximum matching by brute force (small graphs only).
size_t BruteForce(const BipartiteGraph& g, uint32_t row, std::vector<bool>* used) {
  if (row == g.num_rows()) return 0;
  size_t best = BruteForce(g, row + 1, used);
  for (uint32_t k = g.row_start[row]; k < g.row_start[row + 1]; ++k) {
    uint32_t c = g.cols[k];
    if ((*used)[c]) continue;
    (*used)[c] = true;
    best = std::max(best, 1 + BruteForce(g, row + 1, used));
    (*used)[c] = false;
  }
  return best;
}

TEST(GraphTest, PerfectMatching) {
  BipartiteGraph g = Graph(3, {{0, 1}, {1}, {1, 2}});
  Matching m = MaximumMatching(g);
  ExpectValid(g, m);
  EXPECT_EQ(m.size, 3u);
  EXPECT_EQ(m.row_to_col[1], 1);
  EXPECT_EQ(m.row_to_col[0], 0);
  EXPECT_EQ(m.row_to_col[2], 2);
}

TEST(GraphTest, MatchingNeedsAugmentingPaths) {
  // The greedy pass gives row r column r; the last row only fits column 0, which forces every
  // row to shift one to the right: an augmenting path through all rows.
  const uint32_t n = 6;
  std::vector<std::vector<uint32_t>> rows;
  for (uint32_t r = 0; r + 1 < n; ++r) rows.push_back({r, r + 1});
  rows.push_back({0});
  BipartiteGraph g = Graph(n, rows);
  Matching m = MaximumMatching(g);
  ExpectValid(g, m);
  EXPECT_EQ(m.size, n);
  EXPECT_EQ(m.row_to_col[n - 1], 0);
  for (uint32_t r = 0; r + 1 < n; ++r) EXPECT_EQ(m.row_to_col[r], static_cast<int32_t>(r + 1));
}

TEST(GraphTest, MatchingAgreesWithBruteForceOnRandomGraphs) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 300; ++trial) {
    uint32_t nr = rng() % 7, nc = rng() % 7 + 1;
    std::vector<std::vector<uint32_t>> rows(nr);
    for (auto& r : rows) {
      for (uint32_t c = 0; c < nc; ++c) {
        if (rng() % 3 == 0) r.push_back(c);
      }
    }
    BipartiteGraph g = Graph(nc, rows);
    Matching m = MaximumMatching(g);
    ExpectValid(g, m);
    std::vector<bool> used(nc, false);
    EXPECT_EQ(m.size, BruteForce(g, 0, &used)) << "trial " << trial;
  }
}

TEST(GraphTest, FastMatchingAgreesWithBruteForceOnRandomGraphs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 1000; ++trial) {
    uint32_t nr = rng() % 8, nc = rng() % 8 + 1;
    std::vector<std::vector<uint32_t>> rows(nr);
    for (auto& r : rows) {
      for (uint32_t c = 0; c < nc; ++c) {
        if (rng() % 3 == 0) r.push_back(c);
      }
      if (!r.empty() && rng() % 5 == 0) r.push_back(r.front());  // a repeated column
    }
    BipartiteGraph g = Graph(nc, rows);
    Matching m = FastMaximumMatching(g);
    ExpectValid(g, m);
    std::vector<bool> used(nc, false);
    EXPECT_EQ(m.size, BruteForce(g, 0, &used)) << "trial " << trial;
  }
}

TEST(GraphTest, FastMatchingOnLongChains) {
  // The 100 000-long augmenting path below, and a chain of rows r touching r-1, r, r+1.
  const uint32_t n = 100000;
  BipartiteGraph g;
  g.num_cols = n;
  for (uint32_t r = 0; r + 1 < n; ++r) g.AddRow({r, r + 1});
  g.AddRow({0});
  Matching m = FastMaximumMatching(g);
  ExpectValid(g, m);
  EXPECT_EQ(m.size, n);
  BipartiteGraph h;
  h.num_cols = n;
  for (uint32_t r = 0; r < n; ++r) h.AddRow({r == 0 ? 0 : r - 1, r, std::min(r + 1, n - 1)});
  m = FastMaximumMatching(h);
  ExpectValid(h, m);
  EXPECT_EQ(m.size, n);
}

TEST(GraphTest, EmptyAndDegenerateGraphs) {
  BipartiteGraph empty;
  Matching m = MaximumMatching(empty);
  EXPECT_EQ(m.size, 0u);
  // Rows without columns and columns without rows.
  BipartiteGraph g = Graph(3, {{}, {2}, {}});
  m = MaximumMatching(g);
  ExpectValid(g, m);
  EXPECT_EQ(m.size, 1u);
  std::vector<uint32_t> rows, cols;
  OverDeterminedPart(g, m, &rows, &cols);
  EXPECT_EQ(rows, (std::vector<uint32_t>{0, 2}));
  EXPECT_TRUE(cols.empty());
  rows.clear();
  cols.clear();
  UnderDeterminedPart(g, m, &rows, &cols);
  EXPECT_EQ(cols, (std::vector<uint32_t>{0, 1}));
  EXPECT_TRUE(rows.empty());
}

TEST(GraphTest, Matching100000LongChain) {
  // Row r touches columns r and r+1 (r < n-1); the last row only column 0: one augmenting path
  // of length n, deeper than any call stack would allow.
  const uint32_t n = 100000;
  BipartiteGraph g;
  g.num_cols = n;
  for (uint32_t r = 0; r + 1 < n; ++r) g.AddRow({r, r + 1});
  g.AddRow({0});
  Matching m = MaximumMatching(g);
  EXPECT_EQ(m.size, n);
  EXPECT_EQ(m.row_to_col[n - 1], 0);
  EXPECT_EQ(m.row_to_col[0], 1);
  EXPECT_EQ(m.row_to_col[n - 2], static_cast<int32_t>(n - 1));
}

TEST(GraphTest, OverDeterminedPart) {
  // Three equations in x0 and x1 (rows 0-2), one equation in x2 and x3 (row 3): the first three
  // over-determine {x0, x1}; x2/x3 are under-determined.
  BipartiteGraph g = Graph(4, {{0, 1}, {0}, {1, 0}, {2, 3}});
  Matching m = MaximumMatching(g);
  ExpectValid(g, m);
  EXPECT_EQ(m.size, 3u);
  std::vector<uint32_t> rows, cols;
  OverDeterminedPart(g, m, &rows, &cols);
  EXPECT_EQ(rows, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(cols, (std::vector<uint32_t>{0, 1}));
  rows.clear();
  cols.clear();
  UnderDeterminedPart(g, m, &rows, &cols);
  EXPECT_EQ(rows, (std::vector<uint32_t>{3}));
  EXPECT_EQ(cols, (std::vector<uint32_t>{2, 3}));
}

TEST(GraphTest, PartsOfAPerfectMatchingAreEmpty) {
  BipartiteGraph g = Graph(3, {{0, 1}, {1, 2}, {2, 0}});
  Matching m = MaximumMatching(g);
  EXPECT_EQ(m.size, 3u);
  std::vector<uint32_t> rows, cols;
  OverDeterminedPart(g, m, &rows, &cols);
  UnderDeterminedPart(g, m, &rows, &cols);
  EXPECT_TRUE(rows.empty());
  EXPECT_TRUE(cols.empty());
}

TEST(GraphTest, UnderDeterminedPartFollowsAlternatingPaths) {
  // Columns 0..3, rows: r0 {0,1}, r1 {1,2}, r2 {3}. Four unknowns, three equations; whichever of
  // 0/1/2 stays unmatched, alternating paths reach all of 0, 1, 2 and rows 0, 1, but not the
  // separately determined column 3.
  BipartiteGraph g = Graph(4, {{0, 1}, {1, 2}, {3}});
  Matching m = MaximumMatching(g);
  EXPECT_EQ(m.size, 3u);
  std::vector<uint32_t> rows, cols;
  UnderDeterminedPart(g, m, &rows, &cols);
  EXPECT_EQ(rows, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(cols, (std::vector<uint32_t>{0, 1, 2}));
  rows.clear();
  cols.clear();
  OverDeterminedPart(g, m, &rows, &cols);
  EXPECT_TRUE(rows.empty());
}

struct Digraph {
  std::vector<uint32_t> start{0}, adj;
  void Node(const std::vector<uint32_t>& out) {
    adj.insert(adj.end(), out.begin(), out.end());
    start.push_back(static_cast<uint32_t>(adj.size()));
  }
  uint32_t size() const { return static_cast<uint32_t>(start.size() - 1); }
};

TEST(GraphTest, StronglyConnectedComponentsComeDependenciesFirst) {
  // 0 -> 1 -> {2, 3}; 2 <-> 3 form a cycle; 4 -> 0; 5 alone; 6 -> 6 (self-loop).
  Digraph d;
  d.Node({1});     // 0
  d.Node({2, 3});  // 1
  d.Node({3});     // 2
  d.Node({2});     // 3
  d.Node({0});     // 4
  d.Node({});      // 5
  d.Node({6});     // 6
  auto comps = StronglyConnectedComponents(d.size(), d.start, d.adj);
  // Every node in exactly one component.
  std::vector<int> comp_of(d.size(), -1);
  for (size_t c = 0; c < comps.size(); ++c) {
    for (uint32_t v : comps[c]) {
      EXPECT_EQ(comp_of[v], -1);
      comp_of[v] = static_cast<int>(c);
    }
  }
  for (int c : comp_of) EXPECT_GE(c, 0);
  EXPECT_EQ(comps.size(), 6u);
  EXPECT_EQ(comp_of[2], comp_of[3]);
  EXPECT_EQ((std::set<uint32_t>(comps[comp_of[2]].begin(), comps[comp_of[2]].end())),
            (std::set<uint32_t>{2, 3}));
  // u -> v: v's component comes no later than u's.
  for (uint32_t u = 0; u < d.size(); ++u) {
    for (uint32_t k = d.start[u]; k < d.start[u + 1]; ++k) {
      EXPECT_LE(comp_of[d.adj[k]], comp_of[u]) << u << " -> " << d.adj[k];
    }
  }
  EXPECT_LT(comp_of[3], comp_of[1]);
  EXPECT_LT(comp_of[1], comp_of[0]);
  EXPECT_LT(comp_of[0], comp_of[4]);
}

TEST(GraphTest, StronglyConnectedComponentsOnRandomGraphs) {
  // Against reachability: u and v share a component iff each reaches the other; and the order
  // is topological.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const uint32_t n = rng() % 12 + 1;
    Digraph d;
    std::vector<std::vector<bool>> reach(n, std::vector<bool>(n, false));
    for (uint32_t u = 0; u < n; ++u) {
      std::vector<uint32_t> out;
      for (uint32_t v = 0; v < n; ++v) {
        if (rng() % 5 == 0) {
          out.push_back(v);
          reach[u][v] = true;
        }
      }
      d.Node(out);
      reach[u][u] = true;
    }
    for (uint32_t k = 0; k < n; ++k) {
      for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) reach[i][j] = reach[i][j] || (reach[i][k] && reach[k][j]);
      }
    }
    auto comps = StronglyConnectedComponents(n, d.start, d.adj);
    std::vector<int> comp_of(n, -1);
    for (size_t c = 0; c < comps.size(); ++c) {
      for (uint32_t v : comps[c]) comp_of[v] = static_cast<int>(c);
    }
    for (uint32_t u = 0; u < n; ++u) {
      ASSERT_GE(comp_of[u], 0);
      for (uint32_t v = 0; v < n; ++v) {
        EXPECT_EQ(comp_of[u] == comp_of[v], reach[u][v] && reach[v][u]) << "trial " << trial;
        if (reach[u][v]) EXPECT_LE(comp_of[v], comp_of[u]) << "trial " << trial;
      }
    }
  }
}

TEST(GraphTest, StronglyConnectedComponentsOf100000Cycle) {
  const uint32_t n = 100000;
  Digraph cycle;
  for (uint32_t v = 0; v < n; ++v) cycle.Node({(v + 1) % n});
  auto comps = StronglyConnectedComponents(n, cycle.start, cycle.adj);
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_EQ(comps[0].size(), n);
  // And a 100 000-long chain: n singletons, the end of the chain first.
  Digraph chain;
  for (uint32_t v = 0; v < n; ++v) chain.Node(v + 1 < n ? std::vector<uint32_t>{v + 1} : std::vector<uint32_t>{});
  comps = StronglyConnectedComponents(n, chain.start, chain.adj);
  ASSERT_EQ(comps.size(), n);
  EXPECT_EQ(comps.front(), std::vector<uint32_t>{n - 1});
  EXPECT_EQ(comps.back(), std::vector<uint32_t>{0});
}

TEST(GraphTest, IncrementalMatchingKeepsRowsThatStillFit) {
  // Rows {0,1} and {1,2} over columns 0..3, matched 0->0, 1->1. A row {0} fits (the path
  // 0 -> row 0 -> 1 -> row 1 -> 2 frees column 0); a second {0} or a {1} then does not; {3} does.
  BipartiteGraph g;
  g.num_cols = 4;
  g.AddRow({0, 1});
  g.AddRow({1, 2});
  Matching m = MaximumMatching(g);
  ASSERT_EQ(m.size, 2u);
  IncrementalMatching im(g, m);
  EXPECT_FALSE(im.ColumnMatched(2));
  EXPECT_TRUE(im.TryAdd({0}));
  EXPECT_TRUE(im.ColumnMatched(2));
  EXPECT_FALSE(im.TryAdd({0}));
  EXPECT_FALSE(im.TryAdd({1}));
  // What a row {1} competes with: row 0 (now on column 1, which could move only to column 0) and
  // the added row {0} — not row 1, whose column 2 row 0 cannot take.
  EXPECT_EQ(im.Reach({1}), (std::vector<uint32_t>{0, 2}));
  EXPECT_TRUE(im.TryAdd({3}));
  EXPECT_EQ(im.Reach({3}), (std::vector<uint32_t>{3}));
  // A 100 000-long chain of augmenting steps stays iterative.
  const uint32_t n = 100000;
  BipartiteGraph chain;
  chain.num_cols = n + 1;
  for (uint32_t r = 0; r < n; ++r) chain.AddRow({r, r + 1});
  Matching cm = MaximumMatching(chain);
  ASSERT_EQ(cm.size, n);
  IncrementalMatching ic(chain, cm);
  EXPECT_EQ(ic.ColumnMatched(0) && ic.ColumnMatched(n), false);
  EXPECT_TRUE(ic.TryAdd({cm.col_to_row[0] < 0 ? n : 0}));
  for (uint32_t c = 0; c <= n; ++c) EXPECT_TRUE(ic.ColumnMatched(c)) << c;
}

TEST(GraphTest, DisjointSetsInElementOrder) {
  DisjointSets sets(7);
  sets.Join(5, 1);
  sets.Join(3, 6);
  sets.Join(6, 1);
  EXPECT_EQ(sets.Find(3), sets.Find(5));
  EXPECT_NE(sets.Find(0), sets.Find(1));
  // Ordered by first element, each in element order, whichever element is the root.
  const std::vector<std::vector<uint32_t>> expected = {{0}, {1, 3, 5, 6}, {2}, {4}};
  EXPECT_EQ(sets.Sets(), expected);
}

TEST(GraphTest, DisjointSetsJoinHangsTheFirstRootUnderTheSecond) {
  // Callers that order sets by their roots (dummy derivatives) rely on which root stays.
  DisjointSets sets(3);
  sets.Join(0, 1);
  EXPECT_EQ(sets.Find(0), 1u);
  sets.Join(2, 0);
  EXPECT_EQ(sets.Find(2), 1u);
}

TEST(GraphTest, DisjointSets100000LongChain) {
  const uint32_t n = 100000;
  DisjointSets sets(n);
  for (uint32_t k = 0; k + 1 < n; ++k) sets.Join(k, k + 1);
  EXPECT_EQ(sets.Find(0), n - 1);
  const std::vector<std::vector<uint32_t>> all = sets.Sets();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].size(), n);
}

}  // namespace
}  // namespace momenta

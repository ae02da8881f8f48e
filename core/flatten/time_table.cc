#include "core/flatten/time_table.h"

#include "core/expr/expr_chain.h"

namespace momenta {

namespace {
/// The sum of `terms` as a balanced tree (a long table stays shallow).
ExprId SumOf(ExprPool* pool, const std::vector<ExprId>& terms) {
  return BuildChain(terms, std::vector<bool>(terms.size(), false),
                    [&](ExprId a, bool, ExprId b) { return pool->Add(a, b); });
}
}  // namespace

ExprId TimeTableSum(ExprPool* pool, ExprId x, ExprId table, int smoothness, int extrapolation,
                    const std::vector<uint8_t>& jumps) {
  ExprPool& p = *pool;
  const Node t = p.node(table);
  const uint32_t n = t.b, cols = t.TableColumns(), column = t.TableColumn();
  auto abscissa = [&](uint32_t r) { return p.Param(ParamId(t.a + r * cols)); };
  auto ordinate = [&](uint32_t r) { return p.Param(ParamId(t.a + r * cols + column - 1)); };
  auto reached = [&](uint32_t r) { return p.Binary(Op::kGe, x, abscissa(r)); };
  if (n == 1) return ordinate(0);
  std::vector<ExprId> terms{ordinate(0)};
  // Constant segments: a step at every later row.
  if (smoothness == kConstantSegments) {
    for (uint32_t r = 1; r < n; ++r) terms.push_back(p.Mul(reached(r), p.Sub(ordinate(r), ordinate(r - 1))));
    return SumOf(pool, terms);
  }
  // Linear segments: a hinge (change of slope) at every row, a step at every jump.
  auto slope = [&](uint32_t r) {
    return p.Div(p.Sub(ordinate(r + 1), ordinate(r)), p.Sub(abscissa(r + 1), abscissa(r)));
  };
  auto hinge = [&](uint32_t r, ExprId change) { return p.Mul(p.Mul(reached(r), change), p.Sub(x, abscissa(r))); };
  const bool hold = extrapolation == kHoldLastPoint;
  // The slope so far; LastTwoPoints extends the first segment backwards.
  ExprId prev = p.Zero();
  uint32_t r0 = 0;
  if (!hold && !jumps[0]) {
    prev = slope(0);
    terms.push_back(p.Mul(prev, p.Sub(x, abscissa(0))));
    r0 = 1;
  }
  for (uint32_t r = r0; r + 1 < n; ++r) {
    if (jumps[r]) {  // a jump at t_r; the slope carries on after it
      terms.push_back(p.Mul(reached(r + 1), p.Sub(ordinate(r + 1), ordinate(r))));
      continue;
    }
    ExprId s = slope(r);
    terms.push_back(hinge(r, p.Sub(s, prev)));
    prev = s;
  }
  // HoldLastPoint: the slope returns to 0 after the last row.
  if (hold) terms.push_back(p.Neg(hinge(n - 1, prev)));
  return SumOf(pool, terms);
}

ExprId BooleanTableSum(ExprPool* pool, ExprId x, ExprId table) {
  ExprPool& p = *pool;
  const Node t = p.node(table);
  std::vector<ExprId> terms;
  for (uint32_t r = 0; r < t.b; ++r) {
    ExprId c = p.Binary(Op::kGe, x, p.Param(ParamId(t.a + r * t.TableColumns())));
    terms.push_back(r % 2 == 0 ? c : p.Neg(c));
  }
  return SumOf(pool, terms);
}

}  // namespace momenta

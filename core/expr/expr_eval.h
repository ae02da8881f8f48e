#pragma once
/// Evaluation outside the compiled programs: the numeric meaning of a table read, and a walk that
/// evaluates an expression (parameter bindings at build time, tests). The arithmetic of the other
/// operations is core/expr/ops.h's, shared with constant folding and the compiled programs, so
/// that all three agree to the bit.

#include <cmath>
#include <cstdint>
#include <cstddef>
#include <vector>

#include "core/expr/expr.h"
#include "core/expr/ops.h"

namespace momenta {

/// interpolate(table, x) (`slope` false) or its derivative in x (`slope` true): `table` points at
/// element [1,1] of a rows × cols table stored row by row, `column` is 1-based. The first column
/// holds strictly increasing abscissas (checked when parameters are evaluated). Between rows the
/// value is linear; beyond the ends it extends the first or last segment (linear extrapolation
/// through two rows, MSL's Modelica.Math.Vectors.interpolate and tempInterpol1); a one-row table
/// is constant. At an interior abscissa the segment to its right applies, as in the MSL.
inline double InterpolateTable(const double* table, uint32_t rows, uint32_t cols, uint32_t column,
                               double x, bool slope) {
  const double* y = table + (column - 1);
  if (rows == 1) return slope ? 0.0 : y[0];
  // The segment [i, i+1] (0-based rows): the last row whose abscissa is <= x, kept in
  // 0 .. rows-2 so that beyond either end the outer segment extends.
  uint32_t lo = 0, hi = rows - 1;  // invariant: x >= t[lo] or lo == 0; x < t[hi] or hi == rows-1
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (x >= table[static_cast<size_t>(mid) * cols]) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const double x0 = table[static_cast<size_t>(lo) * cols], x1 = table[static_cast<size_t>(hi) * cols];
  const double y0 = y[static_cast<size_t>(lo) * cols], y1 = y[static_cast<size_t>(hi) * cols];
  const double k = (y1 - y0) / (x1 - x0);
  return slope ? k : y0 + k * (x - x0);
}

/// Values for the leaves of an expression, for evaluation outside the compiled programs (parameter
/// bindings at build time, tests). Missing vectors read as zero.
struct LeafValues {
  const double* params = nullptr;
  const double* vars = nullptr;
  const double* ders = nullptr;
  const double* pres = nullptr;
  const double* conds = nullptr;
  double time = 0;
  bool initial = false;
};

/// Evaluates `e` by walking the tree with an explicit stack, each node once: for build time and
/// tests, not hot paths.
double Evaluate(const ExprPool& pool, ExprId e, const LeafValues& leaves);

}  // namespace momenta

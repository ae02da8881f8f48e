#pragma once
/// Linear structure: an expression as a sum of numeric multiples of leaves plus an offset (an
/// alias equation, a defining equation v = c*der(s)), and an equation solved for a leaf it is
/// linear in.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

/// The leaf kinds an alias equation never holds: derivatives, pre-values, time, initial() and
/// conditions (alias elimination; the sure aliases of core/flatten/equation_template.h).
constexpr uint8_t kNeverAliasLeaves = kHasDer | kHasPre | kHasTime | kHasInitial | kHasCond;

/// e = sum(coef_k * leaf_k) + offset, with numeric coefficients and a parameter-only offset.
struct AffineForm {
  std::vector<std::pair<ExprId, double>> terms;  ///< leaf (kVar or kDer) and its coefficient
  ExprId offset;
};

/// Decomposes `e` as an AffineForm; false when `e` is not affine in its variables with numeric
/// coefficients, or has more than `max_terms` terms.
bool DecomposeAffine(ExprPool* pool, ExprId e, size_t max_terms, AffineForm* out);

/// Solves `residual = 0` for `leaf` when the residual is linear in it: residual = a*leaf + b with a
/// free of `leaf`. With `param_coefficient_ok`, `a` may be a parameter expression (its value is
/// then checked for zero at run time: see *coefficient); otherwise `a` must be a nonzero number.
/// Returns an invalid id when the equation cannot be solved this way.
ExprId SolveFor(ExprPool* pool, ExprId residual, ExprId leaf, bool param_coefficient_ok,
                ExprId* coefficient);

}  // namespace momenta

#pragma once
/// Pantelides' algorithm (C. C. Pantelides, "The consistent initialization of differential-
/// algebraic systems", SIAM J. Sci. Stat. Comput. 9, 1988): finds which equations of a DAE must
/// be differentiated, and how often, so that the highest derivatives of the variables can be
/// matched one to one with the equations — the structural index reduction that lets a
/// constraint such as x^2 + y^2 = L^2 between integrated positions be solved together with the
/// dynamics.
///
/// The unknowns of the graph are the variables' derivatives of every order that occurs,
/// (v, k) = der^k(v); only the highest order of each variable takes part in the matching (the
/// lower ones are known from integration). For each equation in turn an augmenting path is
/// sought; when none exists, every equation and unknown the search visited is differentiated
/// once — symbolically, with the chain rule, each branch of an if-expression on its own — and
/// the search repeats from the equation's derivative. The differentiated equations are added to
/// the system; the dummy-derivative pass (dummy_derivatives.h) then chooses which derivatives
/// become algebraic so that the result is an index-1 DAE.

#include <cstdint>
#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

/// The derivative graph of the equations after Pantelides' algorithm.
struct DifferentiatedSystem {
  /// By equation (index into sys.equations): its time derivative, or -1.
  std::vector<int32_t> derivative;
  /// By equation: the equation it is the time derivative of, or -1.
  std::vector<int32_t> antiderivative;
  /// By flat variable: the highest derivative order that occurs in the equations (0: none).
  std::vector<uint32_t> max_order;
  /// Differentiations of the most differentiated equation, plus one (1: nothing to do; a
  /// mechanical constraint on positions gives 3).
  uint32_t structural_index = 1;
  size_t num_differentiated = 0;  ///< equations added
};

/// Runs Pantelides' algorithm on the continuous equations of `sys` and adds the differentiated
/// equations to it. A system that is not structurally regular (unbalanced, or singular in all
/// its derivatives) is left unchanged for the structural analysis to report. Throws ModelError
/// naming the equations when differentiation does not terminate.
DifferentiatedSystem Pantelides(EquationSystem* sys);

}  // namespace momenta

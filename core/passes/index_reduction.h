#pragma once
/// Structural index reduction for the constraints that acausal connection produces most often.
///
/// 1. Derivative aliases. When der(s) occurs in several equations and one of them reads
///    v = c*der(s) (+ offset), der(s) is replaced by that expression of v in the others. A speed
///    sensor on a mass then yields sensor.v = mass.v, an alias, instead of a second equation for
///    der(s).
/// 2. Constrained states. An equation without derivatives whose variables are all differentiated
///    somewhere (e.g. s_rel = flange_b.s - flange_a.s between two masses) is an index-2 constraint.
///    It is solved for one of its variables x (linear, with a numeric or parameter coefficient),
///    and x and der(x) are replaced everywhere by the solution and its time derivative — the
///    dummy-derivative method for constraints that are linear in the chosen variable. A variable
///    with `stateSelect: never` is chosen first, then the one in the fewest constraints, then one
///    with `avoid` (or without `prefer`); `always` variables are never chosen, and a constraint
///    whose `never` variable cannot be solved for is left to Pantelides' algorithm.
///
/// This is the fast path for the constraints acausal connection produces most often (a chain of
/// 100 000 masses reduces in linear time with banded results). What remains of index > 1
/// (nonlinear position constraints, closed kinematic loops) goes to Pantelides' algorithm
/// (pantelides.h) and the dummy-derivative method (dummy_derivatives.h).

#include "core/passes/equation_system.h"

namespace momenta {

struct IndexStats {
  size_t derivative_aliases = 0;
  size_t constrained_states = 0;
  /// Constraints kept as the equation of their variable, whose derivative became a named variable
  /// (see ConstrainedStates in index_reduction.cc): a chain's frames.
  size_t kept_constraints = 0;
};

/// Steps 1 and 2. `leaves`, when given, holds the equations' leaves (collected here when not
/// valid) and is kept current, for the next round of alias elimination.
EquationSystem ReduceIndex(EquationSystem sys, IndexStats* stats, EquationLeaves* leaves = nullptr);

/// Step 1 again, after Pantelides' algorithm and the dummy derivatives, for the defining equations
/// v = c*der(x) + offset whose v is itself a state (differentiated); returns how many der(x) it
/// replaced. The differentiated constraints bring der(x) into equations it was not in before (a
/// revolute joint's der(phi) in the differentiated frame positions, squared in the centripetal
/// terms). Left there, der(x) is IDA's y' = c_j (y - y_pred) + y'_pred, and a residual nonlinear
/// in y' has second derivatives in y growing like c_j^2 ~ 1/h^2: whenever y'_pred is off (after
/// IDA drops to order 1, by O(h_old) whatever the new h), Newton's second correction is as large
/// as its first, the step fails however much IDA shrinks it, and IDA stops with IDA_CONV_FAIL.
/// With der(x) -> v the residuals are nonlinear in states and algebraic unknowns only, as when
/// the alias is found before differentiation. An algebraic v is left alone: substituting it
/// would merge the acceleration-level unknowns into one large algebraic loop.
size_t SubstituteDerivativeAliases(EquationSystem* sys);

}  // namespace momenta

#pragma once
/// The dummy-derivative method (S. E. Mattsson and G. Söderlind, "Index reduction in
/// differential-algebraic equations using dummy derivatives", SIAM J. Sci. Comput. 14, 1993):
/// after Pantelides' algorithm has added the differentiated equations, some derivatives are made
/// algebraic unknowns of their own ("dummy derivatives") so that the original and the
/// differentiated equations together form an index-1 DAE with no extra constraint.
///
/// Level by level, from the most differentiated equations down: the equations h that are
/// derivatives of others must be solvable for as many of the candidate derivatives z, so a
/// square, nonsingular block dh/dz_selected is chosen; z_selected become dummy derivatives, and
/// the next level works on the equations h differentiated once less with z_selected's lower
/// derivatives as candidates. The block is chosen by elimination with pivoting on dh/dz at the
/// start values (a pivot must be within a factor of ten of its row's largest entry; among those,
/// lower stateSelect priorities are made dummy first — never, avoid, default, prefer, always,
/// with a `default` or `avoid` variable whose derivative the model's own equations do not hold
/// below every `avoid` that they do; a variable left with the default by alias elimination takes
/// its aliases' stateSelect — then higher derivatives, then larger pivots; `never` takes any
/// nonzero pivot and `always` only when its row has no other), falling back to the structure
/// where the start values give zeros.
/// A block whose choice depends on the motion becomes a state set over the candidates of its
/// highest priority (one such candidate alone is kept statically).
///
/// Then every derivative of order two or more that is not a dummy is rewritten in first-order
/// form: der(der(x)) = der(x_d) with a new state x_d = der(x) ("der(x)"), so that IDA sees one
/// derivative per state.

#include <string>
#include <vector>

#include "core/passes/pantelides.h"

namespace momenta {

struct StateSelection {
  std::vector<std::string> dummy_derivatives;  ///< e.g. "der(pendulum.y)"
  std::vector<std::string> new_states;         ///< first-order form: "der(spring.x)"
  /// Where a choice was made: the candidates and how many of them stay states, in words.
  std::vector<std::string> choices;
  std::vector<std::string> warnings;  ///< stateSelect: never that could not be honoured
};

/// Chooses the dummy derivatives of `sys` (after Pantelides) and rewrites the system in them;
/// `params` are the parameter values (for the start values). Throws ModelError naming the
/// equations when a level admits no nonsingular choice.
StateSelection SelectDummyDerivatives(EquationSystem* sys,
                                      const DifferentiatedSystem& differentiated,
                                      const std::vector<double>& params);

}  // namespace momenta

#pragma once
/// The model of a zero-crossing function between two samples, used to find crossings that go
/// through zero and back between them (a threshold touched for a tiny fraction of a step).
///
/// On a sample interval [a, b] of length h, with τ = (t - a)/h, the crossing function's values
/// u0, u1 and its time derivatives scaled to τ (v0 = h·du/dt(a), v1 = h·du/dt(b)) determine the
/// cubic Hermite interpolant
///     u(τ) = c0 + c1 τ + c2 τ² + c3 τ³,  c0 = u0, c1 = v0, c2 = 3(u1 - u0) - 2 v0 - v1,
///                                        c3 = 2(u0 - u1) + v0 + v1,
/// exact when the function is a polynomial of degree ≤ 3 in time along the interval, with error
/// h⁴/384 · max|u''''| otherwise. Its interior minimum is where u'(τ) = c1 + 2 c2 τ + 3 c3 τ² = 0
/// and u''(τ) > 0.

#include <optional>

namespace momenta {

struct CubicMinimum {
  double tau;    ///< in (0, 1)
  double value;  ///< the cubic's value there
};

/// The interior minimum of the cubic Hermite interpolant described above, if it has one in (0, 1).
std::optional<CubicMinimum> HermiteInteriorMinimum(double u0, double v0, double u1, double v1);

}  // namespace momenta

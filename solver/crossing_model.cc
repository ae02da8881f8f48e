#include "solver/crossing_model.h"

#include <cmath>

namespace momenta {

std::optional<CubicMinimum> HermiteInteriorMinimum(double u0, double v0, double u1, double v1) {
  const double c0 = u0, c1 = v0, c2 = 3 * (u1 - u0) - 2 * v0 - v1, c3 = 2 * (u0 - u1) + v0 + v1;
  // u' = 3 c3 τ² + 2 c2 τ + c1; the minimum is the root where u'' = 2 c2 + 6 c3 τ = +2 √d,
  // d = c2² - 3 c3 c1, written without cancellation for either sign of c2.
  const double d = c2 * c2 - 3 * c3 * c1;
  if (!(d >= 0)) return std::nullopt;
  const double root = std::sqrt(d);
  double tau;
  if (c2 >= 0) {
    if (!(c2 + root > 0)) return std::nullopt;  // u'' = 0: no strict minimum
    tau = -c1 / (c2 + root);
  } else {
    if (c3 == 0) return std::nullopt;  // a parabola opening downwards
    tau = (-c2 + root) / (3 * c3);
  }
  if (!(tau > 0 && tau < 1)) return std::nullopt;
  return CubicMinimum{tau, c0 + tau * (c1 + tau * (c2 + tau * c3))};
}

}  // namespace momenta

#pragma once
// Helpers of the physics tests that compare runs with closed forms: a build that fails the test
// on any warning, and the largest deviation of an output column from a function of time.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta::testing {

/// Builds inline YAML and fails the test on any warning (none is expected from these models).
inline Built BuildClean(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  Built b = BuildYaml(yaml, overrides);
  for (const auto& w : b.report.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  return b;
}

/// The largest |column - exact(t)| over all rows.
template <typename F>
double MaxError(const Trajectory& tr, const std::string& column, F exact) {
  const size_t j = tr.Index(column);
  double worst = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) worst = std::max(worst, std::abs(tr.values[k][j] - exact(tr.t[k])));
  return worst;
}

}  // namespace momenta::testing

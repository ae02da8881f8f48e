#pragma once
// Where a trajectory's events are: an event writes two rows at one time (left and right limits).

#include <cstddef>
#include <vector>

#include "tests/support/test_models.h"

namespace momenta::testing {

/// The first row of each pair of rows at one time.
inline std::vector<size_t> EventRows(const Trajectory& tr) {
  std::vector<size_t> rows;
  for (size_t k = 0; k + 1 < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k + 1]) rows.push_back(k);
  }
  return rows;
}

/// The times of those rows.
inline std::vector<double> EventTimes(const Trajectory& tr) {
  std::vector<double> times;
  for (size_t row : EventRows(tr)) times.push_back(tr.t[row]);
  return times;
}

}  // namespace momenta::testing

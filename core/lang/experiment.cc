// The output grid's check (core/lang/experiment.h).

#include "core/lang/experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace momenta {

std::string OutputGridProblem(double start, double stop, double interval) {
  const double rows = (stop - start) / interval;
  char buf[160];
  if (!(rows <= kMaxOutputRows)) {
    std::snprintf(buf, sizeof buf,
                  "from %g to %g s that is %.3g output rows; at most 1e9 can be written", start,
                  stop, rows);
    return buf;
  }
  const double resolution = 1e-13 * std::max(std::fabs(start), std::fabs(stop));
  if (!(interval > resolution)) {
    std::snprintf(buf, sizeof buf, "it is below the time resolution at t = %g (%g s)",
                  std::max(std::fabs(start), std::fabs(stop)), resolution);
    return buf;
  }
  return "";
}

}  // namespace momenta

// The output grid's check (core/lang/experiment.h), which the experiment section, the solver and
// the command line share: too many rows, an interval below the time resolution, a usable grid.

#include "core/lang/experiment.h"

#include <gtest/gtest.h>

namespace momenta {
namespace {

TEST(ExperimentTest, GridOfTooManyRowsSaysHowMany) {
  EXPECT_EQ(OutputGridProblem(0, 1, 1e-300),
            "from 0 to 1 s that is 1e+300 output rows; at most 1e9 can be written");
}

TEST(ExperimentTest, IntervalBelowTheTimeResolutionAtTheEnds) {
  EXPECT_EQ(OutputGridProblem(1e9, 1e9 + 1, 1e-7),
            "it is below the time resolution at t = 1e+09 (0.0001 s)");
  EXPECT_EQ(OutputGridProblem(-1e9 - 1, -1e9, 1e-7),
            "it is below the time resolution at t = 1e+09 (0.0001 s)");
}

TEST(ExperimentTest, UsableGridHasNoProblem) {
  EXPECT_EQ(OutputGridProblem(0, 1, 1e-3), "");
  EXPECT_EQ(OutputGridProblem(0, 1e9, 1), "");
}

}  // namespace
}  // namespace momenta

// The SUNDIALS boundary's helpers: a callback's work runs guarded (an exception becomes -1 and a
// stored message, never an exception through C code), a non-finite value asks for a retry, and
// the build reports which SUNDIALS it links.

#include "solver/sundials_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "solver/simulator.h"

namespace momenta {
namespace {

TEST(SundialsSupportTest, GuardedCallStoresTheExceptionAndStopsTheSolver) {
  std::string error;
  EXPECT_EQ(GuardedCall(&error, [] { throw std::runtime_error("table index out of range"); }), -1);
  EXPECT_EQ(error, "table index out of range");
  bool ran = false;
  std::string untouched;
  EXPECT_EQ(GuardedCall(&untouched, [&] { ran = true; }), 0);
  EXPECT_TRUE(ran);
  EXPECT_TRUE(untouched.empty());
}

TEST(SundialsSupportTest, NonFiniteValuesAskForARetry) {
  ContextPtr context = MakeContext();
  VectorPtr values = MakeVector(3, context.get());
  EXPECT_EQ(RetryUnlessFinite(values.get()), 0);  // zeros
  N_VGetArrayPointer(values.get())[1] = std::nan("");
  EXPECT_EQ(RetryUnlessFinite(values.get()), 1);
  N_VGetArrayPointer(values.get())[1] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(RetryUnlessFinite(values.get()), 1);
}

TEST(SundialsSupportTest, BuildInfoNamesTheLinkedVersion) {
  EXPECT_EQ(SolverBuildInfo().sundials_version, SUNDIALS_VERSION);
  EXPECT_EQ(SolverBuildInfo().sundials_version.rfind("6.4.", 0), 0u);  // the version CMake requires
}

}  // namespace
}  // namespace momenta

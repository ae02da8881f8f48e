// The cubic Hermite model of a crossing function between two samples: its interior minimum, in
// closed form for cubics and parabolas (where the model is exact).

#include "solver/crossing_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace momenta {
namespace {

TEST(CrossingModelTest, ParabolaDippingBelowZeroBetweenPositiveEnds) {
  // u = (τ - 0.5)² - 0.01: u(0) = u(1) = 0.24, u' = -1 and 1, minimum -0.01 at τ = 0.5.
  auto m = HermiteInteriorMinimum(0.24, -1, 0.24, 1);
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->tau, 0.5, 1e-15);
  EXPECT_NEAR(m->value, -0.01, 1e-15);
}

TEST(CrossingModelTest, CubicMinimumInClosedForm) {
  // u = τ³ - τ + 1: u(0) = 1, u'(0) = -1, u(1) = 1, u'(1) = 2; minimum at τ = 1/√3.
  auto m = HermiteInteriorMinimum(1, -1, 1, 2);
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->tau, 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(m->value, 1 - 2 / (3 * std::sqrt(3.0)), 1e-15);
  // The same cubic from the other end (τ -> 1 - τ flips the slopes' signs).
  auto r = HermiteInteriorMinimum(1, -2, 1, 1);
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->tau, 1 - 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(r->value, m->value, 1e-15);
}

TEST(CrossingModelTest, NoInteriorMinimum) {
  EXPECT_FALSE(HermiteInteriorMinimum(0, 1, 1, 1));      // u = τ: monotone
  EXPECT_FALSE(HermiteInteriorMinimum(0, 1, 0, -1));     // u = τ - τ²: a maximum only
  EXPECT_FALSE(HermiteInteriorMinimum(1, 0, 0, -3));      // u = 1 - τ³: decreasing, flat at τ = 0
  EXPECT_FALSE(HermiteInteriorMinimum(2, 0, 2, 0));      // constant
}

}  // namespace
}  // namespace momenta

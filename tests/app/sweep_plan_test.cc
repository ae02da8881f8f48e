// The runs of `momenta sweep`: the SPEC parser (values, lists, grids, distributions, and the
// messages of bad specs) and the plan (Cartesian product order, draws reproducible from the seed
// and shared by the grid points, the limits).

#include "app/sweep_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/base/error.h"

namespace momenta {
namespace {

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(SweepSpecTest, ValuesListsAndGrids) {
  EXPECT_EQ(ParseSweepAxis("eC=0.8").values, (std::vector<double>{0.8}));
  EXPECT_FALSE(ParseSweepAxis("eC=0.8").swept());
  EXPECT_EQ(ParseSweepAxis("eC=0.5,0.8,1").values, (std::vector<double>{0.5, 0.8, 1}));
  EXPECT_TRUE(ParseSweepAxis("eC=0.5,0.8,1").swept());
  EXPECT_EQ(ParseSweepAxis("eS=0:1:3").values, (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(ParseSweepAxis("x=-1:1:5").values, (std::vector<double>{-1, -0.5, 0, 0.5, 1}));
  EXPECT_EQ(ParseSweepAxis("on=true,false").values, (std::vector<double>{1, 0}));
  const std::vector<double> log = ParseSweepAxis("k=1e-2:1e2:log:5").values;
  ASSERT_EQ(log.size(), 5u);
  const double expected[] = {1e-2, 1e-1, 1, 10, 100};
  for (size_t k = 0; k < 5; ++k) EXPECT_NEAR(log[k], expected[k], 1e-14 * expected[k]) << k;
  EXPECT_EQ(log.front(), 1e-2);  // the ends exactly as given
  EXPECT_EQ(log.back(), 1e2);
  SweepAxis n = ParseSweepAxis("vA0=normal(5,0.5)");
  EXPECT_EQ(n.kind, SweepAxis::Kind::kNormal);
  EXPECT_EQ(n.a, 5);
  EXPECT_EQ(n.b, 0.5);
  SweepAxis u = ParseSweepAxis("eC=uniform(0.5, 1)");
  EXPECT_EQ(u.kind, SweepAxis::Kind::kUniform);
  EXPECT_EQ(u.a, 0.5);
  EXPECT_EQ(u.b, 1);
}

TEST(SweepSpecTest, BadSpecsNameTheOptionAndTheProblem) {
  const std::pair<const char*, const char*> cases[] = {
      {"eC", "-p takes NAME=SPEC"},
      {"eC=", "-p takes NAME=SPEC"},
      {"eC=0.5,x", "-p eC=0.5,x: the value 'x' is not a decimal number"},
      {"eC=0.5,,1", "-p eC=0.5,,1: the value '' is not a decimal number"},
      {"eS=0:1:x", "-p eS=0:1:x: the number of grid points 'x' is not a whole number from 1 to 10000000"},
      {"eS=0:1:2.5", "the number of grid points '2.5' is not a whole number"},
      {"eS=0:1:0", "the number of grid points '0' is not a whole number"},
      {"eS=0:1", "-p eS=0:1: a grid is a:b:n (linear) or a:b:log:n (logarithmic)"},
      {"eS=0:1:lin:3", "a grid is a:b:n"},
      {"k=0:1:log:3", "-p k=0:1:log:3: a logarithmic grid needs a positive start and end"},
      {"eS=nan:1:3", "the grid's start 'nan' is not a decimal number"},
      {"eC=normal(1)", "-p eC=normal(1): normal(mu,sigma) takes two numbers"},
      {"eC=normal(1,-1)", "the standard deviation must not be negative"},
      {"eC=uniform(1,0)", "the upper bound is below the lower bound"},
      {"eC=uniform(0,1", "uniform(a,b) must end with ')'"},
  };
  for (const auto& [text, message] : cases) {
    try {
      ParseSweepAxis(text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_TRUE(Contains(e.what(), message)) << text << ": " << e.what();
    }
  }
}

TEST(SweepPlanTest, CartesianProductFirstParameterSlowest) {
  SweepPlan plan = MakeSweepPlan({ParseSweepAxis("eC=0.5,0.8,1"), ParseSweepAxis("mA=40"), ParseSweepAxis("eS=0:1:3")}, 0, 0);
  EXPECT_EQ(plan.names, (std::vector<std::string>{"eC", "mA", "eS"}));
  ASSERT_EQ(plan.values.size(), 9u);
  for (size_t k = 0; k < 9; ++k) {
    EXPECT_EQ(plan.values[k][0], (std::vector<double>{0.5, 0.8, 1})[k / 3]) << k;
    EXPECT_EQ(plan.values[k][1], 40) << k;
    EXPECT_EQ(plan.values[k][2], (std::vector<double>{0, 0.5, 1})[k % 3]) << k;
  }
}

TEST(SweepPlanTest, DrawsAreReproducibleFromTheSeedAndShared) {
  auto plan = [](uint64_t seed) {
    return MakeSweepPlan({ParseSweepAxis("eS=0,1"), ParseSweepAxis("vA0=normal(5,0.5)"),
                          ParseSweepAxis("eC=uniform(0.5,1)")}, 4, seed);
  };
  SweepPlan a = plan(42), b = plan(42), c = plan(43);
  ASSERT_EQ(a.values.size(), 8u);  // 2 grid points x 4 draws, the draw fastest
  EXPECT_EQ(a.values, b.values);
  EXPECT_NE(a.values, c.values);
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(a.values[k][0], k < 4 ? 0 : 1);
    // Every grid point gets the same draws (common random numbers).
    EXPECT_EQ(a.values[k][1], a.values[k % 4][1]);
    EXPECT_EQ(a.values[k][2], a.values[k % 4][2]);
    EXPECT_GE(a.values[k][2], 0.5);
    EXPECT_LT(a.values[k][2], 1);
  }
  // The draws' first values are fixed by std::mt19937_64 (whose output the standard specifies) and
  // our own transforms, so they are the same with every standard library: the engine's first
  // output for seed 42 gives u1, its second u2.
  std::mt19937_64 engine(42);
  const double u1 = 1.0 - static_cast<double>(engine() >> 11) * 0x1.0p-53;
  const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  EXPECT_EQ(a.values[0][1], 5 + 0.5 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
  // The sample mean and spread of many draws.
  SweepPlan many = MakeSweepPlan({ParseSweepAxis("x=normal(5,0.5)"), ParseSweepAxis("y=uniform(-1,3)")}, 20000, 7);
  double sx = 0, sxx = 0, sy = 0;
  for (const auto& v : many.values) {
    sx += v[0];
    sxx += v[0] * v[0];
    sy += v[1];
  }
  const double n = many.values.size(), mean = sx / n;
  EXPECT_NEAR(mean, 5, 0.02);                              // 4 standard errors (0.5/sqrt(20000))
  EXPECT_NEAR(std::sqrt(sxx / n - mean * mean), 0.5, 0.02);
  EXPECT_NEAR(sy / n, 1, 0.04);                            // uniform(-1,3): mean 1, sd 1.15
}

TEST(SweepPlanTest, PlanErrors) {
  auto message = [](const std::vector<std::string>& specs, size_t samples) {
    std::vector<SweepAxis> axes;
    for (const auto& s : specs) axes.push_back(ParseSweepAxis(s));
    try {
      MakeSweepPlan(axes, samples, 0);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(message({"eC=normal(0.8,0.1)"}, 0), "-p eC=normal(0.8,0.1) is a distribution: give the number of draws with --samples K");
  EXPECT_EQ(message({"eC=0.5,0.8"}, 10), "--samples 10: no -p is a distribution (normal(mu,sigma) or uniform(a,b)) to draw from");
  EXPECT_EQ(message({"eC=0.5", "eC=0.8"}, 0), "-p eC is given twice");
  EXPECT_TRUE(Contains(message({"a=0:1:10000", "b=0:1:10000"}, 0), "more than 10000000 runs")) << message({"a=0:1:10000", "b=0:1:10000"}, 0);
}

}  // namespace
}  // namespace momenta

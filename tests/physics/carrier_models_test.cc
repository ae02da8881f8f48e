// The seed's Example 2 built two ways must agree: models/carrier_collision.yaml simulates the
// impacts (exact, from the model's equations), models/carrier_collision_maplesim.yaml is the
// seed's MapleSim construction (velocities from the custom Collision blocks, imposed through
// exact Position sources). After both collisions the velocities are the closed form
//   vB1 = mA vA0 (1 + eC) / (mA + mB),   vA1 = (mA vA0 - mB vB1) / mA,
//   vB2 = (mB - eS mS) vB1 / (mB + mS),  vS2 = mB (1 + eS) vB1 / (mB + mS),
// which both must give to rounding.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

struct Case {
  double mA, mB, mS, vA0, eC, eS;
};

double Final(const testing::Trajectory& tr, const std::string& name) { return tr.values.back()[tr.Index(name)]; }

TEST(CarrierModels, BothConstructionsGiveTheClosedForm) {
  testing::Built impacts = testing::BuildFile("models/carrier_collision.yaml");
  testing::Built maplesim = testing::BuildFile("models/carrier_collision_maplesim.yaml");
  for (const Case& c : {Case{40, 40, 15, 5, 0.8, 0.3}, Case{30, 50, 10, 4, 0.5, 0.9}, Case{60, 20, 25, 6, 1.0, 0.0},
                        Case{40, 40, 15, 3, 0.2, 0.6}}) {
    ParameterOverrides p{{"mA", c.mA}, {"mB", c.mB}, {"mS", c.mS}, {"vA0", c.vA0}, {"eC", c.eC}, {"eS", c.eS}};
    SCOPED_TRACE("mA " + std::to_string(c.mA) + " mB " + std::to_string(c.mB) + " mS " + std::to_string(c.mS) +
                 " vA0 " + std::to_string(c.vA0) + " eC " + std::to_string(c.eC) + " eS " + std::to_string(c.eS));
    const double vB1 = c.mA * c.vA0 * (1 + c.eC) / (c.mA + c.mB);
    // Stop just after the later model's second collision (gaps 1 m and 0.3 m in one, 0.5 m and
    // 0.5 m in the other), before A, if faster than B by then, catches it up again.
    SimulationOptions options = OptionsFromExperiment(impacts.model->experiment);
    options.stop = std::max(1 / c.vA0 + 0.3 / vB1, 0.5 / c.vA0 + 0.5 / vB1) + 0.01;
    testing::Trajectory a = testing::Run(impacts, options, p);
    testing::Trajectory b = testing::Run(maplesim, options, p);
    const double vA1 = (c.mA * c.vA0 - c.mB * vB1) / c.mA;
    const double vB2 = (c.mB - c.eS * c.mS) * vB1 / (c.mB + c.mS);
    const double vS2 = c.mB * (1 + c.eS) * vB1 / (c.mB + c.mS);
    EXPECT_NEAR(Final(b, "probeB.v"), vB2, 1e-12);
    EXPECT_NEAR(Final(b, "A.v"), vA1, 1e-12);
    EXPECT_NEAR(Final(b, "S.v"), vS2, 1e-12);
    // The two models agree to 1e-9 (both are within rounding of the closed form).
    EXPECT_NEAR(Final(a, "B.v"), Final(b, "B.v"), 1e-9);
    EXPECT_NEAR(Final(a, "A.v"), Final(b, "A.v"), 1e-9);
    EXPECT_NEAR(Final(a, "S.v"), Final(b, "S.v"), 1e-9);
  }
}

TEST(CarrierModels, MapleSimConstructionDetectsTheGapsAtTheirTimes) {
  // Each gap closes 0.5 m: A at 5 m/s meets B at 0.1 s; B at 4.5 m/s meets S 0.5/4.5 s later.
  testing::Built b = testing::BuildFile("models/carrier_collision_maplesim.yaml");
  testing::Trajectory tr = testing::RunDefault(b);
  EXPECT_NEAR(Final(tr, "probeB.v"), 2.9045454545454545, 1e-12);
  const size_t iv = tr.Index("probeB.v");
  double t_first = -1, t_second = -1;
  for (size_t k = 1; k < tr.t.size(); ++k) {
    if (tr.t[k] != tr.t[k - 1]) continue;  // an event: left and right limits at one time
    if (tr.values[k - 1][iv] == 0 && t_first < 0) t_first = tr.t[k];
    if (tr.values[k - 1][iv] == 4.5) t_second = tr.t[k];
  }
  EXPECT_NEAR(t_first, 0.1, 1e-10);
  EXPECT_NEAR(t_second, 0.1 + 0.5 / 4.5, 1e-10);
}

}  // namespace
}  // namespace momenta

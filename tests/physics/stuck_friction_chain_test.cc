// Two friction elements stuck in series at the start: the MSL's Rotational LossyGearDemo2
// (models/msl/Mechanics/Rotational/Examples/LossyGearDemo2.yaml.pending), where a BearingFriction
// and a LossyGear both hold Inertia1 at rest at t = 0. Locked, each carries a torque (its path
// parameter sa) that the equations do not split between them: the load of 10 N.m behind the
// gear is held by their sum only, so the initial system is singular where it holds. Its solution
// nearest the guesses puts more than the bearing's 0.5 N.m on the bearing, which breaks away
// backward at once, and the gear with it, as in the published reference (Dymola settles it the
// same way: bearingFriction.startBackward = 1 in its first row, both at mode -1 from 5.9e-11 s).
//
// Checked against that reference (tests/data/msl/...LossyGearDemo2.csv) within the MSL tube
// (2e-3 of max(1, max|column|)) at its grid times up to 0.06 s; at 0.0636 s both elements stop
// together, a singular restart the run does not get past yet (the file stays .pending for it).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

TEST(StuckFrictionChain, BothElementsBreakAwayBackwardFromTheStartAsTheReferenceDoes) {
  const testing::Built b =
      testing::BuildFile("models/msl/Mechanics/Rotational/Examples/LossyGearDemo2.yaml.pending");
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  opt.stop = 0.06;
  const testing::Trajectory ours = testing::Run(b, opt);
  ASSERT_NEAR(ours.t.back(), 0.06, 1e-12);
  const testing::Csv ref = testing::ReadCsv(
      testing::SourcePath("tests/data/msl/Modelica.Mechanics.Rotational.Examples.LossyGearDemo2.csv"));
  double worst = 0;
  int compared = 0;
  for (size_t c = 1; c < ref.header.size(); ++c) {
    double max_abs = 0;
    for (const auto& row : ref.rows) max_abs = std::max(max_abs, std::fabs(row[c]));
    const double allowed = 2e-3 * std::max(1.0, max_abs);
    const size_t col = ours.Index(ref.header[c]);
    for (const auto& row : ref.rows) {
      // Grid times after the start (the start's rows hold the initial event's left and right
      // limits; the breakaway event is at 5.9e-11 s in the reference, 5.9e-13 s in ours).
      if (row[0] < 1e-3 || row[0] > opt.stop + 1e-12) continue;
      auto at = std::lower_bound(ours.t.begin(), ours.t.end(), row[0] - 1e-12);
      ASSERT_TRUE(at != ours.t.end() && std::fabs(*at - row[0]) < 1e-12) << row[0];
      const size_t k = static_cast<size_t>(at - ours.t.begin());
      worst = std::max(worst, std::fabs(ours.values[k][col] - row[c]) / allowed);
      ++compared;
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_LE(worst, 1.0);
  std::printf("[   INFO   ] LossyGearDemo2 to 0.06 s: worst %.3g of the MSL tube over %d values\n", worst, compared);
  // Both broke away backward at once and slide on.
  EXPECT_EQ(ours.Column("bearingFriction.mode", 1 + ours.t.size() / 2), -1);
  EXPECT_EQ(ours.Column("gear.mode", 1 + ours.t.size() / 2), -1);
}

}  // namespace
}  // namespace momenta

// Planar multibody models that go through Pantelides' algorithm, at tolerances well below their
// experiments' 1e-6. Their differentiated position constraints bring der(phi) of the joint angles
// into the acceleration-level equations (squared, in the centripetal terms); left as IDA's y' there,
// Newton's iteration diverged whenever IDA's y' predictor was off, and the runs stopped with
// IDA_CONV_FAIL (DoublePendulum at 1e-7 to 1e-9, PendulumWithSpringDamper at 1e-7, 1e-9, 1e-10;
// at 1e-10 DoublePendulum took 301 738 steps). Index reduction now writes der(phi) as the state w
// of w = der(phi) there (index_reduction.h, SubstituteDerivativeAliases). Checked here: the runs
// finish without a failed step and with a bounded number of steps, the undamped double pendulum
// keeps its energy, and the tighter runs agree with each other.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

Trajectory RunAt(const Built& b, double rtol, const ParameterOverrides& overrides = {}) {
  SimulationOptions o = OptionsFromExperiment(b.model->experiment);
  o.rtol = rtol;
  return testing::Run(b, o, overrides);
}

// models/msl/DoublePendulum.yaml: two boxes (m = 13.86 kg, I = 0.292908 kg.m2 about the centre of
// mass, 0.25 m from their joints; bar 1 0.5 m long), angles relative, gravity 9.80665 along -y.
double DoublePendulumEnergy(const Trajectory& tr, size_t k) {
  const double m = 0.5 * 0.06 * 0.06 * 7700, inertia = m / 12 * (0.5 * 0.5 + 0.06 * 0.06), g = 9.80665;
  const double p1 = tr.Column("revolute1.phi", k), w1 = tr.Column("revolute1.w", k);
  const double p2 = p1 + tr.Column("revolute2.phi", k), w2 = w1 + tr.Column("revolute2.w", k);
  const double vx2 = -0.5 * std::sin(p1) * w1 - 0.25 * std::sin(p2) * w2;
  const double vy2 = 0.5 * std::cos(p1) * w1 + 0.25 * std::cos(p2) * w2;
  const double kinetic = 0.5 * m * std::pow(0.25 * w1, 2) + 0.5 * inertia * w1 * w1 +
                         0.5 * m * (vx2 * vx2 + vy2 * vy2) + 0.5 * inertia * w2 * w2;
  return kinetic + m * g * (0.25 * std::sin(p1) + 0.5 * std::sin(p1) + 0.25 * std::sin(p2));
}

// Without its damper the MSL double pendulum conserves energy (scale m g L = 136 J): at each
// tolerance the run finishes without a failed Newton step, in a few thousand steps, and the energy
// drift shrinks with the tolerance.
TEST(TightTolerances, MslDoublePendulumConservesEnergy) {
  Built b = testing::BuildFile("models/msl/DoublePendulum.yaml");
  // rtol, largest energy drift [J] (observed 5.4e-5, 5.0e-6, 1.1e-6, 1.6e-7), most steps (observed
  // 3 000 to 9 500).
  const struct {
    double rtol, drift;
    long steps;
  } cases[] = {{1e-7, 3e-4, 8000}, {1e-8, 3e-5, 12000}, {1e-9, 6e-6, 16000}, {1e-10, 1e-6, 25000}};
  for (const auto& c : cases) {
    SCOPED_TRACE("rtol " + std::to_string(c.rtol));
    Trajectory tr = RunAt(b, c.rtol, {{"damper.d", 0.0}});
    ASSERT_DOUBLE_EQ(tr.t.back(), 3.0);
    EXPECT_LT(tr.stats.steps, c.steps);
    // Failed Newton iterations that a fresh Jacobian recovers (observed at most 6); before, there
    // were tens of thousands, or a stop with IDA_CONV_FAIL.
    EXPECT_LT(tr.stats.nonlinear_failures, 30);
    const double e0 = DoublePendulumEnergy(tr, 0);
    double worst = 0;
    for (size_t k = 0; k < tr.t.size(); ++k) worst = std::max(worst, std::fabs(DoublePendulumEnergy(tr, k) - e0));
    EXPECT_LT(worst, c.drift);
  }
}

// The models as they are (damped), at 1e-7 to 1e-9 against 1e-10: every output row within a
// bound that shrinks with the tolerance (observed for DoublePendulum 3.3e-5, 2.0e-6, 5.6e-7; for
// PendulumWithSpringDamper 2.9e-6, 3.3e-7, 4.4e-8).
TEST(TightTolerances, MslPendulumsAgreeAcrossTolerances) {
  const struct {
    const char* model;
    double bound[3];
  } cases[] = {{"models/msl/DoublePendulum.yaml", {2e-4, 2e-5, 5e-6}},
               {"models/msl/PendulumWithSpringDamper.yaml", {2e-5, 3e-6, 5e-7}}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.model);
    Built b = testing::BuildFile(c.model);
    Trajectory ref = RunAt(b, 1e-10);
    ASSERT_EQ(ref.t.back(), b.model->experiment.stop);
    EXPECT_LT(ref.stats.nonlinear_failures, 30);
    const double rtols[] = {1e-7, 1e-8, 1e-9};
    for (int i = 0; i < 3; ++i) {
      SCOPED_TRACE("rtol " + std::to_string(rtols[i]));
      Trajectory tr = RunAt(b, rtols[i]);
      ASSERT_EQ(tr.t.size(), ref.t.size());
      EXPECT_LT(tr.stats.nonlinear_failures, 30);
      double worst = 0;
      for (size_t k = 0; k < tr.t.size(); ++k) {
        for (size_t j = 0; j < tr.names.size(); ++j) worst = std::max(worst, std::fabs(tr.values[k][j] - ref.values[k][j]));
      }
      EXPECT_LT(worst, c.bound[i]);
    }
  }
}

}  // namespace
}  // namespace momenta

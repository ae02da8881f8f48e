// Exact and filtered motion sources (Translational Position and Speed, MSL semantics) against
// closed forms. With exact = true the position is imposed and the source's force is whatever the
// motion needs: for a mass m on a spring c (rest length 1) driven along s = 1 + A sin(w t), the
// force the source exerts on the mass is m s'' + c (s - 1) = (c - m w^2) A sin(w t). With
// exact = false the reference goes through the MSL's filters:
//   Position: s'' + (af w/bf) s' + (w^2/bf) s = (w^2/bf) s_ref, s(0) = s_ref(0), v(0) = 0;
//   Speed:    v' = w (v_ref - v), v(0) = v_ref(0).
// For the ramp s_ref = v_ref = t these give, with sigma = af w/(2 bf), wd^2 = w^2/bf - sigma^2,
//   s = t - af/w + e^(-sigma t) (af/w cos(wd t) + (sigma af/w - 1)/wd sin(wd t)),
//   v = t - (1 - e^(-w t))/w.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

std::string DrivenMassYaml(const std::string& exact) {
  return R"(model: DrivenMass
parameters: {m: 2, c: 100, A: 0.1, f: 0.5}
components:
  wall: {type: Fixed, s0: 0}
  spring: {type: Spring, c: c, s_rel0: 1}
  mass: {type: Mass, m: m}
  source: {type: Position, exact: )" + exact + R"(}
  sine: {type: Sine, amplitude: A, f: f, offset: 1}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [mass.flange_b, source.flange]
  - [sine.y, source.s_ref]
experiment: {stop: 3, tolerance: 1e-10, interval: 0.01}
outputs: [mass.s, mass.a, mass.flange_b.f]
)";
}

TEST(PositionSource, ExactSineOnSpringMassGivesTheForceItNeeds) {
  Built b = testing::BuildYaml(DrivenMassYaml("true"));
  Trajectory tr = testing::RunDefault(b);
  const double m = 2, c = 100, A = 0.1, w = 2 * kPi * 0.5;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    EXPECT_NEAR(tr.values[k][0], 1 + A * std::sin(w * t), 1e-12) << "t = " << t;
    EXPECT_NEAR(tr.values[k][1], -A * w * w * std::sin(w * t), 1e-10) << "t = " << t;
    // The connection's force on the mass at flange_b is the source's: (c - m w^2) A sin(w t).
    EXPECT_NEAR(tr.values[k][2], (c - m * w * w) * A * std::sin(w * t), 1e-9) << "t = " << t;
  }
}

TEST(PositionSource, ExactThroughARodMovesBothMasses) {
  // Two masses joined by a rod, driven along s_ref = 0.5 + t^2/2 (a ramp integrated once, so
  // s'' = 1): the source must push m1 + m2 with 8 N.
  Built b = testing::BuildYaml(R"(model: RodPair
components:
  ramp: {type: Ramp, height: 2, duration: 2}
  integrator: {type: Integrator, y_start: 0.5}
  source: {type: Position, exact: true}
  m1: {type: Mass, m: 3, L: 1}
  rod: {type: Rod, L: 2}
  m2: {type: Mass, m: 5, L: 1}
connections:
  - [ramp.y, integrator.u]
  - [integrator.y, source.s_ref]
  - [source.flange, m1.flange_a]
  - [m1.flange_b, rod.flange_a]
  - [rod.flange_b, m2.flange_a]
experiment: {stop: 1.5, tolerance: 1e-10, interval: 0.01}
outputs: [m1.s, m2.s, m2.v, source.flange.f]
)");
  Trajectory tr = testing::RunDefault(b);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    // s_ref = 0.5 + t^2/2 is m1's left flange: m1.s = s_ref + 0.5; m2's centre is 1 + 2 + 0.5
    // further.
    EXPECT_NEAR(tr.values[k][0], 1 + t * t / 2, 1e-9) << "t = " << t;
    EXPECT_NEAR(tr.values[k][1], 4 + t * t / 2, 1e-9) << "t = " << t;
    EXPECT_NEAR(tr.values[k][2], t, 1e-9) << "t = " << t;
    // The flow into the source is minus the force it exerts: -(m1 + m2) * 1.
    EXPECT_NEAR(tr.values[k][3], -8.0, 1e-8) << "t = " << t;
  }
}

TEST(PositionSource, FilteredRampFollowsTheBesselFilter) {
  Built b = testing::BuildYaml(R"(model: FilteredRamp
components:
  ramp: {type: Ramp, height: 10, duration: 10}
  source: {type: Position, f_crit: 2}
  mass: {type: Mass, m: 1}
connections:
  - [ramp.y, source.s_ref]
  - [source.flange, mass.flange_a]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [source.s, source.v]
)");
  // The filter's velocity has no initial condition of its own (MSL: v(start = 0)): its start value
  // is used, with the usual warning.
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_NE(b.report.warnings[0].find("source.v"), std::string::npos) << b.report.warnings[0];
  Trajectory tr = testing::RunDefault(b);
  const double af = 1.3617, bf = 0.6180, w = 2 * kPi * 2;
  const double sigma = af * w / (2 * bf), wd = std::sqrt(w * w / bf - sigma * sigma);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    const double s = t - af / w + std::exp(-sigma * t) * (af / w * std::cos(wd * t) + (sigma * af / w - 1) / wd * std::sin(wd * t));
    EXPECT_NEAR(tr.values[k][0], s, 1e-8) << "t = " << t;
  }
}

TEST(SpeedSource, ExactAndFilteredRamp) {
  const std::string yaml = R"(model: SpeedRamp
parameters: {exact: false}
components:
  ramp: {type: Ramp, height: 10, duration: 10}
  source: {type: Speed, exact: exact, f_crit: 1}
  mass: {type: Mass, m: 1}
connections:
  - [ramp.y, source.v_ref]
  - [source.flange, mass.flange_a]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [source.s, source.v]
)";
  const double w = 2 * kPi;
  Trajectory filtered = testing::RunDefault(testing::BuildYaml(yaml));
  Trajectory exact = testing::RunDefault(testing::BuildYaml(yaml, {{"exact", 1}}));
  for (size_t k = 0; k < filtered.t.size(); ++k) {
    const double t = filtered.t[k];
    EXPECT_NEAR(filtered.values[k][1], t - (1 - std::exp(-w * t)) / w, 1e-8) << "t = " << t;
    EXPECT_NEAR(exact.values[k][1], t, 1e-12) << "t = " << t;
    EXPECT_NEAR(exact.values[k][0], t * t / 2, 1e-9) << "t = " << t;
  }
}

TEST(StructuralParameters, ExactIsFixedWhenTheModelIsBuilt) {
  // exact chooses equations: a new value needs a new build, and says so.
  Built b = testing::BuildYaml(DrivenMassYaml("true"));
  ModelState state(b.model);
  try {
    state.SetParameters({{"source.exact", 0}});
    FAIL() << "expected an error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("source.exact shapes the model's structure"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace momenta

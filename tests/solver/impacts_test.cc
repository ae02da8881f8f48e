// Exact impacts against closed forms: two free masses, a rod-linked pair, a mass held by a spring,
// the seed's carrier collision, a bouncing ball (impact times and the Zeno end) and Newton's
// cradle. Momentum and energy balances are checked across every impact.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

/// Two masses on a line, A at 0 moving at vA0 towards B at 1 (moving at vB0), an Impact between.
std::string TwoMasses(double mA, double mB, double vA0, double vB0, double e) {
  std::ostringstream y;
  y.precision(17);
  y << "model: TwoMasses\n"
       "components:\n"
       "  A: {type: Mass, m: " << mA << ", L: 0.2, s: {start: 0, fixed: true}, v: {start: " << vA0 << ", fixed: true}}\n"
       "  B: {type: Mass, m: " << mB << ", L: 0.2, s: {start: 1, fixed: true}, v: {start: " << vB0 << ", fixed: true}}\n"
       "  AB: {type: Impact, e: " << e << "}\n"
       "connections:\n"
       "  - [A.flange_b, AB.flange_a]\n"
       "  - [AB.flange_b, B.flange_a]\n"
       "experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}\n"
       "outputs: [A.v, B.v]\n";
  return y.str();
}

/// The rows just before and just after the first impact (the event's two rows).
std::pair<size_t, size_t> ImpactRows(const Trajectory& tr) {
  for (size_t k = 0; k + 1 < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k + 1]) return {k, k + 1};
  }
  ADD_FAILURE() << "no event rows";
  return {0, 0};
}

struct Case {
  double mA, mB, vA0, vB0, e;
};

class TwoMassImpactTest : public ::testing::TestWithParam<Case> {};

TEST_P(TwoMassImpactTest, ClosedFormMomentumAndEnergy) {
  const Case c = GetParam();
  Built b = testing::BuildYaml(TwoMasses(c.mA, c.mB, c.vA0, c.vB0, c.e));
  Trajectory tr = testing::RunDefault(b);
  auto [before, after] = ImpactRows(tr);
  const double M = c.mA + c.mB, dv = c.vA0 - c.vB0;
  const double vA1 = (c.mA * c.vA0 + c.mB * c.vB0 - c.mB * c.e * dv) / M;
  const double vB1 = (c.mA * c.vA0 + c.mB * c.vB0 + c.mA * c.e * dv) / M;
  // The jump is a linear solve of a few equations: rounding only (1e-12 relative to the speeds).
  const double scale = std::fabs(c.vA0) + std::fabs(c.vB0);
  EXPECT_NEAR(tr.Column("A.v", after), vA1, 1e-12 * scale);
  EXPECT_NEAR(tr.Column("B.v", after), vB1, 1e-12 * scale);
  EXPECT_NEAR(tr.Column("A.v", before), c.vA0, 1e-12 * scale);
  // The impact time: the 0.8 m gap closes at the relative speed (event location to 1e-10 s).
  EXPECT_NEAR(tr.t[after], 0.8 / dv, 1e-10);
  // Momentum conserved to 1e-12 relative.
  double p0 = c.mA * tr.Column("A.v", before) + c.mB * tr.Column("B.v", before);
  double p1 = c.mA * tr.Column("A.v", after) + c.mB * tr.Column("B.v", after);
  EXPECT_NEAR(p1, p0, 1e-12 * (c.mA + c.mB) * scale);
  // Kinetic energy lost: (1 - e^2) mA mB / (2 (mA + mB)) (vA0 - vB0)^2, to 1e-12 relative.
  auto ke = [&](size_t row) {
    return 0.5 * c.mA * std::pow(tr.Column("A.v", row), 2) + 0.5 * c.mB * std::pow(tr.Column("B.v", row), 2);
  };
  double expected_loss = (1 - c.e * c.e) * c.mA * c.mB / (2 * M) * dv * dv;
  EXPECT_NEAR(ke(before) - ke(after), expected_loss, 1e-12 * std::max(1.0, ke(before)));
  // After the impact the bodies separate (or, for e = 0, rest against each other): one impact.
  EXPECT_EQ(tr.stats.impacts, 1);
  if (c.e == 0) EXPECT_NEAR(tr.Column("B.v", tr.t.size() - 1), tr.Column("A.v", tr.t.size() - 1), 1e-12 * scale);
}

INSTANTIATE_TEST_SUITE_P(Cases, TwoMassImpactTest,
                         ::testing::Values(Case{40, 40, 5, 0, 0.8}, Case{1, 3, 2, -1, 1.0},
                                           Case{2, 1, 1, 0, 0.0}, Case{0.5, 7, 3, 0.5, 0.3},
                                           Case{10, 0.1, 1, 0, 0.95}));

TEST(ImpactTest, RodLinkedBodiesActAsOneMass) {
  // B and C joined by a rigid rod: A sees B + C as one body of mass mB + mC.
  const double mA = 2, mB = 1, mC = 3, vA0 = 4, e = 0.6;
  Built b = testing::BuildYaml(R"yaml(
model: RodLinked
components:
  A: {type: Mass, m: 2, L: 0.2, s: {start: 0, fixed: true}, v: {start: 4, fixed: true}}
  B: {type: Mass, m: 1, L: 0.2, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  rod: {type: Rod, L: 0.5}
  C: {type: Mass, m: 3, L: 0.2}
  AB: {type: Impact, e: 0.6}
connections:
  - [A.flange_b, AB.flange_a]
  - [AB.flange_b, B.flange_a]
  - [B.flange_b, rod.flange_a]
  - [rod.flange_b, C.flange_a]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: [A.v, B.v, C.v]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  auto [before, after] = ImpactRows(tr);
  const double M = mB + mC;
  // Rounding only: 1e-12 relative to vA0.
  EXPECT_NEAR(tr.Column("A.v", after), (mA - e * M) * vA0 / (mA + M), 1e-12 * vA0);
  EXPECT_NEAR(tr.Column("B.v", after), mA * (1 + e) * vA0 / (mA + M), 1e-12 * vA0);
  EXPECT_NEAR(tr.Column("C.v", after), tr.Column("B.v", after), 1e-12 * vA0);
}

TEST(ImpactTest, SpringsCarryNoImpulse) {
  // B hangs on a spring from C: at the impact instant only B's mass counts and C does not move.
  const double mA = 1, mB = 2, vA0 = 3, e = 1;
  Built b = testing::BuildYaml(R"yaml(
model: SpringAttached
components:
  A: {type: Mass, m: 1, L: 0.2, s: {start: 0, fixed: true}, v: {start: 3, fixed: true}}
  B: {type: Mass, m: 2, L: 0.2, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  spring: {type: Spring, c: 100, s_rel0: 0.8}
  C: {type: Mass, m: 5, L: 0.2, s: {start: 2, fixed: true}, v: {start: 0, fixed: true}}
  AB: {type: Impact, e: 1}
connections:
  - [A.flange_b, AB.flange_a]
  - [AB.flange_b, B.flange_a]
  - [B.flange_b, spring.flange_a]
  - [spring.flange_b, C.flange_a]
experiment: {stop: 0.3, tolerance: 1e-10, interval: 0.001}
outputs: [A.v, B.v, C.v]
)yaml");
  Trajectory tr = testing::RunDefault(b);
  auto [before, after] = ImpactRows(tr);
  EXPECT_NEAR(tr.Column("A.v", after), (mA - e * mB) * vA0 / (mA + mB), 1e-12 * vA0);
  EXPECT_NEAR(tr.Column("B.v", after), mA * (1 + e) * vA0 / (mA + mB), 1e-12 * vA0);
  EXPECT_NEAR(tr.Column("C.v", after), tr.Column("C.v", before), 1e-12 * vA0);
}

TEST(ImpactTest, CarrierCollisionMatchesTheSeed) {
  Built b = testing::BuildFile("models/carrier_collision.yaml");
  Trajectory tr = testing::RunDefault(b);
  ASSERT_EQ(tr.stats.impacts, 2);
  // The seed's analytic values: vB = 4.5 after the carriers collide, 2.9045454545... after the
  // suitcase hits B's wall (319/109.82...: exactly 2.904545454545 = 31.95/11), within 1e-9
  // relative: the computation is a linear solve, so the only error is rounding.
  const double vB2 = (40 * 4.5 - 15 * 0.3 * 4.5) / 55;  // (mB vB1 - mS eS vB1)/(mB + mS)
  const double vS2 = (40 * 4.5 + 40 * 0.3 * 4.5) / 55;
  size_t last = tr.t.size() - 1;
  EXPECT_NEAR(tr.Column("B.v", last), vB2, 1e-9 * vB2);
  EXPECT_NEAR(tr.Column("B.v", last), 2.9045454545454545, 1e-9 * vB2);
  EXPECT_NEAR(tr.Column("S.v", last), vS2, 1e-9 * vS2);
  EXPECT_NEAR(tr.Column("A.v", last), 0.5, 1e-12);
  // The seed's Collision blocks compute the same velocities algebraically.
  EXPECT_NEAR(tr.Column("suitcase.v_J1", last), tr.Column("B.v", last), 1e-9 * vB2);
  EXPECT_NEAR(tr.Column("carriers.v_K1", last), 4.5, 1e-12);
  // Between the impacts B moves at 4.5 m/s: find a row between the two event pairs.
  std::vector<size_t> event_rows;
  for (size_t k = 0; k + 1 < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k + 1]) event_rows.push_back(k);
  }
  ASSERT_EQ(event_rows.size(), 2u);
  EXPECT_NEAR(tr.Column("B.v", event_rows[0] + 1), 4.5, 1e-12);
  EXPECT_NEAR(tr.t[event_rows[0]], 0.2, 1e-10);                 // 1 m gap at 5 m/s
  EXPECT_NEAR(tr.t[event_rows[1]], 0.2 + 0.3 / 4.5, 1e-10);     // 0.3 m at 4.5 m/s
  // Momentum of the three bodies is conserved throughout (no external force).
  for (size_t k = 0; k < tr.t.size(); ++k) {
    double p = 40 * tr.Column("A.v", k) + 40 * tr.Column("B.v", k) + 15 * tr.Column("S.v", k);
    EXPECT_NEAR(p, 200.0, 1e-12 * 200) << "t = " << tr.t[k];
  }
}

TEST(ImpactTest, CarrierCollisionParametersOverride) {
  // -p eS=1: an elastic suitcase impact gives vB2 = (mB - mS) vB1/(mB + mS).
  Built b = testing::BuildFile("models/carrier_collision.yaml");
  Trajectory tr = testing::RunDefault(b, {{"eS", 1.0}});
  EXPECT_NEAR(tr.Column("B.v", tr.t.size() - 1), 25.0 / 55.0 * 4.5, 1e-12);
}

TEST(ImpactTest, BouncingBallImpactTimesAndZenoEnd) {
  Built b = testing::BuildFile("models/bouncing_ball.yaml");
  Trajectory tr = testing::RunDefault(b);
  const double g = 9.81, h = 1, e = 0.8;
  const double v0 = std::sqrt(2 * g * h), t1 = std::sqrt(2 * h / g);
  // Closed form t_k = t_1 + (2 v0/g)(e + ... + e^(k-1)). Free flight is a parabola, which BDF
  // integrates exactly, so the times are limited by event location (1e-10 s here).
  double tk = t1, vk = v0;
  ASSERT_GE(tr.stats.impact_times.size(), 10u);
  for (size_t k = 0; k < 10; ++k) {
    EXPECT_NEAR(tr.stats.impact_times[k], tk, 1e-10) << "impact " << k + 1;
    vk *= e;
    tk += 2 * vk / g;
  }
  // Zeno: the bounces accumulate at t_inf; the ball arrives slower than v_small = 1 mm/s after
  // ceil(log(v_small/v0)/log(e)) = 38 bounces and rests from then on: 39 impacts in all
  // (the bound on events is the point of the test).
  const double t_inf = t1 + 2 * v0 * e / (g * (1 - e));
  EXPECT_NEAR(t_inf, 4.0637, 1e-4);
  EXPECT_EQ(tr.stats.impacts, 39);
  EXPECT_LT(tr.stats.impact_times.back(), t_inf);
  size_t last = tr.t.size() - 1;
  EXPECT_DOUBLE_EQ(tr.t[last], 6.0);
  EXPECT_NEAR(tr.Column("ball.s", last), 0.0, 1e-9);   // resting on the floor
  EXPECT_EQ(tr.Column("ball.v", last), 0.0);
  EXPECT_NEAR(tr.Column("contact.f", last), -9.81, 1e-9);  // the floor carries the weight
  EXPECT_EQ(tr.Column("contact.contact", last), 1.0);
  EXPECT_EQ(tr.Column("counter.bounces", last), 38.0);
}

TEST(ImpactTest, NewtonsCradlePassesTheImpulseDownTheRow) {
  Built b = testing::BuildFile("models/newtons_cradle.yaml");
  Trajectory tr = testing::RunDefault(b);
  size_t last = tr.t.size() - 1;
  // e = 1: ball 1 stops, ball 5 leaves at v0 (rounding only).
  for (int i = 1; i <= 4; ++i) EXPECT_NEAR(tr.Column("ball[" + std::to_string(i) + "].v", last), 0.0, 1e-12);
  EXPECT_NEAR(tr.Column("ball[5].v", last), 1.0, 1e-12);
  EXPECT_EQ(tr.stats.impacts, 4);
  // e = 0.5: sequential pairs; momentum conserved, energy lost at each of the four impacts.
  Trajectory half = testing::RunDefault(b, {{"e", 0.5}});
  double p = 0, ke = 0;
  for (int i = 1; i <= 5; ++i) {
    double v = half.Column("ball[" + std::to_string(i) + "].v", half.t.size() - 1);
    p += 0.1 * v;
    ke += 0.05 * v * v;
  }
  EXPECT_NEAR(p, 0.1, 1e-13);
  EXPECT_LT(ke, 0.05);
  // Resolution ends when no touching pair approaches: the velocities increase along the row.
  for (int i = 1; i <= 4; ++i) {
    EXPECT_LE(half.Column("ball[" + std::to_string(i) + "].v", half.t.size() - 1),
              half.Column("ball[" + std::to_string(i + 1) + "].v", half.t.size() - 1) + 1e-12);
  }
}

TEST(ImpactTest, EventRowsAreLeftThenRightLimits) {
  Built b = testing::BuildYaml(TwoMasses(1, 1, 1, 0, 1));
  Trajectory tr = testing::RunDefault(b);
  auto [before, after] = ImpactRows(tr);
  EXPECT_EQ(tr.t[before], tr.t[after]);
  EXPECT_EQ(tr.Column("A.v", before), 1.0);  // left limit: still moving
  EXPECT_NEAR(tr.Column("A.v", after), 0.0, 1e-12);  // right limit: stopped
  EXPECT_NEAR(tr.Column("B.v", after), 1.0, 1e-12);
  // Time is nondecreasing and the grid rows go on after the event.
  for (size_t k = 1; k < tr.t.size(); ++k) EXPECT_LE(tr.t[k - 1], tr.t[k]);
  EXPECT_DOUBLE_EQ(tr.t.back(), 1.0);
}

}  // namespace
}  // namespace momenta

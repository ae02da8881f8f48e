// The seed's Example 1, ball and pendulum (models/ball_pendulum_impact.yaml and the MapleSim
// penalty version models/ball_pendulum.yaml; in 3-D with the MSL MultiBody library
// models/ball_pendulum_3d_impact.yaml and models/ball_pendulum_3d.yaml), against the closed form.
//
// Ball A (radius r) falls from rest at (r, 4) beside the cord of pendulum B, a point mass hanging
// L below the pivot (0, 4). The centres are 2r apart when A's centre is r beside the cord, so the
// line of centres from B to A is n = (sin θ, cos θ) with sin θ = 1/2 (θ = 30°) whatever r, and A
// has fallen h = L - √3 r: v0 = sqrt(2 g h). B hangs at rest and its cord is vertical, so the
// cord's impulse is vertical and B leaves horizontally. With the contact impulse P along n on A
// (and -P n on B), momentum of A, horizontal momentum of B and Newton's law along n,
//   mA vA⁺ = mA (0, -v0) + P n,   mB vB⁺ = -P nx,   n·(vA⁺ - vB⁺) = e v0 ny,
// give P = (1 + e) v0 ny / (1/mA + nx²/mB). For e = 1, mA = mB: A leaves at 0.7211 v0, 16.1°
// above the x axis, and B at 0.6928 v0 along -x (the seed's figures). The 3-D models are the same
// scene in the x-y plane of space (A at [r, 4, 0], the joint at [0, 4, 0] turning about z) with the
// MSL's g = 9.80665 (the planar library's is 9.81): nothing acts along z, the ratios are the same.

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kG = 9.81;        // the planar library's
constexpr double kG3d = 9.80665;   // the MSL's World.g

/// Which model of the scene: the planar ones (velocities A.v, B.v) or the 3-D ones (A.v_0, B.v_0).
struct Kind {
  const char* impact;   ///< the exact model
  const char* penalty;  ///< MapleSim's penalty model
  const char* v;        ///< the velocities' name
  double g;
  bool space;
};
constexpr Kind kPlanar = {"models/ball_pendulum_impact.yaml", "models/ball_pendulum.yaml", "v", kG, false};
constexpr Kind kSpace = {"models/ball_pendulum_3d_impact.yaml", "models/ball_pendulum_3d.yaml", "v_0", kG3d, true};
void PrintTo(const Kind& kind, std::ostream* out) { *out << kind.impact; }

struct Velocities {
  double v0;          ///< A's speed just before the impact
  double ax, ay, az;  ///< A's velocity just after, divided by v0 (az 0 in the plane)
  double bx, by, bz;  ///< B's velocity just after, divided by v0
};

Velocities ClosedForm(double r, double L, double mA, double mB, double e, double g = kG) {
  const double nx = 0.5, ny = std::sqrt(3.0) / 2;
  Velocities c{};
  c.v0 = std::sqrt(2 * g * (L - std::sqrt(3.0) * r));
  const double P = (1 + e) * ny / (1 / mA + nx * nx / mB);  // per unit v0
  c.ax = P * nx / mA;
  c.ay = -1 + P * ny / mA;
  c.bx = -P * nx / mB;
  c.by = 0;
  return c;
}

/// The velocities across the rows `before` and `after`.
Velocities Across(const Trajectory& tr, size_t before, size_t after, const Kind& kind) {
  auto at = [&](const char* body, int i, size_t k) {
    if (i == 3 && !kind.space) return 0.0;
    return tr.Column(std::string(body) + "." + kind.v + "[" + std::to_string(i) + "]", k);
  };
  Velocities s;
  s.v0 = std::sqrt(std::pow(at("A", 1, before), 2) + std::pow(at("A", 2, before), 2) + std::pow(at("A", 3, before), 2));
  s.ax = at("A", 1, after) / s.v0, s.ay = at("A", 2, after) / s.v0, s.az = at("A", 3, after) / s.v0;
  s.bx = at("B", 1, after) / s.v0, s.by = at("B", 2, after) / s.v0, s.bz = at("B", 3, after) / s.v0;
  return s;
}

/// The velocities at the impact: its two rows (left and right limits) share a time.
Velocities AtImpact(const Trajectory& tr, const Kind& kind = kPlanar) {
  for (size_t k = 1; k < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k - 1]) return Across(tr, k - 1, k, kind);
  }
  ADD_FAILURE() << "no impact in the run";
  return {};
}

class BallPendulumModels : public ::testing::TestWithParam<Kind> {};

TEST_P(BallPendulumModels, SeedFiguresForAnElasticImpactOfEqualMasses) {
  const Kind kind = GetParam();
  Built b = testing::BuildFile(kind.impact);
  Trajectory tr = testing::RunDefault(b);
  ASSERT_EQ(tr.stats.impacts, 1);
  const Velocities s = AtImpact(tr, kind);
  // v0 follows from free fall; rtol 1e-8 over 0.73 s of a polynomial motion leaves ~1e-12.
  EXPECT_NEAR(s.v0, std::sqrt(2 * kind.g * (3.5 - std::sqrt(3.0) * 0.5)), 1e-9);
  // The seed's rounded figures: 0.7211 v0 at 16.1°, 0.6928 v0 along -x.
  EXPECT_NEAR(std::hypot(s.ax, s.ay), 0.7211, 5e-5);
  EXPECT_NEAR(std::atan2(s.ay, s.ax) * 180 / M_PI, 16.1, 0.05);
  EXPECT_NEAR(s.bx, -0.6928, 5e-5);
  // Exactly: A (2√3/5, 1/5) v0, B (-2√3/5, 0) v0. The jump is a linear solve at the located
  // contact (gap within 1e-10 m), so the ratios hold to ~1e-12; the issue asks for 1e-6.
  EXPECT_NEAR(s.ax, 2 * std::sqrt(3.0) / 5, 1e-9);
  EXPECT_NEAR(s.ay, 0.2, 1e-9);
  EXPECT_NEAR(s.bx, -2 * std::sqrt(3.0) / 5, 1e-9);
  EXPECT_NEAR(s.by, 0, 1e-9);
  EXPECT_EQ(s.az, 0);  // nothing acts along z in space
  EXPECT_EQ(s.bz, 0);
}

INSTANTIATE_TEST_SUITE_P(PlanarAndSpace, BallPendulumModels, ::testing::Values(kPlanar, kSpace),
                         [](const ::testing::TestParamInfo<Kind>& info) { return info.param.space ? "Space" : "Planar"; });

struct Case {
  double e, mA, mB, r;
};

class BallPendulumCases : public ::testing::TestWithParam<Case> {};

TEST_P(BallPendulumCases, VelocityJumpsMatchTheClosedForm) {
  const Case c = GetParam();
  Built b = testing::BuildFile("models/ball_pendulum_impact.yaml");
  Trajectory tr = testing::RunDefault(b, {{"e", c.e}, {"mA", c.mA}, {"mB", c.mB}, {"r", c.r}});
  const Velocities s = AtImpact(tr);
  const Velocities x = ClosedForm(c.r, 3.5, c.mA, c.mB, c.e);
  EXPECT_NEAR(s.v0, x.v0, 1e-9 * x.v0);
  EXPECT_NEAR(s.ax, x.ax, 1e-9);
  EXPECT_NEAR(s.ay, x.ay, 1e-9);
  EXPECT_NEAR(s.bx, x.bx, 1e-9);
  EXPECT_NEAR(s.by, x.by, 1e-9);
  // Momentum along x of both balls is conserved (the cord's impulse is vertical) and the
  // kinetic energy lost is (1 - e²) times that of the normal approach in the reduced mass.
  EXPECT_NEAR(c.mA * s.ax + c.mB * s.bx, 0, 1e-12 * (c.mA + c.mB));
  const double ke_before = 0.5 * c.mA;
  const double ke_after = 0.5 * c.mA * (s.ax * s.ax + s.ay * s.ay) + 0.5 * c.mB * (s.bx * s.bx + s.by * s.by);
  const double ny = std::sqrt(3.0) / 2, m_eff = 1 / (1 / c.mA + 0.25 / c.mB);
  EXPECT_NEAR(ke_before - ke_after, 0.5 * (1 - c.e * c.e) * m_eff * ny * ny, 1e-9);
  // In 3-D: the same closed form (with the MSL's g) and the planar model's ratios.
  Built space = testing::BuildFile(kSpace.impact);
  const Velocities q = AtImpact(testing::RunDefault(space, {{"e", c.e}, {"mA", c.mA}, {"mB", c.mB}, {"r", c.r}}), kSpace);
  EXPECT_NEAR(q.v0, ClosedForm(c.r, 3.5, c.mA, c.mB, c.e, kG3d).v0, 1e-9 * x.v0);
  EXPECT_NEAR(q.ax, s.ax, 1e-9);
  EXPECT_NEAR(q.ay, s.ay, 1e-9);
  EXPECT_NEAR(q.bx, s.bx, 1e-9);
  EXPECT_NEAR(q.by, s.by, 1e-9);
  EXPECT_NEAR(q.ax, x.ax, 1e-9);
  EXPECT_NEAR(q.ay, x.ay, 1e-9);
  EXPECT_NEAR(q.bx, x.bx, 1e-9);
  EXPECT_EQ(q.az, 0);
}

INSTANTIATE_TEST_SUITE_P(RestitutionAndMasses, BallPendulumCases,
                         ::testing::Values(Case{1, 1, 1, 0.5}, Case{0.5, 1, 1, 0.5}, Case{0, 1, 1, 0.5},
                                           Case{1, 2, 1, 0.5}, Case{0.3, 1, 3, 0.4}, Case{0.8, 0.5, 2, 0.25}));

TEST(BallPendulumPenalty, MapleSimContactForceComesCloseToTheClosedForm) {
  // The penalty model: 10 000 N while the centres are within 2r. Its error is the model's, not
  // the solver's: the balls overlap for about a millisecond while B's cord turns and gravity
  // acts, and the force does no work back exactly. Observed at the defaults: |A| 0.72082 v0
  // (exact 0.72111), 15.62° (16.10°), B 0.69391 v0 (0.69282); the bounds below are about twice
  // those deviations.
  Built b = testing::BuildFile("models/ball_pendulum.yaml");
  Trajectory tr = testing::RunDefault(b);
  size_t first = 0, last = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    if (tr.Column("touching.y", k) > 0.5) {
      if (!first) first = k;
      last = k;
    }
  }
  ASSERT_GT(first, 0u);
  const double v0 = std::hypot(tr.Column("A.v[1]", first - 1), tr.Column("A.v[2]", first - 1));
  EXPECT_NEAR(v0, std::sqrt(2 * kG * (3.5 - std::sqrt(3.0) * 0.5)), 1e-6);
  const size_t after = last + 1;
  const double ax = tr.Column("A.v[1]", after) / v0, ay = tr.Column("A.v[2]", after) / v0;
  EXPECT_NEAR(std::hypot(ax, ay), 0.72111, 1e-3);
  EXPECT_NEAR(std::atan2(ay, ax) * 180 / M_PI, 16.10, 1.0);
  EXPECT_NEAR(tr.Column("B.v[1]", after) / v0, -0.69282, 3e-3);
  // Contact lasts about a millisecond (v0 / (F/m) ≈ 0.7 ms per direction).
  EXPECT_LT(tr.t[last] - tr.t[first], 3e-3);
}

/// The penalty run's velocities: v0 on the last row before the force switches on, the others on
/// the first row after it switches off.
Velocities AcrossPenalty(const Trajectory& tr, const Kind& kind) {
  size_t first = 0, last = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    if (tr.Column("touching.y", k) > 0.5) {
      if (!first) first = k;
      last = k;
    }
  }
  if (first == 0 || last + 1 >= tr.t.size()) {
    ADD_FAILURE() << "no contact in the run";
    return {};
  }
  EXPECT_LT(tr.t[last] - tr.t[first], 3e-3);  // about a millisecond, as in the planar model
  return Across(tr, first - 1, last + 1, kind);
}

TEST(BallPendulumPenalty, MapleSimContactForceInSpaceIsWithinOneHundredthOfV0) {
  // The 3-D penalty model: 10 000 N along the line of centres, through a LineForceWithMass and a
  // Force2, while they are within 2r. The issue asks for 0.01 v0 on each velocity component.
  // Observed at the defaults: A (0.69419, 0.19410) v0 (exact (0.69282, 0.2)), B -0.69391 v0
  // (-0.69282). The error grows with the contact time, mA v0 / F: for mA = 2 the force is
  // doubled (at 10 000 N A's y velocity is off by 0.0118 v0, at 20 000 N by 0.0059 v0).
  Built b = testing::BuildFile(kSpace.penalty);
  Built planar = testing::BuildFile(kPlanar.penalty);
  struct Masses {
    double mA, mB, F;
  };
  for (const Masses m : {Masses{1, 1, 1e4}, Masses{2, 1, 2e4}, Masses{1, 3, 1e4}}) {
    const ParameterOverrides p = {{"mA", m.mA}, {"mB", m.mB}, {"F", m.F}};
    const Velocities s = AcrossPenalty(testing::RunDefault(b, p), kSpace);
    const Velocities x = ClosedForm(0.5, 3.5, m.mA, m.mB, 1, kG3d);
    EXPECT_NEAR(s.v0, x.v0, 1e-6);
    EXPECT_NEAR(s.ax, x.ax, 0.01) << "mA " << m.mA << " mB " << m.mB;
    EXPECT_NEAR(s.ay, x.ay, 0.01) << "mA " << m.mA << " mB " << m.mB;
    EXPECT_NEAR(s.bx, x.bx, 0.01) << "mA " << m.mA << " mB " << m.mB;
    EXPECT_NEAR(s.by, x.by, 0.01) << "mA " << m.mA << " mB " << m.mB;
    EXPECT_EQ(s.az, 0);
    // The planar penalty model takes the same force for the same overlap; only g differs, by
    // 1.4e-4 relative, which moves the ratios by about 1e-6 (observed).
    const Velocities q = AcrossPenalty(testing::RunDefault(planar, p), kPlanar);
    EXPECT_NEAR(s.ax, q.ax, 2e-5);
    EXPECT_NEAR(s.ay, q.ay, 2e-5);
    EXPECT_NEAR(s.bx, q.bx, 2e-5);
  }
  // A's probe is the norm of its velocity.
  const Trajectory tr = testing::RunDefault(b);
  const size_t k = tr.t.size() / 2;
  EXPECT_NEAR(tr.Column("speedA.y", k), std::hypot(tr.Column("A.v_0[1]", k), tr.Column("A.v_0[2]", k)), 1e-12);
}

TEST(BallPendulumImpact, BallsThatStartOverlappedAreAnError) {
  // A cord of 0.3 m hangs B 0.58 m from A's start: the circles (2r = 1) overlap from the start,
  // so the contact can never close; the run stops at once with the overlap named.
  Built b = testing::BuildFile("models/ball_pendulum_impact.yaml");
  try {
    testing::RunDefault(b, {{"L", 0.3}});
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("at t = 0: the bodies of contact start overlapped (gap -0.4169"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace momenta

// Exact contact in space (components/multibody_contact.yaml): two free spheres meeting obliquely
// (models/spheres_3d.yaml) against the closed form of a frictionless impact — the velocity
// components along the line of centres at touch-down change by Newton's law of restitution and
// the conservation of momentum, the tangential ones are kept; a ball bouncing on a tilted plane
// (models/ball_on_tilted_plane_3d.yaml) through its Zeno point to rest; simultaneous impacts in a
// Newton's cradle of pendulums (models/newtons_cradle_3d.yaml) and an oblique break of a touching
// cluster (models/billiards_3d.yaml), against momentum and energy.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "solver/simulator.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildFile;
using testing::Built;
using testing::RunDefault;
using testing::Trajectory;
using V3 = std::array<double, 3>;

V3 Add(V3 a, V3 b, double s = 1) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}; }
double Dot(V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 Cross(V3 a, V3 b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double Norm(V3 a) { return std::sqrt(Dot(a, a)); }

/// The vector output `name` (name[1..3]) on row k.
V3 At(const Trajectory& tr, const std::string& name, size_t k) {
  return {tr.Column(name + "[1]", k), tr.Column(name + "[2]", k), tr.Column(name + "[3]", k)};
}

/// The events of a run: the rows of each left limit and right limit (two rows at one time).
std::vector<std::pair<size_t, size_t>> EventRows(const Trajectory& tr) {
  std::vector<std::pair<size_t, size_t>> rows;
  for (size_t k = 1; k < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k - 1]) rows.push_back({k - 1, k});
  }
  return rows;
}

/// Momentum, angular momentum about the origin and kinetic energy of equal point masses m.
struct Totals {
  V3 p{}, l{};
  double ke = 0;
};
Totals TotalsOf(const Trajectory& tr, const std::vector<std::string>& bodies, double m, size_t k,
                bool with_positions = false) {
  Totals s;
  for (const std::string& b : bodies) {
    const V3 v = At(tr, b + ".v_0", k);
    s.p = Add(s.p, v, m);
    if (with_positions) s.l = Add(s.l, Cross(At(tr, b + ".r_0", k), v), m);
    s.ke += 0.5 * m * Dot(v, v);
  }
  return s;
}

struct Scene {
  V3 rA, vA, rB, vB;
  double mA, mB, RA, RB, e;
};

/// Positions and velocities at time t of the closed form (one impact, which the scene makes).
std::array<V3, 4> ClosedForm(const Scene& s, double t) {
  // |dr + dv τ| = RA + RB, the first root.
  const V3 dr = Add(s.rB, s.rA, -1), dv = Add(s.vB, s.vA, -1);
  const double a = Dot(dv, dv), b = 2 * Dot(dr, dv), c = Dot(dr, dr) - std::pow(s.RA + s.RB, 2);
  const double tc = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const V3 rAc = Add(s.rA, s.vA, tc), rBc = Add(s.rB, s.vB, tc);
  V3 n = Add(rBc, rAc, -1);
  const double len = std::sqrt(Dot(n, n));
  for (double& x : n) x /= len;
  const double u = Dot(Add(s.vA, s.vB, -1), n);  // approach speed along n
  const double J = (1 + s.e) * u * s.mA * s.mB / (s.mA + s.mB);
  const V3 vA = Add(s.vA, n, -J / s.mA), vB = Add(s.vB, n, J / s.mB);
  return {Add(rAc, vA, t - tc), vA, Add(rBc, vB, t - tc), vB};
}

TEST(Contact3dTest, ObliqueImpactOfTwoFreeSpheresMatchesTheClosedForm) {
  Built b = BuildFile("models/spheres_3d.yaml");
  struct Case {
    ParameterOverrides p;
    Scene s;
  };
  const Case cases[] = {
      {{}, {{0, 0, 0}, {1, 0, 0}, {2, 0.3, 0.2}, {0, 0, 0}, 1, 1, 0.25, 0.25, 1}},
      {{{"mB", 3}, {"e", 0.6}, {"RB", 0.4}, {"vB0[2]", -0.2}, {"rB0[3]", -0.1}},
       {{0, 0, 0}, {1, 0, 0}, {2, 0.3, -0.1}, {0, -0.2, 0}, 1, 3, 0.25, 0.4, 0.6}},
      {{{"mA", 0.5}, {"e", 0}, {"vA0[3]", 0.3}, {"rA0[2]", 0.1}, {"vB0[1]", -0.5}},
       {{0, 0.1, 0}, {1, 0, 0.3}, {2, 0.3, 0.2}, {-0.5, 0, 0}, 0.5, 1, 0.25, 0.25, 0}},
  };
  for (const Case& c : cases) {
    Trajectory tr = testing::Run(b, OptionsFromExperiment(b.model->experiment), c.p);
    const double t = tr.t.back();
    const auto want = ClosedForm(c.s, t);
    const char* names[4] = {"A.r_0", "A.v_0", "B.r_0", "B.v_0"};
    double worst = 0;
    for (int q = 0; q < 4; ++q) {
      for (int i = 0; i < 3; ++i) {
        const std::string name = std::string(names[q]) + "[" + std::to_string(i + 1) + "]";
        size_t k = 0;
        while (k < tr.names.size() && tr.names[k] != name) ++k;
        ASSERT_LT(k, tr.names.size()) << name;
        worst = std::max(worst, std::fabs(tr.values.back()[k] - want[q][i]));
      }
    }
    // The motion is linear between impacts, which BDF integrates exactly; what remains is the
    // touch-down time, located to IDA's root tolerance: 1e-9 m and m/s.
    EXPECT_LT(worst, 1e-9) << "mB " << c.s.mB << " e " << c.s.e;
  }
}

// A ball on a plane tilted by 0.3 rad (models/ball_on_tilted_plane_3d.yaml): the first bounce at
// the closed form's time, then the intervals between bounces shrink by e each time.
TEST(Contact3dTest, BounceTimesOnATiltedPlaneAreAGeometricSeries) {
  Built b = BuildFile("models/ball_on_tilted_plane_3d.yaml");
  for (double e : {0.8, 0.5}) {
    Trajectory tr = testing::Run(b, OptionsFromExperiment(b.model->experiment), {{"e", e}});
    std::vector<double> bounces;  // an event is two rows at one time
    for (size_t k = 1; k < tr.t.size(); ++k) {
      if (tr.t[k] == tr.t[k - 1]) bounces.push_back(tr.t[k]);
    }
    ASSERT_GE(bounces.size(), 3u);
    const double theta = 0.3, g = 9.80665, gn = g * std::cos(theta);
    const double d0 = std::cos(theta) * 1 - 0.1, vn0 = -std::sin(theta) * 0.5;  // gap and normal speed at 0
    const double t1 = (vn0 + std::sqrt(vn0 * vn0 + 2 * gn * d0)) / gn;
    EXPECT_NEAR(bounces[0], t1, 1e-9);
    // Each bounce is located to about 1e-10 s; a ratio of intervals down to 0.05 s carries a few
    // 1e-9 of that: 1e-7.
    for (size_t k = 2; k < bounces.size(); ++k) {
      EXPECT_NEAR((bounces[k] - bounces[k - 1]) / (bounces[k - 1] - bounces[k - 2]), e, 1e-7) << "bounce " << k;
    }
  }
}

// A ball bouncing on the tilted plane with e < 1: the bounces accumulate at
// t_inf = t1 + (t2 - t1)/(1 - e) (Zeno); the run goes on past it with the ball resting on the plane
// and sliding down it without friction. Normal to the plane it is a bouncing ball under
// g cos(theta); along the plane no impulse acts, so the tangential velocity is v0_t + g_t t and the
// position r0_t + v0_t t + g_t t^2/2 whatever the bounces, and at rest the centre is `radius` above
// the plane and the plane carries the normal component of the weight.
TEST(Contact3dTest, BallOnATiltedPlaneRunsThroughItsZenoPointToRest) {
  // The model's outputs with the ball's motion and the contact's state added.
  std::string yaml = testing::ReadText(testing::SourcePath("models/ball_on_tilted_plane_3d.yaml"));
  const std::string outputs = "outputs: [plane.d, plane.v_n]";
  ASSERT_NE(yaml.find(outputs), std::string::npos);
  yaml.replace(yaml.find(outputs), outputs.size(), "outputs: [plane.d, plane.v_n, plane.f, plane.contact, ball.r_0, ball.v_0]");
  Built b = testing::BuildYaml(yaml);
  const double e = 0.5, stop = 3;
  SimulationOptions options = OptionsFromExperiment(b.model->experiment);
  options.stop = stop;
  Trajectory tr = testing::Run(b, options, {{"e", e}});

  // The closed form: gap d0 and normal speed vn0 at 0, the first touch t1, the second t2.
  const double theta = 0.3, g = 9.80665, gn = g * std::cos(theta), radius = 0.1;
  const double d0 = std::cos(theta) * 1 - radius, vn0 = -std::sin(theta) * 0.5;
  const double t1 = (vn0 + std::sqrt(vn0 * vn0 + 2 * gn * d0)) / gn;
  const double t2 = t1 + 2 * e * (gn * t1 - vn0) / gn;
  const double t_inf = t1 + (t2 - t1) / (1 - e);
  ASSERT_LT(t_inf, stop - 1);
  // A finite number of bounces, the last just before t_inf: a bounce whose approach speed is
  // below v_small (1e-3 m/s) ends in rest, and from a bounce at u the series has 2 e u/(gn (1 - e))
  // left, under 4.3e-4 s here.
  ASSERT_GE(tr.stats.impact_times.size(), 5u);
  EXPECT_LT(tr.stats.impacts, 40);
  EXPECT_NEAR(tr.stats.impact_times[0], t1, 1e-9);
  EXPECT_NEAR(tr.stats.impact_times[1], t2, 1e-8);
  EXPECT_LT(tr.stats.impact_times.back(), t_inf);
  EXPECT_GT(tr.stats.impact_times.back(), t_inf - 4.3e-4);

  // At the stop time, long after t_inf: resting on the plane, the weight's normal part carried.
  const size_t last = tr.t.size() - 1;
  ASSERT_DOUBLE_EQ(tr.t[last], stop);
  EXPECT_EQ(tr.Column("plane.contact", last), 1.0);
  EXPECT_NEAR(tr.Column("plane.d", last), radius, 1e-9);
  EXPECT_NEAR(tr.Column("plane.v_n", last), 0, 1e-9);
  EXPECT_NEAR(tr.Column("plane.f", last), -gn, 1e-9);
  // ... and sliding down it: gravity along the plane g_t = g - (g.n) n, from r0 = [0, 1, 0] and
  // v0 = [0.5, 0, 0.2]. Rtol 1e-8 over 3 s of motion polynomial between events: 1e-7.
  const double s = std::sin(theta), c = std::cos(theta);
  const V3 n = {-s, c, 0}, gv = {0, -g, 0}, r0 = {0, 1, 0}, v0 = {0.5, 0, 0.2};
  const V3 g_t = Add(gv, n, -Dot(gv, n)), v0_t = Add(v0, n, -Dot(v0, n)), r0_t = Add(r0, n, -Dot(r0, n));
  const V3 v_end = Add(v0_t, g_t, stop);
  const V3 r_end = Add(Add(Add(r0_t, v0_t, stop), g_t, stop * stop / 2), n, radius);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(At(tr, "ball.v_0", last)[i], v_end[i], 1e-7) << i;
    EXPECT_NEAR(At(tr, "ball.r_0", last)[i], r_end[i], 1e-7) << i;
  }
}

// Newton's cradle of five pendulums in a row turned about the vertical: ball 1, released from
// phi0 = -0.5 rad, strikes the row at the bottom of its swing; the four contacts close at one
// instant. The cords are vertical there and take no horizontal impulse: momentum and kinetic
// energy are conserved by every event, ball 1 stops and ball 5 leaves along the row at ball 1's
// speed; ball 5 swings back and the impulse runs the other way.
TEST(Contact3dTest, NewtonsCradleInSpacePassesTheImpulseDownTheRow) {
  Built b = BuildFile("models/newtons_cradle_3d.yaml");
  const std::vector<std::string> balls = {"ball[1]", "ball[2]", "ball[3]", "ball[4]", "ball[5]"};
  const double m = 0.1, L = 0.3, a = 0.6, g = 9.80665;
  Trajectory tr = RunDefault(b);
  const auto events = EventRows(tr);
  ASSERT_EQ(events.size(), 3u);  // 1 -> 5, 5 -> 1, 1 -> 5 in 1.5 s (half a period is 0.558 s)
  EXPECT_EQ(tr.stats.impacts, 12);
  const double v0 = std::sqrt(2 * g * L * (1 - std::cos(0.5)));
  const V3 u = {std::cos(a), 0, std::sin(a)};  // along the row
  for (size_t k = 0; k < events.size(); ++k) {
    const auto [before, after] = events[k];
    const Totals x = TotalsOf(tr, balls, m, before), y = TotalsOf(tr, balls, m, after);
    // Each impulse is a linear solve at the located contact: the totals hold to rounding.
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(y.p[i], x.p[i], 1e-12 * m * v0) << "event " << k << " p[" << i << "]";
    EXPECT_NEAR(y.ke, x.ke, 1e-12 * x.ke) << "event " << k;
    // The striking ball stops, the one at the far end leaves with its velocity, along the row.
    const std::string& from = balls[k % 2 == 0 ? 0 : 4];
    const std::string& to = balls[k % 2 == 0 ? 4 : 0];
    const V3 v_in = At(tr, from + ".v_0", before), v_out = At(tr, to + ".v_0", after);
    EXPECT_NEAR(Norm(v_in), v0, 1e-8 * v0) << "event " << k;  // the swing, to rtol 1e-10
    EXPECT_NEAR(std::fabs(Dot(v_in, u)), Norm(v_in), 1e-12) << "event " << k;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(v_out[i], v_in[i], 1e-12) << "event " << k;
    for (const std::string& ball : balls) {
      if (ball != to) EXPECT_LT(Norm(At(tr, ball + ".v_0", after)), 1e-12) << ball << " event " << k;
    }
  }
  // e = 0.5: the first event shares the velocity out along the row (momentum kept, energy lost)
  // and ends when no touching pair approaches: the speeds along the row increase towards ball 5.
  Trajectory half = RunDefault(b, {{"e", 0.5}});
  const auto [before, after] = EventRows(half).at(0);
  const Totals x = TotalsOf(half, balls, m, before), y = TotalsOf(half, balls, m, after);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(y.p[i], x.p[i], 1e-12 * m * v0) << i;
  EXPECT_LT(y.ke, 0.5 * x.ke);
  for (size_t i = 0; i + 1 < balls.size(); ++i) {
    EXPECT_LE(Dot(At(half, balls[i] + ".v_0", after), u), Dot(At(half, balls[i + 1] + ".v_0", after), u) + 1e-12) << i;
  }
}

// The break in space: the cue ball strikes the apex of a touching tetrahedron of four balls off
// its axis in y and z. Every impulse is along a line of centres between free bodies, so each
// event keeps the momentum and the angular momentum about any point, and with e = 1 the kinetic
// energy; no balls interpenetrate at any row.
TEST(Contact3dTest, ObliqueBreakOfATouchingClusterKeepsMomentumAndEnergy) {
  Built b = BuildFile("models/billiards_3d.yaml");
  const std::vector<std::string> balls = {"A", "P[1]", "P[2]", "P[3]", "P[4]"};
  const double m = 0.17, v0 = 2, R = 0.03;
  for (const double e : {1.0, 0.5}) {
    Trajectory tr = RunDefault(b, {{"e", e}, {"e_cue", e == 1 ? 1.0 : 0.8}});
    const auto events = EventRows(tr);
    ASSERT_GE(events.size(), 1u);
    EXPECT_GE(tr.stats.impacts, 4) << "e " << e;  // the cue, then the apex against the base
    for (const auto& [before, after] : events) {
      const Totals x = TotalsOf(tr, balls, m, before, true), y = TotalsOf(tr, balls, m, after, true);
      // Rounding in a linear solve per impulse: 1e-12 of m v0 (and of m v0 times the 0.5 m lever).
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(y.p[i], x.p[i], 1e-12 * m * v0) << "e " << e << " p[" << i << "]";
        EXPECT_NEAR(y.l[i], x.l[i], 1e-12 * m * v0) << "e " << e << " l[" << i << "]";
      }
      if (e == 1) {
        EXPECT_NEAR(y.ke, x.ke, 1e-12 * x.ke);
      } else {
        EXPECT_LT(y.ke, x.ke);
      }
    }
    // Every pair stays at least 2R apart (contacts are located to 1e-10 m).
    for (size_t k = 0; k < tr.t.size(); ++k) {
      for (size_t i = 0; i < balls.size(); ++i) {
        for (size_t j = i + 1; j < balls.size(); ++j) {
          const double d = Norm(Add(At(tr, balls[j] + ".r_0", k), At(tr, balls[i] + ".r_0", k), -1));
          ASSERT_GE(d, 2 * R - 1e-9) << balls[i] << " " << balls[j] << " at t = " << tr.t[k];
        }
      }
    }
  }
}

}  // namespace
}  // namespace momenta

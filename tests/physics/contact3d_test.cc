// Exact contact in space (components/multibody_contact.yaml): two free spheres meeting obliquely
// (models/spheres_3d.yaml) against the closed form of a frictionless impact — the velocity
// components along the line of centres at touch-down change by Newton's law of restitution and
// the conservation of momentum, the tangential ones are kept.

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "solver/simulator.h"
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

}  // namespace
}  // namespace momenta

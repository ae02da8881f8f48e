// Planar multibody scenes on components/planar.yaml, each a model in models/ checked against an
// independent solution: a double pendulum (energy over 20 s, small-amplitude normal modes), a
// slider-crank closed loop (slider kinematics against the crank angle, work of the torque against
// the energy gained), billiards (oblique impacts against Newton's law, momentum and energy) and a
// ball bouncing down a staircase (impact times and velocities against the projectile's closed
// form); and the messages momenta gives for two bad planar models.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kG = 9.81;

std::string ReadSource(const std::string& relative) {
  std::ifstream in(testing::SourcePath(relative));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// text with the one occurrence of `from` replaced by `to` (a test failure when it is absent).
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The event rows: pairs (left limit, right limit) at equal times.
std::vector<std::pair<size_t, size_t>> EventRows(const Trajectory& tr) {
  std::vector<std::pair<size_t, size_t>> rows;
  for (size_t k = 0; k + 1 < tr.t.size(); ++k) {
    if (tr.t[k] == tr.t[k + 1]) rows.emplace_back(k, k + 1);
  }
  return rows;
}

// ---------------------------------------------------------------------------------------------
// 1. Double pendulum

constexpr double kL1 = 1, kL2 = 0.8, kM1 = 1, kM2 = 0.6, kI1 = 0.02, kI2 = 0.01;

double PendulumEnergy(const Trajectory& tr, size_t k) {
  auto c = [&](const char* name) { return tr.Column(name, k); };
  return 0.5 * kM1 * (std::pow(c("body1.v[1]"), 2) + std::pow(c("body1.v[2]"), 2)) + 0.5 * kI1 * std::pow(c("body1.w"), 2) +
         0.5 * kM2 * (std::pow(c("body2.v[1]"), 2) + std::pow(c("body2.v[2]"), 2)) + 0.5 * kI2 * std::pow(c("body2.w"), 2) +
         kG * (kM1 * c("body1.r[2]") + kM2 * c("body2.r[2]"));
}

// Released at rest from 90 degrees (chaotic): the energy, computed here from the bodies' velocities,
// angular velocities and heights, stays at its start value 0 over 20 s.
TEST(PlanarScenes, DoublePendulumConservesEnergy) {
  Built b = testing::BuildFile("models/double_pendulum.yaml");
  EXPECT_EQ(b.report.states.size(), 4u);
  Trajectory tr = testing::RunDefault(b);
  ASSERT_DOUBLE_EQ(tr.t.back(), 20.0);
  const double e0 = PendulumEnergy(tr, 0);
  EXPECT_NEAR(e0, 0.0, 1e-14);
  double worst = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) worst = std::max(worst, std::fabs(PendulumEnergy(tr, k) - e0));
  // Energy scale (m1 + m2) g L1 + m2 g L2 = 20.4 J; at rtol 1e-10 the drift over 20 s (about 15
  // swings, body 2 turning over, chaotic) stays within 5e-8 of it: observed 7.7e-7 J with IDA's
  // error test on the four states (9 537 steps), 2e-8 J with every unknown tested (35 921 steps).
  EXPECT_LT(worst, 1e-6) << "worst energy error " << worst;
  // The bars keep their lengths: body 1 at L1 from the origin, body 2 at L2 from body 1.
  for (size_t k = 0; k < tr.t.size(); k += 50) {
    const double x1 = tr.Column("body1.r[1]", k), y1 = tr.Column("body1.r[2]", k);
    EXPECT_NEAR(std::hypot(x1, y1), kL1, 1e-9);
    EXPECT_NEAR(std::hypot(tr.Column("body2.r[1]", k) - x1, tr.Column("body2.r[2]", k) - y1), kL2, 1e-9);
  }
}

// Linearised about the bottom, in the absolute angles th1, th2 of the bars:
//   M th'' + K th = 0, M = [(m1 + m2) L1^2 + I1, m2 L1 L2; m2 L1 L2, m2 L2^2 + I2],
//   K = diag((m1 + m2) g L1, m2 g L2);
// started in a mode shape u (K u = w^2 M u) the pendulum swings in that mode alone at w.
TEST(PlanarScenes, DoublePendulumNormalModes) {
  const double a = (kM1 + kM2) * kL1 * kL1 + kI1, c = kM2 * kL1 * kL2, d = kM2 * kL2 * kL2 + kI2;
  const double k1 = (kM1 + kM2) * kG * kL1, k2 = kM2 * kG * kL2;
  const double qa = a * d - c * c, qb = -(a * k2 + d * k1), qc = k1 * k2;
  const double disc = std::sqrt(qb * qb - 4 * qa * qc);
  Built b = testing::BuildFile("models/double_pendulum.yaml");
  for (double lambda : {(-qb - disc) / (2 * qa), (-qb + disc) / (2 * qa)}) {
    const double omega = std::sqrt(lambda), period = 2 * M_PI / omega;
    // Mode shape: (k1 - lambda a) u1 = lambda c u2; amplitude 1e-3 rad keeps the nonlinear
    // correction to the frequency near 1e-7.
    double u1 = lambda * c, u2 = k1 - lambda * a;
    const double scale = 1e-3 / std::max(std::fabs(u1), std::fabs(u2));
    u1 *= scale;
    u2 *= scale;
    SimulationOptions o;
    o.stop = 10 * period;
    o.interval = period / 2000;
    o.rtol = 1e-10;
    Trajectory tr = testing::Run(b, o, {{"theta1", u1}, {"theta2", u2 - u1}});
    // Downward zero crossings of joint 1's angle, interpolated linearly.
    std::vector<double> ts;
    const size_t i1 = tr.Index("joint1.phi"), i2 = tr.Index("joint2.phi");
    double worst_shape = 0;
    for (size_t k = 1; k < tr.t.size(); ++k) {
      const double p = tr.values[k - 1][i1], q = tr.values[k][i1];
      if (p > 0 && q <= 0) ts.push_back(tr.t[k - 1] + (tr.t[k] - tr.t[k - 1]) * p / (p - q));
      // In a mode the two angles stay proportional: th2 = (u2/u1) th1.
      const double th1 = tr.values[k][i1], th2 = th1 + tr.values[k][i2];
      worst_shape = std::max(worst_shape, std::fabs(th2 * u1 - th1 * u2) / (1e-3 * 1e-3));
    }
    ASSERT_GE(ts.size(), 9u);
    const double measured = (ts.back() - ts.front()) / static_cast<double>(ts.size() - 1);
    EXPECT_NEAR(measured / period, 1.0, 2e-6) << "mode at " << omega << " rad/s";
    // The other mode stays unexcited: the shape holds to the nonlinear terms (amplitude^2).
    EXPECT_LT(worst_shape, 1e-3) << "mode at " << omega << " rad/s";
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Slider-crank

constexpr double kR = 0.1, kL = 0.35;

double SliderX(double th) { return kR * std::cos(th) + std::sqrt(kL * kL - std::pow(kR * std::sin(th), 2)); }
double SliderV(double th, double w) {
  const double s = std::sin(th), co = std::cos(th);
  return -kR * s * w - kR * kR * s * co * w / std::sqrt(kL * kL - std::pow(kR * s, 2));
}

// The model driven at a constant crank speed (an exact Rotational.Speed instead of the torque):
// the slider's position and velocity follow the crank angle and speed by the closed form.
TEST(PlanarScenes, SliderCrankKinematicsAtConstantSpeed) {
  std::string yaml = ReadSource("models/slider_crank.yaml");
  yaml = Replace(yaml, "  drive: {type: ConstantTorque, tau_constant: tau}",
                 "  drive: {type: Rotational.Speed, exact: true}\n  speed: {type: Constant, k: 5}");
  yaml = Replace(yaml, "  crank: {type: Revolute, phi: {start: theta0, fixed: true}, w: {start: w0, fixed: true}}",
                 "  crank: {type: Revolute}");
  yaml = Replace(yaml, "  - [drive.flange, crank.flange_a]", "  - [drive.flange, crank.flange_a]\n  - [speed.y, drive.w_ref]");
  yaml = Replace(yaml, "tolerance: 1e-6", "tolerance: 1e-10");
  Built b = testing::BuildYaml(yaml);
  Trajectory tr = testing::RunDefault(b);
  ASSERT_DOUBLE_EQ(tr.t.back(), 5.0);
  double worst_x = 0, worst_v = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double th = tr.Column("crank.phi", k);
    EXPECT_NEAR(th, 5 * tr.t[k], 1e-9);
    EXPECT_NEAR(tr.Column("crank.w", k), 5, 1e-12);
    worst_x = std::max(worst_x, std::fabs(tr.Column("guide.s", k) - SliderX(th)));
    worst_v = std::max(worst_v, std::fabs(tr.Column("guide.v", k) - SliderV(th, 5)));
  }
  // Four turns of the crank; x in 0.25 .. 0.45 m, v up to 0.53 m/s.
  EXPECT_LT(worst_x, 1e-10) << worst_x;
  EXPECT_LT(worst_v, 5e-9) << worst_v;  // observed 1.2e-9 (rows from IDA's interpolant)
}

/// The slider-crank with its torque drive: the largest errors of the energy balance (the torque's
/// work is the energy gained) and of the slider's closed-form kinematics over a run.
struct SliderCrankErrors {
  double balance = 0, x = 0, v = 0, th_min = 0, th_max = 0, work_max = 0;
};

SliderCrankErrors CheckSliderCrank(const Trajectory& tr) {
  const double mc = 0.5, mr = 0.3, ms = 0.4, tau = 0.2;
  auto c = [&](const std::string& n, size_t k) { return tr.Column(n, k); };
  auto energy = [&](size_t k) {
    double e = 0.5 * mc * (std::pow(c("crankBody.v[1]", k), 2) + std::pow(c("crankBody.v[2]", k), 2)) +
               0.5 * mc * kR * kR / 12 * std::pow(c("crankBody.w", k), 2) +
               0.5 * mr * (std::pow(c("rodBody.v[1]", k), 2) + std::pow(c("rodBody.v[2]", k), 2)) +
               0.5 * mr * kL * kL / 12 * std::pow(c("rodBody.w", k), 2) +
               0.5 * ms * (std::pow(c("slider.v[1]", k), 2) + std::pow(c("slider.v[2]", k), 2));
    return e + kG * (mc * c("crankBody.r[2]", k) + mr * c("rodBody.r[2]", k));  // the slider stays at y = 0
  };
  const double e0 = energy(0);
  SliderCrankErrors err;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double th = c("crank.phi", k), work = tau * th;
    err.th_min = std::min(err.th_min, th);
    err.th_max = std::max(err.th_max, th);
    err.work_max = std::max(err.work_max, std::fabs(work));
    err.balance = std::max(err.balance, std::fabs(energy(k) - e0 - work));
    err.x = std::max(err.x, std::fabs(c("guide.s", k) - SliderX(th)));
    err.v = std::max(err.v, std::fabs(c("guide.v", k) - SliderV(th, c("crank.w", k))));
  }
  return err;
}

// Driven by the constant torque from rest at the dead centre, against gravity: the kinematics
// hold whatever drives the crank, and the torque's work is the energy gained, at the model's
// rtol 1e-6 (see its experiment).
TEST(PlanarScenes, SliderCrankTorqueWorkIsEnergyGained) {
  Built b = testing::BuildFile("models/slider_crank.yaml");
  EXPECT_EQ(b.report.states, (std::vector<std::string>{"crank.phi", "crank.w"}));
  Trajectory tr = testing::RunDefault(b);
  ASSERT_DOUBLE_EQ(tr.t.back(), 5.0);
  const SliderCrankErrors err = CheckSliderCrank(tr);
  std::cout << "slider-crank: crank angle " << err.th_min << " .. " << err.th_max << " rad, energy balance error "
            << err.balance << " J, x error " << err.x << " m, v error " << err.v << " m/s\n";
  // Gravity on the crank (mc g R/2 = 0.245 N m) outweighs the torque at first: the crank swings.
  EXPECT_LT(err.th_min, -0.5);
  // |work| up to 0.37 J; at rtol 1e-6 the balance holds to 1e-5 J (observed 1.9e-6 J).
  EXPECT_LT(err.balance, 1e-5) << "largest |work| " << err.work_max;
  // The loop closure holds to the local error of rtol 1e-6 (observed 6.2e-9 m and 3.1e-7 m/s).
  EXPECT_LT(err.x, 5e-8);
  EXPECT_LT(err.v, 5e-6);
}

// The same at rtol 1e-8 and 1e-10. These stopped with IDA_CONV_FAIL (at t = 0.92 and 0.044):
// der(wrist.phi) and der(crank.phi) entered the differentiated loop constraints as y' of IDA,
// squared; see tests/physics/tight_tolerance_test.cc. Now the runs finish without a failed step,
// and the balance and the closure tighten with the tolerance.
TEST(PlanarScenes, SliderCrankAtTightTolerances) {
  Built b = testing::BuildFile("models/slider_crank.yaml");
  // rtol, bounds on the balance [J], x [m] and v [m/s], most steps.
  const struct {
    double rtol, balance, x, v;
    long steps;
  } cases[] = {{1e-8, 3e-7, 5e-10, 5e-8, 12000}, {1e-10, 2e-9, 5e-12, 5e-10, 25000}};
  for (const auto& c : cases) {
    SCOPED_TRACE("rtol " + std::to_string(c.rtol));
    SimulationOptions o = OptionsFromExperiment(b.model->experiment);
    o.rtol = c.rtol;
    Trajectory tr = testing::Run(b, o);
    ASSERT_DOUBLE_EQ(tr.t.back(), 5.0);
    EXPECT_LT(tr.stats.steps, c.steps);
    EXPECT_LT(tr.stats.nonlinear_failures, 150);  // recovered by a fresh Jacobian (observed 19, 52)
    const SliderCrankErrors err = CheckSliderCrank(tr);
    std::cout << "slider-crank at rtol " << c.rtol << ": " << tr.stats.steps << " steps, energy balance error "
              << err.balance << " J, x error " << err.x << " m, v error " << err.v << " m/s\n";
    EXPECT_LT(err.th_min, -0.5);
    EXPECT_LT(err.balance, c.balance);
    EXPECT_LT(err.x, c.x);
    EXPECT_LT(err.v, c.v);
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Billiards

struct Ball {
  double x, y, vx, vy, m;
};

/// Time until balls a and b (moving in straight lines) touch at distance 2R, or -1.
double TimeToTouch(const Ball& a, const Ball& b, double R) {
  const double dx = b.x - a.x, dy = b.y - a.y, dvx = b.vx - a.vx, dvy = b.vy - a.vy;
  const double qa = dvx * dvx + dvy * dvy, qb = 2 * (dx * dvx + dy * dvy), qc = dx * dx + dy * dy - 4 * R * R;
  const double disc = qb * qb - 4 * qa * qc;
  if (qa == 0 || disc < 0) return -1;
  const double t = (-qb - std::sqrt(disc)) / (2 * qa);
  return t > 0 ? t : -1;
}

void Advance(std::vector<Ball>* balls, double dt) {
  for (Ball& b : *balls) {
    b.x += b.vx * dt;
    b.y += b.vy * dt;
  }
}

/// Frictionless impact: the normal components by Newton's law and momentum, the tangential kept.
void Collide(Ball* a, Ball* b, double e) {
  const double d = std::hypot(b->x - a->x, b->y - a->y), nx = (b->x - a->x) / d, ny = (b->y - a->y) / d;
  const double vn = (b->vx - a->vx) * nx + (b->vy - a->vy) * ny;
  const double j = -(1 + e) * vn / (1 / a->m + 1 / b->m);
  a->vx -= j / a->m * nx;
  a->vy -= j / a->m * ny;
  b->vx += j / b->m * nx;
  b->vy += j / b->m * ny;
}

TEST(PlanarScenes, BilliardsObliqueImpacts) {
  const double R = 0.03, m = 0.17, v0 = 2, eAB = 1, eAC = 0.8;
  Built b = testing::BuildFile("models/billiards.yaml");
  Trajectory tr = testing::RunDefault(b);
  ASSERT_DOUBLE_EQ(tr.t.back(), 1.0);
  ASSERT_EQ(tr.stats.impacts, 2);
  auto events = EventRows(tr);
  ASSERT_EQ(events.size(), 2u);
  // The closed form: straight lines between the impacts.
  std::vector<Ball> ref = {{0, 0, v0, 0, m}, {0.5, 0.03, 0, 0, m}, {0.7, -0.33, 0, 0, m}};
  const char* names[] = {"A", "B", "C"};
  auto ball = [&](size_t row, int i) {
    const std::string n = names[i];
    return Ball{tr.Column(n + ".r[1]", row), tr.Column(n + ".r[2]", row), tr.Column(n + ".v[1]", row),
                tr.Column(n + ".v[2]", row), m};
  };
  const int partner[] = {1, 2};
  const double restitution[] = {eAB, eAC};
  double t_ref = 0;
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "A strikes B (e = 1)" : "A strikes C (e = 0.8)");
    const double dt = TimeToTouch(ref[0], ref[partner[k]], R);
    ASSERT_GT(dt, 0);
    Advance(&ref, dt);
    t_ref += dt;
    auto [before, after] = events[k];
    EXPECT_NEAR(tr.t[after], t_ref, 1e-10);
    // Left limits: the balls where the straight lines put them, touching.
    for (int i = 0; i < 3; ++i) {
      Ball s = ball(before, i);
      EXPECT_NEAR(s.x, ref[i].x, 1e-9) << names[i];
      EXPECT_NEAR(s.y, ref[i].y, 1e-9) << names[i];
      EXPECT_NEAR(s.vx, ref[i].vx, 1e-12 * v0) << names[i];
      EXPECT_NEAR(s.vy, ref[i].vy, 1e-12 * v0) << names[i];
    }
    const Ball a0 = ball(before, 0), p0 = ball(before, partner[k]);
    const Ball a1 = ball(after, 0), p1 = ball(after, partner[k]);
    EXPECT_NEAR(std::hypot(p0.x - a0.x, p0.y - a0.y), 2 * R, 1e-10);
    // Newton's law along the line of centres n, the tangential components unchanged (from the
    // simulated left limits, so the check is of the impact alone).
    const double nx = (p0.x - a0.x) / (2 * R), ny = (p0.y - a0.y) / (2 * R);
    const double vn0 = (p0.vx - a0.vx) * nx + (p0.vy - a0.vy) * ny, vn1 = (p1.vx - a1.vx) * nx + (p1.vy - a1.vy) * ny;
    EXPECT_LT(vn0, -0.3);  // an oblique, not a grazing, blow (1.73 and 0.46 m/s)
    EXPECT_NEAR(vn1, -restitution[k] * vn0, 1e-12 * v0);
    EXPECT_NEAR(a1.vx * -ny + a1.vy * nx, a0.vx * -ny + a0.vy * nx, 1e-12 * v0);
    EXPECT_NEAR(p1.vx * -ny + p1.vy * nx, p0.vx * -ny + p0.vy * nx, 1e-12 * v0);
    // Momentum of the three free bodies, to 1e-12 relative.
    double px0 = 0, py0 = 0, px1 = 0, py1 = 0, ke0 = 0, ke1 = 0;
    for (int i = 0; i < 3; ++i) {
      Ball s0 = ball(before, i), s1 = ball(after, i);
      px0 += m * s0.vx, py0 += m * s0.vy, px1 += m * s1.vx, py1 += m * s1.vy;
      ke0 += 0.5 * m * (s0.vx * s0.vx + s0.vy * s0.vy);
      ke1 += 0.5 * m * (s1.vx * s1.vx + s1.vy * s1.vy);
      // No spin: no impulse has a moment about a centre.
      EXPECT_EQ(tr.Column(std::string(names[i]) + ".w", after), 0.0);
    }
    EXPECT_NEAR(px1, px0, 1e-12 * m * v0);
    EXPECT_NEAR(py1, py0, 1e-12 * m * v0);
    // Energy: kept for e = 1; for e < 1 the loss is (1 - e^2) mu vn^2 / 2 with mu = m/2.
    EXPECT_NEAR(ke0 - ke1, (1 - restitution[k] * restitution[k]) * m / 4 * vn0 * vn0, 1e-12 * ke0);
    // Against the closed form.
    Collide(&ref[0], &ref[partner[k]], restitution[k]);
    for (int i = 0; i < 3; ++i) {
      Ball s = ball(after, i);
      EXPECT_NEAR(s.vx, ref[i].vx, 1e-12 * v0) << names[i];
      EXPECT_NEAR(s.vy, ref[i].vy, 1e-12 * v0) << names[i];
    }
  }
  // Equal masses, e = 1: A and B leave at right angles.
  auto [b1, a1] = events[0];
  (void)b1;
  EXPECT_NEAR(tr.Column("A.v[1]", a1) * tr.Column("B.v[1]", a1) + tr.Column("A.v[2]", a1) * tr.Column("B.v[2]", a1), 0.0,
              1e-12 * v0 * v0);
  // After both impacts: straight lines to the end.
  Advance(&ref, 1.0 - t_ref);
  const size_t last = tr.t.size() - 1;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(ball(last, i).x, ref[i].x, 1e-9) << names[i];
    EXPECT_NEAR(ball(last, i).y, ref[i].y, 1e-9) << names[i];
  }
}

// ---------------------------------------------------------------------------------------------
// 4. Staircase

TEST(PlanarScenes, StaircaseBouncesAgainstTheProjectile) {
  const double r = 0.05, h = 0.2, w = 0.4, e = 0.7;
  Built b = testing::BuildFile("models/staircase.yaml");
  Trajectory tr = testing::RunDefault(b);
  ASSERT_DOUBLE_EQ(tr.t.back(), 2.8);
  // Closed form: parabolas; the next impact is the earliest time at which the centre comes down
  // to r above a step while over it; there v_y -> -e v_y, v_x stays.
  double x = 0.1, y = 0.3, vx = 0.9, vy = 0, t = 0;
  struct Bounce {
    double t, x, vy_before, vy_after;
    int step;
  };
  std::vector<Bounce> ref;
  for (int n = 0; n < 8; ++n) {
    double best = HUGE_VAL;
    int best_step = -1;
    for (int k = 0; k < 6; ++k) {
      // y + vy s - g s^2/2 = -k h + r, descending.
      const double qa = -kG / 2, qb = vy, qc = y - (-k * h + r), disc = qb * qb - 4 * qa * qc;
      if (disc < 0) continue;
      for (double s : {(-qb - std::sqrt(disc)) / (2 * qa), (-qb + std::sqrt(disc)) / (2 * qa)}) {
        const double xs = x + vx * s;
        if (s > 1e-9 && vy - kG * s < 0 && xs >= k * w && xs <= (k + 1) * w && s < best) {
          best = s;
          best_step = k;
        }
      }
    }
    if (best_step < 0 || t + best > 2.8) break;
    t += best;
    x += vx * best;
    y = -best_step * h + r;
    const double vy_before = vy - kG * best;
    vy = -e * vy_before;
    ref.push_back({t, x, vy_before, vy, best_step});
  }
  ASSERT_EQ(ref.size(), 6u);  // one bounce on each step
  for (int k = 0; k < 6; ++k) EXPECT_EQ(ref[k].step, k);
  ASSERT_EQ(tr.stats.impacts, 6);
  auto events = EventRows(tr);
  ASSERT_EQ(events.size(), 6u);
  double worst_t = 0, worst_v = 0;
  for (size_t k = 0; k < ref.size(); ++k) {
    SCOPED_TRACE("bounce " + std::to_string(k + 1));
    auto [before, after] = events[k];
    // Free flight is a parabola, which BDF integrates exactly: the times are limited by event
    // location, the velocities by rounding.
    EXPECT_NEAR(tr.stats.impact_times[k], ref[k].t, 1e-10);
    EXPECT_NEAR(tr.t[after], ref[k].t, 1e-10);
    EXPECT_NEAR(tr.Column("ball.r[1]", after), ref[k].x, 1e-9);
    EXPECT_NEAR(tr.Column("ball.r[2]", after), -ref[k].step * h + r, 1e-9);
    EXPECT_NEAR(tr.Column("ball.v[2]", before), ref[k].vy_before, 1e-9);
    EXPECT_NEAR(tr.Column("ball.v[2]", after), ref[k].vy_after, 1e-9);
    EXPECT_NEAR(tr.Column("ball.v[2]", after), -e * tr.Column("ball.v[2]", before), 1e-12);
    EXPECT_NEAR(tr.Column("ball.v[1]", before), 0.9, 1e-12);
    EXPECT_NEAR(tr.Column("ball.v[1]", after), 0.9, 1e-12);
    worst_t = std::max(worst_t, std::fabs(tr.stats.impact_times[k] - ref[k].t));
    worst_v = std::max(worst_v, std::fabs(tr.Column("ball.v[2]", after) - ref[k].vy_after));
  }
  std::cout << "staircase: worst impact time error " << worst_t << " s, worst v_y+ error " << worst_v << " m/s\n";
}

// ---------------------------------------------------------------------------------------------
// 5. Bad planar models

TEST(PlanarScenes, NegativeInertiaIsRefused) {
  const std::string msg = testing::BuildError(R"(model: Bad
components:
  A: {type: Body, m: 1, I: -1}
outputs: [A.r]
)");
  EXPECT_EQ(msg,
            "test.yaml:3:28: A.I (Planar.Body.I: moment of inertia about the centre of mass (positive when the body "
            "can turn freely) [kg.m2]) = -1 is below its minimum 0");
}

// Two circles that start overlapped (centres 0.5 apart, radii 0.5) are not refused: today the
// overlap, approaching, is taken for a contact closing at once and resolved as an impact at t = 0
// (a swap of velocities for e = 1); separating, they pass on. Recorded here as the behaviour of
// today, not as the desired one.
TEST(PlanarScenes, OverlappedCirclesAtTheStartAreAnError) {
  // Half-overlapped circles: the contact can never close, so the run stops at the start with the
  // contact named (the model itself builds).
  const std::string yaml = R"(model: Overlap
components:
  A: {type: Body, m: 1, I: 0.1, g: [0, 0], r: {start: [0, 0], fixed: true}, v: {start: [1, 0], fixed: true}, phi: {start: 0, fixed: true}, w: {start: 0, fixed: true}}
  B: {type: Body, m: 1, I: 0.1, g: [0, 0], r: {start: [0.5, 0], fixed: true}, v: {start: [0, 0], fixed: true}, phi: {start: 0, fixed: true}, w: {start: 0, fixed: true}}
  AB: {type: CircleContact, ra: 0.5, rb: 0.5, e: 1}
connections:
  - [A.frame_a, AB.frame_a]
  - [B.frame_a, AB.frame_b]
experiment: {stop: 1, interval: 0.1}
outputs: [A.v, B.v, AB.d]
)";
  EXPECT_EQ(testing::BuildError(yaml), "");
  Built b = testing::BuildYaml(yaml);
  try {
    testing::RunDefault(b);
    FAIL() << "no error";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("at t = 0: the bodies of AB start overlapped (gap -0.5)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace momenta

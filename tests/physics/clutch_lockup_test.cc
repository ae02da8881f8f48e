// A clutch that locks when its slip reaches zero, whatever the inertias (components/rotational.yaml,
// Rotational.Clutch; the same decision in Brake, BearingFriction and the translational friction
// elements).
//
// The drive: inertia1 (J1, at flange_a) turns at w0 = 10 rad/s and is driven by a constant
// T = 40 N.m; inertia2 (J2, at flange_b) is at rest. The clutch is fully engaged from the start
// (f_normalized = 1, fn_max = 160 N, mu = 0.5, cgeo = 1 m): it transmits tau0 = 80 N.m while it
// slips and up to 80 N.m while it is stuck. Slipping (w_rel = w2 - w1 < 0, so the friction torque
// accelerates inertia2 and brakes inertia1):
//   w1 = w0 - (tau0 - T) t / J1,   w2 = tau0 t / J2,   until t* = w0 / ((tau0 - T)/J1 + tau0/J2).
// Locked from t* on, both turn together: w = w(t*) + T (t - t*) / (J1 + J2), and the clutch carries
// the torque that accelerates inertia2, J2 T / (J1 + J2) <= T = 40 N.m, half its limit: the locked
// configuration is consistent for every J1, J2, so the clutch must lock and stay locked.
//
// The decision to stay locked is taken on the torque of the locked configuration (the clutch's sa
// while locked), not on the sliding configuration's sa, an acceleration (about tau0/J2 =
// 1 600 rad/s2 behind J2 = 0.05 kg.m2, far beyond 80): compared with the torque limit, that one
// flips the clutch between forward and backward sliding at the instant of lock-up, reported as
// chattering.
//
// Tolerances: the run uses rtol = 1e-10; the motion is piecewise linear in t, so BDF integrates it
// exactly up to rounding and the lock-up instant is located to about 1e-12 s; the speeds are
// compared to 1e-6 rad/s, the locked torque to 1e-6 N.m (observed at most 1.3e-11 rad/s and
// 7e-15 N.m over the sweep; one event and 7 or 8 restarts each). Before the fix, J2 = 0.05 and the
// sweep's small inertias stopped at the lock-up with "chattering".

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/physics_checks.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildClean;
using testing::Trajectory;

constexpr double kW0 = 10, kT = 40, kTau0 = 80;

std::string ClutchDrive(double J1, double J2) {
  return R"(model: ClutchLockUp
parameters: {J1: )" +
         std::to_string(J1) + ", J2: " + std::to_string(J2) + R"(}
components:
  drive: {type: Rotational.ConstantTorque, tau_constant: 40}
  inertia1: {type: Inertia, J: J1, phi: {start: 0, fixed: true}, w: {start: 10, fixed: true}}
  clutch: {type: Clutch, fn_max: 160, mu_pos: [[0, 0.5]], cgeo: 1}
  pressure: {type: Constant, k: 1}
  inertia2: {type: Inertia, J: J2, phi: {start: 0, fixed: true}, w: {start: 0, fixed: true}}
connections:
  - [drive.flange, inertia1.flange_a]
  - [inertia1.flange_b, clutch.flange_a]
  - [clutch.flange_b, inertia2.flange_a]
  - [pressure.y, clutch.f_normalized]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: [inertia1.w, inertia2.w, clutch.tau, clutch.mode]
)";
}

/// Runs the drive and checks it against the closed form above.
void ExpectLockUp(double J1, double J2) {
  SCOPED_TRACE("J1 = " + std::to_string(J1) + ", J2 = " + std::to_string(J2));
  const Trajectory tr = testing::RunDefault(BuildClean(ClutchDrive(J1, J2)));
  const double t_lock = kW0 / ((kTau0 - kT) / J1 + kTau0 / J2);
  const double w_lock = kTau0 * t_lock / J2;
  auto w1 = [&](double t) { return t < t_lock ? kW0 - (kTau0 - kT) * t / J1 : w_lock + kT * (t - t_lock) / (J1 + J2); };
  auto w2 = [&](double t) { return t < t_lock ? kTau0 * t / J2 : w_lock + kT * (t - t_lock) / (J1 + J2); };
  double worst_w = 0, worst_tau = 0;
  bool locked_at_end = false;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    // Rows at the lock-up instant itself hold its left and right limits: skip the instant.
    if (std::abs(t - t_lock) < 1e-9) continue;
    worst_w = std::max(worst_w, std::abs(tr.Column("inertia1.w", k) - w1(t)));
    worst_w = std::max(worst_w, std::abs(tr.Column("inertia2.w", k) - w2(t)));
    if (t > t_lock) {
      worst_tau = std::max(worst_tau, std::abs(tr.Column("clutch.tau", k) - (-J2 * kT / (J1 + J2))));
      locked_at_end = tr.Column("clutch.mode", k) == 0;
    }
  }
  EXPECT_LT(worst_w, 1e-6);
  EXPECT_LT(worst_tau, 1e-6);
  EXPECT_TRUE(locked_at_end);
}

TEST(ClutchLockUp, SmallSecondInertiaLocksAsTheClosedFormSays) { ExpectLockUp(1, 0.05); }

TEST(ClutchLockUp, LargeInertiasLockAsTheClosedFormSays) { ExpectLockUp(10, 10); }

TEST(ClutchLockUp, InertiaSweepLocksEveryTime) {
  // From inertias whose sliding accelerations dwarf the 80 N.m limit (J2 = 0.01: 8 000 rad/s2) to
  // ones whose do not.
  for (double J2 : {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
    for (double J1 : {0.05, 1.0}) ExpectLockUp(J1, J2);
  }
}

}  // namespace
}  // namespace momenta

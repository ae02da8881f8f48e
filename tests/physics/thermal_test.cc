// The thermal library (components/thermal.yaml, MSL Modelica.Thermal.HeatTransfer), the heat
// ports of the lossy mechanical components and the EddyCurrentForce against closed forms and
// conservation of energy.
//
// Closed forms (C heat capacity, G conductance, T0 the start temperature):
//   HeatCapacitor cooled through a ThermalConductor (or a Convection of constant Gc = G) towards
//   a fixed temperature Tf:   T = Tf + (T0 - Tf) e^(-G t/C).
//   Two capacitors joined by a conductor: C1 T1 + C2 T2 is constant and
//   T1 - T2 = (T10 - T20) e^(-G (1/C1 + 1/C2) t).
//   FixedHeatFlow Q (temperature coefficient alpha, reference T_ref) into a capacitor:
//   C T' = Q (1 + alpha (T - T_ref)), so T - T_ref + 1/alpha = (T0 - T_ref + 1/alpha) e^(Q alpha t/C),
//   and T = T0 + Q t/C for alpha = 0.
//   EddyCurrentForce on a mass m, constant excitation 1, fin temperature T (no heat port):
//   m v' = -2 F v_n/(1 + v_n^2), v_n = v/vn, vn = v_nominal (1 + alpha20 (T - TRef)) (TRef =
//   20 degC), which integrates to t(v) = m vn/(2F) (ln(v0/v) + (v0^2 - v^2)/(2 vn^2)).
//
// Energy balance: with useHeatPort = true every watt a damper dissipates flows into the heat
// capacitor, so (mechanical energy at the start) - (mechanical energy now) = C (T - T0).
//
// Tolerances: every run uses rtol = atol = 1e-10; each bound is about ten times the largest
// error observed (given beside it) and is justified against that tolerance where it says so.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "tests/support/physics_checks.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildClean;
using testing::Built;
using testing::MaxError;
using testing::Trajectory;

// A 10 J/K capacitor at 350 K cools through G = 2 W/K towards 300 K: time constant C/G = 5 s.
// The same law twice: through a ThermalConductor to a FixedTemperature, and through a
// Convection (Gc from a Constant block) to a PrescribedTemperature, read by a TemperatureSensor.
TEST(ThermalTest, HeatCapacitorCoolsExponentially) {
  Built b = BuildClean(R"(model: Cooling
parameters: {C: 10, G: 2, T0: 350, Tf: 300}
components:
  body: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
  wall: {type: ThermalConductor, G: G}
  ambient: {type: FixedTemperature, T: Tf}
  body2: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
  film: {type: Convection}
  gc: {type: Constant, k: G}
  fluid: {type: PrescribedTemperature}
  tf: {type: Constant, k: Tf}
  sensor: {type: TemperatureSensor}
connections:
  - [body.port, wall.port_a]
  - [wall.port_b, ambient.port]
  - [body2.port, film.solid]
  - [film.fluid, fluid.port]
  - [gc.y, film.Gc]
  - [tf.y, fluid.T]
  - [sensor.port, body2.port]
experiment: {stop: 20, tolerance: 1e-10, interval: 0.01}
outputs: [body.T, wall.Q_flow, body.der_T, body2.T, film.Q_flow, sensor.T]
)");
  Trajectory tr = testing::RunDefault(b);
  auto T = [](double t) { return 300 + 50 * std::exp(-t / 5); };
  // T is about 350 K, so IDA's local tolerance is rtol*|T| = 3.5e-8 K a step; observed 1.7e-7 K
  // over the run (3.3e-7 W in Q_flow = G dT, 3.3e-8 K/s in der_T = -dT/5).
  EXPECT_LT(MaxError(tr, "body.T", T), 2e-6);
  EXPECT_LT(MaxError(tr, "wall.Q_flow", [&](double t) { return 2 * (T(t) - 300); }), 4e-6);
  EXPECT_LT(MaxError(tr, "body.der_T", [&](double t) { return -(T(t) - 300) / 5; }), 4e-7);
  EXPECT_LT(MaxError(tr, "body2.T", T), 2e-6);
  EXPECT_LT(MaxError(tr, "film.Q_flow", [&](double t) { return 2 * (T(t) - 300); }), 4e-6);
  EXPECT_LT(MaxError(tr, "sensor.T", T), 2e-6);
  // After four time constants, e^-4 of the 50 K difference is left.
  EXPECT_NEAR(tr.Column("body.T", tr.t.size() - 1), 300 + 50 * std::exp(-4.0), 2e-6);
}

// Two capacitors (C1 = 2, C2 = 6 J/K, at 400 K and 300 K) joined by G = 3 W/K: heat is conserved
// and the difference decays with the rate G (1/C1 + 1/C2) = 2 1/s towards the mean 325 K.
TEST(ThermalTest, TwoCapacitorsConserveHeat) {
  Built b = BuildClean(R"(model: TwoBodies
components:
  a: {type: HeatCapacitor, C: 2, T: {start: 400, fixed: true}}
  b: {type: HeatCapacitor, C: 6, T: {start: 300, fixed: true}}
  g: {type: ThermalConductor, G: 3}
connections:
  - [a.port, g.port_a]
  - [g.port_b, b.port]
experiment: {stop: 5, tolerance: 1e-10, interval: 0.01}
outputs: [a.T, b.T, "2*a.T + 6*b.T", g.dT]
)");
  Trajectory tr = testing::RunDefault(b);
  // The heat content is a linear invariant of the equations: IDA keeps it to rounding of the
  // 2600 J sum over the steps (observed 2.3e-12 J).
  EXPECT_LT(MaxError(tr, "2*a.T + 6*b.T", [](double) { return 2 * 400.0 + 6 * 300.0; }), 1e-9);
  // Temperatures of 300-400 K at rtol 1e-10: observed 3.8e-7 K in their difference.
  EXPECT_LT(MaxError(tr, "g.dT", [](double t) { return 100 * std::exp(-2 * t); }), 4e-6);
  EXPECT_NEAR(tr.Column("a.T", tr.t.size() - 1), 325 + 75 * std::exp(-10.0), 4e-6);
}

// FixedHeatFlow of 5 W into a 10 J/K capacitor: T = T0 + t/2 exactly without a temperature
// coefficient; with alpha = 0.01 1/K (T_ref = 300 K, T0 = 300 K) the heat flow grows with T and
// T = 300 - 100 + 100 e^(0.005 t). PrescribedHeatFlow from a Constant block is the same law.
TEST(ThermalTest, HeatFlowSourcesHeatACapacitor) {
  Built b = BuildClean(R"(model: Heating
components:
  c1: {type: HeatCapacitor, C: 10, T: {start: 300, fixed: true}}
  q1: {type: FixedHeatFlow, Q_flow: 5}
  c2: {type: HeatCapacitor, C: 10, T: {start: 300, fixed: true}}
  q2: {type: FixedHeatFlow, Q_flow: 5, T_ref: 300, alpha: 0.01}
  c3: {type: HeatCapacitor, C: 10, T: {start: 300, fixed: true}}
  q3: {type: PrescribedHeatFlow, T_ref: 300, alpha: 0.01}
  k: {type: Constant, k: 5}
connections:
  - [q1.port, c1.port]
  - [q2.port, c2.port]
  - [q3.port, c3.port]
  - [k.y, q3.Q_flow]
experiment: {stop: 100, tolerance: 1e-10, interval: 0.1}
outputs: [c1.T, c2.T, c3.T]
)");
  Trajectory tr = testing::RunDefault(b);
  // Linear in t: the integrator is exact up to rounding of 350 K (observed 1e-13 K).
  EXPECT_LT(MaxError(tr, "c1.T", [](double t) { return 300 + t / 2; }), 1e-10);
  auto grown = [](double t) { return 200 + 100 * std::exp(0.005 * t); };
  EXPECT_LT(MaxError(tr, "c2.T", grown), 1e-6);  // observed 6e-8 K of a 65 K rise
  EXPECT_LT(MaxError(tr, "c3.T", grown), 1e-6);
}

// The mechanical energy a damped oscillator loses is the heat its heat capacitor gains. Four
// oscillators (m = 1 kg or J = 1 kg.m2, c = 100, start deflection 0.1), each dissipating through
// one lossy component with useHeatPort = true into its own capacitor (C = 10 J/K at 300 K):
// translational SpringDamper (d = 2), Damper (d = 2) beside a Spring, rotational SpringDamper
// (d = 2), and an ElastoGap (c = 1e4, d = 50) that the mass, thrown at 1 m/s, bounces off.
TEST(ThermalTest, DissipatedEnergyIsStoredAsHeat) {
  Built b = BuildClean(R"y(model: HeatedOscillators
parameters: {C: 10, T0: 300}
components:
  wall: {type: Fixed}
  sd: {type: SpringDamper, c: 100, d: 2, useHeatPort: true}
  m1: {type: Mass, m: 1, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
  h1: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
  spring: {type: Spring, c: 100}
  damper: {type: Damper, d: 2, useHeatPort: true}
  m2: {type: Mass, m: 1, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
  h2: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
  axle: {type: Rotational.Fixed}
  rsd: {type: Rotational.SpringDamper, c: 100, d: 2, useHeatPort: true}
  j3: {type: Inertia, J: 1, phi: {start: 0.1, fixed: true}, w: {start: 0, fixed: true}}
  h3: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
  gap: {type: ElastoGap, c: 1e4, d: 50, useHeatPort: true}
  m4: {type: Mass, m: 1, s: {start: 0.5, fixed: true}, v: {start: -1, fixed: true}}
  h4: {type: HeatCapacitor, C: C, T: {start: T0, fixed: true}}
connections:
  - [wall.flange, sd.flange_a]
  - [sd.flange_b, m1.flange_a]
  - [sd.heatPort, h1.port]
  - [wall.flange, spring.flange_a]
  - [wall.flange, damper.flange_a]
  - [spring.flange_b, m2.flange_a]
  - [damper.flange_b, m2.flange_a]
  - [damper.heatPort, h2.port]
  - [axle.flange, rsd.flange_a]
  - [rsd.flange_b, j3.flange_a]
  - [rsd.heatPort, h3.port]
  - [m4.flange_a, gap.flange_b]
  - [gap.flange_a, wall.flange]
  - [gap.heatPort, h4.port]
experiment: {stop: 5, tolerance: 1e-10, interval: 1e-3}
outputs:
  - "0.5 - (0.5*m1.m*m1.v^2 + 0.5*sd.c*sd.s_rel^2) - h1.C*(h1.T - T0)"
  - "0.5 - (0.5*m2.m*m2.v^2 + 0.5*spring.c*spring.s_rel^2) - h2.C*(h2.T - T0)"
  - "0.5 - (0.5*j3.J*j3.w^2 + 0.5*rsd.c*rsd.phi_rel^2) - h3.C*(h3.T - T0)"
  - "0.5 - (0.5*m4.m*m4.v^2 + 0.5*gap.c*max(-gap.s_rel, 0)^2) - h4.C*(h4.T - T0)"
  - h1.T
  - h4.T
  - m4.v
)y");
  Trajectory tr = testing::RunDefault(b);
  // Most of the 0.5 J each starts with is heat after 5 s (d/(2m) = 1/s: e^-10 of it is left in
  // the oscillators; the bouncing mass leaves the gap with less than its 1 m/s).
  EXPECT_GT(tr.Column("h1.T", tr.t.size() - 1) - 300, 0.9 * 0.05);
  EXPECT_GT(tr.Column("h4.T", tr.t.size() - 1) - 300, 0.01 * 0.05);
  EXPECT_LT(tr.Column("m4.v", tr.t.size() - 1), 1.0);
  EXPECT_GT(tr.Column("m4.v", tr.t.size() - 1), 0.0);
  // The balance holds exactly for the exact solution. Numerically its error is that of the
  // states: the heat term reads T (about 300 K) to IDA's local tolerance rtol*|T| + atol = 3e-8 K
  // per step, i.e. C*3e-8 = 3e-7 J, and the mechanical energy (0.5 J) to rtol of it. We allow
  // ten times the local bound, 3e-6 J (6e-6 of the 0.5 J at stake); observed 1.8e-9 J for the
  // three smooth oscillators and 3.1e-7 J for the ElastoGap (stiff contact, c = 1e4, events).
  for (const char* balance : {"0.5 - (0.5*m1.m*m1.v^2 + 0.5*sd.c*sd.s_rel^2) - h1.C*(h1.T - T0)",
                              "0.5 - (0.5*m2.m*m2.v^2 + 0.5*spring.c*spring.s_rel^2) - h2.C*(h2.T - T0)",
                              "0.5 - (0.5*j3.J*j3.w^2 + 0.5*rsd.c*rsd.phi_rel^2) - h3.C*(h3.T - T0)",
                              "0.5 - (0.5*m4.m*m4.v^2 + 0.5*gap.c*max(-gap.s_rel, 0)^2) - h4.C*(h4.T - T0)"}) {
    const double err = MaxError(tr, balance, [](double) { return 0.0; });
    RecordProperty(balance, std::to_string(err));
    std::printf("[   INFO   ] energy balance error %.3g J: %s\n", err, balance);
    EXPECT_LT(err, 3e-6) << balance;
  }
}

// EddyCurrentForce without a heat port brakes a 1 kg mass from 20 m/s with F = 100 N at
// v_nominal = 10 m/s, its fin at T = 333.15 K (60 degC, copper alpha20 = 3.92e-3 1/K), so
// vn = 10 (1 + 3.92e-3*40) = 11.568 m/s. Along the run, t(v) from the closed form must give back
// the time at which the mass has speed v; lossPower = f v is the power the mass loses.
TEST(ThermalTest, EddyCurrentForceFollowsKlossLaw) {
  Built b = BuildClean(R"(model: EddyBrake
components:
  brake: {type: EddyCurrentForce, f_nominal: 100, v_nominal: 10, alpha20: 3.92e-3, T: 333.15}
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 20, fixed: true}}
connections:
  - [brake.flange, mass.flange_b]
experiment: {stop: 1, tolerance: 1e-10, interval: 1e-3}
outputs: [mass.v, brake.lossPower, brake.f, brake.TheatPort]
)");
  Trajectory tr = testing::RunDefault(b);
  const double vn = 10 * (1 + 3.92e-3 * 40), F = 100, v0 = 20;
  double worst = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double v = tr.Column("mass.v", k);
    // t(v) is compared while v >= 0.01 m/s: dt/dv = -vn/(2F) (1/v + v/vn^2) turns the absolute
    // tolerance atol = 1e-10 on v into up to 6e-10 s there, but into far more as v -> 0.
    const double t = vn / (2 * F) * (std::log(v0 / v) + (v0 * v0 - v * v) / (2 * vn * vn));
    if (v >= 0.01) worst = std::max(worst, std::abs(t - tr.t[k]));
    const double vnorm = v / vn;
    EXPECT_NEAR(tr.Column("brake.f", k), 2 * F * vnorm / (1 + vnorm * vnorm), 1e-9);
    EXPECT_NEAR(tr.Column("brake.lossPower", k), tr.Column("brake.f", k) * v, 1e-9);
    EXPECT_EQ(tr.Column("brake.TheatPort", k), 333.15);
  }
  std::printf("[   INFO   ] EddyCurrentForce: worst |t(v) - t| %.3g s\n", worst);
  EXPECT_LT(worst, 3e-8);  // observed 2.6e-9 s
  // The mass is slowed well below vn by t = 1 s (t(v = 1 m/s) = 0.5 s).
  EXPECT_LT(tr.Column("mass.v", tr.t.size() - 1), 1.0);
}

}  // namespace
}  // namespace momenta

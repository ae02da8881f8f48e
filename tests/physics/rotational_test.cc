// The rotational library (components/rotational.yaml, MSL Modelica.Mechanics.Rotational) against
// closed forms.
//
// Oscillator: Rotational.Fixed (phi0 = 0) holds a torsional spring (and damper) whose flange_b
// turns an Inertia J: J phi'' + d phi' + c phi = 0, phi(0) = phi0, w(0) = 0; w0 = sqrt(c/J),
// zeta = d/(2 sqrt(c J)), sigma = zeta w0, wd = w0 sqrt(1 - zeta^2):
//   phi = e^(-sigma t) (phi0 cos(wd t) + sigma phi0/wd sin(wd t)).
// IdealGear (MSL: flange_a.phi = ratio*flange_b.phi, flange_b.tau = -ratio*flange_a.tau): a
// torque tau on J1 at flange_a, J2 at flange_b, from rest:
//   a2 = ratio*tau/(J2 + ratio^2*J1), a1 = ratio*a2, and the gear passes J2*a2 on to J2.
// Exact Position along phi = A sin(w t) of an inertia held by a spring: the source's torque is
//   J phi'' + c phi = (c - J w^2) A sin(w t).
// Filtered sources for the ramp phi_ref = w_ref = t (the MSL's filters, as for translational):
//   Speed:    w = t - (1 - e^(-wc t))/wc, phi = t^2/2 - t/wc + (1 - e^(-wc t))/wc^2;
//   Position: phi = t - af/wc + e^(-s t)(af/wc cos(wd t) + (s af/wc - 1)/wd sin(wd t)),
//             s = af wc/(2 bf), wd^2 = wc^2/bf - s^2.
//
// Tolerances: every run uses rtol = atol = 1e-10. Where the integration error shows, each bound
// is about ten times the largest error observed (given beside it); where the answer is exact up
// to rounding (uniform acceleration, motion imposed through symbolic derivatives), 1e-12 for
// quantities of order 1-10.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tests/support/physics_checks.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildClean;
using testing::Built;
using testing::MaxError;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

/// Times at which the column crosses zero upwards, linearly interpolated between rows.
std::vector<double> UpwardZeros(const Trajectory& tr, const std::string& column) {
  const size_t j = tr.Index(column);
  std::vector<double> zeros;
  for (size_t k = 1; k < tr.t.size(); ++k) {
    const double y0 = tr.values[k - 1][j], y1 = tr.values[k][j];
    if (y0 < 0 && y1 >= 0) zeros.push_back(tr.t[k - 1] + (tr.t[k] - tr.t[k - 1]) * (-y0) / (y1 - y0));
  }
  return zeros;
}

std::string OscillatorYaml(const std::string& compliance) {
  return R"(model: TorsionalOscillator
parameters: {J: 0.25, c: 100, d: 0, phi0: 0.1}
components:
  fixed: {type: Rotational.Fixed, phi0: 0}
  inertia: {type: Inertia, J: J, phi: {start: phi0, fixed: true}, w: {start: 0, fixed: true}}
)" + compliance + R"(
experiment: {stop: 2, tolerance: 1e-10, interval: 1e-4}
outputs: [inertia.phi, inertia.w]
)";
}

// One SpringDamper between the wall and the inertia.
const char* kSpringDamper = R"(  sd: {type: Rotational.SpringDamper, c: c, d: d}
connections:
  - [fixed.flange, sd.flange_a]
  - [sd.flange_b, inertia.flange_a])";

// A Spring and a Damper in parallel: the same oscillator.
const char* kSpringAndDamper = R"(  spring: {type: Rotational.Spring, c: c}
  damper: {type: Rotational.Damper, d: d}
connections:
  - [fixed.flange, spring.flange_a]
  - [fixed.flange, damper.flange_a]
  - [spring.flange_b, inertia.flange_a]
  - [damper.flange_b, inertia.flange_a])";

TEST(RotationalOscillator, UndampedPeriodAndAmplitude) {
  const double J = 0.25, c = 100, phi0 = 0.1, w0 = std::sqrt(c / J);
  Trajectory tr = testing::RunDefault(BuildClean(OscillatorYaml(kSpringDamper)));
  // Pointwise over 6 periods: observed 8.0e-10 rad and 1.7e-8 rad/s (amplitude 2 rad/s).
  EXPECT_LT(MaxError(tr, "inertia.phi", [&](double t) { return phi0 * std::cos(w0 * t); }), 1e-8);
  EXPECT_LT(MaxError(tr, "inertia.w", [&](double t) { return -phi0 * w0 * std::sin(w0 * t); }), 2e-7);
  // Period from the upward zero crossings against 2 pi sqrt(J/c): the crossings are interpolated
  // linearly where phi is straight (phi'' = 0 at phi = 0), observed 3.5e-13 s.
  std::vector<double> zeros = UpwardZeros(tr, "inertia.phi");
  ASSERT_GE(zeros.size(), 5u);
  const double period = (zeros.back() - zeros.front()) / (zeros.size() - 1);
  EXPECT_NEAR(period, 2 * kPi * std::sqrt(J / c), 5e-12);
  // Amplitude at every row, from the energy: sqrt(phi^2 + (w/w0)^2) = phi0 (observed 8.9e-10).
  double amplitude_error = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double phi = tr.Column("inertia.phi", k), w = tr.Column("inertia.w", k) / w0;
    amplitude_error = std::max(amplitude_error, std::abs(std::sqrt(phi * phi + w * w) - phi0));
  }
  EXPECT_LT(amplitude_error, 1e-8);
}

TEST(RotationalOscillator, DampedMatchesClosedFormWithSpringDamperAndWithSpringAndDamper) {
  const double J = 0.25, c = 100, d = 2, phi0 = 0.1;
  const double w0 = std::sqrt(c / J), zeta = d / (2 * std::sqrt(c * J)), sigma = zeta * w0;
  const double wd = w0 * std::sqrt(1 - zeta * zeta);
  auto phi = [&](double t) { return std::exp(-sigma * t) * (phi0 * std::cos(wd * t) + sigma * phi0 / wd * std::sin(wd * t)); };
  auto w = [&](double t) { return -std::exp(-sigma * t) * phi0 * (w0 * w0 / wd) * std::sin(wd * t); };
  for (const char* compliance : {kSpringDamper, kSpringAndDamper}) {
    SCOPED_TRACE(compliance);
    Trajectory tr = testing::RunDefault(BuildClean(OscillatorYaml(compliance)), {{"d", d}});
    EXPECT_LT(MaxError(tr, "inertia.phi", phi), 2e-9);  // observed 1.5e-10 rad (both models)
    EXPECT_LT(MaxError(tr, "inertia.w", w), 3e-8);      // observed 2.4e-9 rad/s
  }
}

TEST(RotationalSigns, PositiveTorqueAcceleratesAndTwistedSpringPullsBack) {
  // A Torque fed +2 N.m turns a free inertia (J = 0.5) forwards: a = +4.
  Trajectory driven = testing::RunDefault(BuildClean(R"(model: Driven
components:
  source: {type: Constant, k: 2}
  torque: {type: Torque}
  inertia: {type: Inertia, J: 0.5, phi: {start: 0, fixed: true}, w: {start: 0, fixed: true}}
connections:
  - [source.y, torque.tau]
  - [torque.flange, inertia.flange_a]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: [inertia.a, inertia.w, inertia.phi, torque.flange.tau]
)"));
  // Uniform acceleration is integrated exactly up to rounding: observed 0, 1.3e-15, 1.3e-15.
  EXPECT_LT(MaxError(driven, "inertia.a", [](double) { return 4.0; }), 1e-12);
  EXPECT_LT(MaxError(driven, "inertia.w", [](double t) { return 4 * t; }), 1e-12);
  EXPECT_LT(MaxError(driven, "inertia.phi", [](double t) { return 2 * t * t; }), 1e-12);
  // The flow into the source is minus the torque it exerts.
  EXPECT_LT(MaxError(driven, "torque.flange.tau", [](double) { return -2.0; }), 1e-12);

  // An inertia turned to +0.1 rad on a spring from a fixed flange: the spring is twisted
  // forwards (tau = c phi_rel > 0) and turns the inertia back (a < 0).
  Trajectory sprung = testing::RunDefault(BuildClean(R"(model: Twisted
components:
  fixed: {type: Rotational.Fixed}
  spring: {type: Rotational.Spring, c: 100}
  inertia: {type: Inertia, J: 0.25, phi: {start: 0.1, fixed: true}, w: {start: 0, fixed: true}}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, inertia.flange_a]
experiment: {stop: 0.01, tolerance: 1e-10, interval: 0.01}
outputs: [spring.phi_rel, spring.tau, spring.flange_b.tau, inertia.a]
)"));
  EXPECT_NEAR(sprung.Column("spring.phi_rel", 0), 0.1, 1e-14);
  EXPECT_NEAR(sprung.Column("spring.tau", 0), 10.0, 1e-12);
  EXPECT_NEAR(sprung.Column("spring.flange_b.tau", 0), 10.0, 1e-12);
  EXPECT_NEAR(sprung.Column("inertia.a", 0), -40.0, 1e-10);
}

TEST(RotationalGear, ConstantTorqueThroughIdealGear) {
  // ConstantTorque 2 N.m on J1 = 0.5 at the gear's flange_a, ratio 3, J2 = 4 at flange_b through
  // a TorqueSensor.
  Built b = BuildClean(R"(model: Gearbox
parameters: {J1: 0.5, J2: 4, ratio: 3, tau: 2}
components:
  motor: {type: ConstantTorque, tau_constant: tau}
  load1: {type: Inertia, J: J1, phi: {start: 0, fixed: true}, w: {start: 0, fixed: true}}
  gear: {type: IdealGear, ratio: ratio}
  sensor: {type: TorqueSensor}
  load2: {type: Inertia, J: J2}
connections:
  - [motor.flange, load1.flange_a]
  - [load1.flange_b, gear.flange_a]
  - [gear.flange_b, sensor.flange_a]
  - [sensor.flange_b, load2.flange_a]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [load1.a, load2.a, load2.w, load2.phi, load1.phi, sensor.tau, motor.tau, motor.w]
)");
  Trajectory tr = testing::RunDefault(b);
  const double J1 = 0.5, J2 = 4, ratio = 3, tau = 2;
  const double a2 = ratio * tau / (J2 + ratio * ratio * J1), a1 = ratio * a2;
  // Uniform acceleration: accelerations and speeds exact up to rounding (observed <= 9e-16); the
  // angles carry the integration error (observed 8.0e-11 and 2.4e-10 rad at 1.4 and 4.2 rad).
  EXPECT_LT(MaxError(tr, "load2.a", [&](double) { return a2; }), 1e-12);
  EXPECT_LT(MaxError(tr, "load1.a", [&](double) { return a1; }), 1e-12);
  EXPECT_LT(MaxError(tr, "load2.w", [&](double t) { return a2 * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "motor.w", [&](double t) { return a1 * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "load2.phi", [&](double t) { return a2 * t * t / 2; }), 1e-9);
  EXPECT_LT(MaxError(tr, "load1.phi", [&](double t) { return a1 * t * t / 2; }), 3e-9);
  // The sensor passes J2 the torque J2*a2 = ratio*tau - ratio^2*J1*a2.
  EXPECT_LT(MaxError(tr, "sensor.tau", [&](double) { return J2 * a2; }), 1e-12);
  EXPECT_LT(MaxError(tr, "motor.tau", [&](double) { return tau; }), 1e-12);
}

TEST(RotationalMotion, ExactPositionThroughSpringNeedsJaPlusCphi) {
  // The fixed wall holds a spring whose flange_b turns the inertia; the source imposes the
  // inertia's angle from the other side, through a TorqueSensor.
  Built b = BuildClean(R"(model: DrivenInertia
parameters: {J: 2, c: 100, A: 0.1, f: 0.5}
components:
  fixed: {type: Rotational.Fixed}
  spring: {type: Rotational.Spring, c: c}
  inertia: {type: Inertia, J: J}
  sensor: {type: TorqueSensor}
  source: {type: Rotational.Position, exact: true}
  sine: {type: Sine, amplitude: A, f: f}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, inertia.flange_a]
  - [source.flange, sensor.flange_a]
  - [sensor.flange_b, inertia.flange_b]
  - [sine.y, source.phi_ref]
experiment: {stop: 3, tolerance: 1e-10, interval: 0.01}
outputs: [inertia.phi, inertia.a, sensor.tau, source.flange.tau]
)");
  Trajectory tr = testing::RunDefault(b);
  const double J = 2, c = 100, A = 0.1, w = 2 * kPi * 0.5;
  // The angle and acceleration come from the symbolic derivatives of the sine: rounding only
  // (observed 0 and 1.1e-16; the torques 1.8e-15).
  EXPECT_LT(MaxError(tr, "inertia.phi", [&](double t) { return A * std::sin(w * t); }), 1e-12);
  EXPECT_LT(MaxError(tr, "inertia.a", [&](double t) { return -A * w * w * std::sin(w * t); }), 1e-12);
  // The torque the source exerts (the sensor's reading, minus the flow into the source).
  auto needed = [&](double t) { return (c - J * w * w) * A * std::sin(w * t); };
  EXPECT_LT(MaxError(tr, "sensor.tau", needed), 1e-12);
  EXPECT_LT(MaxError(tr, "source.flange.tau", [&](double t) { return -needed(t); }), 1e-12);
}

TEST(RotationalMotion, FilteredAndExactSpeedRamp) {
  const std::string yaml = R"(model: SpeedRamp
parameters: {exact: false}
components:
  ramp: {type: Ramp, height: 10, duration: 10}
  source: {type: Rotational.Speed, exact: exact, f_crit: 1}
  inertia: {type: Inertia, J: 1}
  speed: {type: Rotational.SpeedSensor}
connections:
  - [ramp.y, source.w_ref]
  - [source.flange, inertia.flange_a]
  - [inertia.flange_b, speed.flange]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [inertia.phi, inertia.w, speed.w, source.a]
)";
  const double wc = 2 * kPi;
  Trajectory filtered = testing::RunDefault(BuildClean(yaml));
  auto w = [&](double t) { return t - (1 - std::exp(-wc * t)) / wc; };
  auto phi = [&](double t) { return t * t / 2 - t / wc + (1 - std::exp(-wc * t)) / (wc * wc); };
  EXPECT_LT(MaxError(filtered, "inertia.w", w), 1e-8);      // observed 7.7e-10 rad/s
  EXPECT_LT(MaxError(filtered, "speed.w", w), 1e-8);        // the sensor reads the same
  EXPECT_LT(MaxError(filtered, "inertia.phi", phi), 1e-9);  // observed 1.0e-10 rad
  EXPECT_LT(MaxError(filtered, "source.a", [&](double t) { return 1 - std::exp(-wc * t); }), 5e-8);  // 4.8e-9

  Trajectory exact = testing::RunDefault(BuildClean(yaml, {{"exact", 1}}));
  EXPECT_LT(MaxError(exact, "inertia.w", [](double t) { return t; }), 1e-12);
  EXPECT_LT(MaxError(exact, "speed.w", [](double t) { return t; }), 1e-12);
  EXPECT_LT(MaxError(exact, "inertia.phi", [](double t) { return t * t / 2; }), 1e-9);  // 1.1e-10
}

TEST(RotationalMotion, FilteredPositionFollowsTheBesselFilter) {
  Built b = testing::BuildYaml(R"(model: FilteredRamp
components:
  ramp: {type: Ramp, height: 10, duration: 10}
  source: {type: Rotational.Position, f_crit: 2}
  inertia: {type: Inertia, J: 1}
connections:
  - [ramp.y, source.phi_ref]
  - [source.flange, inertia.flange_a]
experiment: {stop: 2, tolerance: 1e-10, interval: 0.01}
outputs: [source.phi, inertia.phi]
)");
  // As in the MSL, the filter's angular velocity has no initial condition (w(start = 0)): its
  // start value is used, with the usual warning.
  ASSERT_EQ(b.report.warnings.size(), 1u);
  EXPECT_NE(b.report.warnings[0].find("source.w"), std::string::npos) << b.report.warnings[0];
  Trajectory tr = testing::RunDefault(b);
  const double af = 1.3617, bf = 0.6180, wc = 2 * kPi * 2;
  const double s = af * wc / (2 * bf), wd = std::sqrt(wc * wc / bf - s * s);
  auto phi = [&](double t) {
    return t - af / wc + std::exp(-s * t) * (af / wc * std::cos(wd * t) + (s * af / wc - 1) / wd * std::sin(wd * t));
  };
  EXPECT_LT(MaxError(tr, "source.phi", phi), 4e-9);  // observed 3.8e-10 rad
  EXPECT_LT(MaxError(tr, "inertia.phi", phi), 4e-9);
}

TEST(RotationalSensors, ReadAngleSpeedAndRelativeQuantitiesWithoutLoading) {
  // ConstantTorque 2 N.m on J = 0.5 from rest at phi = 0.3: phi = 0.3 + 2 t^2, w = 4 t. The
  // sensors hang on the inertia and on a Fixed flange at phi0 = 0.3 and must not change the
  // motion.
  Trajectory tr = testing::RunDefault(BuildClean(R"(model: Sensors
components:
  fixed: {type: Rotational.Fixed, phi0: 0.3}
  motor: {type: ConstantTorque, tau_constant: 2}
  inertia: {type: Inertia, J: 0.5, phi: {start: 0.3, fixed: true}, w: {start: 0, fixed: true}}
  angle: {type: AngleSensor}
  speed: {type: Rotational.SpeedSensor}
  relAngle: {type: RelAngleSensor}
  relSpeed: {type: Rotational.RelSpeedSensor}
connections:
  - [motor.flange, inertia.flange_a]
  - [inertia.flange_b, angle.flange]
  - [inertia.flange_b, speed.flange]
  - [fixed.flange, relAngle.flange_a]
  - [inertia.flange_b, relAngle.flange_b]
  - [fixed.flange, relSpeed.flange_a]
  - [inertia.flange_a, relSpeed.flange_b]
experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: [angle.phi, speed.w, relAngle.phi_rel, relSpeed.w_rel, inertia.a, fixed.flange.tau]
)"));
  // Uniform acceleration: observed errors at rounding level (<= 1.8e-15).
  EXPECT_LT(MaxError(tr, "angle.phi", [](double t) { return 0.3 + 2 * t * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "speed.w", [](double t) { return 4 * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "relAngle.phi_rel", [](double t) { return 2 * t * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "relSpeed.w_rel", [](double t) { return 4 * t; }), 1e-12);
  EXPECT_LT(MaxError(tr, "inertia.a", [](double) { return 4.0; }), 1e-12);
  EXPECT_LT(MaxError(tr, "fixed.flange.tau", [](double) { return 0.0; }), 1e-12);
}

TEST(RotationalErrors, TranslationalSpringOnARotationalFlange) {
  // `type: Spring` is the translational spring (the translational types own the short names);
  // connected to an inertia it is refused at the connection, naming both connector types.
  const std::string error = testing::BuildError(R"(model: Wrong
components:
  fixed: {type: Rotational.Fixed}
  spring: {type: Spring, c: 100}
  inertia: {type: Inertia, J: 1}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, inertia.flange_a]
)");
  EXPECT_NE(error.find("test.yaml:7:6: cannot connect fixed.flange (Rotational.Flange) to spring.flange_a "
                       "(Flange): connectors of different kinds"),
            std::string::npos)
      << error;

  // A rotational parameter on the translational spring is an unknown key.
  const std::string key = testing::BuildError(R"(model: Wrong
components:
  spring: {type: Spring, phi_rel0: 0.1}
)");
  EXPECT_NE(key.find("test.yaml:3:26: unknown key 'phi_rel0' for spring (Spring)"), std::string::npos) << key;
  EXPECT_NE(key.find("valid parameters and variables: c, s_rel0,"), std::string::npos) << key;
}

}  // namespace
}  // namespace momenta

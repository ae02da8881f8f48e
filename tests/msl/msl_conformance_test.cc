// MSL examples in models/msl/ against the MSL's own reference results (tests/data/msl/), with the
// models' own experiment settings:
// - ten Modelica.Mechanics.Translational examples (tolerance 1e-6, interval 5e-4 — Vehicle
//   5e-3 —, the reference's output interval), EddyCurrentBrake among them with its
//   single-precision reference;
// - six Modelica.Mechanics.MultiBody.Examples.Elementary examples whose motion lies in the x-y
//   plane, built from the planar library (tolerance 1e-6, interval StopTime/5000, the
//   reference's output interval).
//
// - two models with events: ModelicaTest.Blocks.Logical (every Boolean block, interval 2e-3)
//   and Translational PreLoad (ElastoGap contacts, interval 0.05).
//
// Criterion: the MSL's CSV-compare tube with tolerance 2e-3 (tests/support/msl_tube.h): for every
// reference column, our rows at the reference's times and at events lie within a rectangle
// 2e-3 * max(range, |lowest value|, 1e-3) high and 2e-3 of the run wide in time, swept along the
// reference's curve. Our output times are start + k*interval plus a left- and a right-limit row at
// every event (as the reference's events=true output); the reference lists event times twice
// (left, then right limit). A reference event our solver located a little apart (within
// kEventTimeWindow) is compared with our rows there.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "tests/support/msl_tube.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Compare;
using testing::Csv;
using testing::CsvCompareTube;
using testing::Trajectory;
using testing::TubeWidth;
using testing::Worst;

std::string ModelPath(const std::string& name) { return "models/msl/" + name + ".yaml"; }

constexpr const char* kTranslational = "Modelica.Mechanics.Translational.Examples";
constexpr const char* kMultiBody = "Modelica.Mechanics.MultiBody.Examples.Elementary";
constexpr const char* kModelicaTestBlocks = "ModelicaTest.Blocks";

/// The reference result of the MSL example `package`.`name` (the file's name is the full class
/// name).
Csv Reference(const std::string& name, const std::string& package = kTranslational) {
  return testing::ReadCsv(testing::SourcePath("tests/data/msl/" + package + "." + name + ".csv"));
}

/// One MSL example: its package, its short name (the model file's and the test's name), the
/// output interval of its reference, which the model's experiment must use, the tube, and the
/// reference run's event counts where MODELS.md gives them (-1: not given), printed beside ours.
struct MslExample {
  const char* package;
  const char* name;
  double interval;
  TubeWidth tube = CsvCompareTube;
  int ref_state_events = -1, ref_time_events = -1;
  /// The reference was stored in single precision (EddyCurrentBrake): its times carry a relative
  /// error up to 2^-24, so 0.0005 reads 0.00050000002.
  bool single_precision = false;
  /// A column whose reference rows before `settle_until` are compared as our rows at events are,
  /// against the reference's curve within the tube's time width, not row by row: HeatLosses'
  /// brake.mode, which in the reference is Forward for the first 0.43 µs after the brake
  /// engages at t = 8e-14 s, decided on a sliding velocity of rounding size (the brake is at
  /// rest, every force on it is zero; springDamper1.v_rel is -2.7e-24 m/s, then 1e-10 m/s),
  /// where we find the brake Stuck at once.
  const char* settle_column = nullptr;
  double settle_until = 0;
};

std::ostream& operator<<(std::ostream& os, const MslExample& e) {
  return os << e.package << "." << e.name;
}

class MslConformanceTest : public ::testing::TestWithParam<MslExample> {};

TEST_P(MslConformanceTest, WithinTheMslTube) {
  // The models' own experiment: every MSL example here runs at the reference's tolerance, 1e-6,
  // and output interval (5e-4 for Translational but Vehicle's 5e-3, StopTime/5000 for MultiBody);
  // rows at every event, as the reference has them.
  const MslExample& e = GetParam();
  testing::TubeCheck check;
  check.interval = e.interval;
  check.tube = e.tube;
  check.single_precision = e.single_precision;
  check.settle_column = e.settle_column ? e.settle_column : "";
  check.settle_until = e.settle_until;
  SolverStats stats;
  testing::CheckAgainstReference(e.name, ModelPath(e.name), Reference(e.name, e.package), check, &stats);
  if (e.ref_state_events >= 0) {
    std::printf("[   INFO   ] %s: %ld state events and %ld time events (reference: %d and %d)\n", e.name,
                stats.events - stats.time_events, stats.time_events, e.ref_state_events, e.ref_time_events);
  }
}

std::string ExampleName(const ::testing::TestParamInfo<MslExample>& info) {
  return info.param.name;
}

INSTANTIATE_TEST_SUITE_P(Translational, MslConformanceTest,
                         ::testing::Values(MslExample{kTranslational, "SignConvention", 5e-4},
                                           MslExample{kTranslational, "InitialConditions", 5e-4},
                                           MslExample{kTranslational, "WhyArrows", 5e-4},
                                           MslExample{kTranslational, "Accelerate", 5e-4},
                                           MslExample{kTranslational, "Damper", 5e-4},
                                           MslExample{kTranslational, "Oscillator", 5e-4},
                                           MslExample{kTranslational, "Sensors", 5e-4},
                                           MslExample{kTranslational, "Vehicle", 5e-3},
                                           MslExample{kTranslational, "GenerationOfFMUs", 5e-4},
                                           MslExample{kTranslational, "EddyCurrentBrake", 5e-4, CsvCompareTube, -1, -1, true}),
                         ExampleName);

// MultiBody.Examples.Elementary in the plane (models/msl/<Name>.yaml say how each maps to the
// planar library). The reference interval is StopTime/5000.
INSTANTIATE_TEST_SUITE_P(
    MultiBody, MslConformanceTest,
    ::testing::Values(MslExample{kMultiBody, "Pendulum", 5.0 / 5000},
                      MslExample{kMultiBody, "DoublePendulum", 3.0 / 5000},
                      MslExample{kMultiBody, "PendulumWithSpringDamper", 10.0 / 5000},
                      MslExample{kMultiBody, "SpringMassSystem", 5.0 / 5000},
                      MslExample{kMultiBody, "SpringDamperSystem", 10.0 / 5000},
                      MslExample{kMultiBody, "SpringWithMass", 5.0 / 5000}),
    ExampleName);

// Models with events, compared at every reference row including both limits at each event
// (2e-3 of each signal's range). Logical: 38 state and 10 time events in the reference run;
// PreLoad: 7 state events; HeatLosses: 41 state events (MODELS.md).
INSTANTIATE_TEST_SUITE_P(Events, MslConformanceTest,
                         ::testing::Values(MslExample{kModelicaTestBlocks, "Logical", 2e-3, CsvCompareTube, 38, 10},
                                           MslExample{kTranslational, "PreLoad", 0.05, CsvCompareTube, 7, 0},
                                           MslExample{kTranslational, "Friction", 5e-4, CsvCompareTube, 18, 0},
                                           MslExample{kTranslational, "Brake", 5e-4, CsvCompareTube, 1, 1},
                                           MslExample{kTranslational, "HeatLosses", 5e-4, CsvCompareTube, 41, 0, false,
                                                      "brake.mode", 1e-6}),
                         ExampleName);

// The event comparison has teeth too: PreLoad with 10 % more damping between spool and housing
// slows the spool's creep (friction.v_rel) by about 10 %, ten times the tube's width.
TEST(MslTubeTest, RejectsAStifferPreloadDamper) {
  const ParameterOverrides stiffer = {{"friction.d", 2750}};
  Built b = testing::BuildFile(ModelPath("PreLoad"), stiffer);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  opt.rows_at_every_event = true;
  Trajectory ours = testing::Run(b, opt, stiffer);
  Worst worst;
  Compare("PreLoad with friction.d = 2750", ours, Reference("PreLoad"), opt.interval, CsvCompareTube, &worst);
  EXPECT_GT(worst.ratio, 1.0) << worst.ToString();
}

// The tube has teeth: WhyArrows with a 2 % stiffer spring in both oscillators (c = 11.22 instead
// of 11) shifts the frequency by 1 % and must leave the tube.
TEST(MslTubeTest, RejectsAWrongParameter) {
  const ParameterOverrides stiffer = {{"spring1.c", 11.22}, {"spring2.c", 11.22}};
  Built b = testing::BuildFile(ModelPath("WhyArrows"), stiffer);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  Trajectory ours = testing::Run(b, opt, stiffer);
  Worst worst;
  Compare("WhyArrows with c = 11.22", ours, Reference("WhyArrows"), opt.interval, CsvCompareTube, &worst);
  EXPECT_GT(worst.ratio, 1.0) << worst.ToString();
}

// EddyCurrentBrake's tube tests the temperature law too: without it (alpha20 = 0, so the heated
// copper fin keeps v_nominal = 10 m/s) the braking is so different that lossPower leaves the tube
// about fifty times over.
TEST(MslTubeTest, EddyCurrentBrakeNeedsTheTemperatureLaw) {
  const ParameterOverrides cold = {{"eddyCurrentForce.alpha20", 0}};
  Built b = testing::BuildFile(ModelPath("EddyCurrentBrake"), cold);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  Trajectory ours = testing::Run(b, opt, cold);
  Worst worst;
  Compare("EddyCurrentBrake with alpha20 = 0", ours, Reference("EddyCurrentBrake"), opt.interval, CsvCompareTube, &worst,
          true);
  EXPECT_GT(worst.ratio, 10.0) << worst.ToString();
}

// At a tight tolerance our InitialConditions converges to the exact solution; the reference's own
// error in sd1.v_rel and m1.v (against an independent RK4 cross-check) is 5.3e-4, so ours must
// then agree with it to 1e-3 at the same times (the reference's error plus margin for ours,
// ~1e-7 at rtol 1e-10).
TEST(MslInitialConditionsTest, TightToleranceApproachesTheExactSolution) {
  Built b = testing::BuildFile(ModelPath("InitialConditions"));
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  opt.rtol = 1e-10;
  Trajectory ours = testing::Run(b, opt);
  Csv ref = Reference("InitialConditions");
  Csv only;
  only.header = {"time", "sd1.v_rel", "m1.v"};
  for (const auto& row : ref.rows) {
    only.rows.push_back({row[0], row[ref.Index("sd1.v_rel")], row[ref.Index("m1.v")]});
  }
  Worst worst;
  Compare("InitialConditions at rtol 1e-10", ours, only, opt.interval, [](double, double) { return 1e-3; },
          &worst, false, "", 0, /*same_time=*/true);
  RecordProperty("worst_error", worst.ToString());
  std::printf("[   INFO   ] InitialConditions at rtol 1e-10: worst %s\n", worst.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << worst.ToString();
}

}  // namespace
}  // namespace momenta

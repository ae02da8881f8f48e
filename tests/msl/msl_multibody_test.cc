// The MSL MultiBody examples of stages S1 and S2 (trees of bodies and joints; free bodies and
// multi-degree-of-freedom joints) against their published reference results
// (tests/data/msl-multibody/<Full.Name>.csv, from MAP-LIB_ReferenceResults v4.1.0, Dymola 2020x,
// DASSL, thinned to about 1 000 rows; /work/shared/reference/msl-multibody/README.md). The model of
// `Modelica.A.B.C` is models/msl/A/B/C.yaml, of `ModelicaTest.A.B` models/msl/ModelicaTest/A/B.yaml;
// it runs with its own experiment (the example's stop time, tolerance and output interval), with rows
// at every event, and every reference column must lie within the MSL's CSV-compare tube, 2e-3 of
// max(range, |lowest value|, 1e-3) high and 2e-3 of the run wide in time (tests/support/msl_tube.h),
// as MslMoreTest's. (2e-3 of the column's range alone would fail columns that are constant up to
// rounding: FreeMotion's Q[4] spans 2.2e-16 in the reference; CSV-compare's floor of 1e-3 and
// |lowest| keep such a tube 2e-3 of the value.) An example without a model yet is skipped, and counted:
// MslMultiBodyCoverage fails when fewer than kMultiBodyModelled models exist, so that none goes
// missing. Each run prints its steps and events beside Dymola's (the reference run's log).

#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "tests/support/msl_examples.h"
#include "tests/support/msl_tube.h"

namespace momenta {
namespace {

/// One example: its full class name, stop time (0: not given in the README), and Dymola's
/// accepted steps, state events and time events in the reference run.
struct MultiBodyExample {
  const char* name;
  double stop;
  long dymola_steps;
  int dymola_state_events, dymola_time_events;
};

void PrintTo(const MultiBodyExample& e, std::ostream* os) { *os << e.name; }

const MultiBodyExample kExamples[] = {
    // S1
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.DoublePendulum", 3, 665, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.ForceAndTorque", 1.01, 472, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.InitSpringConstant", 1.01, 23, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.Pendulum", 5, 314, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.PendulumWithSpringDamper", 10, 406, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.SpringMassSystem", 5, 330, 0, 0},
    {"ModelicaTest.MultiBody.Forces.Damper", 7, 698, 0, 0},
    {"ModelicaTest.MultiBody.Forces.Damper2", 7, 2579, 13, 42},
    {"ModelicaTest.MultiBody.Forces.Force", 1.1, 214, 0, 0},
    {"ModelicaTest.MultiBody.Forces.Force2", 1.1, 214, 0, 0},
    {"ModelicaTest.MultiBody.Forces.ForceWithTwoMasses", 3, 288, 0, 0},
    {"ModelicaTest.MultiBody.Forces.ForcesAndTorques", 1.1, 975, 0, 0},
    {"ModelicaTest.MultiBody.Forces.FrameForces", 1.1, 224, 0, 0},
    {"ModelicaTest.MultiBody.Forces.FrameForces2", 2, 774, 0, 0},
    {"ModelicaTest.MultiBody.Forces.FrameForcesAndTorques3", 2, 1846, 0, 0},
    {"ModelicaTest.MultiBody.Forces.FrameTorques", 1.1, 25, 0, 0},
    {"ModelicaTest.MultiBody.Forces.FrameTorques2", 1.1, 25, 0, 0},
    {"ModelicaTest.MultiBody.Forces.Spring", 3, 92, 0, 0},
    {"ModelicaTest.MultiBody.Forces.WorldForces2", 1.1, 196, 0, 0},
    {"ModelicaTest.MultiBody.Forces.WorldTorques", 1.1, 272, 0, 0},
    {"ModelicaTest.MultiBody.Joints.Prismatic", 1.1, 24, 0, 0},
    {"ModelicaTest.MultiBody.Joints.PrismaticInit", 5, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.Revolute", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.RevoluteInitialization", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Parts.Bodies", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Parts.FixedRotation", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Parts.FixedTranslation", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Parts.PointMass", 1.1, 89, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.AbsoluteSensor", 0, 520, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.AbsoluteSensor2", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutForce", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutForce3", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutForceAndTorque1", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutForceAndTorque3", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutTorque", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutTorque2", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.CutTorque3", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.Distance", 5, 386, 0, 0},
    {"ModelicaTest.MultiBody.Sensors.Distance2", 0.5, 277, 0, 0},
    // S2
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.DoublePendulumInitTip", 5, 1193, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.FreeBody", 10, 495, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.HeatLosses", 3, 149, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.PointGravity", 5, 556, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.PointGravityWithPointMasses", 2, 381, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.PointGravityWithPointMasses2", 3, 577, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.SpringDamperSystem", 10, 567, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.SpringWithMass", 5, 226, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.ThreeSprings", 10, 809, 0, 0},
    {"Modelica.Mechanics.MultiBody.Examples.Elementary.UserDefinedGravityField", 10, 467, 0, 0},
    {"ModelicaTest.MultiBody.Forces.Spring2", 3, 135, 0, 0},
    {"ModelicaTest.MultiBody.Frames.AngularVelocity", 1.1, 233, 0, 0},
    {"ModelicaTest.MultiBody.Joints.Cylindrical", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.FreeMotion", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.FreeMotionScalarInit", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.FreeMotionScalarInit2", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.FreeMotionScalarInit3", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.FreeMotionScalarInit4", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.Planar", 1.1, 23, 0, 0},
    {"ModelicaTest.MultiBody.Joints.Universal", 1.1, 96, 0, 0},
    {"ModelicaTest.MultiBody.Parts.BodyShape", 10, 564, 0, 0},
    {"ModelicaTest.MultiBody.SphericalDoublePendulum", 3, 1476, 0, 0},
};

/// How many of the examples have a model that passes (the count only grows).
constexpr int kMultiBodyModelled = 59;

const char kReferences[] = "tests/data/msl-multibody/";

class MslMultiBodyTest : public ::testing::TestWithParam<MultiBodyExample> {};

TEST_P(MslMultiBodyTest, WithinTheMslTube) {
  const MultiBodyExample& e = GetParam();
  const std::string model = testing::MslModelFile(e.name);
  if (!testing::SourceExists(model)) GTEST_SKIP() << "no model yet: " << model;
  testing::CheckMslExample(e.name, model, std::string(kReferences) + e.name + ".csv", testing::CsvCompareTube,
                           {e.dymola_steps, e.dymola_state_events, e.dymola_time_events});
}

std::string ExampleName(const ::testing::TestParamInfo<MultiBodyExample>& info) {
  return testing::MslTestName(info.param.name);
}

INSTANTIATE_TEST_SUITE_P(References, MslMultiBodyTest, ::testing::ValuesIn(kExamples), ExampleName);

TEST(MslMultiBodyCoverage, EveryModelledExampleIsKept) {
  int modelled = 0;
  for (const MultiBodyExample& e : kExamples) {
    if (testing::SourceExists(testing::MslModelFile(e.name))) ++modelled;
    EXPECT_TRUE(testing::SourceExists(std::string(kReferences) + e.name + ".csv")) << e.name;
  }
  std::printf("[   INFO   ] %d of %zu examples modelled\n", modelled, std::size(kExamples));
  EXPECT_EQ(std::size(kExamples), 61u);  // S1's 39 and S2's 22
  EXPECT_GE(modelled, kMultiBodyModelled);
}

}  // namespace
}  // namespace momenta

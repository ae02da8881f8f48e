// The MSL examples of Rotational, Electrical.Analog, Blocks and HeatTransfer against their
// published reference results (tests/data/msl/<Full.Name>.csv, from MAP-LIB_ReferenceResults v4.1.0,
// Dymola 2020x, DASSL, thinned to about 1 000 rows). The model of `Modelica.A.B.C` is
// models/msl/A/B/C.yaml; it runs with its own experiment (the example's stop time, tolerance and
// output interval), with rows at every event, and every reference column must lie within the
// MSL's CSV-compare tube: 2e-3 of max(range, |lowest value|, 1e-3) high, 2e-3 of the run wide in
// time, as modelica-tools/csv-compare builds it (tests/support/msl_tube.h). An example without a model yet is skipped, and counted:
// MslMoreCoverage fails when fewer than kModelled models exist, so that none goes missing.
// Each run prints its steps and events beside Dymola's (the reference run's log).

#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "tests/support/msl_examples.h"
#include "tests/support/msl_tube.h"

namespace momenta {
namespace {

/// One example: its full class name, stop time (0: not given), and Dymola's accepted steps,
/// state events and time events in the reference run.
struct MoreExample {
  const char* name;
  double stop;
  long dymola_steps;
  int dymola_state_events, dymola_time_events;
};

void PrintTo(const MoreExample& e, std::ostream* os) { *os << e.name; }

const MoreExample kExamples[] = {
    {"Modelica.Blocks.Examples.BooleanNetwork1", 10, 850, 0, 50},
    {"Modelica.Blocks.Examples.BusUsage", 2, 43, 0, 1},
    {"Modelica.Blocks.Examples.CompareSincExpSine", 1, 26, 1, 0},
    {"Modelica.Blocks.Examples.Filter", 0.9, 138, 0, 1},
    {"Modelica.Blocks.Examples.FilterWithDifferentiation", 0.9, 129, 0, 1},
    {"Modelica.Blocks.Examples.FilterWithRiseTime", 4, 113, 0, 1},
    {"Modelica.Blocks.Examples.IntegerNetwork1", 10, 655, 14, 25},
    {"Modelica.Blocks.Examples.Interaction1", 10, 190, 0, 9},
    {"Modelica.Blocks.Examples.LogicalNetwork1", 10, 172, 0, 8},
    {"Modelica.Blocks.Examples.Modulation", 1, 107, 0, 0},
    {"Modelica.Blocks.Examples.RealNetwork1", 10, 440, 0, 25},
    {"Modelica.Blocks.Examples.Rectifier12pulseFFT", 0.25, 84214, 302, 4201},
    {"Modelica.Blocks.Examples.Rectifier6pulseFFT", 0.25, 79617, 150, 4201},
    {"Modelica.Blocks.Examples.ShowLogicalSources", 10, 472, 0, 27},
    {"Modelica.Blocks.Examples.TotalHarmonicDistortion", 0.1, 1051, 0, 5},
    {"Modelica.Electrical.Analog.Examples.AD_DA_conversion", 0.2, 5200, 0, 400},
    {"Modelica.Electrical.Analog.Examples.AmplifierWithOpAmpDetailed", 0.003, 3647, 0, 0},
    {"Modelica.Electrical.Analog.Examples.CauerLowPassOPV", 60, 335, 0, 1},
    {"Modelica.Electrical.Analog.Examples.CauerLowPassSC", 60, 120724, 0, 1200},
    {"Modelica.Electrical.Analog.Examples.CharacteristicThyristors", 6, 570, 12, 18},
    {"Modelica.Electrical.Analog.Examples.ControlledSwitchWithArc", 6, 2639, 18, 0},
    {"Modelica.Electrical.Analog.Examples.DifferenceAmplifier", 1, 7601, 0, 1},
    {"Modelica.Electrical.Analog.Examples.GenerationOfFMUs", 1, 178, 0, 0},
    {"Modelica.Electrical.Analog.Examples.HeatingMOSInverter", 5, 1770, 40, 1},
    {"Modelica.Electrical.Analog.Examples.HeatingNPN_NORGate", 200, 744, 5, 21},
    {"Modelica.Electrical.Analog.Examples.HeatingPNP_NORGate", 200, 714, 5, 21},
    {"Modelica.Electrical.Analog.Examples.HeatingRectifier", 5, 545, 0, 0},
    {"Modelica.Electrical.Analog.Examples.IdealTriacCircuit", 2, 819, 16, 16},
    {"Modelica.Electrical.Analog.Examples.InvertingAmp", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.NandGate", 1e-07, 1791, 26, 16},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Adder", 1, 21, 0, 0},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Comparator", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.ControlCircuit", 1, 330, 0, 2},
    {"Modelica.Electrical.Analog.Examples.OpAmps.DifferentialAmplifier", 0.2, 1882, 0, 10},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Differentiator", 1, 2811, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.HighPass", 1, 1313, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Integrator", 1, 1147, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.InvertingAmplifier", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.InvertingSchmittTrigger", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.LCOscillator", 0.01, 438, 0, 0},
    {"Modelica.Electrical.Analog.Examples.OpAmps.LowPass", 1, 1313, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Multivibrator", 1, 1301, 0, 0},
    {"Modelica.Electrical.Analog.Examples.OpAmps.NonInvertingAmplifier", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.SchmittTrigger", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OpAmps.SignalGenerator", 1, 547, 20, 0},
    {"Modelica.Electrical.Analog.Examples.OpAmps.Subtracter", 1, 21, 0, 0},
    {"Modelica.Electrical.Analog.Examples.OpAmps.VoltageFollower", 1, 654, 10, 30},
    {"Modelica.Electrical.Analog.Examples.OvervoltageProtection", 0.4, 801, 0, 0},
    {"Modelica.Electrical.Analog.Examples.ParallelResonance", 1, 7273, 0, 1},
    {"Modelica.Electrical.Analog.Examples.Resistor", 5, 23, 0, 0},
    {"Modelica.Electrical.Analog.Examples.ResonanceCircuits", 1, 971, 0, 0},
    {"Modelica.Electrical.Analog.Examples.SeriesResonance", 1, 5257, 0, 1},
    {"Modelica.Electrical.Analog.Examples.ShowSaturatingInductor", 6.2832, 78, 0, 0},
    {"Modelica.Electrical.Analog.Examples.ShowVariableResistor", 1, 23, 0, 0},
    {"Modelica.Electrical.Analog.Examples.SimpleTriacCircuit", 0.001, 79263, 197, 61},
    {"Modelica.Electrical.Analog.Examples.SwitchWithArc", 2, 888, 2, 4},
    {"Modelica.Electrical.Analog.Examples.ThyristorBehaviourTest", 0.0002, 1032, 13, 3},
    {"Modelica.Mechanics.Rotational.Examples.Backlash", 1, 2060, 53, 0},
    {"Modelica.Mechanics.Rotational.Examples.EddyCurrentBrake", 0, 159, 0, 2},
    {"Modelica.Mechanics.Rotational.Examples.GenerationOfFMUs", 1, 366, 0, 0},
    {"Modelica.Mechanics.Rotational.Examples.LossyGearDemo1", 0.5, 169, 5, 0},
    {"Modelica.Mechanics.Rotational.Examples.LossyGearDemo2", 0.5, 178, 7, 0},
    {"Modelica.Mechanics.Rotational.Examples.LossyGearDemo3", 1, 61, 1, 1},
    {"Modelica.Mechanics.Rotational.Examples.OneWayClutchDisengaged", 2, 450, 12, 0},
    {"Modelica.Mechanics.Rotational.Examples.RollingWheel", 5, 104, 0, 1},
    {"Modelica.Mechanics.Rotational.Examples.SimpleGearShift", 5, 158, 5, 3},
    {"Modelica.Thermal.HeatTransfer.Examples.GenerationOfFMUs", 1, 89, 0, 0},
};

/// How many of the examples have a model (the count only grows).
constexpr int kModelled = 60;

class MslMoreTest : public ::testing::TestWithParam<MoreExample> {};

TEST_P(MslMoreTest, WithinTheMslTube) {
  const MoreExample& e = GetParam();
  const std::string model = testing::MslModelFile(e.name);
  if (!testing::SourceExists(model)) GTEST_SKIP() << "no model yet: " << model;
  testing::CheckMslExample(e.name, model, std::string("tests/data/msl/") + e.name + ".csv", testing::CsvCompareTube,
                           {e.dymola_steps, e.dymola_state_events, e.dymola_time_events});
}

std::string ExampleName(const ::testing::TestParamInfo<MoreExample>& info) {
  return testing::MslTestName(info.param.name);
}

INSTANTIATE_TEST_SUITE_P(References, MslMoreTest, ::testing::ValuesIn(kExamples), ExampleName);

TEST(MslMoreCoverage, EveryModelledExampleIsKept) {
  int modelled = 0;
  for (const MoreExample& e : kExamples) {
    if (testing::SourceExists(testing::MslModelFile(e.name))) ++modelled;
    EXPECT_TRUE(testing::SourceExists(std::string("tests/data/msl/") + e.name + ".csv")) << e.name;
  }
  std::printf("[   INFO   ] %d of %zu examples modelled\n", modelled, std::size(kExamples));
  EXPECT_GE(modelled, kModelled);
}

}  // namespace
}  // namespace momenta

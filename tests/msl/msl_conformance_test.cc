// MSL examples in models/msl/ against the MSL's own reference results (tests/data/msl/), with the
// models' own experiment settings:
// - ten Modelica.Mechanics.Translational examples (tolerance 1e-6, interval 5e-4 — Vehicle
//   5e-3 —, the reference's output interval), EddyCurrentBrake among them with its
//   single-precision reference;
// - six Modelica.Mechanics.MultiBody.Examples.Elementary examples whose motion lies in the x-y
//   plane, built from the planar library (tolerance 1e-6, interval StopTime/5000, the
//   reference's output interval).
//
// Criterion: the MSL's CSV-compare tube with tolerance 2e-3 — at every reference time that is
// also one of our output times, for every reference column,
//   |ours - ref| <= 2e-3 * max(1, max over time |ref| of that signal).
// Our output times are start + k*interval (plus any event rows); the reference lists event times
// (here the stop time) twice, and each of its rows is compared with our row at the same time.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Csv;
using testing::Trajectory;

/// The MSL CSV-compare tolerance (Modelica Association's regression-test default).
constexpr double kTubeTolerance = 2e-3;

std::string ModelPath(const std::string& name) { return "models/msl/" + name + ".yaml"; }

constexpr const char* kTranslational = "Modelica.Mechanics.Translational.Examples";
constexpr const char* kMultiBody = "Modelica.Mechanics.MultiBody.Examples.Elementary";

/// The reference result of the MSL example `package`.`name` (the file's name is the full class
/// name).
Csv Reference(const std::string& name, const std::string& package = kTranslational) {
  return testing::ReadCsv(testing::SourcePath("tests/data/msl/" + package + "." + name + ".csv"));
}

/// One MSL example: its package, its short name (the model file's and the test's name) and the
/// output interval of its reference, which the model's experiment must use.
struct MslExample {
  const char* package;
  const char* name;
  double interval;
  /// The reference was stored in single precision (EddyCurrentBrake): its times carry a relative
  /// error up to 2^-24, so 0.0005 reads 0.00050000002.
  bool single_precision = false;
};

std::ostream& operator<<(std::ostream& os, const MslExample& e) {
  return os << e.package << "." << e.name;
}

/// The worst point of one comparison; ratio = |error| / allowed, so ratio <= 1 passes.
struct Worst {
  double ratio = 0, abs_error = 0, allowed = 0, time = 0, ours = 0, ref = 0;
  std::string column;
  std::string ToString() const {
    std::ostringstream s;
    s << column << " at t = " << time << ": ours " << ours << ", reference " << ref << ", |error| "
      << abs_error << " (" << ratio * 100 << "% of the allowed " << allowed << ")";
    return s.str();
  }
};

/// Our rows whose time is `t` (within `eps`); rows are in time order, an event time may repeat.
std::pair<size_t, size_t> RowsAt(const Trajectory& ours, double t, double eps) {
  auto lo = std::lower_bound(ours.t.begin(), ours.t.end(), t - eps);
  auto hi = std::upper_bound(lo, ours.t.end(), t + eps);
  return {static_cast<size_t>(lo - ours.t.begin()), static_cast<size_t>(hi - ours.t.begin())};
}

/// Compares every reference column of `ref` with `ours` at the times both have; `tube(max_abs)`
/// is the allowed absolute deviation of a column whose largest |ref| is max_abs. Fails the test
/// when a reference time is missing from our output or a column is missing; `worst` receives the
/// worst point.
template <typename Tube>
void Compare(const std::string& model, const Trajectory& ours, const Csv& ref, double interval,
             Tube tube, Worst* worst, bool single_precision = false) {
  // Match each reference row to our row at the same time. Reference times are printed to 17
  // digits and ours are start + k*interval, so a match is within 1e-9 of an interval (far below
  // the grid step); a single-precision reference's times are off by up to 2^-24 of their value
  // (6e-8 s at t = 1 s), matched within 1e-7 of the largest time (still 1e-4 of a 5e-4 step at
  // t = 1 s). At a time listed more than once (an event: left and right limits), the first
  // reference row goes with our first row there and the last with our last.
  // A reference row off the output grid is a state event of the reference's (a relation's
  // crossing, located by each tool to its own resolution): it is compared only if we have a row
  // at that very time, and the grid rows on both sides of it are compared anyway.
  const double eps = single_precision ? 1e-7 * std::max(1.0, std::fabs(ref.rows.back()[0])) : 1e-9 * interval;
  constexpr size_t kSkip = SIZE_MAX;
  std::vector<size_t> row_of(ref.rows.size());
  for (size_t r = 0; r < ref.rows.size(); ++r) {
    const double t = ref.rows[r][0];
    auto [lo, hi] = RowsAt(ours, t, eps);
    const bool on_grid = std::fabs(t - std::round(t / interval) * interval) <= eps;
    if (lo == hi && !on_grid) {
      row_of[r] = kSkip;
      continue;
    }
    ASSERT_LT(lo, hi) << model << ": no output row at the reference time " << t;
    const bool first = r == 0 || std::fabs(ref.rows[r - 1][0] - t) > eps;
    row_of[r] = first ? lo : hi - 1;
  }
  *worst = Worst{};
  for (size_t c = 1; c < ref.header.size(); ++c) {
    const std::string& col = ref.header[c];
    size_t ours_col = 0;
    ASSERT_NO_THROW(ours_col = ours.Index(col)) << model << ": no output " << col;
    double max_abs = 0;
    for (const auto& row : ref.rows) max_abs = std::max(max_abs, std::fabs(row[c]));
    const double allowed = tube(max_abs);
    for (size_t r = 0; r < ref.rows.size(); ++r) {
      if (row_of[r] == kSkip) continue;
      const double mine = ours.values[row_of[r]][ours_col];
      const double err = std::fabs(mine - ref.rows[r][c]);
      if (!(err / allowed <= worst->ratio)) {  // also catches a NaN of ours
        *worst = Worst{err / allowed, err, allowed, ref.rows[r][0], mine, ref.rows[r][c], col};
      }
    }
  }
}

/// The MSL tube: 2e-3 relative to the signal's largest magnitude, absolute below 1.
double MslTube(double max_abs) { return kTubeTolerance * std::max(1.0, max_abs); }

class MslConformanceTest : public ::testing::TestWithParam<MslExample> {};

TEST_P(MslConformanceTest, WithinTheMslTube) {
  const std::string name = GetParam().name;
  Built b = testing::BuildFile(ModelPath(name));
  for (const auto& w : b.report.warnings) ADD_FAILURE() << name << ": unexpected warning: " << w;
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  // The models' own experiment: every MSL example here runs at the reference's tolerance, 1e-6,
  // and output interval (5e-4 for Translational but Vehicle's 5e-3, StopTime/5000 for MultiBody).
  ASSERT_EQ(opt.rtol, 1e-6) << name;
  ASSERT_EQ(opt.interval, GetParam().interval) << name;
  Trajectory ours = testing::Run(b, opt);
  Csv ref = Reference(name, GetParam().package);
  ASSERT_FALSE(ref.rows.empty());

  // Our rows cover the whole reference time range: in time order, from the start to the stop
  // time, with a row at every grid time start + k*interval, k = 0..N (events may add rows).
  ASSERT_FALSE(ours.t.empty());
  EXPECT_TRUE(std::is_sorted(ours.t.begin(), ours.t.end())) << name;
  EXPECT_EQ(ours.t.front(), opt.start) << name;
  EXPECT_NEAR(ours.t.back(), opt.stop, 1e-12) << name;
  EXPECT_LE(ours.t.front(), ref.rows.front()[0]) << name;
  EXPECT_GE(ours.t.back(), ref.rows.back()[0] - 1e-12) << name;
  const long num_steps = std::lround((opt.stop - opt.start) / opt.interval);
  for (long k = 0; k <= num_steps; ++k) {
    auto [lo, hi] = RowsAt(ours, opt.start + k * opt.interval, 1e-9 * opt.interval);
    if (lo == hi) {
      ADD_FAILURE() << name << ": no output row at the grid time " << opt.start + k * opt.interval;
      break;
    }
  }

  Worst worst;
  Compare(name, ours, ref, opt.interval, MslTube, &worst, GetParam().single_precision);
  RecordProperty("worst_error", worst.ToString());
  std::printf("[   INFO   ] %s: worst %s\n", name.c_str(), worst.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << name << ": outside the MSL tube: " << worst.ToString();
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
                                           MslExample{kTranslational, "EddyCurrentBrake", 5e-4, true}),
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

// The tube has teeth: WhyArrows with a 2 % stiffer spring in both oscillators (c = 11.22 instead
// of 11) shifts the frequency by 1 % and must leave the tube.
TEST(MslTubeTest, RejectsAWrongParameter) {
  const ParameterOverrides stiffer = {{"spring1.c", 11.22}, {"spring2.c", 11.22}};
  Built b = testing::BuildFile(ModelPath("WhyArrows"), stiffer);
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  Trajectory ours = testing::Run(b, opt, stiffer);
  Worst worst;
  Compare("WhyArrows with c = 11.22", ours, Reference("WhyArrows"), opt.interval, MslTube, &worst);
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
  Compare("EddyCurrentBrake with alpha20 = 0", ours, Reference("EddyCurrentBrake"), opt.interval, MslTube, &worst,
          true);
  EXPECT_GT(worst.ratio, 10.0) << worst.ToString();
}

// At a tight tolerance our InitialConditions converges to the exact solution; the reference's own
// error in sd1.v_rel and m1.v (against an independent RK4 cross-check) is 5.3e-4, so ours must
// then agree with it to 1e-3 (the reference's error plus margin for ours, ~1e-7 at rtol 1e-10).
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
  Compare("InitialConditions at rtol 1e-10", ours, only, opt.interval, [](double) { return 1e-3; },
          &worst);
  RecordProperty("worst_error", worst.ToString());
  std::printf("[   INFO   ] InitialConditions at rtol 1e-10: worst %s\n", worst.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << worst.ToString();
}

}  // namespace
}  // namespace momenta

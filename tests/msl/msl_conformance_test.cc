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
// Criterion: the MSL's CSV-compare tube with tolerance 2e-3 — at every reference time that is
// also one of our output times, for every reference column,
//   |ours - ref| <= 2e-3 * max(1, max over time |ref| of that signal),
// or, for the models with events, 2e-3 of the signal's range (max - min over time; a constant
// signal takes max(1, |ref|)), which is what a Boolean's 0/1 and PreLoad's millimetres need.
// Our output times are start + k*interval plus a left- and a right-limit row at every event (as
// the reference's events=true output); the reference lists event times twice (left, then right
// limit), and each of its rows is compared with our row at the same time. A reference event our
// solver located a little apart (within kEventTimeWindow) is compared with our rows there.

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

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Csv;
using testing::Trajectory;

/// The MSL CSV-compare tolerance (Modelica Association's regression-test default).
constexpr double kTubeTolerance = 2e-3;

/// How far apart (relative to the run's length) a reference event and ours may lie and still be
/// compared as one event: the CSV-compare tube's width in time, 2e-3 of the run. Logical's
/// switching times agree with the reference's to < 1e-9 s (its initial event, listed at
/// 1.8e-11 s, is ours at 0); PreLoad's contacts, which close or open at a crawl (5e-6 m/s),
/// within 1.5e-4 s; Vehicle's within 2e-4 s. Where such a window has no event of ours, the test
/// fails; our rows at events are checked against the reference's curve (DistanceToReference).
constexpr double kEventTimeWindow = kTubeTolerance;

std::string ModelPath(const std::string& name) { return "models/msl/" + name + ".yaml"; }

constexpr const char* kTranslational = "Modelica.Mechanics.Translational.Examples";
constexpr const char* kMultiBody = "Modelica.Mechanics.MultiBody.Examples.Elementary";
constexpr const char* kModelicaTestBlocks = "ModelicaTest.Blocks";

/// The reference result of the MSL example `package`.`name` (the file's name is the full class
/// name).
Csv Reference(const std::string& name, const std::string& package = kTranslational) {
  return testing::ReadCsv(testing::SourcePath("tests/data/msl/" + package + "." + name + ".csv"));
}

/// The allowed absolute deviation of a signal whose largest |ref| is max_abs and whose range
/// (max - min over time) is range.
using TubeWidth = double (*)(double max_abs, double range);

/// The MSL tube: 2e-3 relative to the signal's largest magnitude, absolute below 1.
double MslTube(double max_abs, double /*range*/) { return kTubeTolerance * std::max(1.0, max_abs); }

/// 2e-3 of the signal's range; a constant signal's is that of MslTube.
double RangeTube(double max_abs, double range) {
  return range > 0 ? kTubeTolerance * range : MslTube(max_abs, range);
}

/// One MSL example: its package, its short name (the model file's and the test's name), the
/// output interval of its reference, which the model's experiment must use, the tube, and the
/// reference run's event counts where MODELS.md gives them (-1: not given), printed beside ours.
struct MslExample {
  const char* package;
  const char* name;
  double interval;
  TubeWidth tube = MslTube;
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

/// Our rows at the event (a time listed more than once) nearest to `t` within `window`; an empty
/// range when there is none.
std::pair<size_t, size_t> EventRowsNear(const Trajectory& ours, double t, double window) {
  auto [lo, hi] = RowsAt(ours, t, window);
  std::pair<size_t, size_t> best{0, 0};
  double best_dt = window;
  for (size_t k = lo; k + 1 < hi; ++k) {
    if (ours.t[k + 1] != ours.t[k] || std::fabs(ours.t[k] - t) > best_dt) continue;
    best_dt = std::fabs(ours.t[k] - t);
    best = RowsAt(ours, ours.t[k], 0);
  }
  return best;
}

/// The distance from v to the reference column c's curve within [t - window, t + window]: the
/// CSV-compare tube's rectangle. The curve joins the reference rows by straight lines (a time
/// listed twice, an event, joins its left and right limits by a vertical one).
double DistanceToReference(const Csv& ref, size_t c, double t, double v, double window) {
  double best = HUGE_VAL;
  for (size_t r = 0; r + 1 < ref.rows.size(); ++r) {
    const double t0 = ref.rows[r][0], t1 = ref.rows[r + 1][0];
    const double a = std::max(t0, t - window), b = std::min(t1, t + window);
    if (a > b) continue;
    const double v0 = ref.rows[r][c], v1 = ref.rows[r + 1][c];
    const double va = t1 > t0 ? v0 + (v1 - v0) * (a - t0) / (t1 - t0) : v0;
    const double vb = t1 > t0 ? v0 + (v1 - v0) * (b - t0) / (t1 - t0) : v1;
    const double lo = std::min(va, vb), hi = std::max(va, vb);
    best = std::min(best, v < lo ? lo - v : v > hi ? v - hi : 0.0);
  }
  return best;
}

/// Compares every reference column of `ref` with `ours`; `tube(max_abs, range)` is the allowed
/// absolute deviation of a column. Fails the test when a reference time is missing from our
/// output or a column is missing; `worst` receives the worst point.
template <typename Tube>
void Compare(const std::string& model, const Trajectory& ours, const Csv& ref, double interval,
             Tube tube, Worst* worst, bool single_precision = false,
             const std::string& settle_column = "", double settle_until = 0) {
  // Match each reference row to our row at the same time. Reference times are printed to 17
  // digits and ours are start + k*interval, so a match is within 1e-9 of an interval (far below
  // the grid step); a single-precision reference's times are off by up to 2^-24 of their value
  // (6e-8 s at t = 1 s), matched within 1e-7 of the largest time (still 1e-4 of a 5e-4 step at
  // t = 1 s). At a time listed more than once (an event: left and right limits), the
  // first reference row goes with our first row there and the last with our last. A reference
  // event off our grid must have an event of ours within kEventTimeWindow; its rows are not
  // paired (the two events' times differ), our rows there are checked against the reference's
  // curve below instead.
  // Rows within 1e-11 of the time's magnitude are at the same time: an event that both tools put
  // on a grid time (the Brake's stop at t = 1.1, ours 1e-12 s later) is located by each to its
  // own resolution; two events 7e-11 s apart (Friction's breakaway and mode = Forward) stay two.
  const double eps = single_precision ? 1e-7 * std::max(1.0, std::fabs(ref.rows.back()[0])) : 1e-9 * interval;
  auto eps_at = [&](double t) { return std::max(eps, 1e-11 * std::max(1.0, std::fabs(t))); };
  const double window = kEventTimeWindow * (ref.rows.back()[0] - ref.rows.front()[0]);
  constexpr size_t kUnpaired = static_cast<size_t>(-1);
  std::vector<size_t> row_of(ref.rows.size(), kUnpaired);
  std::vector<std::pair<size_t, size_t>> instant_of(ref.rows.size(), {0, 0});  // a middle row's
  std::vector<bool> paired(ours.t.size(), false);
  double event_offset = 0;
  for (size_t r = 0; r < ref.rows.size(); ++r) {
    const double t = ref.rows[r][0];
    auto [lo, hi] = RowsAt(ours, t, eps_at(t));
    if (lo == hi) {
      auto [elo, ehi] = EventRowsNear(ours, t, window);
      ASSERT_LT(elo, ehi) << model << ": no output row at the reference time " << t
                          << " and no event of ours within " << window << " s";
      event_offset = std::max(event_offset, std::fabs(ours.t[elo] - t));
      continue;
    }
    // The reference's first row is after its initial event iteration (a friction element that
    // starts sliding shows mode = Backward and startBackward = false there), so it goes with our
    // last row at the start time; our first there holds the values the initialisation solved.
    // The rows of one instant: the reference's first goes with our first, its last with our
    // last, and one between them (a grid time a fraction of a picosecond before an event: the
    // grid row, then the event's left limit) with the nearest of ours there.
    const bool first = r == 0 || std::fabs(ref.rows[r - 1][0] - t) > eps_at(t);
    const bool last = r + 1 == ref.rows.size() || std::fabs(ref.rows[r + 1][0] - t) > eps_at(t);
    const bool single_start_row = r == 0 && last;
    row_of[r] = first && !single_start_row ? lo : hi - 1;
    if (!first && !last) instant_of[r] = {lo, hi};
    for (size_t k = lo; k < hi; ++k) paired[k] = true;
  }
  if (event_offset > 0) {
    std::printf("[   INFO   ] %s: reference events off our grid have ours within %.3g s\n",
                model.c_str(), event_offset);
  }
  *worst = Worst{};
  for (size_t c = 1; c < ref.header.size(); ++c) {
    const std::string& col = ref.header[c];
    size_t ours_col = 0;
    ASSERT_NO_THROW(ours_col = ours.Index(col)) << model << ": no output " << col;
    double max_abs = 0, lowest = HUGE_VAL, highest = -HUGE_VAL;
    for (const auto& row : ref.rows) {
      max_abs = std::max(max_abs, std::fabs(row[c]));
      lowest = std::min(lowest, row[c]);
      highest = std::max(highest, row[c]);
    }
    const double allowed = tube(max_abs, highest - lowest);
    auto record = [&](double err, double t, double mine, double theirs) {
      if (!(err / allowed <= worst->ratio)) {  // also catches a NaN of ours
        *worst = Worst{err / allowed, err, allowed, t, mine, theirs, col};
      }
    };
    // Rows at the same time: their difference (a settling column's early rows: the distance to
    // the reference's curve, as below).
    const bool settling = col == settle_column;
    for (size_t r = 0; r < ref.rows.size(); ++r) {
      if (row_of[r] == kUnpaired) continue;
      const double mine = ours.values[row_of[r]][ours_col];
      if (settling && ref.rows[r][0] < settle_until) {
        const double d = DistanceToReference(ref, c, ours.t[row_of[r]], mine, window);
        record(d, ours.t[row_of[r]], mine, mine - d);
        continue;
      }
      auto [ilo, ihi] = instant_of[r];
      size_t best = row_of[r];
      for (size_t k = ilo; k < ihi; ++k) {
        if (std::fabs(ours.values[k][ours_col] - ref.rows[r][c]) < std::fabs(ours.values[best][ours_col] - ref.rows[r][c])) best = k;
      }
      const double nearest = ours.values[best][ours_col];
      record(std::fabs(nearest - ref.rows[r][c]), ref.rows[r][0], nearest, ref.rows[r][c]);
    }
    // Our rows at times the reference does not list (events): inside the tube around the
    // reference's curve (the reported "reference" value is ours less the distance).
    for (size_t k = 0; k < ours.t.size(); ++k) {
      if (paired[k] || ours.t[k] < ref.rows.front()[0] || ours.t[k] > ref.rows.back()[0]) continue;
      const double mine = ours.values[k][ours_col];
      const double d = DistanceToReference(ref, c, ours.t[k], mine, window);
      record(d, ours.t[k], mine, mine - d);
    }
  }
}

class MslConformanceTest : public ::testing::TestWithParam<MslExample> {};

TEST_P(MslConformanceTest, WithinTheMslTube) {
  const std::string name = GetParam().name;
  Built b = testing::BuildFile(ModelPath(name));
  for (const auto& w : b.report.warnings) ADD_FAILURE() << name << ": unexpected warning: " << w;
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  // The models' own experiment: every MSL example here runs at the reference's tolerance, 1e-6,
  // and output interval (5e-4 for Translational but Vehicle's 5e-3, StopTime/5000 for MultiBody);
  // rows at every event, as the reference has them.
  ASSERT_EQ(opt.rtol, 1e-6) << name;
  ASSERT_EQ(opt.interval, GetParam().interval) << name;
  opt.rows_at_every_event = true;
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
  const MslExample& e = GetParam();
  Compare(name, ours, ref, opt.interval, e.tube, &worst, e.single_precision,
          e.settle_column ? e.settle_column : "", e.settle_until);
  RecordProperty("worst_error", worst.ToString());
  std::printf("[   INFO   ] %s: worst %s\n", name.c_str(), worst.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << name << ": outside the MSL tube: " << worst.ToString();
  if (GetParam().ref_state_events >= 0) {
    std::printf("[   INFO   ] %s: %ld state events and %ld time events (reference: %d and %d)\n",
                name.c_str(), ours.stats.events - ours.stats.time_events, ours.stats.time_events,
                GetParam().ref_state_events, GetParam().ref_time_events);
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
                                           MslExample{kTranslational, "EddyCurrentBrake", 5e-4, MslTube, -1, -1, true}),
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
                         ::testing::Values(MslExample{kModelicaTestBlocks, "Logical", 2e-3, RangeTube, 38, 10},
                                           MslExample{kTranslational, "PreLoad", 0.05, RangeTube, 7, 0},
                                           MslExample{kTranslational, "Friction", 5e-4, RangeTube, 18, 0},
                                           MslExample{kTranslational, "Brake", 5e-4, RangeTube, 1, 1},
                                           MslExample{kTranslational, "HeatLosses", 5e-4, RangeTube, 41, 0, false,
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
  Compare("PreLoad with friction.d = 2750", ours, Reference("PreLoad"), opt.interval, RangeTube, &worst);
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
  Compare("InitialConditions at rtol 1e-10", ours, only, opt.interval, [](double, double) { return 1e-3; },
          &worst);
  RecordProperty("worst_error", worst.ToString());
  std::printf("[   INFO   ] InitialConditions at rtol 1e-10: worst %s\n", worst.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << worst.ToString();
}

}  // namespace
}  // namespace momenta

#pragma once
// The MSL's CSV-compare tube, as the conformance tests (tests/msl/) apply it: our result, with rows
// at every event, against a published reference result of the same example.

#include <functional>
#include <string>

#include "tests/support/test_models.h"

namespace momenta::testing {

/// The MSL CSV-compare tolerance (Modelica Association's regression-test default).
constexpr double kTubeTolerance = 2e-3;

/// How far apart (relative to the run's length) a reference event and ours may lie and still be
/// compared as one event: the CSV-compare tube's width in time, 2e-3 of the run. Logical's
/// switching times agree with the reference's to < 1e-9 s (its initial event, listed at
/// 1.8e-11 s, is ours at 0); PreLoad's contacts, which close or open at a crawl (5e-6 m/s),
/// within 1.5e-4 s; Vehicle's within 2e-4 s. Where such a window has no event of ours, the test
/// fails; our rows at events are checked against the reference's curve (DistanceToReference).
constexpr double kEventTimeWindow = kTubeTolerance;

/// The allowed absolute deviation (the tube's half height) of a signal whose range (max - min
/// over time) is range and whose lowest value is lowest.
using TubeWidth = double (*)(double range, double lowest);

/// CSV-compare's tube as the MSL's regression tests run it (modelica-tools/csv-compare,
/// CsvFile.cs: TubeSize with the legacy base and the default nominal value 1e-3): 2e-3 of
/// max(range, |lowest|, 1e-3). Until 2026-11-28 the harness used 2e-3 * max(1, max |ref|), with
/// no width in time: 500 times too loose for a signal of milliamperes, too strict for a steep one.
double CsvCompareTube(double range, double lowest);


/// The worst point of one comparison; ratio = |error| / allowed, so ratio <= 1 passes.
struct Worst {
  double ratio = 0, abs_error = 0, allowed = 0, time = 0, ours = 0, ref = 0;
  std::string column;
  std::string ToString() const;
};

/// Compares every reference column of `ref` with `ours`; `tube(range, lowest)` is the allowed
/// absolute deviation of a column. Fails the test when a reference time is missing from our
/// output or a column is missing; `worst` receives the worst point.
///
/// The tube is CSV-compare's (modelica-tools/csv-compare, Tube.Validate, as the MSL's regression
/// tests run it): a rectangle 2 * tube(range, lowest) high and 2 * kEventTimeWindow of the run wide swept
/// along the reference's curve (rows joined by straight lines, an event's two rows by a vertical
/// one), and each of our rows at a reference time or an event must lie inside it. With
/// `same_time`, the stricter comparison: our row at each reference time against that row's value
/// (no width in time), as the harness applied it before 2026-11-28; the tests of the harness's
/// row pairing use it, and CheckAgainstReference prints its figure beside the MSL's.
void Compare(const std::string& model, const Trajectory& ours, const Csv& ref, double interval,
             const std::function<double(double, double)>& tube, Worst* worst, bool single_precision = false,
             const std::string& settle_column = "", double settle_until = 0, bool same_time = false);

/// How one example is checked: the model's experiment must have this tolerance and output
/// interval (0: whatever it has), and the tube and settling as Compare takes them.
struct TubeCheck {
  double rtol = 1e-6;
  double interval = 0;
  TubeWidth tube = CsvCompareTube;
  bool single_precision = false;
  std::string settle_column;
  double settle_until = 0;
};

/// Builds `model_file` (relative to the source tree), runs it with its own experiment and rows at
/// every event, checks that the rows cover the reference's time range and every grid time, and
/// compares it with `reference` (ADD_FAILUREs, and the worst point printed); returns the worst
/// point (ratio > 1: outside the tube). `stats` receives the run's statistics when not null.
Worst CheckAgainstReference(const std::string& label, const std::string& model_file, const Csv& reference,
                            const TubeCheck& check, SolverStats* stats = nullptr);

}  // namespace momenta::testing

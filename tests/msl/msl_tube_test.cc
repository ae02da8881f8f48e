// The CSV-compare harness's pairing of rows at events (tests/support/msl_tube.h), on synthetic
// results whose exact answer is known: our result equals the reference's curve, so every ratio
// must be ~0; a row paired with one at another time shows as a ratio far above 1 in the
// same-time comparison (the MSL tube's width in time would hide it), which these tests use.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "tests/support/msl_tube.h"

namespace momenta::testing {
namespace {

/// Rows t = start + k*interval (k = 0..n) of f, with the event te listed twice (left and right
/// limits: f_left(te), f(te)); every `thin`-th grid row only (the references are thinned).
struct Rows {
  std::vector<double> t;
  std::vector<double> y;
};
Rows Sample(double interval, long n, long thin, double te, const std::function<double(double)>& f,
            const std::function<double(double)>& f_left) {
  Rows r;
  bool event_done = false;
  for (long k = 0; k <= n; k += thin) {
    const double t = k * interval;
    if (!event_done && te <= t) {
      r.t.insert(r.t.end(), {te, te});
      r.y.insert(r.y.end(), {f_left(te), f(te)});
      event_done = true;
      if (te == t) continue;  // an event on a grid time: its two rows are the grid time's
    }
    r.t.push_back(t);
    r.y.push_back(t < te ? f_left(t) : f(t));
  }
  return r;
}

Trajectory Ours(const Rows& r) {
  Trajectory ours;
  ours.t = r.t;
  ours.names = {"y"};
  for (double y : r.y) ours.values.push_back({y});
  return ours;
}

Csv Reference(const Rows& r) {
  Csv ref;
  ref.header = {"time", "y"};
  for (size_t k = 0; k < r.t.size(); ++k) ref.rows.push_back({r.t[k], r.y[k]});
  return ref;
}

// NandGate's case: a 1e-7 s run on a 2e-11 s grid, a 5 V/ns ramp (tube 0.01 V) with a mode
// change at 8.2437e-10 s, 4.4e-12 s after a grid time. A window of an absolute 1e-11 s paired
// the reference's left limit with our grid row 4.4e-12 s earlier: 0.022 V off, ratio 2.2.
TEST(MslTubePairingTest, EventsOfAShortRunAreNotMergedWithGridRows) {
  const double interval = 2e-11, te = 8.2437694621148e-10;
  auto ramp = [](double t) { return std::min(5.0, 5e9 * t); };
  Rows ours = Sample(interval, 5000, 1, te, ramp, ramp);
  Rows ref = Sample(interval, 5000, 6, te, ramp, ramp);
  Worst worst;
  Compare("short run", Ours(ours), Reference(ref), interval, CsvCompareTube, &worst, false, "", 0, /*same_time=*/true);
  EXPECT_LT(worst.ratio, 1e-3) << worst.ToString();
}

// LossyGearDemo1's case: a 0.5 s run on a 1e-3 s grid, a mode that goes from 0 to -1 at once,
// ours at 4.75e-13 s, the reference's at 4.75e-11 s. The reference's row at t = 0 (mode 0) must
// go with our row at t = 0, not with our row after our event (mode -1: ratio 500).
TEST(MslTubePairingTest, AnEventJustAfterTheStartIsNotTheStart) {
  const double interval = 1e-3;
  auto mode = [](double) { return -1.0; };
  auto before = [](double) { return 0.0; };
  Rows ours = Sample(interval, 500, 1, 4.75e-13, mode, before);
  Rows ref = Sample(interval, 500, 1, 4.75e-11, mode, before);
  Worst worst;
  Compare("event after the start", Ours(ours), Reference(ref), interval, CsvCompareTube, &worst, false, "", 0, /*same_time=*/true);
  EXPECT_LT(worst.ratio, 1e-3) << worst.ToString();
}

// The window still joins what one instant is in both tools: an event both put on a grid time,
// ours 1e-12 s after it at t = 1.1 s (the Brake's stop), and ours 5e-14 s after the
// reference's at t = 0.01 s; a signal that steps there, so a row paired across the step fails.
TEST(MslTubePairingTest, AnEventOnAGridTimeIsOneInstant) {
  const double interval = 1e-3;
  for (double te : {1.1, 0.01}) {
    auto after = [](double) { return 1.0; };
    auto before = [](double) { return 0.0; };
    Rows ref = Sample(interval, 2000, 1, te, after, before);
    Rows ours = ref;
    // Ours: the grid row at te (the left limit), then the event 1e-12 (5e-14) s later.
    const double shift = te > 1 ? 1e-12 : 5e-14;
    const auto at = std::find(ours.t.begin(), ours.t.end(), te) - ours.t.begin();
    ours.t.insert(ours.t.begin() + at + 1, te + shift);
    ours.y.insert(ours.y.begin() + at + 1, 0.0);
    ours.t[at + 2] += shift;
    Worst worst;
    Compare("event on a grid time", Ours(ours), Reference(ref), interval, CsvCompareTube, &worst, false, "", 0, /*same_time=*/true);
    EXPECT_LT(worst.ratio, 1e-3) << te << ": " << worst.ToString();
  }
}

// The MSL tube's width in time (CSV-compare's rectangle, 2e-3 of the run): a steep swing shifted
// in time by a quarter of the width is inside it however steep (AbsoluteSensor's angular
// accelerations, -213 to +227 rad/s2 in 12 ms, shifted 3e-5 s); shifted by twice the width it is
// outside. The same-time comparison flags the small shift too.
TEST(MslTubeWidthTest, AShiftInTimeWithinTheWidthPassesAndBeyondItFails) {
  const double interval = 1e-3, stop = 5.0, width = kEventTimeWindow * stop;  // 0.01 s
  auto swing = [](double t) { return 200 * std::tanh((t - 2.5) / 0.003); };
  auto shifted = [&](double shift) {
    return [=](double t) { return 200 * std::tanh((t - shift - 2.5) / 0.003); };
  };
  Rows ref = Sample(interval, 5000, 5, 1e9, swing, swing);
  for (auto [shift, msl_inside] : {std::pair{0.25 * width, true}, std::pair{2 * width, false}}) {
    auto f = shifted(shift);
    Rows ours = Sample(interval, 5000, 1, 1e9, f, f);
    Worst msl, same;
    Compare("shifted", Ours(ours), Reference(ref), interval, CsvCompareTube, &msl);
    Compare("shifted", Ours(ours), Reference(ref), interval, CsvCompareTube, &same, false, "", 0, /*same_time=*/true);
    EXPECT_EQ(msl.ratio <= 1, msl_inside) << shift << ": " << msl.ToString();
    EXPECT_GT(same.ratio, 10) << shift << ": " << same.ToString();
  }
}

}  // namespace
}  // namespace momenta::testing

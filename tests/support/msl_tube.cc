// The MSL's CSV-compare tube (tests/support/msl_tube.h).

#include "tests/support/msl_tube.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>
#include <vector>

namespace momenta::testing {

double CsvCompareTube(double range, double lowest) {
  return kTubeTolerance * std::max({range, std::fabs(lowest), 1e-3});
}


std::string Worst::ToString() const {
  std::ostringstream s;
  s << column << " at t = " << time << ": ours " << ours << ", reference " << ref << ", |error| "
    << abs_error << " (" << ratio * 100 << "% of the allowed " << allowed << ")";
  return s.str();
}

namespace {

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
  // The first segment that can reach the window: the one that ends at the first row at or after
  // t - window (rows are in time order).
  auto first = std::lower_bound(ref.rows.begin(), ref.rows.end(), t - window,
                                [](const std::vector<double>& row, double x) { return row[0] < x; });
  size_t r = first == ref.rows.begin() ? 0 : static_cast<size_t>(first - ref.rows.begin()) - 1;
  for (; r + 1 < ref.rows.size() && ref.rows[r][0] <= t + window; ++r) {
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

/// Whether reference row r and a neighbour are at the same time with every value the same (to 1e-12).
bool SameValuesAtOneInstant(const Csv& ref, size_t r) {
  // The same to rounding: Dymola's restart when its dynamic state set switches lists the instant
  // twice with a quaternion element 4e-15 apart (SphericalDoublePendulum's at t = 0.3444).
  auto same = [&](size_t a, size_t b) {
    if (ref.rows[a][0] != ref.rows[b][0]) return false;
    for (size_t c = 1; c < ref.rows[a].size(); ++c) {
      const double x = ref.rows[a][c], y = ref.rows[b][c];
      if (!(std::fabs(x - y) <= 1e-12 * std::max({1.0, std::fabs(x), std::fabs(y)}))) return false;
    }
    return true;
  };
  return (r > 0 && same(r - 1, r)) || (r + 1 < ref.rows.size() && same(r + 1, r));
}

/// True when our row k is an output grid row (start + j*interval, to 1e-9 of an interval) and
/// the only row at its time (not an event's left or right limit).
bool OnGridAlone(const Trajectory& ours, size_t k, double interval) {
  const double t = ours.t[k], start = ours.t.front();
  const double grid = start + std::round((t - start) / interval) * interval;
  if (std::fabs(t - grid) > 1e-9 * interval) return false;
  const bool repeated_before = k > 0 && ours.t[k - 1] == t;
  const bool repeated_after = k + 1 < ours.t.size() && ours.t[k + 1] == t;
  return !repeated_before && !repeated_after;
}

}  // namespace

void Compare(const std::string& model, const Trajectory& ours, const Csv& ref, double interval,
             const std::function<double(double, double)>& tube, Worst* worst, bool single_precision,
             const std::string& settle_column, double settle_until, bool same_time) {
  // Match each reference row to our rows at the same time. Rows within 1e-11 of the time's
  // magnitude are at the same time: grid times (start + k*interval in both tools, printed to 17
  // digits) agree to < 1e-15 of t; an event that both tools put on a grid time (the Brake's stop
  // at t = 1.1, ours 1e-12 s later) is located by each to its own resolution; two events 7e-11 s
  // apart (Friction's breakaway and mode = Forward) stay two. Near t = 0 the time's magnitude
  // gives no scale and the run's does: the output interval, a fixed fraction of the run (1/500
  // by the MSL's default, 1/5000 in the finest references), so the window never exceeds 1e-11
  // of an output interval there. An absolute floor (it was 1e-11 s) merges a 1e-7 s run's events
  // with grid rows 4e-12 s away (NandGate's grid is 2e-11 s) and an event 5e-13 s after the
  // start with the start (LossyGearDemo1). A single-precision reference's times are off by up to
  // 2^-24 of their value (6e-8 s at t = 1 s), matched within 1e-7 of the largest time (still
  // 1e-4 of a 5e-4 step at t = 1 s). At a time listed more than once (an event: left and right
  // limits), the first reference row goes with our first row there and the last with our last.
  // A reference event off our grid must have an event of ours within kEventTimeWindow; its rows
  // are not paired (the two events' times differ), our rows there are checked against the
  // reference's curve below instead.
  const double span = ref.rows.back()[0] - ref.rows.front()[0];
  const double eps = single_precision ? 1e-7 * std::max(1.0, std::fabs(ref.rows.back()[0])) : 0.0;
  auto eps_at = [&](double t) { return std::max(eps, 1e-11 * std::max(interval, std::fabs(t))); };
  const double window = kEventTimeWindow * span;
  constexpr size_t kUnpaired = static_cast<size_t>(-1);
  std::vector<size_t> row_of(ref.rows.size(), kUnpaired);
  std::vector<std::pair<size_t, size_t>> instant_of(ref.rows.size(), {0, 0});  // a middle row's
  std::vector<bool> paired(ours.t.size(), false);
  double event_offset = 0;
  for (size_t r = 0; r < ref.rows.size(); ++r) {
    const double t = ref.rows[r][0];
    auto [lo, hi] = RowsAt(ours, t, eps_at(t));
    if (lo == hi) {
      // An instant listed twice with the same values (Dymola's restart when its dynamic state
      // selection switches, AngularVelocity's at t = 0.5460961) jumps nowhere: its rows are
      // points of the reference's curve, against which our rows at events are checked below.
      if (SameValuesAtOneInstant(ref, r)) continue;
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
  const size_t start_rows_skipped = row_of[0] == kUnpaired ? 0 : row_of[0];  // see below
  *worst = Worst{};
  for (size_t c = 1; c < ref.header.size(); ++c) {
    const std::string& col = ref.header[c];
    size_t ours_col = 0;
    ASSERT_NO_THROW(ours_col = ours.Index(col)) << model << ": no output " << col;
    double lowest = HUGE_VAL, highest = -HUGE_VAL;
    for (const auto& row : ref.rows) {
      lowest = std::min(lowest, row[c]);
      highest = std::max(highest, row[c]);
    }
    const double allowed = tube(highest - lowest, lowest);
    auto record = [&](double err, double t, double mine, double theirs) {
      if (!(err / allowed <= worst->ratio)) {  // also catches a NaN of ours
        *worst = Worst{err / allowed, err, allowed, t, mine, theirs, col};
      }
    };
    // The MSL's tube (CSV-compare's Tube.Validate): every row of ours lies within the
    // rectangle swept along the reference's curve, 2e-3 of the run wide in time.
    // Where the reference lists its start time once (after its initial event iteration), our
    // rows there before the last (the values the initialisation solved) are not compared.
    if (!same_time) {
      for (size_t k = 0; k < ours.t.size(); ++k) {
        if (!paired[k] || k < start_rows_skipped) continue;
        const double mine = ours.values[k][ours_col];
        const double d = DistanceToReference(ref, c, ours.t[k], mine, window);
        record(d, ours.t[k], mine, mine - d);
      }
    }
    // At the same time (no width in time): rows at the same time, their difference (a settling
    // column's early rows: the distance to the reference's curve, as below).
    const bool settling = col == settle_column;
    for (size_t r = 0; same_time && r < ref.rows.size(); ++r) {
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
    // reference's curve (the reported "reference" value is ours less the distance). A single row
    // of ours on the output grid is a grid row the thinned reference left out: the straight line
    // between the reference's rows either side of it is no reference value where the curve bends
    // (ForcesAndTorques' Revolute4.w peaks at 459.13 rad/s, converged to 1e-12, between rows of
    // 453.14 and 398.85), and ours less that line is our own curvature, not an error: such rows
    // are not compared. The rows that are compared bound ours between them all the same. Our
    // rows at events are compared (PreLoad with 10 % more damping leaves the tube there).
    for (size_t k = 0; k < ours.t.size(); ++k) {
      if (paired[k] || ours.t[k] < ref.rows.front()[0] || ours.t[k] > ref.rows.back()[0]) continue;
      if (OnGridAlone(ours, k, interval)) continue;
      const double mine = ours.values[k][ours_col];
      const double d = DistanceToReference(ref, c, ours.t[k], mine, window);
      record(d, ours.t[k], mine, mine - d);
    }
  }
}


Worst CheckAgainstReference(const std::string& label, const std::string& model_file, const Csv& ref,
                            const TubeCheck& check, SolverStats* stats) {
  Worst worst;
  worst.ratio = HUGE_VAL;
  Built b = BuildFile(model_file);
  for (const auto& w : b.report.warnings) ADD_FAILURE() << label << ": unexpected warning: " << w;
  SimulationOptions opt = OptionsFromExperiment(b.model->experiment);
  if (check.rtol > 0) EXPECT_EQ(opt.rtol, check.rtol) << label;
  if (check.interval > 0) EXPECT_EQ(opt.interval, check.interval) << label;
  opt.rows_at_every_event = true;
  Trajectory ours = Run(b, opt);
  if (stats) *stats = ours.stats;
  if (ref.rows.empty()) {
    ADD_FAILURE() << label << ": the reference has no rows";
    return worst;
  }
  // Our rows cover the whole reference time range: in time order, from the start to the stop
  // time, with a row at every grid time start + k*interval, k = 0..N (events may add rows).
  if (ours.t.empty()) {
    ADD_FAILURE() << label << ": no output rows";
    return worst;
  }
  EXPECT_TRUE(std::is_sorted(ours.t.begin(), ours.t.end())) << label;
  EXPECT_EQ(ours.t.front(), opt.start) << label;
  EXPECT_NEAR(ours.t.back(), opt.stop, 1e-12) << label;
  EXPECT_LE(ours.t.front(), ref.rows.front()[0]) << label;
  EXPECT_GE(ours.t.back(), ref.rows.back()[0] - 1e-12 * std::max(1.0, std::fabs(opt.stop))) << label;
  const long num_steps = std::lround((opt.stop - opt.start) / opt.interval);
  for (long k = 0; k <= num_steps; ++k) {
    auto [lo, hi] = RowsAt(ours, opt.start + k * opt.interval, 1e-9 * opt.interval);
    if (lo == hi) {
      ADD_FAILURE() << label << ": no output row at the grid time " << opt.start + k * opt.interval;
      break;
    }
  }
  // The stricter figure first, for the record: each of our rows against the reference's row at
  // the same time; then the MSL's tube, which the example must pass.
  Worst same_time;
  Compare(label, ours, ref, opt.interval, check.tube, &same_time, check.single_precision, check.settle_column,
          check.settle_until, /*same_time=*/true);
  Compare(label, ours, ref, opt.interval, check.tube, &worst, check.single_precision, check.settle_column,
          check.settle_until);
  ::testing::Test::RecordProperty("worst_error", worst.ToString());
  ::testing::Test::RecordProperty("worst_error_same_time", same_time.ToString());
  std::printf("[   INFO   ] %s: worst %s\n", label.c_str(), worst.ToString().c_str());
  std::printf("[   INFO   ] %s: at the same time %s\n", label.c_str(), same_time.ToString().c_str());
  EXPECT_LE(worst.ratio, 1.0) << label << ": outside the MSL tube: " << worst.ToString();
  return worst;
}

}  // namespace momenta::testing

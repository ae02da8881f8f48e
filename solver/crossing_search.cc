// The crossing search: where a frozen relation switches, or an open contact closes, inside a step.
//
// Between events every relation outside noEvent() keeps the value it had after the last event
// (docs/FORMAT.md, "Events"). Its zero-crossing function z = a - b is watched on IDA's
// interpolant at the end of each step and at kInteriorSamples interior points, so a sign change
// inside a step is not missed however large the step. Between two samples z is modelled by the
// cubic through its values and time derivatives (crossing_model.h) and sampled again where that
// cubic dips more than halfway to zero, so a crossing there and back between samples is found too
// (README, "Events and impacts", says when); an open contact's gap is watched the same way, with
// the contact's velocity as its rate. The crossing is then located by bisection on the
// interpolant (on whether anything has switched, which covers every condition and contact at
// once), and the event placed just past it.
//
// Relations of time alone that are affine in it (Step, Ramp, startTime) are not searched for:
// their times are computed and hit exactly as IDA stop times (NextTimeEvent).

#include "solver/crossing_search.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/crossing_model.h"
#include "solver/ida_session.h"
#include "solver/impacts.h"

namespace momenta {

namespace {

/// Samples of the zero-crossing functions inside each step: the end and three interior points.
constexpr int kInteriorSamples = 3;

/// Extra samples per step where the cubic models of the crossing functions point to a dip, and
/// how often an interval may be split.
constexpr int kMaxRefinements = 32, kMaxDepth = 12;

/// Condition i is a time event whose time is computed exactly (affine in time): never sampled.
bool Scheduled(const CompiledModel& model, const IntegrationState& run, size_t i) {
  return model.conditions[i].time_only && i < run.affine_in_time.size() && run.affine_in_time[i];
}

/// Whether condition i is watched with a cubic model: it has a time derivative, is not an
/// equality, and is not scheduled as a time event.
bool WatchedByCubic(const CompiledModel& model, const IntegrationState& run, size_t i) {
  const auto& c = model.conditions[i];
  return c.has_rate && c.op != Op::kEq && c.op != Op::kNe && !Scheduled(model, run, i);
}

/// Whether an open contact's gap has closed while it approaches, at (t, run->y, run->y').
bool ContactCloses(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (model.impacts.empty()) return false;
  run->contacts.Evaluate(state, t, run->y.data(), run->yp.data());
  const double* discrete = state->discrete();
  for (size_t k = 0; k < model.impacts.size(); ++k) {
    if (discrete[model.impacts[k].contact] != 0) continue;
    if (run->contacts.gap(k) < 0 && run->contacts.velocity(k) < -kVelocityBand) return true;
  }
  return false;
}

/// An open contact whose gap is closed in run.contacts (as ContactCloses left them), or -1.
int OverlappingContact(const CompiledModel& model, const ModelState& state, const IntegrationState& run) {
  const double* discrete = state.discrete();
  for (size_t k = 0; k < model.impacts.size(); ++k) {
    if (discrete[model.impacts[k].contact] == 0 && run.contacts.gap(k) < -kGapBand) return static_cast<int>(k);
  }
  return -1;
}

/// Whether, at time t (interpolated), some condition or contact has switched.
bool Crossed(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  Interpolate(run, t);
  if (run->num_conditions) {
    std::vector<double>& z = run->crossing_values;
    state->ZeroCrossings(t, run->y.data(), run->yp.data(), z.data());
    const double* conditions = state->conditions();
    for (size_t i = 0; i < run->num_conditions; ++i) {
      if (Scheduled(model, *run, i)) continue;  // scheduled exactly
      bool now = RelationHolds(model.conditions[i].op, z[i]);
      // A relation the last event set by its rate (at zero, within the band the event
      // iteration counts as zero) stays set while its function creeps across zero there.
      const bool set_by_rate = i < run->moving_at_zero.size() && run->moving_at_zero[i];
      if (now != (conditions[i] != 0) && std::fabs(z[i]) > (set_by_rate ? 4 : 1) * RoundingBand(*run, i)) {
        return true;
      }
    }
  }
  return ContactCloses(model, state, run, t);
}

/// Bisection on "crossed or not", shrinking [lo, hi] until it is below the time resolution (about
/// 50 halvings of a step); the event is placed at hi, where the switch has happened. Regula falsi
/// on the crossing functions' values would take fewer, but would place events elsewhere at
/// rounding.
double Locate(const CompiledModel& model, ModelState* state, IntegrationState* run, double lo, double hi) {
  const double tol = 100 * 2.2e-16 * (std::fabs(hi) + std::fabs(hi - lo)) + 1e-15;
  for (int it = 0; it < 200 && hi - lo > tol; ++it) {
    double mid = 0.5 * (lo + hi);
    if (Crossed(model, state, run, mid)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hi;
}

/// *sample := the sample at t, from run->crossing_values (computed at t) and run->y, run->y'
/// (interpolated at t).
void TakeSample(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                CrossingSample* sample) {
  sample->t = t;
  sample->z.assign(run->crossing_values.begin(), run->crossing_values.end());
  // A relation set by its rate at the last event is an ordinary one again once its function
  // has left the band around zero.
  for (size_t i = 0; i < run->moving_at_zero.size(); ++i) {
    if (run->moving_at_zero[i] && std::fabs(run->crossing_values[i]) > 4 * RoundingBand(*run, i)) {
      run->moving_at_zero[i] = false;
    }
  }
  sample->dz.resize(run->num_conditions);
  state->ZeroCrossingRates(t, run->y.data(), run->yp.data(), sample->dz.data());
  if (model.impacts.empty()) return;
  run->contacts.Evaluate(state, t, run->y.data(), run->yp.data());
  sample->gap.resize(model.impacts.size());
  sample->rate.resize(model.impacts.size());
  for (size_t k = 0; k < model.impacts.size(); ++k) {
    sample->gap[k] = run->contacts.gap(k);
    sample->rate[k] = run->contacts.velocity(k);
  }
}

/// Where in (0, 1) the cubic model of a function through (ua, va) and (ub, vb) (values, and rates
/// scaled to the interval) dips below `level`, more than halfway from its nearer end to zero:
/// its minimum's τ, or +inf.
double DipBelow(double ua, double va, double ub, double vb, double level) {
  // The cubic lies above its Bezier control points ua, ua + va/3, ub - vb/3, ub: most
  // intervals are cleared by those alone.
  if (std::min(ua + va / 3, ub - vb / 3) >= level) return HUGE_VAL;
  auto dip = HermiteInteriorMinimum(ua, va, ub, vb);
  return dip && dip->value < level ? dip->tau : HUGE_VAL;
}

/// A crossing between samples a and b that the cubic models of the crossing functions point to:
/// its located time, or +inf. Where a model dips more than halfway from its nearer end to zero,
/// the functions are sampled at the dip: crossed there, the crossing is located before it;
/// otherwise both halves are examined the same way (at most kMaxRefinements samples per step).
double CrossingBetweenSamples(const CompiledModel& model, ModelState* state, IntegrationState* run,
                              const CrossingSample& a, const CrossingSample& b, int depth) {
  const double h = b.t - a.t;
  if (depth >= kMaxDepth || run->refinements_left <= 0 || !(h > 1e-14 * std::max(1.0, std::fabs(b.t)))) {
    return HUGE_VAL;
  }
  const double* conditions = state->conditions();
  double tau = HUGE_VAL;
  for (size_t i : run->cubic_watched) {
    // u = side * z is positive on the side the frozen condition is on; crossing makes it negative.
    const Op op = model.conditions[i].op;
    const bool holds_when_positive = op == Op::kGt || op == Op::kGe;
    const double side = (conditions[i] != 0) == holds_when_positive ? 1.0 : -1.0;
    const double ua = side * a.z[i], ub = side * b.z[i], va = side * a.dz[i] * h, vb = side * b.dz[i] * h;
    const double level = 0.5 * std::max(0.0, std::min(ua, ub)) - RoundingBand(*run, i);
    tau = std::min(tau, DipBelow(ua, va, ub, vb, level));
  }
  // Open contacts the same way: the gap, with the contact's velocity as its rate (a body that
  // passes through another inside one step).
  const double* discrete = state->discrete();
  for (size_t k = 0; k < a.gap.size(); ++k) {
    if (discrete[model.impacts[k].contact] != 0) continue;
    const double ua = a.gap[k], ub = b.gap[k], va = a.rate[k] * h, vb = b.rate[k] * h;
    const double level = 0.5 * std::max(0.0, std::min(ua, ub)) - kGapBand;
    tau = std::min(tau, DipBelow(ua, va, ub, vb, level));
  }
  if (tau == HUGE_VAL) return HUGE_VAL;
  --run->refinements_left;
  const double tm = a.t + tau * h;
  // Crossed there; or a contact overlaps there, at its deepest, so it closed (approaching)
  // before: either way the crossing lies in (a.t, tm].
  if (Crossed(model, state, run, tm) || OverlappingContact(model, *state, *run) >= 0) {
    return Locate(model, state, run, a.t, tm);
  }
  CrossingSample middle;
  TakeSample(model, state, run, tm, &middle);
  if (double tc = CrossingBetweenSamples(model, state, run, a, middle, depth + 1); tc < HUGE_VAL) return tc;
  return CrossingBetweenSamples(model, state, run, middle, b, depth + 1);
}

/// The time of the first affine time event after run->t (+inf when none); marks which conditions
/// are affine in time.
double ComputeNextTimeEvent(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const size_t nc = run->num_conditions;
  const double t = run->t;
  if (run->affine_in_time.size() != nc) run->affine_in_time.assign(nc, false);
  double best = HUGE_VAL;
  if (nc == 0) return best;
  std::vector<double> z0(nc), z1(nc), z2(nc);
  state->ZeroCrossings(t, nullptr, nullptr, z0.data());
  state->ZeroCrossings(t + 1.0, nullptr, nullptr, z1.data());
  state->ZeroCrossings(t + 2.0, nullptr, nullptr, z2.data());
  for (size_t i = 0; i < nc; ++i) {
    if (!model.conditions[i].time_only) continue;
    double slope = z1[i] - z0[i];
    run->affine_in_time[i] = std::fabs((z2[i] - z1[i]) - slope) <= 1e-9 * (std::fabs(slope) + std::fabs(z0[i]) + 1);
    if (!run->affine_in_time[i] || slope == 0) continue;
    double te = t - z0[i] / slope;
    if (te > t * (1 + 1e-15) + 1e-300 && te < best) best = te;
  }
  return best;
}

}  // namespace

bool RelationHolds(Op op, double z) {
  switch (op) {
    case Op::kLt: return z < 0;
    case Op::kLe: return z <= 0;
    case Op::kGt: return z > 0;
    case Op::kGe: return z >= 0;
    case Op::kEq: return z == 0;
    default: return z != 0;
  }
}

double RoundingBand(const IntegrationState& run, size_t i) {
  return 1e-12 * std::max(run.crossing_scale[i], 1e-3);
}

double FirstCrossing(const CompiledModel& model, ModelState* state, IntegrationState* run,
                     double t0, double t1) {
  // Nothing to watch when every condition is a scheduled time event and there are no contacts.
  bool watch = !model.impacts.empty();
  for (size_t i = 0; i < run->num_conditions && !watch; ++i) watch = !Scheduled(model, *run, i);
  if (!watch) return HUGE_VAL;
  const bool use_cubic = !run->cubic_watched.empty() || !model.impacts.empty();
  if (use_cubic && !(run->sample_valid && run->sample.t == t0)) {
    Interpolate(run, t0);
    state->ZeroCrossings(t0, run->y.data(), run->yp.data(), run->crossing_values.data());
    TakeSample(model, state, run, t0, &run->sample);
  }
  run->refinements_left = kMaxRefinements;
  double lo = t0;
  for (int s = 1; s <= kInteriorSamples + 1; ++s) {
    double ts = t0 + (t1 - t0) * s / (kInteriorSamples + 1);
    if (s == kInteriorSamples + 1) ts = t1;
    if (Crossed(model, state, run, ts)) {
      run->sample_valid = false;
      return Locate(model, state, run, lo, ts);
    }
    if (use_cubic) {
      TakeSample(model, state, run, ts, &run->next_sample);
      if (double tc = CrossingBetweenSamples(model, state, run, run->sample, run->next_sample, 0); tc < HUGE_VAL) {
        run->sample_valid = false;
        return tc;
      }
      std::swap(run->sample, run->next_sample);
    }
    lo = ts;
  }
  run->sample_valid = use_cubic;  // the next step starts where this one ended
  return HUGE_VAL;
}

double NextTimeEvent(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  if (!run->time_events_stale && run->t < run->next_time_event) return run->next_time_event;
  run->time_events_stale = false;
  run->next_time_event = ComputeNextTimeEvent(model, state, run);
  // Which conditions the crossing models watch follows from which are scheduled.
  run->cubic_watched.clear();
  for (size_t i = 0; i < run->num_conditions; ++i) {
    if (WatchedByCubic(model, *run, i)) run->cubic_watched.push_back(i);
  }
  return run->next_time_event;
}

bool TimeRelationSwitchesAtStart(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const size_t nc = run->num_conditions;
  if (nc == 0) return false;
  NextTimeEvent(model, state, run);  // which conditions are affine in time
  const double t = run->t;
  std::vector<double> z0(nc), z1(nc);
  state->ZeroCrossings(t, nullptr, nullptr, z0.data());
  state->ZeroCrossings(t + 1.0, nullptr, nullptr, z1.data());
  const double* conditions = state->conditions();
  for (size_t i = 0; i < nc; ++i) {
    const Op op = model.conditions[i].op;
    if (!Scheduled(model, *run, i) || op == Op::kEq || op == Op::kNe) continue;
    const double slope = z1[i] - z0[i];
    if (slope == 0 || std::fabs(z0[i]) > 1e-15 * std::fabs(slope) * std::max(1.0, std::fabs(t))) continue;
    if (RelationHolds(op, slope) != (conditions[i] != 0)) return true;
  }
  return false;
}

void CheckNoContactOverlaps(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (model.impacts.empty()) return;
  run->contacts.Evaluate(state, t, run->y.data(), run->yp.data());
  if (const int k = OverlappingContact(model, *state, *run); k >= 0) {
    throw SolverError("at t = " + NumberText(t) + ": the bodies of " + model.impacts[k].name +
                      " start overlapped (gap " + NumberText(run->contacts.gap(k)) +
                      "); move them apart so that the gap is zero or positive");
  }
}

}  // namespace momenta

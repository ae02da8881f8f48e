// One event (docs/FORMAT.md, "Events"), at time t, from the left-limit values y⁻, y'⁻ that the
// crossing search or a time event left in the IntegrationState:
//
//   DoEvent(t):
//     left := the outputs at (t, y⁻, y'⁻);  pre() := y⁻ and the discrete values
//     ResolveImpacts: while an open contact approaches with its gap closed, the fastest one
//       takes its impulse (impacts.cc)
//     Iterate, for round = 0, 1, …:
//       if round > 0: Restart (consistent y, y' for the discrete values so far)
//       conditions := their values at (t, y, y') (SetConditions)
//       the discrete equations evaluated; if a condition or discrete value changed:
//         SettleMixedSystem (the continuous unknowns and the discrete equations until they agree;
//         when the rounds come back to conditions already solved with, TryOtherBranches)
//       closed contacts whose release condition holds open (ReleaseContacts)
//       when-clauses whose condition has become true run: assignments and reinit() (FireWhens)
//       nothing changed or fired: done;  otherwise pre() := the new values
//     Restart: consistent y, y' for the new discrete values (IDACalcIC), IDA from there
//     if an output changed, an impact happened, or rows at every event are asked for:
//       the rows (t, left) and (t, outputs)
//
// A relation whose function is within rounding of zero at an event takes the value its rate
// leads to in the first round: the crossing that caused the event is passed; one at rest there
// (no rate) has not crossed and keeps its value. Later rounds follow
// a restart that changed the continuous solution: a relation that was at rest at zero in the
// first round keeps its value, and its crossing, if the new motion brings one, is a new event — as
// in Modelica, where a friction element that starts to slide reports startForward at the
// breakaway and mode = Forward an instant later. A relation that was passing through zero still
// follows its rate, so a sliding mode (each side's motion drives the relation back) is reported as
// chattering here rather than crept through event by event. At the initial event (no restart)
// nothing has crossed yet: relations take their values, and one at zero that moves away switches
// at its crossing an instant later (a brake whose normal force starts at 0 and rises is free at
// t = 0).
//
// More than kChatterLimit events in a row, each within 1e-10 s of the one before, or more than 100
// rounds of one iteration, stop the run as chattering.

#include "solver/event_iteration.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/crossing_search.h"
#include "solver/ida_session.h"
#include "solver/impacts.h"
#include "solver/output_rows.h"

namespace momenta {

namespace {

/// "the conditions involved include …" for a chattering message: the first five conditions and
/// every impact.
std::string ActiveConditions(const CompiledModel& model) {
  std::string s = "the conditions involved include";
  for (size_t i = 0; i < model.conditions.size() && i < 5; ++i) s += (i ? ", " : " ") + model.conditions[i].text;
  for (const auto& impact : model.impacts) s += ", the impact of " + impact.name;
  return s;
}

/// Counts events in a row that are close in time to the last one that wrote rows; more than
/// kChatterLimit is chattering, an error.
void CheckChattering(const CompiledModel& model, IntegrationState* run, double t) {
  if (t - run->last_event_time <= 1e-10 * std::max(1.0, std::fabs(t))) {
    if (++run->close_events > kChatterLimit) {
      throw SolverError("at t = " + NumberText(t) + ": chattering: more than " + std::to_string(kChatterLimit) +
                        " events within 1e-10 s of each other; " + ActiveConditions(model) +
                        ". Smooth the switching relation, add hysteresis, or wrap it in noEvent()");
    }
  } else {
    run->close_events = 0;
  }
}

/// Closed contacts whose release condition holds open; true when one did.
bool ReleaseContacts(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (model.impacts.empty()) return false;
  run->contacts.Evaluate(state, t, run->y.data(), run->yp.data());
  double* discrete = state->mutable_discrete();
  bool changed = false;
  for (size_t k = 0; k < model.impacts.size(); ++k) {
    if (discrete[model.impacts[k].contact] != 0 && run->contacts.release(k)) {
      discrete[model.impacts[k].contact] = 0;
      changed = true;
    }
  }
  return changed;
}

/// Executes when-clause k: its assignments and reinit(). `values` holds every statement's value,
/// computed at the first clause that runs in this round (all read the same pre-values).
void RunWhen(const CompiledModel& model, ModelState* state, IntegrationState* run, size_t k, double t,
             std::vector<double>* values) {
  if (values->empty()) {
    size_t count = 0;
    for (const auto& when : model.whens) count += when.assigns.size() + when.reinits.size();
    values->resize(count);
    state->WhenValues(t, run->y.data(), run->yp.data(), values->data());
  }
  // A value that is not finite stops the run here, before it is stored (and lost at a restart).
  const CompiledModel::When& when = model.whens[k];
  auto check = [&](double v, VarId target, const char* what) {
    if (std::isfinite(v)) return;
    throw SolverError("at t = " + NumberText(t) + ": " + what + model.flat->VariableName(target) + " = " +
                      NonFiniteText(v) + " in when-clause '" + when.text + "': a value must be a finite number");
  };
  double* discrete = state->mutable_discrete();
  for (const auto& [variable, slot] : when.assigns) {
    check((*values)[slot], model.discrete_vars[variable], "");
    discrete[variable] = (*values)[slot];
  }
  for (const auto& [unknown, slot] : when.reinits) {
    check((*values)[slot], model.unknowns[unknown], "reinit sets ");
    run->y[unknown] = (*values)[slot];
  }
}

/// When-clauses whose condition has become true run; true when one did.
bool FireWhens(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (model.whens.empty()) return false;
  std::vector<double> condition(model.whens.size());
  state->WhenConditions(t, run->y.data(), run->yp.data(), condition.data());
  std::vector<double> values;
  bool fired = false;
  for (size_t k = 0; k < model.whens.size(); ++k) {
    bool now = condition[k] != 0;
    bool edge = now && !run->when_true[k];
    run->when_true[k] = now;
    if (!edge) continue;
    RunWhen(model, state, run, k, t, &values);
    fired = true;
  }
  return fired;
}

/// One round of the mixed system: the conditions it solved with, and the zero-crossing functions
/// at that solution.
struct Visit {
  std::vector<double> conditions, z;
};

/// The conditions whose zero-crossing functions differ between the visited solutions: those that
/// read what the branches change. At an event the states and time stay, so relations of them alone
/// are not among them; the difference may be tiny (the branches' solutions meet at the crossing
/// that caused the event), so any is taken.
std::vector<size_t> MovedConditions(const IntegrationState& run, const std::vector<Visit>& visits) {
  std::vector<size_t> moved;
  for (size_t i = 0; i < run.num_conditions; ++i) {
    for (const Visit& v : visits) {
      if (v.z[i] != visits[0].z[i] || v.conditions[i] != visits[0].conditions[i]) {
        moved.push_back(i);
        break;
      }
    }
  }
  return moved;
}

/// The mixed system came back to conditions it had solved with: each branch it follows puts its
/// solution in the other (a saturated amplifier with positive feedback, whose saturated solution
/// has ceased to exist, flips between that branch and the linear one). Tries the other values of
/// the conditions the visits moved, nearest first (one flipped, then two, …; at most kTrials
/// restarts), and keeps the first branch whose solution gives back its own conditions: true.
/// Otherwise leaves the values as they were and returns false.
bool TryOtherBranches(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                      const std::vector<Visit>& visits) {
  constexpr int kTrials = 64;
  constexpr size_t kMaxMoved = 16;
  const std::vector<size_t> moved = MovedConditions(*run, visits);
  if (moved.empty() || moved.size() > kMaxMoved) return false;
  // A branch that is tried and left leaves no trace: not in the values, nor in the crossing
  // functions' scales (which set the rounding band of later crossings).
  const std::vector<double> y = run->y, yp = run->yp, z = run->crossing_values, scale = run->crossing_scale;
  const std::vector<double> saved(state->event_values(), state->event_values() + state->num_event_values());
  const std::vector<double> base(state->conditions(), state->conditions() + run->num_conditions);
  auto restore = [&] {
    run->y = y;
    run->yp = yp;
    run->crossing_values = z;
    run->crossing_scale = scale;
    std::copy(saved.begin(), saved.end(), state->mutable_event_values());
  };
  int trials = 0;
  const uint32_t all = 1u << moved.size();
  for (size_t flipped = 1; flipped <= moved.size() && trials < kTrials; ++flipped) {
    for (uint32_t mask = 1; mask < all && trials < kTrials; ++mask) {
      if (static_cast<size_t>(std::popcount(mask)) != flipped) continue;
      std::vector<double> candidate = base;
      for (size_t j = 0; j < moved.size(); ++j) {
        if (mask & (1u << j)) candidate[moved[j]] = 1.0 - candidate[moved[j]];
      }
      if (std::any_of(visits.begin(), visits.end(), [&](const Visit& v) { return v.conditions == candidate; })) continue;
      ++trials;
      restore();
      std::copy(candidate.begin(), candidate.end(), state->mutable_conditions());
      UpdateDiscrete(state, run, t);
      try {
        Restart(model, state, run, t);
      } catch (const SolverError&) {
        continue;  // no consistent values in this branch
      }
      bool changed = SetConditions(model, state, run, t, kHoldAtZero);
      changed = UpdateDiscrete(state, run, t) || changed;
      if (!changed) return true;
    }
  }
  restore();
  return false;
}

/// With the pre-values fixed, solves the continuous unknowns for the new discrete values and
/// evaluates the discrete equations again until the two agree: Modelica's mixed
/// continuous/discrete systems. A friction element that stops decides whether it stays stuck
/// from the force that holds it (sa while locked), not from the force of the sliding mode it
/// just left. When the rounds come back to conditions already solved with, the other branches
/// are tried (TryOtherBranches). Gives up after 20 rounds; the event iteration goes on from there.
void SettleMixedSystem(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  std::vector<Visit> visits;
  bool tried = false;
  for (int round = 0; round < 20; ++round) {
    Visit visit{{state->conditions(), state->conditions() + run->num_conditions}, {}};
    Restart(model, state, run, t);
    bool again = SetConditions(model, state, run, t, kHoldAtZero);
    again = UpdateDiscrete(state, run, t) || again;
    if (!again) return;
    visit.z = run->crossing_values;
    visits.push_back(std::move(visit));
    const std::vector<double> next(state->conditions(), state->conditions() + run->num_conditions);
    const bool cycle =
        std::any_of(visits.begin(), visits.end(), [&](const Visit& v) { return v.conditions == next; });
    if (cycle && !tried) {
      tried = true;
      if (TryOtherBranches(model, state, run, t, visits)) return;
    }
  }
}

/// What made the restart's matrix M = [dF/dy' over the states | dF/dy over the algebraic
/// unknowns] singular at (t, y, y'), when it is structural at this point: an equation whose row of
/// M is all zero (it lost its unknowns) and an unknown whose column is (no equation determines it
/// any more), in words; "" when no row or column is zero.
std::string SingularCause(const CompiledModel& model, ModelState* state, const IntegrationState& run, double t) {
  const SparsePattern& pattern = model.jacobian_pattern;
  if (model.num_unknowns() == 0) return "";
  std::vector<double> dfdy(pattern.nnz()), dfdyp(pattern.nnz());
  state->JacobianParts(t, run.y.data(), run.yp.data(), dfdy.data(), dfdyp.data());
  std::vector<bool> row_used(pattern.rows, false), column_used(pattern.cols, false);
  for (int32_t j = 0; j < pattern.cols; ++j) {
    for (int32_t k = pattern.col_start[j]; k < pattern.col_start[j + 1]; ++k) {
      if ((model.is_state[j] ? dfdyp[k] : dfdy[k]) == 0.0) continue;
      row_used[pattern.row_index[k]] = true;
      column_used[j] = true;
    }
  }
  std::string cause;
  for (int32_t i = 0; i < pattern.rows; ++i) {
    if (!row_used[i]) {
      cause += "; the equation " + model.residual_origin(i) + " no longer depends on any unknown";
      break;
    }
  }
  for (int32_t j = 0; j < pattern.cols; ++j) {
    if (!column_used[j]) {
      cause += std::string("; ") + (model.is_state[j] ? "der(" : "") + model.flat->VariableName(model.unknowns[j]) +
               (model.is_state[j] ? ")" : "") + " is determined by no equation any more";
      break;
    }
  }
  return cause;
}

/// Whether some when-clause's condition has become true at (t, run->y, run->y').
bool WhenWouldFire(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                   std::vector<double>* condition) {
  if (model.whens.empty()) return false;
  condition->resize(model.whens.size());
  state->WhenConditions(t, run->y.data(), run->yp.data(), condition->data());
  for (size_t k = 0; k < model.whens.size(); ++k) {
    if ((*condition)[k] != 0 && !run->when_true[k]) return true;
  }
  return false;
}

/// Whether program `p` reads a register in [lo, hi) (an operand field equal to one: conservative,
/// since a field that is not a register may match too).
bool ReadsRegisters(const Program& p, uint32_t lo, uint32_t hi, std::vector<bool>* which = nullptr) {
  bool any = false;
  for (const Instruction& in : p.code()) {
    for (uint32_t r : {in.a, in.b, in.c}) {
      if (r < lo || r >= hi) continue;
      any = true;
      if (which) (*which)[r - lo] = true;
    }
  }
  return any;
}

}  // namespace

void PrepareQuietCrossings(const CompiledModel& model, IntegrationState* run) {
  run->residual_reads_condition.clear();
  const RegisterLayout& l = model.layout;
  if (!model.impacts.empty() || model.conditions.empty()) return;
  // pre(y) changes at every event (SavePre): equations that read it need the restart.
  const uint32_t pre_y = l.pre_base, pre_y_end = l.pre_base + l.num_unknowns;
  if (ReadsRegisters(model.residual, pre_y, pre_y_end) || ReadsRegisters(model.jacobian, pre_y, pre_y_end)) return;
  std::vector<bool> reads(model.conditions.size(), false);
  const uint32_t end = l.cond_base + l.num_conditions;
  ReadsRegisters(model.residual, l.cond_base, end, &reads);
  ReadsRegisters(model.jacobian, l.cond_base, end, &reads);
  run->residual_reads_condition = std::move(reads);
}

bool QuietCrossing(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (run->residual_reads_condition.empty()) return false;
  const size_t nc = model.conditions.size();
  std::vector<double> saved(state->event_values(), state->event_values() + state->num_event_values());
  const std::vector<double> before(state->conditions(), state->conditions() + nc);
  const std::vector<bool> saved_moving = run->moving_at_zero;
  std::vector<double> left(run->outputs.size());
  state->Outputs(t, run->y.data(), run->yp.data(), left.data());
  state->SavePre(run->y.data());
  SetConditions(model, state, run, t, kRightLimit);
  bool quiet = true;
  for (size_t i = 0; i < nc && quiet; ++i) {
    if (state->conditions()[i] != before[i] && run->residual_reads_condition[i]) quiet = false;
  }
  std::vector<double> when_now;
  if (quiet) quiet = !UpdateDiscrete(state, run, t) && !WhenWouldFire(model, state, run, t, &when_now);
  if (!quiet) {
    std::copy(saved.begin(), saved.end(), state->mutable_event_values());
    run->moving_at_zero = saved_moving;
    return false;
  }
  for (size_t k = 0; k < when_now.size(); ++k) run->when_true[k] = when_now[k] != 0;
  ++run->stats->quiet_crossings;
  run->time_events_stale = true;
  run->sample_valid = false;
  std::vector<double> right(run->outputs.size());
  state->Outputs(t, run->y.data(), run->yp.data(), right.data());
  if (right != left || run->options.rows_at_every_event) {
    Row(run, t, left);
    Row(run, t, right);
    run->outputs = right;
  }
  return true;
}

void DoEvent(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
             bool time_event) {
  run->time_events_stale = true;
  run->sample_valid = false;  // the conditions and discrete values change
  ++run->stats->events;
  run->stats->event_times.push_back(t);
  if (time_event) ++run->stats->time_events;
  CheckChattering(model, run, t);
  // The left limit is written only if the event changes an output (or every event's is asked
  // for): an event that merely flips a relation nobody sees leaves no rows.
  std::vector<double> left(run->outputs.size());
  state->Outputs(t, run->y.data(), run->yp.data(), left.data());
  state->SavePre(run->y.data());
  const long impacts_before = run->stats->impacts;
  try {
    ResolveImpacts(model, state, run, t);
    Iterate(model, state, run, t, /*restart=*/true);
    Restart(model, state, run, t);
  } catch (const SolverError& e) {
    // The left limit was computed before the event went wrong: it is kept, with the cause when
    // the system lost an unknown.
    if (t > run->stats->final_time) Row(run, t, left);
    throw SolverError(e.what() + SingularCause(model, state, *run, t));
  }
  run->t = t;
  state->Outputs(t, run->y.data(), run->yp.data(), run->outputs.data());
  CheckRowValues(*state, *run, t, run->y.data());
  if (run->outputs != left || run->stats->impacts != impacts_before || run->options.rows_at_every_event) {
    Row(run, t, left);
    Row(run, t, run->outputs);
    run->last_event_time = t;
  }
}

bool Iterate(const CompiledModel& model, ModelState* state, IntegrationState* run, double t, bool restart) {
  bool any = false;
  for (int round = 0;; ++round) {
    if (round > 0 && restart) Restart(model, state, run, t);
    // The first round passes the crossing; later ones hold relations at rest at zero (above).
    const ZeroSide side = !restart ? kAtValue : round == 0 ? kRightLimit : kHoldAtZero;
    bool changed = SetConditions(model, state, run, t, side);
    changed = UpdateDiscrete(state, run, t) || changed;
    if (changed && restart) SettleMixedSystem(model, state, run, t);
    changed = ReleaseContacts(model, state, run, t) || changed;
    bool fired = FireWhens(model, state, run, t);
    if (!changed && !fired) break;
    any = true;
    state->SavePre(run->y.data());
    if (round == 100) {
      throw SolverError("at t = " + NumberText(t) + ": chattering: the event iteration does not settle, the conditions switch back and forth at one instant (a sliding mode: each branch drives the relation back); " +
                        ActiveConditions(model) + ". Add hysteresis, or model the sliding state explicitly");
    }
  }
  return any;
}

bool SetConditions(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                   ZeroSide side) {
  const size_t nc = run->num_conditions;
  if (nc == 0) return false;
  std::vector<double>& z = run->crossing_values;
  state->ZeroCrossings(t, run->y.data(), run->yp.data(), z.data());
  std::vector<double> rate(nc, 0.0);
  if (side != kAtValue) state->ZeroCrossingRates(t, run->y.data(), run->yp.data(), rate.data());
  if (side == kRightLimit) run->moving_at_zero.assign(nc, false);
  double* conditions = state->mutable_conditions();
  bool changed = false;
  for (size_t i = 0; i < nc; ++i) {
    run->crossing_scale[i] = std::max(run->crossing_scale[i], std::fabs(z[i]));
    double zi = z[i];
    const double band = RoundingBand(*run, i);
    // Within the location error of zero (the event is placed just past the crossing) the
    // relation takes the value its derivative leads to: the right limit. Without this, h < 0
    // at h = -1e-12 after a bounce would switch back an instant later: a duplicate event.
    const double near = 4 * band + std::fabs(rate[i]) * 1e-12 * std::max(1.0, std::fabs(t));
    const bool ordered = model.conditions[i].op != Op::kEq && model.conditions[i].op != Op::kNe;
    if (std::fabs(zi) <= near && ordered) {
      // A rate that would not carry z out of its band in a second is rounding, not motion:
      // a mass resting at its stop (s reinitialised to smax - L/2, v = -1e-26 m/s left by
      // the solve) is not sliding back off it.
      const double moving = std::fabs(rate[i]) * std::max(1.0, std::fabs(t)) > band ? rate[i] : 0.0;
      if (side == kRightLimit) run->moving_at_zero[i] = moving != 0;
      if (side == kHoldAtZero && !run->moving_at_zero[i]) continue;
      // At another relation's event, one at rest within rounding of zero has not crossed: it
      // keeps its value, as the step's crossing test kept it (a bearing starting forward whose
      // sa rests at its limit while the gear it drives holds it stays starting when the gear
      // breaks away).
      if (side == kRightLimit && moving == 0 && std::fabs(zi) <= band) continue;
      // At zero up to the location error or rounding: at the start (a velocity of 1e-17 m/s
      // left by the initial Newton solve) zero itself, at an event the side the rate leads to,
      // and zero itself where nothing moves (a brake engaging on a shaft at rest, whose
      // sliding velocity is -2e-43 m/s, is stuck, not sliding backward).
      // (Only within the band a crossing is measured against: beyond it, where a step's
      // crossing test already sees the relation switched, z is taken as it is.)
      if (side == kAtValue) {
        zi = 0;
      } else if (moving != 0) {
        zi = moving;
      } else if (std::fabs(zi) <= band) {
        zi = 0;
      }
    }
    double value = RelationHolds(model.conditions[i].op, zi) ? 1.0 : 0.0;
    if (value != conditions[i]) changed = true;
    conditions[i] = value;
  }
  return changed;
}

bool UpdateDiscrete(ModelState* state, IntegrationState* run, double t) {
  const size_t nd = state->num_discrete();
  if (nd == 0) return false;
  std::vector<double> before(state->discrete(), state->discrete() + nd);
  state->UpdateDiscrete(t, run->y.data(), run->yp.data());
  return !std::equal(before.begin(), before.end(), state->discrete());
}

void StartWhens(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const double start = run->options.start;
  run->when_true.resize(model.whens.size());
  if (model.whens.empty()) return;
  std::vector<double> now(model.whens.size()), at_init(model.whens.size());
  state->WhenConditions(start, run->y.data(), run->yp.data(), now.data());
  state->set_initial(true);
  state->WhenConditions(start, run->y.data(), run->yp.data(), at_init.data());
  state->set_initial(false);
  std::vector<double> values;
  for (size_t k = 0; k < now.size(); ++k) {
    run->when_true[k] = now[k] != 0;
    if (at_init[k] == 0 || now[k] != 0) continue;
    state->set_initial(true);
    RunWhen(model, state, run, k, start, &values);
    state->set_initial(false);
  }
}

}  // namespace momenta

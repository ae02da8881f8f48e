#pragma once
/// Where, inside a step, a frozen relation switches or an open contact closes: the state events of
/// a run, and the time events that are scheduled instead of searched for. The method is described
/// at the top of crossing_search.cc.

#include <cstddef>

#include "core/compile/compiled_model.h"
#include "solver/integration_state.h"

namespace momenta {

/// Whether a relation `op` holds for its zero-crossing function's value z = a - b.
bool RelationHolds(Op op, double z);

/// The rounding band of condition i's zero-crossing function: 1e-12 of the largest magnitude it
/// has had (run.crossing_scale), and at least 1e-15.
double RoundingBand(const IntegrationState& run, size_t i);

/// The earliest time in (t0, t1] at which a frozen condition no longer agrees with its relation
/// (or an open contact's gap closes while approaching), located on IDA's interpolant; +inf when
/// none. Leaves run->y, run->y' interpolated at some time in the step.
double FirstCrossing(const CompiledModel& model, ModelState* state, IntegrationState* run,
                     double t0, double t1);

/// The time of the next affine time event after run->t (+inf when none). Parameters are fixed
/// during a run, so the answer changes only when an event has been handled (or it has been
/// reached).
double NextTimeEvent(const CompiledModel& model, ModelState* state, IntegrationState* run);

/// A relation of time alone that is at zero at the start (`time > 0` from t = 0) took its value
/// there; time only moves on, so it switches at once if its slope says so: an event at the start
/// time, after the initial one (scheduling looks only past the current time).
bool TimeRelationSwitchesAtStart(const CompiledModel& model, ModelState* state, IntegrationState* run);

/// An open contact that starts overlapped has no impact to resolve (its gap never closes): throws
/// a SolverError naming it.
void CheckNoContactOverlaps(const CompiledModel& model, ModelState* state, IntegrationState* run, double t);

}  // namespace momenta

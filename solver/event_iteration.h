#pragma once
/// One event: the left-limit row, impacts, the event iteration over conditions, discrete
/// equations, releases and when-clauses, the restart, the right-limit row. The semantics are at
/// the top of event_iteration.cc.

#include "core/compile/compiled_model.h"
#include "solver/integration_state.h"

namespace momenta {

/// How an event relation whose zero-crossing function is at zero (within the location error)
/// is set at an event: by the value (at the start), by the side its rate leads to (the right
/// limit: the crossing that caused the event is passed), or left as it was.
enum ZeroSide { kAtValue, kRightLimit, kHoldAtZero };

/// Sets run->residual_reads_condition: which conditions the residual or its Jacobian reads (left
/// empty when no crossing may be quiet: a model with impacts, or whose equations read pre(y)).
void PrepareQuietCrossings(const CompiledModel& model, IntegrationState* run);

/// A crossing at t that changes nothing IDA's equations read: the conditions that switch are read
/// only by discrete equations whose values stay, and no when-clause fires. Then the conditions
/// are set (and rows written if an output changed), IDA goes on without a restart, and it returns
/// true; otherwise nothing is changed and it returns false (the crossing is an event: DoEvent).
bool QuietCrossing(const CompiledModel& model, ModelState* state, IntegrationState* run, double t);

/// Handles the event at t from the left-limit values in run->y, run->y'; leaves run->t = t and the
/// right-limit values, with IDA restarted from them.
void DoEvent(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
             bool time_event);

/// The event iteration: conditions, discrete equations, releases and when-clauses until nothing
/// changes; returns whether anything did. With `restart`, the continuous values are made
/// consistent (IDACalcIC) between rounds; without, it is the initial event.
bool Iterate(const CompiledModel& model, ModelState* state, IntegrationState* run, double t, bool restart);

/// Sets every frozen condition to its value at (t, run->y, run->y'), as `side` says at zero;
/// true when one changed.
bool SetConditions(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                   ZeroSide side);

/// Evaluates the discrete equations at (t, run->y, run->y'); true when a discrete value changed.
bool UpdateDiscrete(ModelState* state, IntegrationState* run, double t);

/// The when-clauses at the start: each condition's value is remembered, and a clause runs only
/// when its condition is true because of initial() (`when initial() then …`); one already true
/// for other reasons waits for an edge.
void StartWhens(const CompiledModel& model, ModelState* state, IntegrationState* run);

}  // namespace momenta

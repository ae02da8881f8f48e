#pragma once
/// The output rows of a run: the grid start, start + interval, …, stop, interpolated within IDA's
/// steps, the rows of events, and the interrupt that stops the rows between two of them.

#include <string>
#include <vector>

#include "core/compile/model_state.h"
#include "solver/integration_state.h"

namespace momenta {

/// The time of grid row k (0 is the start; num_intervals is the stop time).
double GridTime(const IntegrationState& run, long k);

/// Whether the run has been asked to stop (SimulationOptions::interrupt); records, the first time,
/// where it was.
bool Interrupted(IntegrationState* run, double t);

/// Gives out a row, unless the run has been interrupted (then no row follows a gap).
void Row(IntegrationState* run, double t, const std::vector<double>& values);

/// A value that is not finite in a message: "inf", "-inf" or "NaN".
std::string NonFiniteText(double v);

/// Stops the run (SolverError naming the value and t) when run->outputs, the unknowns y (may be
/// null) or the discrete values hold a value that is not finite, or an Integer one that is not a
/// whole number: looked at once a row, before the
/// row is written, so that the rows before it are kept (a pass over numbers the row has just
/// computed, small against the residual evaluations of a step).
void CheckRowValues(const ModelState& state, const IntegrationState& run, double t, const double* y);

/// The outputs at (t, y, y') as a row (y and y' null for a model without unknowns).
void Emit(ModelState* state, IntegrationState* run, double t, const double* y, const double* yp);

/// Grid rows up to `t` (and at t when inclusive), interpolated within the last step.
void EmitGrid(ModelState* state, IntegrationState* run, double t, bool inclusive);

/// An event at t that changed no output wrote no rows: the grid row at t, if there is one, is
/// written now from the values after the event (at the stop time no later step would write it).
void EmitGridAtEvent(ModelState* state, IntegrationState* run, double t);

}  // namespace momenta

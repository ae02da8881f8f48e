#pragma once
/// The SUNDIALS boundary of a run: IDA started, stepped, interpolated and restarted after events,
/// its statistics collected and its failures turned into messages. The IdaSession that owns every
/// SUNDIALS object of the run is defined in ida_session.cc; no other phase sees a SUNDIALS type.

#include "core/compile/compiled_model.h"
#include "solver/integration_state.h"

namespace momenta {

/// Creates IDA at options.start from run->y, run->y' (consistent), with the options' tolerances
/// and linear solver, and stop time options.stop.
void StartIda(const CompiledModel& model, ModelState* state, IntegrationState* run);

/// Where one IDA step ended.
struct IdaStepEnd {
  double t = 0;
  bool at_stop_time = false;  ///< the step was cut at the stop time (IDA_TSTOP_RETURN)
};

/// One IDA step from run->t (IDA_ONE_STEP), the first after a start or restart sized by `tout`.
/// Throws SolverError ("at t = …: …") when IDA fails.
IdaStepEnd StepIda(const CompiledModel& model, IntegrationState* run, double tout);

/// IDA stops its steps at `tstop` (IDASetStopTime).
void SetStopTime(IntegrationState* run, double tstop);

/// run->y, run->y' := the values in IDA's vectors: the end of its last step, or the consistent
/// values of a restart.
void ReadIdaValues(IntegrationState* run);

/// run->y, run->y' := IDA's interpolant at t (within the last step). Nothing without unknowns.
void Interpolate(IntegrationState* run, double t);

/// Consistent y, y' for the current discrete values and states (IDACalcIC), polished, and IDA
/// restarted from them at t. Nothing without unknowns.
void Restart(const CompiledModel& model, ModelState* state, IntegrationState* run, double t);

/// Polishes run->y, run->y' at t after a start or restart. First up to two Newton steps on
/// F(t, y, y') = 0 for the states' rates and the algebraic unknowns (the states stay): IDACalcIC
/// stops at its own tolerance, which leaves the rates of states noisy by about tolerance/step
/// (1e-4), enough to flip a relation that sits exactly at zero after a reinit (a mass put at its
/// stop with v = 0 would seem to move on). Then the rates of the algebraic unknowns that agree
/// with the equations differentiated in time,
///   [dF/dy over the algebraic unknowns | dF/dy' over the states] [y'_alg; y''_states]
///     = -(dF/dt + dF/dy over the states * y'_states),
/// with dF/dt by a central difference. IDA predicts every unknown from its rate: a zero rate for
/// an algebraic unknown that moves (a stuck friction element's force following a sine) makes the
/// error test fail again and again on the first step at a tight tolerance. Leaves the values as
/// they are where the system is singular.
void PolishConsistentValues(const CompiledModel& model, ModelState* state, IntegrationState* run,
                            double t);

/// Copies IDA's counters, added to those of the sessions before the last restart, to run->stats.
void CollectIdaStats(IntegrationState* run);

/// Throws IDA's "too much work" failure: SimulationOptions::max_steps steps without an output row.
/// The message names the model's fastest modes and what helps (stiffness_report.h).
[[noreturn]] void FailTooMuchWork(const CompiledModel& model, IntegrationState* run);

}  // namespace momenta

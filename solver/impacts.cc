// Impacts, resolved exactly (ARCHITECTURE.md decision 7).
//
// Integrating the DAE F(t, y, y') = 0 over an impact of vanishing length, bounded terms vanish,
// each y' becomes the jump Δx of a state, and each algebraic unknown that carries the impact
// becomes its impulse Λ. For F linear in y' and in the impulsive unknowns (masses times
// accelerations balanced by forces) this is
//     [dF/dy' (state columns) | dF/dz (algebraic columns)] [Δx; Λ] = 0,
// the IDA Jacobian's two parts (cj = 1 minus cj = 0, and cj = 0): the mixed Jacobian
// (mixed_jacobian.h). The contact's own law, its `0 = if contact then der(velocity) else force`
// row taken in contact mode, integrates to the jump of the velocity, and Newton's law sets it:
//     ∫ der(velocity) dt = Δvelocity = -(1 + e) · velocity⁻.
// This holds through index reduction: a dummy derivative (der(v) made algebraic) integrates to
// the jump of v like a state's derivative does, and the integrals of velocity-level unknowns
// come out zero, so the velocity may be any expression of the model's unknowns.
//
// Solving that one system, with this row for the contact and Newton's law on its right-hand side,
// decides where the impulse goes: it passes through rods (rigid: one velocity), not through
// springs (bounded forces: Λ = 0), and through closed contacts as through rods. Positions do not
// jump (der(s) = v gives Δs = 0). An approach slower than v_small closes the contact (e = 0); it
// then rests, with der(velocity) = 0, until its release condition (a pulling force) holds.

#include "solver/impacts.h"

#include <Eigen/Core>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/ida_session.h"
#include "solver/mixed_jacobian.h"

namespace momenta {

namespace {

/// Solves [dF/dy' | dF/dz] [Δx; Λ] = b, the DAE integrated over the impact, with the impact's
/// contact law taken in contact mode: its row is then der(velocity), whose integral is the jump
/// of the velocity, and b asks that jump to be `dvel` (every other row is 0). Adds Δx to the
/// states.
void ApplyImpulse(const CompiledModel& model, ModelState* state, IntegrationState* run, double t,
                  const CompiledModel::Impact& impact, double dvel) {
  double* discrete = state->mutable_discrete();
  const double mode = discrete[impact.contact];
  discrete[impact.contact] = 1;
  MixedJacobian jacobian(state, t, run->y.data(), run->yp.data());
  discrete[impact.contact] = mode;
  const size_t n = run->num_unknowns;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<int>(n));
  b[impact.mode_row] = dvel;
  if (!jacobian.Factor()) {
    throw SolverError("at t = " + NumberText(t) + ": the impact of " + impact.name +
                      " has no unique solution (the integrated equations are singular: is a body without mass in the impulse's path?)");
  }
  const Eigen::VectorXd x = jacobian.Solve(b);
  for (size_t c = 0; c < n; ++c) {
    if (model.is_state[c]) run->y[c] += x[static_cast<int>(c)];
  }
}

/// The open contact that approaches fastest with its gap closed, in run->contacts; -1 if none.
int FastestApproach(const CompiledModel& model, const ModelState& state, const IntegrationState& run) {
  const double* discrete = state.discrete();
  int which = -1;
  double fastest = 0;
  for (size_t k = 0; k < model.impacts.size(); ++k) {
    if (discrete[model.impacts[k].contact] != 0) continue;
    double gap = run.contacts.gap(k), vel = run.contacts.velocity(k);
    if (gap <= kGapBand && vel < -kVelocityBand && vel < fastest) {
      fastest = vel;
      which = static_cast<int>(k);
    }
  }
  return which;
}

}  // namespace

void ResolveImpacts(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (model.impacts.empty()) return;
  for (int round = 0;; ++round) {
    run->contacts.Evaluate(state, t, run->y.data(), run->yp.data());
    const int which = FastestApproach(model, *state, *run);
    if (which < 0) return;
    if (round == 10000) {
      throw SolverError("at t = " + NumberText(t) + ": the impacts do not come to an end (more than 10000 in one instant)");
    }
    const auto& impact = model.impacts[which];
    double vel = run->contacts.velocity(which);
    double e = run->contacts.restitution(which), v_small = run->contacts.small_velocity(which);
    // A plastic impact, or one slower than v_small, leaves the bodies resting together.
    bool close = -vel < v_small || e == 0;
    double dvel = close ? -vel : -(1 + e) * vel;
    ApplyImpulse(model, state, run, t, impact, dvel);
    if (close) state->mutable_discrete()[impact.contact] = 1;
    if (model.impacts_read_algebraic) Restart(model, state, run, t);
    ++run->stats->impacts;
    run->stats->impact_times.push_back(t);
  }
}

}  // namespace momenta

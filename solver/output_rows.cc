// The output rows of a run (see output_rows.h). Rows go out as they are computed, so that a run
// that fails or is interrupted keeps the rows before it; an event's rows stand for the grid row
// at the same time.

#include "solver/output_rows.h"

#include <cmath>
#include <string>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/ida_session.h"

namespace momenta {

double GridTime(const IntegrationState& run, long k) {
  return k >= run.num_intervals ? run.options.stop : run.options.start + k * run.interval;
}

bool Interrupted(IntegrationState* run, double t) {
  const std::atomic<bool>* interrupt = run->options.interrupt;
  if (!interrupt || !interrupt->load(std::memory_order_relaxed)) return false;
  if (!run->stats->interrupted) {
    run->stats->interrupted = true;
    run->stats->interrupted_at = t;
  }
  return true;
}

void Row(IntegrationState* run, double t, const std::vector<double>& values) {
  if (run->stats->interrupted) return;
  run->row(t, values);
  run->stats->final_time = t;
}

std::string NonFiniteText(double v) { return std::isnan(v) ? "NaN" : NumberText(v); }

void CheckRowValues(const ModelState& state, const IntegrationState& run, double t, const double* y) {
  const CompiledModel& model = state.model();
  auto fail = [&](const std::string& what, double v) {
    throw SolverError("at t = " + NumberText(t) + ": " + what + " is " + NonFiniteText(v) +
                      " (a division by zero, an overflow or a function outside its domain in what computes it)");
  };
  for (size_t k = 0; k < run.outputs.size(); ++k) {
    if (!std::isfinite(run.outputs[k])) fail("the output " + model.output_names[k], run.outputs[k]);
  }
  for (size_t i = 0; y && i < model.num_unknowns(); ++i) {
    if (!std::isfinite(y[i])) fail(model.flat->VariableName(model.unknowns[i]), y[i]);
  }
  for (size_t d = 0; d < model.discrete_vars.size(); ++d) {
    const double v = state.discrete()[d];
    const VarId var = model.discrete_vars[d];
    if (!std::isfinite(v)) fail(model.flat->VariableName(var), v);
    if (model.flat->variables[var.value()].type == ValueType::kInteger && v != std::floor(v)) {
      throw SolverError("at t = " + NumberText(t) + ": the Integer " + model.flat->VariableName(var) + " is " +
                        NumberText(v) + ": an Integer takes whole numbers only");
    }
  }
}

void Emit(ModelState* state, IntegrationState* run, double t, const double* y, const double* yp) {
  state->Outputs(t, y, yp, run->outputs.data());
  CheckRowValues(*state, *run, t, y);
  Row(run, t, run->outputs);
}

void EmitGrid(ModelState* state, IntegrationState* run, double t, bool inclusive) {
  while (run->next_grid_row <= run->num_intervals && !Interrupted(run, t)) {
    double tg = GridTime(*run, run->next_grid_row);
    if (tg > t || (!inclusive && tg >= t)) break;
    if (tg <= run->last_event_time) {  // already written as an event's rows
      ++run->next_grid_row;
      continue;
    }
    Interpolate(run, tg);
    Emit(state, run, tg, run->y.data(), run->yp.data());
    ++run->next_grid_row;
  }
}

void EmitGridAtEvent(ModelState* state, IntegrationState* run, double t) {
  if (run->next_grid_row > run->num_intervals || GridTime(*run, run->next_grid_row) != t ||
      t <= run->last_event_time) {
    return;
  }
  Emit(state, run, t, run->y.data(), run->yp.data());
  ++run->next_grid_row;
}

}  // namespace momenta

// The output rows of a run (see output_rows.h). Rows go out as they are computed, so that a run
// that fails or is interrupted keeps the rows before it; an event's rows stand for the grid row
// at the same time.

#include "solver/output_rows.h"

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

void Emit(ModelState* state, IntegrationState* run, double t, const double* y, const double* yp) {
  state->Outputs(t, y, yp, run->outputs.data());
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

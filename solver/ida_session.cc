// The SUNDIALS boundary of a run (see ida_session.h): the IdaSession that owns IDA and its
// vectors, the residual and Jacobian callbacks, the start, steps, interpolation and restarts, and
// the messages of IDA's failures. The callbacks keep the contract of STYLE.md, "Errors": a
// non-finite residual asks IDA for a smaller step (positive return); an exception is stored and
// stops the solver (negative return), and is thrown again with the time at which it happened.

#include "solver/ida_session.h"

#include <ida/ida.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/jacobian_fill.h"
#include "solver/mixed_jacobian.h"
#include "solver/stiffness_report.h"
#include "solver/sundials_support.h"

namespace momenta {

namespace {

/// The absolute tolerance of unknowns left out of IDA's error test (dummy derivatives).
constexpr double kUntestedTolerance = 1e30;

/// What IDA's callbacks are given: the model to evaluate, and where they leave what went wrong.
struct IdaData {
  ModelState* state;
  std::vector<double> jac_values;
  std::string error;         ///< an exception caught in a callback
  std::string last_message;  ///< IDA's own last error message
};

int Residual(double t, N_Vector y, N_Vector yp, N_Vector r, void* user) {
  auto* data = static_cast<IdaData*>(user);
  const int flag = GuardedCall(&data->error, [&] {
    data->state->Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r));
  });
  return flag != 0 ? flag : RetryUnlessFinite(r);
}

int Jacobian(double t, double cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix J, void* user,
             N_Vector, N_Vector, N_Vector) {
  auto* data = static_cast<IdaData*>(user);
  return FillJacobian(data->state->model().jacobian_pattern, &data->jac_values, J, &data->error,
                      [&](double* values) {
                        data->state->Jacobian(t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), values);
                      });
}

void IdaMessage(int, const char*, const char*, char* msg, void* user) {
  static_cast<IdaData*>(user)->last_message = msg;
}

struct IdaDeleter {
  void operator()(void* mem) const { IDAFree(&mem); }
};

std::string FlagMeaning(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK: return "too many steps without reaching the next output time";
    case IDA_TOO_MUCH_ACC: return "the requested accuracy is finer than the solution's rounding errors";
    case IDA_ERR_FAIL: return "the error test failed repeatedly (a discontinuity or a singularity?)";
    case IDA_CONV_FAIL: return "Newton's method failed to converge repeatedly";
    case IDA_LSETUP_FAIL:
    case IDA_LSOLVE_FAIL: return "the linear solver failed (a singular Jacobian?)";
    case IDA_RES_FAIL: return "the residual could not be evaluated";
    case IDA_REP_RES_ERR: return "the residual returned non-finite values repeatedly";
    default: return "";
  }
}

/// IDA's name for a return flag (IDAGetReturnFlagName allocates; the caller frees).
std::string FlagName(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string out = name ? name : "unknown flag";
  std::free(name);
  return out;
}

}  // namespace

/// Every SUNDIALS object of a run. The members are freed in reverse order: IDA first, then the
/// linear solver and the vectors it uses, the context last.
class IdaSession {
 public:
  ContextPtr context;
  VectorPtr y, yp;
  VectorPtr differential;  ///< IDASetId: 1 for a state, 0 for an algebraic unknown
  /// The algebraic unknowns are out of IDA's error test (IDASetSuppressAlg, masked by
  /// `differential`): see SuppressAlgebraicErrors.
  bool algebraic_untested = false;
  /// The matrix that solves for the untested unknowns between IDA's steps (SolveUntestedAt),
  /// factored once per step: at IDA's time interpolated_at.
  std::unique_ptr<MixedJacobian> interpolation_matrix;
  double interpolated_at = NAN;
  /// SolveUntestedAt's residual, right-hand side and step, kept from call to call: it runs at
  /// every sample of the crossing search (about 500 times in the carrier collision's run).
  std::vector<double> untested_residual;
  Eigen::VectorXd untested_rhs, untested_step;
  VectorPtr interpolated_y, interpolated_yp;
  VectorPtr abstol;
  VectorPtr restart_abstol;  ///< abstol with dummy derivatives tested (null when none is untested)
  LinearSystem linear_system;
  IdaData callback_data{nullptr, {}, {}, {}};
  std::unique_ptr<void, IdaDeleter> mem;
  /// (y index of an algebraic unknown, y index of the dummy derivative that is its rate).
  std::vector<std::pair<uint32_t, uint32_t>> rate_of_algebraic;
  SolverStats before_restart;  ///< the counters of the sessions before the last restart
};

void IdaSessionDeleter::operator()(IdaSession* session) const { delete session; }

namespace {

/// Copies run->y, run->y' into IDA's vectors.
void Load(IntegrationState* run) {
  IdaSession& ida = *run->ida;
  std::copy(run->y.begin(), run->y.end(), N_VGetArrayPointer(ida.y.get()));
  std::copy(run->yp.begin(), run->yp.end(), N_VGetArrayPointer(ida.yp.get()));
}

/// The algebraic unknowns whose derivative index reduction made a dummy unknown.
std::vector<std::pair<uint32_t, uint32_t>> RatesOfAlgebraicUnknowns(const CompiledModel& model) {
  std::vector<std::pair<uint32_t, uint32_t>> rates;
  const size_t n = model.num_unknowns();
  std::vector<int64_t> y_of_var(model.flat->variables.size(), -1);
  for (size_t k = 0; k < n; ++k) y_of_var[model.unknowns[k].value()] = static_cast<int64_t>(k);
  for (size_t k = 0; k < n; ++k) {
    const FlatVariable& v = model.flat->variables[model.unknowns[k].value()];
    if (!model.is_state[k] && v.derivative_order == 1 && v.derivative_of.valid()) {
      const int64_t x = y_of_var[v.derivative_of.value()];
      if (x >= 0 && !model.is_state[x]) rates.emplace_back(static_cast<uint32_t>(x), k);
    }
  }
  return rates;
}

/// IDA's residual does not depend on an algebraic unknown's y', but its first predictor does
/// (y + h y'): where index reduction made the unknown's derivative a dummy, y' := that dummy,
/// so the first step after a start or restart is not an O(h) guess of an algebraic value.
void SetAlgebraicRates(IntegrationState* run) {
  for (auto [algebraic, rate] : run->ida->rate_of_algebraic) run->yp[algebraic] = run->y[rate];
}

/// The absolute tolerances of the error test (and of restarts), and which unknowns are states.
void SetTolerances(const CompiledModel& model, IntegrationState* run, double atol) {
  IdaSession& ida = *run->ida;
  const size_t n = run->num_unknowns;
  double* abstol = N_VGetArrayPointer(ida.abstol.get());
  bool untested = false;
  for (size_t k = 0; k < n; ++k) {
    abstol[k] = atol * model.nominal[k];
    // Dummy derivatives (derivatives index reduction made algebraic) follow from the other
    // unknowns through the differentiated constraints; IDA's estimate of their local error is
    // poor (a pendulum's der(der(y)) makes its steps collapse), so they are left out of the
    // error test: an absolute tolerance no value reaches.
    if (!model.is_state[k] && model.flat->variables[model.unknowns[k].value()].derivative_order > 0) {
      abstol[k] = kUntestedTolerance;
      untested = true;
    }
    N_VGetArrayPointer(ida.differential.get())[k] = model.is_state[k] ? 1.0 : 0.0;
  }
  // The consistent restarts after events solve for every algebraic unknown, dummy derivatives
  // included, to the ordinary tolerance (after an impulse they are all stale).
  if (untested) {
    ida.restart_abstol.reset(N_VClone(ida.abstol.get()));
    for (size_t k = 0; k < n; ++k) N_VGetArrayPointer(ida.restart_abstol.get())[k] = atol * model.nominal[k];
  }
}

/// Why IDA rejected its input. Tolerances below double precision make IDA's step size vanish, and
/// its own message then blames the stop time: name the tolerance instead. Otherwise IDA's message
/// says which input.
std::string IllInputReason(const SimulationOptions& options, const std::string& ida_message) {
  const double atol = options.atol > 0 ? options.atol : options.rtol;
  std::string reason = "IDA rejected its input (IDA_ILL_INPUT): ";
  if (!(options.rtol >= kMinRelTolerance)) {
    return reason + "the relative tolerance " + NumberText(options.rtol) +
           " is below what double precision resolves (use at least 1e-15)";
  }
  if (!(atol >= kMinAbsTolerance)) {
    return reason + "the absolute tolerance " + NumberText(atol) + " is below the smallest normal double (2.2e-308)";
  }
  return reason + (ida_message.empty() ? "no reason given" : ida_message) + " (rtol " +
         NumberText(options.rtol) + ", atol " + NumberText(atol) + ")";
}

/// ". The largest local error is in …, governed by …" when IDA can say, else "".
std::string LargestLocalError(const CompiledModel& model, IntegrationState* run) {
  IdaSession& ida = *run->ida;
  const size_t n = run->num_unknowns;
  VectorPtr weights = MakeVector(static_cast<sunindextype>(n), ida.context.get());
  VectorPtr errors = MakeVector(static_cast<sunindextype>(n), ida.context.get());
  if (IDAGetErrWeights(ida.mem.get(), weights.get()) != IDA_SUCCESS ||
      IDAGetEstLocalErrors(ida.mem.get(), errors.get()) != IDA_SUCCESS) {
    return "";
  }
  size_t worst = 0;
  double worst_error = -1;
  for (size_t j = 0; j < n; ++j) {
    double e = std::fabs(N_VGetArrayPointer(errors.get())[j] * N_VGetArrayPointer(weights.get())[j]);
    if (e > worst_error) {
      worst_error = e;
      worst = j;
    }
  }
  return ". The largest local error is in " + model.flat->DescribeVariable(model.unknowns[worst]) +
         ", governed by " + model.residual_origin(worst);
}

/// Why the steps ran out: how many, and the model's fastest modes where it stands (the values of
/// IDA's last step) with the advice that fits them.
std::string TooMuchWorkReason(IntegrationState* run) {
  IdaSession& ida = *run->ida;
  const double* y = N_VGetArrayPointer(ida.y.get());
  const double* yp = N_VGetArrayPointer(ida.yp.get());
  double t = run->t;
  IDAGetCurrentTime(ida.mem.get(), &t);
  return "IDA stopped (IDA_TOO_MUCH_WORK): " + NumberText(static_cast<double>(run->options.max_steps)) +
         " steps (--max-steps) without reaching the next output time" +
         ExplainStepCost(*ida.callback_data.state, t, std::vector<double>(y, y + run->num_unknowns),
                         std::vector<double>(yp, yp + run->num_unknowns), run->interval,
                         static_cast<double>(run->options.max_steps), /*stopped=*/true) +
         ".";
}

/// Throws IDA's failure `flag` as a SolverError at the time IDA had reached, with the counters
/// and times of the run so far in run->stats.
[[noreturn]] void Fail(const CompiledModel& model, IntegrationState* run, int flag) {
  CollectIdaStats(run);
  run->stats->integrate_seconds = SecondsSince(run->integration_started);
  IdaSession& ida = *run->ida;
  double t_fail = run->t;
  IDAGetCurrentTime(ida.mem.get(), &t_fail);
  run->stats->final_time = t_fail;
  std::string msg = "at t = " + NumberText(t_fail) + ": ";
  if (!ida.callback_data.error.empty()) {
    msg += ida.callback_data.error;
  } else if (flag == IDA_ILL_INPUT) {
    msg += IllInputReason(run->options, ida.callback_data.last_message);
  } else if (flag == IDA_TOO_MUCH_WORK) {
    msg += TooMuchWorkReason(run);
  } else {
    msg += "IDA stopped (" + FlagName(flag) + "): " + FlagMeaning(flag) + LargestLocalError(model, run);
    if (flag == IDA_TOO_MUCH_ACC) {
      msg += ". Loosen the tolerance (a larger --rtol or --atol): double precision cannot deliver this one.";
    } else {
      msg += ". Try a tighter tolerance (--rtol), check the parameters of that component, or "
             "look for a singularity in its equations.";
    }
  }
  throw SolverError(msg);
}

/// IDACalcIC from run->y, run->y' at t (with or without its line search), to restart_abstol when
/// there is one; returns its flag.
int CalcConsistentValues(IntegrationState* run, double t, bool line_search) {
  IdaSession& ida = *run->ida;
  void* mem = ida.mem.get();
  double tout1 = std::min(run->options.stop, t + run->interval);
  if (tout1 <= t) tout1 = t + std::max(1e-6, 1e-6 * std::fabs(t));
  if (ida.restart_abstol) CheckFlag(IDASVtolerances(mem, run->options.rtol, ida.restart_abstol.get()), "IDASVtolerances");
  CheckFlag(IDASetLineSearchOffIC(mem, line_search ? SUNFALSE : SUNTRUE), "IDASetLineSearchOffIC");
  return IDACalcIC(mem, IDA_YA_YDP_INIT, tout1);
}

/// Whether IDA's error test leaves out the algebraic unknowns, which follow from the states
/// within a step (forces, accelerations, currents), as an ODE solver such as DASSL in Dymola's
/// ODE form never tests them. Not in a model that index reduction differentiated: there the
/// algebraic unknowns hold the constraint forces and the dummy states, and untested they let the
/// solution leave the constraints (the MSL double pendulum's Newton failures went from at most 6
/// to 97 at rtol 1e-10, its energy drift up fivefold).
bool SuppressAlgebraicErrors(const CompiledModel& model, const SimulationOptions& options) {
  const auto& equations = model.flat->equations;
  const auto& is_state = model.is_state;
  return !options.test_algebraic && !std::all_of(is_state.begin(), is_state.end(), [](bool s) { return s; }) &&
         std::none_of(equations.begin(), equations.end(), [](const FlatEquation& e) { return e.differentiations > 0; });
}

}  // namespace

void StartIda(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const auto n = static_cast<sunindextype>(run->num_unknowns);
  const SimulationOptions& options = run->options;
  run->ida.reset(new IdaSession);
  IdaSession& ida = *run->ida;
  ida.context = MakeContext();
  SUNContext context = ida.context.get();
  ida.y = MakeVector(n, context);
  ida.yp = MakeVector(n, context);
  ida.abstol = MakeVector(n, context);
  ida.differential = MakeVector(n, context);
  ida.interpolated_y = MakeVector(n, context);
  ida.interpolated_yp = MakeVector(n, context);
  ida.rate_of_algebraic = RatesOfAlgebraicUnknowns(model);
  SetAlgebraicRates(run);
  SetTolerances(model, run, options.atol > 0 ? options.atol : options.rtol);
  Load(run);
  ida.callback_data = IdaData{state, {}, {}, {}};
  ida.mem.reset(IDACreate(context));
  CheckNotNull(ida.mem.get(), "IDACreate");
  void* mem = ida.mem.get();
  CheckFlag(IDAInit(mem, Residual, options.start, ida.y.get(), ida.yp.get()), "IDAInit");
  CheckFlag(IDASetUserData(mem, &ida.callback_data), "IDASetUserData");
  CheckFlag(IDASetErrHandlerFn(mem, IdaMessage, &ida.callback_data), "IDASetErrHandlerFn");
  CheckFlag(IDASVtolerances(mem, options.rtol, ida.abstol.get()), "IDASVtolerances");
  CheckFlag(IDASetId(mem, ida.differential.get()), "IDASetId");
  ida.algebraic_untested = SuppressAlgebraicErrors(model, options);
  if (ida.algebraic_untested) CheckFlag(IDASetSuppressAlg(mem, SUNTRUE), "IDASetSuppressAlg");
  ida.linear_system = MakeLinearSystem(ida.y.get(), n, static_cast<sunindextype>(model.jacobian_pattern.nnz()),
                                       run->sparse, context);
  CheckFlag(IDASetLinearSolver(mem, ida.linear_system.solver.get(), ida.linear_system.matrix.get()),
            "IDASetLinearSolver");
  CheckFlag(IDASetJacFn(mem, Jacobian), "IDASetJacFn");
  CheckFlag(IDASetMaxNumSteps(mem, options.max_steps), "IDASetMaxNumSteps");
  CheckFlag(IDASetMaxOrd(mem, options.max_order), "IDASetMaxOrd");
  CheckFlag(IDASetStopTime(mem, options.stop), "IDASetStopTime");
}

IdaStepEnd StepIda(const CompiledModel& model, IntegrationState* run, double tout) {
  IdaSession& ida = *run->ida;
  IdaStepEnd end;
  const int flag = IDASolve(ida.mem.get(), tout, &end.t, ida.y.get(), ida.yp.get(), IDA_ONE_STEP);
  if (flag < 0) Fail(model, run, flag);
  end.at_stop_time = flag == IDA_TSTOP_RETURN;
  return end;
}

void SetStopTime(IntegrationState* run, double tstop) {
  CheckFlag(IDASetStopTime(run->ida->mem.get(), tstop), "IDASetStopTime");
}

void ReadIdaValues(IntegrationState* run) {
  const double* y = N_VGetArrayPointer(run->ida->y.get());
  const double* yp = N_VGetArrayPointer(run->ida->yp.get());
  run->y.assign(y, y + run->num_unknowns);
  run->yp.assign(yp, yp + run->num_unknowns);
}

namespace {

/// Whether the step dx is within a hundredth of the error test's tolerance for every unknown.
bool Converged(const IntegrationState& run, const N_Vector abstol, const Eigen::VectorXd& dx,
               const std::vector<double>& y, const std::vector<double>& yp, const std::vector<bool>& is_state) {
  const double* atol = N_VGetArrayPointer(abstol);
  for (size_t k = 0; k < run.num_unknowns; ++k) {
    const double v = is_state[k] ? yp[k] : y[k];
    if (std::fabs(dx[static_cast<int>(k)]) > 0.01 * (run.options.rtol * std::fabs(v) + atol[k])) return false;
  }
  return true;
}

/// With unknowns out of IDA's error test, its interpolating polynomial is not held to the
/// tolerance for them between steps (a source of time drives a current while the states rest):
/// they are solved from the interpolated states instead, as an ODE solver computes them at output
/// points. F(t, y, y') = 0 is solved for the states' rates and the algebraic unknowns with the
/// states fixed, by Newton steps with the matrix of the first such point in IDA's step.
void SolveUntestedAt(IntegrationState* run, double t) {
  IdaSession& ida = *run->ida;
  ModelState* state = ida.callback_data.state;
  const std::vector<bool>& is_state = state->model().is_state;
  const size_t n = run->num_unknowns;
  std::vector<double>& y = run->y;
  std::vector<double>& yp = run->yp;
  std::vector<double>& f = ida.untested_residual;
  Eigen::VectorXd& b = ida.untested_rhs;
  Eigen::VectorXd& dx = ida.untested_step;
  f.resize(n);
  b.resize(static_cast<int>(n));
  double step_time = NAN;
  CheckFlag(IDAGetCurrentTime(ida.mem.get(), &step_time), "IDAGetCurrentTime");
  bool fresh = false;
  for (int it = 0; it < 6; ++it) {
    state->Residual(t, y.data(), yp.data(), f.data());
    if (std::all_of(f.begin(), f.end(), [](double r) { return r == 0; })) return;
    if (!ida.interpolation_matrix || ida.interpolated_at != step_time || (it == 3 && !fresh)) {
      if (ida.interpolation_matrix) {
        ida.interpolation_matrix->Evaluate(state, t, y.data(), yp.data());  // keeps its ordering
      } else {
        ida.interpolation_matrix = std::make_unique<MixedJacobian>(state, t, y.data(), yp.data());
      }
      ida.interpolated_at = step_time;
      fresh = true;
      if (!ida.interpolation_matrix->Factor()) {
        ida.interpolation_matrix.reset();
        return;
      }
    }
    for (size_t r = 0; r < n; ++r) b[static_cast<int>(r)] = -f[r];
    ida.interpolation_matrix->Solve(b, &dx);
    if (!dx.allFinite()) return;
    for (size_t c = 0; c < n; ++c) (is_state[c] ? yp[c] : y[c]) += dx[static_cast<int>(c)];
    if (Converged(*run, ida.abstol.get(), dx, y, yp, is_state)) return;
  }
}

}  // namespace

void Interpolate(IntegrationState* run, double t) {
  if (run->num_unknowns == 0) return;
  IdaSession& ida = *run->ida;
  CheckFlag(IDAGetDky(ida.mem.get(), t, 0, ida.interpolated_y.get()), "IDAGetDky");
  CheckFlag(IDAGetDky(ida.mem.get(), t, 1, ida.interpolated_yp.get()), "IDAGetDky");
  const double* y = N_VGetArrayPointer(ida.interpolated_y.get());
  const double* yp = N_VGetArrayPointer(ida.interpolated_yp.get());
  run->y.assign(y, y + run->num_unknowns);
  run->yp.assign(yp, yp + run->num_unknowns);
  if (ida.algebraic_untested) SolveUntestedAt(run, t);
}

void Restart(const CompiledModel& model, ModelState* state, IntegrationState* run, double t) {
  if (run->num_unknowns == 0) return;
  // The same values at the same time as the last restart: IDA already starts from them.
  const double* events = state->event_values();
  const size_t num_events = state->num_event_values();
  if (t == run->restarted_at && run->y == run->restarted_y &&
      std::equal(events, events + num_events, run->restarted_event_values.begin(),
                 run->restarted_event_values.end())) {
    return;
  }
  IdaSession& ida = *run->ida;
  SolverStats* stats = run->stats;
  CollectIdaStats(run);
  ida.before_restart.steps = stats->steps;
  ida.before_restart.residual_evals = stats->residual_evals;
  ida.before_restart.jacobian_evals = stats->jacobian_evals;
  ida.before_restart.error_test_failures = stats->error_test_failures;
  ida.before_restart.nonlinear_failures = stats->nonlinear_failures;
  ++stats->restarts;
  ida.interpolated_at = NAN;  // evaluated anew at the next step; factored anew if it changed
  void* mem = ida.mem.get();
  SetAlgebraicRates(run);
  Load(run);
  CheckFlag(IDAReInit(mem, t, ida.y.get(), ida.yp.get()), "IDAReInit");
  int flag = CalcConsistentValues(run, t, /*line_search=*/true);
  if (flag < 0) {
    // IDACalcIC's line search can stall on a step that the plain Newton iteration takes (after
    // an impulse, where velocities and the unknowns that follow them jump): once more without.
    Load(run);
    CheckFlag(IDAReInit(mem, t, ida.y.get(), ida.yp.get()), "IDAReInit");
    flag = CalcConsistentValues(run, t, /*line_search=*/false);
  }
  // IDACalcIC stops at a singular matrix where the equations leave a split open (two stuck
  // friction elements in series): then steps of least norm from run->y, run->y' pick one.
  if (flag >= 0) {
    CheckFlag(IDAGetConsistentIC(mem, ida.y.get(), ida.yp.get()), "IDAGetConsistentIC");
    ReadIdaValues(run);
  } else if (!SolveMixedByMinimumNormSteps(state, t, &run->y, &run->yp)) {
    const std::string& error = ida.callback_data.error;
    throw SolverError("at t = " + NumberText(t) + ": no consistent restart after the event (IDACalcIC: " +
                      FlagName(flag) + (error.empty() ? "" : ", " + error) +
                      "); the discrete values or re-initialised states contradict the equations");
  }
  if (ida.restart_abstol) {
    // Back to the integration's tolerances; IDA takes them at its next (re)initialisation.
    CheckFlag(IDASVtolerances(mem, run->options.rtol, ida.abstol.get()), "IDASVtolerances");
  }
  // Consistent values polished, the rates of the algebraic unknowns with them (IDACalcIC
  // leaves those as they were), then IDA from there.
  SetAlgebraicRates(run);
  PolishConsistentValues(model, state, run, t);
  Load(run);
  CheckFlag(IDAReInit(mem, t, ida.y.get(), ida.yp.get()), "IDAReInit");
  run->restarted_at = t;
  run->restarted_y = run->y;
  run->restarted_event_values.assign(events, events + num_events);
}

void PolishConsistentValues(const CompiledModel& model, ModelState* state, IntegrationState* run,
                            double t) {
  const size_t n = run->num_unknowns;
  if (n == 0) return;
  std::vector<double>& y = run->y;
  std::vector<double>& yp = run->yp;
  const bool all_states = std::all_of(model.is_state.begin(), model.is_state.end(), [](bool s) { return s; });
  std::vector<double> f(n);
  state->Residual(t, y.data(), yp.data(), f.data());
  const auto consistent = [&f] { return std::all_of(f.begin(), f.end(), [](double r) { return r == 0; }); };
  if (all_states && consistent()) return;
  // One factorisation serves the Newton steps (a simplified Newton: the values move by about
  // the tolerance) and the rates.
  MixedJacobian jacobian(state, t, y.data(), yp.data());
  if (!jacobian.Factor()) return;
  Eigen::VectorXd b(static_cast<int>(n));
  for (int it = 0; it < 2 && !consistent(); ++it) {
    for (size_t r = 0; r < n; ++r) b[static_cast<int>(r)] = -f[r];
    const Eigen::VectorXd x = jacobian.Solve(b);
    if (!x.allFinite()) return;
    for (size_t c = 0; c < n; ++c) (model.is_state[c] ? yp[c] : y[c]) += x[static_cast<int>(c)];
    state->Residual(t, y.data(), yp.data(), f.data());
  }
  if (all_states) return;
  // The algebraic unknowns' rates: dF/dt by a central difference, less dF/dy over the states
  // times their rates.
  const double h = 1e-6 * std::max(1.0, std::fabs(t));
  std::vector<double> ahead(n), behind(n);
  state->Residual(t + h, y.data(), yp.data(), ahead.data());
  state->Residual(t - h, y.data(), yp.data(), behind.data());
  for (size_t r = 0; r < n; ++r) b[static_cast<int>(r)] = -(ahead[r] - behind[r]) / (2 * h);
  const SparsePattern& pattern = model.jacobian_pattern;
  const std::vector<double>& dfdy = jacobian.dfdy();
  for (int32_t c = 0; c < pattern.cols; ++c) {
    if (!model.is_state[c]) continue;
    for (int32_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) {
      b[pattern.row_index[k]] -= dfdy[k] * yp[c];
    }
  }
  const Eigen::VectorXd x = jacobian.Solve(b);
  if (!x.allFinite()) return;
  for (size_t c = 0; c < n; ++c) {
    if (!model.is_state[c]) yp[c] = x[static_cast<int>(c)];
  }
}

void CollectIdaStats(IntegrationState* run) {
  void* mem = run->ida->mem.get();
  const SolverStats& before = run->ida->before_restart;
  SolverStats* stats = run->stats;
  long v = 0;
  IDAGetNumSteps(mem, &v);
  stats->steps = before.steps + v;
  IDAGetNumResEvals(mem, &v);
  stats->residual_evals = before.residual_evals + v;
  IDAGetNumJacEvals(mem, &v);
  stats->jacobian_evals = before.jacobian_evals + v;
  IDAGetNumErrTestFails(mem, &v);
  stats->error_test_failures = before.error_test_failures + v;
  IDAGetNumNonlinSolvConvFails(mem, &v);
  stats->nonlinear_failures = before.nonlinear_failures + v;
}

void FailTooMuchWork(const CompiledModel& model, IntegrationState* run) { Fail(model, run, IDA_TOO_MUCH_WORK); }

}  // namespace momenta

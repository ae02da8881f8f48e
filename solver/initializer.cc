#include "solver/initializer.h"

#include <Eigen/Dense>
#include <kinsol/kinsol.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/base/messages.h"
#include "solver/crossing_search.h"
#include "solver/event_iteration.h"
#include "solver/jacobian_fill.h"
#include "solver/minimum_norm_newton.h"
#include "solver/output_rows.h"
#include "solver/sundials_support.h"

namespace momenta {

namespace {

struct KinsolData {
  ModelState* state;
  double t0;
  std::vector<double> values;
  std::string error;
  std::string last_message;
};

int InitResidual(N_Vector z, N_Vector f, void* user) {
  auto* data = static_cast<KinsolData*>(user);
  const int flag = GuardedCall(&data->error, [&] {
    data->state->InitResidual(data->t0, N_VGetArrayPointer(z), N_VGetArrayPointer(f));
  });
  return flag != 0 ? flag : RetryUnlessFinite(f);  // the line search backs off a non-finite one
}

int InitJacobian(N_Vector z, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector) {
  auto* data = static_cast<KinsolData*>(user);
  return FillJacobian(data->state->model().init_pattern, &data->values, J, &data->error,
                      [&](double* values) { data->state->InitJacobian(data->t0, N_VGetArrayPointer(z), values); });
}

void KinsolMessage(int, const char*, const char*, char* msg, void* user) {
  static_cast<KinsolData*>(user)->last_message = msg;
}

struct KinsolDeleter {
  void operator()(void* mem) const { KINFree(&mem); }
};

/// The initial conditions left out as redundant must hold at the solution of the others (to
/// 1e-8 of the largest value, at least 1e-8): otherwise they contradict them, a ModelError.
void CheckRedundant(ModelState* state, double t0, const double* z) {
  const CompiledModel& m = state->model();
  if (m.redundant_exprs.empty()) return;
  std::vector<double> r(m.redundant_exprs.size());
  state->RedundantResidual(t0, z, r.data());
  double scale = 1.0;
  for (size_t k = 0; k < m.num_unknowns(); ++k) scale = std::max(scale, std::fabs(z[k]));
  std::ostringstream msg;
  size_t violated = 0;
  for (size_t k = 0; k < r.size(); ++k) {
    if (std::fabs(r[k]) <= 1e-8 * scale) continue;
    std::string from = m.redundant_from[k];
    for (size_t pos = 0; (pos = from.find('\n', pos)) != std::string::npos; pos += 5) from.replace(pos, 1, "\n    ");
    msg << (violated++ ? "\n  and the " : "") << m.redundant_origin[k] << " is off by " << r[k]
        << " at the solution of the others; it follows from\n    " << from;
  }
  if (violated == 0) return;
  throw ModelError("at initialisation: the initial conditions contradict each other: the " + msg.str() +
                   "\n  Make the fixed start values consistent, or set fixed: false on " +
                   (violated == 1 ? "it." : "them."));
}

}  // namespace

namespace {

/// One Newton solve of [F; G] = 0 from the guesses `y0` for y (y' from 0); throws SolverError when
/// it fails.
InitialValues SolveFrom(ModelState* state, double t0, bool sparse, const std::vector<double>& y0) {
  const CompiledModel& m = state->model();
  const size_t n = m.num_unknowns(), ns = m.num_states(), nz = n + ns;
  InitialValues out;
  out.y = y0;
  out.yp.assign(n, 0.0);

  ContextPtr ctx = MakeContext();
  VectorPtr z = MakeVector(static_cast<sunindextype>(nz), ctx.get());
  VectorPtr scale = MakeVector(static_cast<sunindextype>(nz), ctx.get());
  N_VConst(1.0, scale.get());
  double* zv = N_VGetArrayPointer(z.get());
  for (size_t k = 0; k < n; ++k) zv[k] = out.y[k];
  for (size_t k = n; k < nz; ++k) zv[k] = 0.0;
  KinsolData data{state, t0, {}, {}, {}};
  std::unique_ptr<void, KinsolDeleter> kin(KINCreate(ctx.get()));
  CheckNotNull(kin.get(), "KINCreate");
  CheckFlag(KINInit(kin.get(), InitResidual, z.get()), "KINInit");
  CheckFlag(KINSetUserData(kin.get(), &data), "KINSetUserData");
  CheckFlag(KINSetErrHandlerFn(kin.get(), KinsolMessage, &data), "KINSetErrHandlerFn");
  LinearSystem ls = MakeLinearSystem(z.get(), static_cast<sunindextype>(nz),
                                     static_cast<sunindextype>(m.init_pattern.nnz()), sparse, ctx.get());
  CheckFlag(KINSetLinearSolver(kin.get(), ls.solver.get(), ls.matrix.get()), "KINSetLinearSolver");
  CheckFlag(KINSetJacFn(kin.get(), InitJacobian), "KINSetJacFn");
  CheckFlag(KINSetMaxSetupCalls(kin.get(), 1), "KINSetMaxSetupCalls");
  CheckFlag(KINSetNumMaxIters(kin.get(), 200), "KINSetNumMaxIters");
  CheckFlag(KINSetFuncNormTol(kin.get(), 1e-12), "KINSetFuncNormTol");
  CheckFlag(KINSetScaledStepTol(kin.get(), 1e-14), "KINSetScaledStepTol");
  // KINSOL bounds a Newton step by 1000*|z0| (at least 1): from an all-zero guess that clips the
  // first step of even a linear system. Initial values may be far from the guesses, so lift it.
  // The derivatives can be huge (an RC ladder's last capacitor: dv/dt ~ n^3), so no cap that
  // a linear system could exceed; the line search still guards nonlinear ones.
  CheckFlag(KINSetMaxNewtonStep(kin.get(), 1e300), "KINSetMaxNewtonStep");

  int flag = KINSol(kin.get(), z.get(), KIN_LINESEARCH, scale.get(), scale.get());
  long iters = 0;
  KINGetNumNonlinSolvIters(kin.get(), &iters);
  out.iterations = iters;
  if (!data.error.empty()) throw SolverError("initialisation at t = " + NumberText(t0) + ": " + data.error);

  // Residuals at the solution: accept KINSOL's step-tolerance stop when they are small.
  std::vector<double> f(nz);
  state->InitResidual(t0, zv, f.data());
  // The worst residual: the first that is not a number (NaN or infinite: an equation evaluated
  // outside its domain, which is what the user must see), else the largest in magnitude.
  size_t worst = 0;
  for (size_t k = 0; k < nz; ++k) {
    if (!std::isfinite(f[worst])) break;
    if (!std::isfinite(f[k]) || std::fabs(f[k]) > std::fabs(f[worst])) worst = k;
  }
  out.max_residual = std::fabs(f[worst]);
  double scale_of_z = 1.0;
  for (size_t k = 0; k < nz; ++k) scale_of_z = std::max(scale_of_z, std::fabs(zv[k]));
  if (flag < 0 || !(out.max_residual <= 1e-8 * scale_of_z)) {
    std::ostringstream msg;
    msg << "initialisation failed";
    if (flag < 0) msg << " (KINSOL: " << (data.last_message.empty() ? "flag " + std::to_string(flag) : data.last_message) << ")";
    const std::string origin = worst < n ? m.residual_origin(worst) : m.initial_origin[worst - n];
    if (std::isfinite(f[worst])) {
      msg << ": the largest remaining residual, " << f[worst] << ", is in " << origin;
    } else {
      msg << ": the residual of " << origin << " is " << f[worst] << " (evaluated outside its domain?)";
    }
    msg << ". Check the fixed start values and the parameters, or give better start values.";
    throw SolverError(msg.str());
  }
  CheckRedundant(state, t0, zv);
  for (size_t k = 0; k < n; ++k) out.y[k] = zv[k];
  for (size_t s = 0; s < ns; ++s) out.yp[m.state_y[s]] = zv[n + s];
  return out;
}

/// The initial system by Newton steps of least norm (minimum_norm_newton.h) from the guesses
/// `y0`, for a system that holds but leaves some unknowns free where KINSOL's LU stops at a zero
/// pivot. False when that finds no solution.
bool SolveMinimumNorm(ModelState* state, double t0, const std::vector<double>& y0, InitialValues* out) {
  const CompiledModel& m = state->model();
  const size_t n = m.num_unknowns(), nz = n + m.num_states();
  const SparsePattern& pattern = m.init_pattern;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nz));
  for (size_t k = 0; k < n; ++k) z[static_cast<Eigen::Index>(k)] = y0[k];
  std::vector<double> values(pattern.nnz());
  std::string ignored;  // a residual or Jacobian that cannot be evaluated ends the search
  const auto residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd* f) {
    return GuardedCall(&ignored, [&] { state->InitResidual(t0, at.data(), f->data()); }) == 0;
  };
  const auto jacobian = [&](const Eigen::VectorXd& at, Eigen::MatrixXd* J) {
    if (GuardedCall(&ignored, [&] { state->InitJacobian(t0, at.data(), values.data()); }) != 0) return false;
    for (int32_t c = 0; c < pattern.cols; ++c) {
      for (int32_t p = pattern.col_start[c]; p < pattern.col_start[c + 1]; ++p) (*J)(pattern.row_index[p], c) = values[p];
    }
    return true;
  };
  const int iterations = SolveByMinimumNormSteps(residual, jacobian, &z);
  if (iterations < 0) return false;
  Eigen::VectorXd f(z.size());
  state->InitResidual(t0, z.data(), f.data());
  out->y.assign(z.data(), z.data() + n);
  out->yp.assign(n, 0.0);
  for (size_t s = 0; s < m.num_states(); ++s) out->yp[m.state_y[s]] = z[static_cast<Eigen::Index>(n + s)];
  out->iterations = iterations;
  out->max_residual = f.cwiseAbs().maxCoeff();
  CheckRedundant(state, t0, z.data());
  return true;
}

}  // namespace

InitialValues SolveInitialization(ModelState* state, double t0, bool sparse) {
  const CompiledModel& m = state->model();
  const size_t n = m.num_unknowns(), nz = n + m.num_states();
  std::vector<double> y0(n, 0.0);
  state->StartValues(y0.data());
  if (nz == 0) {
    InitialValues out;
    out.y = y0;
    out.yp.assign(n, 0.0);
    return out;
  }
  // The start values first (as given: a model that initialises from them is solved as before);
  // when Newton fails from them, once more from the guesses that the equations determining the
  // unknowns explicitly give (a chain's bodies where its joint angles put them).
  // Last, Newton with minimum-norm steps from the start values, for a system that holds but
  // leaves some unknowns free (SolveMinimumNorm); its solution is checked as KINSOL's is.
  try {
    return SolveFrom(state, t0, sparse, y0);
  } catch (const SolverError& first) {
    std::vector<double> y1(n, 0.0);
    state->StartGuesses(y1.data());
    if (y1 != y0) {
      try {
        return SolveFrom(state, t0, sparse, y1);
      } catch (const SolverError&) {
      }
    }
    InitialValues out;
    if (!SolveMinimumNorm(state, t0, y0, &out)) throw first;
    return out;
  }
}

namespace {

/// run->y, run->y' := consistent values at the start for the current discrete values.
void SolveAtStart(ModelState* state, IntegrationState* run) {
  InitialValues init = SolveInitialization(state, run->options.start, run->sparse);
  run->stats->init_iterations += init.iterations;
  run->y = init.y;
  run->yp = init.yp;
}

/// Continuous values at the start (SolveAtStart) and the conditions and discrete values they
/// give, until the two agree. Discrete equations solved with the initial system see
/// initial() = true (MSL's friction elements start sliding from `initial() and v > 0`).
void SettleStartValues(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const double start = run->options.start;
  for (int iter = 0;; ++iter) {
    SolveAtStart(state, run);
    if (!run->has_events) break;
    state->set_initial(true);
    bool changed = SetConditions(model, state, run, start, kAtValue);
    changed = UpdateDiscrete(state, run, start) || changed;
    state->set_initial(false);
    if (!changed) break;
    if (iter == 50) {
      throw SolverError("at t = " + NumberText(start) +
                        ": the initial discrete values do not settle (the conditions switch back and forth)");
    }
  }
}

}  // namespace

void InitializeRun(const CompiledModel& model, ModelState* state, IntegrationState* run) {
  const double start = run->options.start;
  const auto started = std::chrono::steady_clock::now();
  state->StartDiscrete();
  run->y.assign(run->num_unknowns, 0.0);
  run->yp.assign(run->num_unknowns, 0.0);
  state->StartValues(run->y.data());
  state->SavePre(run->y.data());
  // First guesses for the conditions: their values at the start values.
  SetConditions(model, state, run, start, kAtValue);
  SettleStartValues(model, state, run);
  StartWhens(model, state, run);
  state->SavePre(run->y.data());
  CheckNoContactOverlaps(model, state, run, start);
  run->stats->init_seconds = SecondsSince(started);
  Emit(state, run, start, run->y.data(), run->yp.data());
  // The initial event: with pre() now the initial values, discrete equations such as
  // edge(u) = u and not pre(u) may change at once; a second row at the start time shows it.
  if (run->has_events && Iterate(model, state, run, start, /*restart=*/false)) {
    if (run->num_unknowns > 0) SolveAtStart(state, run);
    run->last_event_time = start;
    Emit(state, run, start, run->y.data(), run->yp.data());
  }
}

}  // namespace momenta

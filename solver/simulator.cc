#include "solver/simulator.h"

#include <ida/ida.h>

#include <chrono>
#include <cmath>
#include <sstream>

#include "solver/initializer.h"
#include "solver/jacobian_fill.h"
#include "solver/sundials_support.h"

namespace momenta {

namespace {

struct IdaData {
  ModelState* state;
  std::vector<double> jac_values;
  std::string error;         ///< an exception caught in a callback
  std::string last_message;  ///< IDA's own last error message
};

// The SUNDIALS boundary: no exception crosses it. A non-finite residual asks IDA for a smaller
// step (positive return); an exception is stored and stops the solver (negative return).
int Residual(double t, N_Vector y, N_Vector yp, N_Vector r, void* user) {
  auto* d = static_cast<IdaData*>(user);
  try {
    d->state->Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r));
  } catch (const std::exception& e) {
    d->error = e.what();
    return -1;
  }
  const double* rv = N_VGetArrayPointer(r);
  for (sunindextype k = 0, n = N_VGetLength(r); k < n; ++k) {
    if (!std::isfinite(rv[k])) return 1;
  }
  return 0;
}

int Jacobian(double t, double cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix J, void* user,
             N_Vector, N_Vector, N_Vector) {
  auto* d = static_cast<IdaData*>(user);
  try {
    const SparsePattern& pattern = d->state->model().jacobian_pattern;
    d->jac_values.resize(pattern.nnz());
    d->state->Jacobian(t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), d->jac_values.data());
    FillMatrix(pattern, d->jac_values, J);
  } catch (const std::exception& e) {
    d->error = e.what();
    return -1;
  }
  return 0;
}

void IdaMessage(int, const char*, const char*, char* msg, void* user) {
  static_cast<IdaData*>(user)->last_message = msg;
}

struct IdaDeleter {
  void operator()(void* mem) const { IDAFree(&mem); }
};

double Elapsed(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string FlagMeaning(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK: return "too many steps without reaching the next output time";
    case IDA_TOO_MUCH_ACC: return "the requested accuracy cannot be reached";
    case IDA_ERR_FAIL: return "the error test failed repeatedly (a discontinuity or a singularity?)";
    case IDA_CONV_FAIL: return "Newton's method failed to converge repeatedly";
    case IDA_LSETUP_FAIL:
    case IDA_LSOLVE_FAIL: return "the linear solver failed (a singular Jacobian?)";
    case IDA_RES_FAIL: return "the residual could not be evaluated";
    case IDA_REP_RES_ERR: return "the residual returned non-finite values repeatedly";
    default: return "";
  }
}

}  // namespace

SimulationOptions OptionsFromExperiment(const ExperimentSpec& e) {
  SimulationOptions o;
  o.start = e.start;
  o.stop = e.stop;
  o.interval = e.interval;
  o.rtol = e.tolerance;
  o.linear_solver = e.linear_solver;
  return o;
}

void Simulate(ModelState* state, const SimulationOptions& opt, const RowCallback& row,
              SolverStats* stats) {
  const CompiledModel& m = state->model();
  const size_t n = m.num_unknowns();
  const double interval = opt.interval > 0 ? opt.interval : (opt.stop - opt.start) / 500.0;
  const double atol = opt.atol > 0 ? opt.atol : opt.rtol;
  bool sparse = opt.linear_solver == "klu" || (opt.linear_solver == "auto" && n > kDenseLimit);
  stats->linear_solver = sparse ? "klu" : "dense";
  std::vector<double> outputs(m.output_names.size());

  // Consistent initial values.
  auto t_init = std::chrono::steady_clock::now();
  InitialValues init = SolveInitialization(state, opt.start, sparse);
  stats->init_iterations = init.iterations;
  stats->init_seconds = Elapsed(t_init);
  state->Outputs(opt.start, init.y.data(), init.yp.data(), outputs.data());
  row(opt.start, outputs);
  stats->final_time = opt.start;

  // Output times: start + k*interval, and stop itself.
  const long num_intervals = static_cast<long>(std::ceil((opt.stop - opt.start) / interval - 1e-9));
  auto tout_of = [&](long k) { return k >= num_intervals ? opt.stop : opt.start + k * interval; };

  auto t_run = std::chrono::steady_clock::now();
  if (n == 0) {
    // Nothing to integrate: the outputs are explicit functions of time.
    for (long k = 1; k <= num_intervals; ++k) {
      state->Outputs(tout_of(k), nullptr, nullptr, outputs.data());
      row(tout_of(k), outputs);
    }
    stats->final_time = opt.stop;
    stats->integrate_seconds = Elapsed(t_run);
    return;
  }

  ContextPtr ctx = MakeContext();
  VectorPtr y = MakeVector(static_cast<sunindextype>(n), ctx.get());
  VectorPtr yp = MakeVector(static_cast<sunindextype>(n), ctx.get());
  VectorPtr abstol = MakeVector(static_cast<sunindextype>(n), ctx.get());
  VectorPtr id = MakeVector(static_cast<sunindextype>(n), ctx.get());
  double* yv = N_VGetArrayPointer(y.get());
  double* ypv = N_VGetArrayPointer(yp.get());
  for (size_t k = 0; k < n; ++k) {
    yv[k] = init.y[k];
    ypv[k] = init.yp[k];
    N_VGetArrayPointer(abstol.get())[k] = atol * m.nominal[k];
    N_VGetArrayPointer(id.get())[k] = m.is_state[k] ? 1.0 : 0.0;
  }

  IdaData data{state, {}, {}, {}};
  std::unique_ptr<void, IdaDeleter> ida(IDACreate(ctx.get()));
  CheckNotNull(ida.get(), "IDACreate");
  void* mem = ida.get();
  CheckFlag(IDAInit(mem, Residual, opt.start, y.get(), yp.get()), "IDAInit");
  CheckFlag(IDASetUserData(mem, &data), "IDASetUserData");
  CheckFlag(IDASetErrHandlerFn(mem, IdaMessage, &data), "IDASetErrHandlerFn");
  CheckFlag(IDASVtolerances(mem, opt.rtol, abstol.get()), "IDASVtolerances");
  CheckFlag(IDASetId(mem, id.get()), "IDASetId");
  LinearSystem ls = MakeLinearSystem(y.get(), static_cast<sunindextype>(n),
                                     static_cast<sunindextype>(m.jacobian_pattern.nnz()), sparse, ctx.get());
  CheckFlag(IDASetLinearSolver(mem, ls.solver.get(), ls.matrix.get()), "IDASetLinearSolver");
  CheckFlag(IDASetJacFn(mem, Jacobian), "IDASetJacFn");
  CheckFlag(IDASetMaxNumSteps(mem, 200000), "IDASetMaxNumSteps");
  CheckFlag(IDASetStopTime(mem, opt.stop), "IDASetStopTime");

  auto collect = [&]() {
    long v = 0;
    IDAGetNumSteps(mem, &v);
    stats->steps = v;
    IDAGetNumResEvals(mem, &v);
    stats->residual_evals = v;
    IDAGetNumJacEvals(mem, &v);
    stats->jacobian_evals = v;
    IDAGetNumErrTestFails(mem, &v);
    stats->error_test_failures = v;
    IDAGetNumNonlinSolvConvFails(mem, &v);
    stats->nonlinear_failures = v;
    stats->integrate_seconds = Elapsed(t_run);
  };

  for (long k = 1; k <= num_intervals; ++k) {
    double tout = tout_of(k), tret = 0;
    int flag = IDASolve(mem, tout, &tret, y.get(), yp.get(), IDA_NORMAL);
    if (flag < 0) {
      collect();
      double t_fail = tret;
      IDAGetCurrentTime(mem, &t_fail);
      stats->final_time = t_fail;
      std::ostringstream msg;
      msg << "at t = " << t_fail << ": ";
      if (!data.error.empty()) {
        msg << data.error;
      } else {
        msg << "IDA stopped (" << IDAGetReturnFlagName(flag) << "): " << FlagMeaning(flag);
        // Name the variable with the largest weighted local error.
        VectorPtr ewt = MakeVector(static_cast<sunindextype>(n), ctx.get());
        VectorPtr ele = MakeVector(static_cast<sunindextype>(n), ctx.get());
        if (IDAGetErrWeights(mem, ewt.get()) == IDA_SUCCESS &&
            IDAGetEstLocalErrors(mem, ele.get()) == IDA_SUCCESS) {
          size_t worst = 0;
          double worst_err = -1;
          for (size_t j = 0; j < n; ++j) {
            double e = std::fabs(N_VGetArrayPointer(ele.get())[j] * N_VGetArrayPointer(ewt.get())[j]);
            if (e > worst_err) {
              worst_err = e;
              worst = j;
            }
          }
          msg << ". The largest local error is in " << m.flat->DescribeVariable(m.unknowns[worst])
              << ", governed by " << m.residual_origin[worst];
        }
        msg << ". Try a tighter tolerance (--rtol), check the parameters of that component, or "
               "look for a singularity in its equations.";
      }
      throw SolverError(msg.str());
    }
    state->Outputs(tout, yv, ypv, outputs.data());
    row(tout, outputs);
    stats->final_time = tout;
  }
  collect();
}

}  // namespace momenta

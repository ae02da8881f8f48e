// Shared driver for the hand-written IDA reference programs (handwritten_chain, handwritten_rc).
//
// They solve a benchmark DAE directly with SUNDIALS IDA, without momenta, so that momenta's
// timings and results can be compared with what a careful hand-written program achieves.
// RAII wrappers own every SUNDIALS object and every return flag is checked (a failure throws).
#pragma once

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_types.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#ifndef MOMENTA_SUNDIALS_OPTIMIZED
#define MOMENTA_SUNDIALS_OPTIMIZED 0
#endif

namespace hw {

// ---- error checking ----------------------------------------------------------------------

inline void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string(what) + " failed with flag " + std::to_string(flag));
}

template <class T>
T* check_ptr(T* p, const char* what) {
  if (p == nullptr) throw std::runtime_error(std::string(what) + " returned NULL");
  return p;
}

// ---- RAII owners -------------------------------------------------------------------------

class Context {
 public:
  Context() { check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create"); }
  ~Context() { SUNContext_Free(&ctx_); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  operator SUNContext() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver ls) const { SUNLinSolFree(ls); }
};
using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;

class Ida {
 public:
  explicit Ida(SUNContext ctx) : mem_(check_ptr(IDACreate(ctx), "IDACreate")) {}
  ~Ida() { IDAFree(&mem_); }
  Ida(const Ida&) = delete;
  Ida& operator=(const Ida&) = delete;
  void* get() const { return mem_; }

 private:
  void* mem_;
};

inline Vector make_vector(sunindextype n, SUNContext ctx) {
  return Vector(check_ptr(N_VNew_Serial(n, ctx), "N_VNew_Serial"));
}

// ---- command line ------------------------------------------------------------------------

struct Options {
  long n = 100;
  double stop = 10.0;
  double rtol = 1e-6;
  double atol = 1e-6;
  double interval = -1.0;  // default: stop / 500
  std::string linear_solver = "klu";
  int repeat = 5;
  int max_order = 5;  // IDA's highest BDF order (IDASetMaxOrd); 5 is IDA's default
};

inline void usage(const char* prog, const Options& d) {
  std::fprintf(stderr,
               "usage: %s [--n N] [--stop T] [--rtol R] [--atol A] [--linear-solver dense|klu]\n"
               "          [--interval DT] [--repeat K] [--max-order Q]\n"
               "defaults: --n %ld --stop %g --rtol %g --atol %g --linear-solver %s --interval stop/500 "
               "--repeat %d\n",
               prog, d.n, d.stop, d.rtol, d.atol, d.linear_solver.c_str(), d.repeat);
}

// Parses "--key value" and "--key=value"; exits with a usage message on errors.
inline Options parse_options(int argc, char** argv, Options o) {
  const Options defaults = o;
  auto fail = [&](const std::string& msg) {
    std::fprintf(stderr, "%s: %s\n", argv[0], msg.c_str());
    usage(argv[0], defaults);
    std::exit(2);
  };
  for (int i = 1; i < argc; ++i) {
    std::string key = argv[i];
    std::string value;
    if (key == "-h" || key == "--help") {
      usage(argv[0], defaults);
      std::exit(0);
    }
    const auto eq = key.find('=');
    if (eq != std::string::npos) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    } else {
      if (i + 1 >= argc) fail("missing value for " + key);
      value = argv[++i];
    }
    try {
      std::size_t used = 0;
      auto whole = [&](std::size_t u) {
        if (u != value.size()) throw std::invalid_argument(value);
      };
      if (key == "--n") {
        o.n = std::stol(value, &used), whole(used);
      } else if (key == "--stop") {
        o.stop = std::stod(value, &used), whole(used);
      } else if (key == "--rtol") {
        o.rtol = std::stod(value, &used), whole(used);
      } else if (key == "--atol") {
        o.atol = std::stod(value, &used), whole(used);
      } else if (key == "--interval") {
        o.interval = std::stod(value, &used), whole(used);
      } else if (key == "--max-order") {
        o.max_order = std::stoi(value, &used), whole(used);
      } else if (key == "--repeat") {
        o.repeat = std::stoi(value, &used), whole(used);
      } else if (key == "--linear-solver") {
        o.linear_solver = value;
      } else {
        fail("unknown option " + key);
      }
    } catch (const std::logic_error&) {
      fail("bad value '" + value + "' for " + key);
    }
  }
  if (o.interval <= 0) o.interval = o.stop / 500.0;
  if (o.n < 1) fail("--n must be >= 1");
  if (!(o.stop > 0)) fail("--stop must be > 0");
  if (!(o.rtol > 0) || !(o.atol > 0)) fail("tolerances must be > 0");
  if (o.repeat < 1) fail("--repeat must be >= 1");
  if (o.max_order < 1 || o.max_order > 5) fail("--max-order must be in 1..5");
  if (o.linear_solver != "dense" && o.linear_solver != "klu") fail("--linear-solver must be dense or klu");
  return o;
}

// ---- problem interface and driver --------------------------------------------------------

// A benchmark problem: residual, analytic Jacobians (dense and CSC), consistent initial values.
// user_data passed to the callbacks is the Problem itself.
struct Problem {
  virtual ~Problem() = default;
  virtual const char* name() const = 0;
  virtual sunindextype size() const = 0;
  virtual sunindextype jacobian_nnz() const = 0;
  virtual void initial_values(double t0, double* y, double* yp) const = 0;
  virtual IDAResFn residual() const = 0;
  virtual IDALsJacFn dense_jacobian() const = 0;
  virtual IDALsJacFn sparse_jacobian() const = 0;
  // Two named final values printed per run (e.g. s_n, v_n), for comparison with other programs.
  virtual const char* final_name(int k) const = 0;
  virtual double final_value(const double* y, int k) const = 0;
};

struct RunResult {
  double setup_s = 0, solve_s = 0;
  double setup_cpu_s = 0, solve_cpu_s = 0;  // CPU time of the process (robust on a shared machine)
  long steps = 0, res_evals = 0, jac_evals = 0, nonlin_iters = 0, lin_setups = 0, err_test_fails = 0,
       nonlin_conv_fails = 0;
  double final0 = 0, final1 = 0, t_end = 0;
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU time used by this process so far (user + system), in seconds.
inline double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// One integration from 0 to opt.stop with output requests every opt.interval.
inline RunResult run_once(const Options& opt, Problem& p) {
  RunResult r;
  const double t0 = 0.0;
  const auto start_setup = std::chrono::steady_clock::now();
  const double cpu_setup = cpu_seconds();

  Context ctx;
  const sunindextype N = p.size();
  Vector y = make_vector(N, ctx);
  Vector yp = make_vector(N, ctx);
  p.initial_values(t0, N_VGetArrayPointer(y.get()), N_VGetArrayPointer(yp.get()));

  Matrix A;
  LinearSolver LS;
  if (opt.linear_solver == "dense") {
    A.reset(check_ptr(SUNDenseMatrix(N, N, ctx), "SUNDenseMatrix"));
    LS.reset(check_ptr(SUNLinSol_Dense(y.get(), A.get(), ctx), "SUNLinSol_Dense"));
  } else {
    A.reset(check_ptr(SUNSparseMatrix(N, N, p.jacobian_nnz(), CSC_MAT, ctx), "SUNSparseMatrix"));
    LS.reset(check_ptr(SUNLinSol_KLU(y.get(), A.get(), ctx), "SUNLinSol_KLU"));
  }

  Ida ida(ctx);
  void* mem = ida.get();
  check(IDAInit(mem, p.residual(), t0, y.get(), yp.get()), "IDAInit");
  check(IDASStolerances(mem, opt.rtol, opt.atol), "IDASStolerances");
  check(IDASetUserData(mem, &p), "IDASetUserData");
  check(IDASetLinearSolver(mem, LS.get(), A.get()), "IDASetLinearSolver");
  check(IDASetJacFn(mem, opt.linear_solver == "dense" ? p.dense_jacobian() : p.sparse_jacobian()),
        "IDASetJacFn");
  check(IDASetStopTime(mem, opt.stop), "IDASetStopTime");
  check(IDASetMaxNumSteps(mem, 1000000), "IDASetMaxNumSteps");
  check(IDASetMaxOrd(mem, opt.max_order), "IDASetMaxOrd");
  r.setup_s = seconds_since(start_setup);
  r.setup_cpu_s = cpu_seconds() - cpu_setup;

  const auto start_solve = std::chrono::steady_clock::now();
  const double cpu_solve = cpu_seconds();
  double tret = t0;
  for (long k = 1;; ++k) {
    const double tout = std::min(t0 + k * opt.interval, opt.stop);
    const int flag = IDASolve(mem, tout, &tret, y.get(), yp.get(), IDA_NORMAL);
    check(flag, "IDASolve");
    if (flag == IDA_TSTOP_RETURN || tout >= opt.stop) break;
  }
  r.solve_s = seconds_since(start_solve);
  r.solve_cpu_s = cpu_seconds() - cpu_solve;

  check(IDAGetNumSteps(mem, &r.steps), "IDAGetNumSteps");
  check(IDAGetNumResEvals(mem, &r.res_evals), "IDAGetNumResEvals");
  check(IDAGetNumJacEvals(mem, &r.jac_evals), "IDAGetNumJacEvals");
  check(IDAGetNumNonlinSolvIters(mem, &r.nonlin_iters), "IDAGetNumNonlinSolvIters");
  check(IDAGetNumLinSolvSetups(mem, &r.lin_setups), "IDAGetNumLinSolvSetups");
  check(IDAGetNumErrTestFails(mem, &r.err_test_fails), "IDAGetNumErrTestFails");
  check(IDAGetNumNonlinSolvConvFails(mem, &r.nonlin_conv_fails), "IDAGetNumNonlinSolvConvFails");
  r.t_end = tret;
  r.final0 = p.final_value(N_VGetArrayPointer(y.get()), 0);
  r.final1 = p.final_value(N_VGetArrayPointer(y.get()), 1);
  return r;
}

template <class T, class F>
double median_of(const std::vector<T>& runs, F field) {
  std::vector<double> v;
  for (const auto& r : runs) v.push_back(static_cast<double>(field(r)));
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// The residual's cost per evaluation [ns]: the median of 5 timings of enough calls at the initial
// values to take about 20 ms each (momenta_bench's res_eval_ns measures momenta's the same way).
inline double residual_eval_ns(Problem& p) {
  Context ctx;
  const sunindextype N = p.size();
  Vector y = make_vector(N, ctx), yp = make_vector(N, ctx), rr = make_vector(N, ctx);
  p.initial_values(0.0, N_VGetArrayPointer(y.get()), N_VGetArrayPointer(yp.get()));
  const IDAResFn res = p.residual();
  const long calls = std::max<long>(10, static_cast<long>(2e6 / static_cast<double>(N)));
  std::vector<double> ns;
  for (int k = 0; k < 5; ++k) {
    const double c0 = cpu_seconds();
    for (long i = 0; i < calls; ++i) res(1e-3 * static_cast<double>(i % 7), y.get(), yp.get(), rr.get(), &p);
    ns.push_back((cpu_seconds() - c0) * 1e9 / static_cast<double>(calls));
  }
  return median_of(ns, [](double v) { return v; });
}

// Runs opt.repeat integrations, prints one line per run and a line of medians.
// Output lines are "key=value" pairs so that scripts can compare them with other programs.
inline int run_benchmark(const Options& opt, Problem& p) {
  std::printf("# %s n=%ld N=%lld stop=%g rtol=%g atol=%g interval=%g linear_solver=%s max_order=%d repeat=%d\n", p.name(),
              opt.n, static_cast<long long>(p.size()), opt.stop, opt.rtol, opt.atol, opt.interval,
              opt.linear_solver.c_str(), opt.max_order, opt.repeat);
  std::printf("# SUNDIALS %s (%s build)\n", SUNDIALS_VERSION,
              MOMENTA_SUNDIALS_OPTIMIZED ? "optimised" : "system");
  std::vector<RunResult> runs;
  for (int k = 0; k < opt.repeat; ++k) {
    RunResult r = run_once(opt, p);
    std::printf(
        "run=%d setup_s=%.6f solve_s=%.6f setup_cpu_s=%.6f solve_cpu_s=%.6f steps=%ld res_evals=%ld "
        "jac_evals=%ld nonlin_iters=%ld lin_setups=%ld err_test_fails=%ld nonlin_conv_fails=%ld t=%.10g "
        "%s=%.17g %s=%.17g\n",
        k + 1, r.setup_s, r.solve_s, r.setup_cpu_s, r.solve_cpu_s, r.steps, r.res_evals, r.jac_evals,
        r.nonlin_iters, r.lin_setups, r.err_test_fails, r.nonlin_conv_fails, r.t_end, p.final_name(0), r.final0, p.final_name(1), r.final1);
    std::fflush(stdout);
    runs.push_back(r);
  }
  std::printf("res_eval_ns=%.1f\n", residual_eval_ns(p));
  std::printf(
      "median setup_s=%.6f solve_s=%.6f setup_cpu_s=%.6f solve_cpu_s=%.6f steps=%.0f res_evals=%.0f jac_evals=%.0f "
      "%s=%.17g %s=%.17g\n",
              median_of(runs, [](const RunResult& r) { return r.setup_s; }),
              median_of(runs, [](const RunResult& r) { return r.solve_s; }),
              median_of(runs, [](const RunResult& r) { return r.setup_cpu_s; }),
              median_of(runs, [](const RunResult& r) { return r.solve_cpu_s; }),
              median_of(runs, [](const RunResult& r) { return r.steps; }),
              median_of(runs, [](const RunResult& r) { return r.res_evals; }),
              median_of(runs, [](const RunResult& r) { return r.jac_evals; }), p.final_name(0),
              median_of(runs, [](const RunResult& r) { return r.final0; }), p.final_name(1),
              median_of(runs, [](const RunResult& r) { return r.final1; }));
  return 0;
}

// Guard against dense Jacobians that cannot finish: N x N doubles and an O(N^3) LU per Jacobian
// (N = 8192: 0.5 GB and ~4e11 flops per factorisation; N = 20000 would take hours).
inline void check_dense_size(const Options& opt, sunindextype N) {
  constexpr sunindextype max_dense = 8192;
  if (opt.linear_solver == "dense" && N > max_dense) {
    throw std::runtime_error("a dense Jacobian of size " + std::to_string(N) + " (> " + std::to_string(max_dense) +
                             ") would need " + std::to_string(8.0 * N * N / 1e9) +
                             " GB and O(N^3) factorisations; use --linear-solver klu");
  }
}

}  // namespace hw

// The undamped oscillator x'' = -w^2 x (w = 2 pi rad/s, x(0) = 1, v(0) = 0) over N periods with
// SUNDIALS directly: IDA (BDF, the integrator momenta uses) on the DAE x' - v = 0, v' + w^2 x = 0,
// and CVODE on the ODE x' = v, v' = -w^2 x with Adams-Moulton (fixed-point iteration, orders 1..12)
// or BDF (Newton, dense). The question it answers: for conservative models whose reduced form is
// an ODE, does CVODE Adams give a smaller energy and phase error than IDA at equal cost?
//
// usage: conservative --method ida|adams|bdf --rtol R [--periods N] [--max-order Q]
// prints: method= rtol= steps= fevals= energy_error= phase_error= seconds=
//   energy_error = |E(T)/E(0) - 1| with E = v^2/2 + w^2 x^2/2; phase_error = |phase(T) - w T| [rad]
// Built and run by bench/stress/stress.py against the system's SUNDIALS (libsundials-dev); a
// benchmark, not a test.

#include <cvode/cvode.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

constexpr double kOmega = 2 * M_PI;

int OdeRhs(double, N_Vector y, N_Vector yd, void*) {
  const double* u = N_VGetArrayPointer(y);
  double* d = N_VGetArrayPointer(yd);
  d[0] = u[1];
  d[1] = -kOmega * kOmega * u[0];
  return 0;
}

int DaeResidual(double, N_Vector y, N_Vector yp, N_Vector r, void*) {
  const double* u = N_VGetArrayPointer(y);
  const double* d = N_VGetArrayPointer(yp);
  double* f = N_VGetArrayPointer(r);
  f[0] = d[0] - u[1];
  f[1] = d[1] + kOmega * kOmega * u[0];
  return 0;
}

struct Outcome {
  long steps = 0, fevals = 0;
  double x = 0, v = 0;
};

Outcome RunCvode(SUNContext ctx, bool adams, double rtol, double stop, int max_order) {
  N_Vector y = N_VNew_Serial(2, ctx);
  N_VGetArrayPointer(y)[0] = 1;
  N_VGetArrayPointer(y)[1] = 0;
  void* mem = CVodeCreate(adams ? CV_ADAMS : CV_BDF, ctx);
  CVodeInit(mem, OdeRhs, 0, y);
  CVodeSStolerances(mem, rtol, rtol);
  CVodeSetMaxNumSteps(mem, 100000000L);
  if (max_order > 0) CVodeSetMaxOrd(mem, max_order);
  CVodeSetStopTime(mem, stop);
  SUNMatrix a = nullptr;
  SUNLinearSolver ls = nullptr;
  SUNNonlinearSolver nls = nullptr;
  if (adams) {
    nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
    CVodeSetNonlinearSolver(mem, nls);
  } else {
    a = SUNDenseMatrix(2, 2, ctx);
    ls = SUNLinSol_Dense(y, a, ctx);
    CVodeSetLinearSolver(mem, ls, a);
  }
  double t = 0;
  const int flag = CVode(mem, stop, y, &t, CV_NORMAL);
  if (flag < 0) std::fprintf(stderr, "CVode failed: %d\n", flag);
  Outcome out;
  CVodeGetNumSteps(mem, &out.steps);
  CVodeGetNumRhsEvals(mem, &out.fevals);
  out.x = N_VGetArrayPointer(y)[0];
  out.v = N_VGetArrayPointer(y)[1];
  CVodeFree(&mem);
  if (nls) SUNNonlinSolFree(nls);
  if (ls) SUNLinSolFree(ls);
  if (a) SUNMatDestroy(a);
  N_VDestroy(y);
  return out;
}

Outcome RunIda(SUNContext ctx, double rtol, double stop, int max_order) {
  N_Vector y = N_VNew_Serial(2, ctx);
  N_Vector yp = N_VNew_Serial(2, ctx);
  N_VGetArrayPointer(y)[0] = 1;
  N_VGetArrayPointer(y)[1] = 0;
  N_VGetArrayPointer(yp)[0] = 0;
  N_VGetArrayPointer(yp)[1] = -kOmega * kOmega;
  void* mem = IDACreate(ctx);
  IDAInit(mem, DaeResidual, 0, y, yp);
  IDASStolerances(mem, rtol, rtol);
  IDASetMaxNumSteps(mem, 100000000L);
  if (max_order > 0) IDASetMaxOrd(mem, max_order);
  IDASetStopTime(mem, stop);
  SUNMatrix a = SUNDenseMatrix(2, 2, ctx);
  SUNLinearSolver ls = SUNLinSol_Dense(y, a, ctx);
  IDASetLinearSolver(mem, ls, a);
  double t = 0;
  const int flag = IDASolve(mem, stop, &t, y, yp, IDA_NORMAL);
  if (flag < 0) std::fprintf(stderr, "IDASolve failed: %d\n", flag);
  Outcome out;
  IDAGetNumSteps(mem, &out.steps);
  IDAGetNumResEvals(mem, &out.fevals);
  out.x = N_VGetArrayPointer(y)[0];
  out.v = N_VGetArrayPointer(y)[1];
  IDAFree(&mem);
  SUNLinSolFree(ls);
  SUNMatDestroy(a);
  N_VDestroy(y);
  N_VDestroy(yp);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string method = "ida";
  double rtol = 1e-6, periods = 1e4;
  int max_order = 0;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (!std::strcmp(argv[k], "--method")) method = argv[k + 1];
    if (!std::strcmp(argv[k], "--rtol")) rtol = std::atof(argv[k + 1]);
    if (!std::strcmp(argv[k], "--periods")) periods = std::atof(argv[k + 1]);
    if (!std::strcmp(argv[k], "--max-order")) max_order = std::atoi(argv[k + 1]);
  }
  SUNContext ctx = nullptr;
  SUNContext_Create(nullptr, &ctx);
  const double stop = periods;  // one period per second
  const auto start = std::chrono::steady_clock::now();
  const Outcome out = method == "ida" ? RunIda(ctx, rtol, stop, max_order)
                                      : RunCvode(ctx, method == "adams", rtol, stop, max_order);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double energy = 0.5 * out.v * out.v + 0.5 * kOmega * kOmega * out.x * out.x;
  const double energy0 = 0.5 * kOmega * kOmega;
  // The phase of (x, v) = (cos wt, -w sin wt) is wt; here against w T = 2 pi N (a whole number of turns).
  const double phase = std::atan2(-out.v / kOmega, out.x);
  std::printf("method=%s rtol=%g steps=%ld fevals=%ld energy_error=%.3e phase_error=%.3e seconds=%.4f\n",
              method.c_str(), rtol, out.steps, out.fevals, std::fabs(energy / energy0 - 1),
              std::fabs(std::remainder(phase - kOmega * stop, 2 * M_PI)), seconds);
  SUNContext_Free(&ctx);
  return 0;
}

#pragma once
/// Owners for SUNDIALS objects (every object freed by exactly one owner), the one checker that
/// every SUNDIALS return flag goes through, naming the failing function (the IDA examples'
/// check_retval), and the guard that every residual and Jacobian callback runs its work in.

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <exception>
#include <memory>
#include <string>

namespace momenta {

/// Throws SolverError("<function> failed with flag <flag>") when flag < 0.
void CheckFlag(int flag, const char* function);
/// Throws SolverError when a SUNDIALS constructor returned null.
void CheckNotNull(const void* p, const char* function);

struct ContextDeleter {
  void operator()(SUNContext c) const { SUNContext_Free(&c); }
};
struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};

using ContextPtr = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter>;
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using MatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using LinearSolverPtr = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;

ContextPtr MakeContext();
VectorPtr MakeVector(sunindextype n, SUNContext ctx);

/// A dense or KLU linear solver with its matrix, for an n x n system with the given pattern size.
struct LinearSystem {
  MatrixPtr matrix;
  LinearSolverPtr solver;
  bool sparse = false;
};
LinearSystem MakeLinearSystem(N_Vector tmpl, sunindextype n, sunindextype nnz, bool sparse,
                              SUNContext ctx);

/// Runs `work` inside a SUNDIALS callback, where no C++ exception may cross into the C code: an
/// exception is stored in *error (the caller rethrows it after the solver returns) and -1 returned,
/// which stops the solver. Returns 0 when `work` finished.
template <class Work>
int GuardedCall(std::string* error, Work&& work) {
  try {
    work();
  } catch (const std::exception& e) {
    *error = e.what();
    return -1;
  }
  return 0;
}

/// 1 when `values` holds a value that is not finite: recoverable, so IDA retries with a smaller
/// step and KINSOL's line search backs off. Otherwise 0.
int RetryUnlessFinite(N_Vector values);

}  // namespace momenta

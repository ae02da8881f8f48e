#pragma once
/// Owners for SUNDIALS objects (every object freed by exactly one owner) and the one checker that
/// every SUNDIALS return flag goes through, naming the failing function (the IDA examples'
/// check_retval).

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

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

/// Whether this build links the optimised SUNDIALS (built from source with -O2).
bool SundialsOptimized();

}  // namespace momenta

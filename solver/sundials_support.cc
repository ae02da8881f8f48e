#include "solver/sundials_support.h"

#include <sundials/sundials_config.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <cmath>

#include "core/base/error.h"
#include "solver/simulator.h"

namespace momenta {

void CheckFlag(int flag, const char* function) {
  if (flag < 0) {
    throw SolverError(std::string(function) + " failed with flag " + std::to_string(flag));
  }
}

void CheckNotNull(const void* p, const char* function) {
  if (!p) throw SolverError(std::string(function) + " returned no object (out of memory?)");
}

ContextPtr MakeContext() {
  SUNContext ctx = nullptr;
  CheckFlag(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  return ContextPtr(ctx);
}

VectorPtr MakeVector(sunindextype n, SUNContext ctx) {
  N_Vector v = N_VNew_Serial(n, ctx);
  CheckNotNull(v, "N_VNew_Serial");
  N_VConst(0.0, v);
  return VectorPtr(v);
}

LinearSystem MakeLinearSystem(N_Vector tmpl, sunindextype n, sunindextype nnz, bool sparse,
                              SUNContext ctx) {
  LinearSystem ls;
  ls.sparse = sparse;
  if (sparse) {
    ls.matrix.reset(SUNSparseMatrix(n, n, nnz > 0 ? nnz : 1, CSC_MAT, ctx));
    CheckNotNull(ls.matrix.get(), "SUNSparseMatrix");
    ls.solver.reset(SUNLinSol_KLU(tmpl, ls.matrix.get(), ctx));
    CheckNotNull(ls.solver.get(), "SUNLinSol_KLU");
  } else {
    ls.matrix.reset(SUNDenseMatrix(n, n, ctx));
    CheckNotNull(ls.matrix.get(), "SUNDenseMatrix");
    ls.solver.reset(SUNLinSol_Dense(tmpl, ls.matrix.get(), ctx));
    CheckNotNull(ls.solver.get(), "SUNLinSol_Dense");
  }
  return ls;
}

int RetryUnlessFinite(N_Vector values) {
  const double* v = N_VGetArrayPointer(values);
  for (sunindextype k = 0, n = N_VGetLength(values); k < n; ++k) {
    if (!std::isfinite(v[k])) return 1;
  }
  return 0;
}

SolverBuild SolverBuildInfo() {
  SolverBuild build;
  build.sundials_version = SUNDIALS_VERSION;
#if defined(MOMENTA_SUNDIALS_OPTIMIZED) && MOMENTA_SUNDIALS_OPTIMIZED
  build.sundials_optimized = true;
#endif
  return build;
}

}  // namespace momenta

#include "solver/jacobian_fill.h"

#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace momenta {

void FillMatrix(const SparsePattern& pattern, const std::vector<double>& values, SUNMatrix J) {
  if (SUNMatGetID(J) == SUNMATRIX_SPARSE) {
    sunindextype* colptr = SUNSparseMatrix_IndexPointers(J);
    sunindextype* rowind = SUNSparseMatrix_IndexValues(J);
    double* data = SUNSparseMatrix_Data(J);
    for (int32_t c = 0; c <= pattern.cols; ++c) colptr[c] = pattern.col_start[c];
    for (size_t k = 0; k < pattern.nnz(); ++k) {
      rowind[k] = pattern.row_index[k];
      data[k] = values[k];
    }
    return;
  }
  SUNMatZero(J);
  for (int32_t c = 0; c < pattern.cols; ++c) {
    double* col = SUNDenseMatrix_Column(J, c);
    for (int32_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) {
      col[pattern.row_index[k]] = values[k];
    }
  }
}

}  // namespace momenta

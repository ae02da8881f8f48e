#pragma once
/// Copies a compressed-column Jacobian (values in pattern order) into a SUNDIALS matrix: the
/// pattern itself for a sparse (KLU) matrix, a scatter for a dense one.

#include <sundials/sundials_matrix.h>

#include <vector>

#include "core/compile/compiled_model.h"

namespace momenta {

void FillMatrix(const SparsePattern& pattern, const std::vector<double>& values, SUNMatrix J);

}  // namespace momenta

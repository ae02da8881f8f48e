#pragma once
/// Copies a compressed-column Jacobian (values in pattern order) into a SUNDIALS matrix: the
/// pattern itself for a sparse (KLU) matrix, a scatter for a dense one. FillJacobian is the whole
/// of a Jacobian callback, IDA's and KINSOL's alike.

#include <sundials/sundials_matrix.h>

#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "solver/sundials_support.h"

namespace momenta {

void FillMatrix(const SparsePattern& pattern, const std::vector<double>& values, SUNMatrix J);

/// `evaluate(values->data())` writes the Jacobian in `pattern` order, which then fills J; run as a
/// GuardedCall (an exception is stored in *error and -1 returned).
template <class Evaluate>
int FillJacobian(const SparsePattern& pattern, std::vector<double>* values, SUNMatrix J,
                 std::string* error, Evaluate&& evaluate) {
  return GuardedCall(error, [&] {
    values->resize(pattern.nnz());
    evaluate(values->data());
    FillMatrix(pattern, *values, J);
  });
}

}  // namespace momenta

#pragma once
/// The model linearised where it stands: the state-space form
///     dx/dt = A dx + B du,    dy = C dx + D du
/// of the DAE F(t, y, y', u) = 0 about a consistent point (t, y, y', u), over the states the build
/// chose (after index reduction), the inputs the build held (BuildOptions::hold_free_inputs) and
/// chosen output columns. What `momenta linearize` writes and the Python module's
/// Model.linearize returns.

#include <complex>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/build.h"
#include "core/compile/model_state.h"

namespace momenta {

/// A dense matrix, row by row.
struct DenseMatrix {
  size_t rows = 0, cols = 0;
  std::vector<double> values;  ///< rows * cols, row by row

  DenseMatrix() = default;
  DenseMatrix(size_t num_rows, size_t num_cols) : rows(num_rows), cols(num_cols), values(num_rows * num_cols, 0.0) {}
  double& operator()(size_t r, size_t c) { return values[r * cols + c]; }
  double operator()(size_t r, size_t c) const { return values[r * cols + c]; }
};

struct Linearization {
  double t = 0;
  std::vector<std::string> states, inputs, outputs;
  std::vector<double> x, u, y;  ///< the operating point: the states', inputs' and outputs' values
  DenseMatrix A, B, C, D;       ///< n x n, n x m, p x n, p x m
  /// A's eigenvalues, by increasing real part, then imaginary part.
  std::vector<std::complex<double>> eigenvalues;
};

/// What to linearise, by name.
struct LinearizationSpec {
  /// Free signal inputs (FlatSystem::free_inputs) with their operating values; empty: every free
  /// input, at 0.
  std::vector<std::pair<std::string, double>> inputs;
  /// Variables of the model; empty: the model's outputs (its states when it lists none).
  std::vector<std::string> outputs;
};

/// Sets `options` up to build a model for `spec`: its free inputs held (hold_free_inputs, with
/// spec's values), and the outputs and the inputs added as outputs (add_outputs). The build then
/// throws UsageError for an input that is not a free input, or an output that names no variable
/// of the model (listing the valid names).
void PrepareLinearizationBuild(const LinearizationSpec& spec, BuildOptions* options);

/// Which of the model's output columns (CompiledModel::output_names) are the linearisation's
/// outputs, and which are its inputs: each input the build held as a state of its own
/// (BuildOptions::hold_free_inputs) is also an output column, which tells which state it is.
struct LinearizationColumns {
  std::vector<size_t> outputs, inputs;
  /// Every input the build held, chosen or not: those not in `inputs` stay at their operating
  /// values and are no states of the linearisation either.
  std::vector<size_t> held;
};

/// The output columns of `model`, built by PrepareLinearizationBuild(spec) with `report`, that are
/// the linearisation's outputs and inputs.
LinearizationColumns ResolveLinearizationColumns(const CompiledModel& model, const BuildReport& report,
                                                 const LinearizationSpec& spec);

/// The state-space form at (t, y, y'), consistent values of the model `state` was built as.
///
/// A and B are exact up to rounding: the implicit function theorem on F with the states x and
/// the inputs given, through one sparse LU of the matrix [dF/dx' | dF/dz] (z: the algebraic
/// unknowns) that IDA's own initial-condition step uses. C and D are central differences of the
/// output programs along the directions (dx, dz, dx') that A's columns give (outputs are
/// expressions of y and y', which the compiled model has no Jacobian of): exact for outputs
/// linear in the unknowns, else to about 1e-10 relative.
///
/// Throws SolverError ("at t = …: …") when [dF/dx' | dF/dz] is singular there, and ModelError
/// naming the input when the build did not keep an input as a state of its own (index reduction
/// made it depend on others: a prescribed position whose derivative the model needs).
Linearization Linearize(const ModelState& state, double t, const std::vector<double>& y,
                        const std::vector<double>& yp, const LinearizationColumns& columns);

}  // namespace momenta

// The state-space form of the model where it stands (see linearization.h).
//
// The maths. After index reduction momenta's DAE is of index 1, F(t, y, y') = 0 with
// y = [x states; z algebraic] and F independent of z'. An input u that the build held is a state
// of its own with der(u) = 0 (BuildOptions::hold_free_inputs), so x = [x_model; u] here. About a
// consistent point,
//     F_x dx + F_x' dx' + F_z dz = 0,
// and with M = [F_x' | F_z] (mixed_jacobian.h; regular for an index-1 system)
//     [dx'; dz] = -M^-1 F_x dx.
// Column j of that solve is what a unit change of state j does to every rate and algebraic
// unknown: its x_model' rows are column j of A (j a model state) or of B (j an input). The row
// der(u) = 0 gives u' = 0 for every column, so the inputs add no dynamics of their own. This is
// the implicit-function elimination the stiffness report uses for the modes (stiffness_report.cc),
// exact up to rounding, and not finite differences of a consistent-initialisation solve: those
// would need a Newton solve per column and carry its tolerance into A.
//
// The outputs are compiled expressions of (t, y, y'), with no Jacobian program: their change along
// column j's direction (dy = e_j + dz, dy' = dx') is a central difference
//     dY = (Y(y + h dy, y' + h dy') - Y(y - h dy, y' - h dy')) / 2h,
// exact for an output linear in the unknowns, with an error of order h^2 Y''' + eps Y / h
// otherwise (h = 1e-5 relative to the state: about 1e-10). An input's own output column has the
// row e_j: it tells which state stands for the input.

#include "solver/linearization.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/mixed_jacobian.h"

namespace momenta {

namespace {

/// Relative step of the outputs' central differences.
constexpr double kOutputStep = 1e-5;

/// An input's output row must single out one state: its other entries stay below this fraction
/// of the largest.
constexpr double kInputRowTolerance = 1e-8;

/// What a unit change of each state does: per state column j, the rates and algebraic unknowns'
/// change ([dx'; dz] by y index) from -M^-1 F_x e_j.
std::vector<Eigen::VectorXd> StateColumns(ModelState* state, double t, const std::vector<double>& y,
                                          const std::vector<double>& yp) {
  const CompiledModel& model = state->model();
  if (model.num_states() == 0) return {};  // nothing moves: A, B and C are empty
  MixedJacobian jacobian(state, t, y.data(), yp.data());
  if (!jacobian.Factor()) {
    throw SolverError("at t = " + NumberText(t) + ": the system cannot be linearised there: the matrix of its "
                      "rates and algebraic unknowns, [dF/dx' | dF/dz], is singular (a constraint that loses rank)");
  }
  const SparsePattern& pattern = model.jacobian_pattern;
  const auto n = static_cast<Eigen::Index>(model.num_unknowns());
  std::vector<Eigen::VectorXd> columns;
  Eigen::VectorXd rhs(n);
  for (uint32_t x : model.state_y) {
    rhs.setZero();
    for (int32_t k = pattern.col_start[x]; k < pattern.col_start[x + 1]; ++k) {
      rhs[pattern.row_index[k]] = -jacobian.dfdy()[k];
    }
    columns.push_back(jacobian.Solve(rhs));
    if (!columns.back().allFinite()) {
      throw SolverError("at t = " + NumberText(t) + ": the linearisation in the state " +
                        model.flat->VariableName(model.unknowns[x]) + " is not finite");
    }
  }
  return columns;
}

/// Per state column j, every output's change along column j's direction (a central difference).
DenseMatrix OutputColumns(ModelState* state, double t, const std::vector<double>& y, const std::vector<double>& yp,
                          const std::vector<Eigen::VectorXd>& columns) {
  const CompiledModel& model = state->model();
  const size_t n = model.num_unknowns(), num_out = model.output_names.size();
  DenseMatrix out(num_out, columns.size());
  std::vector<double> y_plus(n), y_minus(n), yp_plus(n), yp_minus(n), o_plus(num_out), o_minus(num_out);
  for (size_t j = 0; j < columns.size(); ++j) {
    const uint32_t xj = model.state_y[j];
    const double h = kOutputStep * std::max(1.0, std::fabs(y[xj]));
    for (size_t i = 0; i < n; ++i) {
      // dy: e_j and the algebraic unknowns' change; dy': the states' rates' change.
      const double dy = i == xj ? 1.0 : (model.is_state[i] ? 0.0 : columns[j][static_cast<Eigen::Index>(i)]);
      const double dyp = model.is_state[i] ? columns[j][static_cast<Eigen::Index>(i)] : 0.0;
      y_plus[i] = y[i] + h * dy;
      y_minus[i] = y[i] - h * dy;
      yp_plus[i] = yp[i] + h * dyp;
      yp_minus[i] = yp[i] - h * dyp;
    }
    state->Outputs(t, y_plus.data(), yp_plus.data(), o_plus.data());
    state->Outputs(t, y_minus.data(), yp_minus.data(), o_minus.data());
    for (size_t r = 0; r < num_out; ++r) out(r, j) = (o_plus[r] - o_minus[r]) / (2 * h);
  }
  return out;
}

/// The state column that input column `k` stands for (its output row is s e_j) and s; throws
/// ModelError when the row does not single out one state.
std::pair<size_t, double> InputState(const CompiledModel& model, const DenseMatrix& outputs, size_t k) {
  size_t best = 0;
  for (size_t j = 1; j < outputs.cols; ++j) {
    if (std::fabs(outputs(k, j)) > std::fabs(outputs(k, best))) best = j;
  }
  const double s = outputs.cols > 0 ? outputs(k, best) : 0.0;
  bool single = std::fabs(s) > 0.5;
  for (size_t j = 0; j < outputs.cols && single; ++j) {
    single = j == best || std::fabs(outputs(k, j)) <= kInputRowTolerance * std::fabs(s);
  }
  if (!single) {
    throw ModelError("the input " + model.output_names[k] + " is not a state of its own after index reduction "
                     "(the model needs its derivative, as of a prescribed position), so it cannot be an input "
                     "of the linearisation");
  }
  return {best, s};
}

/// The eigenvalues of `a`, by increasing real part, then imaginary part.
std::vector<std::complex<double>> Eigenvalues(const DenseMatrix& a) {
  if (a.rows == 0) return {};
  const auto n = static_cast<Eigen::Index>(a.rows);
  const Eigen::MatrixXd matrix =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(a.values.data(), n, n);
  Eigen::EigenSolver<Eigen::MatrixXd> solver(matrix, /*computeEigenvectors=*/false);
  if (solver.info() != Eigen::Success) return {};
  std::vector<std::complex<double>> values(solver.eigenvalues().begin(), solver.eigenvalues().end());
  std::sort(values.begin(), values.end(), [](auto x, auto y) {
    return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
  });
  return values;
}

}  // namespace

Linearization Linearize(const ModelState& state, double t, const std::vector<double>& y,
                        const std::vector<double>& yp, const LinearizationColumns& columns) {
  ModelState work = state;
  const CompiledModel& model = state.model();
  const std::vector<Eigen::VectorXd> moved = StateColumns(&work, t, y, yp);
  const DenseMatrix outputs = OutputColumns(&work, t, y, yp, moved);
  std::vector<double> values(model.output_names.size());
  work.Outputs(t, y.data(), yp.data(), values.data());

  // Which state each input is; the model's states are the others.
  Linearization lin;
  lin.t = t;
  std::vector<std::pair<size_t, double>> inputs;
  std::vector<bool> is_input(model.num_states(), false);
  for (size_t k : columns.held) is_input[InputState(model, outputs, k).first] = true;
  for (size_t k : columns.inputs) {
    inputs.push_back(InputState(model, outputs, k));
    is_input[inputs.back().first] = true;
    lin.inputs.push_back(model.output_names[k]);
    lin.u.push_back(values[k]);
  }
  std::vector<size_t> states;
  for (size_t j = 0; j < model.num_states(); ++j) {
    if (is_input[j]) continue;
    states.push_back(j);
    lin.states.push_back(model.flat->VariableName(model.unknowns[model.state_y[j]]));
    lin.x.push_back(y[model.state_y[j]]);
  }
  for (size_t k : columns.outputs) {
    lin.outputs.push_back(model.output_names[k]);
    lin.y.push_back(values[k]);
  }

  // A and B from the states' rates; C and D from the outputs.
  const size_t n = states.size(), m = inputs.size(), p = columns.outputs.size();
  lin.A = DenseMatrix(n, n);
  lin.B = DenseMatrix(n, m);
  lin.C = DenseMatrix(p, n);
  lin.D = DenseMatrix(p, m);
  for (size_t r = 0; r < n; ++r) {
    const auto rate = static_cast<Eigen::Index>(model.state_y[states[r]]);
    for (size_t c = 0; c < n; ++c) lin.A(r, c) = moved[states[c]][rate];
    for (size_t c = 0; c < m; ++c) lin.B(r, c) = moved[inputs[c].first][rate] / inputs[c].second;
  }
  for (size_t r = 0; r < p; ++r) {
    for (size_t c = 0; c < n; ++c) lin.C(r, c) = outputs(columns.outputs[r], states[c]);
    for (size_t c = 0; c < m; ++c) lin.D(r, c) = outputs(columns.outputs[r], inputs[c].first) / inputs[c].second;
  }
  lin.eigenvalues = Eigenvalues(lin.A);
  return lin;
}

}  // namespace momenta

#include "core/compile/model_state.h"
#include "core/flatten/flatten.h"

#include <cmath>
#include <algorithm>
#include <cstring>
#include <sstream>

namespace momenta {

namespace {
/// memcpy of n doubles; n = 0 with a null pointer (an empty vector) is allowed.
void CopyDoubles(double* dst, const double* src, size_t n) {
  if (n > 0) std::memcpy(dst, src, n * sizeof(double));
}
}  // namespace

ModelState::ModelState(std::shared_ptr<const CompiledModel> model) : model_(std::move(model)) {
  regs_.assign(model_->layout.size, 0.0);
  for (const auto& [reg, value] : model_->constants) regs_[reg] = value;
  if (model_->native) {
    for (size_t k = 0; k < kNumModelPrograms; ++k) native_[k] = model_->native->function(static_cast<ModelProgram>(k));
  }
}

void ModelState::SetParameters(const ParameterOverrides& overrides) {
  const CompiledModel& m = *model_;
  params_ = EvaluateParameters(*m.flat, overrides);
  if (!params_.empty()) {
    CopyDoubles(regs_.data() + m.layout.param_base, params_.data(), params_.size());
  }
  Run(ModelProgram::kParameters, nullptr);
  // Divisors of eliminated variables' formulas must not vanish.
  if (!m.guards.empty()) {
    std::vector<double> values(m.guards.size());
    Run(ModelProgram::kGuardValues, values.data());
    for (size_t k = 0; k < values.size(); ++k) {
      if (values[k] == 0.0 || !std::isfinite(values[k])) {
        const DivisorGuard& g = m.guards[k];
        std::ostringstream msg;
        msg << m.flat->file << ": with these parameter values, " << m.guard_text(k) << " = "
            << values[k] << ", so the equation "
            << m.flat->DescribeEquation(m.flat->equations[g.equation])
            << " cannot be solved for " << m.flat->VariableName(g.variable)
            << "; give the parameters nonzero values";
        throw ModelError(msg.str());
      }
    }
  }
}

void ModelState::RunAt(ModelProgram which, double t, const double* y, const double* yp, double* out) {
  Load(t, y, yp);
  Run(which, out);
}

void ModelState::Load(double t, const double* y, const double* yp) {
  const RegisterLayout& L = model_->layout;
  regs_[RegisterLayout::kTime] = t;
  const size_t n = L.num_unknowns;
  if (y) CopyDoubles(regs_.data() + L.y_base, y, n);
  if (yp) CopyDoubles(regs_.data() + L.yp_base, yp, n);
}

void ModelState::RunInPlace(ModelProgram which, double t, const double* y, const double* yp, double* out) {
  NativeCode::Function f = native_[static_cast<size_t>(which)];
  if (!f || !y || !yp) {
    RunAt(which, t, y, yp, out);
    return;
  }
  regs_[RegisterLayout::kTime] = t;
  f(regs_.data(), y, yp, out);
}

void ModelState::Residual(double t, const double* y, const double* yp, double* out) {
  RunInPlace(ModelProgram::kResidual, t, y, yp, out);
}

void ModelState::Jacobian(double t, double cj, const double* y, const double* yp, double* values) {
  regs_[RegisterLayout::kCj] = cj;
  RunInPlace(ModelProgram::kJacobian, t, y, yp, values);
}

void ModelState::Outputs(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kOutputs, t, y, yp, out);
}

void ModelState::StartDiscrete() {
  const CompiledModel& m = *model_;
  const size_t nd = m.discrete_vars.size();
  if (nd == 0) return;
  std::vector<double> values(nd);
  Run(ModelProgram::kDiscreteStarts, values.data());
  std::copy(values.begin(), values.end(), mutable_discrete());
  std::copy(values.begin(), values.end(), regs_.begin() + m.layout.pre_base + m.layout.num_unknowns);
}

void ModelState::SavePre(const double* y) {
  const RegisterLayout& L = model_->layout;
  CopyDoubles(regs_.data() + L.pre_base, y, L.num_unknowns);
  CopyDoubles(regs_.data() + L.pre_base + L.num_unknowns, regs_.data() + L.disc_base, L.num_discrete);
}

void ModelState::ZeroCrossings(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kZeroCrossings, t, y, yp, out);
}

void ModelState::ZeroCrossingRates(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kZeroCrossingRates, t, y, yp, out);
}

void ModelState::UpdateDiscrete(double t, const double* y, const double* yp) {
  Load(t, y, yp);
  Run(ModelProgram::kDiscreteUpdate, nullptr);
}

void ModelState::WhenConditions(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kWhenConditions, t, y, yp, out);
}

void ModelState::WhenValues(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kWhenValues, t, y, yp, out);
}

void ModelState::ImpactValues(double t, const double* y, const double* yp, double* out) {
  RunAt(ModelProgram::kImpactValues, t, y, yp, out);
}

void ModelState::JacobianParts(double t, const double* y, const double* yp, double* dfdy,
                               double* dfdyp) {
  const size_t nnz = model_->jacobian_pattern.nnz();
  Jacobian(t, 0.0, y, yp, dfdy);
  Jacobian(t, 1.0, y, yp, dfdyp);
  for (size_t k = 0; k < nnz; ++k) dfdyp[k] -= dfdy[k];
}

void ModelState::StartValues(double* y) { Run(ModelProgram::kStartValues, y); }
void ModelState::StartGuesses(double* y) { Run(ModelProgram::kStartGuesses, y); }

void ModelState::LoadZ(double t, const double* z) {
  const RegisterLayout& L = model_->layout;
  regs_[RegisterLayout::kTime] = t;
  regs_[RegisterLayout::kInitial] = 1.0;
  const size_t n = L.num_unknowns;
  CopyDoubles(regs_.data() + L.y_base, z, n);
  std::fill(regs_.begin() + L.yp_base, regs_.begin() + L.yp_base + n, 0.0);
  for (size_t s = 0; s < model_->state_y.size(); ++s) regs_[L.yp_base + model_->state_y[s]] = z[n + s];
}

void ModelState::InitResidual(double t, const double* z, double* out) {
  LoadZ(t, z);
  Run(ModelProgram::kInitResidual, out);
  regs_[RegisterLayout::kInitial] = 0.0;
}

void ModelState::InitJacobian(double t, const double* z, double* values) {
  LoadZ(t, z);
  Run(ModelProgram::kInitJacobian, values);
  regs_[RegisterLayout::kInitial] = 0.0;
}

void ModelState::RedundantResidual(double t, const double* z, double* out) {
  LoadZ(t, z);
  Run(ModelProgram::kRedundantResidual, out);
  regs_[RegisterLayout::kInitial] = 0.0;
}

}  // namespace momenta

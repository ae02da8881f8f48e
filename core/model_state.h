#pragma once
/// The values of one run of a CompiledModel: parameters, time, y, y' (the model itself stays
/// const, so a parameter sweep never rebuilds it — MuJoCo's mjModel/mjData split).

#include <memory>
#include <vector>

#include "core/compiled_model.h"
#include "core/flat_system.h"

namespace momenta {

class ModelState {
 public:
  explicit ModelState(std::shared_ptr<const CompiledModel> model);

  /// Evaluates every parameter (with overrides), checks ranges and divisors, and runs the
  /// parameter program. Throws ModelError naming the parameter.
  void SetParameters(const ParameterOverrides& overrides);
  const std::vector<double>& parameter_values() const { return params_; }

  void Residual(double t, const double* y, const double* yp, double* out);
  void Jacobian(double t, double cj, const double* y, const double* yp, double* values);
  void Outputs(double t, const double* y, const double* yp, double* out);
  void StartValues(double* y);
  /// z = [y; y' of states]
  void InitResidual(double t, const double* z, double* out);
  void InitJacobian(double t, const double* z, double* values);

  const CompiledModel& model() const { return *model_; }

 private:
  void Load(double t, const double* y, const double* yp);
  void LoadZ(double t, const double* z);

  std::shared_ptr<const CompiledModel> model_;
  std::vector<double> regs_;
  std::vector<double> params_;
};

}  // namespace momenta

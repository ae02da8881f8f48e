#pragma once
/// The values of one run of a CompiledModel: parameters, time, y, y' (the model itself stays
/// const, so a parameter sweep never rebuilds it — MuJoCo's mjModel/mjData split).

#include <memory>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/flatten/flat_system.h"
#include "core/compile/native_code.h"

namespace momenta {

class ModelState {
 public:
  explicit ModelState(std::shared_ptr<const CompiledModel> model);

  /// Evaluates every parameter (with overrides), checks ranges and divisors, and runs the
  /// parameter program. Throws ModelError naming the parameter.
  void SetParameters(const ParameterOverrides& overrides);
  const std::vector<double>& parameter_values() const { return params_; }

  /// With native code the residual and the Jacobian read y and y' in place and leave the
  /// registers' copies of them as an earlier call loaded them: a later call given null y or y'
  /// (ZeroCrossings for conditions of time alone) sees those.
  void Residual(double t, const double* y, const double* yp, double* out);
  void Jacobian(double t, double cj, const double* y, const double* yp, double* values);
  void Outputs(double t, const double* y, const double* yp, double* out);
  void StartValues(double* y);
  void StartGuesses(double* y);
  /// z = [y; y' of states]
  void InitResidual(double t, const double* z, double* out);
  void InitJacobian(double t, const double* z, double* values);
  /// The residuals of the initial conditions left out as redundant, at z = [y; y' of the states].
  void RedundantResidual(double t, const double* z, double* out);

  const CompiledModel& model() const { return *model_; }

  // Events. Conditions and discrete values live in registers; these read and set them.
  size_t num_conditions() const { return model_->conditions.size(); }
  size_t num_discrete() const { return model_->discrete_vars.size(); }
  const double* conditions() const { return regs_.data() + model_->layout.cond_base; }
  double* mutable_conditions() { return regs_.data() + model_->layout.cond_base; }
  const double* discrete() const { return regs_.data() + model_->layout.disc_base; }
  double* mutable_discrete() { return regs_.data() + model_->layout.disc_base; }
  /// What the equations read besides time, y and y' and an event may change: the discrete values,
  /// the pre-values and the conditions, one block of num_event_values() (RegisterLayout).
  const double* event_values() const { return regs_.data() + model_->layout.disc_base; }
  double* mutable_event_values() { return regs_.data() + model_->layout.disc_base; }
  size_t num_event_values() const {
    return model_->layout.cond_base + model_->layout.num_conditions - model_->layout.disc_base;
  }
  /// Discrete values before the first event (and their pre-values).
  void StartDiscrete();
  /// Sets initial() for the programs run next (the initialisation programs set it themselves).
  void set_initial(bool on) { regs_[RegisterLayout::kInitial] = on ? 1.0 : 0.0; }
  /// pre := current values of y and of the discrete variables.
  void SavePre(const double* y);
  void ZeroCrossings(double t, const double* y, const double* yp, double* out);
  void ZeroCrossingRates(double t, const double* y, const double* yp, double* out);
  /// Evaluates the discrete equations in order (with the current conditions and pre-values).
  void UpdateDiscrete(double t, const double* y, const double* yp);
  void WhenConditions(double t, const double* y, const double* yp, double* out);
  void WhenValues(double t, const double* y, const double* yp, double* out);
  /// Per impact: gap, velocity, restitution, v_small, release (5 values each).
  void ImpactValues(double t, const double* y, const double* yp, double* out);
  /// dF/dy (cj = 0) and dF/dy' (the cj = 1 values minus those) in the Jacobian's pattern.
  void JacobianParts(double t, const double* y, const double* yp, double* dfdy, double* dfdyp);

 private:
  void Load(double t, const double* y, const double* yp);
  /// Runs a program on the registers into `out`: its native function when the model has native
  /// code, else the interpreter.
  void Run(ModelProgram which, double* out) {
    if (NativeCode::Function f = native_[static_cast<size_t>(which)]) {
      const RegisterLayout& L = model_->layout;
      f(regs_.data(), regs_.data() + L.y_base, regs_.data() + L.yp_base, out);
    } else {
      ProgramOf(*model_, which).Run(regs_.data(), out);
    }
  }
  /// Loads (t, y, y') and runs `which` into `out`.
  void RunAt(ModelProgram which, double t, const double* y, const double* yp, double* out);
  /// RunAt for the solver's hot calls (residual, Jacobian): native code reads y and y' where they
  /// are, without the copy into the registers (at the 10 000-mass chain the copy was a quarter of
  /// the residual's time), so their registers keep what an earlier call loaded.
  void RunInPlace(ModelProgram which, double t, const double* y, const double* yp, double* out);
  void LoadZ(double t, const double* z);

  std::shared_ptr<const CompiledModel> model_;
  std::vector<double> regs_;
  std::vector<double> params_;
  std::array<NativeCode::Function, kNumModelPrograms> native_{};  ///< null: interpreted
};

}  // namespace momenta

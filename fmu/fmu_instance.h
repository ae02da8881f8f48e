#pragma once
/// One instance of an exported model (fmi2Instantiate's component): the model built from the
/// FMU's resources, its parameters as the importer sets them, and the run for either kind.
///
/// Model Exchange: the importer integrates the states. GetDerivatives solves F(t, y, y') = 0 for
/// the states' rates and the algebraic unknowns with the states given (Newton on the matrix
/// [dF/dx' | dF/dz] of solver/mixed_jacobian.h); an event (fmi2NewDiscreteStates) is the
/// solver's own DoEvent on those values (impacts change the states there), and nextEventTime is
/// the solver's next time event. Co-Simulation: DoStep carries momenta's integration (IDA, exact
/// event location and impacts) on from the last step's end to this one's (solver/simulator.h's
/// Simulation), so a step over an impact ends on the exact post-impact values.
///
/// Errors are thrown as std::exception; fmi2_functions.cc turns them into the logger's message
/// and fmi2Error.

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/compile/model_state.h"
#include "fmu/fmu_layout.h"
#include "solver/integration_state.h"
#include "solver/simulation_options.h"
#include "solver/simulator.h"

namespace momenta::fmu {

class FmuInstance {
 public:
  /// Builds the model of the FMU whose resources folder is `resources` (a path); throws
  /// std::runtime_error when the GUID does not match `guid`.
  FmuInstance(const std::string& resources, const std::string& guid, bool co_simulation);
  ~FmuInstance();

  const FmuLayout& layout() const { return layout_; }
  bool co_simulation() const { return co_simulation_; }

  void SetupExperiment(bool tolerance_defined, double tolerance, double start, bool stop_defined,
                       double stop);
  void SetReal(uint32_t vr, double value);
  double GetReal(uint32_t vr);
  void EnterInitialization() { initializing_ = true; }
  void ExitInitialization();
  void Reset();

  // Model Exchange.
  void SetTime(double t);
  void SetContinuousStates(const double* x, size_t n);
  void GetContinuousStates(double* x, size_t n) const;
  void GetDerivatives(double* dx, size_t n);
  void GetEventIndicators(double* z, size_t n);
  void GetNominals(double* nominal, size_t n) const;
  /// The event at the current time; returns whether the states changed. `next_event` gets the
  /// next time event (+inf when none).
  bool EventUpdate(double* next_event);

  // Co-Simulation.
  void DoStep(double t, double h);
  double time() const { return t_; }

 private:
  void CheckParameterValue(const FmuVariable& v, double value) const;
  /// y, y' consistent with the states at t_ (a no-op when nothing changed since).
  void Solve();
  void StartModelExchange();
  /// The unknowns and their rates where the instance stands (Model Exchange: the run's).
  const std::vector<double>& y() const;
  const std::vector<double>& yp() const;

  std::string resources_, model_file_;
  std::shared_ptr<const CompiledModel> model_;
  std::unique_ptr<ModelState> state_;
  ParameterOverrides built_with_;
  ParameterOverrides initial_parameters_;  ///< as at the initialisation
  /// Co-Simulation: parameters set during the run, with the time each was set at (a run made
  /// again replays them), and whether the last is not yet in the run.
  std::vector<std::pair<double, ParameterOverrides>> changes_;
  bool parameters_changed_ = false;
  std::vector<double> parameters_;  ///< by parameter index, as set
  FmuLayout layout_;
  bool co_simulation_ = false, initializing_ = false, initialized_ = false;
  SimulationOptions options_;
  double t_ = 0;
  std::vector<double> y_, yp_, outputs_;
  bool solved_ = false, first_event_ = true;
  double next_time_event_ = HUGE_VAL;  ///< Model Exchange: as the last event update gave it
  // Model Exchange: the solver's run record, with IDA started for the restarts of events.
  RowCallback row_;
  SolverStats stats_;
  std::unique_ptr<IntegrationState> run_;
  // Co-Simulation: the run that each step carries on (over state_, so declared after it).
  std::unique_ptr<Simulation> simulation_;
};

}  // namespace momenta::fmu

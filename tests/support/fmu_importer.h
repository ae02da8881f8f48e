#pragma once
/// An FMI 2.0 importer for the tests: it unpacks an FMU (with `unzip`), reads the few things it
/// needs from modelDescription.xml, loads the binary with dlopen and looks the functions up by
/// their standard names, and runs the model in either kind:
///   Co-Simulation   fmi2DoStep at a fixed communication step;
///   Model Exchange  the standard's pseudo-code (FMI 2.0, section 3.2.4): classical Runge-Kutta
///                   (RK4) at a fixed step, a state event located by bisection of the step on the
///                   event indicators' signs, time events from nextEventTime, and the event
///                   iteration with fmi2NewDiscreteStates; the states are read back when an event
///                   changed them.

#include <map>
#include <string>
#include <vector>

#include "fmu/fmi2.h"

namespace momenta::testing {

struct FmuRunResult {
  bool ok = false;
  std::string log;                      ///< what the FMU logged, and where the run stopped
  std::map<std::string, double> final;  ///< the asked-for variables at the stop time
  long events = 0;                      ///< Model Exchange: the events handled
};

class FmuImporter {
 public:
  /// Unpacks `fmu` into `dir` and loads its binary; `error()` says what failed.
  FmuImporter(const std::string& fmu, const std::string& dir);
  ~FmuImporter();

  const std::string& error() const { return error_; }
  const std::string& guid() const { return guid_; }
  size_t num_states() const { return num_states_; }
  size_t num_indicators() const { return num_indicators_; }
  /// The value reference of `name`; UINT32_MAX when there is none.
  unsigned ValueReference(const std::string& name) const;

  FmuRunResult RunCoSimulation(const std::map<std::string, double>& params, double stop,
                               double step, const std::vector<std::string>& names);
  FmuRunResult RunModelExchange(const std::map<std::string, double>& params, double stop,
                                double step, const std::vector<std::string>& names);

  /// Instantiates with `guid` (a wrong one for the tests of the check); returns the instance or
  /// null.
  fmi2Component Instantiate(fmi2Type type, const std::string& guid);
  void Free(fmi2Component c);
  /// The functions, looked up by name.
  template <typename F>
  F Function(const char* name) const;

 private:
  void* Symbol(const char* name) const;
  bool Start(fmi2Component c, const std::map<std::string, double>& params, double stop,
             std::string* log);
  /// Reads `names` into r->final (r->ok when the run and every read succeeded), frees `c` and puts
  /// the FMU's log before the run's own.
  void Finish(fmi2Component c, const std::vector<std::string>& names, bool ok, FmuRunResult* r);

  std::string dir_, error_, guid_, id_, resources_uri_;
  size_t num_states_ = 0, num_indicators_ = 0;
  std::map<std::string, unsigned> refs_;
  void* handle_ = nullptr;
};

template <typename F>
F FmuImporter::Function(const char* name) const {
  return reinterpret_cast<F>(Symbol(name));
}

/// What the FMU logged since the last call (the logger collects it for all instances).
std::string TakeFmuLog();

}  // namespace momenta::testing

// The FMI 2.0 functions the FMU exports (fmi2.h), over FmuInstance. Every exception becomes the
// logger's message and fmi2Error: nothing is thrown across the C interface.

#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <string>

#include "fmu/fmi2.h"
#include "fmu/fmu_instance.h"
#include "fmu/fmu_resources.h"

namespace {

using momenta::fmu::FmuInstance;

/// A component: the instance (null until built) and how to reach the importer.
struct Component {
  std::string name;
  fmi2CallbackLogger logger = nullptr;
  fmi2ComponentEnvironment environment = nullptr;
  std::unique_ptr<FmuInstance> instance;
};

void Log(const fmi2CallbackFunctions* functions, const std::string& name, fmi2Status status,
         const std::string& text) {
  if (functions && functions->logger) {
    functions->logger(functions->componentEnvironment, name.c_str(), status, "momenta", "%s",
                      text.c_str());
  }
}

void Log(Component* c, fmi2Status status, const std::string& text) {
  if (c->logger) c->logger(c->environment, c->name.c_str(), status, "momenta", "%s", text.c_str());
}

/// Runs `body` on the component's instance; an exception is logged and gives fmi2Error.
template <typename Body>
fmi2Status Guard(fmi2Component component, const char* function, Body body) {
  auto* c = static_cast<Component*>(component);
  if (c == nullptr || !c->instance) return fmi2Error;
  try {
    body(*c->instance);
    return fmi2OK;
  } catch (const std::exception& e) {
    Log(c, fmi2Error, std::string(function) + ": " + e.what());
    return fmi2Error;
  }
}

fmi2Status Unsupported(fmi2Component component, const char* function) {
  if (component)
    Log(static_cast<Component*>(component), fmi2Error, std::string(function) + " is not supported");
  return fmi2Error;
}

}  // namespace

extern "C" {

const char* fmi2GetTypesPlatform(void) { return "default"; }
const char* fmi2GetVersion(void) { return "2.0"; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean, size_t, const fmi2String[]) {
  return c ? fmi2OK : fmi2Error;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions* functions, fmi2Boolean, fmi2Boolean) {
  const std::string name = instanceName ? instanceName : "";
  try {
    auto c = std::make_unique<Component>();
    c->name = name;
    if (functions) {
      c->logger = functions->logger;
      c->environment = functions->componentEnvironment;
    }
    const std::string resources =
        momenta::fmu::PathOfUri(fmuResourceLocation ? fmuResourceLocation : "");
    c->instance = std::make_unique<FmuInstance>(resources, fmuGUID ? fmuGUID : "",
                                                fmuType == fmi2CoSimulation);
    return c.release();
  } catch (const std::exception& e) {
    Log(functions, name, fmi2Error, std::string("fmi2Instantiate: ") + e.what());
    return nullptr;
  }
}

void fmi2FreeInstance(fmi2Component c) { delete static_cast<Component*>(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  return Guard(c, "fmi2SetupExperiment", [&](FmuInstance& m) {
    m.SetupExperiment(toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime);
  });
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return Guard(c, "fmi2EnterInitializationMode", [](FmuInstance& m) { m.EnterInitialization(); });
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return Guard(c, "fmi2ExitInitializationMode", [](FmuInstance& m) { m.ExitInitialization(); });
}
fmi2Status fmi2Terminate(fmi2Component c) {
  return Guard(c, "fmi2Terminate", [](FmuInstance&) {});
}
fmi2Status fmi2Reset(fmi2Component c) {
  return Guard(c, "fmi2Reset", [](FmuInstance& m) { m.Reset(); });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
  return Guard(c, "fmi2GetReal", [&](FmuInstance& m) {
    for (size_t k = 0; k < nvr; ++k) value[k] = m.GetReal(vr[k]);
  });
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
  return Guard(c, "fmi2SetReal", [&](FmuInstance& m) {
    for (size_t k = 0; k < nvr; ++k) m.SetReal(vr[k], value[k]);
  });
}
// The model has Real variables only.
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Integer[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2GetInteger (the FMU has no Integer variables)");
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2GetBoolean (the FMU has no Boolean variables)");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2String[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2GetString (the FMU has no String variables)");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference[], size_t nvr,
                          const fmi2Integer[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2SetInteger (the FMU has no Integer variables)");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr,
                          const fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2SetBoolean (the FMU has no Boolean variables)");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference[], size_t nvr,
                         const fmi2String[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2SetString (the FMU has no String variables)");
}

// State saving and directional derivatives are not offered (the capability flags say so).
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) {
  return Unsupported(c, "fmi2GetFMUstate");
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) {
  return Unsupported(c, "fmi2SetFMUstate");
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) {
  return Unsupported(c, "fmi2FreeFMUstate");
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) {
  return Unsupported(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[], size_t) {
  return Unsupported(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t, fmi2FMUstate*) {
  return Unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference[], size_t,
                                        const fmi2ValueReference[], size_t, const fmi2Real[],
                                        fmi2Real[]) {
  return Unsupported(c, "fmi2GetDirectionalDerivative");
}

// ---- Model Exchange ------------------------------------------------------------------------

fmi2Status fmi2EnterEventMode(fmi2Component c) {
  return Guard(c, "fmi2EnterEventMode", [](FmuInstance&) {});
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo* info) {
  return Guard(c, "fmi2NewDiscreteStates", [&](FmuInstance& m) {
    double next = HUGE_VAL;
    const bool changed = m.EventUpdate(&next);
    info->newDiscreteStatesNeeded = fmi2False;  // the solver's event iteration ran to its end
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = changed ? fmi2True : fmi2False;
    info->nextEventTimeDefined = std::isfinite(next) ? fmi2True : fmi2False;
    info->nextEventTime = std::isfinite(next) ? next : 0.0;
  });
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
  return Guard(c, "fmi2EnterContinuousTimeMode", [](FmuInstance&) {});
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean, fmi2Boolean* enterEventMode,
                                       fmi2Boolean* terminateSimulation) {
  return Guard(c, "fmi2CompletedIntegratorStep", [&](FmuInstance&) {
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
  });
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) {
  return Guard(c, "fmi2SetTime", [&](FmuInstance& m) { m.SetTime(t); });
}
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
  return Guard(c, "fmi2SetContinuousStates", [&](FmuInstance& m) { m.SetContinuousStates(x, n); });
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
  return Guard(c, "fmi2GetDerivatives", [&](FmuInstance& m) { m.GetDerivatives(dx, n); });
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n) {
  return Guard(c, "fmi2GetEventIndicators", [&](FmuInstance& m) { m.GetEventIndicators(z, n); });
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
  return Guard(c, "fmi2GetContinuousStates", [&](FmuInstance& m) { m.GetContinuousStates(x, n); });
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
  return Guard(c, "fmi2GetNominalsOfContinuousStates",
               [&](FmuInstance& m) { m.GetNominals(x, n); });
}

// ---- Co-Simulation -------------------------------------------------------------------------

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr,
                                       const fmi2Integer[], const fmi2Real[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2SetRealInputDerivatives (the FMU has no inputs)");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr,
                                        const fmi2Integer[], fmi2Real[]) {
  return nvr == 0 ? fmi2OK : Unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean) {
  return Guard(c, "fmi2DoStep", [&](FmuInstance& m) { m.DoStep(t, h); });
}
fmi2Status fmi2CancelStep(fmi2Component c) { return Unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return Unsupported(c, "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real* value) {
  if (kind != fmi2LastSuccessfulTime) return Unsupported(c, "fmi2GetRealStatus of this kind");
  return Guard(c, "fmi2GetRealStatus", [&](FmuInstance& m) { *value = m.time(); });
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) {
  return Unsupported(c, "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind, fmi2Boolean* value) {
  return Guard(c, "fmi2GetBooleanStatus", [&](FmuInstance&) { *value = fmi2False; });
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) {
  return Unsupported(c, "fmi2GetStringStatus");
}

}  // extern "C"

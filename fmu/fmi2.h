#pragma once
/// The FMI 2.0 C interface, declared from the standard's list of functions and types (FMI 2.0.x,
/// sections 2.1.2-2.1.10, 3.2 and 4.2): importers look the functions up by these exact names, so
/// the names and signatures must not change. The standard's own headers are not copied; this is
/// the subset of their content an FMU exports, written out for momenta's runtime and its tests.

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef void* fmi2Component;
typedef void* fmi2ComponentEnvironment;
typedef void* fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char* fmi2String;
typedef char fmi2Byte;

#define fmi2True 1
#define fmi2False 0

typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum {
  fmi2DoStepStatus,
  fmi2PendingStatus,
  fmi2LastSuccessfulTime,
  fmi2Terminated
} fmi2StatusKind;

typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String,
                                   fmi2String, ...);
typedef void* (*fmi2CallbackAllocateMemory)(size_t, size_t);
typedef void (*fmi2CallbackFreeMemory)(void*);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);

typedef struct {
  const fmi2CallbackLogger logger;
  const fmi2CallbackAllocateMemory allocateMemory;
  const fmi2CallbackFreeMemory freeMemory;
  const fmi2StepFinished stepFinished;
  const fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

typedef struct {
  fmi2Boolean newDiscreteStatesNeeded;
  fmi2Boolean terminateSimulation;
  fmi2Boolean nominalsOfContinuousStatesChanged;
  fmi2Boolean valuesOfContinuousStatesChanged;
  fmi2Boolean nextEventTimeDefined;
  fmi2Real nextEventTime;
} fmi2EventInfo;

#define MOMENTA_FMI2_EXPORT __attribute__((visibility("default")))

// ---- Common to both kinds ------------------------------------------------------------------
MOMENTA_FMI2_EXPORT const char* fmi2GetTypesPlatform(void);
MOMENTA_FMI2_EXPORT const char* fmi2GetVersion(void);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component, fmi2Boolean, size_t,
                                                   const fmi2String[]);
MOMENTA_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType,
                                                  fmi2String fmuGUID,
                                                  fmi2String fmuResourceLocation,
                                                  const fmi2CallbackFunctions* functions,
                                                  fmi2Boolean visible, fmi2Boolean loggingOn);
MOMENTA_FMI2_EXPORT void fmi2FreeInstance(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component, fmi2Boolean toleranceDefined,
                                                   fmi2Real tolerance, fmi2Real startTime,
                                                   fmi2Boolean stopTimeDefined, fmi2Real stopTime);
MOMENTA_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component, const fmi2ValueReference[], size_t,
                                           fmi2Real[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component, const fmi2ValueReference[], size_t,
                                              fmi2Integer[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component, const fmi2ValueReference[], size_t,
                                              fmi2Boolean[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component, const fmi2ValueReference[], size_t,
                                             fmi2String[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component, const fmi2ValueReference[], size_t,
                                           const fmi2Real[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component, const fmi2ValueReference[], size_t,
                                              const fmi2Integer[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component, const fmi2ValueReference[], size_t,
                                              const fmi2Boolean[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component, const fmi2ValueReference[], size_t,
                                             const fmi2String[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component, fmi2FMUstate*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component, fmi2FMUstate);
MOMENTA_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component, fmi2FMUstate*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component, fmi2FMUstate, size_t*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component, fmi2FMUstate, fmi2Byte[],
                                                     size_t);
MOMENTA_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component, const fmi2Byte[], size_t,
                                                       fmi2FMUstate*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component,
                                                            const fmi2ValueReference[], size_t,
                                                            const fmi2ValueReference[], size_t,
                                                            const fmi2Real[], fmi2Real[]);

// ---- Model Exchange ------------------------------------------------------------------------
MOMENTA_FMI2_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component, fmi2EventInfo*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status
fmi2CompletedIntegratorStep(fmi2Component, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                            fmi2Boolean* enterEventMode, fmi2Boolean* terminateSimulation);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetTime(fmi2Component, fmi2Real);
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component, const fmi2Real[], size_t);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component, fmi2Real[], size_t);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component, fmi2Real[], size_t);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component, fmi2Real[], size_t);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component, fmi2Real[], size_t);

// ---- Co-Simulation -------------------------------------------------------------------------
MOMENTA_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component,
                                                           const fmi2ValueReference[], size_t,
                                                           const fmi2Integer[], const fmi2Real[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component,
                                                            const fmi2ValueReference[], size_t,
                                                            const fmi2Integer[], fmi2Real[]);
MOMENTA_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component, fmi2Real currentCommunicationPoint,
                                          fmi2Real communicationStepSize,
                                          fmi2Boolean noSetFMUStatePriorToCurrentPoint);
MOMENTA_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component, const fmi2StatusKind, fmi2Status*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component, const fmi2StatusKind, fmi2Real*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component, const fmi2StatusKind,
                                                    fmi2Integer*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component, const fmi2StatusKind,
                                                    fmi2Boolean*);
MOMENTA_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component, const fmi2StatusKind,
                                                   fmi2String*);

#ifdef __cplusplus
}
#endif

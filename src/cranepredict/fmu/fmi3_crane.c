/* SPDX-License-Identifier: MIT */
/*
 * The FMI 3.0 co-simulation interface over crane_fmu.c (docs/fmu.md). The fmi3*.h headers are
 * the FMI standard's (taken from the importer's or FMPy's copy at build time). Functions of other
 * interface types (model exchange, scheduled execution, clocks) and kinds of variables the FMU does
 * not have answer with an error through the logger; nothing aborts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi3Functions.h"
#include "crane_fmu.h"

typedef enum { INSTANTIATED, INITIALIZATION, STEP, TERMINATED } phase;

typedef struct {
    cfmu_instance f;
    phase phase;
    char name[128];
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    int logging;
} instance;

static void log_error(void *env, int error, const char *message)
{
    instance *c = (instance *)env;
    if (c->log)
        c->log(c->env, error ? fmi3Error : fmi3OK, error ? "logStatusError" : "logEvents", message);
}

static fmi3Status status(int failed) { return failed ? fmi3Error : fmi3OK; }

static fmi3Status unsupported(fmi3Instance inst, const char *what)
{
    char msg[160];
    snprintf(msg, sizeof msg, "%s is not supported by this FMU (co-simulation only)", what);
    if (inst)
        log_error(inst, 1, msg);
    return fmi3Error;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance inst, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    (void)nCategories;
    (void)categories;
    if (!inst)
        return fmi3Error;
    ((instance *)inst)->logging = loggingOn;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible,
                                         fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
                                         fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    instance *c;

    (void)resourcePath;
    (void)visible;
    (void)eventModeUsed;
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    if (!instantiationToken || strcmp(instantiationToken, cfmu_token) != 0) {
        if (logMessage)
            logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                       "the instantiation token is not this FMU's");
        return NULL;
    }
    c = (instance *)calloc(1, sizeof *c);
    if (!c) {
        if (logMessage)
            logMessage(instanceEnvironment, fmi3Error, "logStatusError", "out of memory");
        return NULL;
    }
    c->env = instanceEnvironment;
    c->log = logMessage;
    c->logging = loggingOn;
    snprintf(c->name, sizeof c->name, "%s", instanceName ? instanceName : "");
    cfmu_init(&c->f, log_error, c);
    c->phase = INSTANTIATED;
    return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible;
    (void)loggingOn;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "this FMU is for co-simulation only");
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible;
    (void)loggingOn; (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "this FMU is for co-simulation only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance inst)
{
    if (inst)
        cfmu_free(&((instance *)inst)->f);
    free(inst);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance inst, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    instance *c = (instance *)inst;
    (void)toleranceDefined; (void)tolerance; (void)stopTimeDefined; (void)stopTime;
    if (!c)
        return fmi3Error;
    c->f.s.time = startTime;
    c->phase = INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance inst)
{
    instance *c = (instance *)inst;
    if (!c)
        return fmi3Error;
    if (cfmu_exit_initialization(&c->f))
        return fmi3Error;
    c->phase = STEP;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance inst) { return unsupported(inst, "event mode"); }

fmi3Status fmi3Terminate(fmi3Instance inst)
{
    if (!inst)
        return fmi3Error;
    ((instance *)inst)->phase = TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance inst)
{
    instance *c = (instance *)inst;
    if (!c)
        return fmi3Error;
    cfmu_free(&c->f);
    cfmu_init(&c->f, log_error, c);
    c->phase = INSTANTIATED;
    return fmi3OK;
}

/* Get and set over the value references, for the types the FMU has. */
static fmi3Status get_values(fmi3Instance inst, const fmi3ValueReference vr[], size_t n, int type,
                             double *out, size_t nv)
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !out)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k)
        if (cfmu_get(&((instance *)inst)->f, vr[k], type, &out[k]))
            return fmi3Error;
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                          fmi3Float64 values[], size_t nv)
{
    return get_values(inst, vr, n, CFMU_FLOAT64, values, nv);
}

fmi3Status fmi3GetInt32(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                        fmi3Int32 values[], size_t nv)
{
    size_t k;
    double x;
    if (!inst || (n > 0 && (!vr || !values)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k) {
        if (cfmu_get(&((instance *)inst)->f, vr[k], CFMU_INT32, &x))
            return fmi3Error;
        values[k] = (fmi3Int32)x;
    }
    return fmi3OK;
}

fmi3Status fmi3GetBoolean(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                          fmi3Boolean values[], size_t nv)
{
    size_t k;
    double x;
    if (!inst || (n > 0 && (!vr || !values)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k) {
        if (cfmu_get(&((instance *)inst)->f, vr[k], CFMU_BOOLEAN, &x))
            return fmi3Error;
        values[k] = x != 0;
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 values[], size_t nv)
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !values)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k)
        if (cfmu_set(&((instance *)inst)->f, vr[k], CFMU_FLOAT64, values[k]))
            return fmi3Error;
    return fmi3OK;
}

fmi3Status fmi3SetInt32(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                        const fmi3Int32 values[], size_t nv)
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !values)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k)
        if (cfmu_set(&((instance *)inst)->f, vr[k], CFMU_INT32, values[k]))
            return fmi3Error;
    return fmi3OK;
}

fmi3Status fmi3SetBoolean(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                          const fmi3Boolean values[], size_t nv)
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !values)) || nv != n)
        return fmi3Error;
    for (k = 0; k < n; ++k)
        if (cfmu_set(&((instance *)inst)->f, vr[k], CFMU_BOOLEAN, values[k] ? 1.0 : 0.0))
            return fmi3Error;
    return fmi3OK;
}

/* The variable types the FMU has none of. */
#define NO_VARIABLES(NAME, TYPE, CONST)                                                        \
    fmi3Status NAME(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,                \
                    CONST TYPE values[], size_t nv)                                            \
    {                                                                                          \
        (void)vr; (void)values; (void)nv;                                                      \
        return n == 0 ? fmi3OK : unsupported(inst, #NAME " (the FMU has no such variable)");   \
    }
NO_VARIABLES(fmi3GetFloat32, fmi3Float32, )
NO_VARIABLES(fmi3GetInt8, fmi3Int8, )
NO_VARIABLES(fmi3GetUInt8, fmi3UInt8, )
NO_VARIABLES(fmi3GetInt16, fmi3Int16, )
NO_VARIABLES(fmi3GetUInt16, fmi3UInt16, )
NO_VARIABLES(fmi3GetUInt32, fmi3UInt32, )
NO_VARIABLES(fmi3GetInt64, fmi3Int64, )
NO_VARIABLES(fmi3GetUInt64, fmi3UInt64, )
NO_VARIABLES(fmi3GetString, fmi3String, )
NO_VARIABLES(fmi3SetFloat32, fmi3Float32, const)
NO_VARIABLES(fmi3SetInt8, fmi3Int8, const)
NO_VARIABLES(fmi3SetUInt8, fmi3UInt8, const)
NO_VARIABLES(fmi3SetInt16, fmi3Int16, const)
NO_VARIABLES(fmi3SetUInt16, fmi3UInt16, const)
NO_VARIABLES(fmi3SetUInt32, fmi3UInt32, const)
NO_VARIABLES(fmi3SetInt64, fmi3Int64, const)
NO_VARIABLES(fmi3SetUInt64, fmi3UInt64, const)
NO_VARIABLES(fmi3SetString, fmi3String, const)

fmi3Status fmi3GetBinary(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                         size_t valueSizes[], fmi3Binary values[], size_t nv)
{
    (void)vr; (void)valueSizes; (void)values; (void)nv;
    return n == 0 ? fmi3OK : unsupported(inst, "fmi3GetBinary");
}

fmi3Status fmi3SetBinary(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nv)
{
    (void)vr; (void)valueSizes; (void)values; (void)nv;
    return n == 0 ? fmi3OK : unsupported(inst, "fmi3SetBinary");
}

fmi3Status fmi3GetClock(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                        fmi3Clock values[])
{
    (void)vr; (void)values;
    return n == 0 ? fmi3OK : unsupported(inst, "fmi3GetClock");
}

fmi3Status fmi3SetClock(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                        const fmi3Clock values[])
{
    (void)vr; (void)values;
    return n == 0 ? fmi3OK : unsupported(inst, "fmi3SetClock");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance inst, fmi3ValueReference vr,
                                               size_t *nDependencies)
{
    (void)vr; (void)nDependencies;
    return unsupported(inst, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance inst, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents;
    (void)elementIndicesOfIndependents; (void)dependencyKinds; (void)nDependencies;
    return unsupported(inst, "fmi3GetVariableDependencies");
}

/* The FMU state: a copy of the instance's snapshot (plain data). */
fmi3Status fmi3GetFMUState(fmi3Instance inst, fmi3FMUState *state)
{
    instance *c = (instance *)inst;
    if (!c || !state)
        return fmi3Error;
    if (!*state) {
        *state = malloc(sizeof(cfmu_snapshot));
        if (!*state)
            return unsupported(inst, "fmi3GetFMUState (out of memory)");
    }
    memcpy(*state, &c->f.s, sizeof(cfmu_snapshot));
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance inst, fmi3FMUState state)
{
    instance *c = (instance *)inst;
    if (!c || !state)
        return fmi3Error;
    return status(cfmu_restore(&c->f, (const cfmu_snapshot *)state));
}

fmi3Status fmi3FreeFMUState(fmi3Instance inst, fmi3FMUState *state)
{
    (void)inst;
    if (state) {
        free(*state);
        *state = NULL;
    }
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance inst, fmi3FMUState state, size_t *size)
{
    (void)state;
    if (!inst || !size)
        return fmi3Error;
    *size = sizeof(cfmu_snapshot);
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance inst, fmi3FMUState state, fmi3Byte serialized[],
                                 size_t size)
{
    const char *why;
    if (!inst || !state || !serialized)
        return fmi3Error;
    why = cfmu_serialize(state, (unsigned char *)serialized, size);
    return why ? unsupported(inst, why) : fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance inst, const fmi3Byte serialized[], size_t size,
                                   fmi3FMUState *state)
{
    const char *why;
    if (!inst || !serialized || !state)
        return fmi3Error;
    why = cfmu_deserialize((const unsigned char *)serialized, size, state);
    return why ? unsupported(inst, why) : fmi3OK;
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance inst, const fmi3ValueReference unknowns[],
                                        size_t nUnknowns, const fmi3ValueReference knowns[],
                                        size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed;
    (void)sensitivity; (void)nSensitivity;
    return unsupported(inst, "fmi3GetDirectionalDerivative");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance inst, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed;
    (void)sensitivity; (void)nSensitivity;
    return unsupported(inst, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance inst)
{
    return unsupported(inst, "configuration mode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance inst)
{
    return unsupported(inst, "configuration mode");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr; (void)n; (void)intervals; (void)qualifiers;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                   fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)vr; (void)n; (void)counters; (void)resolutions; (void)qualifiers;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                               fmi3Float64 shifts[])
{
    (void)vr; (void)n; (void)shifts;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)vr; (void)n; (void)counters; (void)resolutions;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Float64 intervals[])
{
    (void)vr; (void)n; (void)intervals;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                   const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr; (void)n; (void)counters; (void)resolutions;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                               const fmi3Float64 shifts[])
{
    (void)vr; (void)n; (void)shifts;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr; (void)n; (void)counters; (void)resolutions;
    return unsupported(inst, "clocks");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance inst)
{
    return unsupported(inst, "event mode");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance inst, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime)
{
    (void)discreteStatesNeedUpdate; (void)terminateSimulation;
    (void)nominalsOfContinuousStatesChanged; (void)valuesOfContinuousStatesChanged;
    (void)nextEventTimeDefined; (void)nextEventTime;
    return unsupported(inst, "event mode");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance inst)
{
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance inst,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3SetTime(fmi3Instance inst, fmi3Float64 time)
{
    (void)time;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3SetContinuousStates(fmi3Instance inst, const fmi3Float64 x[], size_t nx)
{
    (void)x; (void)nx;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance inst, fmi3Float64 dx[], size_t nx)
{
    (void)dx; (void)nx;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetEventIndicators(fmi3Instance inst, fmi3Float64 z[], size_t nz)
{
    (void)z; (void)nz;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetContinuousStates(fmi3Instance inst, fmi3Float64 x[], size_t nx)
{
    (void)x; (void)nx;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance inst, fmi3Float64 x[], size_t nx)
{
    (void)x; (void)nx;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance inst, size_t *nz)
{
    (void)nz;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance inst, size_t *nx)
{
    (void)nx;
    return unsupported(inst, "model exchange");
}

fmi3Status fmi3EnterStepMode(fmi3Instance inst)
{
    return unsupported(inst, "event mode");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance inst, const fmi3ValueReference vr[], size_t n,
                                    const fmi3Int32 orders[], fmi3Float64 values[], size_t nv)
{
    (void)vr; (void)n; (void)orders; (void)values; (void)nv;
    return unsupported(inst, "fmi3GetOutputDerivatives");
}

/* One communication step: crane_step over it (the core's own RK4, end stops and valves; the
 * internal step is the parameter step, shortened to the communication step when that is
 * smaller). No early return: the step always reaches its end or fails with nothing changed. */
fmi3Status fmi3DoStep(fmi3Instance inst, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    instance *c = (instance *)inst;
    fmi3Status st;

    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c)
        return fmi3Error;
    if (c->phase != STEP) {
        log_error(c, 1, "fmi3DoStep outside step mode");
        return fmi3Error;
    }
    (void)currentCommunicationPoint;   /* the instance keeps its own time */
    st = status(cfmu_do_step(&c->f, communicationStepSize));
    if (eventHandlingNeeded)
        *eventHandlingNeeded = fmi3False;
    if (terminateSimulation)
        *terminateSimulation = fmi3False;
    if (earlyReturn)
        *earlyReturn = fmi3False;
    if (lastSuccessfulTime)
        *lastSuccessfulTime = c->f.s.time;
    return st;
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance inst, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return unsupported(inst, "scheduled execution");
}

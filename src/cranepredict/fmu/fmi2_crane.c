/* SPDX-License-Identifier: MIT */
/*
 * The FMI 2.0 co-simulation interface over crane_fmu.c (docs/fmu.md). The fmi2*.h headers are
 * the FMI standard's (taken from the importer's or FMPy's copy at build time). Model-exchange
 * functions are not part of a co-simulation-only FMU; what the FMU does not do answers with an
 * error through the logger; nothing aborts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#include "crane_fmu.h"

typedef struct {
    cfmu_instance f;
    int initialized;
    char name[128];
    fmi2CallbackFunctions cb;
    int logging;
} instance;

static void log_error(void *env, int error, const char *message)
{
    instance *c = (instance *)env;
    if (c->cb.logger)
        c->cb.logger(c->cb.componentEnvironment, c->name, error ? fmi2Error : fmi2OK,
                     error ? "logStatusError" : "logEvents", "%s", message);
}

static fmi2Status status(int failed) { return failed ? fmi2Error : fmi2OK; }

static fmi2Status unsupported(fmi2Component inst, const char *what)
{
    char msg[160];
    snprintf(msg, sizeof msg, "%s is not supported by this FMU", what);
    if (inst)
        log_error(inst, 1, msg);
    return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component inst, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    (void)nCategories;
    (void)categories;
    if (!inst)
        return fmi2Error;
    ((instance *)inst)->logging = loggingOn;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn)
{
    instance *c;
    const char *name = instanceName ? instanceName : "";

    (void)fmuResourceLocation;
    (void)visible;
    if (!functions)
        return NULL;
    if (fmuType != fmi2CoSimulation || !fmuGUID || strcmp(fmuGUID, cfmu_token) != 0) {
        if (functions->logger)
            functions->logger(functions->componentEnvironment, name, fmi2Error, "logStatusError",
                              "%s", fmuType != fmi2CoSimulation
                                        ? "this FMU is for co-simulation only"
                                        : "the GUID is not this FMU's");
        return NULL;
    }
    c = (instance *)calloc(1, sizeof *c);
    if (!c) {
        if (functions->logger)
            functions->logger(functions->componentEnvironment, name, fmi2Error,
                              "logStatusError", "%s", "out of memory");
        return NULL;
    }
    c->cb = *functions;
    c->logging = loggingOn;
    snprintf(c->name, sizeof c->name, "%s", name);
    cfmu_init(&c->f, log_error, c);
    return c;
}

void fmi2FreeInstance(fmi2Component inst)
{
    if (inst)
        cfmu_free(&((instance *)inst)->f);
    free(inst);
}

fmi2Status fmi2SetupExperiment(fmi2Component inst, fmi2Boolean toleranceDefined,
                               fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined; (void)tolerance; (void)stopTimeDefined; (void)stopTime;
    if (!inst)
        return fmi2Error;
    ((instance *)inst)->f.s.time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component inst) { return inst ? fmi2OK : fmi2Error; }

fmi2Status fmi2ExitInitializationMode(fmi2Component inst)
{
    if (!inst)
        return fmi2Error;
    return status(cfmu_exit_initialization(&((instance *)inst)->f));
}

fmi2Status fmi2Terminate(fmi2Component inst) { return inst ? fmi2OK : fmi2Error; }

fmi2Status fmi2Reset(fmi2Component inst)
{
    instance *c = (instance *)inst;
    if (!c)
        return fmi2Error;
    cfmu_free(&c->f);
    cfmu_init(&c->f, log_error, c);
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                       fmi2Real value[])
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !value)))
        return fmi2Error;
    for (k = 0; k < n; ++k)
        if (cfmu_get(&((instance *)inst)->f, vr[k], CFMU_FLOAT64, &value[k]))
            return fmi2Error;
    return fmi2OK;
}

static fmi2Status get_ints(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                           fmi2Integer value[], int type)
{
    size_t k;
    double x;
    if (!inst || (n > 0 && (!vr || !value)))
        return fmi2Error;
    for (k = 0; k < n; ++k) {
        if (cfmu_get(&((instance *)inst)->f, vr[k], type, &x))
            return fmi2Error;
        value[k] = (fmi2Integer)x;
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                          fmi2Integer value[])
{
    return get_ints(inst, vr, n, value, CFMU_INT32);
}

fmi2Status fmi2GetBoolean(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                          fmi2Boolean value[])
{
    return get_ints(inst, vr, n, value, CFMU_BOOLEAN);
}

fmi2Status fmi2GetString(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                         fmi2String value[])
{
    (void)vr; (void)value;
    return n == 0 ? fmi2OK : unsupported(inst, "fmi2GetString (the FMU has no strings)");
}

fmi2Status fmi2SetReal(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real value[])
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !value)))
        return fmi2Error;
    for (k = 0; k < n; ++k)
        if (cfmu_set(&((instance *)inst)->f, vr[k], CFMU_FLOAT64, value[k]))
            return fmi2Error;
    return fmi2OK;
}

static fmi2Status set_ints(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                           const fmi2Integer value[], int type)
{
    size_t k;
    if (!inst || (n > 0 && (!vr || !value)))
        return fmi2Error;
    for (k = 0; k < n; ++k)
        if (cfmu_set(&((instance *)inst)->f, vr[k], type,
                     type == CFMU_BOOLEAN ? (value[k] != 0) : (double)value[k]))
            return fmi2Error;
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                          const fmi2Integer value[])
{
    return set_ints(inst, vr, n, value, CFMU_INT32);
}

fmi2Status fmi2SetBoolean(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                          const fmi2Boolean value[])
{
    return set_ints(inst, vr, n, value, CFMU_BOOLEAN);
}

fmi2Status fmi2SetString(fmi2Component inst, const fmi2ValueReference vr[], size_t n,
                         const fmi2String value[])
{
    (void)vr; (void)value;
    return n == 0 ? fmi2OK : unsupported(inst, "fmi2SetString (the FMU has no strings)");
}

/* The FMU state: a copy of the instance's snapshot (plain data). */
fmi2Status fmi2GetFMUstate(fmi2Component inst, fmi2FMUstate *state)
{
    instance *c = (instance *)inst;
    if (!c || !state)
        return fmi2Error;
    if (!*state) {
        *state = malloc(sizeof(cfmu_snapshot));
        if (!*state)
            return unsupported(inst, "fmi2GetFMUstate (out of memory)");
    }
    memcpy(*state, &c->f.s, sizeof(cfmu_snapshot));
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component inst, fmi2FMUstate state)
{
    if (!inst || !state)
        return fmi2Error;
    return status(cfmu_restore(&((instance *)inst)->f, (const cfmu_snapshot *)state));
}

fmi2Status fmi2FreeFMUstate(fmi2Component inst, fmi2FMUstate *state)
{
    (void)inst;
    if (state) {
        free(*state);
        *state = NULL;
    }
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component inst, fmi2FMUstate state, size_t *size)
{
    (void)state;
    if (!inst || !size)
        return fmi2Error;
    *size = sizeof(cfmu_snapshot);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component inst, fmi2FMUstate state, fmi2Byte serialized[],
                                 size_t size)
{
    const char *why;
    if (!inst || !state || !serialized)
        return fmi2Error;
    why = cfmu_serialize(state, (unsigned char *)serialized, size);
    return why ? unsupported(inst, why) : fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component inst, const fmi2Byte serialized[], size_t size,
                                   fmi2FMUstate *state)
{
    const char *why;
    if (!inst || !serialized || !state)
        return fmi2Error;
    why = cfmu_deserialize((const unsigned char *)serialized, size, state);
    return why ? unsupported(inst, why) : fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component inst, const fmi2ValueReference u[],
                                        size_t nu, const fmi2ValueReference k[], size_t nk,
                                        const fmi2Real dk[], fmi2Real du[])
{
    (void)u; (void)nu; (void)k; (void)nk; (void)dk; (void)du;
    return unsupported(inst, "fmi2GetDirectionalDerivative");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component inst, const fmi2ValueReference vr[],
                                       size_t n, const fmi2Integer order[],
                                       const fmi2Real value[])
{
    (void)vr; (void)order; (void)value;
    return n == 0 ? fmi2OK : unsupported(inst, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component inst, const fmi2ValueReference vr[],
                                        size_t n, const fmi2Integer order[], fmi2Real value[])
{
    (void)vr; (void)order; (void)value;
    return n == 0 ? fmi2OK : unsupported(inst, "fmi2GetRealOutputDerivatives");
}

/* One communication step: crane_step over it (the core's own RK4, end stops and valves; the
 * internal step is the parameter step, shortened to the communication step when that is
 * smaller). Synchronous: never fmi2Pending. */
fmi2Status fmi2DoStep(fmi2Component inst, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)currentCommunicationPoint;   /* the instance keeps its own time */
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!inst)
        return fmi2Error;
    return status(cfmu_do_step(&((instance *)inst)->f, communicationStepSize));
}

fmi2Status fmi2CancelStep(fmi2Component inst)
{
    return unsupported(inst, "fmi2CancelStep (doStep is synchronous)");
}

fmi2Status fmi2GetStatus(fmi2Component inst, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s; (void)value;
    return unsupported(inst, "fmi2GetStatus (doStep is synchronous)");
}

fmi2Status fmi2GetRealStatus(fmi2Component inst, const fmi2StatusKind s, fmi2Real *value)
{
    instance *c = (instance *)inst;
    if (!c || !value)
        return fmi2Error;
    if (s != fmi2LastSuccessfulTime)
        return unsupported(inst, "fmi2GetRealStatus of this kind");
    *value = c->f.s.time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component inst, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s; (void)value;
    return unsupported(inst, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component inst, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s; (void)value;
    return unsupported(inst, "fmi2GetBooleanStatus");
}

fmi2Status fmi2GetStringStatus(fmi2Component inst, const fmi2StatusKind s, fmi2String *value)
{
    (void)s; (void)value;
    return unsupported(inst, "fmi2GetStringStatus");
}

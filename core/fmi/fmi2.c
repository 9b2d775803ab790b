/* FMI 2.0 co-simulation interface over the model API (fmu_model.h). Every function checks its
 * instance and its state against a mask of the states the standard allows it in; what the plant
 * does not offer (FMU state, derivatives, asynchronous steps) returns fmi2Error with a log message.
 * Any fmi2Error puts the instance in the error state: then only reading values (for diagnosis),
 * fmi2Reset and fmi2FreeInstance are allowed. */
#include <math.h>
#include <stdio.h>

#include "fmi2Functions.h"
#include "fmu_model.h"

#define MODEL(c) ((fmu_instance *)(c))
/* Every function starts here: a NULL instance cannot even be logged to. */
#define REQUIRE_INSTANCE(c) do { if (!(c)) return fmi2Error; } while (0)
/* ... and the states it may be called in (FMI 2.0.4, section 4.2.4, the co-simulation state
 * machine; stepComplete, stepFailed and stepCanceled are all "step mode" here: no step fails
 * without an fmi2Error, none is asynchronous). */
#define REQUIRE_STATE(c, function, mask)                                                       \
    do {                                                                                       \
        if (!(c)) return fmi2Error;                                                            \
        if (fmu_check_mode(MODEL(c), function, mask) != FMU_OK) return fmi2Error;              \
    } while (0)
#define M(mode) FMU_IN(FMU_##mode)
#define MASK_SetupExperiment M(INSTANTIATED)
#define MASK_EnterInitializationMode M(INSTANTIATED)
#define MASK_ExitInitializationMode M(INITIALIZATION)
#define MASK_Terminate M(STEP)
#define MASK_Reset FMU_ANY_MODE
#define MASK_GetValues (M(INITIALIZATION) | M(STEP) | M(TERMINATED) | M(ERROR_STATE))
#define MASK_SetValues (M(INSTANTIATED) | M(INITIALIZATION) | M(STEP))
#define MASK_DoStep M(STEP)
#define MASK_GetStatus (M(STEP) | M(TERMINATED))

/* The message goes as the format itself, '%' doubled: importers that print it unformatted (FMPy)
 * and those that format it (the standard's printf convention) both show the text. */
static void fmi2_log(fmu_callback callback, void *environment, const char *name, fmu_status status,
                     const char *category, const char *message)
{
    char format[1024];
    size_t n = 0;
    for (const char *c = message; *c && n + 2 < sizeof format; ++c) {
        if (*c == '%') format[n++] = '%';
        format[n++] = *c;
    }
    format[n] = '\0';
    ((fmi2CallbackLogger)callback)(environment, name, (fmi2Status)status, category, format);
}

static fmi2Status unsupported(fmi2Component c, const char *function)
{
    REQUIRE_INSTANCE(c);
    return (fmi2Status)fmu_log(MODEL(c), FMU_ERROR, "%s: not supported by this FMU", function);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    (void)nCategories;
    (void)categories;
    REQUIRE_INSTANCE(c);   /* allowed in every state */
    MODEL(c)->debug_logging = loggingOn != fmi2False;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)fmuResourceLocation;
    (void)visible;
    fmu_callback logger = functions ? (fmu_callback)functions->logger : NULL;
    void *environment = functions ? functions->componentEnvironment : NULL;
    if (fmuType != fmi2CoSimulation) {
        char message[160];
        snprintf(message, sizeof message, "fmi2Instantiate: fmuType = %d: this FMU offers co-simulation only "
                 "(fmi2CoSimulation = %d)", (int)fmuType, (int)fmi2CoSimulation);
        if (logger) fmi2_log(logger, environment, instanceName, FMU_ERROR, "logStatusError", message);
        return NULL;
    }
    return fmu_instantiate(instanceName, fmuGUID, fmi2_log, logger, environment, loggingOn != fmi2False);
}

void fmi2FreeInstance(fmi2Component c) { fmu_free(MODEL(c)); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    REQUIRE_STATE(c, "fmi2SetupExperiment", MASK_SetupExperiment);
    if (startTime != 0.0)
        return (fmi2Status)fmu_log(MODEL(c), FMU_ERROR, "fmi2SetupExperiment: startTime = %g s: must be 0",
                                   startTime);
    if (stopTimeDefined && !(stopTime >= startTime))
        return (fmi2Status)fmu_log(MODEL(c), FMU_ERROR, "fmi2SetupExperiment: stopTime = %g s: must not precede "
                                   "startTime = %g s", stopTime, startTime);
    MODEL(c)->setup_stop_time = stopTimeDefined ? stopTime : NAN;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    REQUIRE_STATE(c, "fmi2EnterInitializationMode", MASK_EnterInitializationMode);
    return (fmi2Status)fmu_enter_initialization(MODEL(c), 0.0, MODEL(c)->setup_stop_time);
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    REQUIRE_STATE(c, "fmi2ExitInitializationMode", MASK_ExitInitializationMode);
    return (fmi2Status)fmu_exit_initialization(MODEL(c));
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    REQUIRE_STATE(c, "fmi2Terminate", MASK_Terminate);
    return (fmi2Status)fmu_terminate(MODEL(c));
}

fmi2Status fmi2Reset(fmi2Component c)
{
    REQUIRE_STATE(c, "fmi2Reset", MASK_Reset);
    return (fmi2Status)fmu_reset(MODEL(c));
}

/* ---- variables (fmi2Boolean is an int) */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    REQUIRE_STATE(c, "fmi2GetReal", MASK_GetValues);
    if (fmu_check_arrays(MODEL(c), "fmi2GetReal", nvr, vr, value) != FMU_OK) return fmi2Error;
    return (fmi2Status)fmu_get_real(MODEL(c), vr, nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    REQUIRE_STATE(c, "fmi2SetReal", MASK_SetValues);
    if (fmu_check_arrays(MODEL(c), "fmi2SetReal", nvr, vr, value) != FMU_OK) return fmi2Error;
    return (fmi2Status)fmu_set_real(MODEL(c), vr, nvr, value);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    REQUIRE_STATE(c, "fmi2GetBoolean", MASK_GetValues);
    if (fmu_check_arrays(MODEL(c), "fmi2GetBoolean", nvr, vr, value) != FMU_OK) return fmi2Error;
    return (fmi2Status)fmu_get_boolean(MODEL(c), vr, nvr, value);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    REQUIRE_STATE(c, "fmi2SetBoolean", MASK_SetValues);
    if (fmu_check_arrays(MODEL(c), "fmi2SetBoolean", nvr, vr, value) != FMU_OK) return fmi2Error;
    return (fmi2Status)fmu_set_boolean(MODEL(c), vr, nvr, value);
}

/* No Integer or String variables: any value reference is unknown. */
static fmi2Status no_variables(fmi2Component c, const char *function, unsigned mask,
                               const fmi2ValueReference vr[], size_t nvr, const void *value)
{
    REQUIRE_STATE(c, function, mask);
    if (fmu_check_arrays(MODEL(c), function, nvr, vr, value) != FMU_OK) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    return (fmi2Status)fmu_log(MODEL(c), FMU_ERROR, "%s: value reference %u is not of this type (the FMU has "
                               "Real and Boolean variables only)", function, vr[0]);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    return no_variables(c, "fmi2GetInteger", MASK_GetValues, vr, nvr, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    return no_variables(c, "fmi2SetInteger", MASK_SetValues, vr, nvr, value);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    return no_variables(c, "fmi2GetString", MASK_GetValues, vr, nvr, value);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    return no_variables(c, "fmi2SetString", MASK_SetValues, vr, nvr, value);
}

/* ---- co-simulation */

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    REQUIRE_STATE(c, "fmi2DoStep", MASK_DoStep);
    return (fmi2Status)fmu_do_step(MODEL(c), currentCommunicationPoint, communicationStepSize);
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    REQUIRE_STATE(c, "fmi2GetRealStatus", MASK_GetStatus);
    if (s != fmi2LastSuccessfulTime) return unsupported(c, "fmi2GetRealStatus");
    if (!value) return (fmi2Status)fmu_log(MODEL(c), FMU_ERROR, "fmi2GetRealStatus: value = NULL");
    *value = fmu_time(MODEL(c));
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetBooleanStatus");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

/* ---- not offered (canGetAndSetFMUstate, providesDirectionalDerivative are false) */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    (void)state;
    return unsupported(c, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{
    (void)state;
    return unsupported(c, "fmi2SetFMUstate");
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    (void)state;
    return unsupported(c, "fmi2FreeFMUstate");
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size)
{
    (void)state;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size)
{
    (void)state;
    (void)bytes;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state)
{
    (void)bytes;
    (void)size;
    (void)state;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown_ref;
    (void)nUnknown;
    (void)vKnown_ref;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

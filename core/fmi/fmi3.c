/* FMI 3.0 co-simulation interface over the model API (fmu_model.h). Every function checks its
 * instance and its state against a mask of the states the standard allows it in; what the plant
 * does not offer (model exchange, scheduled execution, clocks, FMU state, derivatives, event mode)
 * returns fmi3Error with a log message. After any fmi3Error only fmi3Reset and fmi3FreeInstance
 * are allowed (FMI 3.0, section 2.2.3). */
#include <math.h>
#include <stdbool.h>

#include "fmi3Functions.h"
#include "fmu_model.h"

#define MODEL(i) ((fmu_instance *)(i))
/* Every function starts here: a NULL instance cannot even be logged to. */
#define REQUIRE_INSTANCE(i) do { if (!(i)) return fmi3Error; } while (0)
/* ... and the states it may be called in (FMI 3.0, section 4.3, co-simulation without event mode). */
#define REQUIRE_STATE(i, function, mask)                                                       \
    do {                                                                                       \
        if (!(i)) return fmi3Error;                                                            \
        if (fmu_check_mode(MODEL(i), function, mask) != FMU_OK) return fmi3Error;              \
    } while (0)
#define M(mode) FMU_IN(FMU_##mode)
#define MASK_EnterInitializationMode M(INSTANTIATED)
#define MASK_ExitInitializationMode M(INITIALIZATION)
#define MASK_Terminate M(STEP)
#define MASK_Reset FMU_ANY_MODE
#define MASK_GetValues (M(INITIALIZATION) | M(STEP) | M(TERMINATED))
#define MASK_SetValues (M(INSTANTIATED) | M(INITIALIZATION) | M(STEP))
#define MASK_DoStep M(STEP)

static void fmi3_log(fmu_callback callback, void *environment, const char *name, fmu_status status,
                     const char *category, const char *message)
{
    (void)name;
    ((fmi3LogMessageCallback)callback)(environment, (fmi3Status)status, category, message);
}

static fmi3Status unsupported(fmi3Instance instance, const char *function)
{
    REQUIRE_INSTANCE(instance);
    return (fmi3Status)fmu_log(MODEL(instance), FMU_ERROR, "%s: not supported by this FMU", function);
}

/* The FMU has Float64 and Boolean variables only: a value reference of any other type is unknown. */
static fmi3Status no_variables(fmi3Instance instance, const char *function, unsigned mask,
                               const fmi3ValueReference vr[], size_t n, const void *values, size_t nValues)
{
    REQUIRE_STATE(instance, function, mask);
    if (nValues != n)
        return (fmi3Status)fmu_log(MODEL(instance), FMU_ERROR, "%s: nValues = %zu: must equal "
                                   "nValueReferences = %zu", function, nValues, n);
    if (fmu_check_arrays(MODEL(instance), function, n, vr, values) != FMU_OK) return fmi3Error;
    if (n == 0) return fmi3OK;
    return (fmi3Status)fmu_log(MODEL(instance), FMU_ERROR, "%s: value reference %u is not of this type (the FMU "
                               "has Float64 and Boolean variables only)", function, vr[0]);
}

static fmi3Status check_sizes(fmi3Instance instance, const char *function, size_t nvr, size_t nValues,
                              const void *vr, const void *values)
{
    if (nvr == nValues) return (fmi3Status)fmu_check_arrays(MODEL(instance), function, nvr, vr, values);
    return (fmi3Status)fmu_log(MODEL(instance), FMU_ERROR, "%s: nValues = %zu: must equal nValueReferences = %zu "
                               "(every variable is a scalar)", function, nValues, nvr);
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    (void)nCategories;
    (void)categories;
    REQUIRE_INSTANCE(instance);   /* allowed in every state */
    MODEL(instance)->debug_logging = loggingOn;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)resourcePath;
    (void)visible;
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    if (eventModeUsed) {
        if (logMessage)
            logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                       "fmi3InstantiateCoSimulation: eventModeUsed = true: this FMU has no event mode");
        return NULL;
    }
    return fmu_instantiate(instanceName, instantiationToken, fmi3_log, (fmu_callback)logMessage,
                           instanceEnvironment, loggingOn);
}

static fmi3Instance not_co_simulation(fmi3InstanceEnvironment environment, fmi3LogMessageCallback log,
                                      const char *function)
{
    if (log) log(environment, fmi3Error, "logStatusError", function);
    return NULL;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    return not_co_simulation(instanceEnvironment, logMessage,
                             "fmi3InstantiateModelExchange: this FMU offers co-simulation only");
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible,
                                               fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    return not_co_simulation(instanceEnvironment, logMessage,
                             "fmi3InstantiateScheduledExecution: this FMU offers co-simulation only");
}

void fmi3FreeInstance(fmi3Instance instance) { fmu_free(MODEL(instance)); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    REQUIRE_STATE(instance, "fmi3EnterInitializationMode", MASK_EnterInitializationMode);
    if (stopTimeDefined && !(stopTime >= startTime))
        return (fmi3Status)fmu_log(MODEL(instance), FMU_ERROR, "fmi3EnterInitializationMode: stopTime = %g s: "
                                   "must not precede startTime = %g s", stopTime, startTime);
    return (fmi3Status)fmu_enter_initialization(MODEL(instance), startTime, stopTimeDefined ? stopTime : NAN);
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    REQUIRE_STATE(instance, "fmi3ExitInitializationMode", MASK_ExitInitializationMode);
    return (fmi3Status)fmu_exit_initialization(MODEL(instance));
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    REQUIRE_STATE(instance, "fmi3Terminate", MASK_Terminate);
    return (fmi3Status)fmu_terminate(MODEL(instance));
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    REQUIRE_STATE(instance, "fmi3Reset", MASK_Reset);
    return (fmi3Status)fmu_reset(MODEL(instance));
}

/* ---- variables */

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    REQUIRE_STATE(instance, "fmi3GetFloat64", MASK_GetValues);
    if (check_sizes(instance, "fmi3GetFloat64", nValueReferences, nValues, valueReferences, values) != fmi3OK)
        return fmi3Error;
    return (fmi3Status)fmu_get_real(MODEL(instance), valueReferences, nValueReferences, values);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    REQUIRE_STATE(instance, "fmi3SetFloat64", MASK_SetValues);
    if (check_sizes(instance, "fmi3SetFloat64", nValueReferences, nValues, valueReferences, values) != fmi3OK)
        return fmi3Error;
    return (fmi3Status)fmu_set_real(MODEL(instance), valueReferences, nValueReferences, values);
}

/* fmi3Boolean is a bool: converted one by one through the model's int interface. */
fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    REQUIRE_STATE(instance, "fmi3GetBoolean", MASK_GetValues);
    if (check_sizes(instance, "fmi3GetBoolean", nValueReferences, nValues, valueReferences, values) != fmi3OK)
        return fmi3Error;
    for (size_t i = 0; i < nValueReferences; ++i) {
        int value;
        fmu_status s = fmu_get_boolean(MODEL(instance), &valueReferences[i], 1, &value);
        if (s != FMU_OK) return (fmi3Status)s;
        values[i] = value != 0;
    }
    return fmi3OK;
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    REQUIRE_STATE(instance, "fmi3SetBoolean", MASK_SetValues);
    if (check_sizes(instance, "fmi3SetBoolean", nValueReferences, nValues, valueReferences, values) != fmi3OK)
        return fmi3Error;
    for (size_t i = 0; i < nValueReferences; ++i) {
        int value = values[i] ? 1 : 0;
        fmu_status s = fmu_set_boolean(MODEL(instance), &valueReferences[i], 1, &value);
        if (s != FMU_OK) return (fmi3Status)s;
    }
    return fmi3OK;
}

/* ---- co-simulation */

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    REQUIRE_STATE(instance, "fmi3DoStep", MASK_DoStep);
    fmu_status s = fmu_do_step(MODEL(instance), currentCommunicationPoint, communicationStepSize);
    if (eventHandlingNeeded) *eventHandlingNeeded = false;
    if (terminateSimulation) *terminateSimulation = false;
    if (earlyReturn) *earlyReturn = false;
    if (lastSuccessfulTime) *lastSuccessfulTime = fmu_time(MODEL(instance));
    return (fmi3Status)s;
}

/* ---- types without variables */

fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetFloat32", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                       size_t nValueReferences, fmi3Int8 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetInt8", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3UInt8 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetUInt8", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int16 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetInt16", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3UInt16 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetUInt16", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetInt32", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3UInt32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetUInt32", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int64 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetInt64", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3UInt64 values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetUInt64", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3String values[], size_t nValues)
{
    return no_variables(instance, "fmi3GetString", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)valueSizes;
    return no_variables(instance, "fmi3GetBinary", MASK_GetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetFloat32", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                       size_t nValueReferences, const fmi3Int8 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetInt8", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3UInt8 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetUInt8", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int16 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetInt16", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3UInt16 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetUInt16", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetInt32", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3UInt32 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetUInt32", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int64 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetInt64", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3UInt64 values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetUInt64", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3String values[], size_t nValues)
{
    return no_variables(instance, "fmi3SetString", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const size_t valueSizes[], const fmi3Binary values[],
                         size_t nValues)
{
    (void)valueSizes;
    return no_variables(instance, "fmi3SetBinary", MASK_SetValues, valueReferences, nValueReferences,
                        values, nValues);
}

/* ---- not offered: model exchange, scheduled execution, clocks, FMU state, derivatives, event mode */

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterEventMode");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Clock values[])
{
    (void)valueReferences; (void)nValueReferences; (void)values;
    return unsupported(instance, "fmi3GetClock");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Clock values[])
{
    (void)valueReferences; (void)nValueReferences; (void)values;
    return unsupported(instance, "fmi3SetClock");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t* nDependencies)
{
    (void)valueReference; (void)nDependencies;
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents;
    (void)elementIndicesOfIndependents; (void)dependencyKinds; (void)nDependencies;
    return unsupported(instance, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState)
{
    (void)FMUState;
    return unsupported(instance, "fmi3GetFMUState");
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    (void)FMUState;
    return unsupported(instance, "fmi3SetFMUState");
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState)
{
    (void)FMUState;
    return unsupported(instance, "fmi3FreeFMUState");
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t* size)
{
    (void)FMUState; (void)size;
    return unsupported(instance, "fmi3SerializedFMUStateSize");
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size)
{
    (void)FMUState; (void)serializedState; (void)size;
    return unsupported(instance, "fmi3SerializeFMUState");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState* FMUState)
{
    (void)serializedState; (void)size; (void)FMUState;
    return unsupported(instance, "fmi3DeserializeFMUState");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                        size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                                        const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],
                                        size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns;
    (void)seed; (void)nSeed; (void)sensitivity; (void)nSensitivity;
    return unsupported(instance, "fmi3GetDirectionalDerivative");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns;
    (void)seed; (void)nSeed; (void)sensitivity; (void)nSensitivity;
    return unsupported(instance, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences; (void)nValueReferences; (void)intervals; (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions; (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[])
{
    (void)valueReferences; (void)nValueReferences; (void)shifts;
    return unsupported(instance, "fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[])
{
    (void)valueReferences; (void)nValueReferences; (void)intervals;
    return unsupported(instance, "fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[])
{
    (void)valueReferences; (void)nValueReferences; (void)shifts;
    return unsupported(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EvaluateDiscreteStates");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
                                    fmi3Boolean* terminateSimulation,
                                    fmi3Boolean* nominalsOfContinuousStatesChanged,
                                    fmi3Boolean* valuesOfContinuousStatesChanged,
                                    fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime)
{
    (void)discreteStatesNeedUpdate; (void)terminateSimulation; (void)nominalsOfContinuousStatesChanged;
    (void)valuesOfContinuousStatesChanged; (void)nextEventTimeDefined; (void)nextEventTime;
    return unsupported(instance, "fmi3UpdateDiscreteStates");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
    return unsupported(instance, "fmi3CompletedIntegratorStep");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    (void)time;
    return unsupported(instance, "fmi3SetTime");
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return unsupported(instance, "fmi3SetContinuousStates");
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    (void)derivatives; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStateDerivatives");
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    (void)eventIndicators; (void)nEventIndicators;
    return unsupported(instance, "fmi3GetEventIndicators");
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStates");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates)
{
    (void)nominals; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNominalsOfContinuousStates");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators)
{
    (void)nEventIndicators;
    return unsupported(instance, "fmi3GetNumberOfEventIndicators");
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates)
{
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNumberOfContinuousStates");
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterStepMode");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues)
{
    (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
    return unsupported(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return unsupported(instance, "fmi3ActivateModelPartition");
}

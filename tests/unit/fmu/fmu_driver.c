/* Drives an FMI 2 FMU's sources directly (compiled with them under AddressSanitizer by
 * test_fmu_memory.py): instantiate/free cycles, every 100th with a short run, then calls that must
 * fail cleanly. Usage: fmu_driver GUID CYCLES. Exit status 0: every check held (leaks are left to
 * LeakSanitizer, which fails the exit status itself). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi2Functions.h"

static int errors_logged, failures;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env;
    (void)name;
    (void)category;
    if (status >= fmi2Error) errors_logged++;
    (void)message;
}

#define CHECK(condition) do { if (!(condition)) { failures++; fprintf(stderr, "failed: %s\n", #condition); } } while (0)

static fmi2Component instantiate(const char *guid, const fmi2CallbackFunctions *callbacks)
{
    return fmi2Instantiate("driver", fmi2CoSimulation, guid, "", callbacks, fmi2False, fmi2False);
}

static void short_run(fmi2Component c)
{
    CHECK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK);
    CHECK(fmi2EnterInitializationMode(c) == fmi2OK);
    CHECK(fmi2ExitInitializationMode(c) == fmi2OK);
    for (int i = 0; i < 10; ++i) CHECK(fmi2DoStep(c, i * 0.01, 0.01, fmi2True) == fmi2OK);
    CHECK(fmi2Terminate(c) == fmi2OK);
}

/* Calls in the wrong state and bad values: each returns fmi2Error, logs and leaves the instance in
 * the error state, from which fmi2Reset brings it back. */
static void wrong_calls(const char *guid, const fmi2CallbackFunctions *callbacks)
{
    int logged = errors_logged;
    CHECK(instantiate("{not-the-token}", callbacks) == NULL);
    CHECK(fmi2DoStep(NULL, 0.0, 0.001, fmi2True) == fmi2Error);
    fmi2Component c = instantiate(guid, callbacks);
    CHECK(c != NULL);
    if (!c) return;
    fmi2ValueReference unknown = 999999, speed = 1;   /* 1: the first parameter (initial_speed) */
    double nan = NAN, value = 1.0;
    CHECK(fmi2DoStep(c, 0.0, 0.001, fmi2True) == fmi2Error);            /* before initialisation */
    CHECK(fmi2EnterInitializationMode(c) == fmi2Error);                 /* in the error state */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2SetReal(c, &speed, 1, &nan) == fmi2Error);                /* NaN */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2GetReal(c, &unknown, 1, &value) == fmi2Error);            /* before initialisation */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2SetReal(c, &speed, 1, NULL) == fmi2Error);                /* NULL values */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2EnterInitializationMode(c) == fmi2OK);
    CHECK(fmi2Terminate(c) == fmi2Error);                               /* not from initialisation */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2EnterInitializationMode(c) == fmi2OK);
    CHECK(fmi2ExitInitializationMode(c) == fmi2OK);
    CHECK(fmi2SetReal(c, &speed, 1, &value) == fmi2Error);              /* parameter after initialisation */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2EnterInitializationMode(c) == fmi2OK);
    CHECK(fmi2ExitInitializationMode(c) == fmi2OK);
    CHECK(fmi2DoStep(c, 0.0, 9.2e15, fmi2True) == fmi2Error);           /* beyond the longest step */
    CHECK(fmi2Reset(c) == fmi2OK);
    CHECK(fmi2EnterInitializationMode(c) == fmi2OK);
    CHECK(fmi2ExitInitializationMode(c) == fmi2OK);
    CHECK(fmi2DoStep(c, 0.0, 0.001, fmi2True) == fmi2OK);               /* usable after the reset */
    fmi2FreeInstance(c);
    CHECK(errors_logged - logged == 9);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s GUID CYCLES\n", argv[0]);
        return 2;
    }
    const char *guid = argv[1];
    int cycles = atoi(argv[2]);
    fmi2CallbackFunctions callbacks = {logger, NULL, NULL, NULL, NULL};
    for (int i = 0; i < cycles; ++i) {
        fmi2Component c = instantiate(guid, &callbacks);
        CHECK(c != NULL);
        if (!c) break;
        if (i % 100 == 0) short_run(c);
        fmi2FreeInstance(c);
    }
    wrong_calls(guid, &callbacks);
    printf("cycles %d, errors logged %d, failed checks %d\n", cycles, errors_logged, failures);
    return failures ? 1 : 0;
}

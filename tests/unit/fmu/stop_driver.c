/* Runs an FMI 2 railbrake FMU binary through a whole stop in 10 ms doSteps and prints
 * "t speed position cylinder_c1a1 wheel_speed_c1a1" every 0.1 s and at the stop, with 17 digits
 * (test_fmu_platforms.py). Built for Linux (dlopen) and cross-compiled for Windows (LoadLibrary),
 * so the win64 binary runs under Wine beside the linux64 one.
 * Usage: stop_driver LIBRARY GUID VR_SPEED VR_POSITION VR_CYLINDER VR_WHEEL STOP_SPEED MAX_TIME */
#include <stdio.h>
#include <stdlib.h>

#include "fmi2Functions.h"

#ifdef _WIN32
#include <windows.h>
#define OPEN(path) ((void *)LoadLibraryA(path))
#define SYMBOL(library, name) ((void *)GetProcAddress((HMODULE)(library), name))
#else
#include <dlfcn.h>
#define OPEN(path) dlopen(path, RTLD_NOW | RTLD_LOCAL)
#define SYMBOL(library, name) dlsym(library, name)
#endif

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env;
    (void)name;
    (void)category;
    fprintf(stderr, "status %d: %s\n", (int)status, message);
}

#define LOAD(var, type, name)                                                   \
    type *var;                                                                  \
    *(void **)&var = SYMBOL(library, name);                                     \
    if (!var) { fprintf(stderr, "missing %s\n", name); return 1; }

int main(int argc, char **argv)
{
    if (argc != 9) {
        fprintf(stderr, "usage: %s LIBRARY GUID VR_SPEED VR_POSITION VR_CYLINDER VR_WHEEL STOP_SPEED MAX_TIME\n",
                argv[0]);
        return 2;
    }
    void *library = OPEN(argv[1]);
    if (!library) { fprintf(stderr, "cannot load %s\n", argv[1]); return 1; }
    LOAD(instantiate, fmi2InstantiateTYPE, "fmi2Instantiate")
    LOAD(setup, fmi2SetupExperimentTYPE, "fmi2SetupExperiment")
    LOAD(enter, fmi2EnterInitializationModeTYPE, "fmi2EnterInitializationMode")
    LOAD(leave, fmi2ExitInitializationModeTYPE, "fmi2ExitInitializationMode")
    LOAD(do_step, fmi2DoStepTYPE, "fmi2DoStep")
    LOAD(get_real, fmi2GetRealTYPE, "fmi2GetReal")
    LOAD(free_instance, fmi2FreeInstanceTYPE, "fmi2FreeInstance")
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference vr[4];
    for (int i = 0; i < 4; ++i) vr[i] = (fmi2ValueReference)atoi(argv[3 + i]);
    double stop_speed = atof(argv[7]), max_time = atof(argv[8]), value[4];
    fmi2Component c = instantiate("stop", fmi2CoSimulation, argv[2], "", &callbacks, fmi2False, fmi2False);
    if (!c || setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK || enter(c) != fmi2OK || leave(c) != fmi2OK)
        return 1;
    for (long k = 0;; ++k) {
        double t = k * 0.01;
        if (get_real(c, vr, 4, value) != fmi2OK) return 1;
        int stop = value[0] <= stop_speed || t >= max_time;
        if (k % 10 == 0 || stop) printf("%.2f %.17g %.17g %.17g %.17g\n", t, value[0], value[1], value[2], value[3]);
        if (stop) break;
        if (do_step(c, t, 0.01, fmi2True) != fmi2OK) return 1;
    }
    free_instance(c);
    return 0;
}

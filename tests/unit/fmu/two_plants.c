/* Two railbrake FMI 3 plants of different configurations in one process, stepped in turn
 * (test_fmu_binaries.py). Built two ways:
 *   - dynamic: both binaries dlopen'ed with RTLD_GLOBAL, the FMI functions looked up in each;
 *   - static (-DPREFIX_A=... -DPREFIX_B=...): both FMUs' sources compiled with FMI3_FUNCTION_PREFIX
 *     and linked into this executable.
 * Usage: two_plants [LIB_A LIB_B] TOKEN_A TOKEN_B VR_A VR_B SECONDS. Prints "t a b" every 0.1 s:
 * the variable VR_A of plant A and VR_B of plant B. Exit status 0 when every call returned OK. */
#include <stdio.h>
#include <stdlib.h>

#include "fmi3FunctionTypes.h"

typedef struct {
    fmi3InstantiateCoSimulationTYPE *instantiate;
    fmi3EnterInitializationModeTYPE *enter_initialization;
    fmi3ExitInitializationModeTYPE *exit_initialization;
    fmi3DoStepTYPE *do_step;
    fmi3GetFloat64TYPE *get_float64;
    fmi3FreeInstanceTYPE *free_instance;
} plant_api;

#ifdef PREFIX_A
#define PASTE_(a, b) a##b
#define PASTE(a, b) PASTE_(a, b)
#define DECLARE(prefix)                                                                     \
    extern fmi3InstantiateCoSimulationTYPE PASTE(prefix, fmi3InstantiateCoSimulation);      \
    extern fmi3EnterInitializationModeTYPE PASTE(prefix, fmi3EnterInitializationMode);      \
    extern fmi3ExitInitializationModeTYPE PASTE(prefix, fmi3ExitInitializationMode);        \
    extern fmi3DoStepTYPE PASTE(prefix, fmi3DoStep);                                        \
    extern fmi3GetFloat64TYPE PASTE(prefix, fmi3GetFloat64);                                \
    extern fmi3FreeInstanceTYPE PASTE(prefix, fmi3FreeInstance);
#define API(prefix)                                                                         \
    {PASTE(prefix, fmi3InstantiateCoSimulation), PASTE(prefix, fmi3EnterInitializationMode), \
     PASTE(prefix, fmi3ExitInitializationMode), PASTE(prefix, fmi3DoStep),                  \
     PASTE(prefix, fmi3GetFloat64), PASTE(prefix, fmi3FreeInstance)}
DECLARE(PREFIX_A)
DECLARE(PREFIX_B)
enum { LIBRARY_ARGS = 0 };

static int load(char **argv, plant_api *a, plant_api *b)
{
    (void)argv;
    plant_api first = API(PREFIX_A), second = API(PREFIX_B);
    *a = first;
    *b = second;
    return 0;
}
#else
#include <dlfcn.h>
enum { LIBRARY_ARGS = 2 };

static void *symbol(void *library, const char *name, int *missing)
{
    void *f = dlsym(library, name);
    if (!f) { fprintf(stderr, "%s: %s\n", name, dlerror()); ++*missing; }
    return f;
}

static int load_one(const char *path, plant_api *api)
{
    void *library = dlopen(path, RTLD_NOW | RTLD_GLOBAL);
    int missing = 0;
    if (!library) { fprintf(stderr, "%s\n", dlerror()); return 1; }
    *(void **)&api->instantiate = symbol(library, "fmi3InstantiateCoSimulation", &missing);
    *(void **)&api->enter_initialization = symbol(library, "fmi3EnterInitializationMode", &missing);
    *(void **)&api->exit_initialization = symbol(library, "fmi3ExitInitializationMode", &missing);
    *(void **)&api->do_step = symbol(library, "fmi3DoStep", &missing);
    *(void **)&api->get_float64 = symbol(library, "fmi3GetFloat64", &missing);
    *(void **)&api->free_instance = symbol(library, "fmi3FreeInstance", &missing);
    return missing;
}

static int load(char **argv, plant_api *a, plant_api *b)
{
    return load_one(argv[1], a) + load_one(argv[2], b);
}
#endif

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env;
    fprintf(stderr, "status %d %s: %s\n", (int)status, category, message);
}

static fmi3Instance start(const plant_api *api, const char *name, const char *token)
{
    fmi3Instance i = api->instantiate(name, token, "", fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0, NULL,
                                      logger, NULL);
    if (!i || api->enter_initialization(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK ||
        api->exit_initialization(i) != fmi3OK)
        return NULL;
    return i;
}

int main(int argc, char **argv)
{
    plant_api a, b;
    if (argc != 6 + LIBRARY_ARGS) {
        fprintf(stderr, "usage: %s %sTOKEN_A TOKEN_B VR_A VR_B SECONDS\n", argv[0], LIBRARY_ARGS ? "LIB_A LIB_B " : "");
        return 2;
    }
    if (load(argv, &a, &b)) return 1;
    char **arg = argv + 1 + LIBRARY_ARGS;
    fmi3ValueReference vr_a = (fmi3ValueReference)atoi(arg[2]), vr_b = (fmi3ValueReference)atoi(arg[3]);
    int steps = (int)(atof(arg[4]) * 100.0 + 0.5);
    fmi3Instance ia = start(&a, "A", arg[0]), ib = start(&b, "B", arg[1]);
    if (!ia || !ib) return 1;
    for (int k = 0; k <= steps; ++k) {
        double t = k * 0.01, va, vb;
        if (a.get_float64(ia, &vr_a, 1, &va, 1) != fmi3OK || b.get_float64(ib, &vr_b, 1, &vb, 1) != fmi3OK) return 1;
        if (k % 10 == 0) printf("%.3f %.17g %.17g\n", t, va, vb);
        if (k == steps) break;
        if (a.do_step(ia, t, 0.01, fmi3True, NULL, NULL, NULL, NULL) != fmi3OK ||
            b.do_step(ib, t, 0.01, fmi3True, NULL, NULL, NULL, NULL) != fmi3OK)
            return 1;
    }
    a.free_instance(ia);
    b.free_instance(ib);
    return 0;
}

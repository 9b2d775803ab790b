/* FMI call-sequence fuzzer: random sequences of FMI 2 or FMI 3 co-simulation calls with random
 * arguments against the FMU's own sources (compiled together, under AddressSanitizer + UBSan by
 * tests/fuzz/fmu.py). Build with -DFUZZ_FMI=2 or -DFUZZ_FMI=3.
 *
 * The fuzzer keeps its own model of the standard's state machine (FMI 2.0.4 section 4.2.4,
 * FMI 3.0 section 4.3; written from the standard, not from the FMU's masks) and checks, per call:
 *   - no call returns OK in a state the standard forbids it in (nor sets a parameter after
 *     initialisation, an output, or a value outside its declared range or not finite);
 *   - no OK status comes with a non-finite output: after every accepted doStep every Real output
 *     is read back and must be finite;
 *   - the sanitizers report nothing (they abort the run).
 * Usage: fmi_fuzz CALLS SEED. Prints "calls N, ok N, violations N" and exits 1 on a violation. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_model.h"

#if FUZZ_FMI == 2
#include "fmi2Functions.h"
typedef fmi2Component instance_t;
#else
#include "fmi3Functions.h"
typedef fmi3Instance instance_t;
#endif

/* the standard's states, as the fuzzer tracks them */
enum { START, INSTANTIATED, INIT, STEP, TERMINATED, ERROR_STATE };
#define S(x) (1u << (x))
#define ANY_INSTANCE (S(INSTANTIATED) | S(INIT) | S(STEP) | S(TERMINATED) | S(ERROR_STATE))
#if FUZZ_FMI == 2
#define GET_ALLOWED (S(INIT) | S(STEP) | S(TERMINATED) | S(ERROR_STATE))   /* 2.0.4: getters for diagnosis */
#else
#define GET_ALLOWED (S(INIT) | S(STEP) | S(TERMINATED))                    /* 3.0: after an error, reset/free */
#endif
#define SET_ALLOWED (S(INSTANTIATED) | S(INIT) | S(STEP))

static const char *const state_names[] = {"start", "instantiated", "initialization", "step", "terminated",
                                          "error"};

/* ---- random numbers (xorshift64*, seeded: runs are reproducible) */
static uint64_t rng_state;
static uint64_t next_u64(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 2685821657736338717ULL;
}
static unsigned below(unsigned n) { return (unsigned)(next_u64() % n); }
static double uniform(void) { return (double)(next_u64() >> 11) / 9007199254740992.0; }

static long calls, accepted, violations;
static long past_stop, past_stop_accepted;   /* doSteps that would pass the stopTime, and those returning OK */
static int state = START;
static instance_t instance;
static double now;   /* the FMU's time as the fuzzer expects it */
static double stop_time = INFINITY;   /* the stopTime given at the last initialization (none: infinity) */
static double requested_stop;        /* the stopTime of the enterInitializationMode call under way */

/* A random stopTime for enterInitializationMode: none (infinity), one the doSteps soon reach (within
 * 10 ms, on a plant step or between two), or one in [start - 1, start + 9] s. */
static double random_stop(double start);

static void violation(const char *function, const char *what)
{
    violations++;
    if (violations <= 20)
        fprintf(stderr, "violation after %ld calls: %s %s (tracked state %s)\n", calls, function, what,
                state_names[state]);
}

/* Every FMI status: OK must be allowed in the tracked state; an error moves to the error state. */
static int outcome(const char *function, int status, unsigned allowed)
{
    calls++;
    if (status == 0) {
        accepted++;
        if (!(allowed & S(state))) violation(function, "returned OK in a state the standard forbids");
        return 1;
    }
    if (status >= 3) state = ERROR_STATE;
    return 0;
}

static void logger_sink(void) {}

#if FUZZ_FMI == 2
static void log_fmi2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                 fmi2String message, ...)
{
    (void)env; (void)name; (void)status; (void)category; (void)message;
    logger_sink();
}
static const fmi2CallbackFunctions callbacks = {log_fmi2, NULL, NULL, NULL, NULL};
#else
static void log_fmi3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env; (void)status; (void)category; (void)message;
    logger_sink();
}
#endif

/* ---- random arguments */

static double random_value(const fmu_variable *v)
{
    static const double specials[] = {0.0, -0.0, 1.0, -1.0, 1e-308, 5e-324, 1e308, -1e308, 2e9, 1e13, 1e-9};
    switch (below(8)) {
    case 0: return NAN;
    case 1: return below(2) ? INFINITY : -INFINITY;
    case 2: return specials[below(sizeof specials / sizeof specials[0])];
    case 3: return (uniform() - 0.5) * 1e6;
    default: {
        double lo = v && isfinite(v->min) ? v->min : -1e6, hi = v && isfinite(v->max) ? v->max : 1e6;
        return lo + uniform() * (hi - lo);   /* inside the declared range */
    }
    }
}

static unsigned random_vr(void)
{
    switch (below(10)) {
    case 0: return (unsigned)fmu_variable_count + below(5);
    case 1: return 0xffffffffu - below(3);
    default: return below((unsigned)fmu_variable_count);
    }
}

static unsigned random_vr_of(int type)
{
    for (int tries = 0; tries < 8; ++tries) {
        unsigned vr = random_vr();
        if (vr < fmu_variable_count && fmu_variables[vr].type == type) return vr;
    }
    return random_vr();
}

/* May the standard accept setting vr to value in the tracked state? */
static int settable(unsigned vr, double value, int is_real)
{
    if (vr >= fmu_variable_count) return 0;
    const fmu_variable *v = &fmu_variables[vr];
    if (is_real != (v->type == FMU_REAL)) return 0;
    if (v->causality == FMU_PARAMETER && !(S(state) & (S(INSTANTIATED) | S(INIT) | (v->tunable ? S(STEP) : 0u))))
        return 0;
    if (v->causality != FMU_PARAMETER && v->causality != FMU_INPUT) return 0;
    if (is_real && (!isfinite(value) || value < v->min || value > v->max)) return 0;
    return 1;
}

static int readable(unsigned vr, int is_real)
{
    return vr < fmu_variable_count && is_real == (fmu_variables[vr].type == FMU_REAL);
}

/* ---- the FMI calls (version-specific spelling, shared checks) */

#if FUZZ_FMI == 2
#define OK_ fmi2OK
static int call_get_real(const unsigned *vr, size_t n, double *values, int exact)
{
    (void)exact;
    return fmi2GetReal(instance, vr, n, values);
}
static int call_set_real(const unsigned *vr, size_t n, const double *values)
{
    return fmi2SetReal(instance, vr, n, values);
}
static int call_get_boolean(const unsigned *vr, size_t n, int *values)
{
    fmi2Boolean b[8] = {0};
    int s = fmi2GetBoolean(instance, vr, n, values ? b : NULL);
    for (size_t i = 0; values && i < n; ++i) values[i] = b[i];
    return s;
}
static int call_set_boolean(const unsigned *vr, size_t n, const int *values)
{
    fmi2Boolean b[8] = {0};
    for (size_t i = 0; values && i < n; ++i) b[i] = values[i];
    return fmi2SetBoolean(instance, vr, n, values ? b : NULL);
}
static int call_do_step(double t, double h) { return fmi2DoStep(instance, t, h, fmi2True); }
static int call_enter_init(double start)
{
    requested_stop = random_stop(start);
    int s = fmi2SetupExperiment(instance, fmi2False, 0.0, start, isinf(requested_stop) ? fmi2False : fmi2True,
                                isinf(requested_stop) ? 0.0 : requested_stop);
    if (!outcome("fmi2SetupExperiment", s, S(INSTANTIATED))) return s;
    return fmi2EnterInitializationMode(instance);
}
static int call_exit_init(void) { return fmi2ExitInitializationMode(instance); }
static int call_terminate(void) { return fmi2Terminate(instance); }
static int call_reset(void) { return fmi2Reset(instance); }
static void call_free(void) { fmi2FreeInstance(instance); }
static instance_t call_instantiate(const char *token)
{
    return fmi2Instantiate("fuzz", below(8) ? fmi2CoSimulation : fmi2ModelExchange, token, "", &callbacks,
                           fmi2False, (fmi2Boolean)below(2));
}
/* an unsupported or variable-less call, chosen at random: never OK except as the standard allows */
static void call_other(void)
{
    fmi2ValueReference vr = random_vr();
    fmi2Integer i = 0;
    fmi2String str = NULL;
    fmi2Real r = 0.0;
    fmi2FMUstate fs = NULL;
    switch (below(7)) {
    case 0: outcome("fmi2GetInteger", fmi2GetInteger(instance, &vr, below(2), &i), GET_ALLOWED); break;
    case 1: outcome("fmi2SetString", fmi2SetString(instance, &vr, below(2), &str), SET_ALLOWED); break;
    case 2: {
        fmi2StatusKind kind = (fmi2StatusKind)below(4);
        int given = below(4) != 0;
        int ok = outcome("fmi2GetRealStatus", fmi2GetRealStatus(instance, kind, given ? &r : NULL),
                         given && kind == fmi2LastSuccessfulTime ? S(STEP) | S(TERMINATED) : 0u);
        if (ok && !isfinite(r)) violation("fmi2GetRealStatus", "returned OK with a non-finite time");
        break;
    }
    case 3: outcome("fmi2GetFMUstate", fmi2GetFMUstate(instance, &fs), 0); break;
    case 4: outcome("fmi2CancelStep", fmi2CancelStep(instance), 0); break;
    case 5: outcome("fmi2SetDebugLogging", fmi2SetDebugLogging(instance, (fmi2Boolean)below(2), 0, NULL),
                    ANY_INSTANCE); break;
    default: outcome("fmi2GetDirectionalDerivative",
                     fmi2GetDirectionalDerivative(instance, &vr, 1, &vr, 1, &r, &r), 0); break;
    }
}
#else
#define OK_ fmi3OK
static int call_get_real(const unsigned *vr, size_t n, double *values, int exact)
{
    return fmi3GetFloat64(instance, vr, n, values, exact ? n : n + 1);   /* nValues != n: an error */
}
static int call_set_real(const unsigned *vr, size_t n, const double *values)
{
    return fmi3SetFloat64(instance, vr, n, values, n);
}
static int call_get_boolean(const unsigned *vr, size_t n, int *values)
{
    fmi3Boolean b[8] = {0};
    int s = fmi3GetBoolean(instance, vr, n, values ? b : NULL, n);
    for (size_t i = 0; values && i < n; ++i) values[i] = b[i];
    return s;
}
static int call_set_boolean(const unsigned *vr, size_t n, const int *values)
{
    fmi3Boolean b[8] = {0};
    for (size_t i = 0; values && i < n; ++i) b[i] = values[i] != 0;
    return fmi3SetBoolean(instance, vr, n, values ? b : NULL, n);
}
static int call_do_step(double t, double h)
{
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return fmi3DoStep(instance, t, h, fmi3True, &event, &terminate, &early, &last);
}
static int call_enter_init(double start)
{
    requested_stop = random_stop(start);
    return fmi3EnterInitializationMode(instance, fmi3False, 0.0, start, !isinf(requested_stop),
                                       isinf(requested_stop) ? 0.0 : requested_stop);
}
static int call_exit_init(void) { return fmi3ExitInitializationMode(instance); }
static int call_terminate(void) { return fmi3Terminate(instance); }
static int call_reset(void) { return fmi3Reset(instance); }
static void call_free(void) { fmi3FreeInstance(instance); }
static instance_t call_instantiate(const char *token)
{
    return fmi3InstantiateCoSimulation("fuzz", token, "", fmi3False, (fmi3Boolean)below(2), below(8) == 0,
                                       fmi3False, NULL, 0, NULL, log_fmi3, NULL);
}
static void call_other(void)
{
    fmi3ValueReference vr = random_vr();
    fmi3Int32 i = 0;
    fmi3Float64 r = 0.0;
    fmi3FMUState fs = NULL;
    switch (below(6)) {
    case 0: outcome("fmi3GetInt32", fmi3GetInt32(instance, &vr, below(2), &i, 1), GET_ALLOWED); break;
    case 1: outcome("fmi3EnterEventMode", fmi3EnterEventMode(instance), 0); break;
    case 2: outcome("fmi3GetFMUState", fmi3GetFMUState(instance, &fs), 0); break;
    case 3: outcome("fmi3EnterConfigurationMode", fmi3EnterConfigurationMode(instance), 0); break;
    case 4: outcome("fmi3SetDebugLogging", fmi3SetDebugLogging(instance, (fmi3Boolean)below(2), 0, NULL),
                    ANY_INSTANCE); break;
    default: outcome("fmi3SetTime", fmi3SetTime(instance, r), 0); break;
    }
}
#endif

/* After an accepted step or initialisation: every Real output is read back, OK and finite. */
static void check_outputs(const char *after)
{
    for (size_t vr = 0; vr < fmu_variable_count; ++vr) {
        if (fmu_variables[vr].causality != FMU_OUTPUT || fmu_variables[vr].type != FMU_REAL) continue;
        unsigned r = (unsigned)vr;
        double value = 0.0;
        int s = call_get_real(&r, 1, &value, 1);
        calls++;
        if (s != OK_ || !isfinite(value)) {
            char what[160];
            snprintf(what, sizeof what, "accepted, then output %s = %g (status %d)", fmu_variables[vr].name,
                     value, s);
            violation(after, what);
            if (s >= 3) state = ERROR_STATE;
            return;
        }
    }
}

static void fuzz_get(int is_real)
{
    unsigned vr[8];
    double values[8];
    int bools[8];
    size_t n = below(5);
    for (size_t i = 0; i < n; ++i) vr[i] = random_vr_of(is_real ? FMU_REAL : FMU_BOOLEAN);
    int null_args = below(30) == 0, exact = below(20) != 0;
    int s = is_real ? call_get_real(null_args ? NULL : vr, n, values, exact)
                    : call_get_boolean(vr, n, null_args ? NULL : bools);
    int all_readable = exact || !is_real || FUZZ_FMI == 2;
    for (size_t i = 0; i < n; ++i) all_readable &= readable(vr[i], is_real);
    if (outcome(is_real ? "getReal" : "getBoolean", s, all_readable && !(null_args && n) ? GET_ALLOWED : 0u) &&
        is_real)
        for (size_t i = 0; i < n; ++i)
            if (!isfinite(values[i])) violation("getReal", "returned OK with a non-finite value");
}

static void fuzz_set(int is_real)
{
    unsigned vr[8];
    double values[8];
    int bools[8];
    size_t n = below(5);
    int all_settable = 1;
    for (size_t i = 0; i < n; ++i) {
        vr[i] = random_vr_of(is_real ? FMU_REAL : FMU_BOOLEAN);
        values[i] = random_value(vr[i] < fmu_variable_count ? &fmu_variables[vr[i]] : NULL);
        bools[i] = (int)below(3) - (int)below(2);
    }
    for (size_t i = 0; i < n; ++i) all_settable &= settable(vr[i], values[i], is_real);
    int null_args = below(30) == 0;
    int s = is_real ? call_set_real(vr, n, null_args ? NULL : values) : call_set_boolean(null_args ? NULL : vr, n, bools);
    outcome(is_real ? "setReal" : "setBoolean", s, all_settable && !(null_args && n) ? SET_ALLOWED : 0u);
}

static double random_stop(double start)
{
    switch (below(3)) {
    case 0: return INFINITY;
    case 1: return start + 1e-3 * below(10) + (below(2) ? 0.0 : 5e-4);   /* reached within a doStep or two */
    default: return start + 10 * uniform() - 1;
    }
}

static void fuzz_step(void)
{
    static const double sizes[] = {1e-3, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 1.5e-3, 0.0, -1e-3, 1e-4, 601.0, 9.2e15,
                                   1e300, INFINITY, NAN};
    double h = sizes[below(sizeof sizes / sizeof sizes[0])];
    double t = below(10) ? now : (below(2) ? now + 1e-3 : NAN);
    int s = call_do_step(t, h);
    int well_formed = isfinite(h) && h > 0.0 && h <= 600.0 && fabs(h / 1e-3 - round(h / 1e-3)) < 1e-6 && t == now;
    int beyond = now + round(h / 1e-3) * 1e-3 > stop_time + 1e-9;   /* never past the stopTime */
    int valid = well_formed && !beyond;
    if (well_formed && beyond && state == STEP) {
        past_stop++;
        past_stop_accepted += s == 0;
    }
    if (outcome("doStep", s, valid ? S(STEP) : 0u)) {
        now += round(h / 1e-3) * 1e-3;
        check_outputs("doStep");
    }
}

static void fuzz_lifecycle(void)
{
    switch (below(9)) {
    case 0: case 1: {
        double start = below(6) ? 0.0 : 1.0;
        if (outcome("enterInitializationMode", call_enter_init(start), start == 0.0 ? S(INSTANTIATED) : 0u)) {
            state = INIT;
            stop_time = requested_stop;
        }
        break;
    }
    case 2: case 3:
        if (outcome("exitInitializationMode", call_exit_init(), S(INIT))) {
            state = STEP;
            now = 0.0;
            check_outputs("exitInitializationMode");
        }
        break;
    case 4:
        if (outcome("terminate", call_terminate(), S(STEP))) state = TERMINATED;
        break;
    case 5: case 6:
        if (outcome("reset", call_reset(), ANY_INSTANCE)) state = INSTANTIATED;
        break;
    case 7:
        call_free();
        calls++;
        instance = NULL;
        state = START;
        break;
    default:
        call_other();
    }
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s CALLS SEED\n", argv[0]);
        return 2;
    }
    long target = atol(argv[1]);
    rng_state = strtoull(argv[2], NULL, 10) * 0x9E3779B97F4A7C15ULL + 1;
    while (calls < target) {
        if (state == START) {
            int good = below(10) != 0;
            instance = call_instantiate(good ? fmu_token : "{00000000-0000-0000-0000-000000000000}");
            calls++;
            if (instance) {
                accepted++;
                state = INSTANTIATED;
            }
            continue;
        }
        if (state == ERROR_STATE && below(3) == 0) {   /* mostly recover: most calls in live states */
            if (outcome("reset", call_reset(), ANY_INSTANCE)) state = INSTANTIATED;
            continue;
        }
        unsigned what = below(100);
        if (what < 25) fuzz_step();
        else if (what < 45) fuzz_get(1);
        else if (what < 55) fuzz_get(0);
        else if (what < 75) fuzz_set(1);
        else if (what < 82) fuzz_set(0);
        else fuzz_lifecycle();
    }
    if (instance) call_free();
    printf("FMI %d: calls %ld, ok %ld, violations %ld, doSteps past the stopTime %ld (accepted %ld)\n", FUZZ_FMI,
           calls, accepted, violations, past_stop, past_stop_accepted);
    /* the line tools/fuzz_record.py keeps for docs/robustness.md */
    printf("fuzz-result {\"target\": \"fmi%d\", \"calls\": %ld, \"ok\": %ld, \"violations\": %ld, "
           "\"past_stop\": %ld, \"past_stop_accepted\": %ld, \"seed\": \"%s\", "
           "\"sanitizers\": \"address,undefined\"}\n", FUZZ_FMI, calls, accepted, violations, past_stop,
           past_stop_accepted, argv[2]);
    return violations ? 1 : 0;
}

/* The plant as a co-simulation model: lifecycle, variable access by value reference, stepping.
 * The step runs the same calls in the same order as rb_run_advance (run.c), so an FMU run equals
 * the native run. */
#include "fmu_model.h"

#include "railbrake/rb_bounds.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const mode_names[] = {"instantiated", "initialization mode", "step mode", "terminated",
                                         "in the error state (only reset or free it)"};
static const char *const causality_names[] = {"independent", "parameter", "input", "output"};

static void log_message(fmu_log_function log, fmu_callback callback, void *environment, const char *name,
                        fmu_status status, const char *format, va_list args)
{
    char message[512];
    if (!log || !callback) return;
    vsnprintf(message, sizeof message, format, args);
    log(callback, environment, name, status, status >= FMU_ERROR ? "logStatusError" : "logAll", message);
}

fmu_status fmu_log(fmu_instance *m, fmu_status status, const char *format, ...)
{
    if (status >= FMU_ERROR) m->mode = FMU_ERROR_STATE;
    if (status >= FMU_ERROR || m->debug_logging) {
        va_list args;
        va_start(args, format);
        log_message(m->log, m->log_callback, m->environment, m->name, status, format, args);
        va_end(args);
    }
    return status;
}

static void log_early(fmu_log_function log, fmu_callback callback, void *environment, const char *name,
                      const char *format, ...)
{
    va_list args;
    va_start(args, format);
    log_message(log, callback, environment, name, FMU_ERROR, format, args);
    va_end(args);
}

fmu_status fmu_check_mode(fmu_instance *m, const char *function, unsigned allowed)
{
    if (allowed & FMU_IN(m->mode)) return FMU_OK;
    return fmu_log(m, FMU_ERROR, "%s: not allowed when the instance is %s", function, mode_names[m->mode]);
}

fmu_status fmu_check_arrays(fmu_instance *m, const char *function, size_t n, const void *vr, const void *values)
{
    if (n == 0 || (vr && values)) return FMU_OK;
    return fmu_log(m, FMU_ERROR, "%s: %zu values with a NULL %s array", function, n,
                   vr ? "value" : "value reference");
}

/* The first output of the instance's cars and axles that is not finite, or NULL. */
static const char *nonfinite_output(const fmu_instance *m, double *value)
{
    const rb_plant_outputs *o = &m->out;
    const double scalars[] = {o->time, o->speed, o->position, o->deceleration, o->main_reservoir, o->pipe_end,
                              o->air_in_system, o->air_vented, o->air_compressed};
    static const char *const scalar_names[] = {"time", "speed", "position", "deceleration", "main_reservoir",
                                               "pipe_end", "air_in_system", "air_vented", "air_compressed"};
    for (size_t i = 0; i < sizeof scalars / sizeof scalars[0]; ++i)
        if (!isfinite(scalars[i])) { *value = scalars[i]; return scalar_names[i]; }
    for (int c = 0; c < m->plant.n_cars; ++c) {
        const double per_car[] = {o->supply[c], o->pilot[c], o->relay[c], o->ed_force[c], o->car_speed[c]};
        static const char *const car_names[] = {"supply", "pilot", "relay", "ed_force", "car_speed"};
        for (size_t i = 0; i < sizeof per_car / sizeof per_car[0]; ++i)
            if (!isfinite(per_car[i])) { *value = per_car[i]; return car_names[i]; }
    }
    for (int a = 0; a < m->plant.n_cars * RB_AXLES_PER_CAR; ++a) {
        const double per_axle[] = {o->wheel_speed[a], o->wheel_speed_measured[a], o->slip[a], o->adhesion[a],
                                   o->cylinder[a]};
        static const char *const axle_names[] = {"wheel_speed", "wheel_speed_measured", "slip", "adhesion",
                                                 "cylinder"};
        for (size_t i = 0; i < sizeof per_axle / sizeof per_axle[0]; ++i)
            if (!isfinite(per_axle[i])) { *value = per_axle[i]; return axle_names[i]; }
    }
    return NULL;
}

static fmu_status check_finite(fmu_instance *m, const char *function)
{
    double value;
    const char *name = nonfinite_output(m, &value);
    if (!name) return FMU_OK;
    return fmu_log(m, FMU_ERROR, "%s: output %s = %g at t = %.6f s is not finite: the parameters lie outside "
                   "what the plant's numerics bear", function, name, value, fmu_time(m));
}

double fmu_time(const fmu_instance *m) { return (double)m->step * m->plant.dt; }

/* ---- setup: the BCU's load-weighed pressure map follows the (possibly tuned) plant, as
 * railbrake.simulation.bcu_params sets it up; then the states at t = 0. */
static fmu_status setup(fmu_instance *m)
{
    rb_error err;
    if (rb_plant_check(&m->plant, &err) != RB_OK || rb_plant_bounds_check(&m->plant, &err) != RB_OK ||
        rb_wsp_check(&m->wsp, &err) != RB_OK)
        return fmu_log(m, FMU_ERROR, "invalid parameter: %s", err.message);
    double supply = m->plant.car[0].vehicle.supply_pressure;
    for (int c = 1; c < m->plant.n_cars; ++c)
        if (m->plant.car[c].vehicle.supply_pressure < supply) supply = m->plant.car[c].vehicle.supply_pressure;
    m->bcu.n_cars = m->plant.n_cars;
    m->bcu.wsp = NULL;
    m->bcu.wsp_context = NULL;
    rb_bcu_pressure_map(&m->plant, supply, &m->bcu);
    if (rb_plant_init(&m->plant, &m->state, &err) != RB_OK ||
        rb_bcu_init(&m->bcu, &m->wsp, &m->bcu_state, &err) != RB_OK)
        return fmu_log(m, FMU_ERROR, "invalid parameter: %s", err.message);
    memset(&m->in, 0, sizeof m->in);
    rb_plant_get_outputs(&m->plant, &m->state, &m->out);
    m->step = 0;
    return check_finite(m, "initialization");
}

static fmu_status load_defaults(fmu_instance *m)
{
    size_t keep = offsetof(fmu_instance, log);   /* the environment survives a reset */
    memset(m, 0, keep);
    fmu_scenario_defaults(m);
    m->setup_stop_time = NAN;
    m->stop_step = INT64_MAX;
    m->mode = FMU_INSTANTIATED;
    fmu_status s = setup(m);
    if (s == FMU_OK) m->mode = FMU_INSTANTIATED;
    return s;
}

fmu_instance *fmu_instantiate(const char *name, const char *token, fmu_log_function log, fmu_callback log_callback,
                              void *environment, int debug_logging)
{
    if (!token || strcmp(token, fmu_token) != 0) {
        log_early(log, log_callback, environment, name, "instantiate: instantiation token \"%s\" does not match "
                  "this FMU's \"%s\" (modelDescription.xml and binary from different exports?)",
                  token ? token : "(null)", fmu_token);
        return NULL;
    }
    fmu_instance *m = calloc(1, sizeof *m);
    if (!m) {
        log_early(log, log_callback, environment, name, "instantiate: out of memory (%zu bytes)", sizeof *m);
        return NULL;
    }
    m->log = log;
    m->log_callback = log_callback;
    m->environment = environment;
    m->debug_logging = debug_logging;
    snprintf(m->name, sizeof m->name, "%s", name ? name : "");
    if (load_defaults(m) != FMU_OK) {
        free(m);
        return NULL;
    }
    return m;
}

void fmu_free(fmu_instance *m) { free(m); }

fmu_status fmu_reset(fmu_instance *m) { return load_defaults(m); }

/* The FMI layers check the state (each function its own mask); these only move it on. */
fmu_status fmu_enter_initialization(fmu_instance *m, double start_time, double stop_time)
{
    if (start_time != 0.0)
        return fmu_log(m, FMU_ERROR, "startTime = %g s: must be 0 (the scenario starts at t = 0)", start_time);
    m->stop_step = INT64_MAX;
    if (!isnan(stop_time)) {
        if (!(stop_time >= 0.0 && stop_time <= 1e9 * m->plant.dt))
            return fmu_log(m, FMU_ERROR, "stopTime = %g s: must be a finite time from startTime = 0 s to %g s",
                           stop_time, 1e9 * m->plant.dt);
        /* the last whole step at or before stopTime (a step size rounded to 1e-6 of a step reaches it) */
        m->stop_step = (int64_t)floor(stop_time / m->plant.dt + 1e-6);
    }
    m->mode = FMU_INITIALIZATION;
    return FMU_OK;
}

fmu_status fmu_exit_initialization(fmu_instance *m)
{
    fmu_status s = setup(m);
    if (s != FMU_OK) return s;
    m->mode = FMU_STEP;
    return FMU_OK;
}

fmu_status fmu_terminate(fmu_instance *m)
{
    m->mode = FMU_TERMINATED;
    return FMU_OK;
}

/* ---- variable access */

static const fmu_variable *lookup(fmu_instance *m, const char *function, unsigned vr, fmu_type type)
{
    static const char *const type_names[] = {"Real/Float64", "Boolean"};
    if (vr >= fmu_variable_count) {
        fmu_log(m, FMU_ERROR, "%s: unknown value reference %u (this FMU has 0 to %zu)", function, vr,
                fmu_variable_count - 1);
        return NULL;
    }
    const fmu_variable *v = &fmu_variables[vr];
    if (v->type != type) {
        fmu_log(m, FMU_ERROR, "%s: value reference %u (%s) is not of type %s", function, vr, v->name,
                type_names[type]);
        return NULL;
    }
    return v;
}

/* Fixed parameters are set before the end of initialisation, tunable ones and inputs until the
 * end; nothing else. */
static fmu_status settable(fmu_instance *m, const char *function, const fmu_variable *v)
{
    unsigned before_step = FMU_IN(FMU_INSTANTIATED) | FMU_IN(FMU_INITIALIZATION);
    unsigned allowed = v->causality == FMU_PARAMETER ? before_step | (v->tunable ? FMU_IN(FMU_STEP) : 0u)
                     : v->causality == FMU_INPUT ? before_step | FMU_IN(FMU_STEP) : 0u;
    if (allowed & FMU_IN(m->mode)) return FMU_OK;
    if (!allowed)
        return fmu_log(m, FMU_ERROR, "%s: %s is an %s and cannot be set", function, v->name,
                       causality_names[v->causality]);
    return fmu_log(m, FMU_ERROR, "%s: %s (a %s) cannot be set when the instance is %s", function, v->name,
                   causality_names[v->causality], mode_names[m->mode]);
}

fmu_status fmu_get_real(fmu_instance *m, const unsigned *vr, size_t n, double *values)
{
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = lookup(m, "getReal", vr[i], FMU_REAL);
        if (!v) return FMU_ERROR;
        memcpy(&values[i], (const char *)m + v->offset, sizeof(double));
        if (!isfinite(values[i]))   /* only after a failed step; never handed out as OK */
            return fmu_log(m, FMU_ERROR, "getReal: %s = %g is not finite", v->name, values[i]);
    }
    return FMU_OK;
}

/* Every value is checked before any is written: a rejected call changes nothing. */
fmu_status fmu_set_real(fmu_instance *m, const unsigned *vr, size_t n, const double *values)
{
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = lookup(m, "setReal", vr[i], FMU_REAL);
        if (!v || settable(m, "setReal", v) != FMU_OK) return FMU_ERROR;
        if (!isfinite(values[i]) || values[i] < v->min || values[i] > v->max)
            return fmu_log(m, FMU_ERROR, "setReal: %s = %g: must be a finite number in [%g, %g]", v->name,
                           values[i], v->min, v->max);
    }
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = &fmu_variables[vr[i]];
        memcpy((char *)m + v->offset, &values[i], sizeof(double));
        if (m->mode == FMU_STEP && v->tunable) {
            m->retune = 1;
            fmu_log(m, FMU_OK, "setReal: %s = %.17g at t = %.6f s: acts from the next doStep", v->name, values[i],
                    fmu_time(m));
        }
    }
    return FMU_OK;
}

fmu_status fmu_get_boolean(fmu_instance *m, const unsigned *vr, size_t n, int *values)
{
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = lookup(m, "getBoolean", vr[i], FMU_BOOLEAN);
        if (!v) return FMU_ERROR;
        const char *where = (const char *)m + v->offset;
        if (v->size == 1) values[i] = *(const uint8_t *)where != 0;
        else values[i] = *(const int *)where != 0;
    }
    return FMU_OK;
}

fmu_status fmu_set_boolean(fmu_instance *m, const unsigned *vr, size_t n, const int *values)
{
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = lookup(m, "setBoolean", vr[i], FMU_BOOLEAN);
        if (!v || settable(m, "setBoolean", v) != FMU_OK) return FMU_ERROR;
    }
    for (size_t i = 0; i < n; ++i) {
        const fmu_variable *v = &fmu_variables[vr[i]];
        char *where = (char *)m + v->offset;
        if (v->size == 1) *(uint8_t *)where = values[i] != 0;
        else *(int *)where = values[i] != 0;
    }
    return FMU_OK;
}

/* ---- stepping */

/* A switched-on fault starts now unless its scenario start time came first. */
static void switch_faults(fmu_instance *m)
{
    double t = fmu_time(m);
    for (int i = 0; i < m->plant.n_faults; ++i)
        if (m->fault_switch[i] && m->plant.fault[i].start_time > t) {
            m->plant.fault[i].start_time = t;
            fmu_log(m, FMU_OK, "doStep: fault_%d starts at t = %.6f s", i + 1, t);
        }
}

/* One plant step, in rb_run_advance's order: demand, BCU, plant, outputs. */
static void step_once(fmu_instance *m)
{
    if (m->external_bcu) {
        m->in = m->external;
    } else {
        rb_brake_demand d = {m->emergency_demand ? 1.0 : 0.0, m->service_demand};
        if (m->scenario_demand) d = rb_scenario_demand(&m->scenario, m->out.time);
        rb_bcu_step(&m->bcu, &m->bcu_state, &d, &m->out, &m->in);
    }
    rb_plant_step(&m->plant, &m->state, &m->in);
    rb_plant_get_outputs(&m->plant, &m->state, &m->out);
    m->step++;
}

fmu_status fmu_do_step(fmu_instance *m, double t, double h)
{
    double dt = m->plant.dt;
    if (!isfinite(h) || !(h > 0.0) || h > FMU_MAX_STEP_SIZE)
        return fmu_log(m, FMU_ERROR, "doStep: communicationStepSize = %g s: must be a whole number (>= 1) of "
                       "the fixed step %g s, at most %g s", h, dt, FMU_MAX_STEP_SIZE);
    double steps = h / dt;
    int64_t n = (int64_t)llround(steps);   /* h <= FMU_MAX_STEP_SIZE: in range */
    if (n < 1 || fabs(steps - (double)n) > 1e-6)
        return fmu_log(m, FMU_ERROR, "doStep: communicationStepSize = %g s: must be a whole number (>= 1) of "
                       "the fixed step %g s", h, dt);
    if (!isfinite(t) || fabs(t - fmu_time(m)) > 1e-6 * dt)
        return fmu_log(m, FMU_ERROR, "doStep: currentCommunicationPoint = %.9g s: must equal the FMU's time "
                       "%.9g s", t, fmu_time(m));
    if (n > m->stop_step - m->step)
        return fmu_log(m, FMU_ERROR, "doStep: currentCommunicationPoint + communicationStepSize = %.9g s: passes "
                       "the stopTime %.9g s given at initialization", t + h, (double)m->stop_step * dt);
    if (m->retune) {   /* tuned parameters act from this step on, as rb_run_retune in a native run */
        rb_error err;
        if (rb_wsp_check(&m->wsp, &err) != RB_OK || rb_plant_retune_adhesion(&m->plant, &m->state, &err) != RB_OK ||
            rb_bcu_retune_wsp(&m->bcu_state, &m->wsp, &err) != RB_OK)
            return fmu_log(m, FMU_ERROR, "doStep: tuned parameters refused: %s", err.message);
        m->retune = 0;
    }
    switch_faults(m);
    for (int64_t i = 0; i < n; ++i) {
        step_once(m);
        fmu_status s = check_finite(m, "doStep");
        if (s != FMU_OK) return s;
    }
    return FMU_OK;
}

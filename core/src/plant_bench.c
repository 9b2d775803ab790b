/* The benchmarks (rb_run.h), timed with the OS clocks: rb_plant_bench, the plant alone with
 * constant inputs; rb_run_bench, what a whole run costs against its plant alone on the same
 * scenario (railbrake bench). On their own so that no other source needs an OS service: the FMU
 * leaves this file out (railbrake.fmu.export), and its sources build for any target without POSIX.
 *
 * rb_run_bench: one pass runs the scenario as `railbrake run` does (BCU, WSP, KPIs, no recording)
 * and keeps the plant's inputs of every step; a second pass steps a fresh plant through those
 * inputs and nothing else. Both are timed on the thread's CPU clock; the passes alternate so a
 * slower stretch of a shared machine hits both alike. */
#define _POSIX_C_SOURCE 199309L
#include "railbrake/rb_run.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static double clock_us(clockid_t clock)
{
    struct timespec t;
    clock_gettime(clock, &t);
    return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

/* CPU time of this thread (us): what the steps cost while they ran, without the time other
   processes of a shared machine held the core; wall-clock time where the system lacks it. */
static double cpu_us(void)
{
#ifdef CLOCK_THREAD_CPUTIME_ID
    return clock_us(CLOCK_THREAD_CPUTIME_ID);
#else
    return clock_us(CLOCK_MONOTONIC);
#endif
}

rb_status rb_plant_bench(const rb_plant_params *plant, double pressure_demand, long steps,
                         double *step_us_mean, double *step_us_p99, double *step_us_max,
                         double *step_us_wall_mean, char *kernel, size_t kernel_size, rb_error *err)
{
    enum { BINS = 10000 };         /* 0.02 us bins up to 200 us */
    long histogram[BINS + 1] = {0};
    rb_plant_state s;
    rb_plant_inputs in;
    rb_status st;
    if (steps < 1) return rb_fail(err, RB_EINVAL, "steps = %ld: must be >= 1", steps);
    if ((st = rb_plant_init(plant, &s, err))) return st;
    memset(&in, 0, sizeof in);
    for (int c = 0; c < RB_PLANT_MAX_CARS; ++c) in.pressure_demand[c] = pressure_demand;
    long warm_up = steps / 10 < 1000 ? steps / 10 : 1000;
    for (long i = 0; i < warm_up; ++i) rb_plant_step(plant, &s, &in);
    double largest = 0.0, cpu_start = cpu_us(), start = clock_us(CLOCK_MONOTONIC), last = start;
    for (long i = 0; i < steps; ++i) {   /* one clock read per step: each step's time includes one */
        rb_plant_step(plant, &s, &in);
        double now = clock_us(CLOCK_MONOTONIC), us = now - last;
        last = now;
        if (us > largest) largest = us;
        int bin = (int)(us / 0.02);
        histogram[bin < BINS ? bin : BINS]++;
    }
    double cpu = cpu_us() - cpu_start;
    long target = (long)ceil(0.99 * steps), count = 0;
    int bin = 0;
    for (; bin <= BINS && (count += histogram[bin]) < target; ++bin) {}
    *step_us_mean = cpu / steps;
    *step_us_p99 = (bin + 1) * 0.02;   /* the upper edge of the bin that holds the 99th percentile */
    if (step_us_max) *step_us_max = largest;
    if (step_us_wall_mean) *step_us_wall_mean = (last - start) / steps;
    if (kernel && kernel_size) snprintf(kernel, kernel_size, "%s", rb_plant_kernel_name(&s));
    return RB_OK;
}

/* The whole run, step by step so the plant's inputs of each step can be kept (trace != NULL). */
static rb_status whole_run(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_wsp_params *wsp,
                           const rb_scenario *sc, rb_run_state *run, rb_plant_inputs *trace, size_t max_steps,
                           size_t *steps, rb_kpis *kpis, rb_error *err)
{
    rb_status s;
    int finished = 0;
    if ((s = rb_run_init(plant, bcu, wsp, sc, run, err))) return s;
    if (!trace) {
        if ((s = rb_run_advance(plant, bcu, sc, run, sc->max_time, NULL, 0, &finished, err))) return s;
    } else {
        size_t n = 0;
        while (!finished) {
            if (n >= max_steps)
                return rb_fail(err, RB_ESIZE, "max_steps = %zu: the run needs more steps", max_steps);
            if ((s = rb_run_advance(plant, bcu, sc, run, run->out.time + 0.5 * plant->dt, NULL, 0, &finished, err)))
                return s;
            trace[n++] = run->in;
        }
        *steps = n;
    }
    rb_run_kpis(plant, run, kpis);
    return RB_OK;
}

static rb_status plant_alone(const rb_plant_params *plant, rb_plant_state *state, const rb_plant_inputs *trace,
                             size_t steps, rb_error *err)
{
    rb_status s;
    if ((s = rb_plant_init(plant, state, err))) return s;
    for (size_t i = 0; i < steps; ++i) rb_plant_step(plant, state, &trace[i]);
    return RB_OK;
}

rb_status rb_run_bench(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_wsp_params *wsp,
                       const rb_scenario *sc, int repeats, rb_run_state *run, rb_plant_inputs *trace,
                       size_t max_steps, rb_run_bench_result *result, rb_error *err)
{
    rb_status s;
    rb_kpis kpis;
    if (!run || !trace || !result) return rb_fail(err, RB_EINVAL, "run, trace and result must not be NULL");
    if (repeats < 1 || repeats > 1000) return rb_fail(err, RB_EINVAL, "repeats = %d: must be in [1, 1000]", repeats);
    memset(result, 0, sizeof *result);
    size_t steps = 0;
    if ((s = whole_run(plant, bcu, wsp, sc, run, trace, max_steps, &steps, &kpis, err))) return s;
    if (steps == 0) return rb_fail(err, RB_EINVAL, "the scenario ends before its first step");
    result->steps = (double)steps;
    result->run_us = result->plant_us = HUGE_VAL;
    for (int i = 0; i < repeats; ++i) {
        double t0 = cpu_us();
        if ((s = whole_run(plant, bcu, wsp, sc, run, NULL, 0, NULL, &kpis, err))) return s;
        double t1 = cpu_us();
        if ((s = plant_alone(plant, &run->plant, trace, steps, err))) return s;
        double t2 = cpu_us();
        if (t1 - t0 < result->run_us) result->run_us = t1 - t0;
        if (t2 - t1 < result->plant_us) result->plant_us = t2 - t1;
    }
    result->run_us /= (double)steps;
    result->plant_us /= (double)steps;
    snprintf(result->kernel, sizeof result->kernel, "%s", rb_plant_kernel_name(&run->plant));
    return RB_OK;
}

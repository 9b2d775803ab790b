/* The plant benchmark (rb_plant_bench, rb_run.h): the plant alone, timed with the OS clocks.
 * On its own so that no other source needs an OS service: the FMU leaves this file out
 * (railbrake.fmu.export), and its sources build for any target without POSIX. */
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

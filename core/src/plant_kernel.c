/* The wheelset kernel: the wheelsets over one step: torque balance J dw/dt = -F r - T_brake - T_ed with Polach adhesion
 * F = Q f(creep), the slip velocity advanced linearly implicitly with the secant creep stiffness
 * (stable at 1 ms down to walking speed), a wheel whose speed would change sign locked (static pad
 * friction).
 *
 * The axles go through branch-free passes (which a compiler turns into 4-lane vector code, exp and
 * atan included: rb_exp_nonpos, rb_atan_nonneg in rb_common.h) around the scalar pad-table look-up. The same source is compiled twice: portable (the reference, C99) and, on x86
 * with GCC or Clang, for AVX2 (selected at run time, rb_plant_resolve_kernel). Both do the same IEEE
 * operations in the same order (no fused multiply-add: AVX2 alone does not enable it, and ISO C mode
 * does not contract), so their results are equal bit for bit (core/tests/test_plant_kernel.c).
 * core/CMakeLists.txt compiles this file with -fno-trapping-math (both arms of a select may be
 * computed: no value changes) and the dynamic vectoriser cost model; without them (e.g. the FMU's
 * own build) the results are the same, only scalar. */
#include "plant_internal.h"

#include <float.h>
#include <math.h>


#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#if defined(__GNUC__) || defined(__clang__)
#define RB_ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#define RB_ALWAYS_INLINE static inline
#endif

#define NA RB_AXLES_PER_CAR

/* Polach's coefficient of axle a at a creep and speed, with the constants of rb_plant_derived
   (rb_polach_coefficient_fast's law, contact_polach.c). */
RB_ALWAYS_INLINE double polach(const rb_plant_derived *d, int a, double creep, double speed)
{
    double abs_creep = fabs(creep);
    double mu = d->mu_slip[a] * rb_exp_nonpos(-d->polach_B[a] * (abs_creep * speed)) + d->mu_static[a];
    double eps = d->polach_gain[a / NA] * abs_creep / mu;
    double ka_eps = d->polach_kA[a] * eps;
    double f = mu * (2.0 / M_PI) * (ka_eps / (1.0 + ka_eps * ka_eps) + rb_atan_nonneg(d->polach_kS[a] * eps));
    return creep < 0.0 ? -f : f;
}

/* Pad friction coefficient of axle a at wheel speed `speed` from its car's table, as
   rb_speed_table_at_from; it caches the interval the speed falls in, with its spans
   (rb_plant_derived), for the kernel's own interpolation, the same operations in the same order:
   inside the table speed[lo] <= speed < speed[lo + 1]; below it [-DBL_MAX, speed[0]) and above it
   [speed[n - 1], inf), each with value span 0 (value[0] or value[n - 1] + 0). Inlined into each
   kernel, so the vector one never calls code of another instruction set. */
RB_ALWAYS_INLINE double pad_lookup(const rb_speed_table *t, rb_plant_derived *d, int a, double speed)
{
    double value = rb_speed_table_at_from(t, speed, &d->pad_bracket[a]);
    int n = t->n;
    if (n < 1) return value;
    if (speed < t->speed[0]) {
        d->pad_speed_lo[a] = -DBL_MAX;
        d->pad_speed_hi[a] = t->speed[0];
        d->pad_value_lo[a] = t->value[0];
        d->pad_speed_span[a] = 1.0;
        d->pad_value_span[a] = 0.0;
    } else if (speed >= t->speed[n - 1]) {
        d->pad_speed_lo[a] = t->speed[n - 1];
        d->pad_speed_hi[a] = HUGE_VAL;
        d->pad_value_lo[a] = t->value[n - 1];
        d->pad_speed_span[a] = 1.0;
        d->pad_value_span[a] = 0.0;
    } else {
        int lo = d->pad_bracket[a], hi = lo + 1;
        d->pad_speed_lo[a] = t->speed[lo];
        d->pad_speed_hi[a] = t->speed[hi];
        d->pad_speed_span[a] = t->speed[hi] - t->speed[lo];
        d->pad_value_lo[a] = t->value[lo];
        d->pad_value_span[a] = t->value[hi] - t->value[lo];
    }
    return value;
}

/* Working arrays of one pass over the train. */
typedef struct {
    double w[RB_PLANT_MAX_AXLES], abs_probe[RB_PLANT_MAX_AXLES], ex[RB_PLANT_MAX_AXLES];
    double wheel[RB_PLANT_MAX_AXLES], pad[RB_PLANT_MAX_AXLES], friction[RB_PLANT_MAX_AXLES];
    double f[RB_PLANT_MAX_AXLES], omega[RB_PLANT_MAX_AXLES], force[RB_PLANT_MAX_AXLES];
} pass_arrays;

RB_ALWAYS_INLINE void wheelsets(const rb_plant_params *p, rb_plant_state *s, const rb_wheelset_inputs *in,
                                const double *cylinder, double dt)
{
    rb_plant_derived *d = &s->derived;
    const int n = p->n_cars * NA;
    pass_arrays x;

    /* slip velocity, the probe creep of the secant stiffness, the falling friction's exponential,
       the pad friction in each axle's cached interval */
    for (int a = 0; a < n; ++a) {
        const double v = in->speed[a];
        x.w[a] = s->omega[a] * d->axle_radius[a] - v;
        double creep = fabs(x.w[a] * in->inv_creep_speed[a]);
        x.abs_probe[a] = creep > 1e-7 ? creep : 1e-7;
        x.ex[a] = rb_exp_nonpos(-d->polach_B[a] * (x.abs_probe[a] * v));
        x.wheel[a] = s->omega[a] * d->axle_radius[a];
        x.pad[a] = d->pad_value_lo[a] + ((x.wheel[a] - d->pad_speed_lo[a]) / d->pad_speed_span[a]) * d->pad_value_span[a];
    }
    for (int a = 0; a < n; ++a)   /* outside the cached interval (rarely): the table */
        if (!(x.wheel[a] >= d->pad_speed_lo[a] && x.wheel[a] < d->pad_speed_hi[a]))
            x.pad[a] = pad_lookup(&p->car[a / NA].vehicle.brake.pad.table, d, a, x.wheel[a]);
    /* Polach's coefficient at the probe creep (its own pass: short dependency chains, so the
       processor overlaps many axles) */
    for (int a = 0; a < n; ++a) {
        double mu = d->mu_slip[a] * x.ex[a] + d->mu_static[a];
        double eps = d->axle_polach_gain[a] * x.abs_probe[a] / mu;
        double ka_eps = d->polach_kA[a] * eps;
        x.f[a] = mu * (2.0 / M_PI) * (ka_eps / (1.0 + ka_eps * ka_eps) + rb_atan_nonneg(d->polach_kS[a] * eps));
    }
    for (int a = 0; a < n; ++a) {
        const double r = d->axle_radius[a], inv_J = d->axle_inv_inertia[a], f = x.f[a];
        double stiffness = d->axle_axle_load[a] * (f / x.abs_probe[a]) * in->inv_creep_speed[a];  /* N per m/s */
        /* rb_axle_brake_torque (vehicle_brake.c) with its constant factors in brake_gain */
        double piston = (cylinder[a] - d->axle_caliper_atmosphere[a]) * d->axle_caliper_area[a] - d->axle_caliper_spring[a];
        double friction = d->axle_brake_gain[a] * x.pad[a] * (piston > 0.0 ? piston : 0.0);
        x.friction[a] = friction;
        double torque = friction + in->ed_torque[a];
        /* slip velocity, linearly implicit in this axle's own rail force */
        double others = in->others[a] - s->force[a];
        double w_new = (x.w[a] + dt * (-r * torque * inv_J - others * d->axle_inv_mass[a])) /
                       (1.0 + dt * stiffness * d->axle_compliance[a]);
        x.force[a] = stiffness * w_new;
        x.omega[a] = s->omega[a] + dt * (-x.force[a] * r - torque) * inv_J;
    }
    for (int a = 0; a < n; ++a) {
        if (x.omega[a] < 0.0) {   /* pads hold the wheel: locked, sliding at the train speed */
            double creep = -in->speed[a] * in->inv_creep_speed[a];
            /* a wheel locked already was probed at that very creep: the same coefficient */
            double f = s->omega[a] == 0.0 && x.abs_probe[a] == -creep ? -x.f[a] : polach(d, a, creep, in->speed[a]);
            x.omega[a] = 0.0;
            x.force[a] = d->axle_axle_load[a] * f;
        }
    }
    for (int a = 0; a < n; ++a) {
        s->omega[a] = x.omega[a];
        s->force[a] = x.force[a];
        s->coefficient[a] = x.force[a] * d->axle_inv_axle_load[a];   /* an output only */
        s->brake_torque[a] = x.friction[a];   /* for the discs' energy (plant_train.c) */
    }
}

static void wheelsets_portable(const rb_plant_params *p, rb_plant_state *s, const rb_wheelset_inputs *in,
                               const double *cylinder, double dt)
{
    wheelsets(p, s, in, cylinder, dt);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2")))
static void wheelsets_avx2(const rb_plant_params *p, rb_plant_state *s, const rb_wheelset_inputs *in,
                           const double *cylinder, double dt)
{
    wheelsets(p, s, in, cylinder, dt);
}
#endif

void rb_plant_wheelsets(const rb_plant_params *p, rb_plant_state *s, const rb_wheelset_inputs *in,
                        const double *cylinder, double dt)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) {
        wheelsets_avx2(p, s, in, cylinder, dt);
        return;
    }
#endif
    wheelsets_portable(p, s, in, cylinder, dt);
}


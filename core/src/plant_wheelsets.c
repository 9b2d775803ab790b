/* The wheelsets of one car over one step: torque balance J dw/dt = -F r - T_brake - T_ed with
 * Polach adhesion F = Q f(creep), the slip velocity advanced linearly implicitly with the secant
 * creep stiffness (stable at 1 ms down to walking speed), a wheel whose speed would change sign
 * locked (static pad friction).
 *
 * The car's 4 axles go through branch-free passes over arrays of 4 (which a compiler turns into
 * 4-lane vector code, atan included: rb_atan_nonneg) around the scalar libm exp and the pad-table
 * look-up, which every kernel shares. The
 * same source is compiled twice: portable (the reference, C99) and, on x86 with GCC or Clang, for
 * AVX2 (selected at run time, rb_plant_resolve_kernel). Both do the same IEEE operations in the same
 * order (no fused multiply-add: AVX2 alone does not enable it, and ISO C mode does not contract), so
 * their results are equal bit for bit (core/tests/test_plant_kernel.c). */
#include "plant_internal.h"

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

/* Polach's coefficient of axle a (car c) at a creep and speed, with the constants of
   rb_plant_derived (rb_polach_coefficient_fast's law, contact_polach.c). */
static double polach(const rb_plant_derived *d, int c, int a, double creep, double speed)
{
    double abs_creep = fabs(creep);
    double mu = d->mu_slip[a] * exp(-d->polach_B[a] * (abs_creep * speed)) + d->mu_static[a];
    double eps = d->polach_gain[c] * abs_creep / mu;
    double ka_eps = d->polach_kA[a] * eps;
    double f = mu * (2.0 / M_PI) * (ka_eps / (1.0 + ka_eps * ka_eps) + rb_atan_nonneg(d->polach_kS[a] * eps));
    return creep < 0.0 ? -f : f;
}

RB_ALWAYS_INLINE double wheelsets(const rb_plant_params *p, rb_plant_state *s, int c, double other_force,
                                  int ed_lost, const double *cylinder, double dt)
{
    rb_plant_derived *d = &s->derived;
    const rb_axle_brake *brake = &p->car[c].vehicle.brake;
    const rb_caliper *caliper = &brake->caliper;
    const int a0 = c * NA;
    const double r = d->radius[c], inv_J = d->inv_inertia[c], inv_mass = d->inv_mass[c];
    const double axle_load = d->axle_load[c], compliance = d->compliance[c], gain = d->polach_gain[c];
    const double v = s->v[c], vr = v > p->creep_speed_min ? v : p->creep_speed_min, inv_vr = 1.0 / vr;
    const double ed_axle = ed_lost ? 0.0 : s->ed_force[c] / NA * r;
    const double brake_gain = d->brake_gain[c];
    double old_sum = 0.0;
    for (int k = 0; k < NA; ++k) old_sum += s->force[a0 + k];
    const double others_all = other_force + old_sum;
    double w[NA], abs_probe[NA], ex[NA], pad[NA], mu[NA], eps[NA], at[NA], omega[NA], force[NA];

    /* slip velocity, the probe creep of the secant stiffness, exponent of the falling friction */
    for (int k = 0; k < NA; ++k) {
        w[k] = s->omega[a0 + k] * r - v;
        double creep = w[k] * inv_vr;
        abs_probe[k] = fabs(creep) > 1e-7 ? fabs(creep) : 1e-7;
        ex[k] = -d->polach_B[a0 + k] * (abs_probe[k] * v);
    }
    for (int k = 0; k < NA; ++k) {
        ex[k] = exp(ex[k]);
        pad[k] = rb_speed_table_at_from(&brake->pad.table, s->omega[a0 + k] * r, &d->pad_bracket[a0 + k]);
    }
    for (int k = 0; k < NA; ++k) {
        mu[k] = d->mu_slip[a0 + k] * ex[k] + d->mu_static[a0 + k];
        eps[k] = gain * abs_probe[k] / mu[k];
        at[k] = rb_atan_nonneg(d->polach_kS[a0 + k] * eps[k]);
    }
    for (int k = 0; k < NA; ++k) {
        double ka_eps = d->polach_kA[a0 + k] * eps[k];
        double f = mu[k] * (2.0 / M_PI) * (ka_eps / (1.0 + ka_eps * ka_eps) + at[k]);
        double stiffness = axle_load * (f / abs_probe[k]) * inv_vr;   /* secant, N per m/s of slip */
        /* rb_axle_brake_torque (vehicle_brake.c) with its constant factors in brake_gain */
        double piston = (cylinder[a0 + k] - caliper->atmospheric_pressure) * caliper->cylinder_area
                        - caliper->return_spring;
        double torque = brake_gain * pad[k] * (piston > 0.0 ? piston : 0.0) + ed_axle;
        /* slip velocity, linearly implicit in this axle's own rail force */
        double others = others_all - s->force[a0 + k];
        double w_new = (w[k] + dt * (-r * torque * inv_J - others * inv_mass)) / (1.0 + dt * stiffness * compliance);
        force[k] = stiffness * w_new;
        omega[k] = s->omega[a0 + k] + dt * (-force[k] * r - torque) * inv_J;
    }
    double sum = 0.0;
    for (int k = 0; k < NA; ++k) {
        int a = a0 + k;
        if (omega[k] < 0.0) {   /* pads hold the wheel: locked, sliding at the train speed */
            omega[k] = 0.0;
            force[k] = axle_load * polach(d, c, a, -v * inv_vr, v);
        }
        s->omega[a] = omega[k];
        s->force[a] = force[k];
        s->coefficient[a] = force[k] / axle_load;
        sum += force[k];
    }
    return sum;
}

static double wheelsets_portable(const rb_plant_params *p, rb_plant_state *s, int c, double other_force,
                                 int ed_lost, const double *cylinder, double dt)
{
    return wheelsets(p, s, c, other_force, ed_lost, cylinder, dt);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2")))
static double wheelsets_avx2(const rb_plant_params *p, rb_plant_state *s, int c, double other_force,
                             int ed_lost, const double *cylinder, double dt)
{
    return wheelsets(p, s, c, other_force, ed_lost, cylinder, dt);
}
#endif

double rb_plant_car_wheelsets(const rb_plant_params *p, rb_plant_state *s, int c, double other_force,
                              int ed_lost, const double *cylinder, double dt)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) return wheelsets_avx2(p, s, c, other_force, ed_lost, cylinder, dt);
#endif
    return wheelsets_portable(p, s, c, other_force, ed_lost, cylinder, dt);
}

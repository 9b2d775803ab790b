/* The wheelset kernel: the wheelsets over one step: torque balance J dw/dt = -F r - T_brake - T_ed with Polach adhesion
 * F = Q f(creep), the slip velocity advanced linearly implicitly with the secant creep stiffness,
 * probed at the slip the step ends near (stable at 1 ms down to walking speed), a wheel whose speed
 * would change sign locked (static pad friction).
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
#include <stdint.h>
#include <string.h>


#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#ifndef M_LN10
#define M_LN10 2.30258509299404568402
#endif

#if defined(__GNUC__) || defined(__clang__)
#define RB_ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#define RB_ALWAYS_INLINE static inline
#endif

#define NA RB_AXLES_PER_CAR

/* Polach's coefficient (its magnitude) at friction coefficient mu and probe creep |creep|, with the
   axle's constants: 2 mu / pi (k_A eps / (1 + (k_A eps)^2) + atan(k_S eps)), eps = gain |creep| / mu
   (rb_polach_coefficient_fast's law, contact_polach.c), written without eps: with K = k_A gain
   |creep|, the first fraction is K mu / (mu^2 + K^2), and the arc tangent that of k_S gain |creep|
   over mu (rb_atan_ratio_parts); the two are added as one fraction: two divisions in all, neither
   waiting on the other's. */
RB_ALWAYS_INLINE double polach_magnitude(double mu, double abs_creep, double kA_gain, double kS_gain)
{
    double k = kA_gain * abs_creep, k_den = mu * mu + k * k, base, num, den;
    rb_atan_ratio_parts(kS_gain * abs_creep, mu, &base, &num, &den);
    return mu * (2.0 / M_PI) * (base + (num * k_den + k * mu * den) / (den * k_den));
}

/* Polach's coefficient at a creep and speed with an axle's constants (rb_plant_derived's): the
   kernel's own passes' operations, in their order. */
RB_ALWAYS_INLINE double polach_law(double mu_slip, double mu_static, double B, double kA_gain, double kS_gain,
                                   double creep, double speed)
{
    double abs_creep = fabs(creep);
    double mu = mu_slip * rb_exp_nonpos(-B * (abs_creep * speed)) + mu_static;
    double f = polach_magnitude(mu, abs_creep, kA_gain, kS_gain);
    return creep < 0.0 ? -f : f;
}

/* Polach's coefficient of axle a at a creep and speed. */
RB_ALWAYS_INLINE double polach(const rb_plant_derived *d, int a, double creep, double speed)
{
    return polach_law(d->mu_slip[a], d->mu_static[a], d->polach_B[a], d->polach_kA_gain[a], d->polach_kS_gain[a],
                      creep, speed);
}

/* Pad friction coefficient of axle a at wheel speed `speed` from its car's table; caches the
   table's interval there (rb_plant_table_interval) for the kernel's own interpolation. Inlined into
   each kernel, so the vector one never calls code of another instruction set. */
RB_ALWAYS_INLINE double pad_lookup(const rb_speed_table *t, rb_plant_derived *d, int a, double speed)
{
    rb_plant_table_interval(t, speed, &d->pad_bracket[a], &d->pad_speed_lo[a], &d->pad_speed_hi[a],
                            &d->pad_value_lo[a], &d->pad_slope[a]);
    return d->pad_value_lo[a] + (speed - d->pad_speed_lo[a]) * d->pad_slope[a];
}

/* Working arrays of one pass over the train. */
typedef struct {
    double abs_probe[RB_PLANT_MAX_AXLES], mu[RB_PLANT_MAX_AXLES];
    double pad[RB_PLANT_MAX_AXLES], f[RB_PLANT_MAX_AXLES];
} pass_arrays;

RB_ALWAYS_INLINE void wheelsets(const rb_plant_params *p, rb_plant_state *restrict s,
                                const rb_wheelset_inputs *restrict in, const double *restrict cylinder, double dt)
{
    rb_plant_derived *d = &s->derived;
    const int n = p->n_cars * NA;
    pass_arrays x;
    int64_t outside = 0, locking = 0;   /* sign bits ORed over the axles (rb_plant_sign_bits) */

    /* slip velocity, the probe creep of the secant stiffness, the falling friction coefficient, the
       pad friction in each axle's cached interval (and whether any axle left its interval).
       The probe is the slip the update will end near: the start's slip plus the last update's change.
       The secant through it is then the line through the point the linearly implicit update solves
       for; probed at the start's slip, the rail force lags a moving slip by a step, and on wet rail,
       where WSP keeps the slip moving, the 1 ms plant braked about 0.13 % harder than at 0.1 ms
       (docs/detailed.md). Whatever the probe, the secant stiffness is >= 0: the update stays stable.
       (slip_probe_ahead 0, the detailed model's, gives the start's slip exactly.) */
    for (int a = 0; a < n; ++a) {
        const double v = in->speed[a], wheel = s->omega[a] * d->axle_radius[a];
        const double slip = wheel - v, probe = slip + d->slip_probe_ahead * (slip - s->slip_start[a]);
        s->slip_start[a] = slip;
        double creep = fabs(probe * in->inv_creep_speed[a]);
        x.abs_probe[a] = creep > 1e-7 ? creep : 1e-7;
        x.mu[a] = d->mu_slip[a] * rb_exp_nonpos(-d->polach_B[a] * (x.abs_probe[a] * v)) + d->mu_static[a];
        x.pad[a] = d->pad_value_lo[a] + (wheel - d->pad_speed_lo[a]) * d->pad_slope[a];
        outside |= rb_plant_sign_bits(wheel - d->pad_speed_lo[a]) | ~rb_plant_sign_bits(wheel - d->pad_speed_hi[a]);
    }
    if (outside < 0)   /* rarely: the table */
        for (int a = 0; a < n; ++a) {
            const double wheel = s->omega[a] * d->axle_radius[a];
            if (!(wheel >= d->pad_speed_lo[a] && wheel < d->pad_speed_hi[a]))
                x.pad[a] = pad_lookup(&p->car[a / NA].vehicle.brake.pad.table, d, a, wheel);
        }
    /* the pads' heat fading at the friction surface's temperature of the last step (rb_pad_friction:
       a factor of exactly 1 below the onset or without fading) */
    for (int a = 0; a < n; ++a) {
        const double hot = s->disc_temperature[a] - d->pad_fade_onset[a];
        x.pad[a] = x.pad[a] / (1.0 + d->pad_fade_rate[a] * (hot > 0.0 ? hot : 0.0));
        s->pad_friction[a] = x.pad[a];
    }
    /* Polach's coefficient at the probe creep (its own pass: short dependency chains, so the
       processor overlaps many axles) */
    for (int a = 0; a < n; ++a)
        x.f[a] = polach_magnitude(x.mu[a], x.abs_probe[a], d->polach_kA_gain[a], d->polach_kS_gain[a]);
    for (int a = 0; a < n; ++a) {   /* the new state, straight into s (restrict: nothing else is s) */
        const double r = d->axle_radius[a], inv_J = d->axle_inv_inertia[a];
        /* rb_axle_brake_torque (vehicle_brake.c) with its constant factors merged (rb_plant_derived) */
        double push = cylinder[a] * d->axle_brake_per_pa[a] - d->axle_brake_offset[a];
        double friction = x.pad[a] * (push > 0.0 ? push : 0.0);
        double torque = friction + in->ed_torque[a];
        /* slip velocity, linearly implicit in this axle's own rail force F = k w with the secant
           stiffness k = K f / |probe| (N per m/s), K = Q / max(v, v_min): w_new = w_free / (1 + dt
           compliance k), so F = K f w_free / (|probe| + dt compliance K f), one division */
        double others = in->others[a] - s->force[a];
        double w = s->omega[a] * r - in->speed[a];   /* the slip velocity of the first pass */
        double w_free = w + dt * (-r * torque * inv_J - others * d->axle_inv_mass[a]);
        double kf = d->axle_axle_load[a] * in->inv_creep_speed[a] * x.f[a];
        double force = kf * w_free / (x.abs_probe[a] + dt * d->axle_compliance[a] * kf);
        double omega = s->omega[a] + dt * (-force * r - torque) * inv_J;
        s->omega[a] = omega;
        s->force[a] = force;
        s->coefficient[a] = force * d->axle_inv_axle_load[a];   /* an output only */
        s->brake_torque[a] = friction;   /* for the discs' energy (plant_train.c) */
        locking |= rb_plant_sign_bits(omega);   /* also -0 or a NaN: the loop below checks */
    }
    if (locking < 0)
        for (int a = 0; a < n; ++a) {
            if (s->omega[a] < 0.0) {   /* pads hold the wheel: locked, sliding at the train speed */
                double creep = -in->speed[a] * in->inv_creep_speed[a];
                /* probed at that very creep (a wheel locked already): the pass's coefficient, which
                   polach() would compute again from the same operands */
                double f = x.abs_probe[a] == -creep ? -x.f[a] : polach(d, a, creep, in->speed[a]);
                s->omega[a] = 0.0;
                s->force[a] = d->axle_axle_load[a] * f;
                s->coefficient[a] = s->force[a] * d->axle_inv_axle_load[a];
            }
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

double rb_plant_polach(const rb_plant_state *s, int axle, double creep, double speed)
{
    return polach(&s->derived, axle, creep, speed);
}

/* Axle a's Polach curve as the kernel applies it (polach), at its car's speed: the available
   adhesion the run samples is the peak of the very curve the wheelset brakes on. Its creeps 10^x
   (x <= 0) by rb_exp_nonpos and the law's own inline exponential and arc tangent make it some
   three times cheaper than rb_polach_coefficient_fast's library calls; the two agree to
   rounding (core/tests/test_run.c compares the run's means with rb_polach_peak's). */
typedef struct {
    const rb_plant_derived *d;
    int axle, avx2;   /* avx2: the state's kernel is the AVX2 one */
    double speed;
} axle_curve;

RB_ALWAYS_INLINE double axle_curve_law(const axle_curve *k, double log_creep)
{
    return polach(k->d, k->axle, rb_exp_nonpos(log_creep * M_LN10), k->speed);
}

static double axle_curve_at(const void *curve, double log_creep)
{
    return axle_curve_law(curve, log_creep);
}

/* The scan's points in one vector loop, in the kernel's build (as the wheelsets): the same values. */
RB_ALWAYS_INLINE void axle_curve_scan(const axle_curve *k, const double *restrict log_creep, double *restrict f, int n)
{
    for (int i = 0; i < n; ++i) f[i] = axle_curve_law(k, log_creep[i]);
}

static void axle_curve_scan_portable(const axle_curve *k, const double *log_creep, double *f, int n)
{
    axle_curve_scan(k, log_creep, f, n);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2")))
static void axle_curve_scan_avx2(const axle_curve *k, const double *log_creep, double *f, int n)
{
    axle_curve_scan(k, log_creep, f, n);
}
#endif

static void axle_curve_at_many(const void *curve, const double *log_creep, double *f, int n)
{
    const axle_curve *k = curve;
#if RB_PLANT_HAVE_AVX2
    if (k->avx2) {
        axle_curve_scan_avx2(k, log_creep, f, n);
        return;
    }
#endif
    axle_curve_scan_portable(k, log_creep, f, n);
}

/* Several axles' curves, each at its own point, in one vector loop: their constants gathered into
   arrays first (rb_creep_peaks_track's rounds). */
RB_ALWAYS_INLINE void axle_curves_each(const rb_creep_curve *curves, const int *member, const double *log_creep,
                                       double *f, int n)
{
    double mu_slip[RB_CREEP_BATCH * 2], mu_static[RB_CREEP_BATCH * 2], B[RB_CREEP_BATCH * 2];
    double kA[RB_CREEP_BATCH * 2], kS[RB_CREEP_BATCH * 2], speed[RB_CREEP_BATCH * 2];
    for (int j = 0; j < n; ++j) {
        const axle_curve *k = curves[member[j]].curve;
        const int a = k->axle;
        mu_slip[j] = k->d->mu_slip[a]; mu_static[j] = k->d->mu_static[a]; B[j] = k->d->polach_B[a];
        kA[j] = k->d->polach_kA_gain[a]; kS[j] = k->d->polach_kS_gain[a]; speed[j] = k->speed;
    }
    for (int j = 0; j < n; ++j)
        f[j] = polach_law(mu_slip[j], mu_static[j], B[j], kA[j], kS[j], rb_exp_nonpos(log_creep[j] * M_LN10), speed[j]);
}

static void axle_curves_each_portable(const rb_creep_curve *curves, const int *member, const double *log_creep,
                                      double *f, int n)
{
    axle_curves_each(curves, member, log_creep, f, n);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2")))
static void axle_curves_each_avx2(const rb_creep_curve *curves, const int *member, const double *log_creep,
                                  double *f, int n)
{
    axle_curves_each(curves, member, log_creep, f, n);
}
#endif

/* Axle a's curve at its car's speed (a vehicle standing: 0). */
static rb_creep_curve axle_curve_of(const rb_plant_state *s, int axle, axle_curve *k)
{
    const rb_plant_derived *d = &s->derived;
    double v = s->v[axle / NA];
    k->d = d;
    k->axle = axle;
    k->avx2 = s->kernel == RB_PLANT_KERNEL_AVX2;
    k->speed = v > 0.0 ? v : 0.0;
    rb_creep_curve f = {axle_curve_at, axle_curve_at_many, k,
                        d->mu_slip[axle] * rb_exp_nonpos(-d->polach_B[axle] * k->speed) + d->mu_static[axle]};
    return f;
}

double rb_plant_peak_adhesion_track(const rb_plant_params *p, const rb_plant_state *s, int axle, double *log_creep,
                                    int *maxima)
{
    axle_curve k;
    rb_creep_curve f = axle_curve_of(s, axle, &k);
    (void)p;
    return maxima ? rb_creep_peak_scan(&f, log_creep, maxima) : rb_creep_peak_track(&f, log_creep);
}

void rb_plant_peaks_track(const rb_plant_params *p, const rb_plant_state *s, const int *axles, int n,
                          double *log_creep, double *peak)
{
    axle_curve k[RB_PLANT_MAX_AXLES];
    rb_creep_curve f[RB_PLANT_MAX_AXLES];
    (void)p;
    for (int i = 0; i < n; ++i) f[i] = axle_curve_of(s, axles[i], &k[i]);
    rb_creep_at_each each = axle_curves_each_portable;
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) each = axle_curves_each_avx2;
#endif
    rb_creep_peaks_track(f, n, each, log_creep, peak);
}

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


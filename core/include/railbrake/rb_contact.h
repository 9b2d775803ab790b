/* Wheel-rail contact: Hertz ellipse, Kalker's linear-theory coefficients and
 * Polach's creep-force model.
 *
 * Sources (bibliography: docs/references.md):
 *  - Hertz: K. L. Johnson, Contact Mechanics (1985), ch. 4, eqs. (4.39)-(4.41).
 *  - Kalker: J. J. Kalker, Three-dimensional elastic bodies in rolling contact (1990), Table E.3.
 *  - Polach: O. Polach, Wear 258 (2005) 992-1000, eqs. for F, eps and mu(w). */
#ifndef RAILBRAKE_CONTACT_H
#define RAILBRAKE_CONTACT_H

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Hertz contact ellipse. a: semi-axis in the rolling (x) direction, b: lateral (y). */
typedef struct {
    double a;               /* m */
    double b;               /* m */
    double p0;              /* peak pressure, Pa */
    double normal_force;    /* N */
    double youngs_modulus;  /* Pa, both bodies */
    double poisson;         /* -, both bodies */
    double shear_modulus;   /* Pa, E / (2 (1 + nu)) */
} rb_hertz;

/* Complete elliptic integrals K(e), E(e) of modulus e (0 <= e < 1) and the
 * difference K - E computed without cancellation; by the arithmetic-geometric mean. */
void rb_elliptic_ke(double e, double *K, double *E, double *K_minus_E);

/* Hertz contact of two bodies of the same material under normal_force.
 * rx, ry: radii of relative curvature in the rolling and lateral directions,
 * 1/r = sum of the two bodies' curvatures (convex positive). Both must be finite and > 0. */
rb_status rb_hertz_contact(double normal_force, double rx, double ry, double youngs_modulus,
                           double poisson, rb_hertz *out, rb_error *err);

/* Kalker coefficient of the linear theory; which: 11, 22 or 23.
 * Linear in a/b inside Table E.3, quadratic in poisson (on 1/C), asymptotes outside. */
rb_status rb_kalker(int which, double a_over_b, double poisson, double *out, rb_error *err);

/* Polach's five parameters, and an optional rolling-speed factor on mu0 (wet rail: the water film
 * between wheel and rail thickens with rolling speed, so the friction falls with the train speed v
 * itself, not only with the slip velocity w):
 *     mu(v, w) = mu0 / (1 + v v_ref_inv) * ((1 - A) exp(-B w) + A).
 * v_ref_inv = 0 (v_ref infinite) is Polach's law, bit for bit (the factor is exactly 1). The rolling
 * speed is taken as the train speed: the wheel's differs by the slip velocity, the contact's
 * entrainment speed by half of it. */
typedef struct {
    double mu0;  /* maximum friction coefficient (at zero slip velocity; at standstill with v_ref_inv) */
    double A;    /* ratio of the friction at infinite slip velocity to mu0, 0..1 */
    double B;    /* exponential friction decrease rate, s/m */
    double kA;   /* reduction of Kalker's slope in the area of adhesion, (0, 1] */
    double kS;   /* reduction of Kalker's slope in the area of slip, (0, 1] */
    double v_ref_inv;  /* 1 / v_ref, s/m: rolling speed at which mu0 is halved, inverted; 0: none */
} rb_polach_params;

/* The rolling-speed factor 1 / (1 + v v_ref_inv) on mu0 at train speed v (m/s, >= 0): exactly 1
 * with v_ref_inv = 0. */
double rb_polach_rolling_factor(double speed, double v_ref_inv);

/* What the creep-force law needs of a contact. */
typedef struct {
    double a, b;           /* Hertz semi-axes, m */
    double c11;            /* Kalker coefficient */
    double shear_modulus;  /* Pa */
} rb_creep_contact;

rb_status rb_polach_check(const rb_polach_params *p, rb_error *err);
rb_status rb_creep_contact_check(const rb_creep_contact *c, rb_error *err);

/* F/Q for one creep (any sign; braking is negative) at train speed (m/s, >= 0).
 * No argument checks: for inner loops once the inputs are validated. */
double rb_polach_coefficient_fast(double creep, double speed, double normal_force,
                                  const rb_creep_contact *c, const rb_polach_params *p);

/* Checked, array form: out[i] = F/Q(creep[i], speed[i]). */
rb_status rb_polach_coefficient(const double *creep, const double *speed, size_t n,
                                double normal_force, const rb_creep_contact *c,
                                const rb_polach_params *p, double *out, rb_error *err);

/* Maximum of F/Q over creep in (0, 1] at one speed, and the creep where it occurs. */
rb_status rb_polach_peak(double speed, double normal_force, const rb_creep_contact *c,
                         const rb_polach_params *p, double *peak_coefficient,
                         double *peak_creep, rb_error *err);

/* A creep-force curve F at one speed for the peak searches below: at(curve, x) is F at creep 10^x
 * (x in [-7, 0]); at_many, where not NULL, the same for n such x at once (the whole search's scan:
 * a vector loop); mu_full_slip the friction coefficient at creep 1, which bounds F there
 * (F <= mu (1 + 1/pi)). Polach's law of rb_polach_coefficient_fast is one; the plant samples the
 * one its wheelset kernel applies (rb_plant_peak_adhesion_track). */
typedef struct {
    double (*at)(const void *curve, double log_creep);
    void (*at_many)(const void *curve, const double *log_creep, double *f, int n);
    const void *curve;
    double mu_full_slip;
} rb_creep_curve;

/* The peak of a curve for loops that sample it over a run, with *log_creep the log10 of its creep
 * (in: from the last sample, NaN: none; out: this one's). _scan searches the whole range as
 * rb_polach_peak and counts the curve's inner maxima it passed (*maxima: more than 1, the curve
 * has another branch; a rise towards full slip is not one); _track follows the maximum of
 * the last sample's branch by Newton's method (about 5 evaluations of the law against some 200),
 * which misses another branch rising above it. No argument checks. */
double rb_creep_peak_scan(const rb_creep_curve *f, double *log_creep, int *maxima);
double rb_creep_peak_track(const rb_creep_curve *f, double *log_creep);
/* _track for n curves at once (peak[i], log_creep[i] each curve's), the same results: every round
 * of the method evaluates all the curves that need it in one call of at_each (NULL: one by one
 * through each curve's at), so a caller with a vector form of its curves overlaps them. */
enum { RB_CREEP_BATCH = 64 };   /* curves followed side by side; more go in turn */
typedef void (*rb_creep_at_each)(const rb_creep_curve *curves, const int *member, const double *log_creep,
                                 double *f, int n);   /* f[j]: curves[member[j]] at log_creep[j] */
void rb_creep_peaks_track(const rb_creep_curve *curves, int n, rb_creep_at_each at_each, double *log_creep,
                          double *peak);
/* The same on Polach's law (rb_polach_coefficient_fast) at one speed and load. */
double rb_polach_peak_scan(double speed, double normal_force, const rb_creep_contact *c,
                           const rb_polach_params *p, double *log_creep, int *maxima);
double rb_polach_peak_track(double speed, double normal_force, const rb_creep_contact *c,
                            const rb_polach_params *p, double *log_creep);

/* Rail conditioning by the axles ahead (heavy rain): factor on mu0 for the axle with
 * index axle (0 = leading): 1 - (1 - leading_factor) * exp(-axle / recovery_axles). */
double rb_conditioning_factor(double axle, double leading_factor, double recovery_axles);

/* Rail conditioning by energy (core/src/contact_conditioning.c), an option beside the axle count:
 * each axle's friction power, creep force x slip velocity, is spread over the rail strip its
 * contact (width 2b) passes, so the axle leaves on the rail the energy density
 *     e = |F w| / (2 b v)   [J/m^2]   (v: train speed; 0 at standstill: no rail passes under it).
 * The rail conditioned by the energy E dissipated by the axles ahead blends mu0 from the
 * contaminated towards the cleaned characteristic. The blend 1 - exp(-E/E_ref) follows the
 * degraded-adhesion model of B. Allotta, E. Meli, A. Ridolfi, A. Rindi, Tribology International
 * 69 (2014) 128-140 (there of the specific friction power at the contact; here of the energy the
 * axles ahead left on the rail):
 *     factor(E) = 1 - (1 - leading_factor) exp(-E / reference_energy).
 * With the same e for every axle, E = n e and this is the axle-count law with
 * recovery_axles = reference_energy / e. reference_energy has no published value for high-speed
 * rain: it is an input [T] (identify it from measured car-by-car adhesion where available). */
typedef struct {
    double leading_factor;    /* mu0 factor on the uncleaned rail, (0, 1] */
    double reference_energy;  /* J/m^2, energy density that cleans 63 % of the contamination */
} rb_conditioning_energy;

rb_status rb_conditioning_energy_check(const rb_conditioning_energy *c, rb_error *err);
size_t rb_conditioning_energy_size(void);  /* sizeof, for the bindings' check */
double rb_dissipated_energy_density(double creep_force, double slip_velocity, double speed,
                                    double contact_width);
double rb_conditioning_energy_factor(const rb_conditioning_energy *c, double energy_density);

#ifdef __cplusplus
}
#endif
#endif

/* Polach's creep-force model (Polach, Wear 258 (2005) 992-1000). */
#include "railbrake/rb_contact.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

rb_status rb_polach_check(const rb_polach_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "params = NULL: Polach parameters are required");
    if ((s = rb_check_range(err, "mu0", p->mu0, 1e-6, 2.0))) return s;
    if ((s = rb_check_range(err, "A", p->A, 0.0, 1.0))) return s;
    if ((s = rb_check_range(err, "B", p->B, 0.0, 100.0))) return s;
    if ((s = rb_check_range(err, "kA", p->kA, 1e-6, 1.0))) return s;
    if ((s = rb_check_range(err, "kS", p->kS, 1e-6, 1.0))) return s;
    return RB_OK;
}

rb_status rb_creep_contact_check(const rb_creep_contact *c, rb_error *err)
{
    rb_status s;
    if (!c) return rb_fail(err, RB_EINVAL, "contact = NULL: a contact is required");
    if ((s = rb_check_positive(err, "contact.a", c->a))) return s;
    if ((s = rb_check_positive(err, "contact.b", c->b))) return s;
    if ((s = rb_check_positive(err, "contact.c11", c->c11))) return s;
    if ((s = rb_check_positive(err, "shear_modulus", c->shear_modulus))) return s;
    return RB_OK;
}

double rb_polach_coefficient_fast(double creep, double speed, double normal_force,
                                  const rb_creep_contact *c, const rb_polach_params *p)
{
    double slip_velocity = fabs(creep) * speed;
    double mu = p->mu0 * ((1.0 - p->A) * exp(-p->B * slip_velocity) + p->A);
    /* With A = 0 the friction underflows to 0 at large slip velocity: no force (the limit), not 0/0. */
    if (!(mu > 0.0))
        return 0.0;
    /* Gradient of the tangential stress in the area of adhesion, times creep. */
    double eps = c->shear_modulus * M_PI * c->a * c->b * c->c11 / (4.0 * normal_force * mu) * fabs(creep);
    double ka_eps = p->kA * eps;
    double f = 2.0 * mu / M_PI * (ka_eps / (1.0 + ka_eps * ka_eps) + atan(p->kS * eps));
    return creep < 0.0 ? -f : f;
}

rb_status rb_polach_coefficient(const double *creep, const double *speed, size_t n,
                                double normal_force, const rb_creep_contact *c,
                                const rb_polach_params *p, double *out, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "normal_force", normal_force))) return s;
    if ((s = rb_creep_contact_check(c, err))) return s;
    if ((s = rb_polach_check(p, err))) return s;
    if (n > 0 && (!creep || !speed || !out))
        return rb_fail(err, RB_EINVAL, "creep, speed and out must not be NULL");
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(creep[i]))
            return rb_fail(err, RB_EINVAL, "creep[%zu] = %g: must be a finite number", i, creep[i]);
        if (!isfinite(speed[i]) || speed[i] < 0.0)
            return rb_fail(err, RB_EINVAL, "speed[%zu] = %g: must be finite and >= 0 (m/s)", i, speed[i]);
    }
    for (size_t i = 0; i < n; ++i)
        out[i] = rb_polach_coefficient_fast(creep[i], speed[i], normal_force, c, p);
    return RB_OK;
}

rb_status rb_polach_peak(double speed, double normal_force, const rb_creep_contact *c,
                         const rb_polach_params *p, double *peak_coefficient,
                         double *peak_creep, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_nonnegative(err, "speed", speed))) return s;
    if ((s = rb_check_positive(err, "normal_force", normal_force))) return s;
    if ((s = rb_creep_contact_check(c, err))) return s;
    if ((s = rb_polach_check(p, err))) return s;

    /* Scan log10(creep) over [-7, 0], then refine the best bracket by golden section. */
    enum { N_SCAN = 141 };
    const double lo = -7.0, hi = 0.0, step = (hi - lo) / (N_SCAN - 1);
    int best = 0;
    double best_f = -1.0;
    for (int i = 0; i < N_SCAN; ++i) {
        double f = rb_polach_coefficient_fast(pow(10.0, lo + i * step), speed, normal_force, c, p);
        if (f > best_f) { best_f = f; best = i; }
    }
    double x_lo = lo + (best > 0 ? best - 1 : 0) * step;
    double x_hi = lo + (best < N_SCAN - 1 ? best + 1 : N_SCAN - 1) * step;
    const double ratio = 0.6180339887498949;
    double x1 = x_hi - ratio * (x_hi - x_lo), x2 = x_lo + ratio * (x_hi - x_lo);
    double f1 = rb_polach_coefficient_fast(pow(10.0, x1), speed, normal_force, c, p);
    double f2 = rb_polach_coefficient_fast(pow(10.0, x2), speed, normal_force, c, p);
    for (int it = 0; it < 100 && x_hi - x_lo > 1e-12; ++it) {
        if (f1 < f2) {
            x_lo = x1; x1 = x2; f1 = f2;
            x2 = x_lo + ratio * (x_hi - x_lo);
            f2 = rb_polach_coefficient_fast(pow(10.0, x2), speed, normal_force, c, p);
        } else {
            x_hi = x2; x2 = x1; f2 = f1;
            x1 = x_hi - ratio * (x_hi - x_lo);
            f1 = rb_polach_coefficient_fast(pow(10.0, x1), speed, normal_force, c, p);
        }
    }
    double x_best = 0.5 * (x_lo + x_hi);
    double f_best = rb_polach_coefficient_fast(pow(10.0, x_best), speed, normal_force, c, p);
    if (best_f > f_best) { f_best = best_f; x_best = lo + best * step; }
    if (peak_coefficient) *peak_coefficient = f_best;
    if (peak_creep) *peak_creep = pow(10.0, x_best);
    return RB_OK;
}

double rb_conditioning_factor(double axle, double leading_factor, double recovery_axles)
{
    if (!(recovery_axles > 0.0)) return 1.0;
    return 1.0 - (1.0 - leading_factor) * exp(-axle / recovery_axles);
}

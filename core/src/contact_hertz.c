/* Hertz contact ellipse (Johnson, Contact Mechanics, ch. 4). */
#include "railbrake/rb_contact.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* AGM from modulus e and complementary modulus kp = sqrt(1 - e^2), given separately so that
 * slender ellipses (kp -> 0) keep their precision:
 * K = pi / (2 a_inf); K - E = K * sum_{n>=0} 2^(n-1) c_n^2 with c_0 = e. */
static void elliptic_agm(double e, double kp, double *K, double *E, double *K_minus_E)
{
    double an = 1.0, bn = kp, cn = e;
    double sum = 0.5 * cn * cn, weight = 0.5;
    for (int i = 0; i < 60 && cn > 1e-17 * an; ++i) {
        double a_next = 0.5 * (an + bn);
        cn = 0.5 * (an - bn);
        bn = sqrt(an * bn);
        an = a_next;
        weight *= 2.0;
        sum += weight * cn * cn;
    }
    double k = M_PI / (2.0 * an);
    if (K) *K = k;
    if (K_minus_E) *K_minus_E = k * sum;
    if (E) *E = k * (1.0 - sum);
}

void rb_elliptic_ke(double e, double *K, double *E, double *K_minus_E)
{
    elliptic_agm(e, sqrt((1.0 - e) * (1.0 + e)), K, E, K_minus_E);
}

/* (K - E) / e^2 for an ellipse of axis ratio g = minor/major, finite as g -> 1 (limit pi/4). */
static double k_minus_e_over_e2(double g, double *K)
{
    double e = sqrt((1.0 - g) * (1.0 + g));
    if (e < 1e-4) {
        if (K) *K = M_PI / 2.0 * (1.0 + e * e / 4.0);
        return M_PI / 4.0 * (1.0 + 3.0 * e * e / 8.0);
    }
    double kme;
    elliptic_agm(e, g, K, NULL, &kme);
    return kme / (e * e);
}

/* Curvature ratio B/A (>= 1) of an ellipse with axis ratio g = minor/major (Johnson 4.39). */
static double curvature_ratio(double g)
{
    double K;
    double q = k_minus_e_over_e2(g, &K);
    return (K / q - 1.0) / (g * g);
}

rb_status rb_hertz_contact(double normal_force, double rx, double ry, double youngs_modulus,
                           double poisson, rb_hertz *out, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "normal_force", normal_force))) return s;
    if ((s = rb_check_positive(err, "youngs_modulus", youngs_modulus))) return s;
    if (!(poisson >= 0.0 && poisson < 0.5))
        return rb_fail(err, RB_EINVAL, "poisson = %g: must lie in [0, 0.5)", poisson);
    if (isinf(rx) || isinf(ry))
        return rb_fail(err, RB_EINVAL,
                       "%s = inf: an infinite relative radius gives line contact, not a Hertz ellipse",
                       isinf(rx) ? "rx" : "ry");
    if ((s = rb_check_positive(err, "rx", rx))) return s;
    if ((s = rb_check_positive(err, "ry", ry))) return s;
    if (!out) return rb_fail(err, RB_EINVAL, "out = NULL: an output record is required");

    double curv_x = 0.5 / rx, curv_y = 0.5 / ry;   /* Johnson's A and B */
    double small = fmin(curv_x, curv_y), large = fmax(curv_x, curv_y);
    double ratio = large / small;

    /* Solve curvature_ratio(g) = ratio for g in (0, 1]; monotonic decreasing in g. */
    double g = 1.0;
    if (ratio > 1.0 + 1e-14) {
        double lo = 1e-12, hi = 1.0;   /* bisection on log g */
        if (curvature_ratio(lo) < ratio)
            return rb_fail(err, RB_EINVAL, "rx/ry = %g: curvature ratio beyond the solvable range", rx / ry);
        for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
            double mid = sqrt(lo * hi);
            if (curvature_ratio(mid) > ratio) lo = mid; else hi = mid;
        }
        g = sqrt(lo * hi);
    }
    double e_star = youngs_modulus / (2.0 * (1.0 - poisson * poisson));
    double q = k_minus_e_over_e2(g, NULL);
    /* Major semi-axis lies along the direction of smaller relative curvature:
     * major^3 = 3 P (K - E) / (2 pi A E* e^2) with A the smaller curvature. */
    double major = cbrt(3.0 * normal_force * q / (2.0 * M_PI * small * e_star));
    double minor = g * major;

    out->a = (curv_x <= curv_y) ? major : minor;
    out->b = (curv_x <= curv_y) ? minor : major;
    out->p0 = 3.0 * normal_force / (2.0 * M_PI * major * minor);
    out->normal_force = normal_force;
    out->youngs_modulus = youngs_modulus;
    out->poisson = poisson;
    out->shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson));
    return RB_OK;
}

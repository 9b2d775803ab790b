/* Variable-area flow elements and membranes driven by a body position. */
#include "railbrake/rb_pneumatics.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double port_area(double d) { return 0.25 * M_PI * d * d; }

double rb_flapper_nozzle_area(double nozzle_diameter, double gap)
{
    if (!(gap > 0.0)) return 0.0;
    return fmin(M_PI * nozzle_diameter * gap, port_area(nozzle_diameter));
}

double rb_seat_area(double seat_diameter, double lift, double half_angle)
{
    if (!(lift > 0.0)) return 0.0;
    return fmin(M_PI * seat_diameter * lift * sin(half_angle), port_area(seat_diameter));
}

double rb_spool_edge_area(double spool_diameter, double opening, double clearance)
{
    double x = opening > 0.0 ? opening : 0.0;
    return M_PI * spool_diameter * sqrt(x * x + clearance * clearance);
}

/* Fritsch-Carlson slopes: harmonic-type limiting keeps a monotone V(x) monotone. */
static void membrane_slopes(rb_membrane *mb)
{
    int n = mb->n;
    double d[RB_MEMBRANE_MAX_POINTS];
    for (int i = 0; i + 1 < n; ++i)
        d[i] = (mb->volume[i + 1] - mb->volume[i]) / (mb->x[i + 1] - mb->x[i]);
    mb->slope[0] = d[0];
    mb->slope[n - 1] = d[n - 2];
    for (int i = 1; i + 1 < n; ++i) {
        if (d[i - 1] * d[i] <= 0.0) {
            mb->slope[i] = 0.0;
        } else {
            double h0 = mb->x[i] - mb->x[i - 1], h1 = mb->x[i + 1] - mb->x[i];
            double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
            mb->slope[i] = (w1 + w2) / (w1 / d[i - 1] + w2 / d[i]);
        }
    }
}

rb_status rb_membrane_init(rb_membrane *mb, const double *x, const double *volume, int n,
                           rb_error *err)
{
    if (!mb || !x || !volume) return rb_fail(err, RB_EINVAL, "membrane, x and volume must not be NULL");
    if (n < 2 || n > RB_MEMBRANE_MAX_POINTS)
        return rb_fail(err, RB_EINVAL, "membrane points n = %d: must lie in [2, %d]", n,
                       RB_MEMBRANE_MAX_POINTS);
    for (int i = 0; i < n; ++i) {
        rb_status s;
        if ((s = rb_check_finite(err, "membrane x", x[i]))) return s;
        if ((s = rb_check_finite(err, "membrane volume", volume[i]))) return s;
        if (i > 0 && !(x[i] > x[i - 1]))
            return rb_fail(err, RB_EINVAL, "membrane x[%d] = %g: must be > x[%d] = %g (sorted)", i,
                           x[i], i - 1, x[i - 1]);
        if (i > 0 && volume[i] < volume[i - 1])
            return rb_fail(err, RB_EINVAL, "membrane volume[%d] = %g: must be >= volume[%d] = %g",
                           i, volume[i], i - 1, volume[i - 1]);
        mb->x[i] = x[i];
        mb->volume[i] = volume[i];
    }
    mb->n = n;
    membrane_slopes(mb);
    return RB_OK;
}

void rb_membrane_eval(const rb_membrane *mb, double x, double *volume, double *effective_area)
{
    int n = mb->n;
    if (x <= mb->x[0] || x >= mb->x[n - 1]) {
        int i = x <= mb->x[0] ? 0 : n - 1;
        *effective_area = mb->slope[i];
        *volume = mb->volume[i] + mb->slope[i] * (x - mb->x[i]);
        return;
    }
    int i = 0;
    while (x > mb->x[i + 1]) ++i;
    double h = mb->x[i + 1] - mb->x[i], t = (x - mb->x[i]) / h;
    double v0 = mb->volume[i], v1 = mb->volume[i + 1], m0 = mb->slope[i] * h, m1 = mb->slope[i + 1] * h;
    double t2 = t * t, t3 = t2 * t;
    *volume = (2 * t3 - 3 * t2 + 1) * v0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * v1 + (t3 - t2) * m1;
    double dv = (6 * t2 - 6 * t) * v0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * v1 + (3 * t2 - 2 * t) * m1;
    *effective_area = dv / h;
}

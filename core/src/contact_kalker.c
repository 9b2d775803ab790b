/* Kalker's creepage and spin coefficients (Kalker 1990, Table E.3).
 * The table is also kept as validation/code-to-code/kalker-creepage-table/reference.csv; the
 * Python tests and the validation cases check that every node here equals it. Outside the table the asymptotic forms are used,
 * scaled to meet the table at its edge so the coefficient stays continuous:
 *   a/b -> 0  (g = a/b): C11 -> pi^2/(4(1-nu)), C22 -> pi^2/4, C23 ~ sqrt(g);
 *   a/b -> oo (g = b/a): C11 ~ 2 pi / (g (L - 2 nu)) (1 + (3 - ln 4)/(L - 2 nu)),
 *                        C22 ~ 2 pi / (g D) (1 + (1 - nu)(3 - ln 4)/D),  D = (1 - nu) L + 2 nu,
 *                        C23 ~ 2 pi / (3 g^1.5 ((1 - nu) L - 2 + 4 nu)),  L = ln(16 / g^2). */
#include "railbrake/rb_contact.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define N_ROWS 19

static const double TABLE_RATIO[N_ROWS] = {
    0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0,
    1.1111, 1.25, 1.4286, 1.6667, 2.0, 2.5, 3.3333, 5.0, 10.0};

/* [coefficient 11/22/23][row][poisson 0, 0.25, 0.5] */
static const double TABLE[3][N_ROWS][3] = {
    {{2.51, 3.31, 4.85}, {2.59, 3.37, 4.81}, {2.68, 3.44, 4.80}, {2.78, 3.53, 4.82},
     {2.88, 3.62, 4.83}, {2.98, 3.72, 4.91}, {3.09, 3.81, 4.97}, {3.19, 3.91, 5.05},
     {3.29, 4.01, 5.12}, {3.40, 4.12, 5.20}, {3.51, 4.22, 5.30}, {3.65, 4.36, 5.42},
     {3.82, 4.54, 5.58}, {4.06, 4.78, 5.80}, {4.37, 5.10, 6.11}, {4.84, 5.57, 6.57},
     {5.57, 6.34, 7.34}, {6.96, 7.78, 8.82}, {10.7, 11.7, 12.9}},
    {{2.51, 2.52, 2.53}, {2.59, 2.63, 2.66}, {2.68, 2.75, 2.81}, {2.78, 2.88, 2.98},
     {2.88, 3.01, 3.14}, {2.98, 3.14, 3.31}, {3.09, 3.28, 3.48}, {3.19, 3.41, 3.65},
     {3.29, 3.54, 3.82}, {3.40, 3.67, 3.98}, {3.51, 3.81, 4.16}, {3.65, 3.99, 4.39},
     {3.82, 4.21, 4.67}, {4.06, 4.50, 5.04}, {4.37, 4.90, 5.56}, {4.84, 5.48, 6.31},
     {5.57, 6.40, 7.51}, {6.96, 8.14, 9.79}, {10.7, 12.8, 16.0}},
    {{0.334, 0.473, 0.731}, {0.483, 0.603, 0.809}, {0.607, 0.715, 0.889}, {0.720, 0.823, 0.977},
     {0.827, 0.929, 1.07}, {0.930, 1.03, 1.18}, {1.03, 1.14, 1.29}, {1.13, 1.25, 1.40},
     {1.23, 1.36, 1.51}, {1.33, 1.47, 1.63}, {1.44, 1.59, 1.77}, {1.58, 1.75, 1.94},
     {1.76, 1.95, 2.18}, {2.01, 2.23, 2.50}, {2.35, 2.62, 2.96}, {2.88, 3.24, 3.70},
     {3.79, 4.32, 5.01}, {5.72, 6.63, 7.89}, {12.2, 14.6, 18.0}}};

/* Quadratic (Lagrange) interpolation of 1/C through poisson = 0, 0.25, 0.5. */
static double interpolate_poisson(const double c[3], double nu)
{
    double l0 = (nu - 0.25) * (nu - 0.5) / ((0.0 - 0.25) * (0.0 - 0.5));
    double l1 = (nu - 0.0) * (nu - 0.5) / ((0.25 - 0.0) * (0.25 - 0.5));
    double l2 = (nu - 0.0) * (nu - 0.25) / ((0.5 - 0.0) * (0.5 - 0.25));
    return 1.0 / (l0 / c[0] + l1 / c[1] + l2 / c[2]);
}

static double table_value(int k, int row, double nu)
{
    return interpolate_poisson(TABLE[k][row], nu);
}

/* Asymptotic form for a slender ellipse, g = b/a -> 0. */
static double slender_asymptote(int k, double g, double nu)
{
    double L = log(16.0 / (g * g)), c3 = 3.0 - log(4.0);
    if (k == 0) return 2.0 * M_PI / (g * (L - 2.0 * nu)) * (1.0 + c3 / (L - 2.0 * nu));
    if (k == 1) {
        double d = (1.0 - nu) * L + 2.0 * nu;
        return 2.0 * M_PI / (g * d) * (1.0 + (1.0 - nu) * c3 / d);
    }
    return 2.0 * M_PI / (3.0 * pow(g, 1.5) * ((1.0 - nu) * L - 2.0 + 4.0 * nu));
}

/* Asymptotic form for a/b = g -> 0: the finite limits of C11, C22 and C23 ~ sqrt(g). */
static double narrow_value(int k, double g, double nu)
{
    double edge = table_value(k, 0, nu), g0 = TABLE_RATIO[0];
    double limit = (k == 0) ? M_PI * M_PI / (4.0 * (1.0 - nu)) : M_PI * M_PI / 4.0;
    if (k == 2) return edge * sqrt(g / g0);
    return limit + (edge - limit) * g / g0;
}

rb_status rb_kalker(int which, double a_over_b, double poisson, double *out, rb_error *err)
{
    int k = (which == 11) ? 0 : (which == 22) ? 1 : (which == 23) ? 2 : -1;
    if (k < 0) return rb_fail(err, RB_EINVAL, "which = %d: must be 11, 22 or 23", which);
    if (!(poisson >= 0.0 && poisson <= 0.5))
        return rb_fail(err, RB_EINVAL, "poisson = %g: must lie in [0, 0.5]", poisson);
    rb_status s = rb_check_positive(err, "a_over_b", a_over_b);
    if (s) return s;
    if (!out) return rb_fail(err, RB_EINVAL, "out = NULL: an output is required");

    if (a_over_b <= TABLE_RATIO[0]) {
        *out = narrow_value(k, a_over_b, poisson);
    } else if (a_over_b >= TABLE_RATIO[N_ROWS - 1]) {
        double g_edge = 1.0 / TABLE_RATIO[N_ROWS - 1];
        double scale = table_value(k, N_ROWS - 1, poisson) / slender_asymptote(k, g_edge, poisson);
        *out = scale * slender_asymptote(k, 1.0 / a_over_b, poisson);
    } else {
        int i = 0;
        while (a_over_b > TABLE_RATIO[i + 1]) ++i;
        double t = (a_over_b - TABLE_RATIO[i]) / (TABLE_RATIO[i + 1] - TABLE_RATIO[i]);
        *out = (1.0 - t) * table_value(k, i, poisson) + t * table_value(k, i + 1, poisson);
    }
    return RB_OK;
}

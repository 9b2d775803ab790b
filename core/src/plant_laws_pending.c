/* TEMPORARY ADAPTER - delete after merging main.
 *
 * The pneumatics concern (rb_pneumatics.h) owns this law; it was not on main when the plant was
 * written. Same signature as the contract: an ideal nozzle (b = critical_ratio) with the ISO 6358
 * ellipse above b and a linear end near equal pressures. */
#include "plant_internal.h"

#include <math.h>

double rb_orifice_mass_flow_fast(double p1, double T1, double p2, double T2,
                                 double area, double discharge_coefficient, double critical_ratio)
{
    if (p2 > p1)
        return -rb_orifice_mass_flow_fast(p2, T2, p1, T1, area, discharge_coefficient, critical_ratio);
    const double R = 287.05, gamma = 1.4;
    /* choked flux of an ideal nozzle, (2/(g+1))^((g+1)/(2(g-1))) sqrt(g/R) */
    const double choked = 0.578704 * sqrt(gamma / R);
    double mmax = discharge_coefficient * area * p1 * choked / sqrt(T1);
    double r = p2 / p1, b = critical_ratio, r_lin = 0.999;
    if (r <= b) return mmax;
    if (r < r_lin) {
        double x = (r - b) / (1.0 - b);
        return mmax * sqrt(1.0 - x * x);
    }
    double x = (r_lin - b) / (1.0 - b);
    return mmax * sqrt(1.0 - x * x) * (1.0 - r) / (1.0 - r_lin);
}

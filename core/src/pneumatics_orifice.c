/* Orifice mass flow, ISO 6358 form with choked and laminar limits (reference README sec. 4). */
#include "railbrake/rb_pneumatics.h"

#include <math.h>

/* Ideal-nozzle choked mass flux factor sqrt(gamma/R) (2/(gamma+1))^((gamma+1)/(2(gamma-1))),
   so that mdot = Cd A p1 / sqrt(T1) * factor. */
static double choked_factor(void)
{
    const double g = RB_AIR_GAMMA;
    return sqrt(g / RB_AIR_R) * pow(2.0 / (g + 1.0), (g + 1.0) / (2.0 * (g - 1.0)));
}

/* ISO 6358 flow function of the pressure ratio r = p_down/p_up in [0, 1]: 1 when choked,
   the elliptic form above b, linear in (1 - r) above the laminar ratio (continuous there). */
static double flow_function(double r, double b)
{
    if (r <= b) return 1.0;
    double lam = RB_ORIFICE_LAMINAR_RATIO;
    if (b >= lam) return (1.0 - r) / (1.0 - b);
    if (r >= lam) {
        double s = (lam - b) / (1.0 - b);
        return sqrt(1.0 - s * s) * (1.0 - r) / (1.0 - lam);
    }
    double s = (r - b) / (1.0 - b);
    return sqrt(1.0 - s * s);
}

/* mdot = G p_up / sqrt(T_up) * phi(p_down/p_up), G = C rho0 sqrt(T0); sign by direction. */
static double flow(double p1, double T1, double p2, double T2, double G, double b)
{
    if (p1 >= p2) return G * p1 / sqrt(T1) * flow_function(p2 / p1, b);
    return -G * p2 / sqrt(T2) * flow_function(p1 / p2, b);
}

double rb_sonic_conductance(double area, double discharge_coefficient)
{
    return discharge_coefficient * area * choked_factor() / (RB_ISO6358_RHO0 * sqrt(RB_ISO6358_T0));
}

double rb_orifice_mass_flow_fast(double p1, double T1, double p2, double T2,
                                 double area, double discharge_coefficient, double critical_ratio)
{
    return flow(p1, T1, p2, T2, discharge_coefficient * area * choked_factor(), critical_ratio);
}

double rb_orifice_mass_flow_iso_fast(double p1, double T1, double p2, double T2,
                                     double sonic_conductance, double critical_ratio)
{
    double G = sonic_conductance * RB_ISO6358_RHO0 * sqrt(RB_ISO6358_T0);
    return flow(p1, T1, p2, T2, G, critical_ratio);
}

void rb_orifice_law_init(double critical_ratio, rb_orifice_law *law)
{
    double b = critical_ratio, lam = RB_ORIFICE_LAMINAR_RATIO;
    law->b = b;
    law->inv_one_minus_b = 1.0 / (1.0 - b);
    law->laminar_only = b >= lam;
    double s = (lam - b) / (1.0 - b);
    law->laminar_slope = law->laminar_only ? 0.0 : sqrt(1.0 - s * s) / (1.0 - lam);
}

double rb_orifice_unit_conductance(double discharge_coefficient, double temperature)
{
    return discharge_coefficient * choked_factor() / sqrt(temperature);
}

rb_status rb_orifice_check(const rb_orifice *o, rb_error *err)
{
    rb_status s;
    if (!o) return rb_fail(err, RB_EINVAL, "orifice = NULL: an orifice is required");
    if ((s = rb_check_range(err, "critical_ratio", o->critical_ratio, 0.0, 0.999))) return s;
    if ((s = rb_check_nonnegative(err, "sonic_conductance", o->sonic_conductance))) return s;
    if (o->sonic_conductance > 0.0) return RB_OK;
    if ((s = rb_check_nonnegative(err, "area", o->area))) return s;
    if (!isfinite(o->discharge_coefficient) || !(o->discharge_coefficient > 0.0) ||
        o->discharge_coefficient > 1.0)
        return rb_fail(err, RB_EINVAL, "discharge_coefficient = %g: must lie in (0, 1]",
                       o->discharge_coefficient);
    return RB_OK;
}

rb_status rb_orifice_mass_flow(double p1, double T1, double p2, double T2, const rb_orifice *o,
                               double *mdot, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "p1", p1))) return s;
    if ((s = rb_check_positive(err, "T1", T1))) return s;
    if ((s = rb_check_positive(err, "p2", p2))) return s;
    if ((s = rb_check_positive(err, "T2", T2))) return s;
    if ((s = rb_orifice_check(o, err))) return s;
    if (!mdot) return rb_fail(err, RB_EINVAL, "mdot = NULL: an output is required");
    *mdot = o->sonic_conductance > 0.0
                ? rb_orifice_mass_flow_iso_fast(p1, T1, p2, T2, o->sonic_conductance, o->critical_ratio)
                : rb_orifice_mass_flow_fast(p1, T1, p2, T2, o->area, o->discharge_coefficient,
                                            o->critical_ratio);
    return RB_OK;
}

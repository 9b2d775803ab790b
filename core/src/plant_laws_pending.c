/* TEMPORARY ADAPTER - delete after merging main.
 *
 * The pneumatics (rb_pneumatics.h) and vehicle (rb_vehicle.h) concerns own these laws; they were
 * not on main when the plant was written. The orifice law keeps the contract's signature; the
 * vehicle stand-ins are the plainest forms of the published laws (EN 14531 cylinder force,
 * A + B v + C v^2, a tabulated ED curve, a linear coupler with slack). */
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

double rb_pending_pad_friction(const rb_plant_brake *b, double disc_speed)
{
    if (disc_speed >= b->pad_friction_speed) return b->pad_friction;
    double x = disc_speed / b->pad_friction_speed;
    return b->pad_friction_low + (b->pad_friction - b->pad_friction_low) * x;
}

double rb_pending_pad_force(const rb_plant_brake *b, double cylinder_pressure, double atmosphere)
{
    double f = ((cylinder_pressure - atmosphere) * b->cylinder_area - b->spring_force)
               * b->lever_ratio * b->efficiency;
    return f > 0.0 ? f : 0.0;
}

double rb_pending_ed_force_max(const rb_plant_ed *e, double speed)
{
    if (e->n <= 0) return 0.0;
    if (speed <= e->speed[0]) return e->force[0];
    for (int i = 1; i < e->n; ++i)
        if (speed <= e->speed[i]) {
            double w = (speed - e->speed[i - 1]) / (e->speed[i] - e->speed[i - 1]);
            return e->force[i - 1] + w * (e->force[i] - e->force[i - 1]);
        }
    return e->force[e->n - 1];
}

double rb_pending_running_resistance(double a, double b, double c, double speed)
{
    return a + b * speed + c * speed * speed;
}

double rb_pending_coupler_force(double stiffness, double damping, double slack, double dx, double dv)
{
    double stretch = fabs(dx) > slack ? dx - copysign(slack, dx) : 0.0;
    return stiffness * stretch + (stretch != 0.0 ? damping * dv : 0.0);
}

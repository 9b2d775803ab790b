/* The energy balance of each car's relay control chamber (the EP valve's or the emergency choke's
 * pilot volume) in the plant, as the brake cylinders' (plant.c, derive_cylinders) and as the
 * detailed model's volumes: air let in brings its enthalpy at the wall's temperature (m T rises by
 * gamma T_wall dm), air let out leaves with the chamber's (m T falls by gamma T dm), the wall
 * exchanges heat with time constant wall_time. A choked fill through the emergency choke thus rises
 * up to gamma times faster than an isothermal one, then relaxes to it, as in the detailed model.
 * wall_time = 0: isothermal (theta 1). The chamber's pressure is m R T / V: the stiffness
 * (rb_plant_pilot_stiffness) carries the temperature ratio theta = T / T_wall. */
#include "plant_internal.h"

void rb_plant_pilot_init(const rb_plant_params *p, rb_plant_state *s)
{
    double m_ref_per_volume = RB_WALL_REFERENCE_PRESSURE / (RB_AIR_R * p->temperature);
    for (int c = 0; c < p->n_cars; ++c) {
        s->pilot_theta[c] = 1.0;
        s->derived.pilot_heat[c] =
            p->wall_time > 0.0 ? s->derived.h * m_ref_per_volume * p->car[c].pilot_volume / p->wall_time : 0.0;
    }
}

void rb_plant_pilot_energy(const rb_plant_params *p, rb_plant_state *s, const double *m_before)
{
    if (!(p->wall_time > 0.0)) return;
    const double wall = p->temperature;
    for (int c = 0; c < p->n_cars; ++c) {
        double m0 = m_before[c], m = s->m_pilot[c], t = s->pilot_theta[c] * wall, dm = m - m0;
        double mt = m0 * t + RB_AIR_GAMMA * (dm > 0.0 ? wall : t) * dm + s->derived.pilot_heat[c] * (wall - t);
        s->pilot_theta[c] = mt / (m * wall);
    }
}

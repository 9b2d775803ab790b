/* The energy balance of each car's relay control chamber (the EP valve's or the emergency choke's
 * pilot volume) in the plant, as the brake cylinders' (plant.c, derive_cylinders) and as the
 * detailed model's volumes: air let in brings its enthalpy at the wall's temperature (m T rises by
 * gamma T_wall dm), air let out leaves with the chamber's (m T falls by gamma T dm), the relay
 * membrane's sweep does its work p dV, the wall exchanges heat with time constant wall_time. The
 * update follows each step's links at once, before the relays read the chamber (plant_step.c); its
 * links' equalising masses use the adiabatic stiffness. (Without the sweep's work the 1 ms plant
 * stopped 0.095 % short of its 0.1 ms self in heavy rain; with it 0.017 %.) A choked fill through the emergency choke thus rises
 * up to gamma times faster than an isothermal one, then relaxes to it, as in the detailed model.
 * wall_time = 0: isothermal (theta 1). The chamber's pressure is m R T / V: the stiffness
 * (rb_plant_pilot_stiffness) carries the temperature ratio theta = T / T_wall. The update itself,
 * rb_plant_pilot_energy, is inline in plant_internal.h: built into the step's vector code. */
#include "plant_internal.h"

void rb_plant_pilot_init(const rb_plant_params *p, rb_plant_state *s)
{
    rb_plant_derived *d = &s->derived;
    double m_ref_per_volume = RB_WALL_REFERENCE_PRESSURE / (RB_AIR_R * p->temperature);
    /* within a step the chamber is gamma times stiffer than an isothermal one: the equalising
       masses of its links say so (as the cylinders', derive_cylinders; links as in derive_air:
       the supply reservoir has 3, the chamber 2) */
    const double gamma = p->wall_time > 0.0 ? RB_AIR_GAMMA : 1.0, supply_links = 3.0, pilot_links = 2.0;
    for (int c = 0; c < p->n_cars; ++c) {
        s->pilot_theta[c] = 1.0;
        s->pilot_volume[c] = 1.0;   /* relay membrane at rest */
        d->pilot_heat[c] = p->wall_time > 0.0 ? d->h * m_ref_per_volume * p->car[c].pilot_volume / p->wall_time : 0.0;
        d->ik_ep_in[c] = 1.0 / (supply_links * d->k_supply[c] + pilot_links * gamma * d->k_pilot[c]);
        d->ik_ep_out[c] = 1.0 / (pilot_links * gamma * d->k_pilot[c]);
    }
}

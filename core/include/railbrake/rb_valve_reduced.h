/* The real-time plant's reduced valve model (rb_plant.h: EP valve lag and proportional ports)
 * alone, for fitting its parameters to the detailed valve's step responses (docs/pneumatics.md,
 * "From the design to the plant"). One volume V at temperature T fed from a supply reservoir and
 * vented to the atmosphere through ports of area `area` opening in proportion to the error
 * between the lagged demand (first order, tau) and the volume's pressure, fully at `band`:
 *
 *     d lag/dt = (demand - lag) / tau,  e = (lag - p) / band,
 *     dm/dt = area (clamp01(e) q1(p_supply -> p) - clamp01(-e) q1(p -> p_atm))
 *
 * with q1 the ISO 6358 flow per unit area (rb_orifice_mass_flow_fast), explicit steps of dt. The
 * plant also caps the EP target at the supply less ep_supply_margin; it is left out here because
 * the fit's supply (the valve studies' 8 bar) lies far above its targets (4.3 bar at most). */
#ifndef RAILBRAKE_VALVE_REDUCED_H
#define RAILBRAKE_VALVE_REDUCED_H

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double supply, atmosphere;      /* Pa abs */
    double volume, temperature;     /* m^3, K */
    double discharge_coefficient, critical_ratio;
    double tau;                     /* s, demand lag; 0: none (the relay valve) */
    double band;                    /* Pa */
    double area;                    /* m^2 */
} rb_reduced_valve;

/* Responses to n_steps demand steps start[k] -> final[k] (Pa abs) at t_step, each starting at rest
   at start[k]; pressure [k][n_out] at t_out (increasing, from 0); integrated at step dt (s). */
rb_status rb_reduced_valve_steps(const rb_reduced_valve *v, const double *start, const double *final,
                                 size_t n_steps, double t_step, const double *t_out, size_t n_out, double dt,
                                 double *pressure, rb_error *err);
size_t rb_reduced_valve_size(void);

#ifdef __cplusplus
}
#endif
#endif

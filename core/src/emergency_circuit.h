/* The emergency circuit of each car (emergency_circuit.c), shared by the 1 ms plant and the
 * detailed model: the loop's opening time, when each car's emergency valve acts, and the control
 * pressure it fills to. */
#ifndef RAILBRAKE_EMERGENCY_CIRCUIT_H
#define RAILBRAKE_EMERGENCY_CIRCUIT_H

#include "railbrake/rb_plant.h"

/* Checks car i's emergency circuit (the message names car[i].field, its value and range). */
rb_status rb_emergency_check(const rb_plant_car *c, int i, double atmosphere, rb_error *err);
/* The loop's opening time after a step starting at t with the loop input `emergency` (1 open):
 * the first time it is seen open; < 0 once it is closed again. */
double rb_emergency_loop(double open_time, double emergency, double t);
/* Time at which car c's emergency valve acts for a loop opened at open_time (INFINITY: never). */
double rb_emergency_switch_time(const rb_plant_car *c, double open_time);
/* The control pressure the emergency path fills to: the BCU's demand (its emergency pressure
 * for the speed and load), within [atmosphere, the load-weighing valve's limit]. */
double rb_emergency_target(const rb_plant_car *c, double demand, double atmosphere);
/* The pressure car c's choke sees upstream: the load-weighing valve's output, regulated to the
 * target but never above the supply reservoir it draws from (Pa). */
static inline double rb_emergency_source(const rb_plant_state *s, int c, double p_supply)
{
    return s->emergency_target[c] < p_supply ? s->emergency_target[c] : p_supply;
}
/* The plant's circuit at the start of a step (time s->time, inputs in): loop time, each car's
 * EP cut-off, choke conductance and target (s->emergency_open, _g, _target). */
void rb_emergency_plant_update(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in);

#endif

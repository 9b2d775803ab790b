/* The emergency circuit of each car: the emergency command's arrival (the train's emergency loop
 * opening, passed on to each car after its delay), the emergency valve's path into the relay
 * valve's control chamber beside the EP valve, the choke that sets the filling rate and the
 * load-weighing valve's limit (rb_plant.h, rb_plant_car). The relay valve then amplifies the
 * control pressure's flow into the cylinders, as in service braking. Used by the plant's valve
 * phase (plant_step.c) and the detailed model (detailed_run.c, detailed_air.c) alike. */
#include "emergency_circuit.h"

#include <math.h>
#include <stdio.h>

rb_status rb_emergency_check(const rb_plant_car *c, int i, double atmosphere, rb_error *err)
{
    if (!(c->emergency_area >= 0.0 && c->emergency_area <= 1e-4))
        return rb_fail(err, RB_EINVAL, "car[%d].emergency_area = %g m^2: must lie in [0, 1e-4] (a choke of up "
                       "to 11 mm diameter; 0: no emergency circuit)", i, c->emergency_area);
    if (!(c->emergency_area > 0.0)) return RB_OK;
    if (!(c->emergency_delay >= 0.0 && c->emergency_delay <= 10.0))
        return rb_fail(err, RB_EINVAL, "car[%d].emergency_delay = %g s: must lie in [0, 10]", i, c->emergency_delay);
    if (!(c->emergency_limit > atmosphere && c->emergency_limit <= 2e6))
        return rb_fail(err, RB_EINVAL, "car[%d].emergency_limit = %g Pa: must lie in (atmosphere %g, 2e6] Pa "
                       "absolute", i, c->emergency_limit, atmosphere);
    return RB_OK;
}

double rb_emergency_loop(double open_time, double emergency, double t)
{
    if (!(emergency > 0.5)) return -1.0;
    return open_time >= 0.0 ? open_time : t;
}

double rb_emergency_switch_time(const rb_plant_car *c, double open_time)
{
    if (!(c->emergency_area > 0.0) || open_time < 0.0) return INFINITY;
    return open_time + c->emergency_delay;
}

double rb_emergency_target(const rb_plant_car *c, double demand, double atmosphere)
{
    double target = demand < c->emergency_limit ? demand : c->emergency_limit;
    return target > atmosphere ? target : atmosphere;
}

void rb_emergency_plant_update(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in)
{
    s->loop_open_time = rb_emergency_loop(s->loop_open_time, in->emergency, s->time);
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        /* the EP valve is cut off from the loop's opening; the choke acts from the step whose start
           lies nearest the valve's time (within half a step) */
        double at = rb_emergency_switch_time(car, s->loop_open_time);
        s->emergency_open[c] = at < INFINITY ? 1.0 : 0.0;
        s->emergency_g[c] = at <= s->time + 0.5 * p->dt ? s->derived.g_emergency[c] : 0.0;
        s->emergency_target[c] = rb_emergency_target(car, in->pressure_demand[c], p->atmosphere);
    }
}

/* Brake control unit: demand -> EP pressure per car, ED blending, WSP plug-in. */
#include "railbrake/rb_bcu.h"
#include "railbrake/rb_bounds.h"

#include <math.h>
#include <string.h>

rb_status rb_bcu_check(const rb_bcu_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "bcu = NULL: BCU parameters are required");
    if (p->n_cars < 1 || p->n_cars > RB_PLANT_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "bcu.n_cars = %d: must be in [1, %d]", p->n_cars, RB_PLANT_MAX_CARS);
    if ((s = rb_check_range(err, "bcu.cycle", p->cycle, 1e-4, 0.1))) return s;
    if ((s = rb_check_range(err, "bcu.service_decel", p->service_decel, 0.0, 3.0))) return s;
    if ((s = rb_check_range(err, "bcu.emergency_decel", p->emergency_decel, 0.0, 3.0))) return s;
    if ((s = rb_check_range(err, "bcu.service_jerk", p->service_jerk, 0.0, 20.0))) return s;
    for (int c = 0; c < p->n_cars; ++c) {
        if ((s = rb_check_positive(err, "bcu.car_mass", p->car_mass[c]))) return s;
        if ((s = rb_check_nonnegative(err, "bcu.pressure_gain", p->pressure_gain[c]))) return s;
        if ((s = rb_check_range(err, "bcu.pressure_max", p->pressure_max[c], p->atmosphere, 2e6))) return s;
        if (!p->demand_tables) continue;
        if ((s = rb_speed_table_check(&p->emergency_force[c], "bcu.emergency_force", 0.0, 1e7, err))) return s;
        if ((s = rb_speed_table_check(&p->service_force[c], "bcu.service_force", 0.0, 1e7, err))) return s;
        if ((s = rb_speed_table_check(&p->pressure_per_newton[c], "bcu.pressure_per_newton", 0.0, 1e3, err)))
            return s;
    }
    if (p->demand_tables) {
        if ((s = rb_speed_table_check(&p->emergency_profile, "bcu.emergency_profile", 0.0, 5.0, err))) return s;
        if ((s = rb_speed_table_check(&p->service_profile, "bcu.service_profile", 0.0, 5.0, err))) return s;
    }
    return RB_OK;
}

rb_status rb_bcu_init(const rb_bcu_params *p, const rb_wsp_params *wsp, rb_bcu_state *s, rb_error *err)
{
    rb_status st;
    if ((st = rb_bcu_check(p, err))) return st;
    if (!s) return rb_fail(err, RB_EINVAL, "state = NULL: a BCU state is required");
    if (wsp && (st = rb_wsp_check(wsp, err))) return st;
    if (wsp && wsp->conditioning_mode && p->wsp_per_bogie)
        return rb_fail(err, RB_EINVAL, "wsp.conditioning_mode = 1 with bcu.wsp_per_bogie = 1: the conditioning mode "
                       "sets the two axles of a bogie apart, so it needs valves per axle (wsp_per_bogie = 0)");
    memset(s, 0, sizeof *s);
    rb_wsp_params defaults;
    rb_wsp_default_params(&defaults);
    rb_wsp_default_reset(&s->wsp_default, wsp ? wsp : &defaults);
    for (int c = 0; c < RB_PLANT_MAX_CARS; ++c) s->command.pressure_demand[c] = p->atmosphere;
    return RB_OK;
}

rb_status rb_bcu_retune_wsp(rb_bcu_state *s, const rb_wsp_params *wsp, rb_error *err)
{
    rb_status st;
    if (!s) return rb_fail(err, RB_EINVAL, "state = NULL: a BCU state is required");
    if ((st = rb_wsp_check(wsp, err))) return st;
    s->wsp_default.p = *wsp;   /* the algorithm's own state (modes, timers) goes on */
    return RB_OK;
}

void rb_bcu_pressure_map(const rb_plant_params *plant, double pressure_max, rb_bcu_params *p)
{
    const double high_speed = 50.0;  /* m/s: nominal pad friction */
    for (int c = 0; c < plant->n_cars; ++c) {
        const rb_plant_car *car = &plant->car[c];
        double p1 = plant->atmosphere + 2e5, p2 = plant->atmosphere + 4e5;
        double r = car->vehicle.wheelset.wheel_radius;
        double f1 = RB_AXLES_PER_CAR * rb_plant_axle_brake_torque(car, p1, high_speed) / r;
        double f2 = RB_AXLES_PER_CAR * rb_plant_axle_brake_torque(car, p2, high_speed) / r;
        p->pressure_gain[c] = (p2 - p1) / (f2 - f1);
        p->pressure_offset[c] = p1 - p->pressure_gain[c] * f1;
        p->pressure_max[c] = pressure_max;
        p->car_mass[c] = car->vehicle.mass + RB_AXLES_PER_CAR * rb_wheelset_equivalent_mass(&car->vehicle.wheelset);
        p->motor[c] = car->vehicle.motor;
    }
}

static double car_pressure(const rb_bcu_params *p, int c, double pa_per_n, double force)
{
    if (force <= 0.0) return p->atmosphere;
    double pressure = p->pressure_offset[c] + pa_per_n * force;
    return pressure < p->pressure_max[c] ? pressure : p->pressure_max[c];
}

/* Valves per bogie: an axle pair is held or vented when either of its axles asks for it. */
static void share_bogie_commands(rb_wsp_commands *c, int n_axles)
{
    for (int a = 0; a + 1 < n_axles; a += 2) {
        c->hold[a] = c->hold[a + 1] = c->hold[a] | c->hold[a + 1];
        c->vent[a] = c->vent[a + 1] = c->vent[a] | c->vent[a + 1];
        c->active[a] = c->active[a + 1] = c->active[a] | c->active[a + 1];
    }
}

double rb_bcu_speed(const rb_plant_outputs *out, int n_cars)
{
    double v = 0.0;
    for (int a = 0; a < n_cars * RB_AXLES_PER_CAR; ++a)
        if (out->wheel_speed_measured[a] > v) v = out->wheel_speed_measured[a];
    return v;
}

int rb_bcu_wsp_mode(const rb_bcu_params *p, const rb_bcu_state *s, int a)
{
    return p->wsp_enabled && !p->wsp ? s->wsp_default.mode[a] : RB_WSP_OFF;
}

double rb_bcu_demand_deceleration(const rb_bcu_params *p, const rb_brake_demand *d, double speed)
{
    int emergency = d->emergency > 0.5;
    if (!p->demand_tables) return emergency ? p->emergency_decel : d->service * p->service_decel;
    return emergency ? rb_speed_table_at(&p->emergency_profile, speed)
                     : d->service * rb_speed_table_at(&p->service_profile, speed);
}

/* Brake force car c must give (N, ED plus pneumatic) and the Pa per N of its pneumatic law. */
static double car_force(const rb_bcu_params *p, int c, int emergency, double service, double speed,
                        double *pa_per_n)
{
    if (!p->demand_tables) {
        *pa_per_n = p->pressure_gain[c];
        return (emergency ? p->emergency_decel : service * p->service_decel) * p->car_mass[c];
    }
    *pa_per_n = rb_speed_table_at(&p->pressure_per_newton[c], speed);
    return emergency ? rb_speed_table_at(&p->emergency_force[c], speed)
                     : service * rb_speed_table_at(&p->service_force[c], speed);
}

/* The service fraction after the jerk limit: towards the demanded one by at most the limit's
 * share of the full service deceleration over dt (s). Without a limit, the demand as it is. */
static double jerk_limited_service(const rb_bcu_params *p, rb_bcu_state *s, double demanded, double speed,
                                   double dt)
{
    if (!(p->service_jerk > 0.0)) return demanded;
    const rb_brake_demand full = {.emergency = 0.0, .service = 1.0};
    double a_full = rb_bcu_demand_deceleration(p, &full, speed);
    double step = a_full > 0.0 ? p->service_jerk * dt / a_full : 1.0;
    double x = s->service_applied;
    s->service_applied = demanded > x ? fmin(demanded, x + step) : fmax(demanded, x - step);
    return s->service_applied;
}

static void run_cycle(const rb_bcu_params *p, rb_bcu_state *s, const rb_brake_demand *d,
                      const rb_plant_outputs *out)
{
    int emergency = d->emergency > 0.5;
    double speed = rb_bcu_speed(out, p->n_cars);   /* the tables' speed: the fastest measured wheel */
    int ed_step = emergency ? p->ed_in_emergency : (p->demand_tables ? p->ed_in_service : 1);
    rb_wsp_inputs *w = &s->wsp_in;
    w->time = out->time;
    w->cycle = out->time - s->last_cycle;
    w->n_axles = p->n_cars * RB_AXLES_PER_CAR;
    w->atmosphere = p->atmosphere;
    w->body_decel = out->deceleration;
    double service = jerk_limited_service(p, s, d->service, speed, w->cycle);
    for (int c = 0; c < p->n_cars; ++c) {
        double gain = 0.0;
        double needed = car_force(p, c, emergency, service, speed, &gain);
        /* Blending: the ED brake is asked for the car's whole demand, also while the WSP acts (the
           traction control's own slide control governs the motor torque, faster than the air). The
           friction brake gets what the ED brake cannot give (its curve, its response, its loss),
           less what the slide control cut: that cut says the car brakes beyond its adhesion, and
           the friction brake gives way by as much, so the car brakes on the finely controlled ED
           brake again. Handing the cut to the friction brake instead (the former blending on the
           achieved force) fed the slide and kept the ED force cut. */
        int ed_allowed = p->motor[c] && ed_step;
        s->command.ed_demand[c] = ed_allowed ? needed : 0.0;
        double available = ed_allowed ? out->ed_available[c] : 0.0;
        double cut = ed_allowed && available > out->ed_force[c] ? available - out->ed_force[c] : 0.0;
        double ed = available + cut;
        s->command.pressure_demand[c] = car_pressure(p, c, gain, needed - ed);
        for (int k = 0; k < RB_AXLES_PER_CAR; ++k) {
            int a = c * RB_AXLES_PER_CAR + k;
            w->wheel_speed[a] = out->wheel_speed_measured[a];
            w->cylinder[a] = out->cylinder[a];
            w->demand[a] = s->command.pressure_demand[c];
        }
    }
    memset(&s->wsp, 0, sizeof s->wsp);
    if (p->wsp_enabled) {
        if (p->wsp) p->wsp(p->wsp_context, w, &s->wsp);
        else rb_wsp_default_step(&s->wsp_default, w, &s->wsp);
    }
    if (p->wsp_per_bogie) share_bogie_commands(&s->wsp, w->n_axles);
    memcpy(s->command.hold, s->wsp.hold, sizeof s->command.hold);
    memcpy(s->command.vent, s->wsp.vent, sizeof s->command.vent);
    s->last_cycle = out->time;
}

int rb_bcu_update(const rb_bcu_params *p, rb_bcu_state *s, const rb_brake_demand *demand,
                  const rb_plant_outputs *out)
{
    /* the emergency loop is a train line: it acts at once, not at the BCU's next cycle */
    double loop = demand->emergency > 0.5 ? 1.0 : 0.0;
    int changed = loop != s->command.emergency;
    s->command.emergency = loop;
    if (out->time < s->next_cycle - 1e-9) return changed;
    run_cycle(p, s, demand, out);
    s->next_cycle += p->cycle;
    return 1;
}

void rb_bcu_step(const rb_bcu_params *p, rb_bcu_state *s, const rb_brake_demand *demand,
                 const rb_plant_outputs *out, rb_plant_inputs *in)
{
    rb_bcu_update(p, s, demand, out);
    *in = s->command;
}

size_t rb_bcu_params_size(void) { return sizeof(rb_bcu_params); }

/* The plausibility bounds table (rb_bounds.h) and the checks built on it. */
#include "railbrake/rb_bounds.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The physical ranges are wide margins around typical values [T]: high-speed EMU cars of 40 to
 * 70 t, reservoirs of 50 to 400 l, cylinders of 0.5 to 5 l (EP-brake bogie units); the numerical
 * limits are derived in rb_bounds.h. */
static const rb_bound bounds[] = {
    {"car.mass", "kg", 5e3, 2e5, "a car of 5 to 200 t; lighter makes the couplers too stiff for dt"},
    {"coupler.stiffness", "N/m", 1e4, 1e9, "stable mechanics: dt sqrt(4 k / m) < 2 at 5 t"},
    {"coupler.damping", "N.s/m", 0.0, 2e6, "stable mechanics: dt 4 c / m < 2 at 5 t"},
    {"main_reservoir_volume", "m3", 0.01, 10.0, "10 l to 10 m3 of main reservoir"},
    {"car.supply_volume", "m3", 1e-3, 5.0, "1 l to 5 m3 of supply reservoir"},
    {"car.cylinder_volume", "m3", 1e-5, 0.1, "10 cm3 to 100 l per axle; smaller: R T / V unbounded"},
    {"car.pipe_volume", "m3", 1e-6, 5.0, "a finite pressure per kg of air"},
    {"car.pilot_volume", "m3", 1e-6, 1.0, "a finite pressure per kg of air"},
    {"car.relay_volume", "m3", 1e-6, 1.0, "a finite pressure per kg of air"},
    {"car.cylinder_area", "m2", 1e-4, 0.5, "a piston of 11 mm to 800 mm diameter"},
    {"car.hold_area", "m2", 0.0, 1e-3, "a valve port up to 36 mm diameter"},
    {"car.vent_area", "m2", 0.0, 1e-3, "a valve port up to 36 mm diameter"},
    {"car.valve_delay", "s", 0.0, 1.0, "a valve that responds within a second"},
    {"car.ep_tau", "s", 1e-4, 10.0, "an EP valve lag of 0.1 ms to 10 s"},
    {"car.supply_pressure", "Pa", 1.2e5, 1.2e6, "0.2 to 11 bar absolute (the model holds below 10 bar gauge)"},
    {"compressor_flow", "kg/s", 0.0, 1.0, "up to 50 m3/min of free air"},
    {"initial_speed", "m/s", 0.0, 150.0, "up to 540 km/h"},
    {"temperature", "K", 200.0, 400.0, "-73 to 127 degC"},
    {"bcu.cycle", "s", 1e-4, 0.1, "a BCU cycle of 0.1 to 100 ms"},
    {"bcu.service_decel", "m/s2", 0.0, 3.0, "up to 3 m/s2"},
    {"bcu.emergency_decel", "m/s2", 0.0, 3.0, "up to 3 m/s2"},
    {"wsp.ref_decel_max", "m/s2", 0.1, 10.0, "a reference speed that can follow a braking train"},
    {"wsp.ref_accel_max", "m/s2", 0.0, 10.0, "a bounded rise of the reference speed"},
    {"wsp.speed_threshold", "m/s", 0.01, 10.0, "a slide of 0.04 to 36 km/h starts venting"},
    {"wsp.slip_threshold", "1", 0.0, 0.5, "up to 50 % of the reference speed"},
    {"wsp.decel_threshold", "m/s2", 0.1, 100.0, "a positive wheel deceleration"},
    {"wsp.reaccel_threshold", "m/s2", 0.0, 100.0, "a non-negative wheel acceleration"},
    {"wsp.release_fraction", "1", 0.0, 1.0, "a fraction of the threshold"},
    {"wsp.reapply_on", "s", 1e-3, 1.0, "hold-valve pulses of 1 ms to 1 s"},
    {"wsp.reapply_off", "s", 1e-3, 1.0, "hold-valve pulses of 1 ms to 1 s"},
    {"wsp.reapply_time", "s", 0.0, 30.0, "full re-application within 30 s"},
    {"wsp.filter_time", "s", 1e-3, 1.0, "a filter of 1 ms to 1 s"},
    {"wsp.safety_time", "s", 0.5, 30.0, "0.5 to 30 s of continuous venting (typically 5-10 s [T]); 0 isolates every axle"},
    {"wsp.min_speed", "m/s", 0.0, 10.0, "WSP active down to at most 36 km/h"},
};

int rb_bound_count(void) { return (int)(sizeof bounds / sizeof bounds[0]); }

const rb_bound *rb_bound_at(int i) { return i >= 0 && i < rb_bound_count() ? &bounds[i] : NULL; }

const rb_bound *rb_bound_find(const char *name)
{
    for (int i = 0; name && i < rb_bound_count(); ++i)
        if (strcmp(bounds[i].name, name) == 0) return &bounds[i];
    return NULL;
}

rb_status rb_bound_check(rb_error *err, const char *name, const char *label, double value)
{
    const rb_bound *b = rb_bound_find(name);
    if (!b) return rb_fail(err, RB_EINVAL, "%s: no bound named %s (rb_bounds.c)", label, name);
    if (isfinite(value) && value >= b->min && value <= b->max) return RB_OK;
    return rb_fail(err, RB_EINVAL, "%s = %g %s: must be a finite number in [%g, %g] %s (%s)", label, value,
                   b->unit, b->min, b->max, b->unit, b->why);
}

#define CAR_BOUND(field)                                                                      \
    do {                                                                                      \
        snprintf(label, sizeof label, "car[%d].%s", i, #field);                               \
        if ((s = rb_bound_check(err, "car." #field, label, c->field))) return s;              \
    } while (0)

static rb_status car_bounds(const rb_plant_car *c, int i, rb_error *err)
{
    char label[64];
    rb_status s;
    snprintf(label, sizeof label, "car[%d].mass", i);
    if ((s = rb_bound_check(err, "car.mass", label, c->vehicle.mass))) return s;
    snprintf(label, sizeof label, "car[%d].supply_pressure", i);
    if ((s = rb_bound_check(err, "car.supply_pressure", label, c->vehicle.supply_pressure))) return s;
    snprintf(label, sizeof label, "car[%d].cylinder_area", i);
    if ((s = rb_bound_check(err, "car.cylinder_area", label, c->vehicle.brake.caliper.cylinder_area))) return s;
    CAR_BOUND(supply_volume);
    CAR_BOUND(cylinder_volume);
    CAR_BOUND(pipe_volume);
    CAR_BOUND(pilot_volume);
    CAR_BOUND(relay_volume);
    CAR_BOUND(hold_area);
    CAR_BOUND(vent_area);
    CAR_BOUND(valve_delay);
    CAR_BOUND(ep_tau);
    return RB_OK;
}

rb_status rb_plant_bounds_check(const rb_plant_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "params = NULL: plant parameters are required");
    if (p->n_cars < 1 || p->n_cars > RB_PLANT_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "n_cars = %d: must be in [1, %d]", p->n_cars, RB_PLANT_MAX_CARS);
    for (int i = 0; i < p->n_cars; ++i)
        if ((s = car_bounds(&p->car[i], i, err))) return s;
    if (p->n_cars > 1 &&
        ((s = rb_bound_check(err, "coupler.stiffness", "coupler.stiffness", p->coupler.stiffness)) ||
         (s = rb_bound_check(err, "coupler.damping", "coupler.damping", p->coupler.damping))))
        return s;
    if ((s = rb_bound_check(err, "main_reservoir_volume", "main_reservoir_volume", p->main_reservoir_volume)) ||
        (s = rb_bound_check(err, "compressor_flow", "compressor_flow", p->compressor_flow)) ||
        (s = rb_bound_check(err, "initial_speed", "initial_speed", p->initial_speed)) ||
        (s = rb_bound_check(err, "temperature", "temperature", p->temperature)))
        return s;
    return RB_OK;
}

#define WSP_BOUND(field)                                                                      \
    do {                                                                                      \
        if ((s = rb_bound_check(err, "wsp." #field, "wsp." #field, w->field))) return s;      \
    } while (0)

rb_status rb_wsp_check(const rb_wsp_params *w, rb_error *err)
{
    rb_status s;
    if (!w) return rb_fail(err, RB_EINVAL, "wsp = NULL: WSP parameters are required");
    WSP_BOUND(ref_decel_max);
    WSP_BOUND(ref_accel_max);
    WSP_BOUND(speed_threshold);
    WSP_BOUND(slip_threshold);
    WSP_BOUND(decel_threshold);
    WSP_BOUND(reaccel_threshold);
    WSP_BOUND(release_fraction);
    WSP_BOUND(reapply_on);
    WSP_BOUND(reapply_off);
    WSP_BOUND(reapply_time);
    WSP_BOUND(filter_time);
    WSP_BOUND(safety_time);
    WSP_BOUND(min_speed);
    return RB_OK;
}

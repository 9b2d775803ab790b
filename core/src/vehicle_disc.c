/* A dynamometer stop of one disc with its pads (rb_vehicle.h): the pad friction law and the
 * two-node disc as the plant uses them, at a constant pad force, the way bench tests of pads
 * (UIC 541-3, EN 15328) run their stops and average their friction. */
#include "railbrake/rb_vehicle.h"

#include <math.h>

static rb_status check_stop(const rb_dyno_stop *d, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "dyno.initial_speed", d->initial_speed)) ||
        (s = rb_check_range(err, "dyno.initial_speed", d->initial_speed, 0.0, 200.0)) ||
        (s = rb_check_positive(err, "dyno.mass", d->mass)) ||
        (s = rb_check_positive(err, "dyno.pad_force", d->pad_force)) ||
        (s = rb_check_positive(err, "dyno.friction_radius", d->friction_radius)) ||
        (s = rb_check_positive(err, "dyno.wheel_radius", d->wheel_radius)) ||
        (s = rb_check_positive(err, "dyno.heat_capacity", d->heat_capacity)) ||
        (s = rb_check_range(err, "dyno.ambient_temperature", d->ambient_temperature, 200.0, 350.0)) ||
        (s = rb_check_positive(err, "dyno.dt", d->dt)) ||
        (s = rb_check_range(err, "dyno.dt", d->dt, 0.0, 0.1)))
        return s;
    if (!(d->surface_capacity >= 0.0 && d->surface_capacity < d->heat_capacity))
        return rb_fail(err, RB_EINVAL, "dyno.surface_capacity = %g J/K: must lie in [0, heat_capacity = %g J/K)",
                       d->surface_capacity, d->heat_capacity);
    if ((s = d->surface_capacity > 0.0 ? rb_check_positive(err, "dyno.surface_conductance", d->surface_conductance)
                                       : rb_check_nonnegative(err, "dyno.surface_conductance", d->surface_conductance)))
        return s;
    if (d->cooling.n > 0 && (s = rb_speed_table_check(&d->cooling, "dyno.cooling", 0.0, 1e5, err)))
        return s;
    return RB_OK;
}

rb_status rb_dyno_stop_run(const rb_pad_friction *pad, const rb_dyno_stop *d, rb_dyno_result *out, rb_error *err)
{
    rb_status s;
    if ((s = rb_pad_friction_check(pad, err)) || (s = check_stop(d, err)))
        return s;
    const double layered = d->surface_capacity > 0.0;
    const double cs = layered ? d->surface_capacity : d->heat_capacity, cb = layered ? d->heat_capacity - cs : 0.0;
    const double conductance = layered ? d->surface_conductance : 0.0;
    /* rail force per unit friction: 2 pads at the friction radius, seen at the wheel */
    const double force_per_mu = 2.0 * d->pad_force * d->friction_radius / d->wheel_radius;
    double v = d->initial_speed, ts = d->ambient_temperature, tb = d->ambient_temperature;
    double t = 0.0, x = 0.0, mu_x = 0.0, heat = 0.0, cooled = 0.0;
    out->max_surface_temperature = out->max_mean_temperature = d->ambient_temperature;
    /* at most 1e7 steps: a stop of 1e6 s at the largest dt, beyond any real one */
    for (long i = 0; v > 0.0 && i < 10000000L; ++i) {
        double mu = rb_pad_friction_eval(pad, v, ts);
        double decel = mu * force_per_mu / d->mass, dt = d->dt;
        double v_next = v - decel * dt;
        if (!(v_next > 0.0)) {   /* stops within the step: its rest, at the same deceleration */
            dt = decel > 0.0 ? v / decel : dt;
            v_next = 0.0;
        }
        /* the work of the step's force over its distance, m (v^2 - v'^2) / 2: the kinetic energy, exactly */
        double ds = 0.5 * (v + v_next) * dt, work = mu * force_per_mu * ds;
        double h = d->cooling.n > 0 ? rb_speed_table_at(&d->cooling, v) : 0.0;
        double to_bulk = rb_disc_to_bulk(cb, conductance, dt);
        double inverse = rb_disc_inverse(cs, cb, h, to_bulk, dt);
        rb_disc_step(cs, cb * to_bulk, to_bulk, inverse, dt, work / dt, h * d->ambient_temperature, &ts, &tb);
        cooled += dt * h * (ts - d->ambient_temperature);
        heat += work;
        mu_x += mu * ds;
        x += ds;
        t += dt;
        v = v_next;
        double mean = layered ? (cs * ts + cb * tb) / (cs + cb) : ts;
        out->max_surface_temperature = ts > out->max_surface_temperature ? ts : out->max_surface_temperature;
        out->max_mean_temperature = mean > out->max_mean_temperature ? mean : out->max_mean_temperature;
    }
    if (v > 0.0)
        return rb_fail(err, RB_EINVAL, "dyno: no stop within 1e7 steps (speed still %g m/s): pads too weak", v);
    out->mean_friction = x > 0.0 ? mu_x / x : 0.0;
    out->heat = heat;
    out->stored = cs * (ts - d->ambient_temperature) + cb * (tb - d->ambient_temperature);
    out->cooled = cooled;
    out->distance = x;
    out->time = t;
    return RB_OK;
}

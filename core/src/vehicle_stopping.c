/* Stopping distance, integrated in time in the manner of EN 14531: a response phase (delay and
 * build-up, or the equivalent response time te = ta + tb/2), then the braked run to v_end. */
#include "railbrake/rb_vehicle.h"

#include <math.h>

/* Deceleration (m/s^2, positive slowing) at speed v with brake effort 0..1 on a gradient. */
typedef double (*decel_fn)(const void *ctx, double speed, double effort, double gradient);

/* The gradient at distance s from the brake's start: the piecewise profile if given. */
static double gradient_at(const rb_stop_options *o, double s)
{
    if (o->n_gradients <= 0)
        return o->gradient;
    int i = 0;
    while (i + 1 < o->n_gradients && s >= o->gradient_start[i + 1])
        ++i;
    return o->gradient_value[i];
}

/* Brake effort at time t; t_mid is the middle of the current step, which never straddles a
 * break point, so the step response of the equivalent mode is taken from its side of te. */
static double effort_at(const rb_stop_options *o, double t, double t_mid)
{
    if (o->equivalent_response)
        return t_mid >= o->delay + 0.5 * o->build_up ? 1.0 : 0.0;
    if (t <= o->delay)
        return 0.0;
    if (t >= o->delay + o->build_up)
        return 1.0;
    return (t - o->delay) / o->build_up;
}

/* Length of the step from t: dt, cut at the next break point (ta, te, ta + tb). */
static double step_length(const rb_stop_options *o, double t)
{
    const double breaks[3] = {o->delay, o->delay + 0.5 * o->build_up, o->delay + o->build_up};
    double h = o->dt;
    for (int i = 0; i < 3; ++i)
        if (breaks[i] > t + 1e-12 && breaks[i] < t + h)
            h = breaks[i] - t;
    return h;
}

static rb_status check_options(const rb_stop_options *o, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "v0", o->v0)) != RB_OK ||
        (s = rb_check_range(err, "v_end", o->v_end, 0.0, o->v0 * (1.0 - 1e-9))) != RB_OK ||
        (s = rb_check_range(err, "gradient", o->gradient, -0.1, 0.1)) != RB_OK ||
        (s = rb_check_nonnegative(err, "delay", o->delay)) != RB_OK ||
        (s = rb_check_nonnegative(err, "build_up", o->build_up)) != RB_OK ||
        (s = rb_check_range(err, "dt", o->dt, 1e-5, 1.0)) != RB_OK ||
        (s = rb_check_range(err, "dt_out", o->dt_out, o->dt, 1e3)) != RB_OK ||
        (s = rb_check_positive(err, "t_max", o->t_max)) != RB_OK)
        return s;
    if (o->n_gradients < 0 || o->n_gradients > RB_MAX_STOP_GRADIENTS)
        return rb_fail(err, RB_EINVAL, "n_gradients = %d: must be in [0, %d]", o->n_gradients,
                       RB_MAX_STOP_GRADIENTS);
    for (int i = 0; i < o->n_gradients; ++i) {
        if ((s = rb_check_range(err, "gradient_value", o->gradient_value[i], -0.1, 0.1)) != RB_OK)
            return s;
        if (i > 0 && !(o->gradient_start[i] > o->gradient_start[i - 1]))
            return rb_fail(err, RB_EINVAL, "gradient_start[%d] = %g m: must exceed gradient_start[%d] = %g m",
                           i, o->gradient_start[i], i - 1, o->gradient_start[i - 1]);
    }
    if (o->equivalent_response != 0 && o->equivalent_response != 1)
        return rb_fail(err, RB_EINVAL, "equivalent_response = %d: must be 0 or 1",
                       o->equivalent_response);
    return RB_OK;
}

typedef struct {
    double *time, *speed, *distance;
    size_t capacity, n;
    double next;  /* time of the next recorded point */
    double dt_out;
} recorder;

static rb_status record(recorder *r, double t, double v, double s, int force, rb_error *err)
{
    if (!force && t < r->next)
        return RB_OK;
    if (r->n >= r->capacity)
        return rb_fail(err, RB_ESIZE, "capacity = %zu: too few points for the curve at dt_out = %g s",
                       r->capacity, r->dt_out);
    r->time[r->n] = t;
    r->speed[r->n] = v;
    r->distance[r->n] = s;
    r->n++;
    while (r->next <= t)
        r->next += r->dt_out;
    return RB_OK;
}

/* One classical Runge-Kutta step of dv/dt = -a(v, effort(t)), ds/dt = v. */
static void rk4_step(decel_fn a, const void *ctx, const rb_stop_options *o, double t, double h,
                     double *v, double *s)
{
    double g = gradient_at(o, *s);   /* held over the step (a few metres at most) */
    double tm = t + 0.5 * h;
    double k1 = -a(ctx, *v, effort_at(o, t, tm), g);
    double k2 = -a(ctx, *v + 0.5 * h * k1, effort_at(o, tm, tm), g);
    double k3 = -a(ctx, *v + 0.5 * h * k2, effort_at(o, tm, tm), g);
    double k4 = -a(ctx, *v + h * k3, effort_at(o, t + h, tm), g);
    *s += h * (*v + h * (k1 + k2 + k3) / 6.0);
    *v += h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
}

/* Called after each step from t over h with the speeds at its ends (NULL: nothing to follow). */
typedef void (*after_fn)(void *ctx, double t, double h, double v_start, double v_end);

static rb_status integrate(decel_fn a, void *ctx, after_fn after, const rb_stop_options *o, recorder *rec,
                           double *distance_out, double *time_out, rb_error *err)
{
    double t = 0.0, v = o->v0, s = 0.0;
    rb_status st = record(rec, t, v, s, 1, err);
    while (st == RB_OK) {
        if (t > o->t_max)
            return rb_fail(err, RB_ENOCONV, "t_max = %g s: the train has not slowed to v_end = %g m/s "
                           "(speed %g m/s)", o->t_max, o->v_end, v);
        double h = step_length(o, t);
        double a0 = a(ctx, v, effort_at(o, t, t + 0.5 * h), gradient_at(o, s));
        double v1 = v, s1 = s;
        rk4_step(a, ctx, o, t, h, &v1, &s1);
        if (a0 > 0.0 && (v1 <= o->v_end || v - a0 * h <= o->v_end)) {
            /* last step: hold the local deceleration to the end speed */
            t += (v - o->v_end) / a0;
            s += (v * v - o->v_end * o->v_end) / (2.0 * a0);
            if ((st = record(rec, t, o->v_end, s, 1, err)) != RB_OK)
                return st;
            *distance_out = s;
            *time_out = t;
            return RB_OK;
        }
        if (after)
            after(ctx, t, h, v, v1);
        t += h;
        v = v1;
        s = s1;
        st = record(rec, t, v, s, 0, err);
    }
    return st;
}

/* ------------------------------------------------------------------ the whole train */

typedef struct {
    const rb_train *train;
    const rb_brake_command *cmd;
    double gradient;
    double p_atm_motor, p_atm_trailer;
    /* the discs (NULL: cold pads): each car's surface and bulk temperatures, the pads' fading */
    const rb_train_discs *discs;
    const rb_stop_options *options;
    double surface[RB_MAX_CARS], bulk[RB_MAX_CARS], fade[RB_MAX_CARS];
    double max_surface;
} train_ctx;

static double pressure_at(const rb_speed_table *table, double p_atm, double speed)
{
    return table->n > 0 ? rb_speed_table_at(table, speed) : p_atm;
}

static rb_brake_state brake_state(const train_ctx *c, double speed, double effort)
{
    rb_brake_state state = {pressure_at(&c->cmd->p_motor, c->p_atm_motor, speed),
                            pressure_at(&c->cmd->p_trailer, c->p_atm_trailer, speed),
                            c->cmd->ed_mode,
                            c->cmd->ed_mode == RB_ED_BLENDED ? rb_speed_table_at(&c->cmd->ed_demand, speed) : 0.0,
                            effort, {0.0}};
    for (int k = 0; k < c->train->n_cars; ++k) state.fade[k] = c->fade[k];
    return state;
}

static double train_decel(const void *ctx, double speed, double effort, double gradient)
{
    const train_ctx *c = ctx;
    rb_brake_state state = brake_state(c, speed, effort);
    return rb_train_deceleration(c->train, &state, speed, gradient, NULL);
}

/* After a step: each car's discs take its pneumatic brake's power at the step's mean speed and
   effort (rail force x speed, shared by its axles), and the pads' fading follows the surface. */
static void heat_discs(void *ctx, double t, double h, double v_start, double v_end)
{
    train_ctx *c = ctx;
    const rb_train_discs *d = c->discs;
    const double v = 0.5 * (v_start + v_end);
    const double effort = effort_at(c->options, t + 0.5 * h, t + 0.5 * h);
    for (int k = 0; k < c->train->n_cars; ++k) {
        const rb_car *car = &c->train->cars[k];
        if (!(d->heat_capacity[k] > 0.0))
            continue;
        double p = car->motor ? pressure_at(&c->cmd->p_motor, c->p_atm_motor, v)
                              : pressure_at(&c->cmd->p_trailer, c->p_atm_trailer, v);
        double p_atm = car->brake.caliper.atmospheric_pressure;
        double torque = rb_axle_brake_torque(&car->brake, p_atm + effort * (p - p_atm), v) / (1.0 + c->fade[k]);
        double power = torque / car->wheelset.wheel_radius * v;   /* per axle */
        const int layered = d->surface_capacity[k] > 0.0;
        const double cs = layered ? d->surface_capacity[k] : d->heat_capacity[k];
        const double cb = layered ? d->heat_capacity[k] - cs : 0.0;
        const double cooling = d->cooling[k].n > 0 ? rb_speed_table_at(&d->cooling[k], v) : 0.0;
        const double to_bulk = rb_disc_to_bulk(cb, layered ? d->surface_conductance[k] : 0.0, h);
        rb_disc_step(cs, cb * to_bulk, to_bulk, rb_disc_inverse(cs, cb, cooling, to_bulk, h), h, power,
                     cooling * d->ambient_temperature, &c->surface[k], &c->bulk[k]);
        double hot = c->surface[k] - car->brake.pad.fade_onset;
        c->fade[k] = hot > 0.0 ? car->brake.pad.fade_rate * hot : 0.0;
        c->max_surface = c->surface[k] > c->max_surface ? c->surface[k] : c->max_surface;
    }
}

static rb_status check_discs(const rb_train *t, const rb_train_discs *d, rb_error *err)
{
    rb_status s = rb_check_range(err, "discs.ambient_temperature", d->ambient_temperature, 200.0, 350.0);
    for (int k = 0; s == RB_OK && k < t->n_cars; ++k) {
        if (!(d->heat_capacity[k] >= 0.0) || !(d->surface_capacity[k] >= 0.0) ||
            (d->heat_capacity[k] > 0.0 && !(d->surface_capacity[k] < d->heat_capacity[k])) ||
            !(d->surface_conductance[k] >= 0.0) || (d->surface_capacity[k] > 0.0 && !(d->surface_conductance[k] > 0.0)))
            return rb_fail(err, RB_EINVAL, "discs of cars[%d]: heat_capacity = %g J/K, surface_capacity = %g J/K, "
                           "surface_conductance = %g W/K: need capacities >= 0, the surface's below the disc's, and "
                           "a conductance > 0 with a surface layer", k, d->heat_capacity[k], d->surface_capacity[k],
                           d->surface_conductance[k]);
        if (d->cooling[k].n > 0)
            s = rb_speed_table_check(&d->cooling[k], "discs.cooling", 0.0, 1e5, err);
    }
    return s;
}

/* Checks a pressure table of one car type against [atmospheric, supply] of those cars. */
static rb_status check_pressure_table(const rb_train *t, int motor, const rb_speed_table *table,
                                      const char *name, double *p_atm, rb_error *err)
{
    double lo = 0.0, hi = HUGE_VAL;
    for (int k = 0; k < t->n_cars; ++k) {
        const rb_car *c = &t->cars[k];
        if (c->motor != motor)
            continue;
        lo = fmax(lo, c->brake.caliper.atmospheric_pressure);
        hi = fmin(hi, c->supply_pressure);
    }
    *p_atm = lo;
    if (table->n == 0 || hi == HUGE_VAL)
        return RB_OK;
    return rb_speed_table_check(table, name, lo, hi, err);
}

rb_status rb_stop_train(const rb_train *t, const rb_brake_command *cmd, const rb_stop_options *o,
                        double *time, double *speed, double *distance, size_t capacity,
                        size_t *n_out, double *distance_out, double *time_out, rb_error *err)
{
    return rb_stop_train_heated(t, cmd, NULL, o, time, speed, distance, capacity, n_out, distance_out, time_out,
                                NULL, err);
}

rb_status rb_stop_train_heated(const rb_train *t, const rb_brake_command *cmd, const rb_train_discs *discs,
                               const rb_stop_options *o, double *time, double *speed, double *distance,
                               size_t capacity, size_t *n_out, double *distance_out, double *time_out,
                               double *max_surface_temperature, rb_error *err)
{
    static train_ctx ctx_zero;
    train_ctx ctx = ctx_zero;
    ctx.train = t;
    ctx.cmd = cmd;
    ctx.gradient = o->gradient;
    ctx.discs = discs;
    ctx.options = o;
    rb_status s;
    if ((s = rb_train_check(t, err)) != RB_OK || (s = check_options(o, err)) != RB_OK ||
        (s = check_pressure_table(t, 1, &cmd->p_motor, "p_motor", &ctx.p_atm_motor, err)) != RB_OK ||
        (s = check_pressure_table(t, 0, &cmd->p_trailer, "p_trailer", &ctx.p_atm_trailer, err)) != RB_OK)
        return s;
    if (cmd->ed_mode < RB_ED_OFF || cmd->ed_mode > RB_ED_BLENDED)
        return rb_fail(err, RB_EINVAL, "ed_mode = %d: must be 0 (off), 1 (max) or 2 (blended)",
                       cmd->ed_mode);
    if (cmd->ed_mode == RB_ED_BLENDED &&
        (s = rb_speed_table_check(&cmd->ed_demand, "ed_demand", 0.0, 5.0, err)) != RB_OK)
        return s;
    if (discs && (s = check_discs(t, discs, err)) != RB_OK)
        return s;
    ctx.max_surface = discs ? discs->ambient_temperature : 0.0;
    for (int k = 0; discs && k < t->n_cars; ++k) ctx.surface[k] = ctx.bulk[k] = discs->ambient_temperature;
    recorder rec = {time, speed, distance, capacity, 0, 0.0, o->dt_out};
    s = integrate(train_decel, &ctx, discs ? heat_discs : NULL, o, &rec, distance_out, time_out, err);
    *n_out = rec.n;
    if (max_surface_temperature)
        *max_surface_temperature = ctx.max_surface;
    return s;
}

/* ------------------------------------------------------------------ a given deceleration */

static double profile_decel(const void *ctx, double speed, double effort, double gradient)
{
    (void)gradient;   /* the profile is the deceleration itself */
    return effort * rb_speed_table_at((const rb_speed_table *)ctx, speed);
}

rb_status rb_stop_profile(const rb_speed_table *decel, const rb_stop_options *o, double *time,
                          double *speed, double *distance, size_t capacity, size_t *n_out,
                          double *distance_out, double *time_out, rb_error *err)
{
    rb_status s;
    if ((s = check_options(o, err)) != RB_OK ||
        (s = rb_speed_table_check(decel, "deceleration", 1e-3, 5.0, err)) != RB_OK)
        return s;
    recorder rec = {time, speed, distance, capacity, 0, 0.0, o->dt_out};
    s = integrate(profile_decel, (void *)decel, NULL, o, &rec, distance_out, time_out, err);
    *n_out = rec.n;
    return s;
}

rb_status rb_stop_constant(double v0, double deceleration, double response_time,
                           double *distance_out, double *time_out, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "v0", v0)) != RB_OK ||
        (s = rb_check_positive(err, "deceleration", deceleration)) != RB_OK ||
        (s = rb_check_nonnegative(err, "response_time", response_time)) != RB_OK)
        return s;
    *distance_out = v0 * response_time + v0 * v0 / (2.0 * deceleration);
    *time_out = response_time + v0 / deceleration;
    return RB_OK;
}

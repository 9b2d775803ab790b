/* Rolling stock: wheelset, running resistance, ED brake, coupler, cars, the whole-train
 * force balance and its blending rule. */
#include "railbrake/rb_vehicle.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

double rb_wheelset_equivalent_mass(const rb_wheelset *w)
{
    return w->inertia / (w->wheel_radius * w->wheel_radius);
}

rb_status rb_wheelset_check(const rb_wheelset *w, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_range(err, "wheelset.wheel_radius", w->wheel_radius, 0.1, 1.0)) != RB_OK ||
        (s = rb_check_nonnegative(err, "wheelset.inertia", w->inertia)) != RB_OK ||
        (s = rb_check_positive(err, "wheelset.axle_load", w->axle_load)) != RB_OK)
        return s;
    return RB_OK;
}

rb_status rb_equivalent_rotating_mass(const rb_wheelset *w, size_t n, double *out, rb_error *err)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        rb_status s = rb_wheelset_check(&w[i], err);
        if (s != RB_OK)
            return s;
        sum += rb_wheelset_equivalent_mass(&w[i]);
    }
    *out = sum;
    return RB_OK;
}

double rb_running_resistance(const rb_resistance *r, double speed)
{
    return rb_running_resistance_law(r, speed);
}

rb_status rb_resistance_check(const rb_resistance *r, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_nonnegative(err, "resistance.A", r->A)) != RB_OK ||
        (s = rb_check_nonnegative(err, "resistance.B", r->B)) != RB_OK ||
        (s = rb_check_nonnegative(err, "resistance.C", r->C)) != RB_OK)
        return s;
    return RB_OK;
}

double rb_ed_brake_force_max(const rb_ed_curve *e, double speed)
{
    if (e->table.n <= 0 && e->terms <= 0)
        return 0.0;
    double force = e->table.n > 0 ? rb_speed_table_at(&e->table, speed) : HUGE_VAL;
    for (int k = 0; k < e->terms; ++k) {
        double branch = e->c0[k] + e->c1[k] * speed;
        if (e->c2[k] != 0.0)
            branch = speed > 0.0 ? branch + e->c2[k] / speed : HUGE_VAL;
        if (branch < force)
            force = branch;
    }
    if (e->fade_speed > 0.0 && speed < e->fade_speed)
        force *= speed / e->fade_speed;
    force *= e->scale;
    return force > 0.0 ? force : 0.0;
}

rb_status rb_ed_curve_check(const rb_ed_curve *e, rb_error *err)
{
    if (e->table.n != 0) {
        rb_status s = rb_speed_table_check(&e->table, "ed.table", 0.0, 1e9, err);
        if (s != RB_OK)
            return s;
    }
    if (e->terms < 0 || e->terms > RB_MAX_ED_TERMS)
        return rb_fail(err, RB_EINVAL, "ed.terms = %d: must lie in [0, %d]", e->terms, RB_MAX_ED_TERMS);
    char field[48];
    for (int k = 0; k < e->terms; ++k) {
        const double *coef[3] = {&e->c0[k], &e->c1[k], &e->c2[k]};
        for (int j = 0; j < 3; ++j) {
            snprintf(field, sizeof field, "ed.c%d[%d]", j, k);
            rb_status s = rb_check_finite(err, field, *coef[j]);
            if (s != RB_OK)
                return s;
        }
    }
    rb_status s;
    if ((s = rb_check_nonnegative(err, "ed.scale", e->scale)) != RB_OK ||
        (s = rb_check_nonnegative(err, "ed.fade_speed", e->fade_speed)) != RB_OK)
        return s;
    return RB_OK;
}

double rb_coupler_force(const rb_coupler *c, double dx, double dv)
{
    return rb_coupler_force_law(c, dx, dv);
}

rb_status rb_coupler_check(const rb_coupler *c, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_nonnegative(err, "coupler.slack", c->slack)) != RB_OK ||
        (s = rb_check_positive(err, "coupler.stiffness", c->stiffness)) != RB_OK ||
        (s = rb_check_nonnegative(err, "coupler.stiffness_cubic", c->stiffness_cubic)) != RB_OK ||
        (s = rb_check_nonnegative(err, "coupler.damping", c->damping)) != RB_OK)
        return s;
    return RB_OK;
}

/* ------------------------------------------------------------------ cars and trains */

rb_status rb_car_check(const rb_car *c, rb_error *err)
{
    if (c->motor != 0 && c->motor != 1)
        return rb_fail(err, RB_EINVAL, "motor = %d: must be 0 (trailer) or 1 (motor car)", c->motor);
    if (c->axles < 1 || c->axles > RB_MAX_AXLES)
        return rb_fail(err, RB_EINVAL, "axles = %d: must lie in [1, %d]", c->axles, RB_MAX_AXLES);
    rb_status s;
    if ((s = rb_check_positive(err, "mass", c->mass)) != RB_OK ||
        (s = rb_wheelset_check(&c->wheelset, err)) != RB_OK ||
        (s = rb_axle_brake_check(&c->brake, err)) != RB_OK ||
        (s = rb_ed_curve_check(&c->ed, err)) != RB_OK)
        return s;
    double p_atm = c->brake.caliper.atmospheric_pressure;
    if (!(c->supply_pressure > p_atm) || !isfinite(c->supply_pressure))
        return rb_fail(err, RB_EINVAL,
                       "supply_pressure = %g Pa: must be finite and above atmospheric (%g Pa)",
                       c->supply_pressure, p_atm);
    return RB_OK;
}

/* Prefixes the message in err with "cars[k]." so it names the car. */
static rb_status name_car(rb_error *err, rb_status s, int k)
{
    if (err && s != RB_OK) {
        char tail[RB_ERROR_MESSAGE_SIZE];
        memcpy(tail, err->message, sizeof tail);
        snprintf(err->message, sizeof err->message, "cars[%d].%.200s", k, tail);
    }
    return s;
}

rb_status rb_train_check(const rb_train *t, rb_error *err)
{
    if (t->n_cars < 1 || t->n_cars > RB_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "n_cars = %d: must lie in [1, %d]", t->n_cars, RB_MAX_CARS);
    for (int k = 0; k < t->n_cars; ++k) {
        rb_status s = rb_car_check(&t->cars[k], err);
        if (s != RB_OK)
            return name_car(err, s, k);
    }
    return rb_resistance_check(&t->resistance, err);
}

static double car_rotating_mass(const rb_car *c)
{
    return c->axles * rb_wheelset_equivalent_mass(&c->wheelset);
}

double rb_train_mass(const rb_train *t)
{
    double m = 0.0;
    for (int k = 0; k < t->n_cars; ++k)
        m += t->cars[k].mass;
    return m;
}

double rb_train_rotating_mass(const rb_train *t)
{
    double m = 0.0;
    for (int k = 0; k < t->n_cars; ++k)
        m += car_rotating_mass(&t->cars[k]);
    return m;
}

double rb_train_ed_force_max(const rb_train *t, double speed)
{
    double f = 0.0;
    for (int k = 0; k < t->n_cars; ++k)
        if (t->cars[k].motor)
            f += rb_ed_brake_force_max(&t->cars[k].ed, speed);
    return f;
}

static double gravity_along_track(double mass, double gradient)
{
    return mass * RB_GRAVITY * gradient / sqrt(1.0 + gradient * gradient);
}

double rb_car_brake_demand(const rb_train *t, int car, double speed, double deceleration,
                           double gradient)
{
    const rb_car *c = &t->cars[car];
    double share = c->mass / rb_train_mass(t);
    return (c->mass + car_rotating_mass(c)) * deceleration -
           share * rb_running_resistance(&t->resistance, speed) - gravity_along_track(c->mass, gradient);
}

/* ED force of car k in state s (motor cars only). */
static double car_ed_force(const rb_train *t, int k, const rb_brake_state *s, double speed,
                           double gradient)
{
    const rb_car *c = &t->cars[k];
    if (!c->motor || s->ed_mode == RB_ED_OFF)
        return 0.0;
    double f = rb_ed_brake_force_max(&c->ed, speed);
    if (s->ed_mode == RB_ED_BLENDED) {
        double demand = rb_car_brake_demand(t, k, speed, s->ed_demand, gradient);
        f = demand < f ? (demand > 0.0 ? demand : 0.0) : f;
    }
    return s->effort * f;
}

/* Pneumatic brake force of car k at the rails (sum over axles of T / r). */
static double car_pneumatic_force(const rb_car *c, double pressure, double effort, double speed)
{
    double p_atm = c->brake.caliper.atmospheric_pressure;
    double p = p_atm + effort * (pressure - p_atm);
    return c->axles * rb_axle_brake_torque(&c->brake, p, speed) / c->wheelset.wheel_radius;
}

double rb_train_deceleration(const rb_train *t, const rb_brake_state *s, double speed,
                             double gradient, double *brake_force)
{
    double brake = 0.0;
    for (int k = 0; k < t->n_cars; ++k) {
        const rb_car *c = &t->cars[k];
        double p = c->motor ? s->p_motor : s->p_trailer;
        brake += car_pneumatic_force(c, p, s->effort, speed) / (1.0 + s->fade[k]) + car_ed_force(t, k, s, speed, gradient);
    }
    if (brake_force)
        *brake_force = brake;
    double m = rb_train_mass(t);
    double resist = rb_running_resistance(&t->resistance, speed) + gravity_along_track(m, gradient);
    return (brake + resist) / (m + rb_train_rotating_mass(t));
}

/* Fails if pressure p (type motor or trailer) lies below atmospheric or above a car's supply. */
static rb_status check_pressure(const rb_train *t, int motor, double p, const char *name,
                                size_t i, double speed, rb_error *err)
{
    for (int k = 0; k < t->n_cars; ++k) {
        const rb_car *c = &t->cars[k];
        if (c->motor != motor)
            continue;
        double lo = c->brake.caliper.atmospheric_pressure;
        if (!isfinite(p) || p < lo || p > c->supply_pressure)
            return rb_fail(err, RB_EINVAL,
                           "%s[%zu] = %g Pa at %g m/s: must lie in [%g, %g] Pa "
                           "(atmospheric to the supply pressure of cars[%d])",
                           name, i, p, speed, lo, c->supply_pressure, k);
    }
    return RB_OK;
}

rb_status rb_train_deceleration_curve(const rb_train *t, const double *speed, const double *p_motor,
                                      const double *p_trailer, int ed_mode,
                                      const double *ed_demand, size_t n, double gradient,
                                      double *decel, rb_error *err)
{
    rb_status s = rb_train_check(t, err);
    if (s != RB_OK)
        return s;
    if (ed_mode < RB_ED_OFF || ed_mode > RB_ED_BLENDED)
        return rb_fail(err, RB_EINVAL, "ed_mode = %d: must be 0 (off), 1 (max) or 2 (blended)", ed_mode);
    if (ed_mode == RB_ED_BLENDED && !ed_demand)
        return rb_fail(err, RB_EINVAL, "ed_demand = NULL: required with ed_mode = 2 (blended)");
    if ((s = rb_check_finite(err, "gradient", gradient)) != RB_OK)
        return s;
    for (size_t i = 0; i < n; ++i) {
        char field[48];
        snprintf(field, sizeof field, "speed[%zu]", i);
        if ((s = rb_check_nonnegative(err, field, speed[i])) != RB_OK ||
            (s = check_pressure(t, 1, p_motor[i], "p_motor", i, speed[i], err)) != RB_OK ||
            (s = check_pressure(t, 0, p_trailer[i], "p_trailer", i, speed[i], err)) != RB_OK)
            return s;
        rb_brake_state state = {p_motor[i], p_trailer[i], ed_mode,
                                ed_mode == RB_ED_BLENDED ? ed_demand[i] : 0.0, 1.0, {0.0}};
        decel[i] = rb_train_deceleration(t, &state, speed[i], gradient, NULL);
    }
    return RB_OK;
}

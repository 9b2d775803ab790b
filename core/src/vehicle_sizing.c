/* Inverse computation: the cylinder pressure per car type that gives a demanded deceleration. */
#include "railbrake/rb_vehicle.h"

#include <math.h>
#include <stdio.h>

/* Pneumatic force of a car at the rails is gain * max(0, p - threshold) (lambda depends on v
 * only): gain = axles * discs * 2 R_mean lambda(v) * lever * eta * A / r,
 * threshold = p_atm + F_spring / A. This is rb_axle_brake_torque solved for the pressure. */
typedef struct {
    double gain;       /* N/Pa */
    double threshold;  /* Pa abs */
} affine_brake;

static affine_brake car_affine(const rb_car *c, double speed)
{
    const rb_axle_brake *b = &c->brake;
    const rb_caliper *cal = &b->caliper;
    affine_brake a;
    a.gain = c->axles * b->discs * 2.0 * b->mean_radius * rb_pad_friction_at(&b->pad, speed) *
             cal->lever_ratio * cal->efficiency * cal->cylinder_area / c->wheelset.wheel_radius;
    a.threshold = cal->atmospheric_pressure + cal->return_spring / cal->cylinder_area;
    return a;
}

/* Solves sum_k gain_k max(0, p - threshold_k) = demand for p over the cars of one type: with the
 * thresholds in ascending order, the cars engaged at the solution are a leading run of them. */
static double solve_type_pressure(const rb_train *t, int motor, double speed, double demand)
{
    affine_brake a[RB_MAX_CARS];
    int m = 0;
    double p_atm = NAN;
    for (int k = 0; k < t->n_cars; ++k) {
        if (t->cars[k].motor != motor)
            continue;
        affine_brake x = car_affine(&t->cars[k], speed);
        int j = m++;
        for (; j > 0 && a[j - 1].threshold > x.threshold; --j)
            a[j] = a[j - 1];
        a[j] = x;
        p_atm = t->cars[k].brake.caliper.atmospheric_pressure;
    }
    if (m == 0 || demand <= 0.0)
        return p_atm;  /* NaN when the train has no car of this type */
    double gain = 0.0, weighted = 0.0, p = p_atm;
    for (int j = 0; j < m; ++j) {
        gain += a[j].gain;
        weighted += a[j].gain * a[j].threshold;
        p = (demand + weighted) / gain;
        if (j + 1 == m || p <= a[j + 1].threshold)
            break;
    }
    return p;
}

/* Pneumatic force of car c at pressure p, from the same affine form. */
static double car_pneumatic(const rb_car *c, double speed, double p)
{
    affine_brake a = car_affine(c, speed);
    return p > a.threshold ? a.gain * (p - a.threshold) : 0.0;
}

static void size_one_speed(const rb_train *t, double v, double a, double gradient, int ed_on,
                           double *p_motor, double *p_trailer, double *ed_total, double *adhesion)
{
    double ed[RB_MAX_CARS], demand[2] = {0.0, 0.0};  /* pneumatic demand: [trailer, motor] */
    *ed_total = 0.0;
    for (int k = 0; k < t->n_cars; ++k) {
        const rb_car *c = &t->cars[k];
        double f = rb_car_brake_demand(t, k, v, a, gradient);
        ed[k] = 0.0;
        if (c->motor && ed_on) {
            double max = rb_ed_brake_force_max(&c->ed, v);
            ed[k] = f < max ? (f > 0.0 ? f : 0.0) : max;
        }
        demand[c->motor] += f - ed[k];
        *ed_total += ed[k];
    }
    *p_motor = solve_type_pressure(t, 1, v, demand[1]);
    *p_trailer = solve_type_pressure(t, 0, v, demand[0]);
    for (int k = 0; k < t->n_cars; ++k) {
        const rb_car *c = &t->cars[k];
        const rb_wheelset *w = &c->wheelset;
        double force = ed[k] + car_pneumatic(c, v, c->motor ? *p_motor : *p_trailer);
        double rail = force / c->axles - rb_wheelset_equivalent_mass(w) * a;
        adhesion[k] = rail / (w->axle_load * RB_GRAVITY);
    }
}

static rb_status check_points(const double *speed, const double *decel, size_t n, rb_error *err)
{
    rb_status s;
    char field[48];
    for (size_t i = 0; i < n; ++i) {
        snprintf(field, sizeof field, "speed[%zu]", i);
        if ((s = rb_check_nonnegative(err, field, speed[i])) != RB_OK)
            return s;
        snprintf(field, sizeof field, "deceleration[%zu]", i);
        if ((s = rb_check_range(err, field, decel[i], 0.0, 5.0)) != RB_OK)
            return s;
    }
    return RB_OK;
}

rb_status rb_size_target_pressure(const rb_train *t, const double *speed, const double *decel,
                                  size_t n, double gradient, double *p_motor, double *p_trailer,
                                  double *ed_force, double *adhesion, rb_error *err)
{
    return rb_size_target_pressure_ed(t, speed, decel, n, gradient, 1, p_motor, p_trailer, ed_force,
                                      adhesion, err);
}

rb_status rb_size_target_pressure_ed(const rb_train *t, const double *speed, const double *decel,
                                     size_t n, double gradient, int ed_on, double *p_motor,
                                     double *p_trailer, double *ed_force, double *adhesion,
                                     rb_error *err)
{
    rb_status s = rb_train_check(t, err);
    if (s != RB_OK)
        return s;
    if ((s = rb_check_finite(err, "gradient", gradient)) != RB_OK)
        return s;
    if ((s = check_points(speed, decel, n, err)) != RB_OK)
        return s;
    for (size_t i = 0; i < n; ++i)
        size_one_speed(t, speed[i], decel[i], gradient, ed_on != 0, &p_motor[i], &p_trailer[i],
                       &ed_force[i], &adhesion[i * (size_t)t->n_cars]);
    return RB_OK;
}

rb_status rb_size_car_demand(const rb_train *t, int car, const double *speed, const double *decel,
                             size_t n, double gradient, double *force, double *pressure_per_newton,
                             double *threshold, rb_error *err)
{
    rb_status s = rb_train_check(t, err);
    if (s != RB_OK)
        return s;
    if (car < 0 || car >= t->n_cars)
        return rb_fail(err, RB_EINVAL, "car = %d: must be in [0, %d]", car, t->n_cars - 1);
    if ((s = rb_check_finite(err, "gradient", gradient)) != RB_OK ||
        (s = check_points(speed, decel, n, err)) != RB_OK)
        return s;
    for (size_t i = 0; i < n; ++i) {
        affine_brake a = car_affine(&t->cars[car], speed[i]);
        double f = rb_car_brake_demand(t, car, speed[i], decel[i], gradient);
        force[i] = f > 0.0 ? f : 0.0;
        pressure_per_newton[i] = a.gain > 0.0 ? 1.0 / a.gain : 0.0;
        *threshold = a.threshold;
    }
    return RB_OK;
}

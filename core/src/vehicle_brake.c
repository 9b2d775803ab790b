/* Foundation brake: tables over speed, pad friction, caliper (EN 14531), axle brake torque. */
#include "railbrake/rb_vehicle.h"

#include <math.h>
#include <stdio.h>

double rb_speed_table_at(const rb_speed_table *t, double speed)
{
    int lo = 0, hi = t->n - 1;   /* bisection for the interval, then the bracketed look-up */
    while (hi - lo > 1) {        /* selects, not branches: the halves come in no order a predictor learns */
        int mid = (lo + hi) / 2, above = t->speed[mid] <= speed;
        lo = above ? mid : lo;
        hi = above ? hi : mid;
    }
    return rb_speed_table_at_from(t, speed, &lo);
}

/* Whether point i of a table passes rb_speed_table_check's checks (the same checks, no message). */
static int table_point_ok(const rb_speed_table *t, int i, double lo, double hi)
{
    return rb_check_nonnegative(NULL, "", t->speed[i]) == RB_OK && (i == 0 || t->speed[i] > t->speed[i - 1]) &&
           rb_check_range(NULL, "", t->value[i], lo, hi) == RB_OK;
}

rb_status rb_speed_table_check(const rb_speed_table *t, const char *name, double lo, double hi,
                               rb_error *err)
{
    if (t->n < 1 || t->n > RB_MAX_TABLE)
        return rb_fail(err, RB_EINVAL, "%s.n = %d: must lie in [1, %d]", name, t->n, RB_MAX_TABLE);
    char field[96];
    for (int i = 0; i < t->n; ++i) {
        /* the field's name formatted only for a point that fails (the BCU's and the sizing's
           checks look at thousands of points per run set up) */
        if (table_point_ok(t, i, lo, hi)) continue;
        snprintf(field, sizeof field, "%s.speed[%d]", name, i);
        rb_status s = rb_check_nonnegative(err, field, t->speed[i]);
        if (s != RB_OK)
            return s;
        if (i > 0 && !(t->speed[i] > t->speed[i - 1]))
            return rb_fail(err, RB_EINVAL,
                           "%s = %g m/s: speeds must increase strictly (previous %g m/s)", field,
                           t->speed[i], t->speed[i - 1]);
        snprintf(field, sizeof field, "%s.value[%d]", name, i);
        s = rb_check_range(err, field, t->value[i], lo, hi);
        if (s != RB_OK)
            return s;
    }
    return RB_OK;
}

double rb_pad_friction_at(const rb_pad_friction *f, double speed)
{
    return rb_speed_table_at(&f->table, speed);
}

double rb_pad_friction_eval(const rb_pad_friction *f, double speed, double surface_temperature)
{
    return rb_speed_table_at(&f->table, speed) * rb_pad_fade_factor(f->fade_onset, f->fade_rate, surface_temperature);
}

rb_status rb_pad_friction_check(const rb_pad_friction *f, rb_error *err)
{
    rb_status s = rb_speed_table_check(&f->table, "pad_friction", 0.05, 1.0, err);
    if (s != RB_OK)
        return s;
    if ((s = rb_check_range(err, "pad_friction.fade_onset", f->fade_onset, 0.0, 2000.0)) != RB_OK)
        return s;
    return rb_check_range(err, "pad_friction.fade_rate", f->fade_rate, 0.0, 0.1);
}

rb_status rb_pad_friction_sintered(double low_speed_value, rb_pad_friction *out, rb_error *err)
{
    const double high = 0.35, knee = 100.0 / 3.6;  /* [T] sintered pads: about 0.35, rising below 100 km/h */
    rb_status s = rb_check_range(err, "low_speed_value", low_speed_value, high, 0.6);
    if (s != RB_OK)
        return s;
    const int points = 21;  /* 5 km/h spacing up to the knee, then constant */
    out->table.n = points + 1;
    for (int i = 0; i < points; ++i) {
        double v = knee * i / (points - 1);
        double x = 1.0 - v / knee;
        out->table.speed[i] = v;
        out->table.value[i] = high + (low_speed_value - high) * x * x;
    }
    out->table.speed[points] = 2.0 * knee;
    out->table.value[points] = high;
    out->fade_onset = 0.0;
    out->fade_rate = 0.0;   /* no heat fading unless a train file gives it */
    return RB_OK;
}

double rb_caliper_pad_force(const rb_caliper *c, double cylinder_pressure)
{
    double piston = (cylinder_pressure - c->atmospheric_pressure) * c->cylinder_area - c->return_spring;
    return piston > 0.0 ? piston * c->lever_ratio * c->efficiency : 0.0;
}

rb_status rb_caliper_check(const rb_caliper *c, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "caliper.cylinder_area", c->cylinder_area)) != RB_OK ||
        (s = rb_check_nonnegative(err, "caliper.return_spring", c->return_spring)) != RB_OK ||
        (s = rb_check_positive(err, "caliper.lever_ratio", c->lever_ratio)) != RB_OK ||
        (s = rb_check_positive(err, "caliper.efficiency", c->efficiency)) != RB_OK ||
        (s = rb_check_range(err, "caliper.efficiency", c->efficiency, 0.0, 1.0)) != RB_OK ||
        (s = rb_check_positive(err, "caliper.atmospheric_pressure", c->atmospheric_pressure)) != RB_OK)
        return s;
    return RB_OK;
}

double rb_axle_brake_torque(const rb_axle_brake *b, double cylinder_pressure, double speed)
{
    return b->discs * 2.0 * b->mean_radius * rb_pad_friction_at(&b->pad, speed) *
           rb_caliper_pad_force(&b->caliper, cylinder_pressure);
}

rb_status rb_axle_brake_check(const rb_axle_brake *b, rb_error *err)
{
    if (b->discs < 1 || b->discs > 8)
        return rb_fail(err, RB_EINVAL, "brake.discs = %d: must lie in [1, 8]", b->discs);
    if (b->mounting != RB_DISC_AXLE_MOUNTED && b->mounting != RB_DISC_WHEEL_MOUNTED)
        return rb_fail(err, RB_EINVAL, "brake.mounting = %d: must be 0 (axle) or 1 (wheel)",
                       b->mounting);
    rb_status s = rb_check_positive(err, "brake.mean_radius", b->mean_radius);
    if (s != RB_OK)
        return s;
    if ((s = rb_caliper_check(&b->caliper, err)) != RB_OK)
        return s;
    return rb_pad_friction_check(&b->pad, err);
}

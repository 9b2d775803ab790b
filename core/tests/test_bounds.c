/* The plausibility bounds table (rb_bounds.h): the checks refuse the values that made the plant's
 * outputs NaN, accept a plausible train, and the plant stays finite at every corner of the bounds
 * the numerics depend on (smallest car with the stiffest, most damped coupler; smallest volumes
 * with the largest valve ports). */
#include <math.h>
#include <string.h>

#include "plant_fixture.h"
#include "railbrake/rb_bounds.h"
#include "rb_test.h"

static void test_table(void)
{
    CHECK(rb_bound_count() > 20);
    for (int i = 0; i < rb_bound_count(); ++i) {
        const rb_bound *b = rb_bound_at(i);
        CHECK(b && isfinite(b->min) && isfinite(b->max) && b->min <= b->max && b->unit && b->why);
        CHECK(rb_bound_find(b->name) == b);
    }
    CHECK(rb_bound_at(-1) == NULL && rb_bound_at(rb_bound_count()) == NULL);
    CHECK(rb_bound_find("no.such.bound") == NULL);
}

static void test_refuses_what_made_nan(void)
{
    rb_plant_params p;
    rb_error err;
    fill_plant(&p, 3, 80.0);
    CHECK(rb_plant_bounds_check(&p, &err) == RB_OK);
    p.coupler.damping = 2e9;
    CHECK(rb_plant_bounds_check(&p, &err) == RB_EINVAL && strstr(err.message, "coupler.damping = 2e+09"));
    fill_plant(&p, 3, 80.0);
    p.coupler.stiffness = 1e13;
    CHECK(rb_plant_bounds_check(&p, &err) == RB_EINVAL && strstr(err.message, "coupler.stiffness"));
    fill_plant(&p, 3, 80.0);
    p.car[1].vehicle.mass = 1e-308;
    CHECK(rb_plant_bounds_check(&p, &err) == RB_EINVAL && strstr(err.message, "car[1].mass"));
    fill_plant(&p, 3, 80.0);
    p.car[2].cylinder_volume = 5e-324;
    CHECK(rb_plant_bounds_check(&p, &err) == RB_EINVAL && strstr(err.message, "car[2].cylinder_volume"));
    fill_plant(&p, 3, 80.0);
    p.car[0].supply_volume = NAN;
    CHECK(rb_plant_bounds_check(&p, &err) == RB_EINVAL && strstr(err.message, "finite"));
}

static void test_wsp(void)
{
    rb_wsp_params w;
    rb_error err;
    rb_wsp_default_params(&w);
    CHECK(rb_wsp_check(&w, &err) == RB_OK);
    w.safety_time = 0.0;    /* isolated every axle: the train did not stop */
    CHECK(rb_wsp_check(&w, &err) == RB_EINVAL && strstr(err.message, "wsp.safety_time = 0"));
    rb_wsp_default_params(&w);
    w.speed_threshold = -1.0;
    CHECK(rb_wsp_check(&w, &err) == RB_EINVAL && strstr(err.message, "wsp.speed_threshold"));
    rb_wsp_default_params(&w);
    w.filter_time = INFINITY;
    CHECK(rb_wsp_check(&w, &err) == RB_EINVAL);
    /* the BCU refuses them too, so every path (run, HIL, FMU) does */
    rb_bcu_params b;
    rb_bcu_state s;
    memset(&b, 0, sizeof b);
    b.n_cars = 1; b.cycle = 0.01; b.atmosphere = 1.01325e5; b.car_mass[0] = 5e4; b.pressure_max[0] = 5e5;
    rb_wsp_default_params(&w);
    CHECK(rb_bcu_init(&b, &w, &s, &err) == RB_OK);
    w.safety_time = 0.0;
    CHECK(rb_bcu_init(&b, &w, &s, &err) == RB_EINVAL);
}

/* 3 s with car 0 braking hard alone (the couplers ring), all valves cycling: finite, and the
 * speeds stay within [0, the initial speed]. */
static int runs_finite(const rb_plant_params *p)
{
    rb_plant_state s;
    rb_plant_inputs in;
    rb_plant_outputs o;
    rb_error err;
    if (rb_plant_init(p, &s, &err) != RB_OK || rb_plant_bounds_check(p, &err) != RB_OK) {
        fprintf(stderr, "corner refused: %s\n", err.message);
        return 0;
    }
    memset(&in, 0, sizeof in);
    for (int c = 0; c < p->n_cars; ++c) in.pressure_demand[c] = p->atmosphere;
    in.pressure_demand[0] = p->car[0].vehicle.supply_pressure;
    for (long k = 0; k < 3000; ++k) {
        for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
            in.hold[a] = (uint8_t)((k / 37) % 2);
            in.vent[a] = (uint8_t)((k / 53) % 2);
        }
        rb_plant_step(p, &s, &in);
        rb_plant_get_outputs(p, &s, &o);
        for (int c = 0; c < p->n_cars; ++c)
            if (!isfinite(o.car_speed[c]) || o.car_speed[c] < 0.0 || o.car_speed[c] > p->initial_speed + 1e-9 ||
                !isfinite(o.supply[c]))
                return 0;
        for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a)
            if (!isfinite(o.cylinder[a]) || !isfinite(o.wheel_speed[a]) || o.cylinder[a] < 0.0) return 0;
    }
    return 1;
}

static void test_corners_stay_finite(void)
{
    const rb_bound *mass = rb_bound_find("car.mass"), *k = rb_bound_find("coupler.stiffness"),
                   *c = rb_bound_find("coupler.damping"), *vol = rb_bound_find("car.cylinder_volume"),
                   *hold = rb_bound_find("car.hold_area"), *vent = rb_bound_find("car.vent_area");
    for (int corner = 0; corner < 8; ++corner) {
        rb_plant_params p;
        fill_plant(&p, 3, 80.0);
        for (int i = 0; i < p.n_cars; ++i) {
            p.car[i].vehicle.mass = corner & 1 ? mass->max : mass->min;
            p.car[i].vehicle.wheelset.axle_load = p.car[i].vehicle.mass / 4;
            p.car[i].cylinder_volume = vol->min;
            p.car[i].hold_area = hold->max;
            p.car[i].vent_area = vent->max;
        }
        p.coupler.stiffness = corner & 2 ? k->max : k->min;
        p.coupler.damping = corner & 4 ? c->max : c->min;
        int finite = runs_finite(&p);
        if (!finite) fprintf(stderr, "corner %d (mass %g, k %g, c %g) not finite\n", corner,
                             p.car[0].vehicle.mass, p.coupler.stiffness, p.coupler.damping);
        CHECK(finite);
    }
}

int main(void)
{
    test_table();
    test_refuses_what_made_nan();
    test_wsp();
    test_corners_stay_finite();
    return rb_test_summary("test_bounds");
}

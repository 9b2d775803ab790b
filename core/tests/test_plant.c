/* Whole-train plant: limiting cases against closed forms, air-mass conservation, determinism. */
#include "plant_fixture.h"
#include "rb_test.h"
#include "railbrake/rb_run.h"

#include <math.h>
#include <string.h>

#define G 9.80665

/* One car, brakes at a constant pressure well inside the adhesion: the train decelerates at
 * F_brake / (m + rotating mass + 4 J / r^2) (Newton with the wheelsets rolling). */
static void test_constant_torque_deceleration(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 1, 40.0);
    p.car[0].vehicle.brake.pad.table.n = 1;   /* constant pad friction: constant torque */
    p.car[0].vehicle.brake.pad.table.value[0] = 0.35;
    p.n_faults = 1;   /* no air refill effects: compressor off */
    p.fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p.atmosphere + 2.0e5;
    for (int i = 0; i < 5000; ++i) rb_plant_step(&p, &s, &in);   /* 5 s: cylinders filled */
    const rb_plant_car *c = &p.car[0];
    double pc = s.m_cyl[0] * 287.05 * p.temperature / c->cylinder_volume;
    double r = c->vehicle.wheelset.wheel_radius, J = c->vehicle.wheelset.inertia;
    /* EN 14531 by hand: 3 discs x 2 pads x R x 0.35 x ((p - p_atm) A - F_s) i eta */
    double torque = 3 * 2 * 0.247 * 0.35 * ((pc - p.atmosphere) * 0.0314 - 1500.0) * 3.0 * 0.92;
    CHECK_CLOSE(rb_plant_axle_brake_torque(c, pc, 40.0), torque, 1e-12, 0);
    double m_eff = c->vehicle.mass + 4 * J / (r * r);
    double expected = 4 * torque / r / m_eff;
    CHECK_CLOSE(-s.a[0], expected, 2e-3, 0);
    CHECK_CLOSE(pc, in.pressure_demand[0], 0.02, 0);
    CHECK(s.omega[0] * r < s.v[0]);      /* small braking creep */
    CHECK(s.v[0] > 30.0);
}

/* Air: every kilogram is in a volume, vented, or came from the compressor (cylinders with their
 * energy balance, as the presets run them). */
static void test_air_conservation(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 4, 60.0);
    p.wall_time = 1.5;
    p.governor_on = 9.45e5;   /* the compressor cuts in during the run */
    p.n_faults = 1;
    p.fault[0] = (rb_fault){RB_FAULT_CYLINDER_LEAK, 1, 2, 1.0, 2e-6};
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    for (int i = 0; i < 20000; ++i) {
        double t = i * 1e-3;
        for (int c = 0; c < 4; ++c) in.pressure_demand[c] = p.atmosphere + (fmod(t, 4.0) < 2.0 ? 3.8e5 : 0.0);
        for (int a = 0; a < 16; ++a) { in.vent[a] = fmod(t + a * 0.1, 1.0) < 0.2; in.hold[a] = in.vent[a]; }
        rb_plant_step(&p, &s, &in);
    }
    double balance = rb_plant_air_mass(&p, &s) + s.m_vented - s.m_compressed;
    CHECK_CLOSE(balance, s.m_initial, 1e-10, 0);
    CHECK(s.m_vented > 0.01);
    CHECK(s.m_compressed > 0.0);
}

/* A dry emergency stop from 250 km/h with 8 cars stops inside 3000 m without locking. */
static void test_emergency_stop(void)
{
    static rb_plant_params p;
    static rb_bcu_params b;
    static rb_run_state r;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1, 0, {0}};
    rb_kpis k;
    int finished = 0;
    fill_plant(&p, 8, 250 / 3.6);
    memset(&b, 0, sizeof b);
    b.n_cars = 8; b.cycle = 0.01; b.atmosphere = p.atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = 1;
    rb_bcu_pressure_map(&p, p.atmosphere + 3.8e5, &b);
    CHECK(rb_run_init(&p, &b, NULL, &sc, &r, NULL) == RB_OK);
    CHECK(rb_run_advance(&p, &b, &sc, &r, 1e9, NULL, 0, &finished, NULL) == RB_OK);
    rb_run_kpis(&p, &r, &k);
    printf("emergency 250 dry: %.1f m, %.1f s, lock events %g, utilisation %.3f, air %.4f kg, balance %.2e\n",
           k.stopping_distance_m, k.stopping_time_s, k.wheel_lock_events, k.adhesion_utilisation,
           k.air_consumed_kg, k.air_balance_error);
    CHECK(finished && k.stopped);
    CHECK(k.stopping_distance_m < 3000.0);
    CHECK(k.wheel_lock_events == 0);
    CHECK(k.air_balance_error < 1e-9);
}

static void test_bad_parameters(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_error err;
    fill_plant(&p, 2, 10.0);
    p.car[1].length = -5.0;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "car[1].length") != NULL);
    fill_plant(&p, 2, 10.0);
    p.n_faults = 1;
    p.fault[0] = (rb_fault){RB_FAULT_VENT_STUCK_OPEN, 5, 0, 0.0, 0.0};
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "fault[0].car = 5") != NULL);
}

int main(void)
{
    test_constant_torque_deceleration();
    test_air_conservation();
    test_emergency_stop();
    test_bad_parameters();
    return rb_test_summary("test_plant");
}

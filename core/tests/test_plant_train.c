/* Plant equipment of plant_train.c: gradient force, several compressors, disc energy and
 * temperature, air drawn from the main reservoir. */
#include "railbrake/rb_plant.h"
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>

static rb_plant_params params;
static rb_plant_state state;

/* One car coasting up a 10 per mille gradient without resistance: a = -m g sin(theta) / (m + 4 J/r^2). */
static void test_gradient(void)
{
    rb_plant_params *p = &params;
    fill_plant(p, 1, 30.0);
    p->n_gradients = 2;
    p->gradient_start[0] = 0.0; p->gradient[0] = 0.0;
    p->gradient_start[1] = -1e6; p->gradient[1] = 0.010;   /* bad: starts must increase */
    rb_error err;
    CHECK(rb_plant_init(p, &state, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "gradient_start[1]") != NULL);
    p->n_gradients = 1;
    p->gradient[0] = 0.010;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    for (int c = 0; c < RB_PLANT_MAX_CARS; ++c) in.pressure_demand[c] = p->atmosphere;
    for (int i = 0; i < 2000; ++i) rb_plant_step(p, &state, &in);
    const rb_car *v = &p->car[0].vehicle;
    double m_eff = v->mass + 4.0 * v->wheelset.inertia / (v->wheelset.wheel_radius * v->wheelset.wheel_radius);
    double expected = -v->mass * 9.80665 * 0.010 / sqrt(1.0 + 1e-4) / m_eff;
    CHECK_CLOSE((state.v[0] - 30.0) / 2.0, expected, 2e-3, 0);
}

/* Two compressors, one into the main reservoir, one into the pipe of car 3: each delivers while
 * its governor is on; the air balance closes. */
static void test_compressors_and_air_drawn(void)
{
    rb_plant_params *p = &params;
    fill_plant(p, 3, 0.0);
    p->initial_pressure = 8.0e5;   /* below governor_on: both start */
    p->n_compressors = 2;
    p->compressor_position[0] = 0; p->compressor_delivery[0] = 0.02;
    p->compressor_position[1] = 2; p->compressor_delivery[1] = 0.01;
    rb_error err;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    CHECK(state.compressor_running[0] == 1 && state.compressor_running[1] == 1);
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    for (int c = 0; c < RB_PLANT_MAX_CARS; ++c) in.pressure_demand[c] = p->atmosphere + 3e5;
    for (int i = 0; i < 1000; ++i) rb_plant_step(p, &state, &in);
    CHECK_CLOSE(state.m_compressed, 0.03 * 1.0, 1e-9, 0);
    rb_plant_outputs out;
    rb_plant_get_outputs(p, &state, &out);
    CHECK(out.compressor_on == 1);
    CHECK_CLOSE(out.air_in_system + out.air_vented, state.m_initial + out.air_compressed, 1e-12, 0);
    /* what left the MR side went into the supply reservoirs and the brake chain */
    double downstream = 0.0, downstream0 = 0.0, rt = 287.05 * p->temperature;
    for (int c = 0; c < 3; ++c) {
        downstream += state.m_supply[c] + state.m_pilot[c] + state.m_relay[c];
        downstream0 += (8.0e5 * p->car[c].supply_volume + p->atmosphere * (p->car[c].pilot_volume +
                        p->car[c].relay_volume + 4 * p->car[c].cylinder_volume)) / rt;
        for (int k = 0; k < 4; ++k) downstream += state.m_cyl[c * 4 + k];
    }
    CHECK_CLOSE(out.air_drawn, downstream + out.air_vented - downstream0, 1e-9, 1e-12);
    CHECK(out.air_drawn > 0.0);
    p->compressor_position[1] = 3;
    CHECK(rb_plant_init(p, &state, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "compressor_position[1] = 3") != NULL);
}

/* Brakes on a rolling car without cooling: each axle's disc warms by its friction energy over
 * its heat capacity; the energy is the brake torque times the wheel's turn. */
static void test_discs(void)
{
    rb_plant_params *p = &params;
    fill_plant(p, 1, 40.0);
    p->car[0].disc_heat_capacity = 3 * 120.0 * 460.0;
    rb_error err;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p->atmosphere + 3e5;
    double expected = 0.0;
    for (int i = 0; i < 3000; ++i) {
        rb_plant_step(p, &state, &in);
        rb_plant_outputs out;
        rb_plant_get_outputs(p, &state, &out);
        expected += rb_plant_axle_brake_torque(&p->car[0], out.cylinder[0], out.wheel_speed[0]) *
                    out.wheel_speed[0] / p->car[0].vehicle.wheelset.wheel_radius * p->dt;
    }
    rb_plant_outputs out;
    rb_plant_get_outputs(p, &state, &out);
    CHECK(out.brake_energy[0] > 1e5);
    CHECK_CLOSE(out.brake_energy[0], expected, 2e-3, 0);   /* sampled once per step vs per sub-step */
    CHECK_CLOSE(out.disc_temperature[0] - p->ambient_temperature, out.brake_energy[0] / p->car[0].disc_heat_capacity,
                1e-9, 0);
    /* with cooling the disc ends cooler */
    rb_speed_table cooling = {1, {0.0}, {500.0}};
    p->car[0].disc_cooling = cooling;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    for (int i = 0; i < 3000; ++i) rb_plant_step(p, &state, &in);
    rb_plant_outputs cooled;
    rb_plant_get_outputs(p, &state, &cooled);
    CHECK(cooled.disc_temperature[0] < out.disc_temperature[0]);
    CHECK(cooled.disc_temperature[0] > p->ambient_temperature);
}

int main(void)
{
    test_gradient();
    test_compressors_and_air_drawn();
    test_discs();
    return rb_test_summary("test_plant_train");
}

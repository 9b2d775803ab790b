/* The pads' heat fading (rb_pad_friction) and the two-node disc (rb_disc_step) in a dynamometer
 * stop (rb_dyno_stop_run) and in the plant: heat balance, limiting cases, analytic stops. */
#include "plant_fixture.h"
#include "rb_test.h"

#include "railbrake/rb_vehicle.h"

static rb_plant_params params;

static rb_pad_friction flat_pad(double mu, double onset, double rate)
{
    rb_pad_friction f;
    memset(&f, 0, sizeof f);
    f.table.n = 1;
    f.table.value[0] = mu;
    f.fade_onset = onset;
    f.fade_rate = rate;
    return f;
}

/* the law: the table below the onset, divided by 1 + rate (T - onset) above it */
static void test_fade_law(void)
{
    rb_error err;
    rb_pad_friction f = flat_pad(0.4, 600.0, 0.002);
    CHECK(rb_pad_friction_check(&f, &err) == RB_OK);
    CHECK(rb_pad_friction_eval(&f, 50.0, 300.0) == 0.4);
    CHECK(rb_pad_friction_eval(&f, 50.0, 600.0) == 0.4);
    CHECK_CLOSE(rb_pad_friction_eval(&f, 50.0, 700.0), 0.4 / 1.2, 1e-15, 0);
    f.fade_rate = -1e-3;
    CHECK(rb_pad_friction_check(&f, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "pad_friction.fade_rate") != NULL);
}

static rb_dyno_stop stop_of(double v0)
{
    rb_dyno_stop d;
    memset(&d, 0, sizeof d);
    d.initial_speed = v0;
    d.mass = 3750.0;
    d.pad_force = 25e3;
    d.friction_radius = 0.247;
    d.wheel_radius = 0.43;
    d.heat_capacity = 115.0 * 460.0;
    d.surface_capacity = 0.12 * d.heat_capacity;
    d.surface_conductance = 1450.0;
    d.ambient_temperature = 293.15;
    d.dt = 1e-3;
    return d;
}

/* Without fading the stop is one of constant deceleration a = 2 mu F r / (R m): distance v0^2 / 2a,
 * time v0 / a, mean friction mu; the heat into the disc is the kinetic energy, and without cooling
 * all of it is in the disc (Cs dTs + Cb dTb); with cooling what the air took makes up the rest. */
static void test_dyno_energy_and_analytic_stop(void)
{
    rb_error err;
    rb_pad_friction f = flat_pad(0.38, 0.0, 0.0);
    rb_dyno_stop d = stop_of(300.0 / 3.6);
    rb_dyno_result r;
    CHECK(rb_dyno_stop_run(&f, &d, &r, &err) == RB_OK);
    double a = 2.0 * 0.38 * d.pad_force * d.friction_radius / (d.wheel_radius * d.mass);
    double kinetic = 0.5 * d.mass * d.initial_speed * d.initial_speed;
    CHECK_CLOSE(r.distance, d.initial_speed * d.initial_speed / (2.0 * a), 1e-9, 0);
    CHECK_CLOSE(r.time, d.initial_speed / a, 1e-9, 0);
    CHECK_CLOSE(r.mean_friction, 0.38, 1e-12, 0);
    CHECK_CLOSE(r.heat, kinetic, 1e-9, 0);
    CHECK_CLOSE(r.stored, kinetic, 1e-9, 0);
    CHECK(r.cooled == 0.0);
    /* the mean disc ends at ambient + E / C; the surface ran ahead of it */
    CHECK_CLOSE(r.max_mean_temperature - d.ambient_temperature, kinetic / d.heat_capacity, 1e-9, 0);
    CHECK(r.max_surface_temperature > r.max_mean_temperature + 1.0);
    rb_speed_table cooling = {2, {0.0, 100.0}, {50.0, 300.0}};
    d.cooling = cooling;
    rb_dyno_result cooled;
    CHECK(rb_dyno_stop_run(&f, &d, &cooled, &err) == RB_OK);
    CHECK(cooled.cooled > 0.0);
    CHECK_CLOSE(cooled.stored + cooled.cooled, cooled.heat, 1e-9, 0);
    CHECK(cooled.max_surface_temperature < r.max_surface_temperature);
    /* a lumped disc (no surface layer): its one temperature is the mean, ambient + E / C at the stop */
    d.cooling.n = 0;
    d.surface_capacity = d.surface_conductance = 0.0;
    rb_dyno_result lumped;
    CHECK(rb_dyno_stop_run(&f, &d, &lumped, &err) == RB_OK);
    CHECK_CLOSE(lumped.max_surface_temperature - d.ambient_temperature, kinetic / d.heat_capacity, 1e-9, 0);
    /* a surface layer of vanishing conductance keeps all the heat: Cs dTs = E */
    d.surface_capacity = 0.1 * d.heat_capacity;
    d.surface_conductance = 1e-9;
    rb_dyno_result insulated;
    CHECK(rb_dyno_stop_run(&f, &d, &insulated, &err) == RB_OK);
    CHECK_CLOSE(insulated.max_surface_temperature - d.ambient_temperature, kinetic / d.surface_capacity, 1e-6, 0);
    d.surface_capacity = d.heat_capacity;
    CHECK(rb_dyno_stop_run(&f, &d, &insulated, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "dyno.surface_capacity") != NULL);
}

/* Fading lowers the stop's mean friction, the more the hotter the stop: from a higher speed (more
 * energy into the same disc) the mean falls; a stop whose surface stays below the onset keeps the
 * table's friction. */
static void test_dyno_fading(void)
{
    rb_error err;
    rb_pad_friction f = flat_pad(0.38, 293.15 + 250.0, 0.003);
    rb_dyno_stop d = stop_of(120.0 / 3.6);
    rb_dyno_result cool, warm, hot;
    CHECK(rb_dyno_stop_run(&f, &d, &cool, &err) == RB_OK);
    CHECK(cool.max_surface_temperature < f.fade_onset);
    CHECK_CLOSE(cool.mean_friction, 0.38, 1e-12, 0);
    d.initial_speed = 300.0 / 3.6;
    CHECK(rb_dyno_stop_run(&f, &d, &warm, &err) == RB_OK);
    d.initial_speed = 380.0 / 3.6;
    CHECK(rb_dyno_stop_run(&f, &d, &hot, &err) == RB_OK);
    CHECK(warm.mean_friction < 0.38);
    CHECK(hot.mean_friction < warm.mean_friction);
    CHECK_CLOSE(hot.stored, hot.heat, 1e-9, 0);   /* the energy balance holds with fading too */
}

/* The plant's discs with a surface layer: without cooling the axle's disc holds the friction
 * energy (Cs (Ts - T0) + Cb (Tb - T0) = E), the surface hotter than the mean; the mean output is
 * that energy over the whole capacity. With fading the pads' friction output falls below the
 * table once the surface passes the onset. */
static void test_plant_two_node(void)
{
    rb_plant_params *p = &params;
    fill_plant(p, 1, 40.0);
    p->car[0].disc_heat_capacity = 3 * 120.0 * 460.0;
    p->car[0].disc_surface_capacity = 0.12 * p->car[0].disc_heat_capacity;
    p->car[0].disc_surface_conductance = 3 * 1450.0;
    rb_error err;
    rb_plant_state state;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p->atmosphere + 3e5;
    for (int i = 0; i < 3000; ++i) rb_plant_step(p, &state, &in);
    rb_plant_outputs out;
    rb_plant_get_outputs(p, &state, &out);
    const double t0 = p->ambient_temperature, cs = p->car[0].disc_surface_capacity;
    const double cb = p->car[0].disc_heat_capacity - cs;
    CHECK(out.brake_energy[0] > 1e5);
    CHECK_CLOSE(cs * (state.disc_temperature[0] - t0) + cb * (state.disc_bulk_temperature[0] - t0), out.brake_energy[0],
                1e-9, 0);
    CHECK_CLOSE(out.disc_temperature[0] - t0, out.brake_energy[0] / p->car[0].disc_heat_capacity, 1e-9, 0);
    CHECK(out.disc_surface_temperature[0] > out.disc_temperature[0] + 0.1);
    double table = rb_pad_friction_at(&p->car[0].vehicle.brake.pad, out.wheel_speed[0]);
    CHECK_CLOSE(out.pad_friction[0], table, 1e-2, 0);   /* no fading: the table (at the step's start speed) */
    /* fading from just above the ambient */
    p->car[0].vehicle.brake.pad.fade_onset = t0 + 0.5;
    p->car[0].vehicle.brake.pad.fade_rate = 0.01;
    CHECK(rb_plant_init(p, &state, &err) == RB_OK);
    for (int i = 0; i < 3000; ++i) rb_plant_step(p, &state, &in);
    rb_plant_outputs faded;
    rb_plant_get_outputs(p, &state, &faded);
    double expected = rb_pad_friction_eval(&p->car[0].vehicle.brake.pad, faded.wheel_speed[0],
                                           faded.disc_surface_temperature[0]);
    CHECK(faded.pad_friction[0] < 0.95 * table);
    CHECK_CLOSE(faded.pad_friction[0], expected, 1e-2, 0);
    CHECK(faded.brake_energy[0] < out.brake_energy[0]);
    /* a surface layer as large as the disc is refused */
    p->car[0].disc_surface_capacity = p->car[0].disc_heat_capacity;
    CHECK(rb_plant_init(p, &state, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "disc_surface_capacity") != NULL);
}

int main(void)
{
    test_fade_law();
    test_dyno_energy_and_analytic_stop();
    test_dyno_fading();
    test_plant_two_node();
    return rb_test_summary("test_disc_fade");
}

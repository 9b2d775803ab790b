/* The plant's brake cylinders with their energy balance (rb_plant_params.wall_time) against the
 * closed forms of an ideal-gas volume: a fast fill rises gamma times the isothermal rise, a closed
 * cylinder then relaxes to the isothermal pressure with the wall's time constant, a slow fill
 * stays isothermal; wall_time = 0 is the isothermal cylinder. */
#include "plant_fixture.h"
#include "rb_test.h"
#include "railbrake/rb_pneumatics.h"

#include <math.h>
#include <string.h>

/* One car at rest, compressor off, its relay output charged to 3 bar gauge with every hold valve
 * closed (3 s). */
static void charged_car(rb_plant_params *p, rb_plant_state *s, rb_plant_inputs *in, double wall_time,
                        double hold_area)
{
    fill_plant(p, 1, 0.0);
    p->wall_time = wall_time;
    p->car[0].hold_area = hold_area;
    p->n_faults = 1;
    p->fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
    CHECK(rb_plant_init(p, s, NULL) == RB_OK);
    memset(in, 0, sizeof *in);
    in->pressure_demand[0] = p->atmosphere + 3.0e5;
    memset(in->hold, 1, sizeof in->hold);
    for (int i = 0; i < 3000; ++i) rb_plant_step(p, s, in);
}

static double cylinder_pressure(const rb_plant_params *p, const rb_plant_state *s)
{
    rb_plant_outputs out;
    rb_plant_get_outputs(p, s, &out);
    return out.cylinder[0];
}

/* Axle 0's hold valve commanded open for `steps` steps, then closed; runs until it has closed
 * (the response delay) and returns the cylinder's mass and pressure rises. */
static void hold_pulse(const rb_plant_params *p, rb_plant_state *s, rb_plant_inputs *in, int steps, double *dm,
                       double *dp)
{
    double m0 = s->m_cyl[0], p0 = cylinder_pressure(p, s);
    in->hold[0] = 0;
    for (int i = 0; i < steps; ++i) rb_plant_step(p, s, in);
    in->hold[0] = 1;
    for (int i = 0; i < 20; ++i) rb_plant_step(p, s, in);   /* past the 15 ms delay */
    CHECK(s->hold_effective[0] == 1);
    *dm = s->m_cyl[0] - m0;
    *dp = cylinder_pressure(p, s) - p0;
}

/* Filled in 20 ms against a wall time of 1000 s: the air brings its enthalpy, dp = gamma R T dm / V
 * (the heat the wall takes in that time is below 1e-4 of the rise). */
static void test_fast_fill_rises_gamma_times_the_isothermal_rise(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    double dm, dp;
    charged_car(&p, &s, &in, 1e3, 20e-6);
    hold_pulse(&p, &s, &in, 20, &dm, &dp);
    double isothermal = RB_AIR_R * p.temperature * dm / p.car[0].cylinder_volume;
    CHECK(dp > 0.15e5);
    CHECK_CLOSE(dp, RB_AIR_GAMMA * isothermal, 1e-3, 0);
}

/* The same fill with the isothermal cylinder (wall_time = 0): dp = R T dm / V. */
static void test_isothermal_cylinder(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    double dm, dp;
    charged_car(&p, &s, &in, 0.0, 20e-6);
    hold_pulse(&p, &s, &in, 20, &dm, &dp);
    CHECK_CLOSE(dp, RB_AIR_R * p.temperature * dm / p.car[0].cylinder_volume, 1e-12, 0);
    CHECK_CLOSE(s.mt_cyl[0], s.m_cyl[0] * p.temperature, 1e-15, 0);
}

/* After a fast fill the closed cylinder's air cools at the wall: m cv dT/dt = h A (T_w - T) with
 * h A = m_ref cv / wall_time, so the pressure's excess over the isothermal m R T_w / V decays as
 * exp(-t / tau), tau = wall_time m / m_ref (m_ref: the air at RB_WALL_REFERENCE_PRESSURE). */
static void test_closed_cylinder_relaxes_with_the_wall_time(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    double dm, dp;
    const double wall_time = 1.5;
    charged_car(&p, &s, &in, wall_time, 20e-6);
    hold_pulse(&p, &s, &in, 20, &dm, &dp);
    double V = p.car[0].cylinder_volume, m = s.m_cyl[0];
    double isothermal = m * RB_AIR_R * p.temperature / V;
    double m_ref = RB_WALL_REFERENCE_PRESSURE * V / (RB_AIR_R * p.temperature);
    double tau = wall_time * m / m_ref, excess0 = cylinder_pressure(&p, &s) - isothermal;
    CHECK(excess0 > 0.05e5);
    int steps = (int)lround(tau / p.dt);
    for (int i = 0; i < steps; ++i) rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.m_cyl[0], m, 1e-12, 0);   /* closed */
    CHECK_CLOSE(cylinder_pressure(&p, &s) - isothermal, excess0 * exp(-steps * p.dt / tau), 5e-3, 0);
    for (int i = 0; i < 10 * steps; ++i) rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(cylinder_pressure(&p, &s), isothermal, 1e-5, 0);
}

/* Through a port of 0.05 mm^2 the cylinder fills 0.4 bar in 20 s, slowly against the wall time:
 * its temperature stays within (gamma - 1) T_w wall_time mdot / m_ref (quasi-steady balance of the
 * inflow's enthalpy and the wall's heat, 0.3 %) of the wall's, and the rise is the isothermal one. */
static void test_slow_fill_stays_isothermal(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    double dm, dp;
    const double wall_time = 1.5;
    charged_car(&p, &s, &in, wall_time, 0.05e-6);
    hold_pulse(&p, &s, &in, 20000, &dm, &dp);
    double V = p.car[0].cylinder_volume;
    double m_ref = RB_WALL_REFERENCE_PRESSURE * V / (RB_AIR_R * p.temperature);
    double bound = (RB_AIR_GAMMA - 1.0) * wall_time * (dm / 20.0) / m_ref;
    CHECK(dp > 0.3e5);
    CHECK(bound < 0.005);
    CHECK_CLOSE(s.mt_cyl[0] / s.m_cyl[0], p.temperature, bound, 0);
    double isothermal = RB_AIR_R * p.temperature * dm / V;
    CHECK_CLOSE(dp, isothermal, 0.02, 0);
}

int main(void)
{
    test_fast_fill_rises_gamma_times_the_isothermal_rise();
    test_isothermal_cylinder();
    test_closed_cylinder_relaxes_with_the_wall_time();
    test_slow_fill_stays_isothermal();
    return rb_test_summary("test_plant_cylinders");
}

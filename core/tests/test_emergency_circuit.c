/* The emergency circuit (emergency_circuit.c) in the plant: nothing moves before the car's delay;
 * then the choke fills the relay's control chamber from the load-weighing valve's regulated output
 * (the demand or the limit, whichever is lower) at the choked orifice rate of ISO 6358
 * (rb_orifice_mass_flow_fast, the library's law) and it settles there; the EP valve is cut off meanwhile, and a failed EP valve does not
 * stop the emergency brake; the emergency path's faults (emergency valve, loop, limiter, relay valve) act
 * through their component; a leak of the MR pipe lets out the orifice flow; air is conserved; bad
 * parameters are refused by name. */
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>
#include <string.h>

#define BAR 1e5
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* One car at rest, compressor off, with an emergency circuit: choke of `diameter` m, delay
 * `delay` s, limit `limit` Pa gauge; demand `demand` Pa gauge, the loop open from t = 0. */
static void start(rb_plant_params *p, rb_plant_state *s, rb_plant_inputs *in, double diameter, double delay,
                  double limit, double demand)
{
    fill_plant(p, 1, 0.0);
    p->n_faults = 1;
    p->fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
    rb_plant_car *c = &p->car[0];
    c->emergency_area = 0.25 * M_PI * diameter * diameter;
    c->emergency_delay = delay;
    c->emergency_limit = p->atmosphere + limit;
    CHECK(rb_plant_init(p, s, NULL) == RB_OK);
    memset(in, 0, sizeof *in);
    in->pressure_demand[0] = p->atmosphere + demand;
    in->emergency = 1.0;
}

static double pilot(const rb_plant_params *p, const rb_plant_state *s)
{
    rb_plant_outputs out;
    rb_plant_get_outputs(p, s, &out);
    return out.pilot[0];
}

/* Before the delay the chamber stays at the atmosphere (the open loop cuts the EP valve off at
 * once: the demand does not reach the chamber through it); after it, the chamber's pressure rises
 * at R T / V times the choked flow of the choke from the regulated output (checked over 0.2 s,
 * where the pressure ratio stays below b: the flow depends on the upstream pressure alone). */
static void fills_at_the_choked_rate_after_the_delay(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    const double delay = 0.25, d = 0.9e-3;
    start(&p, &s, &in, d, delay, 4.5 * BAR, 4.0 * BAR);
    in.pressure_demand[0] = p.atmosphere + 4.0 * BAR;
    int steps = (int)(delay / p.dt + 0.5);
    for (int i = 0; i < steps - 1; ++i) rb_plant_step(&p, &s, &in);
    CHECK(fabs(pilot(&p, &s) - p.atmosphere) < 1.0);
    rb_plant_step(&p, &s, &in);
    double p0 = pilot(&p, &s);
    for (int i = 0; i < 200; ++i) rb_plant_step(&p, &s, &in);
    double p1 = pilot(&p, &s);
    double area = 0.25 * M_PI * d * d, source = p.atmosphere + 4.0 * BAR;   /* the demand, below the limit */
    double q = rb_orifice_mass_flow_fast(source, p.temperature, 0.5 * (p0 + p1), p.temperature, area,
                                         p.discharge_coefficient, p.critical_ratio);
    double expected = RB_AIR_R * p.temperature / p.car[0].pilot_volume * q * 0.2;
    printf("emergency choke %.1f mm: control chamber rose %.4f bar in 0.2 s (choked orifice law: %.4f bar)\n",
           d * 1e3, (p1 - p0) / BAR, expected / BAR);
    CHECK(p0 - p.atmosphere < 0.02 * BAR);
    CHECK(fabs((p1 - p0) - expected) < 0.01 * expected);
}

/* Settles at the lower of the demand and the limit (within the band), and the air is conserved. */
static void settles_at_demand_or_limit(double limit, double demand)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    start(&p, &s, &in, 1.2e-3, 0.0, limit, demand);
    double m0 = rb_plant_air_mass(&p, &s);
    for (int i = 0; i < 15000; ++i) rb_plant_step(&p, &s, &in);
    double expect = p.atmosphere + (demand < limit ? demand : limit), got = pilot(&p, &s);
    double balance = rb_plant_air_mass(&p, &s) + s.m_vented - m0;
    printf("limit %.2f bar, demand %.2f bar: control chamber %.4f bar; air balance %.2e kg\n", limit / BAR,
           demand / BAR, (got - p.atmosphere) / BAR, balance);
    CHECK(fabs(got - expect) < 0.1 * BAR);
    CHECK(fabs(balance) < 1e-9 * m0 + 1e-12);
}

/* The EP valve failed (ports shut) does not stop the emergency valve's path; without the loop,
 * the failed EP valve keeps the brake released. */
static void a_failed_ep_valve_does_not_stop_the_emergency_brake(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    for (int loop = 0; loop < 2; ++loop) {
        start(&p, &s, &in, 1.2e-3, 0.0, 4.5 * BAR, 3.0 * BAR);
        p.n_faults = 2;
        p.fault[1] = (rb_fault){RB_FAULT_EP_VALVE, 0, -1, 0.0, 0.0};
        CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
        in.emergency = loop;
        for (int i = 0; i < 10000; ++i) rb_plant_step(&p, &s, &in);
        printf("EP valve failed, loop %s: control chamber %.3f bar\n", loop ? "open" : "closed",
               (pilot(&p, &s) - p.atmosphere) / BAR);
        CHECK(loop ? fabs(pilot(&p, &s) - p.atmosphere - 3.0 * BAR) < 0.1 * BAR
                   : fabs(pilot(&p, &s) - p.atmosphere) < 0.01 * BAR);
    }
}

static double relay(const rb_plant_params *p, const rb_plant_state *s)
{
    rb_plant_outputs out;
    rb_plant_get_outputs(p, s, &out);
    return out.relay[0];
}

/* The emergency path's faults, each on its own, loop open, demand 3 bar, limit 4.5 bar: a failed
 * emergency valve leaves the chamber at the atmosphere (the EP valve is cut off all the same); a
 * car that does not see the loop brakes through its EP valve (its demand reaches the chamber); a
 * failed limiter at 1.5 bar holds the chamber there; a relay failed with no output keeps its
 * volume at the atmosphere while the chamber fills; one stuck at 1.2 bar holds it there. */
static void emergency_path_faults_act_through_their_component(void)
{
    struct { int kind; double value, pilot, relay; const char *name; } cases[] = {
        {RB_FAULT_EMERGENCY_VALVE, 0.0, 0.0, 0.0, "emergency valve failed"},
        {RB_FAULT_EMERGENCY_LOOP, 0.0, 3.0, 3.0, "loop not seen"},
        {RB_FAULT_LIMITER, 1.5 * BAR, 1.5, 1.5, "limiter failed at 1.5 bar"},
        {RB_FAULT_RELAY_VALVE, 0.0, 3.0, 0.0, "relay valve, no output"},
        {RB_FAULT_RELAY_VALVE, 1.2 * BAR, 3.0, 1.2, "relay valve stuck at 1.2 bar"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        rb_plant_params p;
        rb_plant_state s;
        rb_plant_inputs in;
        start(&p, &s, &in, 1.2e-3, 0.0, 4.5 * BAR, 3.0 * BAR);
        p.n_faults = 2;
        p.fault[1] = (rb_fault){cases[k].kind, 0, -1, 0.0, cases[k].value};
        CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
        double m0 = rb_plant_air_mass(&p, &s);
        for (int i = 0; i < 10000; ++i) rb_plant_step(&p, &s, &in);
        double got_pilot = (pilot(&p, &s) - p.atmosphere) / BAR, got_relay = (relay(&p, &s) - p.atmosphere) / BAR;
        double balance = rb_plant_air_mass(&p, &s) + s.m_vented - m0;
        printf("%s: control chamber %.3f bar, relay %.3f bar (expected %.1f, %.1f); air balance %.2e kg\n",
               cases[k].name, got_pilot, got_relay, cases[k].pilot, cases[k].relay, balance);
        CHECK(fabs(got_pilot - cases[k].pilot) < 0.1);
        CHECK(fabs(got_relay - cases[k].relay) < 0.1);
        CHECK(fabs(balance) < 1e-9 * m0 + 1e-12);
    }
}

static void bad_parameters_are_refused_by_name(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    rb_error err;
    start(&p, &s, &in, 1e-3, 0.0, 4.5 * BAR, 3.0 * BAR);
    p.car[0].emergency_limit = p.atmosphere - 1.0;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "car[0].emergency_limit") != NULL);
    p.car[0].emergency_limit = p.atmosphere + 4e5;
    p.car[0].emergency_delay = -0.1;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "car[0].emergency_delay") != NULL);
}

static double pipe_end(const rb_plant_params *p, const rb_plant_state *s)
{
    rb_plant_outputs out;
    rb_plant_get_outputs(p, s, &out);
    return out.pipe_end;
}

/* A leak of the MR pipe (the train line; there is no brake pipe): the last car's pipe lets out, over
 * 20 ms, the choked orifice flow of ISO 6358 through its area at the pipe's mean pressure (within
 * 1 %), the air is conserved (what leaves is booked as vented), and without the leak nothing
 * leaves. */
static void a_pipe_leak_vents_the_line_at_the_orifice_rate(void)
{
    for (int leaking = 0; leaking < 2; ++leaking) {
        rb_plant_params p;
        rb_plant_state s;
        rb_plant_inputs in;
        const double area = 20e-6, t = 0.02;
        fill_plant(&p, 2, 0.0);
        p.n_faults = 1 + leaking;
        p.fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
        p.fault[1] = (rb_fault){RB_FAULT_PIPE_LEAK, 1, -1, 0.0, area};
        CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
        memset(&in, 0, sizeof in);
        for (int c = 0; c < 2; ++c) in.pressure_demand[c] = p.atmosphere;
        double m0 = rb_plant_air_mass(&p, &s), p0 = pipe_end(&p, &s);
        int steps = (int)(t / p.dt + 0.5);
        for (int i = 0; i < steps; ++i) rb_plant_step(&p, &s, &in);
        double p1 = pipe_end(&p, &s), balance = rb_plant_air_mass(&p, &s) + s.m_vented - m0;
        double q = rb_orifice_mass_flow_fast(0.5 * (p0 + p1), p.temperature, p.atmosphere, p.temperature, area,
                                             p.discharge_coefficient, p.critical_ratio);
        printf("MR pipe leak %.0f mm2: %.4g kg out in %.0f ms (orifice law %.4g kg); air balance %.2e kg\n",
               leaking * area * 1e6, s.m_vented, t * 1e3, leaking * q * t, balance);
        CHECK(fabs(balance) < 1e-9 * m0 + 1e-12);
        if (leaking) CHECK(fabs(s.m_vented - q * t) < 0.01 * q * t);
        else CHECK(s.m_vented < 1e-9 * m0);
    }
}

int main(void)
{
    fills_at_the_choked_rate_after_the_delay();
    settles_at_demand_or_limit(4.5 * BAR, 3.0 * BAR);
    settles_at_demand_or_limit(2.5 * BAR, 3.0 * BAR);
    a_failed_ep_valve_does_not_stop_the_emergency_brake();
    emergency_path_faults_act_through_their_component();
    bad_parameters_are_refused_by_name();
    a_pipe_leak_vents_the_line_at_the_orifice_rate();
    return rb_test_summary("emergency_circuit");
}

/* The air of the plant's EP and relay valves: the pilot stage's bleed against the ideal nozzle's
 * choked flow, the relay membrane's stroke against the first-order lag's closed form, and the air
 * mass conserved (stored + vented = initial) while WSP cycles a car with bleed, lag and sweep on. */
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>
#include <string.h>

#define BAR 1e5
#define ATM 1.01325e5   /* the fixture's atmosphere */

static void valve_car(rb_plant_params *p)
{
    fill_plant(p, 1, 0.0);
    p->initial_pressure = p->atmosphere + 8.0 * BAR;
    p->n_faults = 1;
    p->fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
    rb_plant_car *c = &p->car[0];
    c->ep_bleed_area = 7.0686e-8;   /* a 0.3 mm feed orifice, pi d^2 / 4 */
    c->relay_tau = 0.004;
    c->relay_sweep = 9e-6;
    c->relay_travel = 2.4;
    c->valve_delay = 0.0;   /* WSP valves as commanded */
}

/* The valve car initialised, no WSP command, the pressure demand `demand` (Pa abs). */
static void start(rb_plant_params *p, rb_plant_state *s, rb_plant_inputs *in, double demand)
{
    valve_car(p);
    CHECK(rb_plant_init(p, s, NULL) == RB_OK);
    memset(in, 0, sizeof *in);
    in->pressure_demand[0] = demand;
}

/* Released (no demand), the nozzle chamber near the atmosphere: the feed orifice is choked, so the
 * bleed is Cd A p sqrt(gamma / (R T)) (2 / (gamma + 1))^((gamma + 1) / (2 (gamma - 1))) at the
 * supply pressure (which falls by under 0.1 % in the second). */
static void bleed_is_the_choked_orifice(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    start(&p, &s, &in, 0.0);
    for (int i = 0; i < 1000; ++i) rb_plant_step(&p, &s, &in);
    const double gamma = 1.4, R = 287.05, T = p.temperature;
    double q = p.discharge_coefficient * p.car[0].ep_bleed_area * p.initial_pressure * sqrt(gamma / (R * T)) *
               pow(2.0 / (gamma + 1.0), (gamma + 1.0) / (2.0 * (gamma - 1.0)));
    printf("bleed over 1 s: %.6f g (choked orifice at the supply: %.6f g)\n", s.m_valves_vented * 1e3, q * 1e3);
    CHECK_CLOSE(s.m_valves_vented, q * 1.0, 2e-3, 0.0);
    CHECK(s.m_vented == s.m_valves_vented);   /* nothing else let out */
}

/* The pilot volume charged to the demand, the relay output released: the relay's error stays far
 * beyond the travel for the first steps, so the stroke's target is the travel and the stroke follows
 * travel (1 - exp(-t / tau)) exactly. */
static void stroke_follows_the_membrane_lag(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    rb_plant_outputs out;
    start(&p, &s, &in, ATM + 4.0 * BAR);
    s.m_pilot[0] = in.pressure_demand[0] * p.car[0].pilot_volume / (287.05 * p.temperature);
    s.ep_demand_lag[0] = in.pressure_demand[0];
    const double tau = p.car[0].relay_tau, travel = p.car[0].relay_travel;
    int steps = 0;
    double worst = 0.0;
    for (int n = 1; n <= 20; ++n) {
        rb_plant_get_outputs(&p, &s, &out);
        if ((out.pilot[0] - out.relay[0]) / p.car[0].relay_band < 2.0 * travel) break;   /* near the stops */
        rb_plant_step(&p, &s, &in);
        double expect = travel * (1.0 - exp(-n * p.dt / tau));
        worst = fmax(worst, fabs(s.relay_stroke[0] - expect));
        ++steps;
    }
    printf("relay stroke over %d steps within %.2e of travel (1 - exp(-t / tau))\n", steps, worst);
    CHECK(steps >= 10);
    CHECK(worst < 1e-12);
}

/* WSP cycles with every valve feature on: the air stored plus the air let out stays the initial
 * air (compressor off), to round-off; and the valves let air out. */
static void air_is_conserved_under_cycling(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    start(&p, &s, &in, ATM + 3.6 * BAR);
    for (int i = 0; i < 3000; ++i) rb_plant_step(&p, &s, &in);
    double worst = 0.0;
    for (int cycle = 0; cycle < 10; ++cycle)
        for (int phase = 0; phase < 3; ++phase) {
            memset(in.hold, phase < 2, RB_AXLES_PER_CAR);
            memset(in.vent, phase == 0, RB_AXLES_PER_CAR);
            for (int i = 0; i < (phase == 2 ? 150 : 75); ++i) {
                rb_plant_step(&p, &s, &in);
                worst = fmax(worst, fabs(rb_plant_air_mass(&p, &s) + s.m_vented - s.m_initial) / s.m_initial);
            }
        }
    printf("WSP cycling: valves let out %.3f g, cylinders %.3f g; air balance within %.1e\n",
           s.m_valves_vented * 1e3, (s.m_vented - s.m_valves_vented) * 1e3, worst);
    CHECK(worst < 1e-12);
    CHECK(s.m_valves_vented > 0.0 && s.m_vented > s.m_valves_vented);
}

int main(void)
{
    bleed_is_the_choked_orifice();
    stroke_follows_the_membrane_lag();
    air_is_conserved_under_cycling();
    return rb_test_summary("test_plant_valve_air");
}

/* Faults in the detailed model (detailed_run.c, cycle_faults and emergency_cycle), each on the
 * component it fails: two cars, emergency from 80 km/h with the emergency circuit (choke from the
 * load-weighing valve's output, limit 4.5 bar, demand 3.8 bar), the fault on car 0 from t = 0, car
 * 1 sound; the pressures after 4 s of the stop (the sound cars' cylinders at the BCU's demand, 2 bar), and the air conserved with what leaks booked as
 * vented. References: the circuit's structure (no choke or no relay output: no cylinder pressure;
 * the limiter's and the stuck relay's pressures; the isolating cocks vent their cylinders) and the
 * sound car. The plant against the detailed model on each kind's stop:
 * tests/unit/simulation/test_detailed_faults.py. */
#include "detailed_fixture.h"
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "railbrake/rb_bcu.h"
#include "railbrake/rb_detailed.h"

#define BAR 1e5
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static rb_detailed_state state;   /* large: off the stack */

typedef struct {
    double pilot, relay, cylinder[RB_AXLES_PER_CAR];   /* car 0, bar gauge */
    double sound_cylinder;                              /* car 1, axle 0, bar gauge */
    double main_reservoir, balance, vented;             /* bar gauge; relative; kg */
} outcome;

/* Runs 4 s of the emergency stop with faults f[0..n) (n = 0: sound). */
static outcome run(const rb_fault *f, int n)
{
    rb_plant_params p;
    rb_detailed_params d;
    rb_bcu_params b;
    rb_error err;
    fill_plant(&p, 2, 80.0 / 3.6);
    for (int c = 0; c < 2; ++c) {   /* the emergency circuit, as test_emergency_circuit.c's */
        p.car[c].emergency_area = 0.25 * M_PI * 1.2e-3 * 1.2e-3;
        p.car[c].emergency_limit = p.atmosphere + 4.5 * BAR;
    }
    p.n_faults = n;
    for (int i = 0; i < n; ++i) p.fault[i] = f[i];
    fill_detailed(&d);
    memset(&b, 0, sizeof b);
    b.n_cars = 2; b.cycle = 0.01; b.atmosphere = p.atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = 1;
    rb_bcu_pressure_map(&p, p.atmosphere + 3.8 * BAR, &b);
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 60.0, 0.05, 1e9, 0.1, 0, {0}};
    int finished = 0;
    outcome o;
    memset(&o, 0, sizeof o);
    if (rb_detailed_init(&p, &d, &b, NULL, &sc, &state, &err) != RB_OK) {
        fprintf(stderr, "init: %s\n", err.message);
        CHECK(0);
        return o;
    }
    CHECK(rb_detailed_advance(&p, &d, &b, &sc, &state, 4.0, NULL, 0, &finished, &err) == RB_OK);
    rb_kpis k;
    rb_detailed_kpis(&p, &state, &k);
    const rb_plant_outputs *out = &state.out;
    o.pilot = (out->pilot[0] - p.atmosphere) / BAR;
    o.relay = (out->relay[0] - p.atmosphere) / BAR;
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) o.cylinder[a] = (out->cylinder[a] - p.atmosphere) / BAR;
    o.sound_cylinder = (out->cylinder[RB_AXLES_PER_CAR] - p.atmosphere) / BAR;
    o.main_reservoir = (out->main_reservoir - p.atmosphere) / BAR;
    o.balance = k.air_balance_error;
    o.vented = k.air_consumed_kg;
    return o;
}

static outcome run1(int kind, int axle, double value)
{
    rb_fault f = {kind, 0, axle, 0.0, value};
    return run(&f, 1);
}

static void show(const char *name, outcome o)
{
    printf("%-30s control %.3f relay %.3f cylinders %.3f %.3f %.3f %.3f bar, sound car %.3f bar, "
           "MR %.2f bar, air balance %.1e\n", name, o.pilot, o.relay, o.cylinder[0], o.cylinder[1], o.cylinder[2],
           o.cylinder[3], o.sound_cylinder, o.main_reservoir, o.balance);
    CHECK(o.balance < 1e-9);
    CHECK(o.sound_cylinder > 1.9);   /* the sound car brakes */
}

int main(void)
{
    outcome sound = run(NULL, 0);
    show("sound", sound);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(sound.cylinder[a] > 1.9);

    /* the emergency valve failed: no choke, and the loop still cuts the EP valve off */
    outcome o = run1(RB_FAULT_EMERGENCY_VALVE, -1, 0.0);
    show("emergency valve failed", o);
    CHECK(o.pilot < 0.01 && o.relay < 0.01);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(o.cylinder[a] < 0.01);

    /* the loop not seen: the EP valve brakes the car to the BCU's demand instead */
    o = run1(RB_FAULT_EMERGENCY_LOOP, -1, 0.0);
    show("loop not seen", o);
    CHECK(fabs(o.cylinder[0] - sound.cylinder[0]) < 0.1);

    /* the relay valve with no output: the control chamber fills, the relay output does not */
    o = run1(RB_FAULT_RELAY_VALVE, -1, 0.0);
    show("relay valve, no output", o);
    CHECK(o.pilot > 1.9 && o.relay < 0.01);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(o.cylinder[a] < 0.01);

    /* stuck at 1.2 bar: the output stops there (above it by at most one BCU cycle's filling) */
    o = run1(RB_FAULT_RELAY_VALVE, -1, 1.2 * BAR);
    show("relay valve stuck at 1.2 bar", o);
    CHECK(o.pilot > 1.9);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(o.cylinder[a] > 1.19 && o.cylinder[a] < 1.3);

    /* the load-weighing valve failed low at 1.5 bar: the control chamber and the cylinders there */
    o = run1(RB_FAULT_LIMITER, -1, 1.5 * BAR);
    show("limiter failed low, 1.5 bar", o);
    CHECK(fabs(o.pilot - 1.5) < 0.02 && fabs(o.cylinder[0] - 1.5) < 0.05);
    /* failed high: the output follows the demand, below the limit either way */
    o = run1(RB_FAULT_LIMITER, -1, 8.0 * BAR);
    show("limiter failed high, 8 bar", o);
    CHECK(fabs(o.cylinder[0] - sound.cylinder[0]) < 1e-9);

    /* a bogie's brake isolated: its two axles vented, the other bogie's as sound */
    rb_fault bogie[2] = {{RB_FAULT_AXLE_ISOLATED, 0, 0, 0.0, 0.0}, {RB_FAULT_AXLE_ISOLATED, 0, 1, 0.0, 0.0}};
    o = run(bogie, 2);
    show("bogie isolated", o);
    CHECK(o.cylinder[0] < 0.01 && o.cylinder[1] < 0.01);
    CHECK(fabs(o.cylinder[2] - sound.cylinder[2]) < 0.05 && fabs(o.cylinder[3] - sound.cylinder[3]) < 0.05);

    /* the car isolated: every cylinder vented */
    o = run1(RB_FAULT_CAR_ISOLATED, -1, 0.0);
    show("car isolated", o);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(o.cylinder[a] < 0.01);

    /* a cylinder leak of 5 mm^2: that cylinder below the relay output, fed through its hold
       port as it leaks; the others as sound */
    o = run1(RB_FAULT_CYLINDER_LEAK, 0, 5e-6);
    show("cylinder leak 5 mm2", o);
    CHECK(o.cylinder[0] < o.relay - 0.03 && o.cylinder[0] > 0.5);
    CHECK(fabs(o.cylinder[1] - o.relay) < 0.02);
    CHECK(o.vented > sound.vented);

    /* the MR pipe leaking 50 mm^2: the line drains, the check valves keep the supply reservoirs */
    o = run1(RB_FAULT_PIPE_LEAK, -1, 50e-6);
    show("MR pipe leak 50 mm2", o);
    CHECK(o.main_reservoir < sound.main_reservoir - 0.5);
    CHECK(o.vented > sound.vented + 0.05);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) CHECK(fabs(o.cylinder[a] - sound.cylinder[a]) < 1e-3);

    /* a WSP vent valve stuck open: that cylinder fed through its hold port as it vents */
    o = run1(RB_FAULT_VENT_STUCK_OPEN, 0, 0.0);
    show("vent valve stuck open", o);
    CHECK(o.cylinder[0] < o.cylinder[1] - 0.3);
    return rb_test_summary("detailed_faults");
}

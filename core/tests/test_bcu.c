/* Default WSP on synthetic wheel speeds: detection, vent/hold/re-apply, safety timer. */
#include "rb_test.h"
#include "railbrake/rb_bcu.h"

#include <math.h>
#include <string.h>

static rb_wsp_inputs inputs(double t, double train, double axle0)
{
    rb_wsp_inputs in;
    memset(&in, 0, sizeof in);
    in.time = t; in.cycle = 0.01; in.n_axles = 4; in.atmosphere = 1e5;
    for (int a = 0; a < 4; ++a) { in.wheel_speed[a] = train; in.cylinder[a] = 4e5; in.demand[a] = 4e5; }
    in.wheel_speed[0] = axle0;
    return in;
}

/* Blending under WSP: a motor car's ED demand is the car's whole demand, also while its WSP acts;
 * the friction brake's pressure is for the demand less the ED force available, less again what the
 * traction's slide control cut (ed_force below ed_available): the friction brake gives way. */
static int wsp_acting;
static void acting_wsp(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out)
{
    (void)context; (void)in;
    memset(out, 0, sizeof *out);
    out->active[0] = (uint8_t)wsp_acting;
}

static void test_ed_blending_under_wsp(void)
{
    static rb_bcu_params b;
    static rb_bcu_state s;
    static rb_plant_outputs o;
    memset(&b, 0, sizeof b);
    b.n_cars = 1; b.cycle = 0.01; b.atmosphere = 1e5; b.emergency_decel = 1.0; b.ed_in_emergency = 1;
    b.car_mass[0] = 50e3; b.pressure_gain[0] = 10.0; b.pressure_max[0] = 5e5; b.motor[0] = 1;
    b.wsp_enabled = 1; b.wsp = acting_wsp;
    CHECK(rb_bcu_init(&b, NULL, &s, NULL) == RB_OK);
    rb_brake_demand d = {1.0, 0.0};
    double t = 0.0;
    for (int a = 0; a < 4; ++a) o.wheel_speed_measured[a] = 50.0;
    o.ed_available[0] = 20e3; o.ed_force[0] = 20e3;
    #define CYCLE() do { o.time = t; rb_bcu_update(&b, &s, &d, &o); t += b.cycle; } while (0)
    CYCLE();
    CHECK_CLOSE(s.command.ed_demand[0], 50e3, 1e-12, 0.0);
    CHECK_CLOSE(s.command.pressure_demand[0], 10.0 * 30e3, 1e-12, 0.0);   /* the 30 kN the ED lacks */
    wsp_acting = 1;
    o.ed_force[0] = 5e3;   /* the slide control cut 15 kN */
    CYCLE(); CYCLE();      /* the WSP's activity is seen at the next cycle */
    CHECK_CLOSE(s.command.ed_demand[0], 50e3, 1e-12, 0.0);
    CHECK_CLOSE(s.command.pressure_demand[0], 10.0 * 15e3, 1e-12, 0.0);   /* 50 - 20 - 15 kN, not 45 kN */
    o.ed_force[0] = 0.0;   /* all cut: the friction brake's 30 kN less 20 */
    CYCLE();
    CHECK_CLOSE(s.command.pressure_demand[0], 10.0 * 10e3, 1e-12, 0.0);
    o.ed_available[0] = 0.0; o.ed_force[0] = 0.0;   /* ED brake lost: the friction brake takes all */
    CYCLE();
    CHECK_CLOSE(s.command.pressure_demand[0], 10.0 * 50e3, 1e-12, 0.0);
    #undef CYCLE
}

static void test_slide_cycle(void)
{
    rb_wsp_params p;
    rb_wsp_default w;
    rb_wsp_commands out;
    rb_wsp_default_params(&p);
    rb_wsp_default_reset(&w, &p);
    double t = 0.0, v = 50.0, axle = 50.0;
    rb_wsp_inputs in = inputs(t, v, axle);
    rb_wsp_default_step(&w, &in, &out);
    CHECK(out.vent[0] == 0 && out.hold[0] == 0);
    /* axle 0 decelerates at 5 m/s^2 while the train does 1 m/s^2: vent within 3 cycles */
    int vent_at = -1;
    for (int i = 1; i < 50 && vent_at < 0; ++i) {
        t += 0.01; v -= 0.01; axle -= 0.05;
        in = inputs(t, v, axle);
        rb_wsp_default_step(&w, &in, &out);
        if (out.vent[0]) vent_at = i;
        CHECK(out.vent[1] == 0 && out.hold[1] == 0);
    }
    CHECK(vent_at > 0 && vent_at <= 3);
    CHECK(out.hold[0] == 1);
    /* the wheel recovers at +5 m/s^2: hold, then pulsed re-application, then apply */
    int held = 0, pulsed = 0;
    for (int i = 0; i < 400; ++i) {
        t += 0.01; v -= 0.01; axle = axle + 0.05 < v ? axle + 0.05 : v;
        in = inputs(t, v, axle);
        rb_wsp_default_step(&w, &in, &out);
        held |= out.hold[0] && !out.vent[0];
        pulsed += w.mode[0] == RB_WSP_REAPPLY && !out.hold[0];
    }
    CHECK(held);
    CHECK(pulsed > 0);
    CHECK(w.mode[0] == RB_WSP_APPLY);
    CHECK(w.trips == 0);
}

/* The slip set-point controller's pressure memory: after a slide vented from a cylinder of 3 bar
 * gauge, it re-applies at once up to setpoint_memory x 3 bar, holds there, and opens again once the
 * ceiling, rising at setpoint_ramp, has passed the cylinder. */
static void test_setpoint_pressure_memory(void)
{
    rb_wsp_params p;
    rb_wsp_default w;
    rb_wsp_commands out;
    rb_wsp_default_params(&p);
    p.controller = RB_WSP_SLIP_SETPOINT;
    rb_wsp_default_reset(&w, &p);
    double t = 0.0;
    rb_wsp_inputs in = inputs(t, 50.0, 50.0);   /* cylinders at their demand, 3 bar gauge */
    rb_wsp_default_step(&w, &in, &out);
    CHECK(out.vent[0] == 0 && out.hold[0] == 0);
    /* axle 0 falls 1 m/s behind (beyond the detection's 0.4 m/s + 0.5 %): engaged, it vents */
    int vented = 0;
    for (int i = 0; i < 5; ++i) {
        t += 0.01;
        in = inputs(t, 50.0, 50.0 - 0.2 * (i + 1));
        rb_wsp_default_step(&w, &in, &out);
        vented |= out.vent[0];
    }
    CHECK(vented && w.engaged[0]);
    CHECK_CLOSE(w.memory[0], 4e5, 0.0, 1.0);   /* the cylinder when it began to vent, Pa abs */
    /* the wheel is back with the train, its cylinder vented to 1 bar gauge: it re-applies */
    for (int i = 0; i < 20; ++i) {
        t += 0.01;
        in = inputs(t, 50.0, 50.0);
        for (int a = 0; a < 4; ++a) in.cylinder[a] = 2e5;
        rb_wsp_default_step(&w, &in, &out);
    }
    CHECK(out.hold[0] == 0 && out.vent[0] == 0);
    /* at 2.7 bar gauge, above 0.87 x 3 bar: held until the ceiling has risen past it */
    double ceiling_passes = (2.7e5 / p.setpoint_memory - (w.memory[0] - 1e5)) / p.setpoint_ramp;
    double opened = -1.0;
    for (int i = 0; i < 200 && opened < 0.0; ++i) {
        t += 0.01;
        in = inputs(t, 50.0, 50.0);
        for (int a = 0; a < 4; ++a) in.cylinder[a] = 3.7e5;
        rb_wsp_default_step(&w, &in, &out);
        if (i == 0) CHECK(out.hold[0] == 1 && out.vent[0] == 0 && w.mode[0] == RB_WSP_HOLD);
        if (!out.hold[0]) opened = (i + 1) * 0.01;
    }
    CHECK(ceiling_passes > 0.1);
    CHECK_CLOSE(opened, ceiling_passes, 0.0, 0.015);
    CHECK(w.trips == 0);
}

static void test_safety_timer_on_continuous_venting(void)
{
    rb_wsp_params p;
    rb_wsp_default w;
    rb_wsp_commands out;
    rb_wsp_default_params(&p);
    rb_wsp_default_reset(&w, &p);
    /* axle 0 stays 5 m/s below the others (a slide that never ends, e.g. a bad sensor) */
    double vented = 0.0;
    for (int i = 0; i < 1000; ++i) {
        rb_wsp_inputs in = inputs(i * 0.01, 50.0, 45.0);
        rb_wsp_default_step(&w, &in, &out);
        vented += out.vent[0] * 0.01;
    }
    CHECK(w.trips == 1);
    CHECK(w.mode[0] == RB_WSP_INHIBITED);
    CHECK(out.vent[0] == 0 && out.hold[0] == 0);
    CHECK_CLOSE(vented, p.safety_time, 0.01, 0.02);
}

static void test_cylinder_vented_without_command_isolates_the_axle(void)
{
    rb_wsp_params p;
    rb_wsp_default w;
    rb_wsp_commands out;
    rb_wsp_default_params(&p);
    rb_wsp_default_reset(&w, &p);
    for (int i = 0; i < 700; ++i) {
        rb_wsp_inputs in = inputs(i * 0.01, 50.0, 50.0);
        in.cylinder[2] = 1.2e5;   /* 0.2 bar against a 3 bar demand */
        rb_wsp_default_step(&w, &in, &out);
    }
    CHECK(w.trips == 1);
    CHECK(w.mode[2] == RB_WSP_ISOLATED);
    CHECK(out.hold[2] == 1 && out.vent[2] == 0);
    CHECK(out.hold[0] == 0);
}

/* The service jerk limit against the analytic ramp: a step of full service on a 1-car BCU with
 * constant decelerations (demand_tables = 0) gives a demanded force rising at jerk x mass per s
 * from the step's first cycle until the full service force, then held; releasing ramps down at the
 * same rate; the emergency demand is not limited. */
static void test_service_jerk_ramp(void)
{
    const double cycle = 0.01, jerk = 0.75, decel = 0.9, mass = 5e4, gain = 2.0, atm = 1.01325e5;
    rb_bcu_params b;
    rb_bcu_state s;
    rb_plant_outputs out;
    rb_error err;
    memset(&b, 0, sizeof b);
    memset(&out, 0, sizeof out);
    b.n_cars = 1; b.cycle = cycle; b.atmosphere = atm; b.service_decel = decel; b.emergency_decel = 1.2;
    b.car_mass[0] = mass; b.pressure_gain[0] = gain; b.pressure_offset[0] = atm; b.pressure_max[0] = 1e6;
    b.service_jerk = jerk;
    CHECK(rb_bcu_init(&b, NULL, &s, &err) == RB_OK);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) out.wheel_speed_measured[a] = 30.0;
    rb_brake_demand d = {.emergency = 0.0, .service = 0.0};
    int k = 0;
    for (; k < 10; ++k) { out.time = k * cycle; rb_bcu_update(&b, &s, &d, &out); }
    d.service = 1.0;   /* the step, between cycles 9 and 10 */
    const double ramp = decel / jerk;   /* s to full service */
    double worst = 0.0;
    for (int i = 1; k < 10 + (int)(3.0 * ramp / cycle); ++k, ++i) {
        out.time = k * cycle;
        rb_bcu_update(&b, &s, &d, &out);
        double expected = fmin(jerk * i * cycle, decel) * mass;     /* N */
        double force = (s.command.pressure_demand[0] - atm) / gain;
        worst = fmax(worst, fabs(force - expected));
    }
    CHECK_CLOSE(worst, 0.0, 0.0, 1e-6 * decel * mass);
    CHECK_CLOSE(s.service_applied, 1.0, 0.0, 1e-12);
    d.service = 0.5;   /* a release to half service: down at the same rate */
    rb_bcu_update(&b, &s, &d, &(rb_plant_outputs){.time = k * cycle});
    CHECK_CLOSE(s.service_applied, 1.0 - jerk * cycle / decel, 0.0, 1e-12);
    d.emergency = 1.0;   /* emergency: the full emergency force at once */
    out.time = (k + 1) * cycle;
    rb_bcu_update(&b, &s, &d, &out);
    CHECK_CLOSE((s.command.pressure_demand[0] - atm) / gain, 1.2 * mass, 1e-12, 0.0);
    b.service_jerk = -1.0;
    CHECK(rb_bcu_check(&b, &err) == RB_EINVAL);
}

int main(void)
{
    test_ed_blending_under_wsp();
    test_slide_cycle();
    test_setpoint_pressure_memory();
    test_safety_timer_on_continuous_venting();
    test_cylinder_vented_without_command_isolates_the_axle();
    test_service_jerk_ramp();
    return rb_test_summary("test_bcu");
}

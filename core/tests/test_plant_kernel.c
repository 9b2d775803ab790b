/* The wheelset kernels: the vector one (where this CPU has it) against the portable reference,
 * bit for bit, over a WSP-cycling emergency stop on wet rail with zones and locking wheels; and
 * the single 1 ms step's timing rules (valve delay, exponential air link). */
#include "plant_fixture.h"
#include "rb_test.h"
#include "railbrake/rb_run.h"
#include "../src/plant_internal.h"   /* rb_plant_link_mass */

#include <math.h>
#include <stdio.h>
#include <string.h>

static void run_stop(int kernel, int wsp, rb_run_state *r, rb_kpis *k, char *name)
{
    static rb_plant_params p;
    static rb_bcu_params b;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1, 0, {0}};
    int finished = 0;
    fill_plant(&p, 4, 250 / 3.6);
    p.kernel = kernel;
    p.n_conditions = 2;   /* wet (Polach) with a low-adhesion zone whose friction falls with rolling speed */
    p.condition[0] = (rb_plant_condition){{0.30, 0.40, 0.25, 0.3, 0.1, 0.0}, 0.5, 4.0, 0.0};
    p.condition[1] = (rb_plant_condition){{0.24, 0.40, 0.20, 0.2, 0.05, 3.6 / 250.0}, 0.6, 4.0, 0.0};
    p.n_zones = 1;
    p.zone[0] = (rb_track_zone){300.0, 900.0, 1};
    memset(&b, 0, sizeof b);
    b.n_cars = 4; b.cycle = 0.01; b.atmosphere = p.atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = wsp;
    rb_bcu_pressure_map(&p, p.atmosphere + 3.8e5, &b);
    CHECK(rb_run_init(&p, &b, NULL, &sc, r, NULL) == RB_OK);
    CHECK(rb_run_advance(&p, &b, &sc, r, 1e9, NULL, 0, &finished, NULL) == RB_OK);
    CHECK(finished);
    rb_run_kpis(&p, r, k);
    snprintf(name, 16, "%s", rb_plant_kernel_name(&r->plant));
}

/* With WSP (valves cycling) and without (wheels locking in the zone). */
static void test_kernels_agree(int wsp)
{
    static rb_run_state a, b;
    rb_kpis ka, kb;
    char na[16], nb[16];
    run_stop(RB_PLANT_KERNEL_PORTABLE, wsp, &a, &ka, na);
    run_stop(RB_PLANT_KERNEL_AUTO, wsp, &b, &kb, nb);
    printf("WSP %s, kernels %s / %s: %.6f / %.6f m, lock events %g, ", wsp ? "on" : "off", na, nb,
           ka.stopping_distance_m, kb.stopping_distance_m, ka.wheel_lock_events);
    if (!wsp) CHECK(ka.wheel_lock_events > 0);
    CHECK(strcmp(na, "portable") == 0);
    CHECK(ka.stopped && kb.stopped);
    CHECK(ka.stopping_distance_m == kb.stopping_distance_m);
    CHECK(memcmp(a.plant.omega, b.plant.omega, sizeof a.plant.omega) == 0);
    CHECK(memcmp(a.plant.force, b.plant.force, sizeof a.plant.force) == 0);
    CHECK(memcmp(a.plant.x, b.plant.x, sizeof a.plant.x) == 0);
    CHECK(a.plant.step == b.plant.step);
    printf("%.3f kg air\n", ka.air_consumed_kg);
}

/* A vent command opens the valve after exactly its response delay: with 14.5 ms at 1 ms steps the
 * cylinder of the vented axle follows its untouched neighbour for 14 steps, loses about half a
 * step's vent flow in the 15th and a whole step's in the 16th. */
static void test_valve_delay(void)
{
    rb_plant_params p;
    static rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 1, 0.0);
    p.car[0].valve_delay = 0.0145;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p.atmosphere + 3.0e5;
    for (int i = 0; i < 3000; ++i) rb_plant_step(&p, &s, &in);
    in.vent[0] = in.hold[0] = in.hold[1] = 1;
    for (int i = 0; i < 14; ++i) {
        rb_plant_step(&p, &s, &in);
        CHECK(s.m_cyl[0] == s.m_cyl[1] && !s.vent_effective[0]);
    }
    rb_plant_step(&p, &s, &in);
    CHECK(s.vent_effective[0]);
    double half = s.m_cyl[1] - s.m_cyl[0], before = s.m_cyl[0];
    rb_plant_step(&p, &s, &in);
    double whole = before - s.m_cyl[0];
    printf("vent: %.3e kg in the 15th step, %.3e kg in the 16th\n", half, whole);
    CHECK(half > 0.45 * whole && half < 0.55 * whole);
}

/* One stiff air link (a small volume vented through a large port) never undershoots the
 * atmosphere, and a slow one moves h q to first order: the exponential link. */
static void test_vent_link(void)
{
    rb_plant_params p;
    static rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 1, 0.0);
    p.car[0].vent_area = 2e-4;   /* 10x: y = h q / dm_eq well above 1/16 */
    p.car[0].valve_delay = 0.0;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p.atmosphere + 3.0e5;
    for (int i = 0; i < 3000; ++i) rb_plant_step(&p, &s, &in);
    in.vent[0] = in.hold[0] = 1;
    double k = 287.05 * p.temperature / p.car[0].cylinder_volume;
    for (int i = 0; i < 200; ++i) {
        rb_plant_step(&p, &s, &in);
        CHECK(s.m_cyl[0] * k >= p.atmosphere - 1e-6);
    }
    CHECK_CLOSE(s.m_cyl[0] * k, p.atmosphere, 0, 5.0);
}

/* The link law against its definition, dm = dm_eq (1 - exp(-h q / dm_eq)) with q the orifice flow
 * (ISO 6358 form, linear above the laminar ratio), evaluated in long double: within 1e-12 relative in
 * every region, in both directions, including pressures within a few Pa of each other, where the
 * plant takes the linear region's y without the pressures. */
static long double link_reference(const rb_plant_derived *d, double pi, double pj, double g, double ik)
{
    const long double b = d->orifice.b, lam = RB_ORIFICE_LAMINAR_RATIO;
    long double up = pi > pj ? pi : pj, down = pi > pj ? pj : pi, r = down / up, up_phi;
    long double s_lam = (lam - b) / (1.0L - b), slope = sqrtl(1.0L - s_lam * s_lam) / (1.0L - lam);
    long double s_r = (r - b) / (1.0L - b);
    if (r <= b) up_phi = up;
    else if (r >= lam) up_phi = slope * (up - down);   /* p_up phi = slope (p_up - p_down), no cancellation */
    else up_phi = up * sqrtl(1.0L - s_r * s_r);
    long double flow = (long double)d->h * g * up_phi, equalise = fabsl((long double)pi - pj) * ik;
    long double dm = -equalise * expm1l(-flow / equalise);
    return pi > pj ? dm : -dm;
}

static void test_link_law(void)
{
    rb_plant_params p;
    static rb_plant_state s;
    fill_plant(&p, 1, 0.0);
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    const rb_plant_derived *d = &s.derived;
    const double ik = d->ik_hold[0], g[3] = {d->g_hold[0], 30.0 * d->g_hold[0], 1e-3 * d->g_hold[0]};
    const double ratio[] = {0.2, 0.528, 0.6, 0.9, 0.99, 0.998, 0.999, 0.9995, 0.99999, 1.0 - 2e-8};
    double worst = 0.0;
    for (int k = 0; k < 3; ++k)
        for (size_t i = 0; i < sizeof ratio / sizeof ratio[0]; ++i)
            for (int dir = 0; dir < 2; ++dir) {
                double hi = 6.5e5, lo = hi * ratio[i];
                double pi = dir ? lo : hi, pj = dir ? hi : lo;
                long double ref = link_reference(d, pi, pj, g[k], ik);
                double dm = rb_plant_link_mass(d, pi, pj, g[k], ik);
                double rel = (double)fabsl((dm - ref) / ref);
                if (rel > worst) worst = rel;
                if (!(rel < 1e-12)) printf("  g %d ratio %.8f dir %d: rel %.2e\n", k, ratio[i], dir, rel);
                CHECK(rel < 1e-12);
            }
    printf("link law: worst %.1e relative to the long-double reference\n", worst);
    CHECK(rb_plant_link_mass(d, 5e5, 5e5 - 0.005, g[0], ik) == 0.0);   /* balanced to 0.01 Pa */
    CHECK(rb_plant_link_mass(d, 5e5, 1e5, 0.0, ik) == 0.0);            /* closed */
}

/* The link law's other forms give rb_plant_link_mass's result bit for bit: the branch-free one of
 * the car valves' vector loops (rb_plant_link_mass_select), and the fixed links' one with its
 * laminar fill from init (rb_plant_link_mass_fixed), at every pressure ratio (choked, subsonic,
 * laminar, balanced), both directions, open, throttled and closed links, for the usual law and a
 * laminar-only one (critical ratio above the laminar region). */
static void test_link_forms(void)
{
    rb_plant_params p;
    static rb_plant_state s;
    static rb_plant_derived derived;
    const double ratio[] = {0.1, 0.528, 0.6, 0.9, 0.99, 0.998, 0.999, 0.9995, 0.99999, 1.0 - 2e-8, 1.0};
    int compared = 0;
    fill_plant(&p, 1, 0.0);
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    for (int law_kind = 0; law_kind < 2; ++law_kind) {
        derived = s.derived;
        if (law_kind) {   /* laminar only (a critical ratio the plant's check does not allow) */
            rb_orifice_law_init(0.9995, &derived.orifice);
            derived.h_laminar = derived.h * derived.orifice.laminar_slope;
        }
        const rb_plant_derived *d = &derived;
        CHECK(d->orifice.laminar_only == law_kind);
        const rb_plant_link_law law = rb_plant_link_law_of(d);
        const double ik[2] = {d->ik_hold[0], d->ik_ep_in[0]};
        const double g[4] = {d->g_hold[0], 30.0 * d->g_hold[0], 1e-3 * d->g_hold[0], 0.0};
        for (int m = 0; m < 2; ++m)
            for (int k = 0; k < 4; ++k) {
                double fill = rb_plant_link_laminar_fill(d, g[k], ik[m]);
                for (size_t i = 0; i < sizeof ratio / sizeof ratio[0]; ++i)
                    for (int dir = 0; dir < 2; ++dir) {
                        double hi = 6.5e5, lo = hi * ratio[i], pi = dir ? lo : hi, pj = dir ? hi : lo;
                        double ref = rb_plant_link_mass(d, pi, pj, g[k], ik[m]);
                        double sel = rb_plant_link_mass_select(&law, pi, pj, g[k], ik[m]);
                        double fixed = rb_plant_link_mass_fixed(d, pi, pj, g[k], ik[m], fill);
                        CHECK(memcmp(&ref, &sel, sizeof ref) == 0);
                        CHECK(memcmp(&ref, &fixed, sizeof ref) == 0);
                        compared += 2;
                        double y = rb_plant_link_y_select(&law, pi, pj, g[k], ik[m]);
                        if (!(y > 0.0625)) {   /* the series alone, as a pass without a larger y takes it */
                            double series = rb_plant_link_mass_of_fill(pi, pj, g[k], ik[m], rb_one_minus_exp_neg_series(y));
                            CHECK(memcmp(&ref, &series, sizeof ref) == 0);
                            ++compared;
                        }
                    }
            }
    }
    printf("link forms: %d results equal to rb_plant_link_mass bit for bit\n", compared);
}

/* The car valves' vector and scalar forms (the AVX2 and portable builds) with a failed EP valve and
 * an isolated car among sound ones, under a demand that rises, holds and falls (inlets, exhausts,
 * balanced valves): the same air state bit for bit. */
static void test_kernels_agree_car_faults(void)
{
    static rb_plant_params p;
    static rb_plant_state a, b;
    rb_plant_inputs in;
    fill_plant(&p, 6, 200 / 3.6);
    p.n_faults = 2;
    p.fault[0] = (rb_fault){RB_FAULT_EP_VALVE, 1, -1, 0.5, 0.0};
    p.fault[1] = (rb_fault){RB_FAULT_CAR_ISOLATED, 4, -1, 1.0, 0.0};
    p.kernel = RB_PLANT_KERNEL_PORTABLE;
    CHECK(rb_plant_init(&p, &a, NULL) == RB_OK);
    p.kernel = RB_PLANT_KERNEL_AUTO;
    CHECK(rb_plant_init(&p, &b, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    for (int i = 0; i < 6000; ++i) {
        double t = i * 1e-3, demand = t < 3.0 ? p.atmosphere + 1.2e5 * t : (t < 4.5 ? p.atmosphere + 3.6e5 : p.atmosphere + 1.5e5);
        for (int c = 0; c < p.n_cars; ++c) in.pressure_demand[c] = demand + 1e4 * c;
        p.kernel = RB_PLANT_KERNEL_PORTABLE;
        rb_plant_step(&p, &a, &in);
        p.kernel = RB_PLANT_KERNEL_AUTO;
        rb_plant_step(&p, &b, &in);
    }
    printf("car faults, kernels %s / %s: relay %.0f / %.0f Pa (car 0), isolated car %.0f Pa\n",
           rb_plant_kernel_name(&a), rb_plant_kernel_name(&b), a.m_relay[0] * a.derived.k_relay[0],
           b.m_relay[0] * b.derived.k_relay[0], a.m_relay[4] * a.derived.k_relay[4]);
    CHECK(a.m_relay[0] * a.derived.k_relay[0] > p.atmosphere + 1e5);   /* braked */
    CHECK(a.m_relay[4] * a.derived.k_relay[4] < p.atmosphere + 100.0);   /* isolated: vented */
    CHECK(memcmp(a.m_pilot, b.m_pilot, sizeof a.m_pilot) == 0);
    CHECK(memcmp(a.m_relay, b.m_relay, sizeof a.m_relay) == 0);
    CHECK(memcmp(a.m_supply, b.m_supply, sizeof a.m_supply) == 0);
    CHECK(memcmp(a.m_cyl, b.m_cyl, sizeof a.m_cyl) == 0);
    CHECK(memcmp(a.ep_demand_lag, b.ep_demand_lag, sizeof a.ep_demand_lag) == 0);
    CHECK(a.m_vented == b.m_vented);
}

/* The kernel's Polach coefficient (divisions merged, rb_atan_ratio_parts) against the law with libm
 * (rb_polach_coefficient_fast) over creeps from 1e-7 to 1 and speeds from 0.5 to 100 m/s, on dry
 * and wet rail (each axle its conditioning) and wet rail with the rolling-speed factor: within
 * 1e-14 relative. */
static void test_polach(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    double worst = 0.0;
    fill_plant(&p, 1, 50.0);
    p.n_conditions = 1;
    const rb_plant_condition sets[3] = {{{0.55, 0.40, 0.60, 0.4, 0.2, 0.0}, 1.0, 0.0, 0.0},
                                        {{0.30, 0.40, 0.25, 0.3, 0.1, 0.0}, 0.5, 4.0, 0.0},
                                        /* wet with the rolling-speed factor (v_ref 100 km/h) */
                                        {{0.18, 0.40, 0.20, 0.3, 0.1, 3.6 / 100.0}, 1.0, 0.0, 0.0}};
    for (int set = 0; set < 3; ++set) {
        p.condition[0] = sets[set];
        CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
        double wheel_load = 0.5 * p.car[0].vehicle.wheelset.axle_load * 9.80665;
        for (int axle = 0; axle < RB_AXLES_PER_CAR; ++axle)
            for (int i = 0; i <= 700; ++i)
                for (int j = 0; j <= 20; ++j) {
                    double creep = -pow(10.0, -7.0 + i * 0.01), speed = 0.5 * pow(200.0, j / 20.0);
                    double law = rb_polach_coefficient_fast(creep, speed, wheel_load, &p.car[0].contact, &s.polach[axle]);
                    double e = fabs(rb_plant_polach(&s, axle, creep, speed) - law) / fabs(law);
                    if (e > worst) worst = e;
                }
    }
    printf("kernel Polach coefficient: largest relative error %.2e against the law with libm\n", worst);
    CHECK(worst < 1e-14);
}

/* Without faults the step takes its constant no-fault record instead of gathering one: the same
 * state bit for bit as a plant whose only fault never starts (gathered in every step), over an
 * emergency stop with the WSP valves commanded to cycle. */
static void test_no_fault_shortcut(void)
{
    static rb_plant_params p, q;
    static rb_plant_state a, b;
    rb_plant_inputs in;
    fill_plant(&p, 2, 200 / 3.6);
    q = p;
    q.n_faults = 1;
    q.fault[0] = (rb_fault){RB_FAULT_VENT_STUCK_OPEN, 1, 2, 1e9, 0.0};
    CHECK(rb_plant_init(&p, &a, NULL) == RB_OK && rb_plant_init(&q, &b, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    for (int c = 0; c < 2; ++c) in.pressure_demand[c] = p.atmosphere + 3.8e5;
    for (int i = 0; i < 20000; ++i) {
        for (int x = 0; x < 8; ++x) in.vent[x] = in.hold[x] = (uint8_t)((i / 40 + x) % 3 == 0);
        rb_plant_step(&p, &a, &in);
        rb_plant_step(&q, &b, &in);
    }
    CHECK(a.v[0] < 200 / 3.6 - 10.0);   /* braked */
    CHECK(memcmp(a.m_cyl, b.m_cyl, sizeof a.m_cyl) == 0);
    CHECK(memcmp(a.omega, b.omega, sizeof a.omega) == 0);
    CHECK(memcmp(a.x, b.x, sizeof a.x) == 0);
    CHECK(memcmp(a.vent_effective, b.vent_effective, sizeof a.vent_effective) == 0);
    CHECK(a.m_vented == b.m_vented && a.m_vented > 0.0);
}

/* ED brake of a motor car: asked for in the steps' loop only when some car has a demand; the
 * force follows min(demand, limit) with the first-order lag h / (tau + h) per step, so after n
 * steps from 0 it is target (1 - (1 - lag)^n); a car that lost its ED gives none, and a demand of 0
 * lets the force decay by the same lag. */
static void test_ed_force(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 2, 50.0);
    p.car[0].vehicle.motor = p.car[1].vehicle.motor = 1;
    for (int c = 0; c < 2; ++c) {
        rb_ed_curve *e = &p.car[c].vehicle.ed;
        memset(e, 0, sizeof *e);
        e->terms = 1; e->c0[0] = 40e3; e->scale = 1.0;   /* 40 kN at any speed */
    }
    p.n_faults = 1;
    p.fault[0] = (rb_fault){RB_FAULT_ED_LOST, 1, -1, 0.0, 0.0};
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    in.ed_demand[0] = in.ed_demand[1] = 100e3;   /* above the limit: the limit */
    const double lag = 1e-3 / (0.3 + 1e-3);
    for (int i = 0; i < 200; ++i) rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.ed_force[0], 40e3 * (1.0 - pow(1.0 - lag, 200)), 1e-12, 0.0);
    CHECK(s.ed_force[1] == 0.0);   /* lost */
    double held = s.ed_force[0];
    in.ed_demand[0] = in.ed_demand[1] = 0.0;
    for (int i = 0; i < 100; ++i) rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.ed_force[0], held * pow(1.0 - lag, 100), 1e-12, 0.0);
    CHECK(held > 15e3);
}

/* The traction control's slide control of the ED brake: an axle of the motor car sliding deeper
 * than ed_slide_slip cuts the fraction of the asked force let through by ed_cut_rate per second;
 * with every axle rolling again it comes back by ed_restore_rate per second; the force achieved
 * is that fraction of the asked (lagged) force; the outputs report both. A trailer's ED stays untouched. */
static void test_ed_slide_control(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    rb_plant_inputs in;
    fill_plant(&p, 1, 50.0);
    p.car[0].vehicle.motor = 1;
    rb_ed_curve *e = &p.car[0].vehicle.ed;
    memset(e, 0, sizeof *e);
    e->terms = 1; e->c0[0] = 40e3; e->scale = 1.0;
    p.car[0].ed_slide_slip = 0.01; p.car[0].ed_slide_release = 0.003;
    p.car[0].ed_cut_rate = 50.0; p.car[0].ed_restore_rate = 0.5;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    memset(&in, 0, sizeof in);
    in.ed_demand[0] = 40e3;
    for (int i = 0; i < 100; ++i) rb_plant_step(&p, &s, &in);
    CHECK(s.ed_slide_factor[0] == 1.0 && s.ed_force[0] == s.ed_asked[0] && s.ed_force[0] > 10e3);
    double r = p.car[0].vehicle.wheelset.wheel_radius;
    s.omega[2] = 0.9 * s.v[0] / r;   /* 10 % slip on one axle */
    rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.ed_slide_factor[0], 1.0 - 50.0 * 1e-3, 1e-12, 0.0);
    CHECK_CLOSE(s.ed_force[0], s.ed_slide_factor[0] * s.ed_asked[0], 1e-12, 0.0);
    static rb_plant_outputs out;   /* the BCU is told both: achieved, and available before the cut */
    rb_plant_update_outputs(&p, &s, &out);
    CHECK(out.ed_force[0] == s.ed_force[0] && out.ed_available[0] == s.ed_asked[0] && out.ed_available[0] > out.ed_force[0]);
    for (int k = 0; k < RB_AXLES_PER_CAR; ++k) s.omega[k] = s.v[0] / r;   /* rolling */
    double cut = s.ed_slide_factor[0];
    rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.ed_slide_factor[0], cut + 0.5 * 1e-3, 1e-12, 0.0);
    p.car[0].ed_slide_release = 0.02;   /* bad: the release above the slide threshold */
    CHECK(rb_plant_check(&p, NULL) != RB_OK);
}

int main(void)
{
    test_ed_force();
    test_ed_slide_control();
    test_link_law();
    test_link_forms();
    test_kernels_agree_car_faults();
    test_polach();
    test_no_fault_shortcut();
    test_kernels_agree(1);
    test_kernels_agree(0);
    test_valve_delay();
    test_vent_link();
    return rb_test_summary("test_plant_kernel");
}

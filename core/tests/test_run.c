/* The scenario runner (run.c): its available-adhesion KPI, whose peaks are followed from sample to
 * sample, must equal the mean of full searches of Polach's curve (rb_polach_peak) at the same
 * samples; its bench (plant_bench.c) replays the run's own plant inputs. */
#include "plant_fixture.h"
#include "rb_test.h"
#include "railbrake/rb_run.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Runs the emergency stop and, after every sample the run takes, the full search over the same
 * axles; returns the relative difference of the two means. */
static double followed_against_full(rb_plant_params *p, double stop_time_limit)
{
    static rb_run_state r;   /* large: off the stack */
    rb_bcu_params b;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, stop_time_limit, 0.05, 1e9, 0.1, 0, {0}};
    int finished = 0;
    memset(&b, 0, sizeof b);
    b.n_cars = p->n_cars; b.cycle = 0.01; b.atmosphere = p->atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = 1;
    rb_bcu_pressure_map(p, p->atmosphere + 3.8e5, &b);
    CHECK(rb_run_init(p, &b, NULL, &sc, &r, NULL) == RB_OK);
    double full_sum = 0.0;
    long samples = 0;
    while (!finished) {
        CHECK(rb_run_advance(p, &b, &sc, &r, r.out.time + 0.5e-3, NULL, 0, &finished, NULL) == RB_OK);
        if (r.peak_samples == samples) continue;
        samples = r.peak_samples;
        double sum = 0.0;
        for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) sum += rb_plant_peak_adhesion(p, &r.plant, a);
        full_sum += sum / (p->n_cars * RB_AXLES_PER_CAR);
    }
    CHECK(samples > 100);
    double followed = r.peak_sum / r.peak_samples, full = full_sum / samples;
    return fabs(followed - full) / full;
}

/* Heavy rain with the rail conditioned by the axles ahead (every axle its own curve), a dry zone
 * on the way (the axles change curves there): one branch, so the two agree to 1e-10. */
static void test_conditioned_rail_with_a_zone(void)
{
    static rb_plant_params p;
    fill_plant(&p, 4, 300 / 3.6);
    p.n_conditions = 2;
    p.condition[1] = p.condition[0];   /* the fixture's: Polach dry */
    p.condition[0] = (rb_plant_condition){{0.126, 0.126, 1.37, 0.30, 0.10}, 0.2, 8.7, 0.0};
    p.n_zones = 1;
    p.zone[0] = (rb_track_zone){1500.0, 2500.0, 1};
    double difference = followed_against_full(&p, 400.0);
    printf("conditioned rail, dry zone: followed peaks against full searches %.2e\n", difference);
    CHECK(difference <= 1e-10);
}

/* A curve on which a second inner maximum forms as the train slows (at about 20 m/s, 0.35
 * decades of creep beside the first, as a shallow hump) and overtakes the first (kS / kA = 0.24,
 * A = 0.17: found by test_contact's sweep). Followed alone, the first branch would stay 2 % low at
 * 11 m/s; the search of one axle in turn sees the hump form, from then on the run searches that
 * curve at every sample, and the means agree to 1e-10. */
static void test_second_branch(void)
{
    static rb_plant_params p;
    fill_plant(&p, 1, 120 / 3.6);
    p.condition[0] = (rb_plant_condition){{0.460578, 0.172817, 1.21811, 0.445929, 0.105872}, 1.0, 0.0, 0.0};
    double difference = followed_against_full(&p, 400.0);
    printf("second branch: followed peaks against full searches %.2e\n", difference);
    CHECK(difference <= 1e-10);
}

/* rb_run_bench: the plant alone stepped through the run's inputs ends where the run's plant
 * ended (the same state, bit for bit); bad counts and a trace too short are refused. */
static void test_bench_replays_the_run(void)
{
    static rb_plant_params p;
    static rb_run_state r, replayed;
    static rb_plant_inputs trace[40000];
    rb_bcu_params b;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 30.0, 0.05, 1e9, 0.1, 0, {0}};
    rb_run_bench_result result;
    rb_error err;
    fill_plant(&p, 2, 120 / 3.6);
    memset(&b, 0, sizeof b);
    b.n_cars = 2; b.cycle = 0.01; b.atmosphere = p.atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = 1;
    rb_bcu_pressure_map(&p, p.atmosphere + 3.8e5, &b);
    CHECK(rb_run_bench(&p, &b, NULL, &sc, 1, &r, trace, 40000, &result, &err) == RB_OK);
    CHECK(result.run_us > 0.0 && result.plant_us > 0.0);
    CHECK(strcmp(result.kernel, rb_plant_kernel_name(&r.plant)) == 0);
    /* r.plant: the replay's end state; the run's own, again */
    int finished = 0;
    CHECK(rb_run_init(&p, &b, NULL, &sc, &replayed, NULL) == RB_OK);
    CHECK(rb_run_advance(&p, &b, &sc, &replayed, 1e9, NULL, 0, &finished, NULL) == RB_OK);
    CHECK(memcmp(replayed.plant.v, r.plant.v, sizeof r.plant.v) == 0);
    CHECK(memcmp(replayed.plant.m_cyl, r.plant.m_cyl, sizeof r.plant.m_cyl) == 0);
    CHECK(replayed.stopped && result.steps == floor(replayed.out.time / p.dt + 0.5));   /* every step of the stop */
    CHECK(rb_run_bench(&p, &b, NULL, &sc, 0, &r, trace, 40000, &result, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "repeats = 0") != NULL);
    CHECK(rb_run_bench(&p, &b, NULL, &sc, 1, &r, trace, 1000, &result, &err) == RB_ESIZE);
    CHECK(strstr(err.message, "max_steps = 1000") != NULL);
}

/* rb_run_batch: each variant's KPIs equal a run of its own; a bad variant gets its error and the
 * others still run. */
static void test_batch_runs_each_variant(void)
{
    static rb_plant_params p[3];
    static rb_run_state r;
    rb_bcu_params b[3];
    rb_scenario sc[3];
    rb_kpis k[3], single;
    rb_error errors[3], err;
    int status[3];
    for (int i = 0; i < 3; ++i) {
        fill_plant(&p[i], 1, (60.0 + 20.0 * i) / 3.6);
        memset(&b[i], 0, sizeof b[i]);
        b[i].n_cars = 1; b[i].cycle = 0.01; b[i].atmosphere = p[i].atmosphere;
        b[i].service_decel = 1.0; b[i].emergency_decel = 1.2; b[i].wsp_enabled = 1;
        rb_bcu_pressure_map(&p[i], p[i].atmosphere + 3.8e5, &b[i]);
        sc[i] = (rb_scenario){1, {0.0}, {0.0}, {1.0}, 120.0, 0.05, 1e9, 0.1, 0, {0}};
    }
    sc[1].max_time = -1.0;   /* refused */
    CHECK(rb_run_batch(3, p, b, NULL, sc, &r, k, status, errors, &err) == RB_OK);
    CHECK(status[0] == RB_OK && status[1] == RB_EINVAL && status[2] == RB_OK);
    CHECK(strstr(errors[1].message, "max_time") != NULL);
    for (int i = 0; i < 3; i += 2) {
        int finished = 0;
        CHECK(rb_run_init(&p[i], &b[i], NULL, &sc[i], &r, NULL) == RB_OK);
        CHECK(rb_run_advance(&p[i], &b[i], &sc[i], &r, 1e9, NULL, 0, &finished, NULL) == RB_OK);
        rb_run_kpis(&p[i], &r, &single);
        CHECK(memcmp(&single, &k[i], sizeof single) == 0);
    }
    CHECK(k[2].stopping_distance_m > k[0].stopping_distance_m);   /* 100 km/h stops longer than 60 */
    CHECK(rb_run_batch(RB_MAX_BATCH + 1, p, b, NULL, sc, &r, k, status, errors, &err) == RB_EINVAL);
}

/* Speed marks: each is noted in the step where the speed fell to it (between that step's and the
 * previous step's position and time); a mark above the speed at the demand is passed at once, one
 * below the stop speed never; marks that do not decrease are refused. */
static void test_speed_marks(void)
{
    static rb_plant_params p;
    static rb_run_state r;
    rb_bcu_params b;
    rb_kpis k;
    rb_error err;
    const double marks[4] = {120 / 3.6, 80 / 3.6, 40 / 3.6, 0.01};
    double before[4][2], after[4][2];
    int finished = 0, next = 0;
    fill_plant(&p, 1, 100 / 3.6);
    memset(&b, 0, sizeof b);
    b.n_cars = 1; b.cycle = 0.01; b.atmosphere = p.atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = 1;
    rb_bcu_pressure_map(&p, p.atmosphere + 3.8e5, &b);
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 120.0, 0.05, 1e9, 0.1, 4, {0}};
    memcpy(sc.speed_mark, marks, sizeof marks);
    CHECK(rb_run_init(&p, &b, NULL, &sc, &r, NULL) == RB_OK);
    while (!finished) {
        double x = r.out.position, t = r.out.time;
        CHECK(rb_run_advance(&p, &b, &sc, &r, r.out.time + 0.5e-3, NULL, 0, &finished, NULL) == RB_OK);
        for (; next < 3 && r.out.speed <= marks[next]; ++next) {
            before[next][0] = next == 0 ? 0.0 : x, before[next][1] = next == 0 ? 0.0 : t;
            after[next][0] = next == 0 ? 0.0 : r.out.position, after[next][1] = next == 0 ? 0.0 : r.out.time;
        }
    }
    rb_run_kpis(&p, &r, &k);
    CHECK(next == 3 && k.mark_distance_m[0] == 0.0 && k.mark_time_s[0] == 0.0);
    for (int i = 1; i < 3; ++i) {
        CHECK(before[i][0] <= k.mark_distance_m[i] && k.mark_distance_m[i] <= after[i][0]);
        CHECK(before[i][1] <= k.mark_time_s[i] && k.mark_time_s[i] <= after[i][1]);
    }
    CHECK(k.mark_distance_m[1] < k.mark_distance_m[2] && k.mark_distance_m[2] < k.stopping_distance_m);
    CHECK(k.mark_time_s[3] == -1.0 && k.mark_distance_m[3] == -1.0);   /* below the stop speed */
    sc.speed_mark[2] = sc.speed_mark[1];
    CHECK(rb_run_init(&p, &b, NULL, &sc, &r, &err) == RB_EINVAL && strstr(err.message, "speed_mark[2]"));
    sc.n_speed_marks = RB_MAX_SPEED_MARKS + 1;
    CHECK(rb_run_init(&p, &b, NULL, &sc, &r, &err) == RB_EINVAL && strstr(err.message, "n_speed_marks"));
}


/* One car braked from 100 km/h to a stop without running resistance: (kinetic energy of the car
 * and its wheelsets at the start) - (at the end) = sum over the axles of the disc energy and the
 * sliding energy (the work of each creep force on its slip velocity), the energy balance of the
 * plant's equations. lock[0], lock[1]: where every wheel of the car first stood still (the
 * plant's lock: omega = 0) and the sliding energy of axle 1 there; -1 if they never did. */
static void energy_stop(const rb_polach_params *polach, int wsp, rb_run_state *r, rb_plant_params *p,
                        double *balance, double *lock)
{
    rb_bcu_params b;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1, 0, {0}};
    int finished = 0;
    fill_plant(p, 1, 100 / 3.6);
    p->condition[0].polach = *polach;
    memset(&b, 0, sizeof b);
    b.n_cars = 1; b.cycle = 0.01; b.atmosphere = p->atmosphere;
    b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = wsp;
    rb_bcu_pressure_map(p, p->atmosphere + 3.8e5, &b);
    CHECK(rb_run_init(p, &b, NULL, &sc, r, NULL) == RB_OK);
    lock[0] = lock[1] = -1.0;
    while (!finished) {
        CHECK(rb_run_advance(p, &b, &sc, r, r->out.time + 0.5e-3, NULL, 0, &finished, NULL) == RB_OK);
        int still = 1;
        for (int a = 0; a < RB_AXLES_PER_CAR; ++a) still &= r->plant.omega[a] == 0.0;
        if (still && lock[0] < 0.0) lock[0] = r->plant.x[0], lock[1] = r->axle_sliding_energy[0];
    }
    CHECK(r->stopped);
    const rb_car *car = &p->car[0].vehicle;
    double kinetic[2] = {0.5 * car->mass * p->initial_speed * p->initial_speed, 0.5 * car->mass * r->plant.v[0] * r->plant.v[0]};
    double disc = 0.0, sliding = 0.0;
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
        double omega0 = p->initial_speed / car->wheelset.wheel_radius;
        kinetic[0] += 0.5 * car->wheelset.inertia * omega0 * omega0;
        kinetic[1] += 0.5 * car->wheelset.inertia * r->plant.omega[a] * r->plant.omega[a];
        disc += r->out.brake_energy[a];
        sliding += r->axle_sliding_energy[a];
    }
    balance[0] = kinetic[0] - kinetic[1];
    balance[1] = disc;
    balance[2] = sliding;
}

/* The sliding energy (rb_kpis.max_sliding_energy, sliding_energy) closes the energy balance with
 * the disc energy to 1e-3: on dry rail with the WSP, where the axles roll at micro-slip (a small
 * share; no WSP valve moves), and without WSP on rail whose friction does not fall with sliding
 * (Polach A = 1: mu0 at any slip velocity), where the wheels lock: then most of the energy is
 * slid, and from the lock on each axle slides the energy mu0 Q times the distance, the limiting
 * case of a locked wheel (its creep force is Polach's at an infinite creep, mu0 Q); no valve
 * moves either. */
static void test_sliding_energy(void)
{
    static rb_plant_params p;
    static rb_run_state r;
    double e[3], lock[2];
    rb_kpis k;
    const rb_polach_params dry = {0.55, 0.40, 0.60, 1.0, 0.4}, flat = {0.05, 1.0, 0.60, 1.0, 0.4};
    energy_stop(&dry, 1, &r, &p, e, lock);
    rb_run_kpis(&p, &r, &k);
    printf("dry, WSP: kinetic %.4e J, discs %.4e J, sliding %.4e J\n", e[0], e[1], e[2]);
    CHECK_CLOSE(e[1] + e[2], e[0], 1e-3, 0);
    CHECK(e[2] > 0.0 && e[2] < 0.01 * e[0]);
    CHECK(lock[0] < 0.0 && k.valve_switchings == 0.0);
    CHECK_CLOSE(k.sliding_energy, e[2], 1e-12, 0);
    energy_stop(&flat, 0, &r, &p, e, lock);
    rb_run_kpis(&p, &r, &k);
    printf("flat mu0 = 0.05, no WSP: kinetic %.4e J, discs %.4e J, sliding %.4e J, locked at %.1f m\n", e[0], e[1],
           e[2], lock[0]);
    CHECK_CLOSE(e[1] + e[2], e[0], 1e-3, 0);
    CHECK(e[2] > 0.9 * e[0]);
    CHECK(lock[0] > 0.0 && k.wheel_lock_events == RB_AXLES_PER_CAR && k.valve_switchings == 0.0);
    double q = p.car[0].vehicle.wheelset.axle_load * 9.80665;   /* N: axle_load is a mass (kg); standard g */
    CHECK_CLOSE(r.axle_sliding_energy[0] - lock[1], flat.mu0 * q * (r.plant.x[0] - lock[0]), 1e-3, 0);
    CHECK(k.max_sliding_energy >= r.axle_sliding_energy[0] && k.max_sliding_energy <= k.sliding_energy);
}

/* The recorded wsp_mode channels: a vent valve stuck open (and its hold valve shut) on axle 2 from
 * 1 s vents its cylinder without command, so the safety timer isolates the axle (RB_WSP_ISOLATED) once it has seen the
 * cylinder low for safety_time, not before: the channel shows it from then on, every mode is one
 * of rb_wsp_mode, and the axles whose last mode is a trip are the safety_timer_trips KPI. Without
 * WSP every axle reads RB_WSP_OFF. */
static int mode_column(int n_cars, const char *channel)
{
    char name[64], unit[16];
    for (int i = 0; i < rb_run_channel_count(n_cars); ++i) {
        CHECK(rb_run_channel_info(i, n_cars, name, sizeof name, unit, sizeof unit, NULL) == RB_OK);
        if (strcmp(name, channel) == 0) return i;
    }
    return -1;
}

static void test_wsp_mode_channels(void)
{
    static rb_plant_params p;
    static rb_run_state r;
    static double series[8000 * 64];
    rb_bcu_params b;
    rb_kpis k;
    rb_wsp_params w;
    rb_scenario sc = {1, {0.0}, {0.0}, {1.0}, 60.0, 0.05, 0.01, 0.1, 0, {0}};
    int nch = rb_run_channel_count(1), first = mode_column(1, "wsp_mode_c1a1");
    CHECK(nch <= 64 && first >= 0 && mode_column(1, "wsp_mode_c1a4") == first + 3);
    rb_wsp_default_params(&w);
    for (int wsp = 1; wsp >= 0; --wsp) {
        int finished = 0;
        fill_plant(&p, 1, 100 / 3.6);
        p.n_faults = 2;   /* (this light car's relay outfeeds a stuck vent alone: its hold valve stuck shut too) */
        p.fault[0] = (rb_fault){RB_FAULT_VENT_STUCK_OPEN, 0, 1, 1.0, 0.0};
        p.fault[1] = (rb_fault){RB_FAULT_HOLD_STUCK_CLOSED, 0, 1, 1.0, 0.0};
        memset(&b, 0, sizeof b);
        b.n_cars = 1; b.cycle = 0.01; b.atmosphere = p.atmosphere;
        b.service_decel = 1.0; b.emergency_decel = 1.2; b.wsp_enabled = wsp;
        rb_bcu_pressure_map(&p, p.atmosphere + 3.8e5, &b);
        CHECK(rb_run_init(&p, &b, &w, &sc, &r, NULL) == RB_OK);
        CHECK(rb_run_advance(&p, &b, &sc, &r, 1e9, series, 8000, &finished, NULL) == RB_OK);
        CHECK(finished && r.rows > 100);
        rb_run_kpis(&p, &r, &k);
        double trip = -1.0;
        int valid = 1, tripped = 0;
        for (size_t i = 0; i < r.rows; ++i) {
            const double *row = series + i * (size_t)nch;
            for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
                double m = row[first + a];
                valid &= wsp ? (m == (int)m && m >= RB_WSP_APPLY && m <= RB_WSP_ISOLATED) : m == RB_WSP_OFF;
            }
            if (trip < 0.0 && row[first + 1] == RB_WSP_ISOLATED) trip = row[0];
            if (trip >= 0.0) valid &= row[first + 1] == RB_WSP_ISOLATED;   /* kept to the end */
        }
        const double *last = series + (r.rows - 1) * (size_t)nch;
        for (int a = 0; a < RB_AXLES_PER_CAR; ++a) tripped += last[first + a] >= RB_WSP_INHIBITED;
        CHECK(valid);
        CHECK(k.safety_timer_trips == tripped);
        if (wsp) {
            printf("vent stuck open, hold shut at 1 s: axle 2 isolated at %.2f s (safety time %.1f s), %d trip(s)\n", trip,
                   w.safety_time, tripped);
            CHECK(trip >= 1.0 + w.safety_time && tripped >= 1);
        } else {
            CHECK(trip < 0.0 && tripped == 0);
        }
    }
}

int main(void)
{
    test_wsp_mode_channels();
    test_sliding_energy();
    test_speed_marks();
    test_batch_runs_each_variant();
    test_conditioned_rail_with_a_zone();
    test_second_branch();
    test_bench_replays_the_run();
    return rb_test_summary("test_run");
}

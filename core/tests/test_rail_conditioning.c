/* Rail conditioning by dissipated energy (rail_conditioning.c): limiting cases, the axles behind
 * seeing more adhesion on uniform contamination, energy and air balances, the ring's limit. */
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>
#include <string.h>

#define HEAVY_RAIN {0.126, 0.126, 1.37, 0.30, 0.10, 0.0}

/* n cars from 300 km/h on uniformly contaminated rail, cylinders filled at a constant demand with
 * no WSP: the wheels slide and clean the rail. */
static void fill_sliding(rb_plant_params *p, int n_cars, double reference_energy)
{
    fill_plant(p, n_cars, 300 / 3.6);
    p->condition[0] = (rb_plant_condition){HEAVY_RAIN, 0.2, 0.0, reference_energy};
    p->rail_cell_length = 0.5;
}

/* A fixed sand rate (kg/s): a table of one point. */
static rb_speed_table fixed_rate(double rate)
{
    rb_speed_table t = {1, {0.0}, {rate}};
    return t;
}

static void brake(const rb_plant_params *p, rb_plant_state *s, double seconds)
{
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    for (int c = 0; c < p->n_cars; ++c) in.pressure_demand[c] = p->atmosphere + 3.8e5;
    for (long i = 0; i < (long)(seconds / p->dt); ++i) rb_plant_step(p, s, &in);
}

/* Uniform contamination: each axle passes rail every axle ahead of it has cleaned, so the mu0 it
 * sees rises from the leading axle's (leading_factor x mu0) along the train. Checked once the
 * brakes have built up: while they build, an axle meets rail the axles ahead passed earlier, with
 * less force, than the rail before the axle ahead of it, and may see a little less. */
static void test_axles_behind_see_more_adhesion(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    fill_sliding(&p, 3, 2.0e5);
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    CHECK_CLOSE(s.polach[0].mu0, 0.2 * 0.126, 1e-12, 0);
    brake(&p, &s, 2.0);
    for (int t = 1; t < 4; ++t) {
        brake(&p, &s, 2.0);
        int monotone = 1;
        for (int a = 1; a < 12; ++a) monotone &= s.polach[a].mu0 >= s.polach[a - 1].mu0;
        printf("t = %d s: mu0 factor on axle 1 %.3f, axle 12 %.3f\n", 2 * (t + 1), s.polach[0].mu0 / 0.126,
               s.polach[11].mu0 / 0.126);
        CHECK(monotone);
        CHECK_CLOSE(s.polach[0].mu0, 0.2 * 0.126, 1e-12, 0);   /* the leading axle: the rail as laid */
        CHECK(s.polach[11].mu0 > 1.5 * s.polach[0].mu0);      /* the rear axles see cleaner rail */
        CHECK(s.polach[11].mu0 <= 0.126);                  /* never beyond the cleaned rail's */
    }
}

/* An energy far beyond what the contacts leave (E_ref at its bound, 1 GJ/m2) leaves the rail as
 * laid: the plant brakes as on a condition of mu0 x leading_factor without conditioning. */
static void test_unreachable_energy_is_the_laid_rail(void)
{
    static rb_plant_params p, q;
    static rb_plant_state s, t;
    fill_sliding(&p, 2, 1e9);
    fill_plant(&q, 2, 300 / 3.6);
    q.condition[0] = (rb_plant_condition){HEAVY_RAIN, 1.0, 0.0, 0.0};
    q.condition[0].polach.mu0 *= 0.2;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK && rb_plant_init(&q, &t, NULL) == RB_OK);
    brake(&p, &s, 3.0);
    brake(&q, &t, 3.0);
    CHECK_CLOSE(s.v[0], t.v[0], 1e-6, 0);
    for (int a = 0; a < 8; ++a) CHECK_CLOSE(s.polach[a].mu0, t.polach[a].mu0, 1e-3, 0);
    for (int a = 0; a < 8; ++a) CHECK_CLOSE(s.omega[a], t.omega[a], 1e-3, 1e-6);
    fill_sliding(&p, 2, INFINITY);   /* cells the sliding wheels do not clean: the laid rail exactly */
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    brake(&p, &s, 3.0);
    for (int a = 0; a < 8; ++a) CHECK_CLOSE(s.polach[a].mu0, t.polach[a].mu0, 1e-12, 0);
}

/* Off (no condition with reference_energy): the cell length has no effect at all. */
static void test_off_leaves_the_plant_as_it_was(void)
{
    static rb_plant_params p, q;
    static rb_plant_state s, t;
    fill_plant(&p, 2, 300 / 3.6);
    p.condition[0] = (rb_plant_condition){HEAVY_RAIN, 0.2, 8.7, 0.0};
    q = p;
    q.rail_cell_length = 0.5;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK && rb_plant_init(&q, &t, NULL) == RB_OK);
    CHECK(!s.rail_active && !t.rail_active);
    brake(&p, &s, 2.0);
    brake(&q, &t, 2.0);
    CHECK(memcmp(s.omega, t.omega, sizeof s.omega) == 0);
    CHECK(memcmp(s.v, t.v, sizeof s.v) == 0);
}

/* Energy: the kinetic energy of car and wheelsets the stop took is the pads' brake energy plus the
 * friction work in the contacts (creep force x slip velocity); air: every kilogram booked. */
static void test_energy_and_air_balance(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    rb_plant_inputs in;
    fill_sliding(&p, 1, 2.0e5);
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    const rb_plant_car *car = &p.car[0];
    double r = car->vehicle.wheelset.wheel_radius, J = car->vehicle.wheelset.inertia;
    double kinetic0 = 0.5 * car->vehicle.mass * s.v[0] * s.v[0], contact = 0.0;
    for (int a = 0; a < 4; ++a) kinetic0 += 0.5 * J * s.omega[a] * s.omega[a];
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = p.atmosphere + 3.8e5;
    for (int i = 0; i < 8000; ++i) {
        rb_plant_step(&p, &s, &in);
        for (int a = 0; a < 4; ++a) contact += s.force[a] * (s.omega[a] * r - s.v[0]) * p.dt;
    }
    double kinetic = 0.5 * car->vehicle.mass * s.v[0] * s.v[0], brake_energy = 0.0;
    for (int a = 0; a < 4; ++a) {
        kinetic += 0.5 * J * s.omega[a] * s.omega[a];
        brake_energy += s.brake_energy[a];
    }
    printf("energy: kinetic lost %.4g J, pads %.4g J, contacts %.4g J\n", kinetic0 - kinetic, brake_energy, contact);
    CHECK(contact > 0.05 * (kinetic0 - kinetic));   /* the wheels slid: the contacts took a share */
    CHECK_CLOSE(brake_energy + contact, kinetic0 - kinetic, 5e-3, 0);
    CHECK_CLOSE(rb_plant_air_mass(&p, &s) + s.m_vented - s.m_compressed, s.m_initial, 1e-10, 0);
}

/* A sander in front of the leading axle: the sand it drops (rate x time, booked) cleans the rail the
 * leading axle meets, which then brakes on more adhesion than on the rail as laid; the train stops
 * sooner. A WSP-triggered sander sands only while a WSP valve is commanded. */
static void test_sand_conditions_the_rail(void)
{
    static rb_plant_params p, q;
    static rb_plant_state s, t;
    fill_sliding(&p, 2, 2.0e5);
    q = p;
    p.n_sanders = 1;
    p.sand_entrained = 1.0; p.sand_retention = 0.0;   /* the axle meeting the sand takes it all */
    p.sander_axle[0] = 0; p.sander_trigger[0] = RB_SAND_DRIVER; p.sander_rate[0] = fixed_rate(0.02); p.sander_start[0] = 0.0;
    p.sand_reference = 2e-4;   /* kg/m: about 2.4e-4 kg/m fall at 300 km/h, cleaning 70 % */
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK && rb_plant_init(&q, &t, NULL) == RB_OK);
    brake(&p, &s, 4.0);
    brake(&q, &t, 4.0);
    CHECK_CLOSE(s.sand_used, 0.02 * 4.0, 1e-9, 0);
    CHECK(s.polach[0].mu0 > 2.0 * t.polach[0].mu0);   /* sanded against as laid (0.2 mu0) */
    CHECK(s.v[0] < t.v[0]);
    p.sander_trigger[0] = RB_SAND_WSP;   /* no WSP command in brake(): no sand */
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    brake(&p, &s, 1.0);
    CHECK(s.sand_used == 0.0);
    rb_plant_inputs in;
    memset(&in, 0, sizeof in);
    in.hold[5] = 1;
    for (int i = 0; i < 100; ++i) rb_plant_step(&p, &s, &in);
    CHECK_CLOSE(s.sand_used, 0.02 * 0.1, 1e-9, 0);
}

/* A variable-rate sander whose rate rises with its car's speed, R = q v, lays q kg on every metre
 * of track whatever the speed (sand used = q x distance, exactly: the plant moves the car by v dt
 * in the step it drops q v dt); a fixed rate R lays R / v, so it books R x time, more than q per
 * metre once the train is slower than R / q. Each cell the sander has passed keeps the
 * contamination exp(-q / sand_reference) (a dry stop, the energy cleaning made unreachable with
 * E_ref at its bound), to within the one step's travel by which a cell's share can differ. */
static void test_variable_rate_sand_per_metre(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    const double q = 2e-4;   /* kg/m */
    fill_plant(&p, 1, 30.0);
    p.condition[0].leading_factor = 0.5;
    p.condition[0].reference_energy = 1e9;
    p.rail_cell_length = 0.5;
    p.n_sanders = 1;
    p.sand_entrained = 1.0; p.sand_retention = 0.0;   /* the axle meeting the sand takes it all */
    p.sander_axle[0] = 0; p.sander_trigger[0] = RB_SAND_DRIVER; p.sander_start[0] = 0.0;
    p.sander_rate[0] = (rb_speed_table){2, {0.0, 100.0}, {0.0, 100.0 * q}};
    p.sand_reference = 2e-4;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    double x0 = s.x[0];
    brake(&p, &s, 15.0);
    printf("variable rate: %.4g kg over %.1f m, the speed falling to %.1f m/s\n", s.sand_used, s.x[0] - x0, s.v[0]);
    CHECK(s.v[0] < 0.6 * p.initial_speed);
    CHECK_CLOSE(s.sand_used, q * (s.x[0] - x0), 1e-9, 0);
    double sum = 0.0, axle = s.x[0] - p.car[0].axle_position[0];
    int n = 0;
    for (double x = axle - 100.0; x < axle - 1.0; x += p.rail_cell_length, ++n) {   /* within the ring */
        long cell = (long)floor(x / p.rail_cell_length);
        double c = s.rail_contamination[((cell % RB_RAIL_MAX_CELLS) + RB_RAIL_MAX_CELLS) % RB_RAIL_MAX_CELLS];
        sum += c;
        CHECK_CLOSE(c, exp(-q / p.sand_reference), 0.1, 0);
    }
    CHECK(n > 100);
    CHECK_CLOSE(sum / n, exp(-q / p.sand_reference), 0.01, 0);
    p.sander_rate[0] = fixed_rate(q * p.initial_speed);   /* the same sand per metre at the start only */
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    brake(&p, &s, 15.0);
    CHECK_CLOSE(s.sand_used, q * p.initial_speed * 15.0, 1e-9, 0);
    CHECK(s.sand_used > 1.2 * q * (s.x[0] - x0));
}

/* Each axle meeting a cell crushes sand_entrained of its loose sand into the rail and leaves
 * sand_retention loose: behind the n = 4 axles of a car sanded from its leading axle, a cell laid
 * with q kg/m keeps the contamination exp(-e q (1 - r^n) / (1 - r) / sand_reference) and r^n q of
 * loose sand (the rest was carried away), and every axle finds at least the adhesion of the one
 * ahead of it. */
static void test_passing_axles_work_the_sand(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    const double q = 2e-4, e = 0.2, r = 0.5;
    fill_plant(&p, 1, 30.0);
    p.condition[0].leading_factor = 0.5;
    p.condition[0].reference_energy = 1e9;
    p.rail_cell_length = 0.5;
    p.n_sanders = 1;
    p.sand_entrained = e; p.sand_retention = r;
    p.sander_axle[0] = 0; p.sander_trigger[0] = RB_SAND_DRIVER; p.sander_start[0] = 0.0;
    p.sander_rate[0] = (rb_speed_table){2, {0.0, 100.0}, {0.0, 100.0 * q}};
    p.sand_reference = 2e-4;
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    brake(&p, &s, 15.0);
    double crushed = e * q * (1.0 - pow(r, 4)) / (1.0 - r);
    double sum_c = 0.0, sum_sand = 0.0, last = s.x[0] - p.car[0].axle_position[3];
    int n = 0;
    for (double x = last - 100.0; x < last - 1.0; x += p.rail_cell_length, ++n) {
        long cell = (long)floor(x / p.rail_cell_length);
        int slot = (int)(((cell % RB_RAIL_MAX_CELLS) + RB_RAIL_MAX_CELLS) % RB_RAIL_MAX_CELLS);
        sum_c += s.rail_contamination[slot];
        sum_sand += s.rail_sand[slot];
    }
    CHECK(n > 100);
    CHECK_CLOSE(sum_c / n, exp(-crushed / p.sand_reference), 0.01, 0);
    CHECK_CLOSE(sum_sand / n, pow(r, 4) * q, 0.01, 0);
    double ahead = 2.0;
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {   /* the contamination of the cell each axle meets */
        long cell = (long)floor((s.x[0] - p.car[0].axle_position[a]) / p.rail_cell_length) + 1;
        double c = s.rail_contamination[((cell % RB_RAIL_MAX_CELLS) + RB_RAIL_MAX_CELLS) % RB_RAIL_MAX_CELLS];
        CHECK(c <= ahead + 1e-12);   /* never dirtier than the one ahead's: adhesion never falls */
        ahead = c;
    }
    p.sand_retention = 0.9;   /* with 0.2 entrained: more than all of it */
    rb_error err;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "sand_retention = 0.9") != NULL);
}

static void test_bad_parameters(void)
{
    static rb_plant_params p;
    static rb_plant_state s;
    rb_error err;
    fill_sliding(&p, 16, 2.0e5);
    p.rail_cell_length = 0.1;   /* 400 m of train in 0.1 m cells: more than the ring holds */
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "rail_cell_length = 0.1 m") != NULL);
    fill_sliding(&p, 2, 2.0e5);
    p.condition[0].recovery_axles = 8.7;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "not both") != NULL);
    fill_sliding(&p, 2, -1.0);
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "condition[0].reference_energy = -1") != NULL);
    fill_sliding(&p, 2, 2.0e5);
    p.n_sanders = 1;
    p.sand_entrained = 1.0; p.sand_retention = 0.0;   /* the axle meeting the sand takes it all */
    p.sander_axle[0] = 8;   /* two cars: axles 0 to 7 */
    p.sander_rate[0] = fixed_rate(0.01); p.sand_reference = 1e-3;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "sander[0].axle = 8") != NULL);
    p.sander_axle[0] = 0;
    p.sander_rate[0] = (rb_speed_table){2, {0.0, 10.0}, {0.0, 0.0}};
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "sander[0].rate: every rate is 0 kg/s") != NULL);
    p.sander_rate[0] = fixed_rate(2.0);   /* 120 kg/min */
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "sander[0].rate") != NULL);
    fill_plant(&p, 2, 10.0);   /* no rail cells: sand would act on nothing */
    p.n_sanders = 1;
    p.sand_entrained = 1.0; p.sand_retention = 0.0;   /* the axle meeting the sand takes it all */
    p.sander_rate[0] = fixed_rate(0.01); p.sand_reference = 1e-3;
    CHECK(rb_plant_init(&p, &s, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "no condition uses") != NULL);
}

int main(void)
{
    test_axles_behind_see_more_adhesion();
    test_unreachable_energy_is_the_laid_rail();
    test_off_leaves_the_plant_as_it_was();
    test_energy_and_air_balance();
    test_sand_conditions_the_rail();
    test_variable_rate_sand_per_metre();
    test_passing_axles_work_the_sand();
    test_bad_parameters();
    return rb_test_summary("test_rail_conditioning");
}

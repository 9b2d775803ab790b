/* rb_run_retune: parameters changed during a run act from the next step on, and a refused change
 * changes nothing. */
#include "plant_fixture.h"
#include "rb_test.h"

#include "railbrake/rb_run.h"

#define G 9.80665

static rb_plant_params plant;
static rb_bcu_params bcu;
static rb_wsp_params wsp;
static rb_run_state run;
static const rb_scenario emergency = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1, 0, {0}};

static void start(void)
{
    fill_plant(&plant, 1, 250 / 3.6);
    memset(&bcu, 0, sizeof bcu);
    bcu.n_cars = 1; bcu.cycle = 0.01; bcu.atmosphere = plant.atmosphere;
    bcu.service_decel = 1.0; bcu.emergency_decel = 1.2; bcu.wsp_enabled = 1;
    rb_bcu_pressure_map(&plant, plant.atmosphere + 3.8e5, &bcu);
    rb_wsp_default_params(&wsp);
    CHECK(rb_run_init(&plant, &bcu, &wsp, &emergency, &run, NULL) == RB_OK);
}

static double speed_at(double t)
{
    int finished = 0;
    CHECK(rb_run_advance(&plant, &bcu, &emergency, &run, t, NULL, 0, &finished, NULL) == RB_OK);
    return run.out.speed;
}

/* Lower adhesion from 1 s on: the train then decelerates no faster than mu0 g (Coulomb: the
 * creep force of an axle never exceeds mu0 times its load; no resistance, no gradient, no ED). */
static void test_adhesion_change_acts_from_the_next_step(void)
{
    start();
    double v_same = speed_at(1.0);
    double v_dry = speed_at(3.0);
    start();
    CHECK(speed_at(1.0) == v_same);
    plant.condition[0].polach.mu0 = 0.05;
    CHECK(rb_run_retune(&plant, &wsp, &run, NULL) == RB_OK);
    double v_low = speed_at(3.0);
    CHECK((v_same - v_low) / 2.0 <= 0.05 * G);
    CHECK(v_low > v_dry);
}

/* A WSP setting out of its bound is refused with the WSP and the plant untouched. */
static void test_refused_change_changes_nothing(void)
{
    rb_error err;
    start();
    speed_at(0.5);
    rb_wsp_params before = run.bcu.wsp_default.p;
    wsp.safety_time = 0.0;
    plant.condition[0].polach.mu0 = 0.3;
    CHECK(rb_run_retune(&plant, &wsp, &run, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "safety_time") != NULL);
    CHECK(memcmp(&before, &run.bcu.wsp_default.p, sizeof before) == 0);
    CHECK(run.plant.polach[0].mu0 == 0.55);
    wsp.safety_time = 3.0;
    CHECK(rb_run_retune(&plant, &wsp, &run, NULL) == RB_OK);
    CHECK(run.bcu.wsp_default.p.safety_time == 3.0 && run.plant.polach[0].mu0 == 0.3);
}

int main(void)
{
    test_adhesion_change_acts_from_the_next_step();
    test_refused_change_changes_nothing();
    return rb_test_summary("test_run_retune");
}

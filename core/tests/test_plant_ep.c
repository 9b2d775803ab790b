/* The plant's EP valve against its supply (rb_plant_car.ep_supply_margin): with the supply well
 * above the demand the output settles at the demand; with the supply below demand + margin it
 * settles at supply - margin, and follows a supply that runs down (exhausting what lies above);
 * a margin of 0 lets the output reach the supply itself. */
#include "plant_fixture.h"
#include "rb_test.h"

#include <math.h>
#include <string.h>

#define BAR 1e5

/* One car at rest, compressor off, every reservoir at `charged` Pa gauge, demand `demand` Pa
 * gauge, hold valves open; a cylinder leak of `leak` m^2 on every axle drains the air. */
static void start(rb_plant_params *p, rb_plant_state *s, rb_plant_inputs *in, double charged, double demand,
                  double margin, double leak)
{
    fill_plant(p, 1, 0.0);
    p->initial_pressure = p->atmosphere + charged;
    p->car[0].ep_supply_margin = margin;
    p->n_faults = 2;
    p->fault[0] = (rb_fault){RB_FAULT_COMPRESSOR_OFF, 0, -1, 0.0, 0.0};
    p->fault[1] = (rb_fault){RB_FAULT_CYLINDER_LEAK, 0, -1, 0.0, leak};
    CHECK(rb_plant_init(p, s, NULL) == RB_OK);
    memset(in, 0, sizeof *in);
    in->pressure_demand[0] = p->atmosphere + demand;
}

static void outputs(const rb_plant_params *p, const rb_plant_state *s, double *supply, double *pilot)
{
    rb_plant_outputs out;
    rb_plant_get_outputs(p, s, &out);
    *supply = out.supply[0];
    *pilot = out.pilot[0];
}

static void settles(double charged, double demand, double margin, double expect_below_supply)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    double supply, pilot;
    start(&p, &s, &in, charged, demand, margin, 0.0);
    for (int i = 0; i < 10000; ++i) rb_plant_step(&p, &s, &in);   /* 10 s */
    outputs(&p, &s, &supply, &pilot);
    double expect = expect_below_supply >= 0.0 ? supply - expect_below_supply : p.atmosphere + demand;
    printf("charged %.1f bar, demand %.1f bar, margin %.2f bar: supply %.4f, EP output %.4f bar (expected %.4f)\n",
           charged / BAR, demand / BAR, margin / BAR, (supply - p.atmosphere) / BAR, (pilot - p.atmosphere) / BAR,
           (expect - p.atmosphere) / BAR);
    CHECK(fabs(pilot - expect) < 0.005 * BAR);
}

/* The supply drains through the cylinders' leaks while the demand stays: once supply - margin is
 * below the demand the output follows it down, never above it. */
static void follows_a_falling_supply(void)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    const double margin = 0.25 * BAR, demand = 3.5 * BAR;
    start(&p, &s, &in, 4.0 * BAR, demand, margin, 2e-6);
    p.main_reservoir_volume = 0.01;   /* little air behind the supply reservoir */
    CHECK(rb_plant_init(&p, &s, NULL) == RB_OK);
    double supply = 0.0, pilot = 0.0, worst_above = -1e9, first = 0.0, last = 0.0;
    int tracked = 0;
    for (int i = 0; i < 60000; ++i) {
        rb_plant_step(&p, &s, &in);
        outputs(&p, &s, &supply, &pilot);
        if (i == 1000) first = supply;
        if (i > 1000 && supply - margin < p.atmosphere + demand - 0.05 * BAR) {   /* settled on the ceiling */
            double above = pilot - (supply - margin);
            if (above > worst_above) worst_above = above;
            ++tracked;
        }
    }
    last = supply;
    printf("falling supply %.3f -> %.3f bar gauge over 60 s: EP output at most %.4f bar from supply - margin "
           "over %d steps\n", (first - p.atmosphere) / BAR, (last - p.atmosphere) / BAR, worst_above / BAR, tracked);
    CHECK(last < p.atmosphere + demand - 0.5 * BAR);   /* the case is exercised */
    CHECK(tracked > 10000);
    CHECK(fabs(worst_above) < 0.01 * BAR);
}

int main(void)
{
    settles(8.0 * BAR, 3.0 * BAR, 0.25 * BAR, -1.0);      /* supply ample: the demand */
    settles(3.0 * BAR, 4.0 * BAR, 0.25 * BAR, 0.25 * BAR); /* supply short: supply - margin */
    settles(3.0 * BAR, 4.0 * BAR, 0.0, 0.0);               /* no margin: the supply itself */
    follows_a_falling_supply();
    return rb_test_summary("test_plant_ep");
}

/* The plant's reduced valve model alone: a choked vent decays exponentially (isothermal), a fill
   settles at the demand within the band's balance, the lag delays the response. */
#include "railbrake/rb_valve_reduced.h"
#include "railbrake/rb_pneumatics.h"
#include "rb_test.h"

static rb_reduced_valve valve(void)
{
    rb_reduced_valve v = {9e5, 1e5, 0.5e-3, 293.15, 0.8, 0.528, 0.0, 1e-3, 3e-6};
    return v;
}

int main(void)
{
    rb_error err;
    rb_reduced_valve v = valve();
    double start = 6e5, final = 1e5, t[3] = {0.0, 0.02, 0.05}, p[3];
    CHECK(rb_reduced_valve_steps(&v, &start, &final, 1, 0.0, t, 3, 1e-6, p, &err) == RB_OK);
    /* choked (p > p_atm / b): q = area c p, so p = p0 exp(-area c R T / V t) */
    double c = rb_orifice_mass_flow_fast(start, v.temperature, v.atmosphere, v.temperature, 1.0, 0.8, 0.528) / start;
    double rate = v.area * c * RB_AIR_R * v.temperature / v.volume;
    for (int i = 0; i < 3; ++i) {
        CHECK(p[i] > v.atmosphere / 0.528);
        CHECK_CLOSE(p[i], start * exp(-rate * t[i]), 1e-4, 0.0);
    }
    /* fill to a demand: settles within the band's error, later with a lag */
    double s0 = 1e5, s1 = 4e5, tt[2] = {0.0, 2.0}, fast[2], slow[2], mid[2], tm[2] = {0.0, 0.1};
    v.band = 0.1e5;
    v.volume = 0.05e-3;   /* fills in a few ms: the lag then dominates */
    CHECK(rb_reduced_valve_steps(&v, &s0, &s1, 1, 0.0, tt, 2, 1e-4, fast, &err) == RB_OK);
    CHECK(fabs(fast[1] - s1) < 0.01 * v.band);
    CHECK(rb_reduced_valve_steps(&v, &s0, &s1, 1, 0.0, tm, 2, 1e-4, mid, &err) == RB_OK);
    v.tau = 0.2;
    CHECK(rb_reduced_valve_steps(&v, &s0, &s1, 1, 0.0, tm, 2, 1e-4, slow, &err) == RB_OK);
    CHECK(slow[1] < mid[1] - 0.3e5);
    v.band = -1.0;
    CHECK(rb_reduced_valve_steps(&v, &s0, &s1, 1, 0.0, tt, 2, 1e-4, slow, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "band") != NULL);
    return rb_test_summary("test_valve_reduced");
}

/* Rail conditioning by energy: limits, the closed form of the energy density and the
 * equivalence with the axle-count law when every axle dissipates the same energy. */
#include "railbrake/rb_contact.h"
#include "rb_test.h"

static void test_energy_density_closed_form(void)
{
    /* 10 kN creep force at 2 m/s slip, 80 m/s, 12 mm wide contact: 1e4 * 2 / (0.012 * 80). */
    CHECK_CLOSE(rb_dissipated_energy_density(1e4, 2.0, 80.0, 0.012), 1e4 * 2.0 / (0.012 * 80.0), 1e-15, 0.0);
    CHECK(rb_dissipated_energy_density(-1e4, 2.0, 80.0, 0.012) > 0.0);   /* braking: same energy */
    CHECK(rb_dissipated_energy_density(1e4, 2.0, 0.0, 0.012) == 0.0);    /* standstill */
    CHECK(rb_dissipated_energy_density(1e4, 2.0, 80.0, 0.0) == 0.0);     /* no contact */
}

static void test_limits_and_monotonic(void)
{
    rb_conditioning_energy c = {0.2, 5e4};
    CHECK_CLOSE(rb_conditioning_energy_factor(&c, 0.0), 0.2, 0.0, 1e-15);
    CHECK_CLOSE(rb_conditioning_energy_factor(&c, 1e9), 1.0, 0.0, 1e-12);
    CHECK_CLOSE(rb_conditioning_energy_factor(&c, 5e4), 1.0 - 0.8 * exp(-1.0), 1e-14, 0.0);
    CHECK_CLOSE(rb_conditioning_energy_factor(&c, -1.0), 0.2, 0.0, 1e-15);  /* no negative energy */
    double last = 0.0;
    for (int i = 0; i <= 20; ++i) {
        double f = rb_conditioning_energy_factor(&c, i * 1e4);
        CHECK(f >= last);
        last = f;
    }
}

static void test_equal_axles_give_the_axle_count_law(void)
{
    rb_conditioning_energy c = {0.2, 5e4};
    double e = rb_dissipated_energy_density(8e3, 1.5, 83.3, 0.011);
    for (int n = 0; n < 64; ++n)
        CHECK_CLOSE(rb_conditioning_energy_factor(&c, n * e),
                    rb_conditioning_factor((double)n, 0.2, c.reference_energy / e), 1e-12, 0.0);
}

static void test_check(void)
{
    rb_error err;
    rb_conditioning_energy good = {0.5, 1e4}, zero = {0.0, 1e4}, above = {1.5, 1e4}, no_energy = {0.5, 0.0};
    CHECK(rb_conditioning_energy_check(&good, &err) == RB_OK);
    CHECK(rb_conditioning_energy_check(&zero, &err) != RB_OK);
    CHECK(strstr(err.message, "leading_factor") != NULL);
    CHECK(rb_conditioning_energy_check(&above, &err) != RB_OK);
    CHECK(rb_conditioning_energy_check(&no_energy, &err) != RB_OK);
    CHECK(strstr(err.message, "reference_energy") != NULL);
    CHECK(rb_conditioning_energy_check(NULL, &err) != RB_OK);
}

int main(void)
{
    test_energy_density_closed_form();
    test_limits_and_monotonic();
    test_equal_axles_give_the_axle_count_law();
    test_check();
    return rb_test_summary("test_conditioning");
}

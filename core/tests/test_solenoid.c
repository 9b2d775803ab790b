/* Solenoid design model against closed forms and conservation laws (rb_solenoid.h). */
#include "railbrake/rb_solenoid.h"
#include "rb_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* A small C-core solenoid: linear iron (mu_r 2000) unless saturating is asked. */
static rb_solenoid c_core(int saturating)
{
    rb_solenoid s;
    memset(&s, 0, sizeof s);
    s.turns = 800.0;
    s.resistance_20c = 10.0;
    s.resistance_tempco = 0.00393;
    s.iron_length = 0.08;
    s.iron_area = 1e-4;
    s.pole_diameter = 0.011;
    s.working_gaps = 2;
    if (!saturating) {
        s.bh_points = 2;
        s.bh_h[1] = 1e6;
        s.bh_b[1] = 2000.0 * RB_MU0 * 1e6;
    } else {   /* a soft steel knee near 1.5 T */
        static const double h[] = {0, 100, 200, 400, 800, 1600, 4000, 10000, 30000};
        static const double b[] = {0, 0.4, 0.8, 1.1, 1.35, 1.5, 1.62, 1.75, 1.9};
        s.bh_points = 9;
        for (int k = 0; k < 9; ++k) s.bh_h[k] = h[k], s.bh_b[k] = b[k];
        s.fringing = 1.0;
        s.parasitic_gap = 0.1e-3;
        s.parasitic_area = 3e-4;
        s.leakage_permeance = 2e-8;
    }
    return s;
}

static void closed_form_c_core(void)
{
    rb_solenoid s = c_core(0);
    rb_error err;
    double a = 0.25 * M_PI * s.pole_diameter * s.pole_diameter;
    for (double gap = 0.2e-3; gap < 1.1e-3; gap += 0.3e-3)
        for (double i = 0.2; i <= 1.01; i += 0.4) {
            /* two gaps in series with the iron: Phi = N i / (2 g / (mu0 A) + l / (mu_r mu0 A_fe)) */
            double phi = s.turns * i / (2.0 * gap / (RB_MU0 * a) + s.iron_length / (2000.0 * RB_MU0 * s.iron_area));
            double force = 2.0 * phi * phi / (2.0 * RB_MU0 * a);   /* two faces, B^2 A / (2 mu0) each */
            rb_solenoid_state st;
            CHECK(rb_solenoid_eval(&s, gap, i, &st, &err) == RB_OK);
            CHECK_CLOSE(st.force, force, 0.01, 0.0);
            CHECK_CLOSE(st.force, force, 1e-9, 0.0);   /* in fact to round-off */
            CHECK_CLOSE(st.flux_linkage, s.turns * phi, 1e-9, 0.0);
        }
}

/* W'(g, i) = int_0^i lambda(g, i') di', Simpson on the model's flux. */
static double coenergy_numeric(const rb_solenoid *s, double gap, double current)
{
    enum { N = 2000 };
    double sum = 0.0, h = current / N;
    for (int k = 0; k <= N; ++k) {
        rb_solenoid_state st;
        rb_solenoid_eval(s, gap, k * h, &st, NULL);
        sum += (k == 0 || k == N ? 1.0 : (k % 2 ? 4.0 : 2.0)) * st.flux_linkage;
    }
    return sum * h / 3.0;
}

static void coenergy_force(void)
{
    rb_solenoid s = c_core(1);
    rb_error err;
    const double gaps[] = {0.2e-3, 0.5e-3, 1.0e-3}, currents[] = {0.3, 1.0, 3.0};
    for (int g = 0; g < 3; ++g)
        for (int c = 0; c < 3; ++c) {
            double gap = gaps[g], i = currents[c], dg = 1e-3 * gap;
            rb_solenoid_state st;
            CHECK(rb_solenoid_eval(&s, gap, i, &st, &err) == RB_OK);
            /* F = dW'/d(-g) at constant current */
            double f_co = -(coenergy_numeric(&s, gap + dg, i) - coenergy_numeric(&s, gap - dg, i)) / (2.0 * dg);
            CHECK_CLOSE(st.force, f_co, 2e-4, 0.0);
            CHECK_CLOSE(st.coenergy, coenergy_numeric(&s, gap, i), 1e-6, 0.0);
            /* F = -dW/dx at constant flux linkage (x closing the gap: dx = -dg) */
            double lambda = st.flux_linkage;
            double f_w = (rb_solenoid_energy(&s, gap + dg, lambda) - rb_solenoid_energy(&s, gap - dg, lambda))
                         / (2.0 * dg);
            CHECK_CLOSE(st.force, f_w, 1e-5, 0.0);
            CHECK_CLOSE(rb_solenoid_current(&s, gap, lambda), i, 1e-9, 0.0);
        }
    /* saturation: at 3 A the iron is past its knee and the force grows slower than i^2 */
    rb_solenoid_state a, b;
    rb_solenoid_eval(&s, 0.2e-3, 1.0, &a, NULL);
    rb_solenoid_eval(&s, 0.2e-3, 3.0, &b, NULL);
    CHECK(b.iron_flux_density > 1.5);
    CHECK(b.force < 0.8 * 9.0 * a.force);
}

static rb_solenoid_drive drive(double r_damping)
{
    rb_solenoid_drive d;
    memset(&d, 0, sizeof d);
    d.voltage = 24.0;
    d.pwm_frequency = 2000.0;
    d.duty = 0.5;
    d.temperature_c = 20.0;
    d.mass = 0.02;
    d.spring_rate = 20000.0;
    d.spring_preload = 0.0;
    d.damping = r_damping;
    d.gap_max = 1.0e-3;
    d.gap_min = 0.1e-3;
    return d;
}

static void energy_balance(void)
{
    enum { N = 201 };
    static rb_solenoid_sample out[N];
    rb_error err;
    /* lossless: no resistance, no damping, the armature swings without reaching a stop */
    rb_solenoid s = c_core(1);
    s.resistance_20c = 0.0;
    rb_solenoid_drive d = drive(0.0);
    d.voltage = 6.0;
    CHECK(rb_solenoid_simulate(&s, &d, 0.01, 1e-6, out, N, &err) == RB_OK);
    double moved = 0.0;
    for (int k = 0; k < N; ++k) {
        double stored = out[k].e_magnetic + out[k].e_mechanical;
        CHECK_CLOSE(out[k].e_electric, stored, 1e-6, 1e-12);
        moved = fmax(moved, d.gap_max - out[k].gap);
        CHECK(out[k].e_impact == 0.0 && out[k].e_copper == 0.0);
    }
    CHECK(moved > 0.05e-3 && moved < d.gap_max - d.gap_min);   /* it did move, mechanics took a share */
    CHECK(out[N - 1].e_mechanical > 0.0);
    /* with resistance, damping and the stops: every joule booked */
    s = c_core(1);
    d = drive(5.0);
    CHECK(rb_solenoid_simulate(&s, &d, 0.02, 1e-6, out, N, &err) == RB_OK);
    const rb_solenoid_sample *e = &out[N - 1];
    CHECK(e->gap < d.gap_min + 1e-9);   /* pulled in */
    CHECK(e->e_impact > 0.0 && e->e_copper > 0.0 && e->e_damping > 0.0);
    CHECK_CLOSE(e->e_electric, e->e_copper + e->e_magnetic + e->e_mechanical + e->e_damping + e->e_impact,
                1e-6, 0.0);
    /* the mean current of the PWM drive approaches duty V / R */
    CHECK_CLOSE(e->current, d.duty * d.voltage / s.resistance_20c, 0.1, 0.0);
}

static void thermal(void)
{
    rb_solenoid s = c_core(0);
    rb_error err;
    double i = 1.2, duty = 0.8, ta = 70.0, g = 0.12, c = 80.0, t_ss;
    CHECK(rb_solenoid_steady_temperature(&s, i, duty, ta, g, &t_ss, &err) == RB_OK);
    /* closed form: T = Ta + duty I^2 R(T) / G solved for T */
    double q = duty * i * i * s.resistance_20c, a = s.resistance_tempco;
    double expected = (g * ta + q * (1.0 - 20.0 * a)) / (g - q * a);
    CHECK_CLOSE(t_ss, expected, 1e-12, 0.0);
    CHECK_CLOSE(t_ss - ta, duty * i * i * s.resistance_20c * (1.0 + a * (t_ss - 20.0)) / g, 1e-12, 0.0);
    enum { N = 11 };
    double temps[N], tau = c / (g - q * a);
    CHECK(rb_solenoid_thermal_transient(&s, i, duty, ta, g, c, 20.0 * tau, 20000, temps, N, &err) == RB_OK);
    CHECK_CLOSE(temps[N - 1], expected, 1e-6, 0.0);
    for (int k = 0; k < N; ++k)   /* first-order response with the time constant C / (G - q alpha) */
        CHECK_CLOSE(temps[k], expected + (ta - expected) * exp(-2.0 * k), 1e-8, 1e-9);
    /* runaway: the loss grows faster than the coil sheds heat */
    CHECK(rb_solenoid_steady_temperature(&s, 10.0, 1.0, ta, g, &t_ss, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "runaway") != NULL);
}

static void bad_inputs(void)
{
    rb_error err;
    rb_solenoid_state st;
    rb_solenoid s = c_core(1);
    s.bh_b[4] = s.bh_b[3];
    CHECK(rb_solenoid_eval(&s, 1e-3, 1.0, &st, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "B-H") && strstr(err.message, "increasing"));
    s = c_core(1);
    s.turns = -5.0;
    CHECK(rb_solenoid_check(&s, &err) == RB_EINVAL && strstr(err.message, "turns"));
    s = c_core(1);
    s.resistance_20c = -1.0;
    CHECK(rb_solenoid_check(&s, &err) == RB_EINVAL && strstr(err.message, "resistance_20c"));
    s = c_core(1);
    double t;
    CHECK(rb_solenoid_steady_temperature(&s, 1.0, 1.5, 20.0, 0.1, &t, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "duty") && strstr(err.message, "[0, 1]"));
    rb_solenoid_drive d = drive(1.0);
    d.duty = -0.1;
    rb_solenoid_sample out[2];
    CHECK(rb_solenoid_simulate(&s, &d, 0.01, 1e-5, out, 2, &err) == RB_EINVAL && strstr(err.message, "duty"));
}

int main(void)
{
    closed_form_c_core();
    coenergy_force();
    energy_balance();
    thermal();
    bad_inputs();
    return rb_test_summary("test_solenoid");
}

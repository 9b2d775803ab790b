/* Contact laws against analytic references and limiting cases. */
#include "rb_test.h"
#include "railbrake/rb_contact.h"

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static void test_elliptic_integrals(void)
{
    /* Abramowitz & Stegun Table 17.1, modulus k = sin 45 deg. */
    double K, E, KmE;
    rb_elliptic_ke(sqrt(0.5), &K, &E, &KmE);
    CHECK_CLOSE(K, 1.8540746773013719, 1e-13, 0);
    CHECK_CLOSE(E, 1.3506438810476755, 1e-13, 0);
    CHECK_CLOSE(KmE, K - E, 1e-13, 0);
    rb_elliptic_ke(0.0, &K, &E, &KmE);
    CHECK_CLOSE(K, M_PI / 2, 1e-15, 0);
    CHECK_CLOSE(E, M_PI / 2, 1e-15, 0);
}

static void test_hertz_sphere(void)
{
    /* Equal curvatures: a = b = (3 P R / (4 E*))^(1/3), Johnson eq. (4.22). */
    rb_hertz h;
    double P = 80e3, R = 0.4, E = 2.1e11, nu = 0.3;
    CHECK(rb_hertz_contact(P, R, R, E, nu, &h, NULL) == RB_OK);
    double e_star = E / (2 * (1 - nu * nu));
    double a = cbrt(3 * P * R / (4 * e_star));
    CHECK_CLOSE(h.a, a, 1e-10, 0);
    CHECK_CLOSE(h.b, a, 1e-10, 0);
    CHECK_CLOSE(h.p0, 3 * P / (2 * M_PI * a * a), 1e-10, 0);
}

static void test_hertz_orientation(void)
{
    /* Swapping rx and ry swaps a and b. */
    rb_hertz h1, h2;
    CHECK(rb_hertz_contact(83e3, 0.46, 0.3, 2.1e11, 0.3, &h1, NULL) == RB_OK);
    CHECK(rb_hertz_contact(83e3, 0.3, 0.46, 2.1e11, 0.3, &h2, NULL) == RB_OK);
    CHECK(h1.a > h1.b);
    CHECK_CLOSE(h1.a, h2.b, 1e-12, 0);
    CHECK_CLOSE(h1.b, h2.a, 1e-12, 0);
}

static void test_hertz_bad_input(void)
{
    rb_hertz h;
    rb_error err;
    CHECK(rb_hertz_contact(-1.0, 0.46, 0.3, 2.1e11, 0.3, &h, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "normal_force") != NULL);
    CHECK(rb_hertz_contact(1e4, 0.46, 0.3, 2.1e11, 0.5, &h, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "poisson") != NULL);
    CHECK(rb_hertz_contact(1e4, INFINITY, 0.3, 2.1e11, 0.3, &h, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "rx") != NULL);
    CHECK(rb_hertz_contact(1e4, 0.46, NAN, 2.1e11, 0.3, &h, &err) == RB_EINVAL);
}

static void test_kalker(void)
{
    double c;
    CHECK(rb_kalker(11, 1.0, 0.25, &c, NULL) == RB_OK);
    CHECK_CLOSE(c, 4.12, 1e-12, 0);
    CHECK(rb_kalker(23, 0.5, 0.5, &c, NULL) == RB_OK);
    CHECK_CLOSE(c, 1.07, 1e-12, 0);
    /* Asymptote a/b -> 0: C11 -> pi^2 / (4 (1 - nu)). */
    CHECK(rb_kalker(11, 1e-9, 0.25, &c, NULL) == RB_OK);
    CHECK_CLOSE(c, M_PI * M_PI / 3.0, 1e-6, 0);
    /* Continuous at the table edges. */
    double inside, outside;
    rb_kalker(22, 10.0 - 1e-9, 0.3, &inside, NULL);
    rb_kalker(22, 10.0 + 1e-9, 0.3, &outside, NULL);
    CHECK_CLOSE(inside, outside, 1e-6, 0);
    rb_error err;
    CHECK(rb_kalker(12, 1.0, 0.3, &c, &err) == RB_EINVAL);
    CHECK(rb_kalker(11, -1.0, 0.3, &c, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "a_over_b") != NULL);
}

static void test_polach(void)
{
    rb_creep_contact c = {6e-3, 4e-3, 4.0, 8.1e10};
    rb_polach_params linear = {0.5, 1.0, 0.0, 1.0, 1.0, 0.0};
    double Q = 8e4, s = 1e-7;
    /* kA = kS = 1, constant mu: Kalker's linear slope G a b c11. */
    double f = rb_polach_coefficient_fast(s, 10.0, Q, &c, &linear) * Q;
    CHECK_CLOSE(f / s, c.shear_modulus * c.a * c.b * c.c11, 1e-6, 0);
    /* Zero creep, antisymmetry, locked wheel, standstill. */
    rb_polach_params dry = {0.55, 0.4, 0.6, 1.0, 0.4, 0.0};
    CHECK(rb_polach_coefficient_fast(0.0, 30.0, Q, &c, &dry) == 0.0);
    CHECK_CLOSE(rb_polach_coefficient_fast(-0.02, 30.0, Q, &c, &dry),
                -rb_polach_coefficient_fast(0.02, 30.0, Q, &c, &dry), 1e-15, 0);
    double locked = rb_polach_coefficient_fast(-1.0, 80.0, Q, &c, &dry);
    CHECK(isfinite(locked) && locked < 0.0 && locked > -dry.mu0);
    CHECK(isfinite(rb_polach_coefficient_fast(0.05, 0.0, Q, &c, &dry)));

    double peak, at;
    CHECK(rb_polach_peak(8.33, Q, &c, &dry, &peak, &at, NULL) == RB_OK);
    CHECK(peak > rb_polach_coefficient_fast(0.5 * at, 8.33, Q, &c, &dry));
    CHECK(peak >= rb_polach_coefficient_fast(2.0 * at, 8.33, Q, &c, &dry));

    rb_error err;
    double creep_nan = NAN, speed = 10.0, out;
    CHECK(rb_polach_coefficient(&creep_nan, &speed, 1, Q, &c, &dry, &out, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "creep[0]") != NULL);
    rb_polach_params bad = dry;
    bad.kS = 0.0;
    CHECK(rb_polach_coefficient(&s, &speed, 1, Q, &c, &bad, &out, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "kS") != NULL);
}

/* A = 0 lets the friction underflow to exactly 0 at a large slip velocity: the force is then 0
 * (its limit), never 0/0. */
static void test_polach_vanishing_friction(void)
{
    rb_creep_contact c = {0.006, 0.005, 4.0, 8.1e10};
    rb_polach_params p = {0.5, 0.0, 20.0, 0.3, 0.1, 0.0};
    double f = rb_polach_coefficient_fast(-1.0, 83.3, 83e3, &c, &p);
    CHECK(isfinite(f));
    CHECK(f == 0.0);
}

/* The rolling-speed factor mu0 / (1 + v / v_ref): off (v_ref_inv 0) and at v_ref -> infinity
 * (v_ref_inv below half an ulp of 1 over the speed) it is Polach's law bit for bit (Polach 2005's
 * mu(w) and F written here again, in the same operations); on, the coefficient and the peak at speed v are those of
 * Polach's law with mu0 / (1 + v / v_ref), so at v = v_ref the peak is that of mu0 / 2; the peak
 * falls with speed at any slip. */
static double polach_reference(double creep, double speed, double Q, const rb_creep_contact *c,
                               const rb_polach_params *p)
{
    double w = fabs(creep) * speed, mu = p->mu0 * ((1.0 - p->A) * exp(-p->B * w) + p->A);
    double eps = c->shear_modulus * M_PI * c->a * c->b * c->c11 / (4.0 * Q * mu) * fabs(creep), k = p->kA * eps;
    double f = 2.0 * mu / M_PI * (k / (1.0 + k * k) + atan(p->kS * eps));
    return creep < 0.0 ? -f : f;
}

static void test_polach_rolling_factor(void)
{
    rb_creep_contact c = {0.0062, 0.0049, 4.12, 8.1e10};
    const double Q = 83e3;
    rb_polach_params off = {0.30, 0.40, 0.20, 0.3, 0.1, 0.0}, far = off, on = off;
    far.v_ref_inv = 1e-300;            /* v_ref -> infinity */
    on.v_ref_inv = 3.6 / 100.0;        /* v_ref 100 km/h */
    int same = 1;
    for (int i = 0; i <= 70; ++i)
        for (int j = 0; j <= 10; ++j) {
            double creep = -pow(10.0, -7.0 + i * 0.1), v = 10.0 * j;
            double reference = polach_reference(creep, v, Q, &c, &off);
            same &= rb_polach_coefficient_fast(creep, v, Q, &c, &off) == reference;
            same &= rb_polach_coefficient_fast(creep, v, Q, &c, &far) == reference;
            rb_polach_params scaled = off;
            scaled.mu0 = off.mu0 / (1.0 + v * on.v_ref_inv);
            CHECK_CLOSE(rb_polach_coefficient_fast(creep, v, Q, &c, &on), polach_reference(creep, v, Q, &c, &scaled),
                        1e-15, 0);
        }
    CHECK(same);
    CHECK(rb_polach_rolling_factor(250.0, 0.0) == 1.0);
    CHECK_CLOSE(rb_polach_rolling_factor(100.0 / 3.6, 3.6 / 100.0), 0.5, 1e-15, 0);
    double peak_on, peak_half, peak_off, creep_on, creep_half;
    rb_polach_params half = off;
    half.mu0 = 0.5 * off.mu0;
    CHECK(rb_polach_peak(100.0 / 3.6, Q, &c, &on, &peak_on, &creep_on, NULL) == RB_OK);
    CHECK(rb_polach_peak(100.0 / 3.6, Q, &c, &half, &peak_half, &creep_half, NULL) == RB_OK);
    CHECK(rb_polach_peak(100.0 / 3.6, Q, &c, &off, &peak_off, NULL, NULL) == RB_OK);
    CHECK_CLOSE(peak_on, peak_half, 1e-9, 0);
    CHECK_CLOSE(creep_on, creep_half, 1e-6, 0);
    CHECK(peak_on < 0.6 * peak_off);
    rb_error err;
    rb_polach_params bad = on;
    bad.v_ref_inv = -0.01;
    CHECK(rb_polach_check(&bad, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "v_ref_inv") != NULL);
}

/* The followed peak (rb_polach_peak_track), down in speed as a run samples it, over the checked
 * parameter ranges: always a maximum of the curve (a value of the law, no higher than the full
 * scan's, with lower values at creep 1e-3 decades either side), and the scan's own wherever the
 * scan's maximum lies on the followed branch (within 0.1 decades of it). Parameters drawn
 * log-uniformly (B, kA, kS) or uniformly (mu0, A) by a fixed linear congruential generator; half
 * of them with kS / kA in [0.14, 1], the law's usual range. */
static double uniform(unsigned long *state)
{
    *state = *state * 6364136223846793005UL + 1442695040888963407UL;
    return (double)((*state >> 11) & ((1UL << 53) - 1)) / (double)(1UL << 53);
}

static void test_polach_peak_track(void)
{
    rb_creep_contact c = {0.0062, 0.0049, 4.12, 8.1e10};
    unsigned long seed = 12345;
    double worst = 0.0;
    int same_branch = 0, other_branch = 0;
    for (int set = 0; set < 200; ++set) {
        rb_polach_params p = {0.01 + 0.99 * uniform(&seed), uniform(&seed), pow(10.0, -2.0 + 4.0 * uniform(&seed)),
                              pow(10.0, -3.0 + 3.0 * uniform(&seed)), pow(10.0, -3.0 + 3.0 * uniform(&seed)), 0.0};
        if (set % 2 == 0) p.kS = p.kA * (0.14 + 0.86 * uniform(&seed));
        double Q = 50e3 + 60e3 * uniform(&seed), log_creep = NAN;
        for (double v = 100.0; v > 2.0; v -= 0.7) {
            double scan = 0.0, scan_creep = 0.0, peak = rb_polach_peak_track(v, Q, &c, &p, &log_creep);
            CHECK(rb_polach_peak(v, Q, &c, &p, &scan, &scan_creep, NULL) == RB_OK);
            double creep = pow(10.0, log_creep);
            CHECK(peak <= scan * (1.0 + 1e-12));
            CHECK(rb_polach_coefficient_fast(creep * pow(10.0, -1e-3), v, Q, &c, &p) <= peak);
            if (log_creep < -1e-3) CHECK(rb_polach_coefficient_fast(creep * pow(10.0, 1e-3), v, Q, &c, &p) <= peak);
            if (fabs(log10(scan_creep) - log_creep) > 0.1) { other_branch++; continue; }
            same_branch++;
            double error = fabs(peak - scan) / scan;
            if (error > worst) worst = error;
            CHECK(error <= 1e-8);   /* Newton stops ~1e-5 decades short: F to ~1e-9 */
        }
    }
    CHECK(same_branch > 20 * other_branch);
    printf("peak track: %d samples on the scan's branch (largest relative difference %.2e), %d on another\n",
           same_branch, worst, other_branch);
}

/* rb_creep_peaks_track: many curves followed side by side (in rounds, more than one batch of
 * them) end where each followed alone ends, bit for bit, with a batch evaluator or without. */
typedef struct {
    double speed, normal_force;
    const rb_creep_contact *c;
    rb_polach_params p;
} test_curve;

static double test_curve_at(const void *curve, double log_creep)
{
    const test_curve *k = curve;
    return rb_polach_coefficient_fast(pow(10.0, log_creep), k->speed, k->normal_force, k->c, &k->p);
}

static void test_curves_each(const rb_creep_curve *curves, const int *member, const double *log_creep, double *f,
                             int n)
{
    for (int j = n - 1; j >= 0; --j) f[j] = curves[member[j]].at(curves[member[j]].curve, log_creep[j]);
}

static void test_peaks_track_batch(void)
{
    enum { N = 150 };
    static test_curve k[N];
    static rb_creep_curve f[N];
    static double alone[N], together[N], each[N], x_alone[N], x_together[N], x_each[N];
    rb_creep_contact c = {0.0062, 0.0049, 4.12, 8.1e10};
    unsigned long seed = 777;
    int differ = 0;
    for (int i = 0; i < N; ++i) {
        rb_polach_params p = {0.01 + 0.99 * uniform(&seed), uniform(&seed), pow(10.0, -2.0 + 4.0 * uniform(&seed)),
                              pow(10.0, -3.0 + 3.0 * uniform(&seed)), pow(10.0, -3.0 + 3.0 * uniform(&seed)), 0.0};
        k[i] = (test_curve){2.0 + 90.0 * uniform(&seed), 50e3 + 60e3 * uniform(&seed), &c, p};
        f[i] = (rb_creep_curve){test_curve_at, NULL, &k[i], p.mu0 * ((1.0 - p.A) * exp(-p.B * k[i].speed) + p.A)};
        int maxima;   /* a start near the peak (Newton's), or none (the scan) */
        double x = NAN;
        rb_creep_peak_scan(&f[i], &x, &maxima);
        x_alone[i] = x_together[i] = x_each[i] = i % 7 == 0 ? NAN : x + 0.05 * (uniform(&seed) - 0.5);
    }
    for (int i = 0; i < N; ++i) alone[i] = rb_creep_peak_track(&f[i], &x_alone[i]);
    rb_creep_peaks_track(f, N, NULL, x_together, together);
    rb_creep_peaks_track(f, N, test_curves_each, x_each, each);
    for (int i = 0; i < N; ++i)
        differ += memcmp(&alone[i], &together[i], sizeof alone[i]) || memcmp(&alone[i], &each[i], sizeof alone[i]) ||
                  memcmp(&x_alone[i], &x_together[i], sizeof x_alone[i]) ||
                  memcmp(&x_alone[i], &x_each[i], sizeof x_alone[i]);
    CHECK(differ == 0);
}

int main(void)
{
    test_polach_vanishing_friction();
    test_elliptic_integrals();
    test_hertz_sphere();
    test_hertz_orientation();
    test_hertz_bad_input();
    test_kalker();
    test_polach();
    test_polach_rolling_factor();
    test_polach_peak_track();
    test_peaks_track_batch();
    return rb_test_summary("test_contact");
}

/* The plant's own elementary functions against libm over their whole range of use. */
#include "rb_test.h"
#include "railbrake/rb_common.h"

#include <math.h>
#include <stdio.h>

/* Largest relative error of rb_atan_nonneg against libm's atan on log-spaced points from 1e-300 to
 * 1e300, dense around the reduction thresholds 0.66 and tan(3 pi / 8), plus 0 and +inf. */
static void test_atan(void)
{
    double worst = 0.0;
    for (long i = 0; i <= 2000000; ++i) {
        double x = pow(10.0, -300.0 + 600.0 * i / 2000000.0);
        double e = fabs(rb_atan_nonneg(x) - atan(x)) / atan(x);
        if (e > worst) worst = e;
    }
    const double edges[] = {0.66, 2.41421356237309504880};
    for (int k = 0; k < 2; ++k)
        for (int i = -100000; i <= 100000; ++i) {
            double x = edges[k] * (1.0 + i * 1e-7);
            double e = fabs(rb_atan_nonneg(x) - atan(x)) / atan(x);
            if (e > worst) worst = e;
        }
    printf("rb_atan_nonneg: largest relative error %.2e\n", worst);
    CHECK(worst < 1e-15);
    CHECK(rb_atan_nonneg(0.0) == 0.0);
    CHECK(rb_atan_nonneg(HUGE_VAL) == atan(HUGE_VAL));
}

/* rb_atan_ratio_parts: atan(y / x) without dividing y by x first, against libm's atan2 over ratios
   from 1e-12 to 1e12 and denominators from 1e-3 to 1e3 (both edges of the reduction included). */
static void test_atan_ratio(void)
{
    double worst = 0.0;
    for (long i = 0; i <= 400000; ++i)
        for (int j = 0; j <= 6; ++j) {
            double x = pow(10.0, -3.0 + j), ratio = pow(10.0, -12.0 + 24.0 * i / 400000.0), y = ratio * x;
            double base, num, den, ref = atan2(y, x);
            rb_atan_ratio_parts(y, x, &base, &num, &den);
            double e = fabs(base + num / den - ref) / ref;
            if (e > worst) worst = e;
        }
    printf("rb_atan_ratio_parts: largest relative error %.2e\n", worst);
    CHECK(worst < 1e-15);
}

/* rb_exp_nonpos against libm's exp over [-708, 0] (dense near 0 and around the rounding points of
 * n = x / ln 2), and 0 below. */
static void test_exp(void)
{
    double worst = 0.0;
    for (long i = 0; i <= 2000000; ++i) {
        double x = -708.0 * i / 2000000.0;
        double e = fabs(rb_exp_nonpos(x) - exp(x)) / exp(x);
        if (e > worst) worst = e;
    }
    for (long i = 0; i <= 1000000; ++i) {
        double x = -pow(10.0, -300.0 + 300.0 * i / 1000000.0);
        double e = fabs(rb_exp_nonpos(x) - exp(x)) / exp(x);
        if (e > worst) worst = e;
    }
    for (int n = 0; n < 1021; ++n)
        for (int i = -50; i <= 50; ++i) {
            double x = -(n + 0.5) * 0.69314718055994530942 * (1.0 + i * 1e-15);
            double e = fabs(rb_exp_nonpos(x) - exp(x)) / exp(x);
            if (e > worst) worst = e;
        }
    printf("rb_exp_nonpos: largest relative error %.2e\n", worst);
    CHECK(worst < 1e-15);
    CHECK(rb_exp_nonpos(0.0) == 1.0);
    CHECK(rb_exp_nonpos(-709.0) == 0.0 && rb_exp_nonpos(-HUGE_VAL) == 0.0);
}

/* 1 - exp(-y) against -expm1(-y) from 1e-300 to 800 (both branches and the switch at 1/16). */
static void test_one_minus_exp_neg(void)
{
    double worst = 0.0;
    for (long i = 0; i <= 1000000; ++i) {
        double y = pow(10.0, -300.0 + 302.9 * i / 1000000.0);
        double ref = -expm1(-y);
        double e = fabs(rb_one_minus_exp_neg(y) - ref) / ref;
        if (e > worst) worst = e;
    }
    for (int i = -10000; i <= 10000; ++i) {
        double y = 0.0625 * (1.0 + i * 1e-6), ref = -expm1(-y);
        double e = fabs(rb_one_minus_exp_neg(y) - ref) / ref;
        if (e > worst) worst = e;
    }
    printf("rb_one_minus_exp_neg: largest relative error %.2e\n", worst);
    CHECK(worst < 1e-14);
    CHECK(rb_one_minus_exp_neg(0.0) == 0.0);
    CHECK(rb_one_minus_exp_neg(HUGE_VAL) == 1.0);
}

int main(void)
{
    test_atan();
    test_atan_ratio();
    test_exp();
    test_one_minus_exp_neg();
    return rb_test_summary("test_fastmath");
}

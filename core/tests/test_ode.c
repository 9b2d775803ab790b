/* The stiff integrator on a stiff linear system (closed form) and Robertson's problem. */
#include "rb_test.h"
#include "railbrake/rb_ode.h"

#include <math.h>

static void linear(double t, const double *y, double *f, void *user)
{
    (void)t; (void)user;
    f[0] = -y[0];
    f[1] = -1000.0 * (y[1] - y[0]);
}

static void robertson(double t, const double *y, double *f, void *user)
{
    (void)t; (void)user;
    f[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
    f[2] = 3e7 * y[1] * y[1];
    f[1] = -f[0] - f[2];
}

static long n_calls;
static void count(double t, const double *y, void *user) { (void)t; (void)y; (void)user; n_calls++; }

static void test_linear(void)
{
    double y[2] = {1.0, 0.0}, t_out[3] = {0.0, 0.5, 2.0}, y_out[6], work[64];
    int iwork[2];
    rb_ode_options opt = {1e-7, 1e-10, NULL, 0.0, 0.0, 100000};
    rb_ode_stats st;
    CHECK(rb_ode_solve(linear, NULL, 2, 0.0, y, t_out, 3, y_out, count, &opt, work, 64, iwork, &st, NULL) == RB_OK);
    /* y0 = e^-t, y1 = c (e^-t - e^-1000t), c = 1000/999. */
    double c = 1000.0 / 999.0;
    CHECK_CLOSE(y_out[0], 1.0, 1e-14, 0);
    CHECK_CLOSE(y_out[2], exp(-0.5), 1e-5, 0);
    CHECK_CLOSE(y_out[3], c * exp(-0.5), 1e-5, 0);
    CHECK_CLOSE(y[0], exp(-2.0), 1e-5, 0);
    CHECK_CLOSE(y[1], c * exp(-2.0), 1e-5, 0);
    CHECK(st.steps == n_calls);
    /* Stiffness does not dictate the step: far fewer steps than 2 s / (2 / 1000 s). */
    CHECK(st.steps < 1000);
    printf("linear: %ld steps, %ld rejected, %ld rhs calls\n", st.steps, st.rejected, st.rhs_calls);
}

static void test_robertson(void)
{
    /* Reference at t = 40 (Hairer & Wanner, Solving ODEs II, sec. IV.10; SUNDIALS cvRoberts_dns). */
    double y[3] = {1.0, 0.0, 0.0}, t_out[1] = {40.0}, y_out[3], work[64];
    int iwork[3];
    rb_ode_options opt = {1e-6, 1e-12, NULL, 0.0, 0.0, 100000};
    rb_ode_stats st;
    CHECK(rb_ode_solve(robertson, NULL, 3, 0.0, y, t_out, 1, y_out, NULL, &opt, work, 64, iwork, &st, NULL) == RB_OK);
    CHECK_CLOSE(y[0], 0.7158270687, 1e-4, 0);
    CHECK_CLOSE(y[1], 9.185534764e-6, 1e-3, 0);
    CHECK_CLOSE(y[2], 0.2841637457, 1e-4, 0);
    CHECK_CLOSE(y[0] + y[1] + y[2], 1.0, 1e-12, 0);
    printf("robertson: %ld steps, %ld rejected\n", st.steps, st.rejected);
}

static void test_bad_input(void)
{
    double y[2] = {1.0, 0.0}, t_out[2] = {1.0, 0.5}, y_out[4], work[4];
    int iwork[2];
    rb_ode_options opt = {1e-6, 1e-9, NULL, 0.0, 0.0, 1000};
    rb_error err;
    CHECK(rb_ode_solve(linear, NULL, 2, 0.0, y, t_out, 2, y_out, NULL, &opt, work, 4, iwork, NULL, &err) == RB_ESIZE);
    double work2[64];
    CHECK(rb_ode_solve(linear, NULL, 2, 0.0, y, t_out, 2, y_out, NULL, &opt, work2, 64, iwork, NULL, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "t_out[1]") != NULL);
}

static void test_lu(void)
{
    /* A 4x4 system that needs row exchanges at several stages; x = (1, 2, 3, 4). */
    double a[16] = {0, 2, 1, 0,  1, 0, 0, 3,  0, 0, 4, 1,  2, 1, 0, 0}, b[4], x[4] = {1, 2, 3, 4};
    double lu[16];
    int piv[4];
    for (int i = 0; i < 4; ++i) {
        b[i] = 0;
        for (int j = 0; j < 4; ++j) b[i] += a[i * 4 + j] * x[j];
    }
    memcpy(lu, a, sizeof a);
    CHECK(rb_lu_factor(lu, 4, piv) == 1);
    rb_lu_solve(lu, 4, piv, b);
    for (int i = 0; i < 4; ++i) CHECK_CLOSE(b[i], x[i], 1e-13, 0);
}

int main(void)
{
    test_lu();
    test_linear();
    test_robertson();
    test_bad_input();
    return rb_test_summary("test_ode");
}

/* Rosenbrock 2(3) stiff integrator (Shampine & Reichelt 1997); see rb_ode.h. */
#include "railbrake/rb_ode.h"

#include <float.h>
#include <math.h>
#include <string.h>

int rb_lu_factor(double *a, size_t n, int *pivot)
{
    for (size_t k = 0; k < n; ++k) {
        size_t p = k;
        for (size_t i = k + 1; i < n; ++i)
            if (fabs(a[i * n + k]) > fabs(a[p * n + k])) p = i;
        pivot[k] = (int)p;
        if (a[p * n + k] == 0.0) return 0;
        if (p != k)
            for (size_t j = 0; j < n; ++j) {
                double t = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = t;
            }
        for (size_t i = k + 1; i < n; ++i) {
            double l = a[i * n + k] /= a[k * n + k];
            for (size_t j = k + 1; j < n; ++j) a[i * n + j] -= l * a[k * n + j];
        }
    }
    return 1;
}

void rb_lu_solve(const double *lu, size_t n, const int *pivot, double *b)
{
    /* Whole rows (multipliers included) were swapped while factoring: permute b first. */
    for (size_t k = 0; k < n; ++k) {
        size_t p = (size_t)pivot[k];
        if (p != k) { double t = b[k]; b[k] = b[p]; b[p] = t; }
    }
    for (size_t k = 0; k < n; ++k)
        for (size_t i = k + 1; i < n; ++i) b[i] -= lu[i * n + k] * b[k];
    for (size_t k = n; k-- > 0;) {
        for (size_t j = k + 1; j < n; ++j) b[k] -= lu[k * n + j] * b[j];
        b[k] /= lu[k * n + k];
    }
}

/* Work layout: W (n*n), then 10 vectors of n. */
enum { V_F0, V_F1, V_F2, V_K1, V_K2, V_K3, V_YN, V_DT, V_TMP, V_ERR, V_COUNT };

size_t rb_ode_workspace_size(size_t n) { return n * n + V_COUNT * n; }

typedef struct {
    rb_ode_rhs rhs;
    void *user;
    size_t n;
    double *W, *v[V_COUNT];
    int *pivot;
    rb_ode_stats st;
} solver;

static void eval(solver *s, double t, const double *y, double *f)
{
    s->rhs(t, y, f, s->user);
    s->st.rhs_calls++;
}

/* W = I - h d J with J by forward differences around (t, y, f0); dT = df/dt. */
static int build_w(solver *s, double t, double *y, const double *f0, double hd)
{
    size_t n = s->n;
    double *ftmp = s->v[V_TMP];
    for (size_t j = 0; j < n; ++j) {
        double yj = y[j], dy = sqrt(DBL_EPSILON) * fmax(fabs(yj), 1e-5);
        y[j] = yj + dy;
        dy = y[j] - yj;
        eval(s, t, y, ftmp);
        y[j] = yj;
        for (size_t i = 0; i < n; ++i)
            s->W[i * n + j] = -hd * (ftmp[i] - f0[i]) / dy + (i == j ? 1.0 : 0.0);
    }
    double dt = sqrt(DBL_EPSILON) * fmax(fabs(t), 1e-3);
    eval(s, t + dt, y, ftmp);
    for (size_t i = 0; i < n; ++i) s->v[V_DT][i] = (ftmp[i] - f0[i]) / dt;
    return rb_lu_factor(s->W, n, s->pivot);
}

/* One step of size h from (t, y, F0): fills YN, F2 and returns the scaled error norm. */
static double step(solver *s, double t, double *y, double h, const rb_ode_options *opt, int *ok)
{
    const double d = 1.0 / (2.0 + sqrt(2.0)), e32 = 6.0 + sqrt(2.0);
    size_t n = s->n;
    double *F0 = s->v[V_F0], *F1 = s->v[V_F1], *F2 = s->v[V_F2], *k1 = s->v[V_K1];
    double *k2 = s->v[V_K2], *k3 = s->v[V_K3], *yn = s->v[V_YN], *T = s->v[V_DT], *tmp = s->v[V_TMP];
    *ok = build_w(s, t, y, F0, h * d);
    if (!*ok) return INFINITY;
    for (size_t i = 0; i < n; ++i) k1[i] = F0[i] + h * d * T[i];
    rb_lu_solve(s->W, n, s->pivot, k1);
    for (size_t i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
    eval(s, t + 0.5 * h, tmp, F1);
    for (size_t i = 0; i < n; ++i) k2[i] = F1[i] - k1[i];
    rb_lu_solve(s->W, n, s->pivot, k2);
    for (size_t i = 0; i < n; ++i) { k2[i] += k1[i]; yn[i] = y[i] + h * k2[i]; }
    eval(s, t + h, yn, F2);
    for (size_t i = 0; i < n; ++i)
        k3[i] = F2[i] - e32 * (k2[i] - F1[i]) - 2.0 * (k1[i] - F0[i]) + h * d * T[i];
    rb_lu_solve(s->W, n, s->pivot, k3);
    double norm = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double e = h / 6.0 * (k1[i] - 2.0 * k2[i] + k3[i]);
        double sc = opt->atol * (opt->atol_scale ? opt->atol_scale[i] : 1.0) + opt->rtol * fmax(fabs(y[i]), fabs(yn[i]));
        double r = fabs(e) / sc;
        if (!(r <= norm)) norm = r; /* NaN propagates as a rejection */
    }
    return norm;
}

/* Continuous extension between t and t + h at fraction th. */
static void interpolate(const solver *s, const double *y, double h, double th, double *out)
{
    const double d = 1.0 / (2.0 + sqrt(2.0));
    double c1 = th * (1.0 - th) / (1.0 - 2.0 * d), c2 = th * (th - 2.0 * d) / (1.0 - 2.0 * d);
    for (size_t i = 0; i < s->n; ++i) out[i] = y[i] + h * (c1 * s->v[V_K1][i] + c2 * s->v[V_K2][i]);
}

static rb_status check_args(size_t n, double t0, const double *y, const double *t_out, size_t n_out,
                            const double *y_out, const rb_ode_options *opt, size_t work_size,
                            const double *work, const int *iwork, rb_error *err)
{
    rb_status s;
    if (!y || !t_out || !y_out || !opt || !work || !iwork || n == 0 || n_out == 0)
        return rb_fail(err, RB_EINVAL, "ode: y, t_out, y_out, options and workspaces are required");
    if (work_size < rb_ode_workspace_size(n))
        return rb_fail(err, RB_ESIZE, "ode work_size = %zu: needs >= %zu doubles", work_size,
                       rb_ode_workspace_size(n));
    if ((s = rb_check_positive(err, "rtol", opt->rtol))) return s;
    if ((s = rb_check_positive(err, "atol", opt->atol))) return s;
    if ((s = rb_check_nonnegative(err, "h_initial", opt->h_initial))) return s;
    if ((s = rb_check_nonnegative(err, "h_max", opt->h_max))) return s;
    if (opt->max_steps < 1) return rb_fail(err, RB_EINVAL, "max_steps = %ld: must be >= 1", opt->max_steps);
    for (size_t i = 0; i < n_out; ++i)
        if (!isfinite(t_out[i]) || t_out[i] < (i ? t_out[i - 1] : t0))
            return rb_fail(err, RB_EINVAL, "t_out[%zu] = %g: must be finite, >= t0 and increasing", i,
                           t_out[i]);
    for (size_t i = 0; i < n; ++i)
        if ((s = rb_check_finite(err, "y0", y[i]))) return s;
    return RB_OK;
}

rb_status rb_ode_solve(rb_ode_rhs rhs, void *user, size_t n, double t0, double *y,
                       const double *t_out, size_t n_out, double *y_out,
                       rb_ode_step_output step_output, const rb_ode_options *opt,
                       double *work, size_t work_size, int *iwork, rb_ode_stats *stats,
                       rb_error *err)
{
    rb_status status = check_args(n, t0, y, t_out, n_out, y_out, opt, work_size, work, iwork, err);
    if (status) return status;
    solver s = {rhs, user, n, work, {0}, iwork, {0, 0, 0}};
    for (int k = 0; k < V_COUNT; ++k) s.v[k] = work + n * n + (size_t)k * n;
    double t = t0, t_end = t_out[n_out - 1], span = t_end - t0;
    double h_max = opt->h_max > 0.0 ? opt->h_max : span;
    size_t next = 0;
    eval(&s, t, y, s.v[V_F0]);
    /* Initial step from the scaled size of f (Hairer-Wanner II.4 style, simplified). */
    double h = opt->h_initial;
    if (h <= 0.0) {
        double fn = 0.0;
        for (size_t i = 0; i < n; ++i)
            fn = fmax(fn, fabs(s.v[V_F0][i]) /
                             (opt->atol * (opt->atol_scale ? opt->atol_scale[i] : 1.0) + opt->rtol * fabs(y[i])));
        h = fn > 0.0 ? 0.1 * pow(opt->rtol, 1.0 / 3.0) / fn : span;
    }
    while (next < n_out && t_out[next] <= t) memcpy(y_out + n * next++, y, n * sizeof *y);
    long attempts = 0;
    while (t < t_end) {
        h = fmin(fmin(h, h_max), t_end - t);
        if (t + 1.1 * h >= t_end && t_end - t <= h_max) h = t_end - t; /* no sliver step */
        if (++attempts > opt->max_steps)
            return rb_fail(err, RB_ENOCONV, "ode: max_steps = %ld reached at t = %g s (h = %g s)",
                           opt->max_steps, t, h);
        if (h < 16.0 * DBL_EPSILON * fmax(fabs(t), 1e-3))
            return rb_fail(err, RB_ENOCONV, "ode: step size %g s too small at t = %g s", h, t);
        int ok;
        double e = step(&s, t, y, h, opt, &ok);
        if (!(e <= 1.0)) {
            s.st.rejected++;
            h *= ok && isfinite(e) ? fmax(0.2, 0.8 * pow(e, -1.0 / 3.0)) : 0.25;
            continue;
        }
        while (next < n_out && t_out[next] <= t + h) {
            interpolate(&s, y, h, (t_out[next] - t) / h, y_out + n * next);
            next++;
        }
        t = (h == t_end - t) ? t_end : t + h;
        memcpy(y, s.v[V_YN], n * sizeof *y);
        memcpy(s.v[V_F0], s.v[V_F2], n * sizeof *y);
        s.st.steps++;
        if (step_output) step_output(t, y, user);
        h *= fmin(5.0, 0.8 * pow(fmax(e, 1e-10), -1.0 / 3.0));
    }
    while (next < n_out) memcpy(y_out + n * next++, y, n * sizeof *y);
    if (stats) *stats = s.st;
    return RB_OK;
}

/* Time schedules and 2-D solenoid force tables used by the network. */
#include "railbrake/rb_network.h"

#include <math.h>

double rb_schedule_eval(const rb_schedule *s, double t)
{
    if (s->n <= 0) return 1.0;
    t -= s->delay;
    if (t <= s->t[0]) return s->value[0];
    for (int i = 1; i < s->n; ++i)
        if (t < s->t[i]) {
            double w = (t - s->t[i - 1]) / (s->t[i] - s->t[i - 1]);
            return s->value[i - 1] + w * (s->value[i] - s->value[i - 1]);
        }
    return s->value[s->n - 1];
}

static rb_status check_axis(rb_error *err, const char *name, const double *v, int n)
{
    if (n < 2 || n > RB_FORCE_TABLE_MAX)
        return rb_fail(err, RB_EINVAL, "force table: %d %s values: needs 2 to %d", n, name,
                       RB_FORCE_TABLE_MAX);
    for (int i = 0; i < n; ++i) {
        if (!isfinite(v[i])) return rb_fail(err, RB_EINVAL, "force table %s[%d] = %g: not finite", name, i, v[i]);
        if (i > 0 && !(v[i] > v[i - 1]))
            return rb_fail(err, RB_EINVAL,
                           "force table %s[%d] = %g: must be > %s[%d] = %g (sorted by %s, increasing)",
                           name, i, v[i], name, i - 1, v[i - 1], name);
    }
    return RB_OK;
}

rb_status rb_force_table_check(const rb_force_table *f, rb_error *err)
{
    rb_status s;
    if (!f) return rb_fail(err, RB_EINVAL, "force table = NULL");
    if ((s = check_axis(err, "airgap", f->gap, f->n_gap))) return s;
    if ((s = check_axis(err, "current", f->current, f->n_current))) return s;
    for (int i = 0; i < f->n_gap * f->n_current; ++i)
        if (!isfinite(f->force[i]))
            return rb_fail(err, RB_EINVAL, "force table force[%d] = %g: not finite", i, f->force[i]);
    return RB_OK;
}

/* Index i and weight w of v in the axis, clamped to the ends. */
static void locate(const double *axis, int n, double v, int *i, double *w)
{
    if (v <= axis[0]) { *i = 0; *w = 0.0; return; }
    if (v >= axis[n - 1]) { *i = n - 2; *w = 1.0; return; }
    int k = 0;
    while (v > axis[k + 1]) ++k;
    *i = k;
    *w = (v - axis[k]) / (axis[k + 1] - axis[k]);
}

double rb_force_table_eval(const rb_force_table *f, double gap, double current)
{
    int i, j, nc = f->n_current;
    double wg, wc;
    locate(f->gap, f->n_gap, gap, &i, &wg);
    locate(f->current, nc, current, &j, &wc);
    const double *r0 = f->force + i * nc, *r1 = f->force + (i + 1) * nc;
    double a = r0[j] + wc * (r0[j + 1] - r0[j]);
    double b = r1[j] + wc * (r1[j + 1] - r1[j]);
    return a + wg * (b - a);
}

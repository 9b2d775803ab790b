/* Solenoid design model: lumped magnetic circuit, electrical drive, thermal model (rb_solenoid.h). */
#include "railbrake/rb_solenoid.h"

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define CHECK(call) do { rb_status st_ = (call); if (st_) return st_; } while (0)

rb_status rb_solenoid_check(const rb_solenoid *s, rb_error *err)
{
    if (!s) return rb_fail(err, RB_EINVAL, "solenoid = NULL");
    CHECK(rb_check_positive(err, "solenoid.turns", s->turns));
    CHECK(rb_check_nonnegative(err, "solenoid.resistance_20c (ohm)", s->resistance_20c));
    CHECK(rb_check_range(err, "solenoid.resistance_tempco (1/K)", s->resistance_tempco, 0.0, 0.1));
    CHECK(rb_check_nonnegative(err, "solenoid.iron_length (m)", s->iron_length));
    CHECK(rb_check_positive(err, "solenoid.iron_area (m^2)", s->iron_area));
    if (s->bh_points < 2 || s->bh_points > RB_BH_MAX_POINTS)
        return rb_fail(err, RB_EINVAL, "solenoid B-H curve: %d points: needs 2 to %d", s->bh_points,
                       RB_BH_MAX_POINTS);
    if (s->bh_h[0] != 0.0 || s->bh_b[0] != 0.0)
        return rb_fail(err, RB_EINVAL, "solenoid B-H curve: first point (H %g A/m, B %g T): must be (0, 0)",
                       s->bh_h[0], s->bh_b[0]);
    for (int k = 1; k < s->bh_points; ++k) {
        if (!(s->bh_h[k] > s->bh_h[k - 1]) || !isfinite(s->bh_h[k]))
            return rb_fail(err, RB_EINVAL, "solenoid B-H curve: H[%d] = %g A/m after %g: must be increasing",
                           k, s->bh_h[k], s->bh_h[k - 1]);
        if (!(s->bh_b[k] > s->bh_b[k - 1]) || !isfinite(s->bh_b[k]))
            return rb_fail(err, RB_EINVAL, "solenoid B-H curve: B[%d] = %g T after %g: must be increasing",
                           k, s->bh_b[k], s->bh_b[k - 1]);
    }
    CHECK(rb_check_positive(err, "solenoid.pole_diameter (m)", s->pole_diameter));
    if (s->working_gaps != 1 && s->working_gaps != 2)
        return rb_fail(err, RB_EINVAL, "solenoid.working_gaps = %d: must be 1 or 2", s->working_gaps);
    CHECK(rb_check_range(err, "solenoid.fringing", s->fringing, 0.0, 10.0));
    CHECK(rb_check_nonnegative(err, "solenoid.parasitic_gap (m)", s->parasitic_gap));
    if (s->parasitic_gap > 0.0) CHECK(rb_check_positive(err, "solenoid.parasitic_area (m^2)", s->parasitic_area));
    return rb_check_nonnegative(err, "solenoid.leakage_permeance (H)", s->leakage_permeance);
}

/* ------------------------------------------------------------------ iron */

/* H(B) of the B-H curve (odd), linear between points, slope 1/mu0 beyond the last; *slope = dH/dB. */
static double iron_h(const rb_solenoid *s, double b, double *slope)
{
    double sign = b < 0.0 ? -1.0 : 1.0, a = fabs(b);
    int n = s->bh_points, k = 1;
    if (a >= s->bh_b[n - 1]) {
        if (slope) *slope = 1.0 / RB_MU0;
        return sign * (s->bh_h[n - 1] + (a - s->bh_b[n - 1]) / RB_MU0);
    }
    while (a > s->bh_b[k]) ++k;
    double m = (s->bh_h[k] - s->bh_h[k - 1]) / (s->bh_b[k] - s->bh_b[k - 1]);
    if (slope) *slope = m;
    return sign * (s->bh_h[k - 1] + m * (a - s->bh_b[k - 1]));
}

/* Energy density int_0^B H dB (J/m^3), exact for the piecewise-linear curve. */
static double iron_energy_density(const rb_solenoid *s, double b)
{
    double a = fabs(b), w = 0.0;
    for (int k = 1; k < s->bh_points; ++k) {
        double b0 = s->bh_b[k - 1], b1 = fmin(a, s->bh_b[k]);
        if (b1 <= b0) return w;
        w += 0.5 * (s->bh_h[k - 1] + iron_h(s, b1, NULL)) * (b1 - b0);
        if (a <= s->bh_b[k]) return w;
    }
    double bn = s->bh_b[s->bh_points - 1], hn = s->bh_h[s->bh_points - 1];
    return w + hn * (a - bn) + 0.5 * (a - bn) * (a - bn) / RB_MU0;
}

/* ------------------------------------------------------------------ gaps */

static double gap_permeance(const rb_solenoid *s, double gap, double *dp_dgap)
{
    double d = s->pole_diameter + s->fringing * gap, n = s->working_gaps;
    double area = 0.25 * M_PI * d * d, darea = 0.5 * M_PI * d * s->fringing;
    if (dp_dgap) *dp_dgap = RB_MU0 / n * (darea * gap - area) / (gap * gap);
    return RB_MU0 * area / (n * gap);
}

static double parasitic_reluctance(const rb_solenoid *s)
{
    return s->parasitic_gap > 0.0 ? s->parasitic_gap / (RB_MU0 * s->parasitic_area) : 0.0;
}

/* MMF (A) the loop needs for the iron flux phi at gap; *dmmf = its derivative in phi. */
static double loop_mmf(const rb_solenoid *s, double gap, double phi, double *dmmf)
{
    double slope, p = gap_permeance(s, gap, NULL) + s->leakage_permeance, rp = parasitic_reluctance(s);
    double mmf = s->iron_length * iron_h(s, phi / s->iron_area, &slope) + rp * phi + phi / p;
    if (dmmf) *dmmf = s->iron_length * slope / s->iron_area + rp + 1.0 / p;
    return mmf;
}

double rb_solenoid_current(const rb_solenoid *s, double gap, double flux_linkage)
{
    return loop_mmf(s, gap, flux_linkage / s->turns, NULL) / s->turns;
}

double rb_solenoid_energy(const rb_solenoid *s, double gap, double flux_linkage)
{
    double phi = flux_linkage / s->turns, p = gap_permeance(s, gap, NULL) + s->leakage_permeance;
    return s->iron_length * s->iron_area * iron_energy_density(s, phi / s->iron_area)
           + 0.5 * parasitic_reluctance(s) * phi * phi + 0.5 * phi * phi / p;
}

double rb_solenoid_force_at_flux(const rb_solenoid *s, double gap, double flux_linkage)
{
    double dp, pg = gap_permeance(s, gap, &dp);
    double u = flux_linkage / s->turns / (pg + s->leakage_permeance);
    return -0.5 * u * u * dp;
}

rb_status rb_solenoid_eval(const rb_solenoid *s, double gap, double current, rb_solenoid_state *out,
                           rb_error *err)
{
    CHECK(rb_solenoid_check(s, err));
    CHECK(rb_check_positive(err, "gap (m)", gap));
    CHECK(rb_check_nonnegative(err, "current (A)", current));
    double ni = s->turns * current, lo = 0.0;
    /* the gap alone bounds the flux from above: mmf(phi) >= phi / P */
    double hi = ni * (gap_permeance(s, gap, NULL) + s->leakage_permeance), phi = hi;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        phi = 0.5 * (lo + hi);
        if (loop_mmf(s, gap, phi, NULL) < ni) lo = phi;
        else hi = phi;
    }
    phi = 0.5 * (lo + hi);
    double dmmf, pg = gap_permeance(s, gap, NULL);
    loop_mmf(s, gap, phi, &dmmf);
    memset(out, 0, sizeof *out);
    out->flux = phi;
    out->gap_flux = phi * pg / (pg + s->leakage_permeance);
    out->flux_linkage = s->turns * phi;
    out->incremental_inductance = s->turns * s->turns / dmmf;
    out->inductance = current > 0.0 ? out->flux_linkage / current : out->incremental_inductance;
    out->force = rb_solenoid_force_at_flux(s, gap, out->flux_linkage);
    out->energy = rb_solenoid_energy(s, gap, out->flux_linkage);
    out->coenergy = out->flux_linkage * current - out->energy;
    out->iron_flux_density = phi / s->iron_area;
    return RB_OK;
}

static rb_status check_axis(rb_error *err, const char *name, const double *v, int n, double lo)
{
    if (n < 2 || n > RB_FORCE_TABLE_MAX)
        return rb_fail(err, RB_EINVAL, "solenoid force table: %d %s values: needs 2 to %d", n, name,
                       RB_FORCE_TABLE_MAX);
    for (int k = 0; k < n; ++k)
        if (!(v[k] >= lo) || !isfinite(v[k]) || (k > 0 && !(v[k] > v[k - 1])))
            return rb_fail(err, RB_EINVAL, "solenoid force table %s[%d] = %g: must be finite, >= %g and increasing",
                           name, k, v[k], lo);
    return RB_OK;
}

rb_status rb_solenoid_force_table(const rb_solenoid *s, const double *gaps, int n_gap, const double *currents,
                                  int n_current, rb_force_table *table, rb_error *err)
{
    CHECK(rb_solenoid_check(s, err));
    CHECK(check_axis(err, "airgap", gaps, n_gap, 1e-9));
    CHECK(check_axis(err, "current", currents, n_current, 0.0));
    memset(table, 0, sizeof *table);
    table->n_gap = n_gap;
    table->n_current = n_current;
    for (int i = 0; i < n_gap; ++i) table->gap[i] = gaps[i];
    for (int j = 0; j < n_current; ++j) table->current[j] = currents[j];
    for (int i = 0; i < n_gap; ++i)
        for (int j = 0; j < n_current; ++j) {
            rb_solenoid_state st;
            CHECK(rb_solenoid_eval(s, gaps[i], currents[j], &st, err));
            table->force[i * n_current + j] = st.force;
        }
    return rb_force_table_check(table, err);
}

/* ------------------------------------------------------------------ drive */

enum { Y_LAMBDA, Y_X, Y_V, Y_ELECTRIC, Y_COPPER, Y_DAMPING, Y_N };

static double resistance(const rb_solenoid *s, double temperature_c)
{
    return s->resistance_20c * (1.0 + s->resistance_tempco * (temperature_c - 20.0));
}

static double drive_voltage(const rb_solenoid_drive *d, double t)
{
    if (d->pwm_frequency <= 0.0) return d->voltage * (d->duty > 0.0 ? 1.0 : 0.0);
    double phase = t * d->pwm_frequency - floor(t * d->pwm_frequency);
    return phase < d->duty ? d->voltage : 0.0;
}

/* x = gap_max - gap: closing travel; v = dx/dt. u is held over the step (zero-order hold). */
static void drive_rates(const rb_solenoid *s, const rb_solenoid_drive *d, double u, double r, const double *y,
                        double *dy)
{
    double gap = d->gap_max - y[Y_X];
    double i = rb_solenoid_current(s, gap, y[Y_LAMBDA]);
    double f = rb_solenoid_force_at_flux(s, gap, y[Y_LAMBDA]);
    double spring = d->spring_preload + d->spring_rate * y[Y_X];
    dy[Y_LAMBDA] = u - r * i;
    dy[Y_X] = y[Y_V];
    dy[Y_V] = (f - spring - d->load_force - d->damping * y[Y_V]) / d->mass;
    dy[Y_ELECTRIC] = u * i;
    dy[Y_COPPER] = r * i * i;
    dy[Y_DAMPING] = d->damping * y[Y_V] * y[Y_V];
}

static double mechanical_energy(const rb_solenoid_drive *d, const double *y)
{
    double x = y[Y_X];
    return 0.5 * d->mass * y[Y_V] * y[Y_V] + d->spring_preload * x + 0.5 * d->spring_rate * x * x
           + d->load_force * x;
}

static rb_status check_drive(const rb_solenoid_drive *d, rb_error *err)
{
    if (!d) return rb_fail(err, RB_EINVAL, "drive = NULL");
    CHECK(rb_check_nonnegative(err, "drive.voltage (V)", d->voltage));
    CHECK(rb_check_nonnegative(err, "drive.pwm_frequency (Hz)", d->pwm_frequency));
    CHECK(rb_check_range(err, "drive.duty", d->duty, 0.0, 1.0));
    CHECK(rb_check_range(err, "drive.temperature_c (C)", d->temperature_c, -60.0, 300.0));
    CHECK(rb_check_positive(err, "drive.mass (kg)", d->mass));
    CHECK(rb_check_nonnegative(err, "drive.spring_rate (N/m)", d->spring_rate));
    CHECK(rb_check_finite(err, "drive.spring_preload (N)", d->spring_preload));
    CHECK(rb_check_nonnegative(err, "drive.damping (N s/m)", d->damping));
    CHECK(rb_check_finite(err, "drive.load_force (N)", d->load_force));
    CHECK(rb_check_positive(err, "drive.gap_min (m)", d->gap_min));
    if (!(d->gap_max > d->gap_min))
        return rb_fail(err, RB_EINVAL, "drive.gap_max = %g m: must be above gap_min = %g m", d->gap_max, d->gap_min);
    return RB_OK;
}

static void record(const rb_solenoid *s, const rb_solenoid_drive *d, double t, double u, const double *y,
                   double impact, rb_solenoid_sample *o)
{
    double gap = d->gap_max - y[Y_X];
    o->t = t;
    o->voltage = u;
    o->current = rb_solenoid_current(s, gap, y[Y_LAMBDA]);
    o->flux_linkage = y[Y_LAMBDA];
    o->gap = gap;
    o->velocity = -y[Y_V];
    o->force = rb_solenoid_force_at_flux(s, gap, y[Y_LAMBDA]);
    o->e_electric = y[Y_ELECTRIC];
    o->e_copper = y[Y_COPPER];
    o->e_magnetic = rb_solenoid_energy(s, gap, y[Y_LAMBDA]);
    o->e_mechanical = mechanical_energy(d, y);
    o->e_damping = y[Y_DAMPING];
    o->e_impact = impact;
}

/* Clamps the armature to its stops; returns the field + mechanical energy that left with it. */
static double stop(const rb_solenoid *s, const rb_solenoid_drive *d, double *y)
{
    double travel = d->gap_max - d->gap_min, x = fmin(fmax(y[Y_X], 0.0), travel);
    if (x == y[Y_X]) return 0.0;
    double before = mechanical_energy(d, y) + rb_solenoid_energy(s, d->gap_max - y[Y_X], y[Y_LAMBDA]);
    y[Y_X] = x;
    y[Y_V] = 0.0;
    return before - mechanical_energy(d, y) - rb_solenoid_energy(s, d->gap_max - x, y[Y_LAMBDA]);
}

rb_status rb_solenoid_simulate(const rb_solenoid *s, const rb_solenoid_drive *d, double t_end, double dt,
                               rb_solenoid_sample *out, size_t n_out, rb_error *err)
{
    CHECK(rb_solenoid_check(s, err));
    CHECK(check_drive(d, err));
    CHECK(rb_check_positive(err, "t_end (s)", t_end));
    CHECK(rb_check_range(err, "dt (s)", dt, 1e-9, t_end));
    if (n_out < 2 || !out) return rb_fail(err, RB_ESIZE, "n_out = %zu: needs at least 2 samples", n_out);
    double y[Y_N] = {0}, k1[Y_N], k2[Y_N], k3[Y_N], k4[Y_N], yt[Y_N];
    double r = resistance(s, d->temperature_c), t = 0.0, impact = 0.0;
    size_t next = 0;
    long n_steps = (long)ceil(t_end / dt - 1e-9);
    double h = t_end / (double)n_steps;
    record(s, d, 0.0, drive_voltage(d, 0.0), y, 0.0, &out[next++]);
    for (long n = 1; n <= n_steps; ++n) {
        double u = drive_voltage(d, t);
        drive_rates(s, d, u, r, y, k1);
        for (int j = 0; j < Y_N; ++j) yt[j] = y[j] + 0.5 * h * k1[j];
        drive_rates(s, d, u, r, yt, k2);
        for (int j = 0; j < Y_N; ++j) yt[j] = y[j] + 0.5 * h * k2[j];
        drive_rates(s, d, u, r, yt, k3);
        for (int j = 0; j < Y_N; ++j) yt[j] = y[j] + h * k3[j];
        drive_rates(s, d, u, r, yt, k4);
        for (int j = 0; j < Y_N; ++j) y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        impact += stop(s, d, y);
        t = n * h;
        while (next < n_out && t >= t_end * (double)next / (double)(n_out - 1) - 0.5 * h)
            record(s, d, t, u, y, impact, &out[next++]);
    }
    while (next < n_out) record(s, d, t, drive_voltage(d, t), y, impact, &out[next++]);
    return RB_OK;
}

/* ------------------------------------------------------------------ thermal */

static rb_status check_thermal(const rb_solenoid *s, double current, double duty, double ambient_c,
                               double conductance, rb_error *err)
{
    CHECK(rb_solenoid_check(s, err));
    CHECK(rb_check_nonnegative(err, "current (A)", current));
    CHECK(rb_check_range(err, "duty", duty, 0.0, 1.0));
    CHECK(rb_check_range(err, "ambient_c (C)", ambient_c, -60.0, 150.0));
    return rb_check_positive(err, "thermal conductance (W/K)", conductance);
}

rb_status rb_solenoid_steady_temperature(const rb_solenoid *s, double current, double duty, double ambient_c,
                                         double conductance, double *temperature_c, rb_error *err)
{
    CHECK(check_thermal(s, current, duty, ambient_c, conductance, err));
    double q = duty * current * current * s->resistance_20c;   /* W at 20 C */
    double denominator = conductance - q * s->resistance_tempco;
    if (!(denominator > 0.0))
        return rb_fail(err, RB_EINVAL,
                       "current = %g A at duty %g: thermal runaway (the copper loss grows by %g W/K, faster "
                       "than the %g W/K the coil sheds)", current, duty, q * s->resistance_tempco, conductance);
    *temperature_c = (conductance * ambient_c + q * (1.0 - 20.0 * s->resistance_tempco)) / denominator;
    return RB_OK;
}

static double heating(const rb_solenoid *s, double q, double ambient_c, double conductance, double temp)
{
    return q * (1.0 + s->resistance_tempco * (temp - 20.0)) - conductance * (temp - ambient_c);
}

rb_status rb_solenoid_thermal_transient(const rb_solenoid *s, double current, double duty, double ambient_c,
                                        double conductance, double heat_capacity, double t_end, size_t n_steps,
                                        double *temperature_c, size_t n_out, rb_error *err)
{
    CHECK(check_thermal(s, current, duty, ambient_c, conductance, err));
    CHECK(rb_check_positive(err, "heat_capacity (J/K)", heat_capacity));
    CHECK(rb_check_positive(err, "t_end (s)", t_end));
    if (n_out < 2 || n_steps < n_out - 1)
        return rb_fail(err, RB_ESIZE, "n_out = %zu, n_steps = %zu: needs n_out >= 2 and n_steps >= n_out - 1",
                       n_out, n_steps);
    double q = duty * current * current * s->resistance_20c, h = t_end / (double)n_steps, T = ambient_c;
    size_t next = 0;
    temperature_c[next++] = T;
    for (size_t n = 1; n <= n_steps; ++n) {
        double k1 = heating(s, q, ambient_c, conductance, T) / heat_capacity;
        double k2 = heating(s, q, ambient_c, conductance, T + 0.5 * h * k1) / heat_capacity;
        double k3 = heating(s, q, ambient_c, conductance, T + 0.5 * h * k2) / heat_capacity;
        double k4 = heating(s, q, ambient_c, conductance, T + h * k3) / heat_capacity;
        T += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        while (next < n_out && (double)n * (double)(n_out - 1) >= (double)next * (double)n_steps - 1e-9)
            temperature_c[next++] = T;
    }
    while (next < n_out) temperature_c[next++] = T;
    return RB_OK;
}

size_t rb_solenoid_size(void) { return sizeof(rb_solenoid); }
size_t rb_solenoid_drive_size(void) { return sizeof(rb_solenoid_drive); }
size_t rb_solenoid_state_size(void) { return sizeof(rb_solenoid_state); }
size_t rb_solenoid_sample_size(void) { return sizeof(rb_solenoid_sample); }

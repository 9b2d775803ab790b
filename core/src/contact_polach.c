/* Polach's creep-force model (Polach, Wear 258 (2005) 992-1000). */
#include "railbrake/rb_contact.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

rb_status rb_polach_check(const rb_polach_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "params = NULL: Polach parameters are required");
    if ((s = rb_check_range(err, "mu0", p->mu0, 1e-6, 2.0))) return s;
    if ((s = rb_check_range(err, "A", p->A, 0.0, 1.0))) return s;
    if ((s = rb_check_range(err, "B", p->B, 0.0, 100.0))) return s;
    if ((s = rb_check_range(err, "kA", p->kA, 1e-6, 1.0))) return s;
    if ((s = rb_check_range(err, "kS", p->kS, 1e-6, 1.0))) return s;
    /* v_ref >= 1 m/s; 0: no rolling-speed factor */
    if ((s = rb_check_range(err, "v_ref_inv", p->v_ref_inv, 0.0, 1.0))) return s;
    return RB_OK;
}

rb_status rb_creep_contact_check(const rb_creep_contact *c, rb_error *err)
{
    rb_status s;
    if (!c) return rb_fail(err, RB_EINVAL, "contact = NULL: a contact is required");
    if ((s = rb_check_positive(err, "contact.a", c->a))) return s;
    if ((s = rb_check_positive(err, "contact.b", c->b))) return s;
    if ((s = rb_check_positive(err, "contact.c11", c->c11))) return s;
    if ((s = rb_check_positive(err, "shear_modulus", c->shear_modulus))) return s;
    return RB_OK;
}

double rb_polach_rolling_factor(double speed, double v_ref_inv)
{
    return 1.0 / (1.0 + speed * v_ref_inv);
}

/* mu0 at rolling speed `speed`: a division by exactly 1 without the factor (Polach's mu0 itself). */
static double mu0_at(const rb_polach_params *p, double speed)
{
    return p->mu0 / (1.0 + speed * p->v_ref_inv);
}

double rb_polach_coefficient_fast(double creep, double speed, double normal_force,
                                  const rb_creep_contact *c, const rb_polach_params *p)
{
    double slip_velocity = fabs(creep) * speed;
    double mu = mu0_at(p, speed) * ((1.0 - p->A) * exp(-p->B * slip_velocity) + p->A);
    /* With A = 0 the friction underflows to 0 at large slip velocity: no force (the limit), not 0/0. */
    if (!(mu > 0.0))
        return 0.0;
    /* Gradient of the tangential stress in the area of adhesion, times creep. */
    double eps = c->shear_modulus * M_PI * c->a * c->b * c->c11 / (4.0 * normal_force * mu) * fabs(creep);
    double ka_eps = p->kA * eps;
    double f = 2.0 * mu / M_PI * (ka_eps / (1.0 + ka_eps * ka_eps) + atan(p->kS * eps));
    return creep < 0.0 ? -f : f;
}

rb_status rb_polach_coefficient(const double *creep, const double *speed, size_t n,
                                double normal_force, const rb_creep_contact *c,
                                const rb_polach_params *p, double *out, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "normal_force", normal_force))) return s;
    if ((s = rb_creep_contact_check(c, err))) return s;
    if ((s = rb_polach_check(p, err))) return s;
    if (n > 0 && (!creep || !speed || !out))
        return rb_fail(err, RB_EINVAL, "creep, speed and out must not be NULL");
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(creep[i]))
            return rb_fail(err, RB_EINVAL, "creep[%zu] = %g: must be a finite number", i, creep[i]);
        if (!isfinite(speed[i]) || speed[i] < 0.0)
            return rb_fail(err, RB_EINVAL, "speed[%zu] = %g: must be finite and >= 0 (m/s)", i, speed[i]);
    }
    for (size_t i = 0; i < n; ++i)
        out[i] = rb_polach_coefficient_fast(creep[i], speed[i], normal_force, c, p);
    return RB_OK;
}

/* The maximum of F over log10(creep) in [-7, 0]: a scan of N_SCAN points, then the best bracket
 * refined by golden section; *maxima counts the scan's inner local maxima (a point above its
 * lower neighbour and not below its upper one; a rise up to creep 1 is not counted). */
enum { N_SCAN = 141 };

static void peak_search(const rb_creep_curve *f, double *peak_coefficient, double *log_creep, int *maxima)
{
    const double lo = -7.0, hi = 0.0, step = (hi - lo) / (N_SCAN - 1);
    int best = 0, count = 0;
    double best_f = -1.0, before = -1.0, last = -1.0, x[N_SCAN], scanned[N_SCAN];
    for (int i = 0; i < N_SCAN; ++i) x[i] = lo + i * step;
    if (f->at_many)
        f->at_many(f->curve, x, scanned, N_SCAN);
    else
        for (int i = 0; i < N_SCAN; ++i) scanned[i] = f->at(f->curve, x[i]);
    for (int i = 0; i < N_SCAN; ++i) {
        double fi = scanned[i];
        if (i > 1 && last > before && last >= fi) ++count;
        if (fi > best_f) { best_f = fi; best = i; }
        before = last;
        last = fi;
    }
    double x_lo = lo + (best > 0 ? best - 1 : 0) * step;
    double x_hi = lo + (best < N_SCAN - 1 ? best + 1 : N_SCAN - 1) * step;
    const double ratio = 0.6180339887498949;
    double x1 = x_hi - ratio * (x_hi - x_lo), x2 = x_lo + ratio * (x_hi - x_lo);
    double f1 = f->at(f->curve, x1), f2 = f->at(f->curve, x2);
    for (int it = 0; it < 100 && x_hi - x_lo > 1e-12; ++it) {
        if (f1 < f2) {
            x_lo = x1; x1 = x2; f1 = f2;
            x2 = x_lo + ratio * (x_hi - x_lo);
            f2 = f->at(f->curve, x2);
        } else {
            x_hi = x2; x2 = x1; f2 = f1;
            x1 = x_hi - ratio * (x_hi - x_lo);
            f1 = f->at(f->curve, x1);
        }
    }
    double x_best = 0.5 * (x_lo + x_hi);
    double f_best = f->at(f->curve, x_best);
    if (best_f > f_best) { f_best = best_f; x_best = lo + best * step; }
    *peak_coefficient = f_best;
    *log_creep = x_best;
    *maxima = count;
}

/* Polach's curve of rb_polach_coefficient_fast at one speed and load (the public searches'). */
typedef struct {
    double speed, normal_force;
    const rb_creep_contact *c;
    const rb_polach_params *p;
} polach_curve;

static double polach_at(const void *curve, double log_creep)
{
    const polach_curve *k = curve;
    return rb_polach_coefficient_fast(pow(10.0, log_creep), k->speed, k->normal_force, k->c, k->p);
}

static rb_creep_curve polach_curve_of(const polach_curve *k)
{
    const rb_polach_params *p = k->p;
    rb_creep_curve f = {polach_at, NULL, k, mu0_at(p, k->speed) * ((1.0 - p->A) * exp(-p->B * k->speed) + p->A)};
    return f;
}

rb_status rb_polach_peak(double speed, double normal_force, const rb_creep_contact *c,
                         const rb_polach_params *p, double *peak_coefficient,
                         double *peak_creep, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_nonnegative(err, "speed", speed))) return s;
    if ((s = rb_check_positive(err, "normal_force", normal_force))) return s;
    if ((s = rb_creep_contact_check(c, err))) return s;
    if ((s = rb_polach_check(p, err))) return s;
    double peak, log_creep;
    int maxima;
    polach_curve k = {speed, normal_force, c, p};
    rb_creep_curve f = polach_curve_of(&k);
    peak_search(&f, &peak, &log_creep, &maxima);
    if (peak_coefficient) *peak_coefficient = peak;
    if (peak_creep) *peak_creep = pow(10.0, log_creep);
    return RB_OK;
}

/* The peak followed from a nearby creep: Newton's method on dF/d(log10 creep) with central
 * differences, from *log_creep. Polach's F can have a second maximum at large creep, where the
 * friction levels off towards mu0 A (with kS / kA outside [0.132, 1] the creep term itself has
 * two humps), so Newton finds the maximum of its own branch only; the full creep 1 is compared
 * too, unless the bound F <= mu (1 + 1/pi) (the creep term is below 1/2 + pi/2) rules it out.
 * A caller that follows the peak over a run re-scans now and then, and always where the scan saw
 * more than one maximum (run.c). A Newton step that leaves the neighbourhood or a convex point:
 * the full scan. */
#define TRACK_H 1e-4          /* decades: the differences' step */
#define TRACK_TOLERANCE 2e-3  /* decades: Newton stops after a move below this (the next would be ~1e-5, F exact to ~1e-9) */
#define TRACK_MAX_MOVE 0.1    /* decades: a longer Newton step is no longer local */

double rb_creep_peak_scan(const rb_creep_curve *f, double *log_creep, int *maxima)
{
    double peak;
    peak_search(f, &peak, log_creep, maxima);
    return peak;
}

/* One round of evaluations of the batch below: curve member[j] at x[j] into f[j], all in one call
 * of at_each where the caller gives one (NULL: each curve's own at). */
static void evaluate(const rb_creep_curve *curves, rb_creep_at_each at_each, const int *member, const double *x,
                     double *f, int k)
{
    if (at_each) {
        at_each(curves, member, x, f, k);
        return;
    }
    for (int j = 0; j < k; ++j) f[j] = curves[member[j]].at(curves[member[j]].curve, x[j]);
}

enum { TRACKING, TRACKED, SCAN };   /* a curve's state in the batch */

/* Newton's method on up to RB_CREEP_BATCH curves side by side: rb_creep_peak_track's steps, each
 * round's evaluations of all the curves still moving in one call (their points; the differences
 * either side; the Newton points), then the full-slip check; *state SCAN where the full scan is
 * needed. */
static void newton_batch(const rb_creep_curve *curves, int n, rb_creep_at_each at_each, double *x, double *fx,
                         int *state)
{
    int member[2 * RB_CREEP_BATCH], k = 0;
    double px[2 * RB_CREEP_BATCH], pf[2 * RB_CREEP_BATCH], move[RB_CREEP_BATCH];
    for (int i = 0; i < n; ++i) {
        move[i] = HUGE_VAL;
        state[i] = x[i] > -7.0 + TRACK_MAX_MOVE && x[i] < -TRACK_MAX_MOVE ? TRACKING : SCAN;   /* NaN, or near an end */
        if (state[i] == TRACKING) { member[k] = i; px[k++] = x[i]; }
    }
    evaluate(curves, at_each, member, px, pf, k);
    for (int j = 0; j < k; ++j) fx[member[j]] = pf[j];
    for (int it = 0; it < 8; ++it) {
        k = 0;
        for (int i = 0; i < n; ++i)
            if (state[i] == TRACKING && fabs(move[i]) >= TRACK_TOLERANCE) {
                member[k] = member[k + 1] = i;
                px[k] = x[i] - TRACK_H;
                px[k + 1] = x[i] + TRACK_H;
                k += 2;
            }
        if (k == 0) break;
        evaluate(curves, at_each, member, px, pf, k);
        int m = 0;   /* the curves with a Newton point, in member[0..m) */
        for (int j = 0; j < k; j += 2) {
            const int i = member[j];
            double fl = pf[j], fr = pf[j + 1], curvature = fl - 2.0 * fx[i] + fr;
            move[i] = curvature < 0.0 ? -0.5 * TRACK_H * (fr - fl) / curvature : HUGE_VAL;
            if (!(fabs(move[i]) <= TRACK_MAX_MOVE && x[i] + move[i] > -7.0 && x[i] + move[i] < 0.0)) {
                state[i] = SCAN;
                continue;
            }
            member[m] = i;
            px[m++] = x[i] + move[i];
        }
        evaluate(curves, at_each, member, px, pf, m);
        for (int j = 0; j < m; ++j) {
            const int i = member[j];
            if (pf[j] < fx[i]) { state[i] = TRACKED; continue; }   /* converged to rounding: keep the better point */
            x[i] += move[i];
            fx[i] = pf[j];
        }
    }
    /* could full slip (creep 1) beat the peak? F <= mu (1/2 + pi/2) 2 / pi everywhere */
    k = 0;
    for (int i = 0; i < n; ++i)
        if (state[i] != SCAN && curves[i].mu_full_slip * (1.0 + 1.0 / M_PI) > fx[i]) { member[k] = i; px[k++] = 0.0; }
    evaluate(curves, at_each, member, px, pf, k);
    for (int j = 0; j < k; ++j)
        if (pf[j] > fx[member[j]]) state[member[j]] = SCAN;
}

void rb_creep_peaks_track(const rb_creep_curve *curves, int n, rb_creep_at_each at_each, double *log_creep,
                          double *peak)
{
    for (int first = 0; first < n; first += RB_CREEP_BATCH) {
        int count = n - first < RB_CREEP_BATCH ? n - first : RB_CREEP_BATCH, state[RB_CREEP_BATCH], maxima;
        double *x = log_creep + first, fx[RB_CREEP_BATCH];
        newton_batch(curves + first, count, at_each, x, fx, state);
        for (int i = 0; i < count; ++i)
            peak[first + i] = state[i] == SCAN ? rb_creep_peak_scan(&curves[first + i], &x[i], &maxima) : fx[i];
    }
}

double rb_creep_peak_track(const rb_creep_curve *f, double *log_creep)
{
    double peak;
    rb_creep_peaks_track(f, 1, NULL, log_creep, &peak);
    return peak;
}

double rb_polach_peak_scan(double speed, double normal_force, const rb_creep_contact *c,
                           const rb_polach_params *p, double *log_creep, int *maxima)
{
    polach_curve k = {speed, normal_force, c, p};
    rb_creep_curve f = polach_curve_of(&k);
    return rb_creep_peak_scan(&f, log_creep, maxima);
}

double rb_polach_peak_track(double speed, double normal_force, const rb_creep_contact *c,
                            const rb_polach_params *p, double *log_creep)
{
    polach_curve k = {speed, normal_force, c, p};
    rb_creep_curve f = polach_curve_of(&k);
    return rb_creep_peak_track(&f, log_creep);
}

double rb_conditioning_factor(double axle, double leading_factor, double recovery_axles)
{
    if (!(recovery_axles > 0.0)) return 1.0;
    return 1.0 - (1.0 - leading_factor) * exp(-axle / recovery_axles);
}

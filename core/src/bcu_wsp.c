/* Default wheel-slide protection: structure after EN 15595 (Railway applications - Braking - Wheel
 * slide protection) and UIC 541-05; thresholds are typical values [T] (docs/references.md). */
#include "railbrake/rb_bcu.h"
#include "wsp_internal.h"

#include <string.h>

void rb_wsp_default_params(rb_wsp_params *p)
{
    p->ref_decel_max = 1.6;       /* above the emergency deceleration */
    p->ref_accel_max = 0.5;
    /* Below the typical 2-5 km/h + a few % and 3-4 m/s^2 [T]: on wet rail the adhesion peak lies
     * at a slip velocity of about 0.25 m/s (railbrake.adhesion heavy-rain), beyond which it falls. */
    p->speed_threshold = 0.4;         /* m/s ... */
    p->slip_threshold = 0.005;        /* ... plus 0.5 % */
    p->decel_threshold = 2.5;         /* m/s^2 */
    p->reaccel_threshold = 0.3;
    p->release_fraction = 0.5;
    p->reapply_on = 0.02;
    p->reapply_off = 0.1;
    p->reapply_time = 1.5;
    p->filter_time = 0.02;
    p->safety_time = 5.0;             /* 5-10 s [T] */
    p->min_speed = 1.5;
    rb_wsp_setpoint_defaults(p);
    rb_wsp_decel_slip_defaults(p);
    p->conditioning_mode = 0;
    /* The trailing axle of a bogie slides at 3 times the leading one's criterion: from the micro-slip
     * of the set-point's default into the macro slip past the wet peak, where the energy dissipated
     * cleans the rail (contact_conditioning.c). No published ratio was found: typical [T], exposed
     * (scenario wsp.conditioning_ratio). */
    p->conditioning_ratio = 3.0;
}

void rb_wsp_default_reset(rb_wsp_default *w, const rb_wsp_params *p)
{
    memset(w, 0, sizeof *w);
    w->p = *p;
}

void rb_wsp_update_reference(rb_wsp_default *w, const rb_wsp_inputs *in, double fall)
{
    double fastest = -1.0;
    for (int a = 0; a < in->n_axles; ++a)
        if (in->wheel_speed[a] > fastest) fastest = in->wheel_speed[a];
    if (fastest < 0.0) return;
    if (!w->initialised) {
        w->reference = fastest;
        for (int a = 0; a < in->n_axles; ++a) w->last_speed[a] = in->wheel_speed[a];
        w->initialised = 1;
        return;
    }
    double lo = w->reference - fall * in->cycle, hi = w->reference + w->p.ref_accel_max * in->cycle;
    w->reference = fastest < lo ? lo : (fastest > hi ? hi : fastest);
    if (w->reference < 0.0) w->reference = 0.0;
}

double rb_wsp_estimate_fall(const rb_wsp_params *p, const rb_wsp_inputs *in)
{
    if (in->body_decel != in->body_decel) return p->ref_decel_max;   /* NaN: no accelerometer */
    return (in->body_decel > 0.0 ? in->body_decel : 0.0) + p->ref_decel_margin;
}

/* A cylinder far below its demand with no WSP command: a vent valve open on its own. */
int rb_wsp_stuck_vent_suspected(const rb_wsp_inputs *in, int a)
{
    double demand = in->demand[a] - in->atmosphere, cylinder = in->cylinder[a] - in->atmosphere;
    return demand > 0.5e5 && cylinder < 0.4 * demand;
}

static int next_mode(rb_wsp_default *w, int a, double dv, double threshold, double dt)
{
    const rb_wsp_params *p = &w->p;
    double accel = w->accel[a];
    int sliding = dv > threshold || -accel > rb_wsp_conditioned(p, a, p->decel_threshold);
    switch (w->mode[a]) {
    case RB_WSP_APPLY: return sliding ? RB_WSP_VENT : RB_WSP_APPLY;
    case RB_WSP_VENT:
        return accel > p->reaccel_threshold || dv < p->release_fraction * threshold ? RB_WSP_HOLD : RB_WSP_VENT;
    case RB_WSP_HOLD:
        if (dv < p->release_fraction * threshold) { w->reapply_clock[a] = 0.0; return RB_WSP_REAPPLY; }
        return sliding && accel < 0.0 ? RB_WSP_VENT : RB_WSP_HOLD;
    case RB_WSP_REAPPLY:
        if (sliding) return RB_WSP_VENT;
        w->reapply_clock[a] += dt;
        return w->reapply_clock[a] > p->reapply_time ? RB_WSP_APPLY : RB_WSP_REAPPLY;
    default: return w->mode[a];
    }
}

int rb_wsp_reapply_holds(const rb_wsp_default *w, int a)
{
    double period = w->p.reapply_on + w->p.reapply_off;
    double phase = w->reapply_clock[a] - period * (double)(long)(w->reapply_clock[a] / period);
    return phase >= w->p.reapply_on;
}

void rb_wsp_mode_commands(const rb_wsp_default *w, rb_wsp_commands *out, int a)
{
    int mode = w->mode[a];
    out->hold[a] = mode == RB_WSP_VENT || mode == RB_WSP_HOLD || (mode == RB_WSP_REAPPLY && rb_wsp_reapply_holds(w, a));
    out->vent[a] = mode == RB_WSP_VENT;
    out->active[a] = mode != RB_WSP_APPLY;
}

double rb_wsp_conditioned(const rb_wsp_params *p, int a, double criterion)
{
    /* axles 0, 1 and 2, 3 of a car are its two bogies', the first of each leading */
    return p->conditioning_mode && a % 2 == 1 ? criterion * p->conditioning_ratio : criterion;
}

int rb_wsp_axle_guard(rb_wsp_default *w, const rb_wsp_inputs *in, rb_wsp_commands *out, int a, double dt)
{
    const rb_wsp_params *p = &w->p;
    double v = in->wheel_speed[a];
    out->hold[a] = out->vent[a] = out->active[a] = 0;
    if (w->mode[a] == RB_WSP_ISOLATED) { out->hold[a] = 1; return 0; }
    if (v < 0.0) { w->mode[a] = RB_WSP_APPLY; return 0; }   /* sensor lost: no WSP on this axle */
    w->accel[a] += ((v - w->last_speed[a]) / dt - w->accel[a]) * dt / (p->filter_time + dt);
    w->last_speed[a] = v;
    w->low_time[a] = w->mode[a] == RB_WSP_APPLY && rb_wsp_stuck_vent_suspected(in, a) ? w->low_time[a] + dt : 0.0;
    if (w->low_time[a] > p->safety_time) {   /* isolate the axle: save the car's air */
        w->mode[a] = RB_WSP_ISOLATED;
        w->trips++;
        out->hold[a] = 1;
        return 0;
    }
    return w->mode[a] != RB_WSP_INHIBITED;
}

int rb_wsp_safety_trip(rb_wsp_default *w, int a, double dt)
{
    w->vent_time[a] = w->mode[a] == RB_WSP_VENT ? w->vent_time[a] + dt : 0.0;
    if (w->vent_time[a] > w->p.safety_time) {   /* a failed WSP must not remove the brake */
        w->mode[a] = RB_WSP_INHIBITED;
        w->trips++;
        return 1;
    }
    return 0;
}

void rb_wsp_default_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out)
{
    rb_wsp_default *w = (rb_wsp_default *)context;
    const rb_wsp_params *p = &w->p;
    if (p->controller == RB_WSP_SLIP_SETPOINT) {
        rb_wsp_setpoint_step(context, in, out);
        return;
    }
    if (p->controller == RB_WSP_DECEL_SLIP_SPEED) {
        rb_wsp_decel_slip_step(context, in, out);
        return;
    }
    rb_wsp_update_reference(w, in, p->ref_decel_max);
    double dt = in->cycle > 0.0 ? in->cycle : 1e-3;
    for (int a = 0; a < in->n_axles; ++a) {
        if (!rb_wsp_axle_guard(w, in, out, a, dt)) continue;
        double threshold = rb_wsp_conditioned(p, a, p->speed_threshold + p->slip_threshold * w->reference);
        w->mode[a] = w->reference < p->min_speed ? RB_WSP_APPLY
                                                  : next_mode(w, a, w->reference - in->wheel_speed[a], threshold, dt);
        if (rb_wsp_safety_trip(w, a, dt)) continue;
        rb_wsp_mode_commands(w, out, a);
    }
}

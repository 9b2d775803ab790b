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

/* Default wheel-slide protection (shared/reference/README.md, section 5). */
#include "railbrake/rb_bcu.h"

#include <string.h>

void rb_wsp_default_params(rb_wsp_params *p)
{
    p->ref_decel_max = 1.6;       /* above the emergency deceleration */
    p->ref_accel_max = 0.5;
    p->speed_threshold = 2.0 / 3.6;   /* 2 km/h ... */
    p->slip_threshold = 0.02;         /* ... plus 2 % [T] */
    p->decel_threshold = 3.5;         /* m/s^2 [T] */
    p->reaccel_threshold = 0.3;
    p->release_fraction = 0.5;
    p->filter_time = 0.02;
    p->safety_time = 5.0;             /* 5-10 s [T] */
    p->min_speed = 1.5;
}

void rb_wsp_default_reset(rb_wsp_default *w, const rb_wsp_params *p)
{
    memset(w, 0, sizeof *w);
    w->p = *p;
}

static void update_reference(rb_wsp_default *w, const rb_wsp_inputs *in)
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
    double lo = w->reference - w->p.ref_decel_max * in->cycle, hi = w->reference + w->p.ref_accel_max * in->cycle;
    w->reference = fastest < lo ? lo : (fastest > hi ? hi : fastest);
    if (w->reference < 0.0) w->reference = 0.0;
}

/* A cylinder far below its demand with no WSP command: a vent valve open on its own. */
static int stuck_vent_suspected(const rb_wsp_inputs *in, int a)
{
    double demand = in->demand[a] - in->atmosphere, cylinder = in->cylinder[a] - in->atmosphere;
    return demand > 0.5e5 && cylinder < 0.3 * demand;
}

static int next_mode(const rb_wsp_default *w, int mode, double dv, double threshold, double accel)
{
    const rb_wsp_params *p = &w->p;
    int sliding = dv > threshold || -accel > p->decel_threshold;
    switch (mode) {
    case RB_WSP_APPLY: return sliding ? RB_WSP_VENT : RB_WSP_APPLY;
    case RB_WSP_VENT: return accel > p->reaccel_threshold || dv < p->release_fraction * threshold ? RB_WSP_HOLD : RB_WSP_VENT;
    case RB_WSP_HOLD:
        if (dv < p->release_fraction * threshold) return RB_WSP_APPLY;
        return sliding && accel < 0.0 ? RB_WSP_VENT : RB_WSP_HOLD;
    default: return mode;
    }
}

void rb_wsp_default_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out)
{
    rb_wsp_default *w = (rb_wsp_default *)context;
    const rb_wsp_params *p = &w->p;
    update_reference(w, in);
    double dt = in->cycle > 0.0 ? in->cycle : 1e-3;
    for (int a = 0; a < in->n_axles; ++a) {
        double v = in->wheel_speed[a];
        out->hold[a] = out->vent[a] = out->active[a] = 0;
        if (w->mode[a] == RB_WSP_ISOLATED) { out->hold[a] = 1; continue; }
        if (v < 0.0) { w->mode[a] = RB_WSP_APPLY; continue; }   /* sensor lost: no WSP on this axle */
        w->accel[a] += ((v - w->last_speed[a]) / dt - w->accel[a]) * dt / (p->filter_time + dt);
        w->last_speed[a] = v;
        w->low_time[a] = w->mode[a] == RB_WSP_APPLY && stuck_vent_suspected(in, a) ? w->low_time[a] + dt : 0.0;
        if (w->low_time[a] > p->safety_time) {   /* isolate the axle: save the car's air */
            w->mode[a] = RB_WSP_ISOLATED;
            w->trips++;
            out->hold[a] = 1;
            continue;
        }
        if (w->mode[a] == RB_WSP_INHIBITED) continue;
        double threshold = p->speed_threshold + p->slip_threshold * w->reference;
        w->mode[a] = w->reference < p->min_speed ? RB_WSP_APPLY
                     : next_mode(w, w->mode[a], w->reference - v, threshold, w->accel[a]);
        w->vent_time[a] = w->mode[a] == RB_WSP_VENT ? w->vent_time[a] + dt : 0.0;
        if (w->vent_time[a] > p->safety_time) {   /* a failed WSP must not remove the brake */
            w->mode[a] = RB_WSP_INHIBITED;
            w->trips++;
            continue;
        }
        out->hold[a] = w->mode[a] == RB_WSP_VENT || w->mode[a] == RB_WSP_HOLD;
        out->vent[a] = w->mode[a] == RB_WSP_VENT;
        out->active[a] = out->hold[a];
    }
}

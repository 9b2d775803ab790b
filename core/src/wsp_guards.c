/* The WSP controllers' shared guards (wsp_internal.h): the vehicle-speed reference, the axle's
 * guard at the start of a cycle, the safety timer, the valve commands of a mode. Below every
 * controller (bcu_wsp.c's threshold one, wsp_controllers.c, wsp_decel_slip.c): they call these,
 * these call none of them. Structure after EN 15595 and UIC 541-05 (docs/references.md). */
#include "railbrake/rb_bcu.h"
#include "wsp_internal.h"

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

int rb_wsp_stuck_vent_suspected(const rb_wsp_inputs *in, int a)
{
    double demand = in->demand[a] - in->atmosphere, cylinder = in->cylinder[a] - in->atmosphere;
    return demand > 0.5e5 && cylinder < 0.4 * demand;
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

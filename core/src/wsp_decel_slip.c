/* Deceleration and slip-speed WSP (RB_WSP_DECEL_SLIP_SPEED), behind the WSP interface of rb_bcu.h
 * (rb_wsp_default_step hands over to it). The classic structure of wheel-slide and anti-lock
 * controllers: a vehicle-speed estimate from the axles, and per axle two signals, the slip speed
 * dv = reference - wheel speed and the wheel's deceleration, each against a threshold.
 *
 * Vehicle speed: the fastest measured axle, falling at most at the body's measured deceleration
 * plus ref_decel_margin, or at ref_decel_max without an accelerometer (rb_wsp_estimate_fall, as
 * the set-point controller's). Per axle, S = ds_speed_threshold + ds_slip_threshold x reference
 * (in the conditioning mode the trailing axle of a bogie has S and ds_decel_threshold x
 * conditioning_ratio):
 * - a slide, dv > S or a deceleration above ds_decel_threshold, vents (either criterion: asking
 *   for both let a wheel that slides slowly lock, its deceleration staying small);
 * - venting stops (HOLD) when the wheel re-accelerates, or when its cylinder is down to a tenth of
 *   the demand (nothing more to let out);
 * - the hold band: the pressure is held while dv > S x release_fraction, unless the wheel slides
 *   again without re-accelerating (vent);
 * - re-application on the wheel's re-acceleration: above ds_reaccel_threshold the hold valve opens
 *   at once (the wheel has found adhesion again); below it, once dv is under the band, the
 *   pressure climbs back in the hold valve's pulses (reapply_on, reapply_off) for reapply_time.
 * Shared with the other controllers: the guard (a lost sensor leaves its axle braked as demanded,
 * a cylinder vented without command for safety_time isolates the axle) and the safety timer
 * (commanded venting longer than safety_time inhibits WSP on the axle), wsp_internal.h.
 * Structure after the slide-protection cycle of EN 15595 and UIC 541-05 and the anti-lock
 * control cycle of road vehicles (a deceleration and a slip threshold, re-application on the
 * wheel's re-acceleration; Bosch Automotive Handbook); values typical [T]. */
#include "wsp_internal.h"

void rb_wsp_decel_slip_defaults(rb_wsp_params *p)
{
    /* Below the typical 2-5 km/h plus a few per cent and 3-4 m/s^2 [T], as the threshold
       controller's: on wet rail at high speed the adhesion peaks at slip speeds of 0.04 to 0.13 m/s
       (railbrake.adhesion hs-wet) and falls beyond, so a slide is caught early. The deceleration
       threshold stays 0.6 m/s^2 above the 1.4 m/s^2 of a wheel rolling in an emergency stop (no
       valve moves on dry rail); with 2.5 m/s^2 wheels sliding together on leaves vented past the
       safety time and locked (their slip speed against the reference they drag down stays small,
       only the deceleration catches them). Values chosen on the hs-wet,
       heavy-rain, leaves and oil-film emergency stops from 300 km/h [T]. */
    p->ds_speed_threshold = 0.3;     /* m/s ... */
    p->ds_slip_threshold = 0.003;    /* ... plus 0.3 % of the reference speed */
    p->ds_decel_threshold = 2.0;     /* m/s^2 */
    p->ds_reaccel_threshold = 0.5;   /* m/s^2: the wheel has found adhesion again */
}

/* A cylinder vented to a tenth of its demand (gauge): venting on lets out nothing more. */
static int vented(const rb_wsp_inputs *in, int a)
{
    return in->cylinder[a] - in->atmosphere < 0.1 * (in->demand[a] - in->atmosphere);
}

/* The next mode of axle a, dv its slip speed. */
static int next_mode(rb_wsp_default *w, const rb_wsp_inputs *in, int a, double dv, double dt)
{
    const rb_wsp_params *p = &w->p;
    double limit = rb_wsp_conditioned(p, a, p->ds_speed_threshold + p->ds_slip_threshold * w->reference);
    double accel = w->accel[a];
    int slide = dv > limit || -accel > rb_wsp_conditioned(p, a, p->ds_decel_threshold);
    switch (w->mode[a]) {
    case RB_WSP_APPLY:
        return slide ? RB_WSP_VENT : RB_WSP_APPLY;
    case RB_WSP_VENT:   /* until the wheel re-accelerates (or nothing is left to vent) */
        return accel > 0.0 || vented(in, a) ? RB_WSP_HOLD : RB_WSP_VENT;
    case RB_WSP_HOLD:   /* the hold band */
        if (slide && accel <= 0.0) return RB_WSP_VENT;
        if (accel <= p->ds_reaccel_threshold && dv >= p->release_fraction * limit) return RB_WSP_HOLD;
        w->reapply_clock[a] = 0.0;
        return RB_WSP_REAPPLY;
    case RB_WSP_REAPPLY:
        if (slide && accel <= 0.0) return RB_WSP_VENT;
        w->reapply_clock[a] += dt;
        return w->reapply_clock[a] > p->reapply_time ? RB_WSP_APPLY : RB_WSP_REAPPLY;
    default:
        return w->mode[a];
    }
}

void rb_wsp_decel_slip_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out)
{
    rb_wsp_default *w = (rb_wsp_default *)context;
    const rb_wsp_params *p = &w->p;
    double dt = in->cycle > 0.0 ? in->cycle : 1e-3;
    rb_wsp_update_reference(w, in, rb_wsp_estimate_fall(p, in));
    for (int a = 0; a < in->n_axles; ++a) {
        if (!rb_wsp_axle_guard(w, in, out, a, dt)) continue;
        double dv = w->reference - in->wheel_speed[a];
        w->mode[a] = w->reference < p->min_speed ? RB_WSP_APPLY
                                                  : next_mode(w, in, a, dv, dt);
        if (rb_wsp_safety_trip(w, a, dt)) continue;
        rb_wsp_mode_commands(w, out, a);
        if (w->mode[a] == RB_WSP_REAPPLY && w->accel[a] > p->ds_reaccel_threshold) out->hold[a] = 0;
    }
}

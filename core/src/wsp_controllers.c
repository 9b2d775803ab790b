/* The slip set-point WSP (RB_WSP_SLIP_SETPOINT), one of the controllers behind the same interface
 * (rb_wsp_function, rb_wsp_default state, rb_wsp_params.controller selects; the threshold state
 * machine is in bcu_wsp.c, the deceleration and slip-speed controller in wsp_decel_slip.c): the
 * BCU (run, studies, `wsp tune`, the reference BCU for HIL, the FMU) calls rb_wsp_default_step,
 * which hands over to the controller chosen. Every controller shares the guard (lost sensor: the
 * axle braked as demanded; a cylinder vented without command for safety_time: the axle isolated)
 * and the safety timer (commanded venting longer than safety_time: WSP inhibited on the axle),
 * wsp_internal.h.
 *
 * Vehicle speed: the fastest wheel, falling at most at the body's measured deceleration plus
 * ref_decel_margin (rb_wsp_estimate_fall). Each axle's slip velocity dv = reference - wheel speed
 * is held about the set-point s* = setpoint_speed + setpoint_slip x reference (the trailing axle
 * of a bogie s* x conditioning_ratio in the conditioning mode), predicted lead_time ahead from its
 * rate (the reference's rate less the wheel's filtered acceleration) to cover the valves'
 * response: above s* (1 + band) vent, within +-band hold, below s* (1 - band) apply. It engages
 * on an axle when the threshold controller's detection fires (speed difference above
 * speed_threshold + slip_threshold x reference, or wheel deceleration above decel_threshold) and
 * lets go after setpoint_release braked as demanded: on good adhesion, where the micro-slip of
 * braking may exceed s* at high speed, no valve moves. Below the band it re-applies with a
 * pressure memory, as WSPs do to spare the air: quickly up to setpoint_memory x the cylinder
 * pressure at which the axle last had to vent, then it holds while that ceiling rises at
 * setpoint_ramp, so that the pressure creeps back to the adhesion limit instead of overshooting
 * it at every cycle (re-applying to the demand at once, each cycle vented about 0.5 bar and the
 * main reservoir of an 8-car train fell from 8.5 to 3.2 bar on hs-wet from 300 km/h). A small s* works in the micro-slip range
 * before the adhesion peak, a larger one in the macro-slip range past it (where a sliding wheel
 * conditions the rail). Structure after the slip-control WSPs described in EN 15595 (WSP
 * performance assessed on deceleration-distance increase and adhesion utilisation) and the
 * slip-velocity control of high-speed train WSPs; the values are typical [T]: no published
 * set-point for a particular WSP was found; exposed (scenario wsp.*). */
#include "wsp_internal.h"

void rb_wsp_setpoint_defaults(rb_wsp_params *p)
{
    p->controller = RB_WSP_THRESHOLD;
    /* Wet rail at high speed (hs-wet, Polach B = 17 s/m) peaks at slip velocities growing with
       speed, 0.042 m/s at 20 km/h to 0.128 m/s at 300 km/h: the set-point is the chord of that
       curve through both ends, so it lies on or below the peak (its stable side) in between.
       A constant set-point (0.07 m/s before) sat at 69 % of the peak adhesion at 300 km/h and past
       the peak below 60 km/h. [T]: no published set-point of a particular WSP was found; exposed
       (scenario wsp.*). */
    p->setpoint_speed = 0.036;   /* m/s ... */
    p->setpoint_slip = 0.0011;   /* ... plus this fraction of the reference speed */
    /* Band, lead time and the estimate's margin chosen on the hs-wet emergency stops from 300 km/h
       of 4 to 16 cars [T] (docs/simulation.md): a narrow band keeps the slip at the
       peak, the lead time covers the valves' delay and the cylinder's first fall, a small margin
       keeps the speed estimate from sinking below the train (the slip is then underestimated) */
    p->setpoint_band = 0.1;
    p->lead_time = 0.15;         /* s */
    p->ref_decel_margin = 0.03;  /* m/s^2 */
    p->setpoint_release = 6.0;   /* s [T]: a short release lets the axle slide to the detection
                                    threshold again, far past the wet peak (1.5 s cost 1 to 3 points
                                    of utilisation on hs-wet) */
    /* Pressure memory [T], chosen on the hs-wet emergency stops from 300 km/h of velaro-8 and
       crh380al-16 for utilisation and air together: 0.87 of the pressure that slid and a
       0.2 bar/s rise re-apply close to the adhesion limit (0.95 or a 1 bar/s rise vented as much
       as re-applying to the demand; 0.8 gave up 4 points of utilisation). No published value of
       a particular WSP was found; exposed (scenario wsp.setpoint_memory, wsp.setpoint_ramp). */
    p->setpoint_memory = 0.87;
    p->setpoint_ramp = 0.2e5;    /* Pa/s */
}

/* Engaged on a detected slide (the threshold controller's criteria), released after
 * setpoint_release braked as demanded (reapply_clock counts it). */
static int engaged(rb_wsp_default *w, int a, double dv, double dt)
{
    const rb_wsp_params *p = &w->p;
    if (!w->engaged[a]) {
        w->engaged[a] = dv > p->speed_threshold + p->slip_threshold * w->reference || -w->accel[a] > p->decel_threshold;
        w->reapply_clock[a] = 0.0;
        return w->engaged[a];
    }
    w->reapply_clock[a] = w->mode[a] == RB_WSP_APPLY ? w->reapply_clock[a] + dt : 0.0;
    if (w->reapply_clock[a] > p->setpoint_release) w->engaged[a] = 0;
    return w->engaged[a];
}

static int setpoint_mode(const rb_wsp_params *p, int a, double reference, double predicted)
{
    double setpoint = rb_wsp_conditioned(p, a, p->setpoint_speed + p->setpoint_slip * reference);
    if (reference < p->min_speed) return RB_WSP_APPLY;
    if (predicted > setpoint * (1.0 + p->setpoint_band)) return RB_WSP_VENT;
    if (predicted > setpoint * (1.0 - p->setpoint_band)) return RB_WSP_HOLD;
    return RB_WSP_APPLY;
}

/* The pressure memory of axle a after its mode was chosen: the cylinder when it begins to vent;
 * below the band (APPLY) the ceiling rises at setpoint_ramp and the brake holds above it; an axle
 * not engaged remembers its demand. */
static void remember(rb_wsp_default *w, const rb_wsp_inputs *in, int a, int last, double dt)
{
    const rb_wsp_params *p = &w->p;
    if (!w->engaged[a]) {
        w->memory[a] = in->demand[a];
        return;
    }
    if (w->mode[a] == RB_WSP_VENT && last != RB_WSP_VENT) w->memory[a] = in->cylinder[a];
    if (w->mode[a] != RB_WSP_APPLY) return;
    w->memory[a] += p->setpoint_ramp * dt;
    if (in->cylinder[a] - in->atmosphere > p->setpoint_memory * (w->memory[a] - in->atmosphere))
        w->mode[a] = RB_WSP_HOLD;
}

void rb_wsp_setpoint_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out)
{
    rb_wsp_default *w = (rb_wsp_default *)context;
    const rb_wsp_params *p = &w->p;
    double dt = in->cycle > 0.0 ? in->cycle : 1e-3;
    int first = !w->initialised;
    double before = w->reference;
    rb_wsp_update_reference(w, in, rb_wsp_estimate_fall(p, in));
    double reference_rate = first ? 0.0 : (w->reference - before) / dt;
    for (int a = 0; a < in->n_axles; ++a) {
        if (!rb_wsp_axle_guard(w, in, out, a, dt)) continue;
        double dv = w->reference - in->wheel_speed[a];
        double predicted = dv + (reference_rate - w->accel[a]) * p->lead_time;
        int last = w->mode[a];
        w->mode[a] = engaged(w, a, dv, dt) ? setpoint_mode(p, a, w->reference, predicted) : RB_WSP_APPLY;
        remember(w, in, a, last, dt);
        if (rb_wsp_safety_trip(w, a, dt)) continue;
        rb_wsp_mode_commands(w, out, a);
    }
}

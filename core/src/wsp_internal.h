/* Private to the WSP controllers (bcu_wsp.c, wsp_controllers.c, wsp_decel_slip.c): what they share,
 * defined in wsp_guards.c below them all (the defaults and steps in the controllers' own files). */
#ifndef RAILBRAKE_WSP_INTERNAL_H
#define RAILBRAKE_WSP_INTERNAL_H

#include "railbrake/rb_bcu.h"

/* Reference (vehicle) speed from the fastest measured axle, falling at most at `fall` (m/s^2) and
 * rising at most at ref_accel_max. */
void rb_wsp_update_reference(rb_wsp_default *w, const rb_wsp_inputs *in, double fall);
/* The fall (m/s^2) of the set-point and slip-speed controllers' vehicle-speed estimate: the body's
 * measured deceleration plus ref_decel_margin, so that wheels sliding together do not drag the
 * estimate down with them; ref_decel_max without an accelerometer (body_decel NaN). */
double rb_wsp_estimate_fall(const rb_wsp_params *p, const rb_wsp_inputs *in);
/* A cylinder far below its demand with no WSP command: a vent valve open on its own. */
int rb_wsp_stuck_vent_suspected(const rb_wsp_inputs *in, int a);
/* Every controller's guard of axle a at the start of its cycle: commands cleared; an isolated axle
 * held, a lost sensor leaves the axle braked as demanded, the wheel acceleration filtered, a
 * cylinder vented without command for the safety time isolates the axle. 1: the controller
 * decides this axle's mode; 0: it must not (isolated, sensor lost, inhibited). */
int rb_wsp_axle_guard(rb_wsp_default *w, const rb_wsp_inputs *in, rb_wsp_commands *out, int a, double dt);
/* The safety timer after the controller set the mode: venting longer than safety_time inhibits
 * WSP on the axle (braked as demanded); 1 when it tripped now. */
int rb_wsp_safety_trip(rb_wsp_default *w, int a, double dt);
/* The hold valve closed in the off part of a re-apply pulse (reapply_on open, reapply_off closed),
 * timed by reapply_clock[a]. */
int rb_wsp_reapply_holds(const rb_wsp_default *w, int a);
/* The valve commands of axle a's mode (VENT: hold and vent; HOLD: hold; REAPPLY: the pulses of
 * rb_wsp_reapply_holds; active whenever the axle is not braked as demanded). */
void rb_wsp_mode_commands(const rb_wsp_default *w, rb_wsp_commands *out, int a);
/* A slide criterion of axle a (a slip speed, a deceleration) in the conditioning mode: the trailing
 * axle of each bogie gets `criterion` x conditioning_ratio; the leading one, and every axle with the
 * mode off, `criterion` itself. */
double rb_wsp_conditioned(const rb_wsp_params *p, int a, double criterion);
/* The controllers' defaults (in rb_wsp_default_params). */
void rb_wsp_setpoint_defaults(rb_wsp_params *p);
void rb_wsp_decel_slip_defaults(rb_wsp_params *p);

#endif

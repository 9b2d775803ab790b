/* Private to the WSP controllers (bcu_wsp.c, wsp_controllers.c): what they share. */
#ifndef RAILBRAKE_WSP_INTERNAL_H
#define RAILBRAKE_WSP_INTERNAL_H

#include "railbrake/rb_bcu.h"

/* Reference (vehicle) speed from the fastest measured axle, falling at most at `fall` (m/s^2) and
 * rising at most at ref_accel_max. */
void rb_wsp_update_reference(rb_wsp_default *w, const rb_wsp_inputs *in, double fall);
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
/* The slip set-point controller's defaults (in rb_wsp_default_params). */
void rb_wsp_setpoint_defaults(rb_wsp_params *p);

#endif

/* Private to the plant: the laws it borrows from other concerns.
 *
 * PENDING (remove after merging main): the pneumatics concern (rb_pneumatics.h) and the vehicle
 * concern (rb_vehicle.h) have not landed yet. Until they do, plant_laws_pending.c provides the
 * contract's orifice law and temporary foundation-brake, ED, resistance and coupler laws; the
 * plant calls only the functions declared here, so the swap touches this header and that file. */
#ifndef RAILBRAKE_PLANT_INTERNAL_H
#define RAILBRAKE_PLANT_INTERNAL_H

#include "railbrake/rb_plant.h"

/* Zone (condition index) of axle `axle` at track position x; refreshes its cached Polach set. */
int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x);

/* Contract signature of rb_pneumatics.h. */
double rb_orifice_mass_flow_fast(double p1, double T1, double p2, double T2,
                                 double area, double discharge_coefficient, double critical_ratio);

/* Stand-ins for rb_vehicle.h laws (temporary). */
double rb_pending_pad_friction(const rb_plant_brake *b, double disc_speed);
double rb_pending_pad_force(const rb_plant_brake *b, double cylinder_pressure, double atmosphere);
double rb_pending_ed_force_max(const rb_plant_ed *e, double speed);
double rb_pending_running_resistance(double a, double b, double c, double speed);
double rb_pending_coupler_force(double stiffness, double damping, double slack, double dx, double dv);

#endif

/* Private to the plant: the laws it borrows from other concerns.
 *
 * PENDING (remove after merging main): the pneumatics concern (rb_pneumatics.h) has not landed
 * yet. Until it does, plant_laws_pending.c provides the contract's orifice law; the swap touches
 * this header and that file only. */
#ifndef RAILBRAKE_PLANT_INTERNAL_H
#define RAILBRAKE_PLANT_INTERNAL_H

#include "railbrake/rb_plant.h"

/* Zone (condition index) of axle `axle` at track position x; refreshes its cached Polach set. */
int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x);

/* Contract signature of rb_pneumatics.h. */
double rb_orifice_mass_flow_fast(double p1, double T1, double p2, double T2,
                                 double area, double discharge_coefficient, double critical_ratio);


#endif

/* Private to the plant. */
#ifndef RAILBRAKE_PLANT_INTERNAL_H
#define RAILBRAKE_PLANT_INTERNAL_H

#include "railbrake/rb_plant.h"
#include "railbrake/rb_pneumatics.h"

/* Zone (condition index) of axle `axle` at track position x; refreshes its cached Polach set. */
int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x);

#endif

/* Private to the scenario runners (run.c, detailed_run.c, hil_runner.c). */
#ifndef RAILBRAKE_RUN_INTERNAL_H
#define RAILBRAKE_RUN_INTERNAL_H

#include "railbrake/rb_run.h"

rb_status rb_run_check_scenario(const rb_scenario *sc, rb_error *err);
/* One row of the time series (layout of rb_run_channel_info) from the outputs o and the BCU's
 * state (its WSP modes). */
void rb_run_record_row(const rb_plant_params *p, const rb_plant_outputs *o, const rb_bcu_params *bcu,
                       const rb_bcu_state *bs, const rb_scenario *sc, double *row);
/* 1 if a car_isolated fault cuts car `car` off (its axles leave the adhesion utilisation out). */
int rb_run_car_isolated(const rb_plant_params *p, int car);

#endif

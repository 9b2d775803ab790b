/* Private: the layout of a recorded time series (global channels, then per car, then per axle),
 * shared by the scenario runner (run.c) and the HIL runner (hil_runner.c). */
#ifndef RAILBRAKE_CHANNELS_INTERNAL_H
#define RAILBRAKE_CHANNELS_INTERNAL_H

#include "railbrake/rb_common.h"

typedef const char *rb_channel_name[2];   /* name, SI unit */

typedef struct {
    const rb_channel_name *global, *car, *axle;
    int n_global, n_car, n_axle;
} rb_channel_layout;

int rb_channel_count(const rb_channel_layout *l, int n_cars);
/* Names: "speed", "supply_c2", "cylinder_c2a3" (cars and axles counted from 1). */
rb_status rb_channel_info(const rb_channel_layout *l, int index, int n_cars, char *name, size_t name_size,
                          char *unit, size_t unit_size, rb_error *err);

#endif

/* Time-series channel names and units (channels_internal.h). */
#include "channels_internal.h"

#include <stdio.h>

#include "railbrake/rb_plant.h"

int rb_channel_count(const rb_channel_layout *l, int n_cars)
{
    return l->n_global + n_cars * (l->n_car + RB_AXLES_PER_CAR * l->n_axle);
}

rb_status rb_channel_info(const rb_channel_layout *l, int index, int n_cars, char *name, size_t name_size,
                          char *unit, size_t unit_size, rb_error *err)
{
    int count = rb_channel_count(l, n_cars);
    if (index < 0 || index >= count)
        return rb_fail(err, RB_EINVAL, "index = %d: must be in [0, %d]", index, count - 1);
    const char *const *entry;
    if (index < l->n_global) {
        entry = l->global[index];
        snprintf(name, name_size, "%s", entry[0]);
    } else if ((index -= l->n_global) < n_cars * l->n_car) {
        entry = l->car[index / n_cars];
        snprintf(name, name_size, "%s_c%d", entry[0], index % n_cars + 1);
    } else {
        index -= n_cars * l->n_car;
        int n_axles = n_cars * RB_AXLES_PER_CAR, axle = index % n_axles;
        entry = l->axle[index / n_axles];
        snprintf(name, name_size, "%s_c%da%d", entry[0], axle / RB_AXLES_PER_CAR + 1, axle % RB_AXLES_PER_CAR + 1);
    }
    snprintf(unit, unit_size, "%s", entry[1]);
    return RB_OK;
}

/* Plausibility bounds of the tunable physical parameters: one table, read by the C checks
 * (rb_plant_bounds_check, rb_wsp_check), the FMU's variable ranges (railbrake.fmu, via _core.py)
 * and the file schemas in Python (railbrake.config.bound_in: scenario, train, adhesion, profile and
 * valve files name an entry next to the unit of each key, and give its range in the user's unit).
 * SI units throughout; entries "train.*", "scenario.*", "profile.*", "adhesion.*", "valve.*" are
 * only read by the schemas (the plant gets those quantities through others).
 *
 * Two kinds of limit: what is physically meaningful for a high-speed train (a car of 5 to 200 t),
 * and what the fixed-step numerics of the plant can bear (dt = 1 ms, explicit mechanics): a coupler
 * of stiffness k between cars of mass m is stable while dt sqrt(4 k / m) < 2 and dt 4 c / m < 2,
 * which at the smallest mass (5 t) gives k <= 1e9 N/m and c <= 2e6 N s/m; a volume below 1e-6 m^3
 * turns a kilogram of air into an unbounded pressure (R T / V). */
#ifndef RAILBRAKE_RB_BOUNDS_H
#define RAILBRAKE_RB_BOUNDS_H

#include "railbrake/rb_bcu.h"
#include "railbrake/rb_common.h"
#include "railbrake/rb_plant.h"

typedef struct {
    const char *name;   /* the parameter's C path: "coupler.damping", "car.mass", "wsp.safety_time" */
    const char *unit;   /* SI unit of min and max */
    double min, max;    /* inclusive */
    const char *why;    /* what the limits protect */
} rb_bound;

int rb_bound_count(void);
const rb_bound *rb_bound_at(int i);          /* NULL outside [0, rb_bound_count()) */
const rb_bound *rb_bound_find(const char *name);
/* Finite and inside the bound `name`; the message names `label` (e.g. "car[2].mass"). */
rb_status rb_bound_check(rb_error *err, const char *name, const char *label, double value);

/* The plant's tunable parameters against the table (rb_plant_check covers the rest). */
rb_status rb_plant_bounds_check(const rb_plant_params *p, rb_error *err);
/* Every WSP parameter: finite and inside its bound. */
rb_status rb_wsp_check(const rb_wsp_params *w, rb_error *err);

#endif

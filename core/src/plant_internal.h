/* Private to the plant. */
#ifndef RAILBRAKE_PLANT_INTERNAL_H
#define RAILBRAKE_PLANT_INTERNAL_H

#include "railbrake/rb_plant.h"
#include "railbrake/rb_pneumatics.h"

/* Zone (condition index) of axle `axle` at track position x; refreshes its cached Polach set. */
int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x);

/* Faults in force at a time, per axle and per car. */
typedef struct {
    signed char hold[RB_PLANT_MAX_AXLES];   /* -1: as commanded, 0: stuck open, 1: stuck closed */
    signed char vent[RB_PLANT_MAX_AXLES];   /* -1: as commanded, 0: stuck closed, 1: stuck open */
    double leak[RB_PLANT_MAX_AXLES];        /* m^2 */
    double noise_sd[RB_PLANT_MAX_AXLES];    /* m/s */
    uint8_t ep_failed[RB_PLANT_MAX_CARS], ed_lost[RB_PLANT_MAX_CARS], isolated[RB_PLANT_MAX_CARS];
    int compressor_off;
} rb_plant_faults;

void rb_plant_gather_faults(const rb_plant_params *p, const rb_plant_state *s, rb_plant_faults *f);
/* Wheelsets (torque balance, Polach adhesion with conditioning, ED) and cars (couplers,
   resistance) over one step dt with the given cylinder pressures (Pa, per axle): the one
   implementation of the mechanics, shared by the real-time plant and the detailed model. */
void rb_plant_step_mechanics(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                             const rb_plant_faults *f, const double *cylinder, double dt);
/* Wheel-speed sensor faults (loss, noise) for the outputs. */
void rb_plant_update_sensors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f);

/* ---- train equipment (plant_train.c): each called from plant.c / plant_step.c in one line */
/* Checks the parameters of plant_train.c (compressors, gradients, discs). */
rb_status rb_plant_train_check(const rb_plant_params *p, rb_error *err);
/* Initial state of the compressors, discs and the air-drawn booking (after the air is set). */
void rb_plant_train_init(const rb_plant_params *p, rb_plant_state *s);
/* The compressors over a step dt: governors, delivery into the MR or the MR pipe. */
void rb_plant_compressors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f, double dt);
/* Force of gravity along the track on car c (N, positive pulling back when uphill). */
double rb_plant_gradient_force(const rb_plant_params *p, const rb_plant_state *s, int c);
/* Friction brake energy and disc temperature of every axle over a sub-step dt at the cylinder
 * pressures it ran with. */
void rb_plant_discs(const rb_plant_params *p, rb_plant_state *s, const double *cylinder, double dt);
/* The outputs of plant_train.c. */
void rb_plant_train_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out);

#endif

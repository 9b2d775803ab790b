/* Private to the detailed model (detailed_air.c, detailed_run.c). */
#ifndef RAILBRAKE_DETAILED_INTERNAL_H
#define RAILBRAKE_DETAILED_INTERNAL_H

#include "railbrake/rb_detailed.h"

/* Car network node and link indices. */
enum { CN_SUPPLY, CN_PILOT, CN_CONTROL, CN_RELAY, CN_CYL, CN_ATM = CN_CYL + RB_AXLES_PER_CAR,
       CN_REGULATED };   /* the load-weighing valve's output (a reservoir at its regulated pressure) */
enum { CL_PILOT_ORIFICE, CL_NOZZLE, CL_EPV_INLET, CL_EPV_EXHAUST, CL_RELAY_INLET, CL_RELAY_EXHAUST,
       CL_HOLD, CL_VENT = CL_HOLD + RB_AXLES_PER_CAR, CL_EMERGENCY = CL_VENT + RB_AXLES_PER_CAR };
enum { CB_ARMATURE, CB_PISTON, CB_MEMBRANE };
/* Car state layout: (m, T) per volume node in node order, (x, v) per body, then the vented mass. */
enum { CS_BODIES = 2 * CN_ATM, CS_VENTED = CS_BODIES + 2 * RB_DET_CAR_BODIES };

/* A network with accumulators: extra states integrating the flow of chosen links. */
typedef struct {
    rb_network net;
    rb_network_eval ev;
    size_t n_net;                       /* network states; accumulators follow */
    int n_acc;
    signed char acc_of_link[RB_DET_LINE_LINKS]; /* -1: none */
    double t_prev, h_step, h_final;     /* step sizes seen, for the next start */
} rb_det_system;

/* Fills car c's network description (nodes, links, bodies) in k. */
void rb_det_build_car(const rb_plant_params *p, const rb_detailed_params *d, int c, rb_detailed_car *k);
/* The network view of car k (pointers into k, d and the membrane). */
void rb_det_car_system(rb_detailed_car *k, const rb_detailed_params *d, const rb_membrane *membrane,
                       rb_det_system *sys);
/* Sets the WSP valve openings of car k from its actual valve states and the EP current. */
void rb_det_apply_commands(rb_detailed_car *k);
/* Lays out the evaluation (work, iwork) and the tolerance scales (accumulators: 1 kg). */
rb_status rb_det_system_init(rb_det_system *sys, double *work, size_t work_size, int *iwork, size_t iwork_size,
                             double *y0, double *scale, rb_error *err);
/* Integrates sys from t0 (state y) to t_out[n_out - 1]; y_out receives the rows. h: first step
   in, a good next first step out. */
rb_status rb_det_solve(rb_det_system *sys, const rb_detailed_params *d, double t0, double *y, const double *t_out,
                       size_t n_out, double *y_out, double *h, const double *scale, double *work, int *iwork,
                       rb_ode_stats *total, rb_error *err);

#endif

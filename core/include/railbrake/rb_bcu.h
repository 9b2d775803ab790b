/* Brake control unit (BCU) logic, separate from the plant: brake demand -> EP pressure demand per
 * car (load-weighed), ED/pneumatic blending, and wheel-slide protection (WSP) behind a plug-in
 * interface. It reads rb_plant_outputs (what a real BCU measures) and writes rb_plant_inputs.
 *
 * WSP defaults (structure after EN 15595 and UIC 541-05; values typical [T], docs/references.md): reference speed from the fastest axle with
 * a limited rate of change; detection on speed difference (km/h plus a percentage), wheel
 * deceleration and slip; vent / hold / re-apply states; a safety timer on continuous venting.
 */
#ifndef RAILBRAKE_BCU_H
#define RAILBRAKE_BCU_H

#include "railbrake/rb_plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the WSP plug-in interface */

typedef struct {
    double time;                          /* s */
    double cycle;                         /* s, time since the previous call */
    int n_axles;
    double wheel_speed[RB_PLANT_MAX_AXLES];     /* m/s, measured; < 0: sensor lost */
    double cylinder[RB_PLANT_MAX_AXLES];        /* Pa */
    double demand[RB_PLANT_MAX_AXLES];          /* Pa, EP pressure demand of the axle's car */
    double atmosphere;                    /* Pa */
    double body_decel;                    /* m/s^2, the leading car body's deceleration (an
                                             accelerometer); NaN: none (the set-point controller's
                                             speed estimate then falls at ref_decel_max) */
} rb_wsp_inputs;

typedef struct {
    uint8_t hold[RB_PLANT_MAX_AXLES];           /* 1: close the hold valve */
    uint8_t vent[RB_PLANT_MAX_AXLES];           /* 1: open the vent valve */
    uint8_t active[RB_PLANT_MAX_AXLES];         /* 1: the axle is under WSP control (ED is cut on its car) */
} rb_wsp_commands;

/* A WSP algorithm: called every BCU cycle. context: the user's (or the default's) data. */
typedef void (*rb_wsp_function)(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out);

/* ---- the default WSP */

typedef enum {
    RB_WSP_OFF = -1,       /* no default WSP on the axle: the BCU's WSP disabled, or a user function (records) */
    RB_WSP_APPLY = 0,      /* brake as demanded */
    RB_WSP_VENT = 1,       /* hold closed, vent open */
    RB_WSP_HOLD = 2,       /* hold closed */
    RB_WSP_REAPPLY = 3,    /* hold valve pulsed open: the pressure climbs back in steps */
    RB_WSP_INHIBITED = 4,  /* safety timer tripped on commanded venting: WSP off on this axle */
    RB_WSP_ISOLATED = 5    /* safety timer tripped on a cylinder vented without command: hold closed */
} rb_wsp_mode;

typedef struct {
    double ref_decel_max;      /* m/s^2, fastest fall of the reference speed */
    double ref_accel_max;      /* m/s^2, fastest rise */
    double speed_threshold;    /* m/s, speed difference that starts venting ... */
    double slip_threshold;     /* ... plus this fraction of the reference speed */
    double decel_threshold;    /* m/s^2, wheel deceleration that starts venting */
    double reaccel_threshold;  /* m/s^2, wheel acceleration that ends venting (hold) */
    double release_fraction;   /* speed difference / its threshold below which the brake re-applies */
    double reapply_on, reapply_off; /* s, hold-valve pulses while re-applying */
    double reapply_time;       /* s without a new slide before the brake is fully re-applied */
    double filter_time;        /* s, wheel acceleration filter */
    double safety_time;        /* s, longest continuous venting (commanded or seen at the cylinder) */
    double min_speed;          /* m/s, WSP inactive below */
    /* the controller (rb_wsp_controller): RB_WSP_THRESHOLD, the state machine above (default),
     * RB_WSP_SLIP_SETPOINT, each axle's slip velocity held in a band about a set-point
     * (wsp_controllers.c), or RB_WSP_DECEL_SLIP_SPEED (wsp_decel_slip.c) */
    int controller;
    double setpoint_speed;     /* m/s, slip-velocity set-point ... */
    double setpoint_slip;      /* ... plus this fraction of the reference speed */
    double setpoint_band;      /* fraction of the set-point: hold inside +-band, vent above, apply below */
    double lead_time;          /* s, the slip velocity predicted this far ahead from its rate (valve delays) */
    double ref_decel_margin;   /* m/s^2, the set-point controller's speed estimate falls at most at
                                  the body's deceleration plus this (when every wheel slides) */
    double setpoint_release;   /* s braked as demanded after which the set-point controller lets an
                                  axle go (until the next detected slide) */
    /* the set-point controller's pressure memory: below the band the brake re-applies quickly up to
       setpoint_memory x the cylinder pressure (gauge) at which the axle last had to vent, then
       holds; that ceiling rises at setpoint_ramp (Pa/s) while the axle stays below the band */
    double setpoint_memory;    /* fraction of the remembered pressure */
    double setpoint_ramp;      /* Pa/s */
    /* RB_WSP_DECEL_SLIP_SPEED (wsp_decel_slip.c): a slide is vented when the wheel's slip speed
     * (reference - wheel) exceeds ds_speed_threshold + ds_slip_threshold x reference or its
     * deceleration exceeds ds_decel_threshold */
    double ds_speed_threshold; /* m/s */
    double ds_slip_threshold;  /* fraction of the reference speed */
    double ds_decel_threshold; /* m/s^2 */
    double ds_reaccel_threshold; /* m/s^2, wheel re-acceleration above which the brake re-applies at once */
    /* Conditioning mode (every controller): the leading axle of each bogie keeps the controller's
     * criteria, the trailing one's slide criteria (the threshold controller's speed difference and
     * deceleration, the set-point, the slip speed and deceleration) are multiplied by
     * conditioning_ratio, so it slides more and cleans the rail for the axles behind. Needs valves
     * per axle (rb_bcu_params.wsp_per_bogie = 0). */
    int conditioning_mode;     /* 1: on */
    double conditioning_ratio;
} rb_wsp_params;

typedef enum {
    RB_WSP_THRESHOLD = 0,      /* thresholds on speed difference and deceleration, vent/hold/re-apply */
    RB_WSP_SLIP_SETPOINT = 1,  /* slip-velocity set-point (micro/macro slip), predicted over lead_time */
    RB_WSP_DECEL_SLIP_SPEED = 2, /* wheel deceleration and slip-speed thresholds, hold band, re-apply
                                    on the wheel's re-acceleration */
    RB_WSP_CONTROLLERS
} rb_wsp_controller;

typedef struct {
    rb_wsp_params p;
    double reference;                     /* m/s */
    int initialised;
    int mode[RB_PLANT_MAX_AXLES];               /* rb_wsp_mode */
    double last_speed[RB_PLANT_MAX_AXLES];
    double accel[RB_PLANT_MAX_AXLES];           /* m/s^2, filtered */
    double vent_time[RB_PLANT_MAX_AXLES];       /* s of continuous commanded venting */
    double reapply_clock[RB_PLANT_MAX_AXLES];   /* s since re-application started */
    double low_time[RB_PLANT_MAX_AXLES];        /* s of cylinder far below demand without a command */
    int trips;
    uint8_t engaged[RB_PLANT_MAX_AXLES];        /* set-point controller: a slide was detected on the axle */
    double memory[RB_PLANT_MAX_AXLES];          /* set-point controller: Pa abs, the cylinder when it
                                                   last began to vent, risen since (setpoint_ramp) */
} rb_wsp_default;

void rb_wsp_default_params(rb_wsp_params *p);
/* The slip set-point controller's step (wsp_controllers.c); rb_wsp_default_step calls it when
 * p.controller is RB_WSP_SLIP_SETPOINT. context: an rb_wsp_default. */
void rb_wsp_setpoint_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out);
/* The deceleration and slip-speed controller's step (wsp_decel_slip.c), for RB_WSP_DECEL_SLIP_SPEED. */
void rb_wsp_decel_slip_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out);
void rb_wsp_default_reset(rb_wsp_default *w, const rb_wsp_params *p);
/* The default algorithm; context: an rb_wsp_default. */
void rb_wsp_default_step(void *context, const rb_wsp_inputs *in, rb_wsp_commands *out);

/* ---- the BCU */

typedef struct {
    int n_cars;
    double cycle;                         /* s, BCU cycle (10 ms typical) */
    double atmosphere;                    /* Pa */
    double service_decel;                 /* m/s^2 at full service demand */
    double emergency_decel;               /* m/s^2 */
    int ed_in_emergency;                  /* 0: pneumatic only in emergency */
    double car_mass[RB_PLANT_MAX_CARS];         /* kg, load-weighed (with rotating mass) */
    double pressure_offset[RB_PLANT_MAX_CARS];  /* Pa abs, demand at zero brake force */
    double pressure_gain[RB_PLANT_MAX_CARS];    /* Pa per N of pneumatic brake force of the car */
    double pressure_max[RB_PLANT_MAX_CARS];     /* Pa abs */
    int motor[RB_PLANT_MAX_CARS];
    int wsp_enabled;
    int wsp_per_bogie;                    /* 1: both axles of a bogie share their valve commands */
    rb_wsp_function wsp;                  /* NULL: the default WSP */
    void *wsp_context;
    /* Brake steps from the sizing (railbrake.sizing, rb_size_car_demand), used when
     * demand_tables = 1 instead of the constant decelerations and the linear map above. Per car
     * and versus the BCU's speed (the fastest measured wheel): the brake force the car gives at
     * full emergency / full service (N, ED plus pneumatic, load-weighed) and the pneumatic law
     * solved for the pressure (Pa per N, pad lambda(v) included). Cylinder pressure demand =
     * pressure_offset + pressure_per_newton(v) * (force(v) * fraction - ED force achieved). */
    int demand_tables;
    int ed_in_service;                    /* 1: ED blending in service (motor cars) */
    rb_speed_table emergency_force[RB_PLANT_MAX_CARS];
    rb_speed_table service_force[RB_PLANT_MAX_CARS];
    rb_speed_table pressure_per_newton[RB_PLANT_MAX_CARS];
    rb_speed_table emergency_profile;     /* m/s^2 demanded at full emergency (recorded) */
    rb_speed_table service_profile;       /* m/s^2 at full service */
    /* The service brake's jerk limit (a comfort limit of the BCU, m/s^3; 0: none): the service
     * fraction the BCU applies moves towards the demanded one by at most service_jerk x (time
     * since its previous cycle) / (full service deceleration at the BCU's speed), applying and
     * releasing. The emergency demand is never limited. */
    double service_jerk;
} rb_bcu_params;

typedef struct {
    double emergency;                     /* 1: emergency brake */
    double service;                       /* 0..1 of full service */
} rb_brake_demand;

typedef struct {
    double next_cycle;                    /* s, time of the next BCU cycle */
    double last_cycle;                    /* s, time of the previous one */
    rb_plant_inputs command;              /* held between cycles */
    rb_wsp_inputs wsp_in;
    rb_wsp_commands wsp;
    rb_wsp_default wsp_default;
    double service_applied;               /* 0..1, the service demand after the jerk limit */
} rb_bcu_state;

size_t rb_bcu_params_size(void);
rb_status rb_bcu_check(const rb_bcu_params *p, rb_error *err);
rb_status rb_bcu_init(const rb_bcu_params *p, const rb_wsp_params *wsp, rb_bcu_state *s, rb_error *err);
/* New parameters for the default WSP during a run (a tuned threshold): checked (rb_wsp_check),
 * then used from the next rb_bcu_step on; the WSP's state (modes, timers) is kept. */
rb_status rb_bcu_retune_wsp(rb_bcu_state *s, const rb_wsp_params *wsp, rb_error *err);
/* Linear demand -> pressure map of each car from the plant's own brake law at nominal pad
 * friction (load-weighed by the car's mass): pressure_offset, pressure_gain, pressure_max. */
void rb_bcu_pressure_map(const rb_plant_params *plant, double pressure_max, rb_bcu_params *p);
/* Runs the BCU if a cycle is due at out->time: s->command holds the plant's inputs, changed only
 * by a cycle, except the emergency loop (a train line), which follows the demand at once. 1: the
 * inputs changed (a cycle ran or the loop switched); 0: they did not. */
int rb_bcu_update(const rb_bcu_params *p, rb_bcu_state *s, const rb_brake_demand *demand,
                  const rb_plant_outputs *out);
/* rb_bcu_update, then writes the plant's inputs (held between cycles) to *in. */
void rb_bcu_step(const rb_bcu_params *p, rb_bcu_state *s, const rb_brake_demand *demand,
                 const rb_plant_outputs *out, rb_plant_inputs *in);
/* The BCU's speed: the fastest measured wheel (a lost sensor reads < 0 and is ignored). */
double rb_bcu_speed(const rb_plant_outputs *out, int n_cars);
/* The default WSP's mode (rb_wsp_mode) of axle a, for records: RB_WSP_OFF when the BCU runs no
 * WSP or a user function (p->wsp), whose state the BCU does not know. A safety-timer trip is the
 * axle's mode becoming RB_WSP_INHIBITED or RB_WSP_ISOLATED, which it keeps to the end of the run. */
int rb_bcu_wsp_mode(const rb_bcu_params *p, const rb_bcu_state *s, int a);
/* Demanded deceleration (m/s^2) of a brake demand at speed v, for records. */
double rb_bcu_demand_deceleration(const rb_bcu_params *p, const rb_brake_demand *d, double speed);

#ifdef __cplusplus
}
#endif
#endif

/* A whole scenario in C: BCU + plant at a fixed step, a decimated time series written into a
 * caller-provided array, and the key performance indicators (KPIs). Runs in chunks so a caller
 * can show progress; the state is one fixed-size struct (no allocation). */
#ifndef RAILBRAKE_RUN_H
#define RAILBRAKE_RUN_H

#include "railbrake/rb_bcu.h"
#include "railbrake/rb_plant.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_MAX_DEMAND_STEPS 16
#define RB_MAX_SPEED_MARKS 16

typedef struct {
    int n_demand;                               /* brake demand, a step function of time */
    double demand_time[RB_MAX_DEMAND_STEPS];    /* s, increasing */
    double demand_service[RB_MAX_DEMAND_STEPS]; /* 0..1 of full service */
    double demand_emergency[RB_MAX_DEMAND_STEPS]; /* 1: emergency */
    double max_time;                            /* s, the run ends here at the latest */
    double stop_speed;                          /* m/s, the run ends when the train is below */
    double record_interval;                     /* s, time-series decimation */
    double adhesion_interval;                   /* s, sampling of the available peak adhesion */
    /* speeds (m/s, decreasing) at which a braking run notes when and where it passed them
     * (rb_kpis.mark_time_s, mark_distance_m): the ETCS braking model's speed steps */
    int n_speed_marks;
    double speed_mark[RB_MAX_SPEED_MARKS];
} rb_scenario;

typedef struct {
    double stopping_distance_m;   /* from the first brake demand to the stop */
    double stopping_time_s;
    double mean_deceleration;     /* m/s^2, initial speed / stopping time */
    double max_slip;              /* largest |slip| while the train runs above 10 km/h */
    double wheel_lock_events;     /* axle below 10 % of the train speed above 10 km/h, per episode */
    double max_lock_duration_s;
    double air_consumed_kg;       /* vented to the atmosphere */
    double adhesion_utilisation;  /* mean rail deceleration / (g * mean available peak adhesion) */
    double safety_timer_trips;
    double air_balance_error;     /* |in volumes + vented - compressed - initial| / initial */
    double stopped;               /* 1 if the train stopped before max_time */
    /* air supply, cylinders, discs */
    double min_main_reservoir;    /* Pa abs, lowest main-reservoir pressure */
    double min_supply;            /* Pa abs, lowest supply-reservoir pressure of any car */
    double air_drawn_kg;          /* taken from the main reservoir and pipe (fills, venting, leaks) */
    double air_vented_kg;         /* to the atmosphere */
    double cylinder_shortfall_s;  /* longest time a cylinder stayed RB_SHORTFALL_PA below its car's
                                     demand while braking with its WSP valves at rest */
    double worst_axle;            /* 0-based axle with the most lock events, then the largest slip
                                     above 2 %; -1: no axle locked or slid */
    double brake_energy;          /* J, friction brake energy of the whole train */
    double max_disc_temperature;  /* K, hottest lumped disc */
    double min_supply_margin;     /* Pa, lowest supply minus cylinder demand of a braking car (< 0:
                                     the supply could not give the demand); 0 if never braking */
    /* per rb_scenario.speed_mark: time (s) and distance (m) from the first brake demand to where
     * the train speed fell to the mark (linear between steps); -1 if it never did */
    double mark_time_s[RB_MAX_SPEED_MARKS];
    double mark_distance_m[RB_MAX_SPEED_MARKS];
    /* WSP effort and wheel-flat risk, while braking */
    double valve_switchings;      /* changes of state of the WSP hold and vent valves, whole train */
    double max_sliding_energy;    /* J, the largest over the axles of the sliding energy, the time
                                     integral of creep force x slip velocity (wheel-flat risk) */
    double sliding_energy;        /* J, the same summed over the axles */
    /* the pads and discs */
    double mean_pad_friction;     /* stop-averaged pad friction: the instantaneous friction averaged
                                     over the pads' sliding distance while they press (UIC 541-3's
                                     mean friction of a dynamometer stop, 1/s int mu ds), all braked
                                     axles together; 0 if no pad pressed */
    double max_disc_surface_temperature; /* K, hottest friction surface of any disc */
} rb_kpis;

#define RB_SHORTFALL_PA 0.2e5

typedef struct {
    rb_plant_state plant;
    rb_bcu_state bcu;
    rb_plant_outputs out;
    rb_plant_inputs in;
    int braking, finished, stopped;
    double brake_time, brake_position, brake_speed;
    double next_record, next_adhesion;
    double rail_decel_sum, rail_decel_time;      /* time integral of the rail deceleration */
    double peak_sum; long peak_samples;
    int lock_events;
    size_t rows;
    double min_main_reservoir;
    /* extremes kept per car and per axle (one vector per car), the train's taken at the end */
    double car_min_supply[RB_PLANT_MAX_CARS], car_min_supply_margin[RB_PLANT_MAX_CARS];
    double lock_time[RB_PLANT_MAX_AXLES], axle_max_lock[RB_PLANT_MAX_AXLES];
    double shortfall_time[RB_PLANT_MAX_AXLES], axle_max_shortfall[RB_PLANT_MAX_AXLES];
    double axle_max_slip[RB_PLANT_MAX_AXLES];
    double axle_locks[RB_PLANT_MAX_AXLES];
    double axle_max_disc_temperature[RB_PLANT_MAX_AXLES];
    double axle_sliding_energy[RB_PLANT_MAX_AXLES];   /* J, integral of F w dt */
    double axle_max_disc_surface_temperature[RB_PLANT_MAX_AXLES];
    /* the pads' sliding distance (at the wheel's radius: the disc's scales both) while they press,
       and the integral of their friction over it */
    double axle_pad_distance[RB_PLANT_MAX_AXLES], axle_pad_friction_distance[RB_PLANT_MAX_AXLES];
    uint8_t last_hold[RB_PLANT_MAX_AXLES], last_vent[RB_PLANT_MAX_AXLES];   /* valve states of the last step */
    long valve_switchings;
    /* constant over the run (rb_run_start_kpis): the train's mass, which axles count for adhesion */
    double total_mass;
    uint8_t adhesion_axle[RB_PLANT_MAX_AXLES];   /* 1: its car is not isolated */
    /* the available peak adhesion, followed per axle (rb_plant_peak_adhesion_track): log10 of its
     * creep, for the adhesion condition peak_zone; the inner maxima its last search saw; searches
     * made in turn */
    double peak_log_creep[RB_PLANT_MAX_AXLES];
    int peak_zone[RB_PLANT_MAX_AXLES];
    int peak_maxima[RB_PLANT_MAX_AXLES];
    long peak_rescans;
    /* speed marks passed so far (rb_scenario.speed_mark), where, and the previous step's values */
    int marks_passed;
    double mark_time[RB_MAX_SPEED_MARKS], mark_position[RB_MAX_SPEED_MARKS];
    double last_time, last_speed, last_position;
} rb_run_state;

/* The scenario's brake demand at time t (a step function; a step applies from its own time on). */
rb_brake_demand rb_scenario_demand(const rb_scenario *scenario, double t);

rb_status rb_run_init(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_wsp_params *wsp,
                      const rb_scenario *scenario, rb_run_state *run, rb_error *err);
/* Runs until time t_until, the stop or max_time, writing rows of rb_run_channel_count(n_cars)
 * values into series (max_rows rows; series = NULL: no recording). *finished = 1 when the run
 * is over. */
rb_status rb_run_advance(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_scenario *scenario,
                         rb_run_state *run, double t_until, double *series, size_t max_rows, int *finished,
                         rb_error *err);
void rb_run_kpis(const rb_plant_params *plant, const rb_run_state *run, rb_kpis *k);
/* Parameters changed between two rb_run_advance calls, acting from the next step on (as the FMU's
 * tunable parameters between doSteps): the WSP's (wsp) and the adhesion of plant->condition[*]
 * (rb_bcu_retune_wsp, rb_plant_retune_adhesion). A fault is started by setting its start_time in
 * plant->fault[*] (read at each step). */
rb_status rb_run_retune(const rb_plant_params *plant, const rb_wsp_params *wsp, rb_run_state *run, rb_error *err);
/* KPI accumulation for a plant stepped by another loop (the HIL runner): run->plant and run->out
 * hold the plant's state and outputs after the step; run->braking, brake_time, brake_position,
 * brake_speed and next_adhesion are set by the caller when braking begins. */
void rb_run_accumulate(const rb_plant_params *plant, const rb_scenario *scenario, rb_run_state *run);
/* Starts the air-supply and disc extremes of the KPIs from run->out (rb_run_init does it; a loop
 * that accumulates on its own plant, as the HIL runner, calls it once it has outputs). */
void rb_run_start_kpis(const rb_plant_params *plant, rb_run_state *run);
size_t rb_run_state_size(void);
size_t rb_kpis_size(void);

/* Time-series layout: number of channels, and the name and SI unit of channel `index`. */
int rb_run_channel_count(int n_cars);
rb_status rb_run_channel_info(int index, int n_cars, char *name, size_t name_size, char *unit,
                              size_t unit_size, rb_error *err);

/* The plant alone at its fixed step with constant inputs (brakes at pressure_demand), `steps` steps
 * after a warm-up of steps / 10 (at most 1000), in microseconds per step: step_us_mean the CPU time
 * of the calling thread over the steps (on a shared machine, without the time other processes held
 * the core; wall-clock where the system has no thread CPU clock), step_us_wall_mean the wall-clock
 * mean, step_us_p99 and step_us_max the 99th percentile and the largest wall-clock time of one step
 * (each including one clock read, about 30 ns); the name of the wheelset kernel used
 * (rb_plant_kernel_name) into kernel. */
rb_status rb_plant_bench(const rb_plant_params *plant, double pressure_demand, long steps,
                         double *step_us_mean, double *step_us_p99, double *step_us_max,
                         double *step_us_wall_mean, char *kernel, size_t kernel_size, rb_error *err);

/* n runs in one call, variant i from plants[i], bcus[i], wsps[i] (wsps NULL: the defaults) and
 * scenarios[i], each to its end without recording, in the caller's run state: kpis[i] and
 * status[i] (RB_OK, or the run's error, its message in errors[i] when errors is not NULL). */
#define RB_MAX_BATCH 4096
rb_status rb_run_batch(int n, const rb_plant_params *plants, const rb_bcu_params *bcus, const rb_wsp_params *wsps,
                       const rb_scenario *scenarios, rb_run_state *run, rb_kpis *kpis, int *status,
                       rb_error *errors, rb_error *err);

/* What a whole run costs against its plant alone on the same scenario, in CPU microseconds of the
 * calling thread per step (plant_bench.c): run_us for the run as rb_run_advance makes it without
 * recording (BCU, WSP, KPIs), plant_us for a fresh plant stepped through the inputs the BCU gave it
 * in that run; each the fastest of `repeats` alternating passes. trace holds max_steps inputs
 * (the run's steps); run is a caller-provided rb_run_state. */
typedef struct {
    double steps;      /* plant steps of the run */
    double run_us;     /* whole run, per step */
    double plant_us;   /* the plant alone, per step */
    char kernel[16];   /* the wheelset kernel used (rb_plant_kernel_name) */
} rb_run_bench_result;

rb_status rb_run_bench(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_wsp_params *wsp,
                       const rb_scenario *scenario, int repeats, rb_run_state *run, rb_plant_inputs *trace,
                       size_t max_steps, rb_run_bench_result *result, rb_error *err);

#ifdef __cplusplus
}
#endif
#endif

/* Detailed whole-train model: the same train as the real-time plant (rb_plant.h) with each car's
 * air side made of the detailed valve models (rb_network.h) and integrated by the variable-step
 * stiff solver (rb_ode.h), against which the real-time plant is checked (docs/detailed.md).
 *
 *  - Per car, one pneumatic network: supply reservoir; EP valve (solenoid armature with its force
 *    table F(airgap, current) over a flapper-nozzle pilot stage fed through an orifice, and a
 *    piston with inlet and exhaust seats and sealing friction setting the control pressure); relay
 *    valve (membrane, A_eff = dV/dx, with inlet and exhaust seats); per axle the WSP hold valve
 *    (relay output -> cylinder) and vent valve (cylinder -> atmosphere), solenoid valves switching
 *    after their response delay; cylinders of fixed volume. Every volume is an ideal gas with mass
 *    and energy balance and heat exchange with the wall. Volumes, port areas of the WSP valves
 *    and the delay are the plant's (rb_plant_car); the valve designs are rb_detailed_params.
 *  - Train line: main reservoir and the MR pipe segments, one more network, charging each car's
 *    supply reservoir through its check valve and choke; the plant's compressors (each into the
 *    main reservoir or its car's MR pipe, with its own governor), delivering at the cycle start.
 *  - The BCU (the same rb_bcu_step) is a sampled controller: at each cycle it reads the outputs and
 *    sets the commands; the solver restarts at each cycle and at each WSP valve switching. The
 *    EP valve is driven by a current: the static inverse of its force balance (at the setup's
 *    supply pressure) plus an integral trim on the measured control pressure (docs/detailed.md).
 *  - Coupling: the air does not depend on the mechanics within a cycle, so each cycle integrates
 *    the train line (supply pressures held; the charged air is then added to the supply
 *    reservoirs, mass and enthalpy), then each car's network with dense output at the mechanics
 *    sub-steps, then the mechanics (the plant's own rb_plant_step_mechanics) at mechanics_dt.
 *  - Not modelled: faults (rb_detailed_init rejects n_faults > 0).
 */
#ifndef RAILBRAKE_DETAILED_H
#define RAILBRAKE_DETAILED_H

#include "railbrake/rb_network.h"
#include "railbrake/rb_run.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_DET_MAX_SUBSTEPS 256   /* mechanics sub-steps per BCU cycle */

/* Valve designs (every car alike) and solver settings; SI units, absolute pressures. */
typedef struct {
    /* EP valve: pilot stage */
    double pilot_volume;            /* m^3, nozzle chamber */
    double pilot_orifice_area;      /* m^2, supply -> nozzle chamber */
    double nozzle_diameter;         /* m */
    double armature_mass, armature_spring_rate, armature_preload, armature_damping; /* kg, N/m, N, N s/m */
    double airgap_open;             /* m, solenoid airgap with the flapper at its open stop (x = 0) */
    double flapper_travel;          /* m, open stop to the nozzle */
    rb_force_table solenoid;        /* N along +x (towards the nozzle) */
    double current_max;             /* A, the drive's limit */
    /* EP valve: piston between the nozzle chamber (+x) and the control chamber (-x) */
    double piston_area, piston_mass, piston_spring_rate, piston_preload, piston_damping;
    double piston_friction, piston_friction_velocity; /* N, m/s */
    double piston_travel, seat_lap;  /* m, each way; both seats shut for |x| <= lap */
    double epv_inlet_diameter, epv_exhaust_diameter; /* m, flat seats */
    /* relay valve: membrane between the control chamber (+x) and the relay output (-x) */
    int membrane_points;
    double membrane_x[RB_MEMBRANE_MAX_POINTS], membrane_volume[RB_MEMBRANE_MAX_POINTS]; /* m, m^3 */
    double membrane_mass, membrane_spring_rate, membrane_preload, membrane_damping, membrane_travel;
    double relay_inlet_diameter, relay_exhaust_diameter; /* m, flat seats */
    /* air */
    double thermal_time;            /* s, wall heat exchange: h A = m cv / thermal_time at 5 bar */
    /* EP valve drive */
    double trim_time;               /* s, integral time of the control-pressure trim; 0: none */
    /* solver */
    double rtol, atol;              /* rb_ode tolerances (atol scaled per state) */
    double mechanics_dt;            /* s, largest mechanics step (rounded to divide the BCU cycle) */
} rb_detailed_params;

enum { RB_DET_CAR_NODES = 10, RB_DET_CAR_LINKS = 15, RB_DET_CAR_BODIES = 3 };
enum { RB_DET_CAR_STATES = 2 * 8 + 2 * RB_DET_CAR_BODIES + 1 };   /* + vented mass */
enum { RB_DET_LINE_NODES = 2 * RB_PLANT_MAX_CARS + 1, RB_DET_LINE_LINKS = 2 * RB_PLANT_MAX_CARS };
enum { RB_DET_LINE_STATES = 2 * (RB_PLANT_MAX_CARS + 1) + RB_PLANT_MAX_CARS };
enum { RB_DET_MAX_STATES = RB_DET_LINE_STATES };
enum { RB_DET_BUFFER = 4 * RB_PLANT_MAX_CARS + RB_PLANT_MAX_AXLES };   /* air outputs per sub-step */

typedef struct {
    rb_net_node node[RB_DET_CAR_NODES];
    rb_net_link link[RB_DET_CAR_LINKS];
    rb_net_body body[RB_DET_CAR_BODIES];
    double y[RB_DET_CAR_STATES];
    double h_last;                  /* s, last full solver step (next cycle's first step) */
    double trim;                    /* Pa, EP drive's integral trim */
    double current;                 /* A, EP valve current held over the cycle */
    uint8_t hold[RB_AXLES_PER_CAR], vent[RB_AXLES_PER_CAR];       /* actual valve states */
    uint8_t hold_pending[RB_AXLES_PER_CAR], vent_pending[RB_AXLES_PER_CAR];
    double hold_switch[RB_AXLES_PER_CAR], vent_switch[RB_AXLES_PER_CAR]; /* s, when pending acts */
    /* emergency circuit (emergency_circuit.h) */
    uint8_t emergency_cut;          /* 1: the loop is open, the EP valve's seats cut off */
    uint8_t emergency;              /* 1: the emergency valve acts: its choke is open */
    double emergency_switch;        /* s; INFINITY: the loop is closed */
} rb_detailed_car;

typedef struct {
    rb_plant_state mech;            /* mechanics (x, v, wheel speeds, adhesion, ED) */
    rb_bcu_state bcu;
    rb_plant_inputs in;
    rb_plant_outputs out;
    rb_membrane membrane;
    rb_detailed_car car[RB_PLANT_MAX_CARS];
    rb_net_node line_node[RB_DET_LINE_NODES];
    rb_net_link line_link[RB_DET_LINE_LINKS];
    double line_y[RB_DET_LINE_STATES];
    double line_h;
    int compressor_on;
    uint8_t compressor_running[RB_MAX_COMPRESSORS];   /* governors of the plant's compressors */
    double m_compressed, m_charged_total, m_initial;
    double m_line_initial;          /* air in the main reservoir and MR pipes at t = 0 (air drawn) */
    long cycle;                     /* BCU cycles done */
    long substep;                   /* mechanics sub-steps done in the cycle */
    int n_sub;
    double dt_mech;
    /* air outputs at each sub-step of the cycle: per car supply, control, relay, vented; per axle
       cylinder; valve states at each sub-step */
    double buffer[RB_DET_MAX_SUBSTEPS][RB_DET_BUFFER];
    uint8_t hold_at[RB_DET_MAX_SUBSTEPS][RB_PLANT_MAX_AXLES], vent_at[RB_DET_MAX_SUBSTEPS][RB_PLANT_MAX_AXLES];
    /* run bookkeeping */
    int braking, finished, stopped;
    double brake_time, brake_position, brake_speed, next_record, max_slip;
    double max_disc_surface_temperature;   /* K, the hottest friction surface so far */
    size_t rows;
    rb_ode_stats stats;             /* summed over every solver call */
    /* scratch for the solver and the network evaluation */
    double work[RB_DET_MAX_STATES * RB_DET_MAX_STATES + 10 * RB_DET_MAX_STATES];
    int iwork[RB_DET_MAX_STATES + RB_DET_LINE_NODES];
    double eval_work[8 * RB_DET_LINE_NODES + RB_DET_LINE_LINKS + 2 * RB_DET_CAR_BODIES];
    double scale[RB_DET_MAX_STATES], y0[RB_DET_MAX_STATES];
    double t_out[RB_DET_MAX_SUBSTEPS + 2], y_out[(RB_DET_MAX_SUBSTEPS + 2) * RB_DET_MAX_STATES];
} rb_detailed_state;

rb_status rb_detailed_check(const rb_detailed_params *d, rb_error *err);
/* Checks everything and sets the state at t = 0 (as rb_plant_init: charged reservoirs, released
   brakes, rolling wheels). The EP drive must reach each car's bcu->pressure_max. */
rb_status rb_detailed_init(const rb_plant_params *plant, const rb_detailed_params *d, const rb_bcu_params *bcu,
                           const rb_wsp_params *wsp, const rb_scenario *sc, rb_detailed_state *s, rb_error *err);
/* As rb_run_advance: runs until t_until, the stop or max_time, writing rows of the rb_run channel
   layout into series (may be NULL). */
rb_status rb_detailed_advance(const rb_plant_params *plant, const rb_detailed_params *d,
                              const rb_bcu_params *bcu, const rb_scenario *sc, rb_detailed_state *s,
                              double t_until, double *series, size_t max_rows, int *finished, rb_error *err);
/* KPIs of rb_run.h that the detailed model gives: stopping distance and time, mean deceleration,
   max slip, air vented, air balance error, stopped (the others are 0). */
void rb_detailed_kpis(const rb_plant_params *plant, const rb_detailed_state *s, rb_kpis *k);
/* The EP valve current (A) whose static force balance gives the control pressure `pressure` (Pa
   abs) with the supply at `supply` (Pa abs); fails when it needs more than current_max. */
rb_status rb_detailed_epv_current(const rb_plant_params *plant, const rb_detailed_params *d, double supply,
                                  double pressure, double *current, rb_error *err);
/* One car's air alone (car 0 of plant) with a constant EP current and the WSP valves open/closed
   as given, from the released state for t_end seconds: pressures (Pa) of the nozzle chamber,
   control chamber, relay output and cylinder 1, and positions (m) of armature, piston, membrane. */
rb_status rb_detailed_valve_run(const rb_plant_params *plant, const rb_detailed_params *d, double current,
                                double t_end, double pressures[4], double positions[3], rb_error *err);
/* The air one car's valves use while WSP cycles its brakes (car 0 of plant, a constant EP current;
   detailed_air.c): filled for `settle` s, then `cycles` cycles of every axle's WSP valves, each
   phase[0] s venting, phase[1] s holding, phase[2] s refilling. air (kg, over the cycles): [0] EP
   feed orifice (the nozzle's bleed), [1] EP exhaust, [2] relay exhaust, [3] relay inlet, [4] cylinder
   vents. The plant's counterpart: rb_plant_valve_air (rb_plant.h). */
rb_status rb_detailed_valve_air(const rb_plant_params *plant, const rb_detailed_params *d, double current,
                                double settle, const double phase[3], int cycles, double air[5], rb_error *err);
/* Solver work so far: accepted and rejected steps and right-hand-side calls, summed over cars. */
void rb_detailed_stats(const rb_detailed_state *s, rb_ode_stats *stats);
size_t rb_detailed_state_size(void);

#ifdef __cplusplus
}
#endif
#endif

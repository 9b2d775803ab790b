/* Whole-train brake plant for a fixed 1 ms step (real-time reduced model).
 *
 * Fixed-size state, no allocation, no I/O, no global state: rb_plant_init / rb_plant_step /
 * rb_plant_get_outputs can be called from an FMU or a paced real-time loop. The brake control
 * unit (rb_bcu.h) is separate: it reads rb_plant_outputs and writes rb_plant_inputs.
 *
 * Model (docs/simulation.md). Air and wheelsets advance in `substeps` equal sub-steps h = dt /
 * substeps (1 at the nominal 1 ms: Python asks for sub-steps only above 2 ms); the BCU's inputs
 * are held over the step. Three timing rules make one 1 ms step as accurate as four of 0.25 ms:
 * a delayed valve's port area is weighted by the fraction of the step it is open; the brake
 * torque uses the step-mean cylinder pressure; each air link moves the exponential solution of
 * its linearised flow (below). The laws' constant parts are derived at rb_plant_init
 * (rb_plant_derived); every init recomputes them, so parameters may change between inits.
 *  - Air: lumped volumes (p = m R T / V; isothermal but for the brake cylinders, below) linked
 *    by orifices, advanced in phases (train
 *    line, then each car's EP and relay valves, then WSP valves and cylinders). With q the
 *    orifice flow and dm_eq the mass that would equalise the two nodes (volumes divided by their
 *    number of links), a link moves dm = dm_eq (1 - exp(-h |q| / dm_eq)) in a step: the
 *    exponential solution of the link linearised in its pressure difference, never beyond full
 *    equalisation (the WSP links take the exponential's rate from the link alone and cap the
 *    mass at their node's share: one 1 ms step moves what four of 0.25 ms do). Every link
 *    takes from one node what it gives the other, so air mass is conserved to round-off
 *    (vented and compressor air are booked).
 *  - Brake cylinders (wall_time > 0): state m and m T; the air taken brings its enthalpy
 *    (m T rises by gamma T_up dm), the air vented leaves with the cylinder's (m T falls by
 *    gamma T dm), the wall adds h A (T_wall - T) / cv per second; orifice flows scale with
 *    sqrt(T_wall / T_up). A fast fill rises gamma times the isothermal rise, then relaxes to it.
 *  - Per car: supply reservoir fed from the main-reservoir pipe through a check valve and a
 *    choke; EP valve (first-order lag on the pressure demand, inlet/exhaust ports opening in
 *    proportion to the error) filling a pilot volume, its pilot stage bleeding supply air through
 *    the feed orifice all the time; relay valve (supply/exhaust ports opening in proportion to
 *    pilot minus output pressure, lagged by the membrane's response; the membrane's stroke sweeps
 *    the pilot volume); per axle a WSP hold valve (output -> cylinder)
 *    and vent valve (cylinder -> atmosphere), each switching after a response delay.
 *  - Wheelsets: J dw/dt = -F r - T_brake - T_ed, F = Q f(creep) from Polach with rail
 *    conditioning by axle index or by rail cells the axles clean (rail_conditioning.c) and track zones; the slip velocity is advanced linearly
 *    implicitly with the secant creep stiffness (stable at 1 ms down to walking speed); a wheel
 *    whose speed would change sign is locked (static pad friction).
 *  - Cars: one mass per car, couplers, running resistance (rb_vehicle.h laws); symplectic Euler.
 */
#ifndef RAILBRAKE_PLANT_H
#define RAILBRAKE_PLANT_H

#include <stdint.h>

#include "railbrake/rb_common.h"
#include "railbrake/rb_contact.h"
#include "railbrake/rb_pneumatics.h"
#include "railbrake/rb_vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_PLANT_MAX_CARS 16
#define RB_AXLES_PER_CAR 4
#define RB_PLANT_MAX_AXLES (RB_PLANT_MAX_CARS * RB_AXLES_PER_CAR)
#define RB_MAX_CONDITIONS 4
#define RB_MAX_ZONES 8
#define RB_MAX_FAULTS 16
#define RB_MAX_COMPRESSORS 4
#define RB_MAX_GRADIENTS 16
#define RB_RAIL_MAX_CELLS 2048   /* rail cells under the train (rail_conditioning.c) */
#define RB_MAX_SANDERS 8

/* Wheelset kernel: the portable C99 one is the reference; the vector one (x86-64 AVX2, chosen at
 * run time when the CPU has it) computes the same operations in the same order, 4 axles at a time,
 * and gives the same results bit for bit. */
typedef enum {
    RB_PLANT_KERNEL_AUTO = 0,     /* the vector kernel where the CPU and the build have it */
    RB_PLANT_KERNEL_PORTABLE = 1,
    RB_PLANT_KERNEL_AVX2 = 2      /* in rb_plant_state.kernel only: what auto resolved to */
} rb_plant_kernel;

/* ---- parameters (SI units, absolute pressures) */

typedef struct {
    rb_car vehicle;           /* mass, wheelset, foundation brake, ED curve (rb_vehicle.h); 4 axles */
    double length;            /* m, over couplers */
    double axle_position[RB_AXLES_PER_CAR]; /* m from the car's front end */
    rb_creep_contact contact; /* Hertz/Kalker data of one wheel */
    double ed_tau;            /* s, ED force response (first-order lag) */
    /* the traction control's slide control of the ED brake (motor cars): while an axle of the car
       slides deeper than ed_slide_slip (braking slip, > 0) it cuts the car's ED force at
       ed_cut_rate (fraction per s), and once every axle is below ed_slide_release it restores it
       at ed_restore_rate; ed_slide_slip = 0: none */
    double ed_slide_slip, ed_slide_release, ed_cut_rate, ed_restore_rate;
    /* pneumatics */
    double supply_volume, pilot_volume, relay_volume, cylinder_volume, pipe_volume; /* m^3 */
    double charge_area;       /* m^2, check valve + choke from the MR pipe to the supply reservoir */
    double ep_area;           /* m^2, EP valve inlet and exhaust ports */
    double ep_tau;            /* s, EP valve response (first-order lag of the demand) */
    double ep_band;           /* Pa, error at which the EP ports are fully open */
    double ep_supply_margin;  /* Pa, >= 0: the EP output held at most this far below the supply
                                 reservoir (the EP piston's preload over its area: the nozzle chamber
                                 that drives it is fed from the supply) */
    double ep_bleed_area;     /* m^2, >= 0: the EP pilot stage's feed orifice, through which supply air
                                 bleeds out of the flapper nozzle all the time (0: none) */
    double relay_supply_area, relay_exhaust_area; /* m^2 */
    double relay_band;        /* Pa */
    double relay_tau;         /* s, >= 0: the relay membrane's response, a first-order lag of its
                                 stroke (0: none) */
    double relay_sweep;       /* m^3, >= 0: the control chamber's growth at the stroke that opens the
                                 inlet fully (the membrane's swept volume; the EP valve fills and
                                 exhausts it as the membrane strokes) */
    double relay_travel;      /* >= 1: the membrane's travel in units of that stroke (its stops) */
    double hold_area, vent_area; /* m^2, WSP valves per axle */
    double valve_delay;       /* s, WSP valve response delay */
    double pipe_area;         /* m^2, MR pipe link to the next car */
    /* brake discs of one axle, lumped (plant_train.c): heat capacity and cooling over speed */
    double disc_heat_capacity;        /* J/K per axle (0: no disc temperature) */
    rb_speed_table disc_cooling;      /* W/K per axle over the car's speed (n = 0: none) */
    /* emergency circuit (emergency_circuit.c): when the train's emergency loop opens
     * (rb_plant_inputs.emergency), the car's EP valve is cut off the relay's control chamber (the
     * loop de-energises it) and the car's emergency valve acts emergency_delay later (the loop's
     * propagation to this car, its relay's drop-out, the valve's response). Main-reservoir air then
     * goes through the load-weighing valve, which regulates it to the BCU's emergency demand but
     * never above its limit (emergency_limit, set by the car's load), and through a choke
     * (emergency_area: the nozzle that sets the filling rate) into the control chamber; the relay
     * valve amplifies the flow into the cylinders. emergency_area = 0: no emergency circuit, the
     * EP valve brakes in emergency too. */
    double emergency_delay;   /* s, >= 0 */
    double emergency_area;    /* m^2, >= 0 */
    double emergency_limit;   /* Pa absolute */
    /* the discs' friction surface (plant_train.c): a surface layer of heat capacity
     * disc_surface_capacity (J/K per axle, part of disc_heat_capacity) takes the braking power and
     * gives it to the air (disc_cooling) and through disc_surface_conductance (W/K per axle) to the
     * rest of the disc (its bulk). Its temperature is the friction surface's, which fades the pads
     * (rb_pad_friction). disc_surface_capacity = 0: one lumped disc, whose temperature the pads see. */
    double disc_surface_capacity;     /* J/K per axle, in [0, disc_heat_capacity) */
    double disc_surface_conductance;  /* W/K per axle, > 0 with a surface layer */
} rb_plant_car;

typedef struct {
    rb_polach_params polach;
    double leading_factor;    /* rail conditioning: mu0 factor on the leading axle (1: none) */
    double recovery_axles;    /* axles over which conditioning recovers (<= 0: none) */
    double reference_energy;  /* J/m^2, > 0: the rail is conditioned cell by cell by the energy the
                                 axles dissipate in the contact (rail_conditioning.c), instead of by
                                 axle index (recovery_axles must then be 0); 0: not; INFINITY:
                                 rail cells that sand conditions, not the sliding wheels */
} rb_plant_condition;

/* Track zone: axles between x_start and x_end (m along the track) see condition `condition`. */
typedef struct {
    double x_start, x_end;
    int condition;
} rb_track_zone;

typedef enum {
    RB_FAULT_HOLD_STUCK_OPEN = 0,
    RB_FAULT_HOLD_STUCK_CLOSED,
    RB_FAULT_VENT_STUCK_OPEN,
    RB_FAULT_VENT_STUCK_CLOSED,
    RB_FAULT_SENSOR_LOST,
    RB_FAULT_SENSOR_NOISY,    /* value: standard deviation, m/s */
    RB_FAULT_CYLINDER_LEAK,   /* value: leak area, m^2 */
    RB_FAULT_EP_VALVE,        /* EP valve ports close: pilot pressure frozen */
    RB_FAULT_ED_LOST,
    RB_FAULT_CAR_ISOLATED,    /* isolating cock: relay output cut off, cylinders vented */
    RB_FAULT_COMPRESSOR_OFF,
    /* the emergency path (emergency_circuit.c), per car: */
    RB_FAULT_EMERGENCY_VALVE, /* emergency valve does not open: EP cut off by the loop, choke shut */
    RB_FAULT_EMERGENCY_LOOP,  /* the car does not see the loop open: its EP valve goes on as demanded */
    RB_FAULT_RELAY_VALVE,     /* relay output held at most at value (Pa gauge; 0: no output) */
    RB_FAULT_LIMITER,         /* load-weighing valve / pressure limiter failed: limits the emergency
                                 control pressure to value (Pa gauge) instead of emergency_limit */
    RB_FAULT_AXLE_ISOLATED,   /* the axle's brake isolated (its bogie's cock): cylinder cut off
                                 from the relay and vented */
    RB_FAULT_PIPE_LEAK,       /* the car's main-reservoir pipe leaks to the atmosphere through an
                                 orifice of area value (m^2; the train has no brake pipe: the MR
                                 pipe is the one train line) */
    RB_FAULT_KINDS
} rb_fault_kind;

typedef struct {
    int kind;                 /* rb_fault_kind */
    int car;                  /* 0-based */
    int axle;                 /* 0..3 within the car; -1: every axle of the car */
    double start_time;        /* s */
    double value;
} rb_fault;

typedef struct {
    int n_cars;
    double dt;                /* s, 1e-3 nominal */
    int substeps;             /* air and wheelsets advance in this many equal sub-steps of dt (1..64) */
    double temperature;       /* K, air (isothermal model) */
    double atmosphere;        /* Pa */
    double discharge_coefficient, critical_ratio;
    rb_plant_car car[RB_PLANT_MAX_CARS];
    rb_coupler coupler;       /* between car i and i+1 */
    rb_resistance resistance; /* whole train, shared by mass */
    /* air supply */
    int compressor_car;
    double main_reservoir_volume, main_reservoir_area; /* m^3; m^2 link to the MR pipe */
    double compressor_flow;   /* kg/s when running */
    double governor_on, governor_off; /* Pa: starts below on, stops above off */
    double initial_pressure;  /* Pa, MR, pipe and supply reservoirs at t = 0 */
    double initial_speed;     /* m/s */
    /* adhesion */
    int n_conditions;
    rb_plant_condition condition[RB_MAX_CONDITIONS]; /* condition[0]: everywhere outside zones */
    int n_zones;
    rb_track_zone zone[RB_MAX_ZONES];
    double creep_speed_min;   /* m/s, creep = slip velocity / max(v, this) */
    /* faults */
    int n_faults;
    rb_fault fault[RB_MAX_FAULTS];
    uint64_t noise_seed;
    int kernel;               /* rb_plant_kernel: AUTO or PORTABLE */
    /* air supply with several compressors (plant_train.c); n_compressors = 0: the single
     * compressor above (compressor_car, compressor_flow). Compressor i feeds the main reservoir
     * when it sits on compressor_car, else the MR pipe of its car; its governor reads the
     * pressure it feeds (on/off at governor_on/governor_off). */
    int n_compressors;
    int compressor_position[RB_MAX_COMPRESSORS];    /* car, 0-based */
    double compressor_delivery[RB_MAX_COMPRESSORS]; /* kg/s when running */
    /* track gradient, piecewise constant in the position of each car's centre (m along the
     * track from the start); gradient[i] applies from gradient_start[i] on, gradient[0] also
     * before it. Rise over run, uphill positive. n_gradients = 0: level. */
    int n_gradients;
    double gradient_start[RB_MAX_GRADIENTS];
    double gradient[RB_MAX_GRADIENTS];
    double ambient_temperature;   /* K: discs at t = 0 and the cooling's reference */
    /* brake cylinders with an energy balance, as the detailed model's volumes: the air fills
     * adiabatically, expands on venting and exchanges heat with a wall at `temperature`;
     * wall_time (s): the time constant of that exchange for the cylinder's air at
     * RB_WALL_REFERENCE_PRESSURE (wall conductance h A = m_ref cv / wall_time, m_ref the air mass
     * at that pressure; at a lower pressure the air, having less mass, follows the wall faster).
     * 0: isothermal cylinders. */
    double wall_time;
    /* rail conditioning by dissipated energy (a condition's reference_energy > 0): the rail under
     * the train as cells of this length (m), at most RB_RAIL_MAX_CELLS over the train's length */
    double rail_cell_length;
    /* sanders (rail_conditioning.c), a conditioning source of the rail cells: sander i drops
     * sander_rate[i] kg/s, a table over its car's speed (m/s: one point for a fixed-rate sander,
     * more for a variable-rate one), in front of axle sander_axle[i] (global index) while it is
     * on: from sander_start[i] s (trigger RB_SAND_DRIVER), or while any WSP valve of the train is
     * commanded (RB_SAND_WSP). The sand lies loose on the cell; each axle that passes entrains
     * the fraction sand_entrained of it, m kg per metre of track, which multiplies the cell's
     * contamination by exp(-m / sand_reference), and leaves the fraction sand_retention of it
     * loose for the axles behind (the rest is carried away). */
    int n_sanders;
    int sander_axle[RB_MAX_SANDERS];
    int sander_trigger[RB_MAX_SANDERS];
    rb_speed_table sander_rate[RB_MAX_SANDERS];
    double sander_start[RB_MAX_SANDERS];
    double sand_reference;    /* kg/m */
    double sand_entrained;    /* fraction of the loose sand an axle passing crushes into the contact */
    double sand_retention;    /* fraction of it left loose behind the axle; sum of the two <= 1 */
} rb_plant_params;

typedef enum { RB_SAND_DRIVER = 0, RB_SAND_WSP = 1 } rb_sand_trigger;

/* ---- inputs (from the BCU) and outputs (to the BCU and the recorder) */

typedef struct {
    double pressure_demand[RB_PLANT_MAX_CARS]; /* Pa absolute, EP valve demand per car */
    double ed_demand[RB_PLANT_MAX_CARS];       /* N, ED brake force demand per car (>= 0) */
    uint8_t hold[RB_PLANT_MAX_AXLES];          /* 1: hold valve closed */
    uint8_t vent[RB_PLANT_MAX_AXLES];          /* 1: vent valve open */
    double emergency;                          /* 1: the train's emergency loop is open (a train line,
                                                  not a BCU output: the BCU only relays the demand) */
} rb_plant_inputs;

typedef struct {
    double time;
    double speed;                 /* m/s, leading car */
    double position;              /* m, leading car front */
    double deceleration;          /* m/s^2, leading car */
    double main_reservoir;        /* Pa */
    double pipe_end;              /* Pa, MR pipe at the last car */
    int compressor_on;
    double wheel_speed[RB_PLANT_MAX_AXLES];    /* m/s peripheral, true */
    double wheel_speed_measured[RB_PLANT_MAX_AXLES]; /* m/s, sensor; < 0: sensor lost */
    double slip[RB_PLANT_MAX_AXLES];           /* (w r - v) / v, braking negative */
    double adhesion[RB_PLANT_MAX_AXLES];       /* F/Q used, braking negative */
    double cylinder[RB_PLANT_MAX_AXLES];       /* Pa */
    uint8_t hold[RB_PLANT_MAX_AXLES], vent[RB_PLANT_MAX_AXLES]; /* actual valve states */
    double supply[RB_PLANT_MAX_CARS], pilot[RB_PLANT_MAX_CARS], relay[RB_PLANT_MAX_CARS]; /* Pa */
    double ed_force[RB_PLANT_MAX_CARS];        /* N, achieved */
    double ed_available[RB_PLANT_MAX_CARS];    /* N, the force the ED brake could give, before its slide
                                                  control's cut (the traction control's report to the BCU) */
    double car_speed[RB_PLANT_MAX_CARS];
    double air_in_system;         /* kg in every volume */
    double air_vented;            /* kg to the atmosphere since t = 0 */
    double air_compressed;        /* kg delivered by the compressor since t = 0 */
    double air_drawn;             /* kg taken from the main reservoir and its pipe since t = 0 */
    double disc_temperature[RB_PLANT_MAX_AXLES]; /* K, mean temperature of each axle's discs */
    double brake_energy[RB_PLANT_MAX_AXLES];     /* J, friction brake energy of each axle since t = 0 */
    double disc_surface_temperature[RB_PLANT_MAX_AXLES]; /* K, the friction surface's (the mean without
                                                            a surface layer) */
    double pad_friction[RB_PLANT_MAX_AXLES];     /* the pads' instantaneous friction coefficient */
} rb_plant_outputs;

/* ---- constants derived from the parameters at rb_plant_init (never set them: init does) */

typedef struct {
    double h;                   /* s, air and wheelset step: dt / substeps */
    double g_unit;              /* kg/(s Pa m^2): Cd x choked factor / sqrt(T), times area = conductance */
    rb_orifice_law orifice;
    /* air: node stiffness k = R T / V (Pa/kg), link conductances (kg/(s Pa)) and
       1 / (n_i k_i + n_j k_j) per link (kg/Pa), n being each node's number of links */
    double k_mr, g_mr, ik_mr;
    double k_pipe[RB_PLANT_MAX_CARS], k_supply[RB_PLANT_MAX_CARS], k_pilot[RB_PLANT_MAX_CARS];
    double k_relay[RB_PLANT_MAX_CARS], k_cyl[RB_PLANT_MAX_CARS];
    double g_pipe[RB_PLANT_MAX_CARS], ik_pipe[RB_PLANT_MAX_CARS];   /* car c -> c + 1 */
    double g_charge[RB_PLANT_MAX_CARS], ik_charge[RB_PLANT_MAX_CARS];
    double ik_pipe_leak[RB_PLANT_MAX_CARS];   /* a leak from the car's MR pipe (RB_FAULT_PIPE_LEAK) */
    double g_ep[RB_PLANT_MAX_CARS], ik_ep_in[RB_PLANT_MAX_CARS], ik_ep_out[RB_PLANT_MAX_CARS];
    double g_relay_supply[RB_PLANT_MAX_CARS], g_relay_exhaust[RB_PLANT_MAX_CARS];
    double ik_relay_supply[RB_PLANT_MAX_CARS], ik_relay_exhaust[RB_PLANT_MAX_CARS];
    double g_hold[RB_PLANT_MAX_CARS], g_vent[RB_PLANT_MAX_CARS], ik_hold[RB_PLANT_MAX_CARS], ik_vent[RB_PLANT_MAX_CARS];
    double inv_ep_band[RB_PLANT_MAX_CARS], inv_relay_band[RB_PLANT_MAX_CARS], ep_lag[RB_PLANT_MAX_CARS];
    double ep_supply_margin[RB_PLANT_MAX_CARS];   /* Pa: the car's, compact for the EP valves' loop */
    double g_bleed[RB_PLANT_MAX_CARS];   /* kg/(s Pa), the EP feed orifice's conductance */
    double relay_lag[RB_PLANT_MAX_CARS]; /* 1 - exp(-h / relay_tau): the relay stroke's step (1: none) */
    double sweep_ratio[RB_PLANT_MAX_CARS]; /* relay_sweep / pilot_volume */
    double relay_travel[RB_PLANT_MAX_CARS];
    double g_emergency[RB_PLANT_MAX_CARS];   /* kg/(s Pa), the emergency choke's conductance */
    double pilot_heat[RB_PLANT_MAX_CARS];    /* kg: h x the control chamber wall's h A / cv (plant_pilot.c) */
    /* mechanics per car */
    double inv_mass[RB_PLANT_MAX_CARS];
    double mass_share[RB_PLANT_MAX_CARS];    /* car mass / train mass */
    double radius[RB_PLANT_MAX_CARS], inv_inertia[RB_PLANT_MAX_CARS], axle_load[RB_PLANT_MAX_CARS];
    double compliance[RB_PLANT_MAX_CARS];    /* r^2 / J + 1 / m: slip velocity per impulse */
    double polach_gain[RB_PLANT_MAX_CARS];   /* G pi a b c11 / (4 N): Polach's epsilon = gain |creep| / mu */
    double brake_gain[RB_PLANT_MAX_CARS];    /* discs x 2 x mean radius x lever x efficiency */
    double caliper_atmosphere[RB_PLANT_MAX_CARS], caliper_area[RB_PLANT_MAX_CARS];
    double caliper_spring[RB_PLANT_MAX_CARS];
    /* Polach per axle (refreshed with the axle's zone): mu = (mu_static + mu_slip exp(-B w)) / (1 + v
       v_ref_inv) (the rolling-speed factor, exactly 1 with v_ref_inv 0); k_A and k_S times the car's
       polach_gain (k_A eps = kA_gain |creep| / mu) */
    double mu_static[RB_PLANT_MAX_AXLES], mu_slip[RB_PLANT_MAX_AXLES], polach_v_ref_inv[RB_PLANT_MAX_AXLES];
    double polach_B[RB_PLANT_MAX_AXLES], polach_kA_gain[RB_PLANT_MAX_AXLES], polach_kS_gain[RB_PLANT_MAX_AXLES];
    /* each axle's last pad-table interval, speed[lo] <= wheel speed < speed[lo + 1], with its ends,
       value and slope (so the kernel interpolates without the table or a division; empty at init:
       pad_speed_lo = pad_speed_hi, never hit) */
    int pad_bracket[RB_PLANT_MAX_AXLES];
    double pad_speed_lo[RB_PLANT_MAX_AXLES], pad_speed_hi[RB_PLANT_MAX_AXLES];
    double pad_value_lo[RB_PLANT_MAX_AXLES], pad_slope[RB_PLANT_MAX_AXLES];
    int cooling_bracket[RB_PLANT_MAX_CARS];  /* last disc-cooling table interval of each car */
    double h_laminar;           /* s: h x the orifice law's laminar slope (rb_plant_link_mass) */
    /* the laminar fill 1 - exp(-h_laminar g / ik) of the links of fixed g and ik
       (rb_plant_link_mass_fixed) */
    double fill_mr, fill_pipe[RB_PLANT_MAX_CARS], fill_charge[RB_PLANT_MAX_CARS];
    /* the per-car constants of the wheelset kernel repeated for each axle (its passes run over the
       train's axles in one loop: full vectors, no per-car set-up) */
    double axle_radius[RB_PLANT_MAX_AXLES], axle_inv_inertia[RB_PLANT_MAX_AXLES], axle_inv_mass[RB_PLANT_MAX_AXLES];
    double axle_axle_load[RB_PLANT_MAX_AXLES], axle_compliance[RB_PLANT_MAX_AXLES];
    /* friction torque = pad friction x max(p_cyl brake_per_pa - brake_offset, 0): brake_gain x the
       caliper's pad force (cylinder area (p - atmosphere) - return spring) with the factors merged */
    double axle_brake_per_pa[RB_PLANT_MAX_AXLES], axle_brake_offset[RB_PLANT_MAX_AXLES];
    double axle_inv_axle_load[RB_PLANT_MAX_AXLES];   /* 1 / axle load: the adhesion coefficient output */
    /* cylinders' energy balance (rb_plant_params.wall_time): state m T, pressure R (m T) / V */
    double gamma_cyl;                        /* adiabatic exponent; 1: isothermal (wall_time = 0) */
    double r_cyl[RB_PLANT_MAX_CARS];         /* R / V_cylinder, Pa/(kg K) */
    double axle_heat_cyl[RB_PLANT_MAX_AXLES]; /* kg: h x h A / cv, times (wall - air temperature) the
                                                step's change of m T by the wall */
    /* the WSP links' exponential rates from the link alone, 1 / (k_i + k_j) with the adiabatic
       stiffness gamma k of the cylinder (the shared ik_hold, ik_vent only cap them) */
    double ik_hold_rate[RB_PLANT_MAX_CARS], ik_vent_rate[RB_PLANT_MAX_CARS];
    double hold_laminar[RB_PLANT_MAX_CARS];  /* kg/Pa: the open hold link's step mass per Pa in its
                                                laminar region, relay air (rb_plant_link_mass_capped) */
    /* the same per axle (the cylinders' vector pass), and the vent valves' conductance */
    double axle_hold_laminar[RB_PLANT_MAX_AXLES], axle_g_vent[RB_PLANT_MAX_AXLES];
    /* what the rest of the step reads of the cars, compact (the car records are 3.6 kB each) */
    double axle_r_cyl[RB_PLANT_MAX_AXLES];   /* r_cyl of the axle's car: cylinder pressure = mt_cyl x it */
    double car_length[RB_PLANT_MAX_CARS], ed_lag[RB_PLANT_MAX_CARS];   /* m; h / (ed_tau + h) */
    double supply_volume[RB_PLANT_MAX_CARS];  /* m^3 (the outputs' supply pressures) */
    double disc_capacity[RB_PLANT_MAX_CARS];  /* J/K per axle: the surface layer's (all of it without one) */
    double disc_bulk_capacity[RB_PLANT_MAX_CARS];  /* J/K per axle: the rest (0 without a surface layer) */
    double disc_conductance[RB_PLANT_MAX_CARS];    /* W/K per axle, surface to bulk (0 without a surface layer) */
    /* the pads' heat fading per axle (rb_pad_friction of the axle's car) */
    double pad_fade_onset[RB_PLANT_MAX_AXLES], pad_fade_rate[RB_PLANT_MAX_AXLES];
    /* each car's last disc-cooling interval (cooling_bracket), as the pad's above */
    double cooling_lo[RB_PLANT_MAX_CARS], cooling_hi[RB_PLANT_MAX_CARS];
    double cooling_value_lo[RB_PLANT_MAX_CARS], cooling_slope[RB_PLANT_MAX_CARS];
    /* the wheelset kernel's secant probe, in steps of the last slip change ahead of the step's start:
       1 (init) for the plant, so that its 1 ms rail force does not lag a moving slip; the detailed
       model sets 0 for its fine mechanics step (its method unchanged, plant_kernel.c) */
    double slip_probe_ahead;
} rb_plant_derived;

/* ---- state (fixed size; plain data, may be copied) */

typedef struct {
    int64_t step;
    double time;
    /* air masses, kg */
    double m_mr;
    double m_pipe[RB_PLANT_MAX_CARS], m_supply[RB_PLANT_MAX_CARS], m_pilot[RB_PLANT_MAX_CARS], m_relay[RB_PLANT_MAX_CARS];
    double m_cyl[RB_PLANT_MAX_AXLES];
    double m_vented, m_compressed;
    double m_valves_vented;   /* kg, the part of m_vented the EP and relay valves let out (bleed, exhausts) */
    int compressor_on;
    double ep_demand_lag[RB_PLANT_MAX_CARS];   /* Pa, EP valve's lagged demand */
    double relay_stroke[RB_PLANT_MAX_CARS];    /* relay membrane's stroke: 1 opens the inlet fully, -1
                                                  the exhaust; within +-relay_travel */
    /* WSP valves: actual state and the command waiting for the response delay */
    uint8_t hold[RB_PLANT_MAX_AXLES], vent[RB_PLANT_MAX_AXLES];
    uint8_t hold_pending[RB_PLANT_MAX_AXLES], vent_pending[RB_PLANT_MAX_AXLES];
    double hold_timer[RB_PLANT_MAX_AXLES], vent_timer[RB_PLANT_MAX_AXLES];
    uint8_t hold_effective[RB_PLANT_MAX_AXLES], vent_effective[RB_PLANT_MAX_AXLES]; /* with stuck faults */
    /* mechanics */
    double x[RB_PLANT_MAX_CARS], v[RB_PLANT_MAX_CARS], a[RB_PLANT_MAX_CARS];
    double omega[RB_PLANT_MAX_AXLES];
    double force[RB_PLANT_MAX_AXLES], coefficient[RB_PLANT_MAX_AXLES];
    double ed_force[RB_PLANT_MAX_CARS];
    /* adhesion: zone seen by each axle, cached Polach parameters */
    int zone_of[RB_PLANT_MAX_AXLES];
    rb_polach_params polach[RB_PLANT_MAX_AXLES];
    /* faults */
    uint64_t rng;
    double noise[RB_PLANT_MAX_AXLES];          /* m/s added to the measured wheel speed */
    uint8_t sensor_lost[RB_PLANT_MAX_AXLES];
    double m_initial;
    int kernel;               /* rb_plant_kernel in use (PORTABLE or AVX2), resolved at init */
    rb_plant_derived derived; /* constants of the laws, derived from the parameters at init */
    /* plant_train.c */
    uint8_t compressor_running[RB_MAX_COMPRESSORS];
    double m_supply_side_initial; /* kg in the main reservoir and pipe at t = 0 */
    double disc_temperature[RB_PLANT_MAX_AXLES]; /* K, the friction surface's (the lumped disc's without a
                                                    surface layer) */
    double disc_bulk_temperature[RB_PLANT_MAX_AXLES]; /* K, the disc under the surface layer */
    double pad_friction[RB_PLANT_MAX_AXLES];     /* the pads' friction coefficient in the last step (kernel) */
    double brake_energy[RB_PLANT_MAX_AXLES];     /* J */
    double brake_torque[RB_PLANT_MAX_AXLES];     /* N m, friction brake torque of the last step (kernel) */
    int sensors_written;      /* a sensor fault has set noise or loss since the last clearing */
    /* each cylinder's air mass times its temperature (kg K): pressure R (m T) / V (isothermal:
       m times the wall's temperature) */
    double mt_cyl[RB_PLANT_MAX_AXLES];
    double slip_start[RB_PLANT_MAX_AXLES];   /* m/s: each axle's slip velocity at the start of its last
                                                wheelset update (plant_kernel.c: the probe's extrapolation) */
    /* the rail under the train (rail_conditioning.c): a ring of cells, cell i of the track (x in
     * [i, i + 1) cell lengths) in slot i mod RB_RAIL_MAX_CELLS; rail_front: the foremost cell an
     * axle has entered (cells ahead of it are as laid) */
    int rail_active;
    int64_t rail_front;
    double rail_contamination[RB_RAIL_MAX_CELLS];   /* 1: as laid, 0: cleaned */
    double rail_sand[RB_RAIL_MAX_CELLS];            /* kg per metre of track: loose sand on the cell */
    int64_t axle_cell[RB_PLANT_MAX_AXLES];          /* the last cell each axle met (rb_rail_factor's) */
    double sand_used;         /* kg the sanders dropped since t = 0 */
    /* emergency circuit (emergency_circuit.c) */
    double loop_open_time;                        /* s, when the emergency loop opened; < 0: closed */
    double emergency_open[RB_PLANT_MAX_CARS];     /* 1: the loop is open and the car has the circuit:
                                                     its EP valve is cut off (a double: read in the
                                                     valves' vector loops) */
    double emergency_g[RB_PLANT_MAX_CARS];        /* kg/(s Pa), the choke's conductance once the car's
                                                     emergency valve acts, 0 before */
    double emergency_target[RB_PLANT_MAX_CARS];   /* Pa, the control pressure it fills to */
    double pilot_theta[RB_PLANT_MAX_CARS];        /* the control chamber air's temperature over the
                                                     wall's (plant_pilot.c; 1: isothermal) */
    double pilot_volume[RB_PLANT_MAX_CARS];       /* its volume over the volume at rest at the last
                                                     update (the membrane's sweep) */
    /* ED brake: the force the traction control is asked for (after its response lag) and the
       fraction of it its slide control lets through (1: no slide; ed_force = the product) */
    double ed_asked[RB_PLANT_MAX_CARS], ed_slide_factor[RB_PLANT_MAX_CARS];
} rb_plant_state;

/* Checks every parameter; the message names the field, its value and the allowed range. */
rb_status rb_plant_check(const rb_plant_params *p, rb_error *err);
/* Checks one fault of a train of n_cars; the message names it as `name` (e.g. "fault[2]"). */
rb_status rb_fault_check(const rb_fault *f, int n_cars, const char *name, rb_error *err);
/* The name of a fault kind as scenario files write it ("vent_stuck_open"; "unknown" outside the kinds). */
const char *rb_fault_kind_name(int kind);
/* Checks p and sets the state at t = 0: charged reservoirs, released brakes, rolling wheels. */
rb_status rb_plant_init(const rb_plant_params *p, rb_plant_state *s, rb_error *err);
/* After p->condition[*].polach changed during a run (a tuned adhesion): checks p and derives every
 * axle's adhesion again from its current track zone; acts from the next rb_plant_step. */
rb_status rb_plant_retune_adhesion(const rb_plant_params *p, rb_plant_state *s, rb_error *err);
/* Advances one step of p->dt. No checks, no allocation. */
void rb_plant_step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in);
void rb_plant_get_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out);
/* The same into outputs that rb_plant_get_outputs filled for this plant before (a loop's own
 * copy): the cars' and axles' entries, without clearing the unused rest each step. */
void rb_plant_update_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out);
/* Only what a run reads after every step (rb_run_advance): time, speed, position, main_reservoir,
 * supply, car_speed, wheel_speed, slip, cylinder, hold, vent, disc_temperature; the rest keeps
 * its last values until rb_plant_update_outputs. */
void rb_plant_update_step_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out);
/* Air mass in every volume of the plant, kg. */
double rb_plant_air_mass(const rb_plant_params *p, const rb_plant_state *s);
/* Brake torque of one axle at cylinder pressure p_cyl and wheel peripheral speed (N m). */
double rb_plant_axle_brake_torque(const rb_plant_car *c, double p_cyl, double wheel_speed);
/* Peak adhesion available to axle (global index from the front) at the present state. */
double rb_plant_peak_adhesion(const rb_plant_params *p, const rb_plant_state *s, int axle);
/* The same for loops that sample it over a run, on the curve the wheelset kernel applies (equal
 * to rounding): followed from *log_creep (rb_creep_peak_track; NaN the first time and after the
 * axle's adhesion condition changed; maxima = NULL), or searched afresh, counting the curve's
 * maxima into *maxima (rb_creep_peak_scan). */
double rb_plant_peak_adhesion_track(const rb_plant_params *p, const rb_plant_state *s, int axle, double *log_creep,
                                    int *maxima);
/* rb_plant_peak_adhesion_track (maxima = NULL) of n axles at once (rb_creep_peaks_track): peak[i]
 * and log_creep[i] those of axles[i] (n <= RB_PLANT_MAX_AXLES); the same results. */
void rb_plant_peaks_track(const rb_plant_params *p, const rb_plant_state *s, const int *axles, int n,
                          double *log_creep, double *peak);
/* "portable" or "avx2": the wheelset kernel the state uses. */
const char *rb_plant_kernel_name(const rb_plant_state *s);
size_t rb_plant_params_size(void);
size_t rb_plant_state_size(void);

/* The air one car's valves use while WSP cycles its brakes, in the plant (valve_reduced.c; the
   detailed model's counterpart is rb_detailed_valve_air): car 0 of plant alone, at rest, with the
   constant pressure demand `demand` (Pa abs): filled for `settle` s, then `cycles` WSP cycles of every
   axle, each phase[0] s venting (hold shut, vent open), phase[1] s holding (both shut) and phase[2]
   s refilling. air (kg, over the cycles): [0] what the EP and relay valves let out (bleed,
   exhausts), [1] what the cylinders' vents did. */
rb_status rb_plant_valve_air(const rb_plant_params *plant, double demand, double settle, const double phase[3],
                             int cycles, double air[2], rb_error *err);
/* The WSP cycle's arguments of the valve air studies (this one's and rb_detailed_valve_air's):
   settle in [0, 100] s, each phase in [1 ms, 10 s], cycles in [1, 10000]. */
rb_status rb_valve_air_cycle_check(double settle, const double phase[3], int cycles, rb_error *err);

#ifdef __cplusplus
}
#endif
#endif

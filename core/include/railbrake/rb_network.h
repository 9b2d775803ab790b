/* Pneumatic networks with moving bodies, simulated whole inside the core with the stiff
 * integrator (rb_ode.h): reservoirs (fixed p, T), lumped volumes (m, T states; optional wall heat
 * transfer and prescribed volume rate), orifices whose area is fixed, scheduled in time (solenoid
 * valves, with a response delay) or driven by a body position (flapper-nozzle, seat, spool edge),
 * and bodies (mass, preloaded spring, damping, regularised Coulomb friction, end stops, pressure
 * faces of constant area or membrane A_eff(x), solenoid force from a 2-D table F(airgap, current)).
 * The topology is flat arrays of fixed-size structs built by the caller (Python compiles it). */
#ifndef RAILBRAKE_NETWORK_H
#define RAILBRAKE_NETWORK_H

#include "railbrake/rb_common.h"
#include "railbrake/rb_ode.h"
#include "railbrake/rb_pneumatics.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_SCHEDULE_MAX 16
/* Piecewise-linear value over time, evaluated at t - delay; n = 0 means the constant 1.
   Before the first point: the first value; after the last: the last value. */
typedef struct {
    int n;
    double delay;                  /* s, >= 0 */
    double t[RB_SCHEDULE_MAX];     /* s, non-decreasing */
    double value[RB_SCHEDULE_MAX];
} rb_schedule;
double rb_schedule_eval(const rb_schedule *s, double t);

#define RB_FORCE_TABLE_MAX 16
/* Solenoid force (N, along +x of its body) on a grid of airgap (m, strictly increasing) and
   current (A, strictly increasing); bilinear inside, clamped to the edge values outside. */
typedef struct {
    int n_gap, n_current;
    double gap[RB_FORCE_TABLE_MAX];
    double current[RB_FORCE_TABLE_MAX];
    double force[RB_FORCE_TABLE_MAX * RB_FORCE_TABLE_MAX]; /* row-major [gap][current] */
} rb_force_table;
rb_status rb_force_table_check(const rb_force_table *f, rb_error *err);
double rb_force_table_eval(const rb_force_table *f, double gap, double current);

enum { RB_NODE_RESERVOIR = 0, RB_NODE_VOLUME = 1 };
typedef struct {
    int kind;
    double pressure, temperature;  /* Pa, K: fixed (reservoir) or initial (volume) */
    double volume;                 /* m^3 with every body at x = 0 */
    double volume_rate;            /* prescribed dV/dt, m^3/s */
    double heat_conductance;       /* h A, W/K; 0 = adiabatic */
    double wall_temperature;       /* K */
} rb_net_node;

enum { RB_LINK_FIXED = 0, RB_LINK_FLAPPER = 1, RB_LINK_SEAT = 2, RB_LINK_SPOOL = 3 };
typedef struct {
    int kind, from, to;            /* node indices; flow positive from -> to */
    rb_orifice orifice;            /* FIXED: full description; others: discharge coefficient, b */
    int body;                      /* driving body (not FIXED) */
    double diameter;               /* m: nozzle, seat or spool diameter */
    double offset, direction;      /* opening = direction * (x - offset), direction = +-1 */
    double shape;                  /* SEAT: half angle (rad); SPOOL: radial clearance (m) */
    rb_schedule opening;           /* multiplies the area, in [0, 1] */
} rb_net_link;

#define RB_BODY_FACES 4
typedef struct {
    double mass;                   /* kg */
    double spring_rate;            /* N/m */
    double spring_preload;         /* N at x = 0; the spring force is -(preload + rate x) */
    double damping;                /* N s/m */
    double friction;               /* Coulomb sealing friction, N */
    double friction_velocity;      /* m/s: friction = -F tanh(v / this) */
    double x_min, x_max;           /* m, end stops */
    double stop_stiffness, stop_damping;
    double x_initial;              /* m */
    double force;                  /* constant external force along +x, N */
    double ambient_pressure;       /* Pa, on the other side of every face */
    int n_faces;
    int face_node[RB_BODY_FACES];
    int face_membrane[RB_BODY_FACES];      /* -1: constant face_area */
    double face_area[RB_BODY_FACES];       /* m^2 */
    double face_direction[RB_BODY_FACES];  /* +1: the node's pressure pushes +x, its volume grows with x */
    int force_table;               /* -1: no solenoid */
    double airgap_initial;         /* m at x = 0; airgap = airgap_initial - x */
    rb_schedule current;           /* A */
} rb_net_body;

typedef struct {
    const rb_net_node *nodes;       size_t n_nodes;
    const rb_net_link *links;       size_t n_links;
    const rb_net_body *bodies;      size_t n_bodies;
    const rb_force_table *tables;   size_t n_tables;
    const rb_membrane *membranes;   size_t n_membranes;
} rb_network;

rb_status rb_network_check(const rb_network *net, rb_error *err);
/* Doubles of work for rb_network_simulate; *n_int receives the ints of iwork. */
size_t rb_network_workspace_size(const rb_network *net, size_t n_out, size_t *n_int);
/* Simulates from t = 0 to t_out[n_out - 1]; outputs row-major [n_out][n_nodes|n_links|n_bodies]:
   node pressure (Pa), temperature (K), mass (kg, 0 for reservoirs), link mass flow (kg/s),
   body position (m) and velocity (m/s). */
rb_status rb_network_simulate(const rb_network *net, const double *t_out, size_t n_out,
                              const rb_ode_options *opt, double *work, size_t work_size, int *iwork,
                              double *node_p, double *node_T, double *node_m, double *link_mdot,
                              double *body_x, double *body_v, rb_ode_stats *stats, rb_error *err);

/* The network's rates for callers that drive rb_ode themselves, e.g. restarting at each cycle of
   a sampled controller that changes currents, openings or reservoir pressures in between (the
   detailed train model, rb_detailed.h). State layout: (m, T) of each volume node in node order,
   then (x, v) of each body. After a call, p, T, mdot, x, v hold that evaluation's values. */
typedef struct {
    const rb_network *net;
    size_t n_volumes;
    int *state_of_node;   /* index of m in y, -1 for reservoirs */
    double *p, *T, *V, *dV, *m_in, *h_in, *m_out, *mdot, *x, *v;
    int volume_error;     /* set when a volume becomes <= 0 (the step is then rejected) */
} rb_network_eval;

size_t rb_network_state_count(const rb_network *net);
/* Doubles (return) and ints (*n_int) of storage an rb_network_eval needs. */
size_t rb_network_eval_size(const rb_network *net, size_t *n_int);
/* Checks net, lays the evaluation out in work / iwork, and writes the initial state y0 (masses from
   the nodes' initial pressures at the bodies' initial positions) and the absolute-tolerance
   scales of each state (may be NULL). */
rb_status rb_network_eval_init(const rb_network *net, rb_network_eval *ev, double *work, size_t work_size,
                               int *iwork, size_t iwork_size, double *y0, double *atol_scale, rb_error *err);
/* dy/dt of the network; an rb_ode_rhs with user = the rb_network_eval. */
void rb_network_rates(double t, const double *y, double *dydt, void *ev);

#ifdef __cplusplus
}
#endif
#endif

/* Private to the plant. */
#ifndef RAILBRAKE_PLANT_INTERNAL_H
#define RAILBRAKE_PLANT_INTERNAL_H

#include "railbrake/rb_plant.h"
#include "railbrake/rb_pneumatics.h"

/* The vector wheelset kernel is compiled where GCC or Clang target x86 (function-level target
   attributes, run-time CPU check); -DRB_PLANT_PORTABLE_ONLY leaves it out. */
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__)) && \
    !defined(RB_PLANT_PORTABLE_ONLY)
#define RB_PLANT_HAVE_AVX2 1
#else
#define RB_PLANT_HAVE_AVX2 0
#endif

/* Inline every call in the function's body (its own file's functions), so that a copy compiled for
   another instruction set (function-level target attribute) computes all of it there. */
#if defined(__GNUC__) || defined(__clang__)
#define RB_FLATTEN __attribute__((flatten))
#else
#define RB_FLATTEN
#endif

#define RB_G 9.80665

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* Mass (kg) one link moves from node i to node j (pressures pi, pj) in a step of d->h, through
 * conductance g (kg/(s Pa)); ik = 1 / (n_i k_i + n_j k_j), so (pi - pj) ik is the mass that would
 * equalise the nodes (each node's volume shared among its links). The exponential solution of the
 * link linearised in its pressure difference: dm = dm_eq (1 - exp(-y)), y = h q / dm_eq with q the
 * orifice flow (rb_orifice_flow_law): h q when the link is slow, never beyond equalisation when it
 * is stiff. The law is written in y directly, so the chain of links along the train waits on few
 * operations: near equal pressures (down >= RB_ORIFICE_LAMINAR_RATIO up) the flow is linear in the
 * difference, g slope (pi - pj), and y = h slope g / ik does not depend on the pressures at all;
 * elsewhere y = [h g p_up / (|pi - pj| ik)] phi(p_down / p_up), the bracket computed alongside the
 * pressure ratio. */
static inline double rb_plant_link_mass(const rb_plant_derived *d, double pi, double pj, double g, double ik)
{
    double diff = pi - pj;
    if (!(g > 0.0) || fabs(diff) < 0.01) return 0.0;   /* closed, or balanced to 0.01 Pa */
    double up = diff > 0.0 ? pi : pj, down = diff > 0.0 ? pj : pi, y;
    if (down >= RB_ORIFICE_LAMINAR_RATIO * up && !d->orifice.laminar_only)
        y = d->h_laminar * g / ik;
    else
        y = d->h * g * up / (fabs(diff) * ik) * rb_orifice_flow_function_law(down / up, &d->orifice);
    return diff * ik * rb_one_minus_exp_neg(y);
}

/* The constants of rb_plant_link_mass as a caller's local copy (its loop then loads nothing that
 * might not be there, and the compiler computes every arm). */
typedef struct {
    double h, h_laminar, b, inv_one_minus_b, laminar_slope;
    int laminar_only;
} rb_plant_link_law;

static inline rb_plant_link_law rb_plant_link_law_of(const rb_plant_derived *d)
{
    rb_plant_link_law k;
    k.h = d->h; k.h_laminar = d->h_laminar; k.b = d->orifice.b; k.inv_one_minus_b = d->orifice.inv_one_minus_b;
    k.laminar_slope = d->orifice.laminar_slope; k.laminar_only = d->orifice.laminar_only;
    return k;
}

/* rb_orifice_flow_function_law with every arm computed and the result selected (the same value;
 * a NaN, which an arm not taken may hold, is never selected). */
static inline double rb_plant_flow_function_select(const rb_plant_link_law *k, double r)
{
    double s = (r - k->b) * k->inv_one_minus_b;   /* rb_orifice_flow_function_law's arms */
    double subsonic = sqrt(1.0 - s * s), linear = k->laminar_slope * (1.0 - r), only = (1.0 - r) * k->inv_one_minus_b;
    return r <= k->b ? 1.0 : (k->laminar_only ? only : (r >= RB_ORIFICE_LAMINAR_RATIO ? linear : subsonic));
}

/* rb_plant_link_mass with every arm computed (rb_orifice_flow_function_law's included) and the
 * result selected: no branch, so a loop over the cars of it vectorises. Each arm is the same
 * operations on the same operands, so the result is the same bit for bit
 * (core/tests/test_plant_kernel.c compares the two). In two parts: the exponent y, then the mass
 * from y and the link's fill 1 - exp(-y) (rb_one_minus_exp_neg_select, or its series alone where no
 * y of a pass exceeds the series' range: the same value there). */
static inline double rb_plant_link_y_select(const rb_plant_link_law *k, double pi, double pj, double g, double ik)
{
    double diff = pi - pj, abs_diff = fabs(diff);
    double up = diff > 0.0 ? pi : pj, down = diff > 0.0 ? pj : pi, r = down / up;
    double phi = rb_plant_flow_function_select(k, r);
    double y_laminar = k->h_laminar * g / ik, y_general = k->h * g * up / (abs_diff * ik) * phi;
    return k->laminar_only ? y_general : (down >= RB_ORIFICE_LAMINAR_RATIO * up ? y_laminar : y_general);
}

static inline double rb_plant_link_mass_of_fill(double pi, double pj, double g, double ik, double fill)
{
    double diff = pi - pj, dm = diff * ik * fill;
    return g > 0.0 ? (fabs(diff) < 0.01 ? 0.0 : dm) : 0.0;   /* closed, or balanced to 0.01 Pa: nothing */
}

static inline double rb_plant_link_mass_select(const rb_plant_link_law *k, double pi, double pj, double g, double ik)
{
    double y = rb_plant_link_y_select(k, pi, pj, g, ik);
    return rb_plant_link_mass_of_fill(pi, pj, g, ik, rb_one_minus_exp_neg_select(y));
}

/* The fill 1 - exp(-y) of a link of fixed conductance g in its laminar region, y = h slope g / ik:
 * rb_plant_link_mass's, once at init (rb_plant_link_laminar_fill) for the links whose g and ik never
 * change (main reservoir, MR pipe, charge chokes); 0 for a closed link. */
static inline double rb_plant_link_laminar_fill(const rb_plant_derived *d, double g, double ik)
{
    return g > 0.0 ? rb_one_minus_exp_neg(d->h_laminar * g / ik) : 0.0;
}

/* rb_plant_link_mass of a link of fixed g and ik with its laminar fill from init: the same
 * operations on the same operands, so the same result. */
static inline double rb_plant_link_mass_fixed(const rb_plant_derived *d, double pi, double pj, double g, double ik,
                                              double laminar_fill)
{
    double diff = pi - pj;
    if (!(g > 0.0) || fabs(diff) < 0.01) return 0.0;   /* closed, or balanced to 0.01 Pa */
    double up = diff > 0.0 ? pi : pj, down = diff > 0.0 ? pj : pi;
    if (down >= RB_ORIFICE_LAMINAR_RATIO * up && !d->orifice.laminar_only) return diff * ik * laminar_fill;
    double y = d->h * g * up / (fabs(diff) * ik) * rb_orifice_flow_function_law(down / up, &d->orifice);
    return diff * ik * rb_one_minus_exp_neg(y);
}

/* rb_plant_link_mass with the exponential's rate from the link alone (ik_rate = 1 / (k_i + k_j)),
 * capped at the equalising mass of the nodes' shares (ik_cap = 1 / (n_i k_i + n_j k_j) <= ik_rate).
 * The shared ik in the exponent makes a slow link's flow fall n times too fast within the step
 * (a WSP vent moved 1.2 % less air per pulse at 1 ms than at 0.25 ms); the cap keeps every link,
 * together with its node's others, from overshooting equalisation when it is stiff. */
static inline double rb_plant_link_mass_capped(const rb_plant_derived *d, double pi, double pj, double g,
                                               double ik_rate, double ik_cap)
{
    double dm = rb_plant_link_mass(d, pi, pj, g, ik_rate), cap = (pi - pj) * ik_cap;
    return pi > pj ? (dm < cap ? dm : cap) : (dm > cap ? dm : cap);
}

/* R T / V of car c's pilot volume, which the relay membrane's stroke sweeps (relay_sweep per unit
 * of stroke), at its air's temperature (pilot_theta, plant_pilot.c): p_pilot = m_pilot times this. */
static inline double rb_plant_pilot_stiffness(const rb_plant_state *s, int c)
{
    return s->derived.k_pilot[c] * s->pilot_theta[c] / (1.0 + s->relay_stroke[c] * s->derived.sweep_ratio[c]);
}

/* The bits of x, its sign in the top one: ORed over a pass, (x - lo) | ~(x - hi) is negative when
 * some x lies outside [lo, hi) (IEEE: a difference is 0 only between equal numbers, and then +0; a
 * NaN sets one of the two), without a compare that would stop the portable build's vectoriser. */
static inline int64_t rb_plant_sign_bits(double x)
{
    int64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* The interval of speed table t that holds `speed`, found from *bracket as rb_speed_table_at_from
 * finds it, as the line value + (speed - lo) slope that holds for lo <= speed < hi: inside the table
 * speed[i] <= speed < speed[i + 1]; below it [-DBL_MAX, speed[0]) and above it [speed[n - 1], inf)
 * with slope 0; an empty table everywhere 0. A caller keeps it and interpolates without the table
 * (or a division) until the speed leaves it. */
static inline void rb_plant_table_interval(const rb_speed_table *t, double speed, int *bracket, double *lo,
                                           double *hi, double *value, double *slope)
{
    int n = t->n;
    *slope = 0.0;
    if (n < 1) {
        *lo = -DBL_MAX; *hi = HUGE_VAL; *value = 0.0;
    } else if (speed < t->speed[0]) {
        *lo = -DBL_MAX; *hi = t->speed[0]; *value = t->value[0];
    } else if (speed >= t->speed[n - 1]) {
        *lo = t->speed[n - 1]; *hi = HUGE_VAL; *value = t->value[n - 1];
    } else {
        int i = *bracket < 0 ? 0 : (*bracket > n - 2 ? n - 2 : *bracket);   /* rb_speed_table_at_from's search */
        while (t->speed[i] > speed) --i;
        while (t->speed[i + 1] <= speed) ++i;
        *bracket = i;
        *lo = t->speed[i]; *hi = t->speed[i + 1]; *value = t->value[i];
        *slope = (t->value[i + 1] - t->value[i]) / (t->speed[i + 1] - t->speed[i]);
    }
}

/* PORTABLE, or AVX2 when requested is AUTO and this build and CPU have it. */
int rb_plant_resolve_kernel(int requested);

/* ---- the adhesion at each axle (rail_conditioning.c) */
/* Zone (condition index) of axle `axle` at track position x; refreshes its cached Polach set. */
int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x);
/* Sets axle's Polach parameters and the wheelset kernel's constants derived from them. */
void rb_plant_set_axle_adhesion(rb_plant_state *s, int axle, const rb_polach_params *q);
/* Derives axle's Polach parameters again from its condition (zone_of) and conditioning. */
void rb_plant_condition_axle(const rb_plant_params *p, rb_plant_state *s, int axle);

/* ---- rail conditioning by dissipated energy (rail_conditioning.c) */
/* Checks each condition's reference_energy and, where one is > 0, rail_cell_length against the
 * ring's size. */
rb_status rb_rail_check(const rb_plant_params *p, rb_error *err);
/* The rail as laid under and ahead of the train (every cell contaminated). */
void rb_rail_init(const rb_plant_params *p, rb_plant_state *s);
/* mu0 factor of the cell under axle: 1 - (1 - leading_factor) x its contamination. */
double rb_rail_factor(const rb_plant_params *p, const rb_plant_state *s, int axle, double leading_factor);
/* After a mechanics step of dt: each axle's friction energy of the step cleans its cell, the
 * sanders that are on sand the cells ahead of their axles, then each axle on a conditioned
 * condition takes the adhesion of its cell. Nothing without conditioning. */
void rb_rail_step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in, double dt);

/* Faults in force at a time, per axle and per car. */
typedef struct {
    signed char hold[RB_PLANT_MAX_AXLES];   /* -1: as commanded, 0: stuck open, 1: stuck closed */
    signed char vent[RB_PLANT_MAX_AXLES];   /* -1: as commanded, 0: stuck closed, 1: stuck open */
    double leak[RB_PLANT_MAX_AXLES];        /* m^2 */
    double noise_sd[RB_PLANT_MAX_AXLES];    /* m/s */
    uint8_t ed_lost[RB_PLANT_MAX_CARS];
    double ep_failed[RB_PLANT_MAX_CARS], isolated[RB_PLANT_MAX_CARS];   /* 1 or 0: doubles, read in the
                                                                        car valves' vector loops */
    int compressor_off;
    int sensor_faults;                      /* any sensor lost or noisy */
    /* the emergency path, per car (0: sound) */
    double emergency_failed[RB_PLANT_MAX_CARS], loop_lost[RB_PLANT_MAX_CARS];
    double relay_limit[RB_PLANT_MAX_CARS];  /* Pa absolute the relay's output is held at most at; 0: none */
    double limiter[RB_PLANT_MAX_CARS];      /* Pa absolute the emergency control pressure is limited to; 0: none */
    int emergency_faults;                   /* any of them */
    double pipe_leak[RB_PLANT_MAX_CARS];    /* m^2, leak from the car's MR pipe */
    int pipe_leaks;                         /* any */
} rb_plant_faults;

void rb_plant_gather_faults(const rb_plant_params *p, const rb_plant_state *s, rb_plant_faults *f);
/* Wheelsets (torque balance, Polach adhesion with conditioning, ED) and cars (couplers,
   resistance) over one step dt with the given cylinder pressures (Pa, per axle): the one
   implementation of the mechanics, shared by the real-time plant and the detailed model. */
void rb_plant_step_mechanics(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                             const rb_plant_faults *f, const double *cylinder, double dt);
/* Each car's state as the wheelset kernel needs it, repeated for each of its axles (filled by the
   mechanics). */
typedef struct {
    double speed[RB_PLANT_MAX_AXLES];             /* m/s, the car's */
    double inv_creep_speed[RB_PLANT_MAX_AXLES];   /* 1 / max(speed, creep_speed_min) */
    double others[RB_PLANT_MAX_AXLES];            /* N: coupler, resistance and every rail force on the car */
    double ed_torque[RB_PLANT_MAX_AXLES];         /* N m per axle, its share of the car's ED brake */
} rb_wheelset_inputs;

/* Every wheelset of the train over dt (plant_kernel.c, in s->kernel): torque balance with Polach
   adhesion, the slip velocity linearly implicit; cylinder: pressures per axle (Pa). Updates omega,
   force and coefficient per axle. */
void rb_plant_wheelsets(const rb_plant_params *p, rb_plant_state *s, const rb_wheelset_inputs *in,
                        const double *cylinder, double dt);
/* Polach's coefficient of axle `axle` at a creep and speed as the wheelset kernel computes it (its
   portable build; for the tests). */
double rb_plant_polach(const rb_plant_state *s, int axle, double creep, double speed);
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
/* Friction brake energy and disc temperature of every axle over a sub-step dt, from the friction
 * torque the wheelset kernel applied in it (s->brake_torque). */
void rb_plant_discs(const rb_plant_params *p, rb_plant_state *s, double dt);
/* The relay control chambers' energy balance (plant_pilot.c): their constants and temperatures at
 * init; after the valves' phase of a sub-step, from each chamber's mass before it (m_before). */
void rb_plant_pilot_init(const rb_plant_params *p, rb_plant_state *s);
/* (inline: the step's build vectorises its loop over the cars, two divisions each) */
static inline void rb_plant_pilot_energy(const rb_plant_params *p, rb_plant_state *s, const double *m_before)
{
    if (!(p->wall_time > 0.0)) return;
    const double wall = p->temperature;
    for (int c = 0; c < p->n_cars; ++c) {
        double m0 = m_before[c], m = s->m_pilot[c], t = s->pilot_theta[c] * wall, dm = m - m0;
        /* the relay membrane's stroke since the last update swept the chamber: its work p dV
           (m T falls by (gamma - 1) m T dV / V) */
        double volume = 1.0 + s->relay_stroke[c] * s->derived.sweep_ratio[c], swept = volume - s->pilot_volume[c];
        double mt = m0 * t * (1.0 - (RB_AIR_GAMMA - 1.0) * swept / volume) + RB_AIR_GAMMA * (dm > 0.0 ? wall : t) * dm +
                    s->derived.pilot_heat[c] * (wall - t);
        s->pilot_volume[c] = volume;
        s->pilot_theta[c] = mt / (m * wall);
    }
}

#endif

/* Brake mechanics and rolling stock: pad friction, caliper, axle brake torque, wheelset,
 * running resistance, electrodynamic (ED) brake, coupler; the whole-train force balance,
 * the inverse computation of the target cylinder pressure and the stopping-distance integrator.
 *
 * Sources:
 *  - EN 14531-1 (railway brake performance: stopping, slowing and stationary braking): cylinder force F_C = p_C A_C i_C eta_C + F_s (F_s the return spring, acting against
 *    the piston); equivalent response time te = ta + tb/2 [P].
 *  - TB/T 1407.2 (CRH380AL): running resistance, ED brake curve, rotating-mass factor [P].
 *  - Sintered pad friction ~0.35 rising below 100 km/h; wheelset inertia 80-150 kg m^2 [T].
 *
 * Conventions: SI units; speeds in m/s and >= 0; pressures ABSOLUTE in Pa (the caliper subtracts
 * the atmospheric pressure); brake forces and decelerations positive when they slow the train;
 * gradient = rise over run, positive uphill. All structs are plain, fixed size, without pointers,
 * so they can be filled from Python (ctypes) or an FMU. The *_check functions validate a struct and
 * name the offending field; the evaluation functions do no checks (inner loops). */
#ifndef RAILBRAKE_VEHICLE_H
#define RAILBRAKE_VEHICLE_H

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_MAX_TABLE 64     /* points of a table over speed */
#define RB_MAX_ED_TERMS 8   /* branches of the ED brake formula */
#define RB_MAX_AXLES 8      /* axles per car */
#define RB_MAX_CARS 20      /* cars per train */
#define RB_GRAVITY 9.80665  /* m/s^2 */
#define RB_MAX_STOP_GRADIENTS 16  /* pieces of a gradient profile for the stopping distance */

/* ------------------------------------------------------------------ tables over speed */

/* y(v) by linear interpolation in a table of n points, speeds strictly increasing; constant
 * beyond either end. n = 1 gives a constant. */
typedef struct rb_speed_table {
    int n;
    double speed[RB_MAX_TABLE];  /* m/s */
    double value[RB_MAX_TABLE];
} rb_speed_table;

double rb_speed_table_at(const rb_speed_table *t, double speed);
/* n in [1, RB_MAX_TABLE], speeds finite, >= 0 and strictly increasing, values finite and within
 * [lo, hi]. name prefixes the message, e.g. "pad_friction". */
rb_status rb_speed_table_check(const rb_speed_table *t, const char *name, double lo, double hi,
                               rb_error *err);

/* ------------------------------------------------------------------ foundation brake */

/* Pad friction coefficient: the instantaneous friction of a pad sliding at speed v on a disc whose
 * friction surface is at temperature T_s,
 *     lambda(v, T_s) = table(v) / (1 + fade_rate * max(T_s - fade_onset, 0)),
 * the table the cold pad's friction over sliding speed, the divisor its heat fading: Cu-based
 * sintered pads keep their friction below a surface temperature and lose it above (friction film
 * softening; the stop-averaged friction of dynamometer stops falls from some 300 km/h on, where
 * the friction surface passes that temperature). fade_rate = 0: no fading, the table alone. */
typedef struct rb_pad_friction {
    rb_speed_table table;
    double fade_onset;   /* K, friction surface temperature where fading begins, >= 0 */
    double fade_rate;    /* 1/K, >= 0 */
} rb_pad_friction;

/* The cold pad's friction table(v): the friction at a surface below fade_onset. */
double rb_pad_friction_at(const rb_pad_friction *f, double speed);
/* 1 / (1 + fade_rate max(T_s - fade_onset, 0)): the fading factor at surface temperature T_s (K). */
static inline double rb_pad_fade_factor(double fade_onset, double fade_rate, double surface_temperature)
{
    double hot = surface_temperature - fade_onset;
    return 1.0 / (1.0 + fade_rate * (hot > 0.0 ? hot : 0.0));
}
/* lambda(v, T_s): the instantaneous friction at sliding speed v (m/s) and surface temperature T_s (K). */
double rb_pad_friction_eval(const rb_pad_friction *f, double speed, double surface_temperature);
rb_status rb_pad_friction_check(const rb_pad_friction *f, rb_error *err);

/* Default for sintered pads [T]: 0.35 at and above 100 km/h, rising as a parabola to
 * low_speed_value at standstill: lambda = 0.35 + (low_speed_value - 0.35) (1 - v / 100 km/h)^2.
 * low_speed_value in [0.35, 0.6]; 0.42 is the documented default. */
rb_status rb_pad_friction_sintered(double low_speed_value, rb_pad_friction *out, rb_error *err);

/* Caliper unit (EN 14531): pad normal force
 * ((p - p_atm) * A_cyl - F_spring) * lever_ratio * efficiency, never negative. */
typedef struct rb_caliper {
    double cylinder_area;         /* m^2, > 0 */
    double return_spring;         /* N, >= 0, opposes the piston */
    double lever_ratio;           /* -, > 0 */
    double efficiency;            /* -, (0, 1] */
    double atmospheric_pressure;  /* Pa, > 0 */
} rb_caliper;

double rb_caliper_pad_force(const rb_caliper *c, double cylinder_pressure);
rb_status rb_caliper_check(const rb_caliper *c, rb_error *err);

typedef enum { RB_DISC_AXLE_MOUNTED = 0, RB_DISC_WHEEL_MOUNTED = 1 } rb_disc_mounting;

/* Brake of one axle: discs identical discs, each gripped by one caliper with 2 pads. */
typedef struct rb_axle_brake {
    int discs;            /* per axle, 1..8 (a wheel-mounted pair per wheel counts as one) */
    int mounting;         /* rb_disc_mounting, for information */
    double mean_radius;   /* m, mean friction radius */
    rb_caliper caliper;
    rb_pad_friction pad;
} rb_axle_brake;

/* rb_speed_table_at starting from *bracket, the interval found last time (0 at first): the same
   value, found in a step or two when the speed moves little between calls (inline: the real-time
   plant looks up every axle's pad friction in every step). */
static inline double rb_speed_table_at_from(const rb_speed_table *t, double speed, int *bracket)
{
    int n = t->n;
    if (n <= 0)
        return 0.0;
    if (speed <= t->speed[0])
        return t->value[0];
    if (speed >= t->speed[n - 1])
        return t->value[n - 1];
    int lo = *bracket < 0 ? 0 : (*bracket > n - 2 ? n - 2 : *bracket);
    while (t->speed[lo] > speed) --lo;          /* speed[lo] <= speed < speed[lo + 1], as bisection */
    while (t->speed[lo + 1] <= speed) ++lo;
    *bracket = lo;
    int hi = lo + 1;
    double w = (speed - t->speed[lo]) / (t->speed[hi] - t->speed[lo]);
    return t->value[lo] + w * (t->value[hi] - t->value[lo]);
}

/* ------------------------------------------------------------------ disc temperature */

/* A brake disc as two thermal nodes: its friction surface layer (capacity Cs, temperature Ts: it
 * takes the braking power P and gives h (Ts - T_amb) to the air) and its bulk (Cb, Tb), linked by
 * the conductance G; both implicit (backward Euler: stable at any step, and each step's heat
 * balance Cs dTs + Cb dTb = dt (P - h (Ts' - T_amb)) exact). The bulk's equation gives
 * Tb' = (1 - g) Tb + g Ts' with g = dt G / (Cb + dt G); the surface's then
 * Ts' = (Cs Ts + dt (P + h T_amb) + Cb g Tb) / (Cs + dt h + Cb g). A lumped disc is Cb = G = 0
 * (g = 0). The plant (plant_train.c) and rb_dyno_stop step their discs with these. */
static inline double rb_disc_to_bulk(double bulk_capacity, double conductance, double dt)
{
    double link = dt * conductance;
    return link > 0.0 ? link / (bulk_capacity + link) : 0.0;
}
/* 1 / (Cs + dt h + Cb g): the surface update's divisor */
static inline double rb_disc_inverse(double surface_capacity, double bulk_capacity, double cooling, double to_bulk,
                                     double dt)
{
    return 1.0 / (surface_capacity + dt * cooling + bulk_capacity * to_bulk);
}
/* The step: *surface and *bulk (K) advanced by dt (s) with the power P (W) and h T_amb (W);
   bulk_g = Cb g. */
static inline void rb_disc_step(double surface_capacity, double bulk_g, double to_bulk, double inverse, double dt,
                                double power, double to_ambient, double *surface, double *bulk)
{
    double heated = (surface_capacity * *surface + dt * (power + to_ambient) + bulk_g * *bulk) * inverse;
    *surface = heated;
    *bulk += to_bulk * (heated - *bulk);
}

/* A dynamometer stop (UIC 541-3, EN 15328 bench tests): one disc with its 2 pads pressed by a
 * constant normal force brakes the translational mass it carries from initial_speed to a stop;
 * its pads' friction follows rb_pad_friction at the vehicle's speed and the disc's surface
 * temperature, the disc heats as above. The stop's mean friction is UIC 541-3's: the friction
 * averaged over the sliding distance, (1/s) int mu ds. */
typedef struct rb_dyno_stop {
    double initial_speed;        /* m/s, the vehicle's, > 0 */
    double mass;                 /* kg braked by the disc, > 0 */
    double pad_force;            /* N, normal force of each of the 2 pads, > 0 */
    double friction_radius;      /* m, > 0 */
    double wheel_radius;         /* m, > 0 */
    double heat_capacity;        /* J/K, the disc's, > 0 */
    double surface_capacity;     /* J/K, its surface layer, in [0, heat_capacity) (0: lumped) */
    double surface_conductance;  /* W/K, surface to bulk, > 0 with a surface layer */
    rb_speed_table cooling;      /* W/K over the vehicle's speed (n = 0: none) */
    double ambient_temperature;  /* K, the disc's at the start */
    double dt;                   /* s, in (0, 0.1] */
} rb_dyno_stop;

typedef struct rb_dyno_result {
    double mean_friction;            /* (1/s) int mu ds */
    double max_surface_temperature;  /* K */
    double max_mean_temperature;     /* K, (Cs Ts + Cb Tb) / (Cs + Cb) */
    double heat;                     /* J into the disc: the mass's kinetic energy */
    double stored;                   /* J in the disc at the stop above the ambient */
    double cooled;                   /* J given to the air (stored + cooled = heat) */
    double distance;                 /* m, the vehicle's */
    double time;                     /* s */
} rb_dyno_result;

rb_status rb_dyno_stop_run(const rb_pad_friction *pad, const rb_dyno_stop *stop, rb_dyno_result *out,
                           rb_error *err);

/* discs * 2 pads * R_mean * lambda(v) * F_pad, N m. */
double rb_axle_brake_torque(const rb_axle_brake *b, double cylinder_pressure, double speed);
rb_status rb_axle_brake_check(const rb_axle_brake *b, rb_error *err);

/* ------------------------------------------------------------------ wheelset, resistance, ED */

typedef struct rb_wheelset {
    double wheel_radius;  /* m */
    double inertia;       /* kg m^2, wheelset with discs and what turns with it, seen at the axle */
    double axle_load;     /* kg, static load of the axle on the rail */
} rb_wheelset;

/* J / r^2, kg: the translational mass equivalent to the wheelset's rotation. */
double rb_wheelset_equivalent_mass(const rb_wheelset *w);
rb_status rb_wheelset_check(const rb_wheelset *w, rb_error *err);
/* Sum of J/r^2 over n wheelsets (checked). */
rb_status rb_equivalent_rotating_mass(const rb_wheelset *w, size_t n, double *out, rb_error *err);

/* Running resistance A + B v + C v^2 (N), v in m/s. */
typedef struct rb_resistance {
    double A;  /* N */
    double B;  /* N s/m */
    double C;  /* N s^2/m^2 */
} rb_resistance;

double rb_running_resistance(const rb_resistance *r, double speed);
/* The law of rb_running_resistance, A + B v + C v^2 (inline: the plant evaluates it per car and step). */
static inline double rb_running_resistance_law(const rb_resistance *r, double speed)
{
    return r->A + speed * (r->B + speed * r->C);
}
rb_status rb_resistance_check(const rb_resistance *r, rb_error *err);

/* Maximum ED brake force (N) at speed:
 *   scale * min( table(v) if table.n > 0, min_k (c0_k + c1_k v + c2_k / v) ) * fade(v),
 * never negative; fade(v) = min(1, v / fade_speed) when fade_speed > 0, else 1. The branches
 * express constant-force, linear and power-limited (hyperbolic) parts exactly, e.g. the
 * CRH380AL whole-train curve min(509.6, 544.34 - 1.787 v, 42942.9/v - 121, 33033/v) kN;
 * scale shares a whole-train curve among the motor cars. No table and no branch: no ED. */
typedef struct rb_ed_curve {
    rb_speed_table table;  /* N over m/s; n = 0 for none */
    int terms;
    double c0[RB_MAX_ED_TERMS];  /* N */
    double c1[RB_MAX_ED_TERMS];  /* N s/m */
    double c2[RB_MAX_ED_TERMS];  /* N m/s (power, W) */
    double scale;                /* -, >= 0 */
    double fade_speed;           /* m/s, >= 0 */
} rb_ed_curve;

double rb_ed_brake_force_max(const rb_ed_curve *e, double speed);
rb_status rb_ed_curve_check(const rb_ed_curve *e, rb_error *err);

/* Coupler: free play 'slack' (total, m), then spring k e + k3 e^3 and damper c de/dt on the
 * engaged extension e = dx -/+ slack/2. Returns the tension (N), positive when stretched. */
typedef struct rb_coupler {
    double slack;            /* m, >= 0 */
    double stiffness;        /* N/m, > 0 */
    double stiffness_cubic;  /* N/m^3, >= 0 */
    double damping;          /* N s/m, >= 0 */
} rb_coupler;

double rb_coupler_force(const rb_coupler *c, double dx, double dv);
/* The law of rb_coupler_force: tension positive, dx the extension beyond the couplers' length, dv its
   rate; a free play of `slack`, then linear and cubic stiffness with damping (inline and
   branch-free: the plant evaluates it per coupler and step, as a vector loop). */
static inline double rb_coupler_force_law(const rb_coupler *c, double dx, double dv)
{
    double half = 0.5 * c->slack;
    int engaged = dx > half || dx < -half;   /* inside the free play: no force, no damping */
    double e = dx > half ? dx - half : dx + half;
    double force = c->stiffness * e + c->stiffness_cubic * e * e * e + c->damping * dv;
    return engaged ? force : 0.0;
}
rb_status rb_coupler_check(const rb_coupler *c, rb_error *err);

/* ------------------------------------------------------------------ cars and trains */

typedef struct rb_car {
    int motor;               /* 1: motor car (has the ED brake), 0: trailer */
    int axles;               /* 1..RB_MAX_AXLES, all alike */
    double mass;             /* kg, tare + load */
    rb_wheelset wheelset;    /* of each axle */
    rb_axle_brake brake;     /* of each axle */
    rb_ed_curve ed;          /* this car's ED brake (motor cars) */
    double supply_pressure;  /* Pa absolute: highest cylinder pressure the brake supply gives */
} rb_car;

typedef struct rb_train {
    int n_cars;
    rb_car cars[RB_MAX_CARS];
    rb_resistance resistance;  /* whole train */
} rb_train;

rb_status rb_car_check(const rb_car *c, rb_error *err);
rb_status rb_train_check(const rb_train *t, rb_error *err);

/* Whole-train figures (no checks). */
double rb_train_mass(const rb_train *t);                 /* kg */
double rb_train_rotating_mass(const rb_train *t);        /* kg, sum of J/r^2 */
double rb_train_ed_force_max(const rb_train *t, double speed);  /* N, sum over cars */

/* Blending rule (ED first on motor cars): each car brakes its own translational and rotating
 * mass at the demanded deceleration a, less its mass share of resistance and gradient force:
 *   F_car = (m + sum J/r^2) a - (m / M) R(v) - m g sin(atan(gradient)).
 * A motor car's ED supplies min(ED_max(v), F_car) (not below 0); the pneumatic brake the rest. */
double rb_car_brake_demand(const rb_train *t, int car, double speed, double deceleration,
                           double gradient);

typedef enum { RB_ED_OFF = 0, RB_ED_MAX = 1, RB_ED_BLENDED = 2 } rb_ed_mode;

/* Operating point of the brakes for the forward force balance. */
typedef struct rb_brake_state {
    double p_motor;       /* Pa abs, cylinder pressure of the motor cars */
    double p_trailer;     /* Pa abs, of the trailers */
    int ed_mode;          /* rb_ed_mode */
    double ed_demand;     /* m/s^2, demanded deceleration for RB_ED_BLENDED */
    double effort;        /* 0..1, build-up: scales ED force and gauge cylinder pressure */
    /* per car: fade_rate x (friction surface temperature - fade_onset) where positive, the pads'
       heat fading (rb_pad_friction: the friction over 1 + this); 0: cold pads */
    double fade[RB_MAX_CARS];
} rb_brake_state;

/* Train as one rigid body: deceleration (m/s^2, positive slowing) from the brake forces at the
 * rails (sum T/r and ED), running resistance and gradient over the mass including the rotating
 * parts. No checks. If brake_force is not NULL it receives the total brake force (N). */
double rb_train_deceleration(const rb_train *t, const rb_brake_state *s, double speed,
                             double gradient, double *brake_force);

/* Checked, array form: decel[i] at speed[i] with pressures p_motor[i], p_trailer[i] and, for
 * RB_ED_BLENDED, the demand ed_demand[i] (may be NULL otherwise). Fails if a pressure exceeds a
 * car's supply pressure or lies below atmospheric. effort = 1. */
rb_status rb_train_deceleration_curve(const rb_train *t, const double *speed, const double *p_motor,
                                      const double *p_trailer, int ed_mode,
                                      const double *ed_demand, size_t n, double gradient,
                                      double *decel, rb_error *err);

/* ------------------------------------------------------------------ sizing (inverse) */

/* For each speed[i] (m/s) and demanded deceleration decel[i] (m/s^2) the cylinder pressure, one
 * per car type, that makes the train decelerate at decel[i] under the blending rule of
 * rb_car_brake_demand. With lambda depending on v only, each car's pneumatic force is affine in
 * the pressure above the return-spring threshold, so the inverse is closed form.
 * Outputs (Pa abs): p_motor[i], p_trailer[i] (NaN when the train has no car of that type;
 * atmospheric where no pneumatic force is needed); ed_force[i] total ED force (N);
 * adhesion[i * n_cars + k]: the adhesion each axle of car k demands,
 * (F_brake_car / axles - J a / r^2) / (axle_load g). Pressures are not limited to the supply
 * (the caller compares). speed[] must be finite, >= 0; decel[] finite, >= 0. */
rb_status rb_size_target_pressure(const rb_train *t, const double *speed, const double *decel,
                                  size_t n, double gradient, double *p_motor, double *p_trailer,
                                  double *ed_force, double *adhesion, rb_error *err);
/* The same with the ED brake on (ed_on = 1, as rb_size_target_pressure) or off (0: pneumatic only,
 * as an emergency brake without ED blending). */
rb_status rb_size_target_pressure_ed(const rb_train *t, const double *speed, const double *decel,
                                     size_t n, double gradient, int ed_on, double *p_motor,
                                     double *p_trailer, double *ed_force, double *adhesion,
                                     rb_error *err);
/* What a brake control unit needs to brake car `car` as the sizing does: at each speed[i] the
 * car's brake force demand force[i] (N, ED plus pneumatic, rb_car_brake_demand, not below 0) for
 * the deceleration decel[i], and its pneumatic law solved for the pressure: cylinder pressure =
 * threshold + pressure_per_newton[i] * pneumatic force (Pa abs; pad lambda(v) included). */
rb_status rb_size_car_demand(const rb_train *t, int car, const double *speed, const double *decel,
                             size_t n, double gradient, double *force, double *pressure_per_newton,
                             double *threshold, rb_error *err);

/* ------------------------------------------------------------------ stopping distance */

/* Brake application in time: no brake until 'delay' (ta), then effort rising linearly to 1 over
 * 'build_up' (tb); or, with equivalent_response = 1, a step to full effort at te = ta + tb/2
 * (EN 14531). Integration: classical Runge-Kutta with step dt, steps cut at ta, te and ta + tb;
 * the last step ends exactly at v_end with the local deceleration held constant. */
typedef struct rb_stop_options {
    double v0;               /* m/s, > 0 */
    double v_end;            /* m/s, 0 <= v_end < v0: stop when the speed reaches it */
    double gradient;         /* rise/run, positive uphill */
    double delay;            /* s, ta >= 0 */
    double build_up;         /* s, tb >= 0 */
    int equivalent_response; /* 1: step at te = ta + tb/2; 0: linear build-up */
    double dt;               /* s, integration step */
    double dt_out;           /* s, spacing of the recorded curve (>= dt) */
    double t_max;            /* s: fail if not stopped by then */
    /* piecewise gradient over the distance s from the brake's start (n_gradients = 0: `gradient`
     * throughout): gradient_value[i] from gradient_start[i] on, [0] also before it; held over
     * each integration step */
    int n_gradients;
    double gradient_start[RB_MAX_STOP_GRADIENTS];  /* m, increasing */
    double gradient_value[RB_MAX_STOP_GRADIENTS];  /* rise/run, uphill positive */
} rb_stop_options;

/* Brake command for rb_stop_train: cylinder pressure per car type over speed (Pa abs; a table
 * with n = 0 means atmospheric, no pneumatic brake) and the ED mode with, for RB_ED_BLENDED, the
 * demanded deceleration over speed. Pressures must not exceed the cars' supply pressure. */
typedef struct rb_brake_command {
    rb_speed_table p_motor;
    rb_speed_table p_trailer;
    int ed_mode;
    rb_speed_table ed_demand;
} rb_brake_command;

/* Whole train (rigid). Writes the curve (time, speed, distance) at dt_out spacing plus the final
 * point into caller arrays of 'capacity' points; n_out receives the count. distance_out and
 * time_out receive the stopping distance (m) and time (s). */
rb_status rb_stop_train(const rb_train *t, const rb_brake_command *cmd, const rb_stop_options *o,
                        double *time, double *speed, double *distance, size_t capacity,
                        size_t *n_out, double *distance_out, double *time_out, rb_error *err);

/* The discs of each car for rb_stop_train_heated, per axle (as rb_plant_car's): heat capacity
 * (0: the car's pads stay cold), its surface layer and conductance (0: one lumped node), cooling
 * over speed (n = 0: none); all start at ambient_temperature (K). */
typedef struct rb_train_discs {
    double heat_capacity[RB_MAX_CARS];       /* J/K per axle */
    double surface_capacity[RB_MAX_CARS];    /* J/K per axle, in [0, heat_capacity) */
    double surface_conductance[RB_MAX_CARS]; /* W/K per axle */
    rb_speed_table cooling[RB_MAX_CARS];     /* W/K per axle over speed */
    double ambient_temperature;              /* K */
} rb_train_discs;

/* rb_stop_train with the pads fading as the plant's (rb_pad_friction): each car's discs heated by
 * its pneumatic brake's power (two nodes, rb_disc_step, advanced after each step with the step's
 * mean power, the friction of the next step faded at the surface's temperature). discs = NULL:
 * rb_stop_train. max_surface_temperature (K, may be NULL): the hottest surface of the stop. */
rb_status rb_stop_train_heated(const rb_train *t, const rb_brake_command *cmd, const rb_train_discs *discs,
                               const rb_stop_options *o, double *time, double *speed, double *distance,
                               size_t capacity, size_t *n_out, double *distance_out, double *time_out,
                               double *max_surface_temperature, rb_error *err);

/* Kinematic: the deceleration over speed is given (effort * decel(v)); no resistance, no train. */
rb_status rb_stop_profile(const rb_speed_table *decel, const rb_stop_options *o, double *time,
                          double *speed, double *distance, size_t capacity, size_t *n_out,
                          double *distance_out, double *time_out, rb_error *err);

/* Hand check: constant deceleration a after an equivalent response time te, no resistance:
 * s = v0 te + v0^2 / (2 a), t = te + v0 / a. */
rb_status rb_stop_constant(double v0, double deceleration, double response_time,
                           double *distance_out, double *time_out, rb_error *err);

#ifdef __cplusplus
}
#endif
#endif

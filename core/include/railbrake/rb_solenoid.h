/* Solenoid design model: a lumped magnetic circuit, the coil's electrical dynamics with the
 * armature's motion, and a lumped thermal model (docs/pneumatics.md, "Solenoid").
 *
 * Magnetic circuit (one loop): the coil's MMF N i drives the flux Phi through the iron path
 * (length l, area A_fe, B-H curve with saturation), a fixed parasitic gap (e.g. the radial gap of
 * a plunger's guide sleeve) and the working air gap(s) of length g, in parallel with a leakage
 * permeance P_l (flux that crosses from pole to pole outside the armature face):
 *
 *     N i = l H(Phi / A_fe) + R_p Phi + Phi / (P_g(g) + P_l),    lambda = N Phi
 *
 * P_g(g) = mu0 A_eff(g) / (n g) for n equal working gaps in series with the pole area grown by
 * fringing, A_eff = pi/4 (D + k_f g)^2 (k_f = 0: none; about 1: each edge grows by about the gap,
 * after H. C. Roters, Electromagnetic Devices, Wiley 1941). The force along the closing direction is
 * the co-energy derivative F = dW'/d(-g) at constant current, which for this circuit is exactly
 * F = -U^2 / 2 dP_g/dg with U = Phi / (P_g + P_l) the MMF across the gap (the iron's energy does
 * not depend on g at constant flux). The flux linkage is explicit in the current given the flux,
 * so the electrical dynamics use lambda as state: d lambda/dt = u(t) - R(T) i(lambda, g).
 * Copper resistance R(T) = R20 (1 + alpha (T - 20 C)).
 *
 * Thermal model: C dT/dt = duty I^2 R(T) - G (T - T_ambient) (the coil at a controlled current I
 * for the fraction duty of the time, averaged over a cycle much shorter than C / G). */
#ifndef RAILBRAKE_SOLENOID_H
#define RAILBRAKE_SOLENOID_H

#include "railbrake/rb_common.h"
#include "railbrake/rb_network.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_BH_MAX_POINTS 32
#define RB_MU0 1.25663706212e-6    /* H/m, vacuum permeability (CODATA 2018) */

typedef struct {
    double turns;                  /* N, > 0 */
    double resistance_20c;         /* ohm at 20 C, >= 0 (0: the lossless idealisation) */
    double resistance_tempco;      /* 1/K at 20 C (copper: 0.00393) */
    double iron_length;            /* m, mean iron path (yoke, pole, armature) */
    double iron_area;              /* m^2, its cross-section */
    int bh_points;                 /* 2..RB_BH_MAX_POINTS; starts at (0, 0); beyond the last point dB/dH = mu0 */
    double bh_h[RB_BH_MAX_POINTS]; /* A/m, strictly increasing */
    double bh_b[RB_BH_MAX_POINTS]; /* T, strictly increasing */
    double pole_diameter;          /* m, working gap face */
    int working_gaps;              /* 1 (plunger) or 2 (C-core with a flat armature), in series */
    double fringing;               /* k_f >= 0 */
    double parasitic_gap;          /* m, fixed gap, >= 0 */
    double parasitic_area;         /* m^2, its face (> 0 when parasitic_gap > 0) */
    double leakage_permeance;      /* H, >= 0 */
} rb_solenoid;

rb_status rb_solenoid_check(const rb_solenoid *s, rb_error *err);

/* Magnetic state at airgap g (m) and current i (A). */
typedef struct {
    double flux;                   /* Wb, through the iron */
    double gap_flux;               /* Wb, through the working gap */
    double flux_linkage;           /* Wb-turns */
    double inductance;             /* H, lambda / i (0 at i = 0: the incremental value) */
    double incremental_inductance; /* H, d lambda / d i */
    double force;                  /* N, closing the gap */
    double energy;                 /* J, magnetic field energy W(lambda, g) */
    double coenergy;               /* J, lambda i - W */
    double iron_flux_density;      /* T */
} rb_solenoid_state;

/* The state at (gap, current): the flux from the loop equation (monotone, solved by bisection to
   round-off). gap > 0, current >= 0. */
rb_status rb_solenoid_eval(const rb_solenoid *s, double gap, double current, rb_solenoid_state *out,
                           rb_error *err);
/* Current (A) for a flux linkage (Wb-turns) at gap: explicit. */
double rb_solenoid_current(const rb_solenoid *s, double gap, double flux_linkage);
/* Magnetic field energy W(lambda, gap), J: the iron's l A_fe int H dB plus the gaps' Phi^2 / 2P. */
double rb_solenoid_energy(const rb_solenoid *s, double gap, double flux_linkage);
/* Force (N, closing) at (gap, flux linkage). */
double rb_solenoid_force_at_flux(const rb_solenoid *s, double gap, double flux_linkage);

/* The force table F(gap, current) of rb_network.h over the given axes (strictly increasing,
   2..RB_FORCE_TABLE_MAX values each, gap > 0, current >= 0). */
rb_status rb_solenoid_force_table(const rb_solenoid *s, const double *gaps, int n_gap, const double *currents,
                                  int n_current, rb_force_table *table, rb_error *err);

/* Drive: voltage u(t) = voltage when PWM is on (always, with pwm_frequency = 0), else 0 (the coil
   freewheels through an ideal diode while i > 0). The armature (mass, spring, viscous damping, a
   constant load against closing) moves between gap_max (open stop) and gap_min; it starts at rest
   at gap_max with zero current. The stops are inelastic (the kinetic energy lost is booked). */
typedef struct {
    double voltage;                /* V */
    double pwm_frequency;          /* Hz; 0: constant voltage */
    double duty;                   /* [0, 1] */
    double temperature_c;          /* coil temperature for R(T), C */
    double mass;                   /* kg, armature and what it moves */
    double spring_rate;            /* N/m */
    double spring_preload;         /* N at gap_max, opening */
    double damping;                /* N s/m */
    double load_force;             /* N, constant, opening */
    double gap_max, gap_min;       /* m */
} rb_solenoid_drive;

typedef struct {
    double t, voltage, current, flux_linkage, gap, velocity, force;
    /* J since t = 0: electrical energy in, copper loss, field energy now, mechanical energy now
       (kinetic + spring + load potential), viscous loss, stop impacts */
    double e_electric, e_copper, e_magnetic, e_mechanical, e_damping, e_impact;
} rb_solenoid_sample;

/* Fixed-step RK4 at step dt (s) to t_end; n_out samples evenly spaced from 0 to t_end. */
rb_status rb_solenoid_simulate(const rb_solenoid *s, const rb_solenoid_drive *d, double t_end, double dt,
                               rb_solenoid_sample *out, size_t n_out, rb_error *err);

/* Steady coil temperature (C) at current I (A) on for the fraction duty, ambient (C), conductance
   G (W/K) to the ambient: closed form of G (T - Ta) = duty I^2 R(T); fails (thermal runaway) when
   G <= duty I^2 R20 alpha. */
rb_status rb_solenoid_steady_temperature(const rb_solenoid *s, double current, double duty, double ambient_c,
                                         double conductance, double *temperature_c, rb_error *err);
/* Coil temperature (C) at n_out times evenly spaced over [0, t_end] from T(0) = ambient, integrated
   with RK4 at n_steps steps (heat capacity C in J/K). */
rb_status rb_solenoid_thermal_transient(const rb_solenoid *s, double current, double duty, double ambient_c,
                                        double conductance, double heat_capacity, double t_end, size_t n_steps,
                                        double *temperature_c, size_t n_out, rb_error *err);

size_t rb_solenoid_size(void);
size_t rb_solenoid_drive_size(void);
size_t rb_solenoid_state_size(void);
size_t rb_solenoid_sample_size(void);

#ifdef __cplusplus
}
#endif
#endif

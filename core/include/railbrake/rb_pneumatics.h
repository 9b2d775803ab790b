/* Pneumatic laws: ideal-gas lumped volume, orifice flow (ISO 6358 form), variable-area
 * elements and membranes.
 *
 * Sources: ideal gas with R = 287.05 J/(kg K), gamma = 1.4 (dry air, ISO 2533:1975 Standard
 * Atmosphere, table 1);
 * the flow-rate characteristic of ISO 6358-1:2013 (sec. 3, annex A) with sonic conductance C
 * and critical pressure ratio b, reference density rho0 = 1.185 kg/m^3 at T0 = 293.15 K; ideal
 * nozzle b = 0.528 (de Saint-Venant flow, (2 / (gamma + 1))^(gamma / (gamma - 1))). */
#ifndef RAILBRAKE_PNEUMATICS_H
#define RAILBRAKE_PNEUMATICS_H

#include "railbrake/rb_common.h"

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RB_AIR_R 287.05        /* J/(kg K) */
#define RB_AIR_GAMMA 1.4
/* Pressure (Pa abs) at which a volume's wall heat exchange time is stated: the wall conductance
   h A = m cv / thermal time, m the volume's air mass at this pressure and the wall temperature
   (the detailed model's and the valve models' convention, rb_detailed_params.thermal_time). */
#define RB_WALL_REFERENCE_PRESSURE 5e5
#define RB_ISO6358_RHO0 1.185  /* kg/m^3, reference density of ISO 6358 */
#define RB_ISO6358_T0 293.15   /* K, reference temperature of ISO 6358 */
/* Above this pressure ratio p_down/p_up the flow is linear in the pressure difference
 * (laminar region), so d(mdot)/dp stays finite at equal pressures. */
#define RB_ORIFICE_LAMINAR_RATIO 0.999

/* Mass flow through an orifice, kg/s, positive from node 1 to node 2; works in both directions
   (the upstream side's temperature is used). Choked below critical_ratio, ISO 6358 form above,
   linear (laminar) region near equal pressures so the derivative stays finite.
   No argument checks: for inner loops. */
double rb_orifice_mass_flow_fast(double p1, double T1, double p2, double T2,
                                 double area, double discharge_coefficient, double critical_ratio);

/* The same law in the ISO 6358 parameters: sonic conductance C (m^3/(s Pa)), critical ratio b. */
double rb_orifice_mass_flow_iso_fast(double p1, double T1, double p2, double T2,
                                     double sonic_conductance, double critical_ratio);

/* The orifice law with its constant parts hoisted (for a real-time loop over many links at one
   temperature): mdot = g p_up phi(p_down / p_up), g = conductance = Cd A x choked factor / sqrt(T).
   Same law as rb_orifice_mass_flow_fast, to round-off. */
typedef struct {
    double b, inv_one_minus_b;           /* critical pressure ratio, 1 / (1 - b) */
    double laminar_slope;                /* phi = slope (1 - r) above the laminar ratio */
    int laminar_only;                    /* b >= laminar ratio: phi = (1 - r) / (1 - b) above b */
} rb_orifice_law;

void rb_orifice_law_init(double critical_ratio, rb_orifice_law *law);
/* kg/(s Pa m^2): Cd x choked factor / sqrt(T); times an area it is that orifice's conductance. */
double rb_orifice_unit_conductance(double discharge_coefficient, double temperature);
/* Mass flow (kg/s) from p1 to p2 (negative when p2 > p1) through conductance g (inline: the
   real-time plant calls it for every air link in every step). */
static inline double rb_orifice_flow_function_law(double r, const rb_orifice_law *law)
{
    if (r <= law->b) return 1.0;
    if (law->laminar_only) return (1.0 - r) * law->inv_one_minus_b;
    if (r >= RB_ORIFICE_LAMINAR_RATIO) return law->laminar_slope * (1.0 - r);
    double s = (r - law->b) * law->inv_one_minus_b;
    return sqrt(1.0 - s * s);
}

static inline double rb_orifice_flow_law(double p1, double p2, double g, const rb_orifice_law *law)
{
    if (p1 >= p2) return g * p1 * rb_orifice_flow_function_law(p2 / p1, law);
    return -g * p2 * rb_orifice_flow_function_law(p1 / p2, law);
}

/* Sonic conductance C of an orifice of area A and discharge coefficient Cd: the C that gives the
   ideal-nozzle choked flow Cd A p1 sqrt(gamma/(R T1)) (2/(gamma+1))^((gamma+1)/(2(gamma-1))). */
double rb_sonic_conductance(double area, double discharge_coefficient);

/* An orifice given either by area and discharge coefficient (sonic_conductance = 0) or by its
   ISO 6358 sonic conductance (area and discharge_coefficient ignored). */
typedef struct {
    double area;                   /* m^2, >= 0 */
    double discharge_coefficient;  /* (0, 1] */
    double sonic_conductance;      /* m^3/(s Pa), >= 0; > 0 selects the ISO 6358 form */
    double critical_ratio;         /* b, [0, 1) */
} rb_orifice;

rb_status rb_orifice_check(const rb_orifice *o, rb_error *err);
/* Checked orifice flow: pressures > 0, temperatures > 0, orifice valid. */
rb_status rb_orifice_mass_flow(double p1, double T1, double p2, double T2, const rb_orifice *o,
                               double *mdot, rb_error *err);

/* Rates of an ideal-gas lumped volume (mass and energy balance, moving boundary).
   mdot_in: sum of inflows (kg/s, >= 0); enthalpy_in: sum over inflows of cp*T_source*mdot (W);
   mdot_out: sum of outflows (kg/s, >= 0) leaving at the volume's temperature T;
   heat: heat flow into the gas (W), e.g. h*A*(T_wall - T); V (m^3) and dV_dt (m^3/s).
   Outputs dm/dt (kg/s), dT/dt (K/s), dp/dt (Pa/s), with p = m R T / V. */
void rb_volume_rates(double m, double T, double V, double dV_dt,
                     double mdot_in, double enthalpy_in, double mdot_out, double heat,
                     double *dm_dt, double *dT_dt, double *dp_dt);
/* Wall heat conductance h A (W/K) of a volume V (m^3) whose air, at reference_pressure (Pa abs) and
   the wall temperature T (K), follows the wall with the time constant thermal_time (s):
   h A = m cv / thermal_time, m = reference_pressure V / (R T) (RB_WALL_REFERENCE_PRESSURE is the
   models' usual reference). */
double rb_wall_conductance(double volume, double temperature, double thermal_time, double reference_pressure);

/* Variable-area elements driven by a body position (m); areas in m^2, never negative.
   Flapper-nozzle: curtain area pi D x, limited by the nozzle bore pi D^2/4. */
double rb_flapper_nozzle_area(double nozzle_diameter, double gap);
/* Conical (or flat: half_angle = pi/2) poppet seat of diameter D lifted by x:
   pi D x sin(half_angle), limited by the port area pi D^2/4. */
double rb_seat_area(double seat_diameter, double lift, double half_angle);
/* Spool metering edge of diameter D opened by x (negative: overlapped) with radial clearance c:
   pi D sqrt(max(x,0)^2 + c^2); the clearance leaks when closed. */
double rb_spool_edge_area(double spool_diameter, double opening, double clearance);

/* Membrane (or any piston of position-dependent area): swept volume V(x) from a table, by a
   monotone piecewise-cubic (Fritsch-Carlson) interpolant, so that A_eff(x) = dV/dx is
   continuous and the p dV work stays consistent with the force p A_eff. */
#define RB_MEMBRANE_MAX_POINTS 32
typedef struct {
    int n;
    double x[RB_MEMBRANE_MAX_POINTS];      /* m, strictly increasing */
    double volume[RB_MEMBRANE_MAX_POINTS]; /* m^3, non-decreasing */
    double slope[RB_MEMBRANE_MAX_POINTS];  /* dV/dx at the points, filled by rb_membrane_init */
} rb_membrane;

rb_status rb_membrane_init(rb_membrane *mb, const double *x, const double *volume, int n,
                           rb_error *err);
/* Swept volume and effective area at x (outside the table: linear extension). */
void rb_membrane_eval(const rb_membrane *mb, double x, double *volume, double *effective_area);

#ifdef __cplusplus
}
#endif
#endif

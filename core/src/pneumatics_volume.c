/* Ideal-gas lumped volume: mass and energy balance (reference README sec. 4).
 * U = m cv T; dU/dt = H_in - cp T mdot_out + Q - p dV/dt. */
#include "railbrake/rb_pneumatics.h"

void rb_volume_rates(double m, double T, double V, double dV_dt,
                     double mdot_in, double enthalpy_in, double mdot_out, double heat,
                     double *dm_dt, double *dT_dt, double *dp_dt)
{
    const double R = RB_AIR_R;
    const double cv = R / (RB_AIR_GAMMA - 1.0);
    const double cp = cv + R;
    double p = m * R * T / V;
    double dm = mdot_in - mdot_out;
    double dU = enthalpy_in - cp * T * mdot_out + heat - p * dV_dt;
    double dT = (dU - cv * T * dm) / (m * cv);
    *dm_dt = dm;
    *dT_dt = dT;
    *dp_dt = R * (dm * T + m * dT) / V - p * dV_dt / V;
}

double rb_wall_conductance(double volume, double temperature, double thermal_time, double reference_pressure)
{
    const double cv = RB_AIR_R / (RB_AIR_GAMMA - 1.0);
    return reference_pressure * volume / (RB_AIR_R * temperature) * cv / thermal_time;
}

/* Pneumatic laws against closed forms (reference README sec. 4) and limiting cases. */
#include "rb_test.h"
#include "railbrake/rb_pneumatics.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const double g = RB_AIR_GAMMA, R = RB_AIR_R;

static double nozzle_choked(double p1, double T1, double cd_area)
{
    /* Ideal nozzle: mdot = Cd A p1 sqrt(gamma/(R T1)) (2/(gamma+1))^((gamma+1)/(2(gamma-1))). */
    return cd_area * p1 * sqrt(g / (R * T1)) * pow(2 / (g + 1), (g + 1) / (2 * (g - 1)));
}

static void test_choked(void)
{
    double A = 1e-5, cd = 0.8;
    CHECK_CLOSE(rb_orifice_mass_flow_fast(6e5, 293.15, 1e5, 293.15, A, cd, 0.528),
                nozzle_choked(6e5, 293.15, cd * A), 1e-12, 0);
    CHECK_CLOSE(rb_orifice_mass_flow_fast(6e5, 350.0, 3e5, 293.15, A, cd, 0.528),
                nozzle_choked(6e5, 350.0, cd * A), 1e-12, 0);
    /* The ISO form with C from the area gives the same flow. */
    double C = rb_sonic_conductance(A, cd);
    CHECK_CLOSE(rb_orifice_mass_flow_iso_fast(6e5, 320.0, 4e5, 293.15, C, 0.528),
                rb_orifice_mass_flow_fast(6e5, 320.0, 4e5, 293.15, A, cd, 0.528), 1e-12, 0);
    /* ISO 6358 definition: choked mdot = C p1 rho0 sqrt(T0/T1). */
    CHECK_CLOSE(rb_orifice_mass_flow_iso_fast(5e5, 300.0, 1e5, 300.0, 2e-8, 0.4),
                2e-8 * 5e5 * RB_ISO6358_RHO0 * sqrt(RB_ISO6358_T0 / 300.0), 1e-12, 0);
}

static void test_continuity_and_equal_pressure(void)
{
    double A = 1e-5, cd = 1.0, b = 0.528, p1 = 5e5, T = 293.15;
    double below = rb_orifice_mass_flow_fast(p1, T, p1 * b * (1 - 1e-10), T, A, cd, b);
    double above = rb_orifice_mass_flow_fast(p1, T, p1 * b * (1 + 1e-10), T, A, cd, b);
    CHECK_CLOSE(above, below, 1e-8, 0);
    double lam = RB_ORIFICE_LAMINAR_RATIO;
    CHECK_CLOSE(rb_orifice_mass_flow_fast(p1, T, p1 * lam * (1 + 1e-12), T, A, cd, b),
                rb_orifice_mass_flow_fast(p1, T, p1 * lam * (1 - 1e-12), T, A, cd, b), 1e-8, 0);
    CHECK(rb_orifice_mass_flow_fast(p1, T, p1, T, A, cd, b) == 0.0);
    /* Finite, equal one-sided derivatives at equal pressures. */
    double dp = 1.0;
    double d_plus = (rb_orifice_mass_flow_fast(p1, T, p1 + dp, T, A, cd, b)) / dp;
    double d_minus = -(rb_orifice_mass_flow_fast(p1, T, p1 - dp, T, A, cd, b)) / dp;
    CHECK(isfinite(d_plus) && d_plus < 0.0);
    CHECK_CLOSE(d_plus, d_minus, 1e-4, 0);
}

static void test_antisymmetry(void)
{
    double ratios[] = {0.2, 0.5, 0.7, 0.9, 0.9995};
    for (int i = 0; i < 5; ++i) {
        double pa = 6e5, pb = 6e5 * ratios[i];
        CHECK_CLOSE(rb_orifice_mass_flow_fast(pa, 300, pb, 280, 2e-6, 0.7, 0.5),
                    -rb_orifice_mass_flow_fast(pb, 280, pa, 300, 2e-6, 0.7, 0.5), 1e-14, 0);
    }
}

static void test_checked(void)
{
    rb_orifice o = {-1e-6, 0.8, 0.0, 0.528};
    rb_error err;
    double m;
    CHECK(rb_orifice_mass_flow(5e5, 293, 1e5, 293, &o, &m, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "area") != NULL);
    o.area = 1e-6;
    CHECK(rb_orifice_mass_flow(0.0, 293, 1e5, 293, &o, &m, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "p1") != NULL);
    CHECK(rb_orifice_mass_flow(5e5, 293, 1e5, 293, &o, &m, &err) == RB_OK);
    CHECK_CLOSE(m, nozzle_choked(5e5, 293, 0.8e-6), 1e-12, 0);
}

static void test_volume_rates(void)
{
    /* Rigid adiabatic filling: dp/dt = gamma R T_s mdot / V (energy balance with U = pV/(gamma-1)). */
    double dm, dT, dp, m = 1e5 * 1e-3 / (R * 293.15), mdot = 1e-3, Ts = 300.0;
    rb_volume_rates(m, 293.15, 1e-3, 0.0, mdot, g / (g - 1) * R * Ts * mdot, 0.0, 0.0, &dm, &dT, &dp);
    CHECK_CLOSE(dm, mdot, 1e-14, 0);
    CHECK_CLOSE(dp, g * R * Ts * mdot / 1e-3, 1e-12, 0);
    /* Closed adiabatic compression: dp/p = -gamma dV/V. */
    rb_volume_rates(m, 293.15, 1e-3, -1e-4, 0, 0, 0, 0, &dm, &dT, &dp);
    CHECK_CLOSE(dp, -g * 1e5 * (-1e-4) / 1e-3, 1e-10, 0);
    /* Discharge at the gas temperature leaves T falling as an isentrope: dT/T = (g-1)/g dp/p. */
    rb_volume_rates(m, 293.15, 1e-3, 0, 0, 0, 1e-4, 0, &dm, &dT, &dp);
    CHECK_CLOSE(dT / 293.15, (g - 1) / g * dp / 1e5, 1e-12, 0);
    /* The wall's conductance for a thermal time: closed air at the reference pressure, 10 K above
       the wall, cools at dT/dt = -10 K / thermal_time; at half the pressure (half the mass) twice as fast. */
    double tw = 293.15, tau = 1.5, V = 2e-3, hA = rb_wall_conductance(V, tw, tau, RB_WALL_REFERENCE_PRESSURE);
    for (int half = 0; half < 2; ++half) {
        double p = RB_WALL_REFERENCE_PRESSURE / (half ? 2.0 : 1.0), T = tw + 10.0, mass = p * V / (R * tw);
        rb_volume_rates(mass, T, V, 0, 0, 0, 0, hA * (tw - T), &dm, &dT, &dp);
        CHECK_CLOSE(dT, -10.0 / tau * (half ? 2.0 : 1.0), 1e-12, 0);
    }
}

static void test_elements(void)
{
    CHECK_CLOSE(rb_flapper_nozzle_area(1e-3, 1e-4), M_PI * 1e-3 * 1e-4, 1e-14, 0);
    CHECK_CLOSE(rb_flapper_nozzle_area(1e-3, 1e-3), M_PI * 0.25e-6, 1e-14, 0);
    CHECK(rb_flapper_nozzle_area(1e-3, -1e-5) == 0.0);
    CHECK(rb_seat_area(8e-3, -1e-4, 0.7) == 0.0);
    CHECK_CLOSE(rb_spool_edge_area(1e-2, -1e-3, 5e-6), M_PI * 1e-2 * 5e-6, 1e-14, 0);
    /* A cylindrical V(x) = A x gives A_eff = A everywhere; a quadratic keeps dV/dx close. */
    double x[5] = {0, 1e-3, 2e-3, 3e-3, 4e-3}, V[5], Vq[5];
    for (int i = 0; i < 5; ++i) { V[i] = 2e-3 * x[i]; Vq[i] = 2e-3 * x[i] - 0.1 * x[i] * x[i]; }
    rb_membrane mb;
    CHECK(rb_membrane_init(&mb, x, V, 5, NULL) == RB_OK);
    double vol, area;
    rb_membrane_eval(&mb, 1.7e-3, &vol, &area);
    CHECK_CLOSE(area, 2e-3, 1e-12, 0);
    CHECK_CLOSE(vol, 3.4e-6, 1e-12, 0);
    CHECK(rb_membrane_init(&mb, x, Vq, 5, NULL) == RB_OK);
    rb_membrane_eval(&mb, 2.5e-3, &vol, &area);
    CHECK_CLOSE(area, 2e-3 - 0.2 * 2.5e-3, 0.02, 0);
    double xbad[3] = {0, 2e-3, 1e-3};
    rb_error err;
    CHECK(rb_membrane_init(&mb, xbad, V, 3, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "x[2]") != NULL);
}

int main(void)
{
    test_choked();
    test_continuity_and_equal_pressure();
    test_antisymmetry();
    test_checked();
    test_volume_rates();
    test_elements();
    return rb_test_summary("test_pneumatics");
}

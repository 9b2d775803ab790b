/* Tests of the vehicle laws against hand calculations and closed forms
 * (EN 14531-1 cylinder force and equivalent response time; TB/T 1407.2 CRH380AL data). */
#include "railbrake/rb_vehicle.h"
#include "rb_test.h"

#include <math.h>
#include <string.h>

static const double P_ATM = 101325.0;

static rb_car trailer(void)
{
    rb_car c;
    memset(&c, 0, sizeof c);
    c.motor = 0;
    c.axles = 4;
    c.mass = 45e3;
    c.wheelset = (rb_wheelset){0.43, 120.0, 45e3 / 4};
    c.brake.discs = 2;
    c.brake.mounting = RB_DISC_AXLE_MOUNTED;
    c.brake.mean_radius = 0.25;
    c.brake.caliper = (rb_caliper){0.02, 700.0, 2.8, 0.95, P_ATM};
    rb_pad_friction_sintered(0.42, &c.brake.pad, NULL);
    c.supply_pressure = P_ATM + 4.5e5;
    return c;
}

static rb_car motor_car(double ed_scale)
{
    rb_car c = trailer();
    c.motor = 1;
    c.mass = 50e3;
    c.wheelset.axle_load = 50e3 / 4;
    c.ed.terms = 4;  /* CRH380AL whole-train curve, kN -> N (TB/T 1407.2) */
    const double c0[4] = {509.6e3, 544.34e3, -121e3, 0.0};
    const double c1[4] = {0.0, -1.787e3, 0.0, 0.0};
    const double c2[4] = {0.0, 0.0, 42942.9e3, 33033e3};
    for (int k = 0; k < 4; ++k) {
        c.ed.c0[k] = c0[k];
        c.ed.c1[k] = c1[k];
        c.ed.c2[k] = c2[k];
    }
    c.ed.scale = ed_scale;
    return c;
}

static void test_table_and_friction(void)
{
    rb_speed_table t = {3, {0.0, 10.0, 20.0}, {1.0, 3.0, 2.0}};
    CHECK_CLOSE(rb_speed_table_at(&t, 5.0), 2.0, 1e-12, 0);
    CHECK_CLOSE(rb_speed_table_at(&t, 15.0), 2.5, 1e-12, 0);
    CHECK_CLOSE(rb_speed_table_at(&t, 99.0), 2.0, 1e-12, 0);
    rb_error err;
    t.speed[2] = 5.0;  /* not monotonic */
    CHECK(rb_speed_table_check(&t, "profile", 0.0, 10.0, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "profile.speed[2]") != NULL);

    rb_pad_friction f;
    CHECK(rb_pad_friction_sintered(0.42, &f, &err) == RB_OK);
    CHECK(rb_pad_friction_check(&f, &err) == RB_OK);
    CHECK_CLOSE(rb_pad_friction_at(&f, 0.0), 0.42, 1e-12, 0);
    CHECK_CLOSE(rb_pad_friction_at(&f, 50.0 / 3.6), 0.35 + 0.07 * 0.25, 1e-12, 0);
    CHECK_CLOSE(rb_pad_friction_at(&f, 300.0 / 3.6), 0.35, 1e-12, 0);
    CHECK(rb_pad_friction_sintered(0.2, &f, &err) == RB_EINVAL);
}

static void test_caliper_and_axle(void)
{
    rb_caliper c = {0.02, 700.0, 2.8, 0.95, P_ATM};
    /* EN 14531: (4 bar * 0.02 m^2 - 700 N) * 2.8 * 0.95 */
    CHECK_CLOSE(rb_caliper_pad_force(&c, P_ATM + 4e5), (8000.0 - 700.0) * 2.8 * 0.95, 1e-12, 0);
    CHECK(rb_caliper_pad_force(&c, P_ATM + 0.2e5) == 0.0);  /* below the spring: no force */
    rb_error err;
    c.lever_ratio = 0.0;
    CHECK(rb_caliper_check(&c, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "caliper.lever_ratio") != NULL);

    rb_car t = trailer();
    double lambda = rb_pad_friction_at(&t.brake.pad, 80.0);
    double pad = rb_caliper_pad_force(&t.brake.caliper, P_ATM + 3e5);
    CHECK_CLOSE(rb_axle_brake_torque(&t.brake, P_ATM + 3e5, 80.0), 2 * 2 * 0.25 * lambda * pad, 1e-12, 0);
}

static void test_wheelset_resistance_ed_coupler(void)
{
    rb_wheelset w[2] = {{0.43, 120.0, 12e3}, {0.46, 150.0, 15e3}};
    double m;
    rb_error err;
    CHECK(rb_equivalent_rotating_mass(w, 2, &m, &err) == RB_OK);
    CHECK_CLOSE(m, 120.0 / (0.43 * 0.43) + 150.0 / (0.46 * 0.46), 1e-12, 0);
    w[1].axle_load = -1.0;
    CHECK(rb_equivalent_rotating_mass(w, 2, &m, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "wheelset.axle_load") != NULL);

    /* TB/T CRH380AL: 3.3 + 0.0469 V + 0.000921 V^2 kN at V = 300 km/h -> 100.29 kN */
    rb_resistance r = {3300.0, 46.9 * 3.6, 0.921 * 3.6 * 3.6};
    CHECK_CLOSE(rb_running_resistance(&r, 300.0 / 3.6), (3.3 + 0.0469 * 300 + 0.000921 * 9e4) * 1e3, 1e-12, 0);

    rb_car mc = motor_car(1.0);
    const double v[5] = {5.0, 20.0, 40.0, 70.0, 97.0};
    for (int i = 0; i < 5; ++i) {
        double expect = fmin(fmin(509.6, 544.34 - 1.787 * v[i]), fmin(42942.9 / v[i] - 121, 33033 / v[i]));
        CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, v[i]), expect * 1e3, 1e-12, 0);
    }
    CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, 0.0), 509.6e3, 1e-12, 0);
    /* a table caps the branches where it is lower; scale shares the curve */
    mc.ed.table = (rb_speed_table){2, {0.0, 100.0}, {400e3, 200e3}};
    mc.ed.scale = 0.5;
    CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, 50.0), 0.5 * fmin(300e3, 33033e3 / 50.0), 1e-12, 0);
    CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, 90.0), 0.5 * 220e3, 1e-12, 0);
    CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, 150.0), 0.5 * (42942.9e3 / 150.0 - 121e3), 1e-12, 0);
    rb_error e2;
    CHECK(rb_ed_curve_check(&mc.ed, &e2) == RB_OK);
    mc.ed.scale = -1.0;
    CHECK(rb_ed_curve_check(&mc.ed, &e2) == RB_EINVAL && strstr(e2.message, "ed.scale") != NULL);
    mc.ed.table.n = 0;
    mc.ed.scale = 1.0;
    mc.ed.fade_speed = 2.0;
    CHECK_CLOSE(rb_ed_brake_force_max(&mc.ed, 1.0), 0.5 * 509.6e3, 1e-12, 0);

    rb_coupler c = {0.02, 1e7, 1e9, 1e4};
    CHECK(rb_coupler_force(&c, 0.009, 1.0) == 0.0);
    CHECK_CLOSE(rb_coupler_force(&c, 0.012, 0.0), 1e7 * 0.002 + 1e9 * 8e-9, 1e-12, 0);
    CHECK_CLOSE(rb_coupler_force(&c, -0.012, -0.5), -(1e7 * 0.002 + 1e9 * 8e-9) - 5e3, 1e-12, 0);
}

static rb_train small_train(void)
{
    rb_train t;
    memset(&t, 0, sizeof t);
    t.n_cars = 4;
    t.cars[0] = motor_car(0.25 * 4.0 / 14.0);
    t.cars[1] = trailer();
    t.cars[2] = trailer();
    t.cars[2].mass = 48e3;  /* cars of one type differ: the type pressure must still fit */
    t.cars[2].wheelset.axle_load = 12e3;
    t.cars[3] = motor_car(0.25 * 4.0 / 14.0);
    t.cars[3].brake.caliper.return_spring = 1500.0;
    t.resistance = (rb_resistance){1500.0, 80.0, 6.0};
    return t;
}

static void test_sizing_inverse(void)
{
    rb_train t = small_train();
    rb_error err;
    CHECK(rb_train_check(&t, &err) == RB_OK);
    enum { N = 6 };
    const double v[N] = {0.0, 10.0, 25.0, 40.0, 70.0, 90.0};
    const double a[N] = {1.2, 1.2, 1.1, 1.0, 0.8, 0.02};
    double pm[N], pt[N], ed[N], adh[N * 4], back[N];
    CHECK(rb_size_target_pressure(&t, v, a, N, 0.0, pm, pt, ed, adh, &err) == RB_OK);
    for (int i = 0; i < N; ++i) {  /* give the supply room, then go forward */
        t.cars[0].supply_pressure = t.cars[3].supply_pressure = fmax(pm[i], P_ATM + 1.0);
        t.cars[1].supply_pressure = t.cars[2].supply_pressure = fmax(pt[i], P_ATM + 1.0);
        CHECK(rb_train_deceleration_curve(&t, &v[i], &pm[i], &pt[i], RB_ED_BLENDED, &a[i], 1, 0.0,
                                          &back[i], &err) == RB_OK);
        if (i < N - 1)
            CHECK_CLOSE(back[i], a[i], 1e-9, 0);
    }
    /* at 90 m/s resistance alone exceeds the demand: no brake, the train coasts */
    CHECK(pm[N - 1] == P_ATM && pt[N - 1] == P_ATM && ed[N - 1] == 0.0);
    double coast = (1500.0 + 80.0 * 90 + 6.0 * 90 * 90) /
                   (rb_train_mass(&t) + rb_train_rotating_mass(&t));
    CHECK_CLOSE(back[N - 1], coast, 1e-12, 0);
    /* the force on the rails of each axle: brake minus what spins its wheelset down */
    t = small_train();
    rb_brake_state s = {pm[2], pt[2], RB_ED_BLENDED, a[2], 1.0, {0.0}};
    double brake;
    rb_train_deceleration(&t, &s, v[2], 0.0, &brake);
    double rail = 0.0;
    for (int k = 0; k < 4; ++k)
        rail += adh[2 * 4 + k] * t.cars[k].wheelset.axle_load * RB_GRAVITY * t.cars[k].axles;
    CHECK_CLOSE(rail, brake - rb_train_rotating_mass(&t) * a[2], 1e-9, 0);

    t.cars[1].mass = -5.0;
    CHECK(rb_size_target_pressure(&t, v, a, N, 0.0, pm, pt, ed, adh, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "cars[1].mass") != NULL);
}

static void test_stopping(void)
{
    rb_error err;
    double time[4000], speed[4000], dist[4000], s, tt, s_ref, t_ref;
    size_t n;
    /* constant deceleration after the equivalent response time: v0 te + v0^2 / 2a */
    rb_speed_table a = {1, {0.0}, {0.9}};
    rb_stop_options o = {250 / 3.6, 0.0, 0.0, 0.5, 2.5, 1, 0.01, 0.5, 600.0, 0, {0.0}, {0.0}};
    CHECK(rb_stop_profile(&a, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    CHECK(rb_stop_constant(o.v0, 0.9, 0.5 + 1.25, &s_ref, &t_ref, &err) == RB_OK);
    CHECK_CLOSE(s, s_ref, 1e-9, 0);
    CHECK_CLOSE(tt, t_ref, 1e-9, 0);
    CHECK(n > 2 && speed[n - 1] == 0.0 && dist[n - 1] == s);
    /* explicit linear build-up: the same speed lost as with te = ta + tb/2, and a distance
     * shorter by a tb^2 / 24 (integrate the ramp by hand) */
    o.equivalent_response = 0;
    CHECK(rb_stop_profile(&a, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    CHECK_CLOSE(s, s_ref - 0.9 * 2.5 * 2.5 / 24.0, 1e-9, 0);
    /* too small a buffer */
    CHECK(rb_stop_profile(&a, &o, time, speed, dist, 10, &n, &s, &tt, &err) == RB_ESIZE);

    /* resistance-only coast-down, A + C v^2: s = M/(2C) ln((A + C v0^2)/(A + C v^2)) */
    rb_train t = small_train();
    t.resistance = (rb_resistance){4000.0, 0.0, 8.0};
    rb_brake_command cmd;
    memset(&cmd, 0, sizeof cmd);
    o = (rb_stop_options){300 / 3.6, 100 / 3.6, 0.0, 0.0, 0.0, 1, 0.05, 5.0, 1e4, 0, {0.0}, {0.0}};
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    double M = rb_train_mass(&t) + rb_train_rotating_mass(&t), A = 4000.0, C = 8.0;
    CHECK_CLOSE(s, M / (2 * C) * log((A + C * o.v0 * o.v0) / (A + C * o.v_end * o.v_end)), 1e-6, 0);
    double k = sqrt(C / A);
    CHECK_CLOSE(tt, M / sqrt(A * C) * (atan(k * o.v0) - atan(k * o.v_end)), 1e-6, 0);

    /* piecewise gradient: one piece from 0 is the constant gradient; one beyond the stop is level;
     * a 2 % climb from 1000 m on lies between the two */
    double s_level = s;
    o.gradient = 0.02;
    double s_const, t_const;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s_const, &t_const, &err) == RB_OK);
    o.gradient = 0.0;
    o.n_gradients = 1;
    o.gradient_start[0] = 0.0; o.gradient_value[0] = 0.02;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    CHECK_CLOSE(s, s_const, 1e-12, 0);
    o.n_gradients = 2;
    o.gradient_value[0] = 0.0;
    o.gradient_start[1] = 1e6;   /* beyond the stop: level */
    o.gradient_value[1] = 0.02;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    CHECK_CLOSE(s, s_level, 1e-12, 0);
    o.gradient_start[1] = 1000.0;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_OK);
    CHECK(s < s_level && s > s_const);
    o.gradient_start[1] = -5.0;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "gradient_start[1] = -5 m") != NULL);
    o.n_gradients = 0;

    /* heated discs: pads that never fade give rb_stop_train's stop exactly; pads fading from the
       ambient on lengthen it, and the hottest surface lies above the ambient */
    cmd.p_trailer = (rb_speed_table){1, {0.0}, {P_ATM + 3e5}};
    cmd.p_motor = cmd.p_trailer;
    o.v_end = 0.0;
    double s_cold, t_cold, s_hot, t_hot, hottest;
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s_cold, &t_cold, &err) == RB_OK);
    static rb_train_discs discs;
    discs.ambient_temperature = 293.15;
    for (int c = 0; c < t.n_cars; ++c) {
        discs.heat_capacity[c] = 3 * 115.0 * 460.0;
        discs.surface_capacity[c] = 0.12 * discs.heat_capacity[c];
        discs.surface_conductance[c] = 3 * 1450.0;
        t.cars[c].brake.pad.fade_onset = 293.15;
        t.cars[c].brake.pad.fade_rate = 0.0;
    }
    CHECK(rb_stop_train_heated(&t, &cmd, &discs, &o, time, speed, dist, 4000, &n, &s_hot, &t_hot, &hottest, &err) ==
          RB_OK);
    CHECK(s_hot == s_cold && t_hot == t_cold);
    CHECK(hottest > 293.15 + 50.0);
    for (int c = 0; c < t.n_cars; ++c) t.cars[c].brake.pad.fade_rate = 0.002;
    CHECK(rb_stop_train_heated(&t, &cmd, &discs, &o, time, speed, dist, 4000, &n, &s_hot, &t_hot, &hottest, &err) ==
          RB_OK);
    CHECK(s_hot > s_cold * 1.01);
    discs.surface_capacity[1] = discs.heat_capacity[1];
    CHECK(rb_stop_train_heated(&t, &cmd, &discs, &o, time, speed, dist, 4000, &n, &s_hot, &t_hot, &hottest, &err) ==
          RB_EINVAL);
    CHECK(strstr(err.message, "discs of cars[1]") != NULL);

    /* a pressure beyond the supply is refused and named */
    cmd.p_trailer = (rb_speed_table){1, {0.0}, {P_ATM + 6e5}};
    CHECK(rb_stop_train(&t, &cmd, &o, time, speed, dist, 4000, &n, &s, &tt, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "p_trailer.value[0]") != NULL);
}

/* The BCU's per-car tables: threshold + Pa/N * force is the sizing's per-type pressure (the two
 * trailers and the two motor cars of small_train are alike); with the ED brake off the motor cars
 * need the whole demand from the air. */
static void test_car_demand_tables(void)
{
    rb_train t = small_train();
    t.cars[2] = t.cars[1];   /* cars of a type alike */
    t.cars[3] = t.cars[0];
    rb_error err;
    enum { N = 3 };
    const double v[N] = {5.0, 40.0, 80.0}, a[N] = {1.2, 1.0, 0.7};
    double pm[N], pt[N], ed[N], adh[N * 4], pm_ed[N], pt_ed[N];
    CHECK(rb_size_target_pressure_ed(&t, v, a, N, 0.0, 0, pm, pt, ed, adh, &err) == RB_OK);
    for (int i = 0; i < N; ++i) CHECK(ed[i] == 0.0);
    CHECK(rb_size_target_pressure_ed(&t, v, a, N, 0.0, 1, pm_ed, pt_ed, ed, adh, &err) == RB_OK);
    for (int i = 0; i < N; ++i) {
        CHECK(pm[i] > pm_ed[i]);
        CHECK_CLOSE(pt[i], pt_ed[i], 1e-12, 0);
    }
    for (int car = 0; car < 4; ++car) {
        double force[N], per_n[N], threshold;
        CHECK(rb_size_car_demand(&t, car, v, a, N, 0.0, force, per_n, &threshold, &err) == RB_OK);
        CHECK_CLOSE(threshold, P_ATM + 700.0 / 0.02, 1e-12, 0);
        for (int i = 0; i < N; ++i) {
            CHECK_CLOSE(force[i], rb_car_brake_demand(&t, car, v[i], a[i], 0.0), 1e-12, 0);
            double p = t.cars[car].motor ? pm[i] : pt[i];
            CHECK_CLOSE(threshold + per_n[i] * force[i], p, 1e-9, 0);
        }
    }
    double force[N], per_n[N], threshold;
    CHECK(rb_size_car_demand(&t, 4, v, a, N, 0.0, force, per_n, &threshold, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "car = 4") != NULL);
}

int main(void)
{
    test_car_demand_tables();
    test_table_and_friction();
    test_caliper_and_axle();
    test_wheelset_resistance_ed_coupler();
    test_sizing_inverse();
    test_stopping();
    return rb_test_summary("test_vehicle");
}

/* The plant's reduced valve model alone, for fitting (rb_valve_reduced.h), and the plant's one-car
 * valve air over WSP cycles, for the reduction's air check (rb_plant_valve_air, rb_plant.h). */
#include "railbrake/rb_valve_reduced.h"

#include "railbrake/rb_plant.h"
#include "railbrake/rb_pneumatics.h"

#include <math.h>
#include <string.h>

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

static rb_status check(const rb_reduced_valve *v, rb_error *err)
{
    rb_status s;
    if (!v) return rb_fail(err, RB_EINVAL, "reduced valve = NULL");
    if ((s = rb_check_positive(err, "reduced.supply (Pa)", v->supply))) return s;
    if ((s = rb_check_positive(err, "reduced.atmosphere (Pa)", v->atmosphere))) return s;
    if ((s = rb_check_positive(err, "reduced.volume (m^3)", v->volume))) return s;
    if ((s = rb_check_positive(err, "reduced.temperature (K)", v->temperature))) return s;
    if ((s = rb_check_range(err, "reduced.discharge_coefficient", v->discharge_coefficient, 0.0, 1.0))) return s;
    if ((s = rb_check_range(err, "reduced.critical_ratio", v->critical_ratio, 0.0, 0.999))) return s;
    if ((s = rb_check_nonnegative(err, "reduced.tau (s)", v->tau))) return s;
    if ((s = rb_check_positive(err, "reduced.band (Pa)", v->band))) return s;
    return rb_check_nonnegative(err, "reduced.area (m^2)", v->area);
}

rb_status rb_reduced_valve_steps(const rb_reduced_valve *v, const double *start, const double *final,
                                 size_t n_steps, double t_step, const double *t_out, size_t n_out, double dt,
                                 double *pressure, rb_error *err)
{
    rb_status s;
    if ((s = check(v, err))) return s;
    if (n_out < 1 || (s = rb_check_positive(err, "dt (s)", dt))) return s ? s : rb_fail(err, RB_ESIZE, "n_out = 0");
    double k = RB_AIR_R * v->temperature / v->volume, T = v->temperature;
    for (size_t j = 0; j < n_steps; ++j) {
        double m = start[j] / k, lag = start[j], t = 0.0;
        for (size_t i = 0; i < n_out; ++i) {
            while (t < t_out[i] - 1e-12) {
                double h = fmin(dt, t_out[i] - t);
                double demand = t >= t_step ? final[j] : start[j];
                lag += v->tau > 0.0 ? (demand - lag) * h / (v->tau + h) : demand - lag;
                double p = m * k, e = (lag - p) / v->band;
                double q_in = rb_orifice_mass_flow_fast(v->supply, T, p, T, v->area * clamp01(e),
                                                        v->discharge_coefficient, v->critical_ratio);
                double q_out = rb_orifice_mass_flow_fast(p, T, v->atmosphere, T, v->area * clamp01(-e),
                                                         v->discharge_coefficient, v->critical_ratio);
                m += h * (q_in - q_out);
                t += h;
            }
            pressure[j * n_out + i] = m * k;
        }
    }
    return RB_OK;
}

size_t rb_reduced_valve_size(void) { return sizeof(rb_reduced_valve); }

rb_status rb_valve_air_cycle_check(double settle, const double phase[3], int cycles, rb_error *err)
{
    static const char *names[3] = {"phase[0] (vent, s)", "phase[1] (hold, s)", "phase[2] (refill, s)"};
    rb_status st;
    if (!phase) return rb_fail(err, RB_EINVAL, "phase = NULL: the cycle's three phases are required");
    if ((st = rb_check_range(err, "settle (s)", settle, 0.0, 100.0))) return st;
    for (int i = 0; i < 3; ++i)
        if ((st = rb_check_range(err, names[i], phase[i], 1e-3, 10.0))) return st;
    if (cycles < 1 || cycles > 10000) return rb_fail(err, RB_EINVAL, "cycles = %d: must be in [1, 10000]", cycles);
    return RB_OK;
}

/* (rb_plant.h) The car at rest, its WSP valves switching as commanded (no response delay: the
   detailed car network's commands act at once too), in whole plant steps. */
rb_status rb_plant_valve_air(const rb_plant_params *plant, double demand, double settle, const double phase[3],
                             int cycles, double air[2], rb_error *err)
{
    rb_plant_params p;
    rb_plant_state s;
    rb_plant_inputs in;
    rb_status st;
    if (!plant || !phase || !air) return rb_fail(err, RB_EINVAL, "plant, phase and air are required");
    if (plant->n_cars != 1) return rb_fail(err, RB_EINVAL, "n_cars = %d: the valve air study takes one car", plant->n_cars);
    if ((st = rb_check_positive(err, "demand (Pa)", demand)) || (st = rb_valve_air_cycle_check(settle, phase, cycles, err)))
        return st;
    p = *plant;
    p.initial_speed = 0.0;
    p.car[0].valve_delay = 0.0;
    if ((st = rb_plant_init(&p, &s, err))) return st;
    memset(&in, 0, sizeof in);
    in.pressure_demand[0] = demand;
    for (long i = lround(settle / p.dt); i > 0; --i) rb_plant_step(&p, &s, &in);
    double start = s.m_vented, start_valves = s.m_valves_vented;
    for (int c = 0; c < cycles; ++c)
        for (int ph = 0; ph < 3; ++ph) {
            memset(in.hold, ph < 2, RB_AXLES_PER_CAR);
            memset(in.vent, ph == 0, RB_AXLES_PER_CAR);
            for (long i = lround(phase[ph] / p.dt); i > 0; --i) rb_plant_step(&p, &s, &in);
        }
    air[0] = s.m_valves_vented - start_valves;
    air[1] = (s.m_vented - start) - air[0];
    return RB_OK;
}

/* The plant's reduced valve model alone, for fitting (rb_valve_reduced.h). */
#include "railbrake/rb_valve_reduced.h"

#include "railbrake/rb_pneumatics.h"

#include <math.h>

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

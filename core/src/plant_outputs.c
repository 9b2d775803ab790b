/* The plant's outputs from its state, updated after every step of a run. Flattened and built
 * once for the portable target and once for AVX2 (s->kernel, as the step): the per-axle loop is
 * one vector per car and the same operations in the same order, so the same values bit for bit. */
#include "plant_internal.h"

double rb_plant_air_mass(const rb_plant_params *p, const rb_plant_state *s)
{
    double m = s->m_mr;
    for (int c = 0; c < p->n_cars; ++c) {
        m += s->m_pipe[c] + s->m_supply[c] + s->m_pilot[c] + s->m_relay[c];
        for (int k = 0; k < RB_AXLES_PER_CAR; ++k) m += s->m_cyl[c * RB_AXLES_PER_CAR + k];
    }
    return m;
}

/* Axle by axle over the train (simple loops over arrays: vectors): the per-car constants the
 * step uses repeated per axle (s->derived.axle_*) are the cars' own. */
static void axle_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    const rb_plant_derived *d = &s->derived;
    int n = p->n_cars * RB_AXLES_PER_CAR;
    size_t doubles = (size_t)n * sizeof(double), bytes = (size_t)n;
    for (int a = 0; a < n; ++a) out->wheel_speed[a] = s->omega[a] * d->axle_radius[a];
    for (int a = 0; a < n; ++a)
        out->wheel_speed_measured[a] = s->sensor_lost[a] ? -1.0 : out->wheel_speed[a] + s->noise[a];
    for (int a = 0; a < n; ++a) out->cylinder[a] = s->mt_cyl[a] * d->axle_r_cyl[a];
    for (int c = 0; c < p->n_cars; ++c) {
        double v = s->v[c], vr = v > p->creep_speed_min ? v : p->creep_speed_min;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a)
            out->slip[a] = (out->wheel_speed[a] - v) / vr;
    }
    memcpy(out->adhesion, s->coefficient, doubles);
    memcpy(out->disc_temperature, s->disc_temperature, doubles);
    memcpy(out->brake_energy, s->brake_energy, doubles);
    memcpy(out->hold, s->hold_effective, bytes);
    memcpy(out->vent, s->vent_effective, bytes);
}

static void car_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, double rt)
{
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        out->supply[c] = s->m_supply[c] * rt / car->supply_volume;
        out->pilot[c] = s->m_pilot[c] * rb_plant_pilot_stiffness(s, c);
        out->relay[c] = s->m_relay[c] * rt / car->relay_volume;
        out->ed_force[c] = s->ed_force[c];
        out->car_speed[c] = s->v[c];
    }
}

static inline void update_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    double rt = 287.05 * p->temperature;
    out->time = s->time;
    out->speed = s->v[0];
    out->position = s->x[0];
    out->deceleration = -s->a[0];
    out->main_reservoir = s->m_mr * rt / p->main_reservoir_volume;
    out->pipe_end = s->m_pipe[p->n_cars - 1] * rt / p->car[p->n_cars - 1].pipe_volume;
    out->compressor_on = s->compressor_on;
    car_outputs(p, s, out, rt);
    axle_outputs(p, s, out);
    out->air_in_system = rb_plant_air_mass(p, s);
    out->air_vented = s->m_vented;
    out->air_compressed = s->m_compressed;
    double m = s->m_mr;
    for (int c = 0; c < p->n_cars; ++c) m += s->m_pipe[c];
    /* the main reservoir and pipe lose air only through the supply-reservoir check valves */
    out->air_drawn = s->m_supply_side_initial + s->m_compressed - m;
}

RB_FLATTEN static void update_portable(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    update_outputs(p, s, out);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2"), flatten))
static void update_avx2(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    update_outputs(p, s, out);
}
#endif

void rb_plant_update_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) {
        update_avx2(p, s, out);
        return;
    }
#endif
    update_portable(p, s, out);
}

void rb_plant_get_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    memset(out, 0, sizeof *out);
    rb_plant_update_outputs(p, s, out);
}

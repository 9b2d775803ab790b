/* The plant's outputs from its state, updated after every step of a run. Flattened and built
 * once for the portable target and once for AVX2 (s->kernel, as the step): vector loops over the
 * axles, the same operations in the same order, so the same values bit for bit. */
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
    for (int a = 0; a < n; ++a) out->wheel_speed[a] = s->omega[a] * d->axle_radius[a];
    for (int a = 0; a < n; ++a) out->cylinder[a] = s->mt_cyl[a] * d->axle_r_cyl[a];
    for (int c = 0; c < p->n_cars; ++c) {
        double v = s->v[c], vr = v > p->creep_speed_min ? v : p->creep_speed_min;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a)
            out->slip[a] = (out->wheel_speed[a] - v) / vr;
    }
    /* the disc's mean temperature (Cs Ts + Cb Tb) / (Cs + Cb); without a surface layer (Cb = 0) the
       lumped disc's, as it is */
    for (int c = 0; c < p->n_cars; ++c) {
        const double cs = d->disc_capacity[c], cb = d->disc_bulk_capacity[c];
        const double inv = cb > 0.0 ? 1.0 / (cs + cb) : 0.0;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a)
            out->disc_temperature[a] = cb > 0.0 ? (cs * s->disc_temperature[a] + cb * s->disc_bulk_temperature[a]) * inv
                                                : s->disc_temperature[a];
    }
    memcpy(out->disc_surface_temperature, s->disc_temperature, (size_t)n * sizeof(double));
    memcpy(out->pad_friction, s->pad_friction, (size_t)n * sizeof(double));
    /* the whole arrays (their rest is 0 in both): a copy of fixed size is a few vector moves, not a call */
    memcpy(out->hold, s->hold_effective, sizeof out->hold);
    memcpy(out->vent, s->vent_effective, sizeof out->vent);
}

/* What a run's KPIs read after every step (rb_run_advance): time and motion, the main and supply
 * reservoirs, and the axles. */
static void step_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, double rt)
{
    out->time = s->time;
    out->speed = s->v[0];
    out->position = s->x[0];
    out->main_reservoir = s->m_mr * rt / p->main_reservoir_volume;
    for (int c = 0; c < p->n_cars; ++c) {   /* a vector loop: whole-vector stores, which the KPIs' loads take */
        out->supply[c] = s->m_supply[c] * rt / s->derived.supply_volume[c];
        out->car_speed[c] = s->v[c];
    }
    axle_outputs(p, s, out);
}

/* The rest: what the BCU, the records and the run's end read. */
static void other_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, double rt)
{
    int n = p->n_cars * RB_AXLES_PER_CAR;
    out->deceleration = -s->a[0];
    out->pipe_end = s->m_pipe[p->n_cars - 1] * rt / p->car[p->n_cars - 1].pipe_volume;
    out->compressor_on = s->compressor_on;
    for (int c = 0; c < p->n_cars; ++c) {
        out->pilot[c] = s->m_pilot[c] * rb_plant_pilot_stiffness(s, c);
        out->relay[c] = s->m_relay[c] * rt / p->car[c].relay_volume;
        out->ed_force[c] = s->ed_force[c];
        out->ed_available[c] = s->ed_asked[c];
    }
    for (int a = 0; a < n; ++a)
        out->wheel_speed_measured[a] = s->sensor_lost[a] ? -1.0 : out->wheel_speed[a] + s->noise[a];
    memcpy(out->adhesion, s->coefficient, (size_t)n * sizeof(double));
    memcpy(out->brake_energy, s->brake_energy, (size_t)n * sizeof(double));
    out->air_in_system = rb_plant_air_mass(p, s);
    out->air_vented = s->m_vented;
    out->air_compressed = s->m_compressed;
    double m = s->m_mr;
    for (int c = 0; c < p->n_cars; ++c) m += s->m_pipe[c];
    /* the main reservoir and pipe lose air only through the supply-reservoir check valves */
    out->air_drawn = s->m_supply_side_initial + s->m_compressed - m;
}

static inline void update_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, int all)
{
    double rt = 287.05 * p->temperature;
    step_outputs(p, s, out, rt);
    if (all) other_outputs(p, s, out, rt);
}

RB_FLATTEN static void update_portable(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out,
                                       int all)
{
    update_outputs(p, s, out, all);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2"), flatten))
static void update_avx2(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, int all)
{
    update_outputs(p, s, out, all);
}
#endif

static void update(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out, int all)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) {
        update_avx2(p, s, out, all);
        return;
    }
#endif
    update_portable(p, s, out, all);
}

void rb_plant_update_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    update(p, s, out, 1);
}

void rb_plant_update_step_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    update(p, s, out, 0);
}

void rb_plant_get_outputs(const rb_plant_params *p, const rb_plant_state *s, rb_plant_outputs *out)
{
    memset(out, 0, sizeof *out);
    rb_plant_update_outputs(p, s, out);
}

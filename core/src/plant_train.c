/* Train equipment of the plant beyond the brake chain: several compressors, the track gradient,
 * and the friction energy and lumped temperature of each axle's brake discs. */
#include "plant_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

rb_status rb_plant_train_check(const rb_plant_params *p, rb_error *err)
{
    rb_status s;
    char name[64];
    if (p->n_compressors < 0 || p->n_compressors > RB_MAX_COMPRESSORS)
        return rb_fail(err, RB_EINVAL, "n_compressors = %d: must be in [0, %d]", p->n_compressors,
                       RB_MAX_COMPRESSORS);
    for (int i = 0; i < p->n_compressors; ++i) {
        if (p->compressor_position[i] < 0 || p->compressor_position[i] >= p->n_cars)
            return rb_fail(err, RB_EINVAL, "compressor_position[%d] = %d: the train has cars 0..%d", i,
                           p->compressor_position[i], p->n_cars - 1);
        snprintf(name, sizeof name, "compressor_delivery[%d]", i);
        if ((s = rb_check_range(err, name, p->compressor_delivery[i], 0.0, 1.0))) return s;
    }
    if (p->n_gradients < 0 || p->n_gradients > RB_MAX_GRADIENTS)
        return rb_fail(err, RB_EINVAL, "n_gradients = %d: must be in [0, %d]", p->n_gradients, RB_MAX_GRADIENTS);
    for (int i = 0; i < p->n_gradients; ++i) {
        snprintf(name, sizeof name, "gradient[%d]", i);
        if ((s = rb_check_range(err, name, p->gradient[i], -0.1, 0.1))) return s;
        if (i > 0 && !(p->gradient_start[i] > p->gradient_start[i - 1]))
            return rb_fail(err, RB_EINVAL, "gradient_start[%d] = %g m: must exceed gradient_start[%d] = %g m", i,
                           p->gradient_start[i], i - 1, p->gradient_start[i - 1]);
    }
    if ((s = rb_check_range(err, "ambient_temperature", p->ambient_temperature, 200.0, 350.0))) return s;
    for (int c = 0; c < p->n_cars; ++c) {
        snprintf(name, sizeof name, "car[%d].disc_heat_capacity", c);
        if ((s = rb_check_nonnegative(err, name, p->car[c].disc_heat_capacity))) return s;
        const double surface = p->car[c].disc_surface_capacity, conductance = p->car[c].disc_surface_conductance;
        snprintf(name, sizeof name, "car[%d].disc_surface_capacity", c);
        if ((s = rb_check_nonnegative(err, name, surface))) return s;
        if (surface > 0.0 && !(surface < p->car[c].disc_heat_capacity))
            return rb_fail(err, RB_EINVAL, "%s = %g J/K: must be below disc_heat_capacity = %g J/K (the surface "
                           "layer is part of the disc)", name, surface, p->car[c].disc_heat_capacity);
        snprintf(name, sizeof name, "car[%d].disc_surface_conductance", c);
        if ((s = surface > 0.0 ? rb_check_positive(err, name, conductance) : rb_check_nonnegative(err, name, conductance)))
            return s;
        if (p->car[c].disc_cooling.n > 0 &&
            (s = rb_speed_table_check(&p->car[c].disc_cooling, "disc_cooling", 0.0, 1e5, err)))
            return s;
    }
    return RB_OK;
}

void rb_plant_train_init(const rb_plant_params *p, rb_plant_state *s)
{
    double m = s->m_mr;
    for (int c = 0; c < p->n_cars; ++c) m += s->m_pipe[c];
    s->m_supply_side_initial = m;
    double rt = RB_AIR_R * p->temperature;
    for (int i = 0; i < p->n_compressors; ++i) {
        int c = p->compressor_position[i];
        double fed = c == p->compressor_car ? s->m_mr * rt / p->main_reservoir_volume
                                            : s->m_pipe[c] * rt / p->car[c].pipe_volume;
        s->compressor_running[i] = fed < p->governor_on;
    }
    for (int c = 0; c < p->n_cars; ++c) {   /* empty: the first step finds the cooling's interval */
        const double surface = p->car[c].disc_surface_capacity;
        s->derived.disc_capacity[c] = surface > 0.0 ? surface : p->car[c].disc_heat_capacity;
        s->derived.disc_bulk_capacity[c] = surface > 0.0 ? p->car[c].disc_heat_capacity - surface : 0.0;
        s->derived.disc_conductance[c] = surface > 0.0 ? p->car[c].disc_surface_conductance : 0.0;
        s->derived.cooling_lo[c] = s->derived.cooling_hi[c] = 0.0;
        s->derived.cooling_value_lo[c] = s->derived.cooling_slope[c] = 0.0;
    }
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        s->disc_temperature[a] = s->disc_bulk_temperature[a] = p->ambient_temperature;
        s->brake_energy[a] = 0.0;
    }
}

static void deliver(rb_plant_state *s, double *node, double flow, double dt)
{
    *node += flow * dt;
    s->m_compressed += flow * dt;
}

void rb_plant_compressors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f, double dt)
{
    const rb_plant_derived *d = &s->derived;   /* the nodes' stiffness R T / V, from init */
    if (p->n_compressors == 0) {   /* the single compressor on compressor_car */
        double p_mr = s->m_mr * d->k_mr;
        if (p_mr < p->governor_on) s->compressor_on = 1;
        if (p_mr > p->governor_off) s->compressor_on = 0;
        if (s->compressor_on && !f->compressor_off) deliver(s, &s->m_mr, p->compressor_flow, dt);
        return;
    }
    int any = 0;
    for (int i = 0; i < p->n_compressors; ++i) {
        int c = p->compressor_position[i];
        int into_mr = c == p->compressor_car;
        double *node = into_mr ? &s->m_mr : &s->m_pipe[c];
        double fed = *node * (into_mr ? d->k_mr : d->k_pipe[c]);
        if (fed < p->governor_on) s->compressor_running[i] = 1;
        if (fed > p->governor_off) s->compressor_running[i] = 0;
        if (s->compressor_running[i] && !f->compressor_off) deliver(s, node, p->compressor_delivery[i], dt);
        any |= s->compressor_running[i];
    }
    s->compressor_on = any;
}

double rb_plant_gradient_force(const rb_plant_params *p, const rb_plant_state *s, int c)
{
    if (p->n_gradients == 0) return 0.0;
    double centre = s->x[c] - 0.5 * p->car[c].length;
    int i = 0;
    while (i + 1 < p->n_gradients && centre >= p->gradient_start[i + 1]) ++i;
    double g = p->gradient[i];
    return p->car[c].vehicle.mass * RB_GRAVITY * g / sqrt(1.0 + g * g);
}

static void discs(const rb_plant_params *p, rb_plant_state *s, double dt)
{
    rb_plant_derived *d = &s->derived;
    const int n_cars = p->n_cars;
    double cooling[RB_PLANT_MAX_CARS];
    int64_t outside = 0;   /* as the wheelset kernel's pad look-up (plant_kernel.c) */
    for (int c = 0; c < n_cars; ++c) {   /* W/K, in each car's cached table interval */
        cooling[c] = d->cooling_value_lo[c] + (s->v[c] - d->cooling_lo[c]) * d->cooling_slope[c];
        outside |= rb_plant_sign_bits(s->v[c] - d->cooling_lo[c]) | ~rb_plant_sign_bits(s->v[c] - d->cooling_hi[c]);
    }
    if (outside < 0)
        for (int c = 0; c < n_cars; ++c)
            if (!(s->v[c] >= d->cooling_lo[c] && s->v[c] < d->cooling_hi[c])) {
                rb_plant_table_interval(&p->car[c].disc_cooling, s->v[c], &d->cooling_bracket[c], &d->cooling_lo[c],
                                        &d->cooling_hi[c], &d->cooling_value_lo[c], &d->cooling_slope[c]);
                cooling[c] = d->cooling_value_lo[c] + (s->v[c] - d->cooling_lo[c]) * d->cooling_slope[c];
            }
    /* each car's constants in a vector loop over the cars, then each car's axles (one vector of
       four in AVX2) with them: the two-node disc of rb_vehicle.h (rb_disc_step), surface layer and
       bulk; without a surface layer (Cb = G = 0) the lumped disc's update, bit for bit */
    double to_ambient[RB_PLANT_MAX_CARS], inv_retained[RB_PLANT_MAX_CARS], to_bulk[RB_PLANT_MAX_CARS];
    for (int c = 0; c < n_cars; ++c) {
        to_bulk[c] = rb_disc_to_bulk(d->disc_bulk_capacity[c], d->disc_conductance[c], dt);
        to_ambient[c] = cooling[c] * p->ambient_temperature;
        inv_retained[c] = rb_disc_inverse(d->disc_capacity[c], d->disc_bulk_capacity[c], cooling[c], to_bulk[c], dt);
    }
    for (int c = 0; c < n_cars; ++c) {
        const double capacity = d->disc_capacity[c], amb = to_ambient[c], inv = inv_retained[c];
        const double g = to_bulk[c], bulk_g = d->disc_bulk_capacity[c] * g;
        if (!(capacity > 0.0)) {   /* no heat capacity: no temperature, the energy only */
            for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a)
                s->brake_energy[a] += s->brake_torque[a] * s->omega[a] * dt;
            continue;
        }
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            double power = s->brake_torque[a] * s->omega[a];   /* W into the discs: the step's torque */
            s->brake_energy[a] += power * dt;
            rb_disc_step(capacity, bulk_g, g, inv, dt, power, amb, &s->disc_temperature[a], &s->disc_bulk_temperature[a]);
        }
    }
}

/* As the plant's step (plant_step.c): portable, or for AVX2 in s->kernel, bit for bit the same. */
RB_FLATTEN static void discs_portable(const rb_plant_params *p, rb_plant_state *s, double dt)
{
    discs(p, s, dt);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2"), flatten))
static void discs_avx2(const rb_plant_params *p, rb_plant_state *s, double dt)
{
    discs(p, s, dt);
}
#endif

void rb_plant_discs(const rb_plant_params *p, rb_plant_state *s, double dt)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) {
        discs_avx2(p, s, dt);
        return;
    }
#endif
    discs_portable(p, s, dt);
}


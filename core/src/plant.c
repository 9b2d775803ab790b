/* Whole-train plant: parameter checks, initial state, outputs (the step is in plant_step.c). */
#include "plant_internal.h"
#include "emergency_circuit.h"
#include "railbrake/rb_bounds.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

size_t rb_plant_params_size(void) { return sizeof(rb_plant_params); }
size_t rb_plant_state_size(void) { return sizeof(rb_plant_state); }

/* Checks a field of car i, naming it car[i].field in the message. */
#define CHECK_CAR(check, field, ...)                                          \
    do {                                                                      \
        snprintf(name, sizeof name, "car[%d].%s", i, #field);                 \
        if ((s = check(err, name, c->field, ##__VA_ARGS__))) return s;        \
    } while (0)

static rb_status check_car(const rb_plant_car *c, int i, rb_error *err)
{
    char name[64];
    rb_status s;
    if ((s = rb_car_check(&c->vehicle, err))) return s;
    if (c->vehicle.axles != RB_AXLES_PER_CAR)
        return rb_fail(err, RB_EINVAL, "car[%d].vehicle.axles = %d: the plant models %d axles per car", i,
                       c->vehicle.axles, RB_AXLES_PER_CAR);
    CHECK_CAR(rb_check_range, length, 1.0, 100.0);
    CHECK_CAR(rb_check_positive, ed_tau);
    CHECK_CAR(rb_check_range, ed_slide_slip, 0.0, 1.0);
    CHECK_CAR(rb_check_range, ed_slide_release, 0.0, c->ed_slide_slip);
    CHECK_CAR(rb_check_range, ed_cut_rate, 0.0, 1e3);
    CHECK_CAR(rb_check_range, ed_restore_rate, 0.0, 1e3);
    CHECK_CAR(rb_check_positive, supply_volume);
    CHECK_CAR(rb_check_positive, pilot_volume);
    CHECK_CAR(rb_check_positive, relay_volume);
    CHECK_CAR(rb_check_positive, cylinder_volume);
    CHECK_CAR(rb_check_positive, pipe_volume);
    CHECK_CAR(rb_check_nonnegative, charge_area);
    CHECK_CAR(rb_check_nonnegative, ep_area);
    CHECK_CAR(rb_check_positive, ep_tau);
    CHECK_CAR(rb_check_positive, ep_band);
    CHECK_CAR(rb_check_nonnegative, ep_supply_margin);
    CHECK_CAR(rb_check_nonnegative, ep_bleed_area);
    CHECK_CAR(rb_check_nonnegative, relay_supply_area);
    CHECK_CAR(rb_check_nonnegative, relay_exhaust_area);
    CHECK_CAR(rb_check_positive, relay_band);
    CHECK_CAR(rb_check_nonnegative, relay_tau);
    CHECK_CAR(rb_check_nonnegative, relay_sweep);
    CHECK_CAR(rb_check_range, relay_travel, 1.0, 100.0);
    if (!(c->relay_sweep * c->relay_travel < c->pilot_volume))
        return rb_fail(err, RB_EINVAL, "car[%d].relay_sweep = %g m^3: times relay_travel = %g must stay below the "
                       "pilot_volume = %g m^3 (the membrane's stroke would empty the chamber)", i, c->relay_sweep,
                       c->relay_travel, c->pilot_volume);
    CHECK_CAR(rb_check_nonnegative, hold_area);
    CHECK_CAR(rb_check_nonnegative, vent_area);
    CHECK_CAR(rb_check_range, valve_delay, 0.0, 1.0);
    CHECK_CAR(rb_check_nonnegative, pipe_area);
    for (int k = 0; k < RB_AXLES_PER_CAR; ++k)
        if (!(c->axle_position[k] >= 0.0 && c->axle_position[k] <= c->length))
            return rb_fail(err, RB_EINVAL, "car[%d].axle_position[%d] = %g: must be in [0, length = %g] m",
                           i, k, c->axle_position[k], c->length);
    if (rb_creep_contact_check(&c->contact, err)) return RB_EINVAL;
    return RB_OK;
}

const char *rb_fault_kind_name(int kind)
{
    static const char *const names[RB_FAULT_KINDS] = {
        "hold_stuck_open", "hold_stuck_closed", "vent_stuck_open", "vent_stuck_closed", "sensor_lost",
        "sensor_noisy", "cylinder_leak", "ep_valve_failed", "ed_lost", "car_isolated", "compressor_off",
        "emergency_valve_failed", "emergency_loop_lost", "relay_valve_failed", "pressure_limiter_failed",
        "axle_isolated"};
    return kind >= 0 && kind < RB_FAULT_KINDS ? names[kind] : "unknown";
}

rb_status rb_fault_check(const rb_fault *f, int n_cars, const char *name, rb_error *err)
{
    if (f->kind < 0 || f->kind >= RB_FAULT_KINDS)
        return rb_fail(err, RB_EINVAL, "%s.kind = %d: must be in [0, %d]", name, f->kind, RB_FAULT_KINDS - 1);
    if (f->car < 0 || f->car >= n_cars)
        return rb_fail(err, RB_EINVAL, "%s.car = %d: the train has cars 0..%d", name, f->car, n_cars - 1);
    if (f->axle < -1 || f->axle >= RB_AXLES_PER_CAR)
        return rb_fail(err, RB_EINVAL, "%s.axle = %d: must be -1 (all) or 0..%d", name, f->axle,
                       RB_AXLES_PER_CAR - 1);
    if (!isfinite(f->start_time) || f->start_time < 0.0)
        return rb_fail(err, RB_EINVAL, "%s.start_time = %g: must be finite and >= 0 s", name, f->start_time);
    if (!isfinite(f->value) || f->value < 0.0)
        return rb_fail(err, RB_EINVAL, "%s.value = %g: must be finite and >= 0", name, f->value);
    return RB_OK;
}

static rb_status check_faults(const rb_plant_params *p, rb_error *err)
{
    if (p->n_faults < 0 || p->n_faults > RB_MAX_FAULTS)
        return rb_fail(err, RB_EINVAL, "n_faults = %d: must be in [0, %d]", p->n_faults, RB_MAX_FAULTS);
    for (int i = 0; i < p->n_faults; ++i) {
        char name[24];
        snprintf(name, sizeof name, "fault[%d]", i);
        if (rb_fault_check(&p->fault[i], p->n_cars, name, err)) return RB_EINVAL;
    }
    return RB_OK;
}

static rb_status check_adhesion(const rb_plant_params *p, rb_error *err)
{
    rb_status s;
    if (p->n_conditions < 1 || p->n_conditions > RB_MAX_CONDITIONS)
        return rb_fail(err, RB_EINVAL, "n_conditions = %d: must be in [1, %d]", p->n_conditions, RB_MAX_CONDITIONS);
    for (int i = 0; i < p->n_conditions; ++i) {
        if ((s = rb_polach_check(&p->condition[i].polach, err))) return s;
        if ((s = rb_check_range(err, "condition.leading_factor", p->condition[i].leading_factor, 1e-3, 1.0)))
            return s;
    }
    if (p->n_zones < 0 || p->n_zones > RB_MAX_ZONES)
        return rb_fail(err, RB_EINVAL, "n_zones = %d: must be in [0, %d]", p->n_zones, RB_MAX_ZONES);
    for (int i = 0; i < p->n_zones; ++i) {
        const rb_track_zone *z = &p->zone[i];
        if (!(z->x_end > z->x_start))
            return rb_fail(err, RB_EINVAL, "zone[%d]: x_end = %g must exceed x_start = %g m", i, z->x_end, z->x_start);
        if (z->condition < 0 || z->condition >= p->n_conditions)
            return rb_fail(err, RB_EINVAL, "zone[%d].condition = %d: must be in [0, %d]", i, z->condition,
                           p->n_conditions - 1);
    }
    return rb_check_positive(err, "creep_speed_min", p->creep_speed_min);
}

rb_status rb_plant_check(const rb_plant_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "params = NULL: plant parameters are required");
    if (p->n_cars < 1 || p->n_cars > RB_PLANT_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "n_cars = %d: must be in [1, %d]", p->n_cars, RB_PLANT_MAX_CARS);
    if ((s = rb_check_range(err, "dt", p->dt, 1e-5, 0.01))) return s;
    if ((s = rb_check_range(err, "substeps", p->substeps, 1, 64))) return s;
    if ((s = rb_check_range(err, "temperature", p->temperature, 200.0, 400.0))) return s;
    if ((s = rb_check_range(err, "atmosphere", p->atmosphere, 5e4, 1.2e5))) return s;
    if ((s = rb_check_range(err, "discharge_coefficient", p->discharge_coefficient, 0.01, 1.0))) return s;
    if ((s = rb_check_range(err, "critical_ratio", p->critical_ratio, 0.0, 0.99))) return s;
    for (int i = 0; i < p->n_cars; ++i)
        if ((s = check_car(&p->car[i], i, err)) || (s = rb_emergency_check(&p->car[i], i, p->atmosphere, err))) return s;
    if (p->n_cars > 1 && (s = rb_coupler_check(&p->coupler, err))) return s;
    if ((s = rb_resistance_check(&p->resistance, err))) return s;
    if (p->compressor_car < 0 || p->compressor_car >= p->n_cars)
        return rb_fail(err, RB_EINVAL, "compressor_car = %d: must be in [0, %d]", p->compressor_car, p->n_cars - 1);
    if ((s = rb_check_positive(err, "main_reservoir_volume", p->main_reservoir_volume))) return s;
    if ((s = rb_check_positive(err, "main_reservoir_area", p->main_reservoir_area))) return s;
    if ((s = rb_check_nonnegative(err, "compressor_flow", p->compressor_flow))) return s;
    if ((s = rb_check_range(err, "initial_pressure", p->initial_pressure, p->atmosphere, 2e6))) return s;
    if ((s = rb_check_range(err, "governor_on", p->governor_on, p->atmosphere, 2e6))) return s;
    if ((s = rb_check_range(err, "governor_off", p->governor_off, p->governor_on, 2e6))) return s;
    if ((s = rb_check_range(err, "initial_speed", p->initial_speed, 0.0, 150.0))) return s;
    if ((s = check_adhesion(p, err))) return s;
    if (p->kernel != RB_PLANT_KERNEL_AUTO && p->kernel != RB_PLANT_KERNEL_PORTABLE)
        return rb_fail(err, RB_EINVAL, "kernel = %d: must be %d (auto) or %d (portable)", p->kernel,
                       RB_PLANT_KERNEL_AUTO, RB_PLANT_KERNEL_PORTABLE);
    if ((s = rb_bound_check(err, "wall_time", "wall_time", p->wall_time))) return s;
    if ((s = rb_plant_train_check(p, err))) return s;
    if ((s = rb_rail_check(p, err))) return s;
    return check_faults(p, err);
}

/* Number of links of car c's MR pipe node (the stiff-link limit divides by it). */
static double pipe_links(const rb_plant_params *p, int c)
{
    return 1.0 + (c > 0) + (c < p->n_cars - 1) + (c == p->compressor_car);
}

/* The cylinders' energy balance (rb_plant_params.wall_time): adiabatic exponent, R / V, and the
 * wall's exchange per step, h x h A / cv = h m_ref / wall_time (kg; times wall minus air
 * temperature, the step's change of m T). Within a step an adiabatic cylinder is gamma times
 * stiffer than an isothermal one (dp = gamma R T dm / V): its links' equalising masses say so. */
static void derive_cylinders(const rb_plant_params *p, rb_plant_derived *d)
{
    int thermal = p->wall_time > 0.0;
    double m_ref_per_volume = RB_WALL_REFERENCE_PRESSURE / (RB_AIR_R * p->temperature);
    d->gamma_cyl = thermal ? RB_AIR_GAMMA : 1.0;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        d->r_cyl[c] = RB_AIR_R / car->cylinder_volume;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) d->axle_r_cyl[a] = d->r_cyl[c];
        double heat = thermal ? d->h * m_ref_per_volume * car->cylinder_volume / p->wall_time : 0.0;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) d->axle_heat_cyl[a] = heat;
        const double relay_links = 2.0 + RB_AXLES_PER_CAR, cyl_links = 3.0;
        double k_cyl = d->gamma_cyl * d->k_cyl[c];
        d->ik_hold[c] = 1.0 / (relay_links * d->k_relay[c] + cyl_links * k_cyl);
        d->ik_vent[c] = 1.0 / (cyl_links * k_cyl);
        d->ik_hold_rate[c] = 1.0 / (d->k_relay[c] + k_cyl);
        d->ik_vent_rate[c] = 1.0 / k_cyl;
        double fill = d->ik_hold_rate[c] * rb_one_minus_exp_neg(d->h * d->orifice.laminar_slope * d->g_hold[c] / d->ik_hold_rate[c]);
        d->hold_laminar[c] = fill < d->ik_hold[c] ? fill : d->ik_hold[c];
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            d->axle_hold_laminar[a] = d->hold_laminar[c];
            d->axle_g_vent[a] = d->g_vent[c];
        }
    }
}

/* The air system's constants: node stiffness R T / V, link conductances, 1 / (n_i k_i + n_j k_j). */
static void derive_air(const rb_plant_params *p, rb_plant_derived *d)
{
    double rt = RB_AIR_R * p->temperature;
    d->h = p->dt / p->substeps;
    d->g_unit = rb_orifice_unit_conductance(p->discharge_coefficient, p->temperature);
    rb_orifice_law_init(p->critical_ratio, &d->orifice);
    d->h_laminar = d->h * d->orifice.laminar_slope;
    d->k_mr = rt / p->main_reservoir_volume;
    d->g_mr = d->g_unit * p->main_reservoir_area;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        d->k_pipe[c] = rt / car->pipe_volume;
        d->k_supply[c] = rt / car->supply_volume;
        d->supply_volume[c] = car->supply_volume;
        d->k_pilot[c] = rt / car->pilot_volume;
        d->k_relay[c] = rt / car->relay_volume;
        d->k_cyl[c] = rt / car->cylinder_volume;
    }
    const double supply_links = 3.0, pilot_links = 2.0, relay_links = 2.0 + RB_AXLES_PER_CAR;
    int cc = p->compressor_car;
    d->ik_mr = 1.0 / (d->k_mr + pipe_links(p, cc) * d->k_pipe[cc]);
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        double n_pipe = pipe_links(p, c);
        d->g_pipe[c] = c + 1 < p->n_cars ? d->g_unit * car->pipe_area : 0.0;
        d->ik_pipe[c] = c + 1 < p->n_cars ? 1.0 / (n_pipe * d->k_pipe[c] + pipe_links(p, c + 1) * d->k_pipe[c + 1]) : 0.0;
        d->g_charge[c] = d->g_unit * car->charge_area;
        d->ik_charge[c] = 1.0 / (n_pipe * d->k_pipe[c] + supply_links * d->k_supply[c]);
        d->g_ep[c] = d->g_unit * car->ep_area;
        d->ik_ep_in[c] = 1.0 / (supply_links * d->k_supply[c] + pilot_links * d->k_pilot[c]);
        d->ik_ep_out[c] = 1.0 / (pilot_links * d->k_pilot[c]);
        d->g_relay_supply[c] = d->g_unit * car->relay_supply_area;
        d->g_relay_exhaust[c] = d->g_unit * car->relay_exhaust_area;
        d->ik_relay_supply[c] = 1.0 / (supply_links * d->k_supply[c] + relay_links * d->k_relay[c]);
        d->ik_relay_exhaust[c] = 1.0 / (relay_links * d->k_relay[c]);
        d->g_hold[c] = d->g_unit * car->hold_area;
        d->g_vent[c] = d->g_unit * car->vent_area;
        d->inv_ep_band[c] = 1.0 / car->ep_band;
        d->ep_supply_margin[c] = car->ep_supply_margin;
        d->inv_relay_band[c] = 1.0 / car->relay_band;
        d->ep_lag[c] = d->h / (car->ep_tau + d->h);
        d->g_bleed[c] = d->g_unit * car->ep_bleed_area;
        d->relay_lag[c] = car->relay_tau > 0.0 ? -expm1(-d->h / car->relay_tau) : 1.0;
        d->sweep_ratio[c] = car->relay_sweep / car->pilot_volume;
        d->relay_travel[c] = car->relay_travel;
        d->g_emergency[c] = d->g_unit * car->emergency_area;
        d->fill_pipe[c] = rb_plant_link_laminar_fill(d, d->g_pipe[c], d->ik_pipe[c]);
        d->fill_charge[c] = rb_plant_link_laminar_fill(d, d->g_charge[c], d->ik_charge[c]);
    }
    d->fill_mr = rb_plant_link_laminar_fill(d, d->g_mr, d->ik_mr);
    derive_cylinders(p, d);
}

/* The mechanics' constants per car and per axle (the step's own dt stays an argument: the detailed
   model steps the same mechanics at its own step). */
static void derive_mechanics(const rb_plant_params *p, rb_plant_derived *d)
{
    double total_mass = 0.0;
    d->slip_probe_ahead = 1.0;   /* (the detailed model sets 0 after init) */
    for (int c = 0; c < p->n_cars; ++c) total_mass += p->car[c].vehicle.mass;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        const rb_wheelset *w = &car->vehicle.wheelset;
        const rb_axle_brake *b = &car->vehicle.brake;
        const rb_creep_contact *k = &car->contact;
        d->inv_mass[c] = 1.0 / car->vehicle.mass;
        d->mass_share[c] = car->vehicle.mass / total_mass;
        double axle_load = w->axle_load * RB_G, wheel_load = 0.5 * axle_load;
        d->radius[c] = w->wheel_radius;
        d->inv_inertia[c] = 1.0 / w->inertia;
        d->axle_load[c] = axle_load;
        d->compliance[c] = w->wheel_radius * w->wheel_radius / w->inertia + 1.0 / car->vehicle.mass;
        d->polach_gain[c] = k->shear_modulus * M_PI * k->a * k->b * k->c11 / (4.0 * wheel_load);
        d->brake_gain[c] = b->discs * 2.0 * b->mean_radius * b->caliper.lever_ratio * b->caliper.efficiency;
        d->caliper_atmosphere[c] = b->caliper.atmospheric_pressure;
        d->caliper_area[c] = b->caliper.cylinder_area;
        d->caliper_spring[c] = b->caliper.return_spring;
        d->car_length[c] = car->length;
        d->ed_lag[c] = d->h / (car->ed_tau + d->h);   /* derive_air set h */
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            d->axle_radius[a] = d->radius[c];
            d->axle_inv_inertia[a] = d->inv_inertia[c];
            d->axle_inv_mass[a] = d->inv_mass[c];
            d->axle_axle_load[a] = d->axle_load[c];
            d->axle_compliance[a] = d->compliance[c];
            d->axle_brake_per_pa[a] = d->brake_gain[c] * d->caliper_area[c];
            d->axle_brake_offset[a] = d->brake_gain[c] * (d->caliper_atmosphere[c] * d->caliper_area[c] + d->caliper_spring[c]);
            d->axle_inv_axle_load[a] = 1.0 / d->axle_load[c];
            d->pad_bracket[a] = 0;
            d->pad_speed_lo[a] = d->pad_speed_hi[a] = 0.0;   /* empty: the kernel's first look-up fills it */
            d->pad_value_lo[a] = d->pad_slope[a] = 0.0;
            d->pad_fade_onset[a] = b->pad.fade_onset;
            d->pad_fade_rate[a] = b->pad.fade_rate;
        }
    }
}

int rb_plant_resolve_kernel(int requested)
{
#if RB_PLANT_HAVE_AVX2
    if (requested == RB_PLANT_KERNEL_AUTO) {
        __builtin_cpu_init();
        if (__builtin_cpu_supports("avx2")) return RB_PLANT_KERNEL_AVX2;
    }
#endif
    (void)requested;
    return RB_PLANT_KERNEL_PORTABLE;
}

const char *rb_plant_kernel_name(const rb_plant_state *s)
{
    return s->kernel == RB_PLANT_KERNEL_AVX2 ? "avx2" : "portable";
}

rb_status rb_plant_init(const rb_plant_params *p, rb_plant_state *s, rb_error *err)
{
    rb_status st;
    if (!s) return rb_fail(err, RB_EINVAL, "state = NULL: a state is required");
    if ((st = rb_plant_check(p, err))) return st;
    memset(s, 0, sizeof *s);
    derive_air(p, &s->derived);
    derive_mechanics(p, &s->derived);
    s->kernel = rb_plant_resolve_kernel(p->kernel);
    rb_rail_init(p, s);   /* before the axles take their adhesion from it */
    double rt = 287.05 * p->temperature;
    double pos = 0.0;
    s->m_mr = p->initial_pressure * p->main_reservoir_volume / rt;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        s->m_pipe[c] = p->initial_pressure * car->pipe_volume / rt;
        s->m_supply[c] = p->initial_pressure * car->supply_volume / rt;
        s->m_pilot[c] = p->atmosphere * car->pilot_volume / rt;
        s->m_relay[c] = p->atmosphere * car->relay_volume / rt;
        s->ep_demand_lag[c] = p->atmosphere;
        s->ed_slide_factor[c] = 1.0;
        s->x[c] = -pos;
        s->v[c] = p->initial_speed;
        pos += car->length;
        for (int k = 0; k < RB_AXLES_PER_CAR; ++k) {
            int a = c * RB_AXLES_PER_CAR + k;
            s->m_cyl[a] = p->atmosphere * car->cylinder_volume / rt;
            s->mt_cyl[a] = s->m_cyl[a] * p->temperature;
            s->omega[a] = p->initial_speed / car->vehicle.wheelset.wheel_radius;
            s->zone_of[a] = -1;
            rb_plant_zone_update(p, s, a, s->x[c] - car->axle_position[k]);
        }
    }
    s->compressor_on = p->initial_pressure < p->governor_on;
    s->loop_open_time = -1.0;   /* emergency loop closed */
    rb_plant_pilot_init(p, s);
    s->rng = p->noise_seed ? p->noise_seed : 0x9E3779B97F4A7C15ULL;
    s->m_initial = rb_plant_air_mass(p, s);
    rb_plant_train_init(p, s);
    return RB_OK;
}

rb_status rb_plant_retune_adhesion(const rb_plant_params *p, rb_plant_state *s, rb_error *err)
{
    rb_status st;
    if (!s) return rb_fail(err, RB_EINVAL, "state = NULL: a state is required");
    if ((st = rb_plant_check(p, err)) || (st = rb_plant_bounds_check(p, err))) return st;
    for (int c = 0; c < p->n_cars; ++c)
        for (int k = 0; k < RB_AXLES_PER_CAR; ++k) {
            int a = c * RB_AXLES_PER_CAR + k;
            s->zone_of[a] = -1;   /* forces the axle's Polach parameters to be derived again */
            rb_plant_zone_update(p, s, a, s->x[c] - p->car[c].axle_position[k]);
        }
    return RB_OK;
}

double rb_plant_axle_brake_torque(const rb_plant_car *c, double p_cyl, double wheel_speed)
{
    return rb_axle_brake_torque(&c->vehicle.brake, p_cyl, wheel_speed);
}

double rb_plant_peak_adhesion(const rb_plant_params *p, const rb_plant_state *s, int axle)
{
    const rb_plant_car *car = &p->car[axle / RB_AXLES_PER_CAR];
    double peak = 0.0, wheel_load = 0.5 * car->vehicle.wheelset.axle_load * RB_G;
    double v = s->v[axle / RB_AXLES_PER_CAR];
    if (rb_polach_peak(v > 0.0 ? v : 0.0, wheel_load, &car->contact, &s->polach[axle], &peak, NULL, NULL))
        return 0.0;
    return peak;
}



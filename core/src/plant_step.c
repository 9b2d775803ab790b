/* One fixed step of the whole-train plant: faults, air system, wheelsets, cars. */
#include "plant_internal.h"

#include <math.h>
#include <string.h>

#define RB_G 9.80665

void rb_plant_gather_faults(const rb_plant_params *p, const rb_plant_state *s, rb_plant_faults *f)
{
    memset(f, 0, sizeof *f);
    memset(f->hold, -1, sizeof f->hold);
    memset(f->vent, -1, sizeof f->vent);
    for (int i = 0; i < p->n_faults; ++i) {
        const rb_fault *q = &p->fault[i];
        if (s->time < q->start_time) continue;
        int first = q->car * RB_AXLES_PER_CAR + (q->axle < 0 ? 0 : q->axle);
        int last = q->axle < 0 ? first + RB_AXLES_PER_CAR : first + 1;
        for (int a = first; a < last; ++a) {
            switch (q->kind) {
            case RB_FAULT_HOLD_STUCK_OPEN: f->hold[a] = 0; break;
            case RB_FAULT_HOLD_STUCK_CLOSED: f->hold[a] = 1; break;
            case RB_FAULT_VENT_STUCK_OPEN: f->vent[a] = 1; break;
            case RB_FAULT_VENT_STUCK_CLOSED: f->vent[a] = 0; break;
            case RB_FAULT_SENSOR_LOST: f->noise_sd[a] = -1.0; break;
            case RB_FAULT_SENSOR_NOISY: if (f->noise_sd[a] >= 0.0) f->noise_sd[a] = q->value; break;
            case RB_FAULT_CYLINDER_LEAK: f->leak[a] += q->value; break;
            default: break;
            }
        }
        if (q->kind == RB_FAULT_EP_VALVE) f->ep_failed[q->car] = 1;
        if (q->kind == RB_FAULT_ED_LOST) f->ed_lost[q->car] = 1;
        if (q->kind == RB_FAULT_CAR_ISOLATED) f->isolated[q->car] = 1;
        if (q->kind == RB_FAULT_COMPRESSOR_OFF) f->compressor_off = 1;
    }
}

/* Deterministic noise: xorshift64*, Gaussian by Box-Muller. */
static double uniform01(uint64_t *x)
{
    *x ^= *x >> 12; *x ^= *x << 25; *x ^= *x >> 27;
    return ((*x * 0x2545F4914F6CDD1DULL) >> 11) * (1.0 / 9007199254740992.0) + 1e-300;
}

static double gaussian(uint64_t *x)
{
    double u1 = uniform01(x), u2 = uniform01(x);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* ------------------------------------------------------------------ air */

typedef struct {
    double dt, rt, T, patm, cd, b;
    double vented;
} air_ctx;

/* Moves air from node i to node j (j = NULL: atmosphere) through an orifice of `area`;
 * k = R T / V turns a node's mass into its pressure; n_i, n_j: number of links of each node
 * (see rb_plant.h on the stiff-link limit). */
static void transfer(air_ctx *x, double *mi, double ki, double ni, double *mj, double kj, double nj,
                     double area)
{
    if (area <= 0.0) return;
    double pi = *mi * ki, pj = mj ? *mj * kj : x->patm;
    if (fabs(pi - pj) < 0.01) return;   /* balanced to 0.01 Pa: nothing worth moving */
    double q = rb_orifice_mass_flow_fast(pi, x->T, pj, x->T, area, x->cd, x->b);
    if (q == 0.0) return;
    double flow = x->dt * fabs(q);
    double equalise = fabs(pi - pj) / (ni * ki + (mj ? nj * kj : 0.0));
    double dm = flow * equalise / (flow + equalise);
    if (q < 0.0) dm = -dm;
    *mi -= dm;
    if (mj) *mj += dm;
    else x->vented += dm;
}

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* Valve switching after the response delay; a stuck valve ignores its command. */
static uint8_t valve(uint8_t cmd, uint8_t *actual, uint8_t *pending, double *timer, double delay,
                     double dt, signed char stuck)
{
    if (cmd != *pending) { *pending = cmd; *timer = delay; }
    if (*actual != *pending) {
        *timer -= dt;
        if (*timer <= 0.0) *actual = *pending;
    }
    return stuck >= 0 ? (uint8_t)stuck : *actual;
}

static void step_air(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                     const rb_plant_faults *f, double dt, uint8_t *hold_eff, uint8_t *vent_eff)
{
    air_ctx x = {dt, RB_AIR_R * p->temperature, p->temperature, p->atmosphere,
                 p->discharge_coefficient, p->critical_ratio, 0.0};
    double rt = x.rt;
    /* compressor with on/off governor */
    rb_plant_compressors(p, s, f, dt);
    int last = p->n_cars - 1;
    double k_mr = rt / p->main_reservoir_volume, k_next_pipe = rt / p->car[0].pipe_volume;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        double k_pipe = k_next_pipe, k_supply = rt / car->supply_volume, k_pilot = rt / car->pilot_volume;
        double k_relay = rt / car->relay_volume, k_cyl = rt / car->cylinder_volume;
        if (c < last) k_next_pipe = rt / p->car[c + 1].pipe_volume;
        double pipe_links = 1.0 + (c > 0) + (c < last) + (c == p->compressor_car);
        if (c == p->compressor_car)
            transfer(&x, &s->m_mr, k_mr, 1.0, &s->m_pipe[c], k_pipe, pipe_links, p->main_reservoir_area);
        if (c < last)
            transfer(&x, &s->m_pipe[c], k_pipe, pipe_links, &s->m_pipe[c + 1], k_next_pipe,
                     1.0 + 1.0 + (c + 1 < last) + (c + 1 == p->compressor_car), car->pipe_area);
        /* check valve and choke: only towards the supply reservoir */
        if (s->m_pipe[c] * k_pipe > s->m_supply[c] * k_supply)
            transfer(&x, &s->m_pipe[c], k_pipe, pipe_links, &s->m_supply[c], k_supply, 3.0, car->charge_area);
        /* EP valve: lagged demand, ports open in proportion to the error */
        double demand = in->pressure_demand[c] > p->atmosphere ? in->pressure_demand[c] : p->atmosphere;
        s->ep_demand_lag[c] += (demand - s->ep_demand_lag[c]) * dt / (car->ep_tau + dt);
        double p_pilot = s->m_pilot[c] * k_pilot;
        if (!f->ep_failed[c]) {
            double e = (s->ep_demand_lag[c] - p_pilot) / car->ep_band;
            transfer(&x, &s->m_supply[c], k_supply, 3.0, &s->m_pilot[c], k_pilot, 2.0, car->ep_area * clamp01(e));
            transfer(&x, &s->m_pilot[c], k_pilot, 2.0, NULL, 0.0, 0.0, car->ep_area * clamp01(-e));
            p_pilot = s->m_pilot[c] * k_pilot;
        }
        /* relay valve: output follows the pilot; an isolated car is cut off and vented */
        double target = f->isolated[c] ? p->atmosphere : p_pilot;
        double e = (target - s->m_relay[c] * k_relay) / car->relay_band;
        double relay_links = 2.0 + RB_AXLES_PER_CAR;
        transfer(&x, &s->m_supply[c], k_supply, 3.0, &s->m_relay[c], k_relay, relay_links,
                 f->isolated[c] ? 0.0 : car->relay_supply_area * clamp01(e));
        transfer(&x, &s->m_relay[c], k_relay, relay_links, NULL, 0.0, 0.0,
                 car->relay_exhaust_area * (f->isolated[c] ? 1.0 : clamp01(-e)));
        for (int k = 0; k < RB_AXLES_PER_CAR; ++k) {
            int a = c * RB_AXLES_PER_CAR + k;
            hold_eff[a] = valve(in->hold[a] != 0, &s->hold[a], &s->hold_pending[a], &s->hold_timer[a],
                                car->valve_delay, dt, f->hold[a]);
            vent_eff[a] = valve(in->vent[a] != 0, &s->vent[a], &s->vent_pending[a], &s->vent_timer[a],
                                car->valve_delay, dt, f->vent[a]);
            if (!hold_eff[a])
                transfer(&x, &s->m_relay[c], k_relay, relay_links, &s->m_cyl[a], k_cyl, 3.0, car->hold_area);
            if (vent_eff[a])
                transfer(&x, &s->m_cyl[a], k_cyl, 3.0, NULL, 0.0, 0.0, car->vent_area);
            transfer(&x, &s->m_cyl[a], k_cyl, 3.0, NULL, 0.0, 0.0, f->leak[a]);
        }
    }
    s->m_vented += x.vented;
}

/* ------------------------------------------------------------------ mechanics */

/* Advances the wheelsets of car c; returns the sum of their rail forces on the car (N). */
static double step_wheelsets(const rb_plant_params *p, rb_plant_state *s, int c, double other_force,
                             double mass, const rb_plant_faults *f, const double *cylinder, double dt)
{
    const rb_plant_car *car = &p->car[c];
    double r = car->vehicle.wheelset.wheel_radius, J = car->vehicle.wheelset.inertia;
    double v = s->v[c], vr = v > p->creep_speed_min ? v : p->creep_speed_min;
    double axle_load = car->vehicle.wheelset.axle_load * RB_G, wheel_load = 0.5 * axle_load;
    double ed_axle = f->ed_lost[c] ? 0.0 : s->ed_force[c] / RB_AXLES_PER_CAR * r;
    double old_sum = 0.0, new_sum = 0.0;
    for (int k = 0; k < RB_AXLES_PER_CAR; ++k) old_sum += s->force[c * RB_AXLES_PER_CAR + k];
    for (int k = 0; k < RB_AXLES_PER_CAR; ++k) {
        int a = c * RB_AXLES_PER_CAR + k;
        rb_plant_zone_update(p, s, a, s->x[c] - car->axle_position[k]);
        double w = s->omega[a] * r - v;
        double creep = w / vr;
        double probe = fabs(creep) > 1e-7 ? creep : -1e-7;
        double f_probe = rb_polach_coefficient_fast(probe, v, wheel_load, &car->contact, &s->polach[a]);
        double stiffness = axle_load * (f_probe / probe) / vr;   /* secant, N per m/s of slip velocity */
        double torque = rb_plant_axle_brake_torque(car, cylinder[a], s->omega[a] * r)
                        + ed_axle;
        /* slip velocity, linearly implicit in this axle's own rail force */
        double others = other_force + old_sum - s->force[a];
        double w_new = (w + dt * (-r * torque / J - others / mass))
                       / (1.0 + dt * stiffness * (r * r / J + 1.0 / mass));
        double force = stiffness * w_new;
        double omega = s->omega[a] + dt * (-force * r - torque) / J;
        if (omega < 0.0) {   /* pads hold the wheel: locked, sliding at the train speed */
            omega = 0.0;
            force = axle_load * rb_polach_coefficient_fast(-v / vr, v, wheel_load, &car->contact, &s->polach[a]);
        }
        s->omega[a] = omega;
        s->force[a] = force;
        s->coefficient[a] = force / axle_load;
        new_sum += force;
    }
    return new_sum;
}

void rb_plant_step_mechanics(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                             const rb_plant_faults *f, const double *cylinder, double dt)
{
    double total_mass = 0.0, coupler[RB_PLANT_MAX_CARS + 1] = {0.0};
    for (int c = 0; c < p->n_cars; ++c) total_mass += p->car[c].vehicle.mass;
    for (int c = 0; c + 1 < p->n_cars; ++c)  /* tension positive */
        coupler[c + 1] = rb_coupler_force(&p->coupler, s->x[c] - s->x[c + 1] - p->car[c].length,
                                          s->v[c] - s->v[c + 1]);
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        double v = s->v[c];
        double ed_max = car->vehicle.motor && !f->ed_lost[c] && v > 0.0 ? rb_ed_brake_force_max(&car->vehicle.ed, v) : 0.0;
        double ed = in->ed_demand[c] > 0.0 ? in->ed_demand[c] : 0.0;
        double ed_target = ed < ed_max ? ed : ed_max;
        s->ed_force[c] += (ed_target - s->ed_force[c]) * dt / (car->ed_tau + dt);
        double mass = car->vehicle.mass;
        double resistance = v > 0.0 ? rb_running_resistance(&p->resistance, v) * mass / total_mass : 0.0;
        double other = coupler[c] - coupler[c + 1] - resistance   /* tension pulls c back */
                       - rb_plant_gradient_force(p, s, c);
        double rail = step_wheelsets(p, s, c, other, mass, f, cylinder, dt);
        s->a[c] = (rail + other) / mass;
    }
    for (int c = 0; c < p->n_cars; ++c) {
        s->v[c] += dt * s->a[c];
        if (s->v[c] < 0.0) s->v[c] = 0.0;   /* brakes hold a stopped train */
        s->x[c] += dt * s->v[c];
    }
}

void rb_plant_update_sensors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f)
{
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        s->sensor_lost[a] = f->noise_sd[a] < 0.0;
        s->noise[a] = f->noise_sd[a] > 0.0 ? f->noise_sd[a] * gaussian(&s->rng) : 0.0;
    }
}

void rb_plant_step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in)
{
    rb_plant_faults f;
    double cylinder[RB_PLANT_MAX_AXLES];
    rb_plant_gather_faults(p, s, &f);
    double h = p->dt / p->substeps;
    for (int k = 0; k < p->substeps; ++k) {
        step_air(p, s, in, &f, h, s->hold_effective, s->vent_effective);
        for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a)
            cylinder[a] = s->m_cyl[a] * (RB_AIR_R * p->temperature) / p->car[a / RB_AXLES_PER_CAR].cylinder_volume;
        rb_plant_step_mechanics(p, s, in, &f, cylinder, h);
        rb_plant_discs(p, s, cylinder, h);
    }
    rb_plant_update_sensors(p, s, &f);
    s->step += 1;
    s->time = (double)s->step * p->dt;
}

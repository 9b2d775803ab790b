/* One fixed step of the whole-train plant: faults, air system, wheelsets, cars. */
#include "plant_internal.h"
#include "emergency_circuit.h"

#include <math.h>
#include <string.h>


/* The faults of a plant without any: every valve as commanded, nothing leaking or lost (what
   gather_faults gives then, without its clearing of 1.2 kB in every step). */
#define RB_NONE_4 -1, -1, -1, -1
#define RB_NONE_16 RB_NONE_4, RB_NONE_4, RB_NONE_4, RB_NONE_4
typedef char rb_no_faults_fills_every_axle[RB_PLANT_MAX_AXLES == 64 ? 1 : -1];
static const rb_plant_faults no_faults = {{RB_NONE_16, RB_NONE_16, RB_NONE_16, RB_NONE_16},
                                          {RB_NONE_16, RB_NONE_16, RB_NONE_16, RB_NONE_16}, {0.0}, {0.0}, {0}, {0.0}, {0.0}, 0, 0,
                                          {0.0}, {0.0}, {0.0}, {0.0}, 0, {0.0}, 0};

static void gather_faults(const rb_plant_params *p, const rb_plant_state *s, rb_plant_faults *f)
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
            case RB_FAULT_SENSOR_LOST: f->noise_sd[a] = -1.0; f->sensor_faults = 1; break;
            case RB_FAULT_SENSOR_NOISY: if (f->noise_sd[a] >= 0.0) f->noise_sd[a] = q->value; f->sensor_faults = 1; break;
            case RB_FAULT_CYLINDER_LEAK: f->leak[a] += q->value; break;
            /* the isolating cock cuts the cylinder off from its relay and vents it: the hold
               valve's and vent valve's paths, held shut and open */
            case RB_FAULT_AXLE_ISOLATED: f->hold[a] = 1; f->vent[a] = 1; break;
            default: break;
            }
        }
        if (q->kind == RB_FAULT_EP_VALVE) f->ep_failed[q->car] = 1.0;
        if (q->kind == RB_FAULT_ED_LOST) f->ed_lost[q->car] = 1;
        if (q->kind == RB_FAULT_CAR_ISOLATED) f->isolated[q->car] = 1.0;
        if (q->kind == RB_FAULT_COMPRESSOR_OFF) f->compressor_off = 1;
        if (q->kind == RB_FAULT_EMERGENCY_VALVE) f->emergency_failed[q->car] = 1.0;
        if (q->kind == RB_FAULT_EMERGENCY_LOOP) f->loop_lost[q->car] = 1.0;
        if (q->kind == RB_FAULT_RELAY_VALVE) f->relay_limit[q->car] = p->atmosphere + q->value;
        if (q->kind == RB_FAULT_LIMITER) f->limiter[q->car] = p->atmosphere + q->value;
        f->emergency_faults |= q->kind >= RB_FAULT_EMERGENCY_VALVE && q->kind <= RB_FAULT_LIMITER;
        if (q->kind == RB_FAULT_PIPE_LEAK) { f->pipe_leak[q->car] += q->value; f->pipe_leaks = 1; }
    }
}

/* The emergency path's faults on the circuit's state of this step (rb_emergency_plant_update): a
 * car that does not see the loop keeps its EP valve (not cut off, no choke); a failed emergency
 * valve leaves the EP valve cut off and its choke shut; a failed limiter regulates the choke's
 * source to its own pressure (the BCU's demand still above it or below it, as the sound valve). */
static void apply_emergency_faults(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                                   const rb_plant_faults *f)
{
    for (int c = 0; c < p->n_cars; ++c) {
        if (f->loop_lost[c] > 0.0) s->emergency_open[c] = 0.0;
        if (f->loop_lost[c] > 0.0 || f->emergency_failed[c] > 0.0) s->emergency_g[c] = 0.0;
        if (f->limiter[c] > 0.0) {
            double target = in->pressure_demand[c] < f->limiter[c] ? in->pressure_demand[c] : f->limiter[c];
            s->emergency_target[c] = target > p->atmosphere ? target : p->atmosphere;
        }
    }
}

/* The control pressure a car's relay valve follows: its pilot chamber's, or at most the pressure a
 * failed relay holds its output at. */
static inline double relay_control(const rb_plant_faults *f, int c, double pilot)
{
    double limit = f->relay_limit[c];
    return limit > 0.0 && limit < pilot ? limit : pilot;
}

/* (exported functions are not inlined into the step under -fPIC: the step calls the static one) */
void rb_plant_gather_faults(const rb_plant_params *p, const rb_plant_state *s, rb_plant_faults *f)
{
    gather_faults(p, s, f);
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

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* A WSP valve with its response delay over one step h: returns the fraction of the step it is on
 * (hold: closed, vent: open). A command starts the delay timer; the valve switches the moment the
 * timer runs out, and is on for the part of the step after that, so the delay is the same at any
 * step. *effective: its state at the end of the step; a stuck valve ignores its command. */
static double valve(uint8_t cmd, uint8_t *actual, uint8_t *pending, double *timer, double delay,
                    double h, signed char stuck, uint8_t *effective)
{
    uint8_t now = *actual, next = *pending;   /* in locals: stores through uint8_t * alias everything */
    double on = now;
    if (cmd != next) { *pending = next = cmd; *timer = delay; }
    if (now != next) {
        double left = *timer;
        if (left < h * (1.0 - 1e-9)) {   /* runs out within this step (not at its very end) */
            double after = left > 0.0 ? (h - left) / h : 1.0;
            on = next ? after : 1.0 - after;
            *actual = now = next;
            *timer = 0.0;
        } else {
            *timer = left - h;
        }
    }
    if (stuck >= 0) { *effective = (uint8_t)stuck; return stuck; }
    *effective = now;
    return on;
}

/* The four WSP valve pairs of the car from axle a on at rest: commanded as they stand, no timer
 * running, none stuck (four bytes compared at once). */
static int valves_at_rest(const rb_plant_inputs *in, const rb_plant_state *s, const rb_plant_faults *f, int a)
{
    uint32_t cmd_hold, cmd_vent, hold, vent, pending_hold, pending_vent, stuck_hold, stuck_vent;
    memcpy(&cmd_hold, &in->hold[a], 4); memcpy(&cmd_vent, &in->vent[a], 4);
    memcpy(&hold, &s->hold[a], 4); memcpy(&vent, &s->vent[a], 4);
    memcpy(&pending_hold, &s->hold_pending[a], 4); memcpy(&pending_vent, &s->vent_pending[a], 4);
    memcpy(&stuck_hold, &f->hold[a], 4); memcpy(&stuck_vent, &f->vent[a], 4);
    return ((cmd_hold ^ hold) | (cmd_vent ^ vent) | (pending_hold ^ hold) | (pending_vent ^ vent) |
            ~stuck_hold | ~stuck_vent) == 0;   /* commands 0/1 as the states; stuck -1: none */
}

/* Whether every WSP valve of the train rests released: no hold or vent commanded, none held or
 * vented, none waiting for its delay (the bytes of the six arrays ORed four at a time; a command
 * is any non-zero byte, as valve() reads it). With no faults, what valve() gives every axle is
 * then known without it: hold open all the step, vent shut. */
static int train_valves_quiet(const rb_plant_inputs *in, const rb_plant_state *s, int n_axles)
{
    uint32_t any = 0;
    for (int a = 0; a < n_axles; a += 4) {
        uint32_t w[6];
        memcpy(&w[0], &in->hold[a], 4); memcpy(&w[1], &in->vent[a], 4);
        memcpy(&w[2], &s->hold[a], 4); memcpy(&w[3], &s->vent[a], 4);
        memcpy(&w[4], &s->hold_pending[a], 4); memcpy(&w[5], &s->vent_pending[a], 4);
        any |= w[0] | w[1] | w[2] | w[3] | w[4] | w[5];
    }
    return any == 0;
}

/* The WSP valves over the step (their own state, nothing of the air): the part of the step each
 * hold valve is open and each cylinder's outlet conductance (vent valve's open part, leak), for the
 * cylinders' phase. wsp_valves_at_rest fills them as every valve at rest gives them (one vector loop
 * over the train) and says whether some car's valves may move or stick: those of each such car then
 * go through valve() in car_wsp_valves, which air_supply calls beside the car's pipe link. */
typedef struct {
    double hold_open[RB_PLANT_MAX_AXLES], outlet[RB_PLANT_MAX_AXLES];
    int moving;   /* 0: every valve rests released and none is stuck (all filled) */
} wsp_valve_parts;

static void wsp_valves_at_rest(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                               const rb_plant_faults *f, wsp_valve_parts *v)
{
    const rb_plant_derived *d = &s->derived;
    const int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    v->moving = !(f == &no_faults && train_valves_quiet(in, s, n_axles));
    if (!v->moving) {   /* every hold open, every vent shut */
        for (int a = 0; a < n_axles; ++a) {
            v->hold_open[a] = 1.0;   /* 1 - 0 */
            v->outlet[a] = 0.0;      /* g_vent 0 + g_unit 0 */
        }
        memset(s->hold_effective, 0, sizeof s->hold_effective);   /* fixed sizes: a few vector stores */
        memset(s->vent_effective, 0, sizeof s->vent_effective);
        return;
    }
    for (int a = 0; a < n_axles; ++a) {   /* what valve() gives a valve at rest */
        v->hold_open[a] = 1.0 - (double)s->hold[a];
        v->outlet[a] = d->axle_g_vent[a] * (double)s->vent[a] + d->g_unit * f->leak[a];
    }
    memcpy(s->hold_effective, s->hold, sizeof s->hold_effective);   /* the rest is 0 in both */
    memcpy(s->vent_effective, s->vent, sizeof s->vent_effective);
}

static void car_wsp_valves(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                           const rb_plant_faults *f, int c, wsp_valve_parts *v)
{
    const rb_plant_derived *d = &s->derived;
    if (valves_at_rest(in, s, f, c * RB_AXLES_PER_CAR)) return;
    const double delay = p->car[c].valve_delay, g_vent = d->g_vent[c], h = d->h;
    for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
        v->hold_open[a] = 1.0 - valve(in->hold[a] != 0, &s->hold[a], &s->hold_pending[a], &s->hold_timer[a], delay,
                                      h, f->hold[a], &s->hold_effective[a]);
        double vent = valve(in->vent[a] != 0, &s->vent[a], &s->vent_pending[a], &s->vent_timer[a], delay,
                            h, f->vent[a], &s->vent_effective[a]);
        v->outlet[a] = g_vent * vent + d->g_unit * f->leak[a];
    }
}

/* Phase 1, supply: compressor with on/off governor, main reservoir, the MR pipe along the train,
 * and each car's check valve and choke into its supply reservoir. Beside each car's pipe link its
 * WSP valves (car_wsp_valves, where they may move): on wet rail the pipe's links are a chain of long
 * waits (each a division, a square root and an exponential on the link before's result), which the
 * processor fills with the valves' scalar, branchy work (the order changes no value: neither reads
 * what the other writes). */
static void air_supply(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                       const rb_plant_faults *f, wsp_valve_parts *valves)
{
    const rb_plant_derived *d = &s->derived;
    rb_plant_compressors(p, s, f, d->h);   /* governors, delivery (plant_train.c) */
    int cc = p->compressor_car;
    double dm = rb_plant_link_mass_fixed(d, s->m_mr * d->k_mr, s->m_pipe[cc] * d->k_pipe[cc], d->g_mr, d->ik_mr,
                                 d->fill_mr);
    s->m_mr -= dm;
    s->m_pipe[cc] += dm;
    /* The pipe links car by car along the train, each car's charge link as soon as its pipe mass is
     * final (after its link to the next car): the results of all pipe links and then all charge
     * links, with the charges off the chain of pipe links (which carries its mass in a register). */
    double carry = s->m_pipe[0];   /* car c's pipe mass, its link from car c - 1 done */
    for (int c = 0; c < p->n_cars; ++c) {
        double m_pipe = carry;
        if (c + 1 < p->n_cars) {
            double m_next = s->m_pipe[c + 1];
            dm = rb_plant_link_mass_fixed(d, m_pipe * d->k_pipe[c], m_next * d->k_pipe[c + 1], d->g_pipe[c],
                                          d->ik_pipe[c], d->fill_pipe[c]);
            m_pipe -= dm;
            carry = m_next + dm;
        }
        double p_pipe = m_pipe * d->k_pipe[c], p_supply = s->m_supply[c] * d->k_supply[c];
        if (p_pipe > p_supply) {   /* check valve: only towards the supply reservoir */
            dm = rb_plant_link_mass_fixed(d, p_pipe, p_supply, d->g_charge[c], d->ik_charge[c], d->fill_charge[c]);
            m_pipe -= dm;
            s->m_supply[c] += dm;
        }
        if (f->pipe_leaks && f->pipe_leak[c] > 0.0) {   /* the pipe's leak, after its other links */
            dm = rb_plant_link_mass(d, m_pipe * d->k_pipe[c], p->atmosphere, d->g_unit * f->pipe_leak[c],
                                    d->ik_pipe_leak[c]);
            m_pipe -= dm;
            s->m_vented += dm;
        }
        s->m_pipe[c] = m_pipe;
        if (valves->moving) car_wsp_valves(p, s, in, f, c, valves);
    }
}

/* The start of the valves' phase, per car: the pilot volume's R T / V at the membrane's stroke into
 * k_pilot[c], and the EP valve's bleed over the step into bled[c] (taken from the supply): the pilot
 * stage's feed orifice passes supply air into the nozzle chamber, which holds the EP output plus the
 * piston's preload over its area (ep_supply_margin), and the flapper nozzle lets it out (the chamber
 * has no volume of its own here: the orifice's flow at the step's start). */
static void valves_start(const rb_plant_params *p, rb_plant_state *s, double *k_pilot, double *bled)
{
    const rb_plant_derived *d = &s->derived;
    const rb_plant_link_law law = rb_plant_link_law_of(d);
    for (int c = 0; c < p->n_cars; ++c) {   /* a vector loop: the orifice law's arms selected */
        k_pilot[c] = rb_plant_pilot_stiffness(s, c);
        double p_supply = s->m_supply[c] * d->k_supply[c];
        double chamber = s->m_pilot[c] * k_pilot[c] + d->ep_supply_margin[c];
        /* rb_orifice_flow_law(p_supply, chamber, g_bleed) where the supply is the higher */
        double q = d->g_bleed[c] * p_supply * rb_plant_flow_function_select(&law, chamber / p_supply);
        bled[c] = (p_supply > chamber ? q : 0.0) * d->h;
        s->m_supply[c] -= bled[c];
    }
}

/* The relay membrane's stroke over the step: its error against the band (1: the inlet fully open,
 * -1 the exhaust), within its stops, followed with the membrane's lag (relay_lag 1: at once). The
 * stroke sweeps the pilot volume from the next step on (rb_plant_pilot_stiffness). */
static double relay_stroke(rb_plant_state *s, int c, double e)
{
    const double travel = s->derived.relay_travel[c];
    double target = e > travel ? travel : (e < -travel ? -travel : e);
    s->relay_stroke[c] += (target - s->relay_stroke[c]) * s->derived.relay_lag[c];
    return s->relay_stroke[c];
}

/* Phase 2 car by car, each valve's one link on its own (the portable build: SSE2's two lanes do not
 * pay for computing every arm of the vector version below, which gives the same results). */
static double air_car_valves_scalar(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                                    const rb_plant_faults *f)
{
    const rb_plant_derived *d = &s->derived;
    const double patm = p->atmosphere;
    double ep_vented[RB_PLANT_MAX_CARS], relay_vented[RB_PLANT_MAX_CARS], p_pilot[RB_PLANT_MAX_CARS];
    double bled[RB_PLANT_MAX_CARS];
    double k_pilot[RB_PLANT_MAX_CARS];
    valves_start(p, s, k_pilot, bled);
    double m_before[RB_PLANT_MAX_CARS];   /* the chambers' air before their links (plant_pilot.c) */
    memcpy(m_before, s->m_pilot, sizeof m_before);
    for (int c = 0; c < p->n_cars; ++c) {
        double demand = in->pressure_demand[c] > patm ? in->pressure_demand[c] : patm;
        s->ep_demand_lag[c] += (demand - s->ep_demand_lag[c]) * d->ep_lag[c];
        p_pilot[c] = s->m_pilot[c] * k_pilot[c];
        ep_vented[c] = 0.0;
        double p_supply = s->m_supply[c] * d->k_supply[c], ceiling = p_supply - d->ep_supply_margin[c];
        if (s->emergency_open[c] > 0.0) {   /* the emergency valve's choke instead of the EP valve */
            double source = rb_emergency_source(s, c, p_supply);
            double dm = rb_plant_link_mass(d, source, p_pilot[c], s->emergency_g[c], d->ik_ep_out[c]);
            s->m_supply[c] -= dm > 0.0 ? dm : 0.0;
            s->m_pilot[c] += dm;
            ep_vented[c] = dm < 0.0 ? -dm : 0.0;
            p_pilot[c] = s->m_pilot[c] * k_pilot[c];
            continue;
        }
        if (f->ep_failed[c] > 0.0) continue;
        double target = s->ep_demand_lag[c] < ceiling ? s->ep_demand_lag[c] : ceiling;
        double e = (target - p_pilot[c]) * d->inv_ep_band[c];
        if (e > 0.0) {
            double dm = rb_plant_link_mass(d, p_supply, p_pilot[c], d->g_ep[c] * clamp01(e), d->ik_ep_in[c]);
            s->m_supply[c] -= dm;
            s->m_pilot[c] += dm;
        } else if (e < 0.0) {
            double dm = rb_plant_link_mass(d, p_pilot[c], patm, d->g_ep[c] * clamp01(-e), d->ik_ep_out[c]);
            s->m_pilot[c] -= dm;
            ep_vented[c] = dm;
        }
        p_pilot[c] = s->m_pilot[c] * k_pilot[c];
    }
    rb_plant_pilot_energy(p, s, m_before);   /* the relays see the chambers at their new temperature */
    for (int c = 0; c < p->n_cars; ++c) p_pilot[c] = s->m_pilot[c] * rb_plant_pilot_stiffness(s, c);
    for (int c = 0; c < p->n_cars; ++c) {
        double p_relay = s->m_relay[c] * d->k_relay[c];
        double e = (((f->isolated[c] > 0.0) ? patm : relay_control(f, c, p_pilot[c])) - p_relay) * d->inv_relay_band[c];
        double u = relay_stroke(s, c, e);
        relay_vented[c] = 0.0;
        if (u > 0.0 && !(f->isolated[c] > 0.0)) {
            double dm = rb_plant_link_mass(d, s->m_supply[c] * d->k_supply[c], p_relay, d->g_relay_supply[c] * clamp01(u),
                                  d->ik_relay_supply[c]);
            s->m_supply[c] -= dm;
            s->m_relay[c] += dm;
        } else if (u < 0.0 || (f->isolated[c] > 0.0)) {
            double open = (f->isolated[c] > 0.0) ? 1.0 : clamp01(-u);
            double dm = rb_plant_link_mass(d, p_relay, patm, d->g_relay_exhaust[c] * open, d->ik_relay_exhaust[c]);
            s->m_relay[c] -= dm;
            relay_vented[c] = dm;
        }
    }
    double vented = 0.0;   /* booked car by car: bleed, EP, relay */
    for (int c = 0; c < p->n_cars; ++c) vented = ((vented + bled[c]) + ep_vented[c]) + relay_vented[c];
    return vented;
}

/* The masses dm[i] of n links from node pressures pi[i] to pj[i] (rb_plant_link_mass_select), in
 * vector loops of their own (so the compiler keeps every arm a select): the exponents, then the
 * masses, with the exponential's arm only if some exponent needs it (the valves' links rarely do). */
static void links_select(const rb_plant_link_law *law, int n, const double *pi, const double *pj, const double *g,
                         const double *ik, double *dm)
{
    double y[RB_PLANT_MAX_CARS];
    int64_t large = 0;   /* negative if some y > 1/16 (rb_plant_sign_bits) */
    for (int i = 0; i < n; ++i) {
        y[i] = rb_plant_link_y_select(law, pi[i], pj[i], g[i], ik[i]);
        large |= rb_plant_sign_bits(0.0625 - y[i]);
    }
    if (large < 0)
        for (int i = 0; i < n; ++i) dm[i] = rb_plant_link_mass_of_fill(pi[i], pj[i], g[i], ik[i], rb_one_minus_exp_neg_select(y[i]));
    else   /* every y <= 1/16 (or a NaN), where rb_one_minus_exp_neg_select is its series */
        for (int i = 0; i < n; ++i) dm[i] = rb_plant_link_mass_of_fill(pi[i], pj[i], g[i], ik[i], rb_one_minus_exp_neg_series(y[i]));
}

/* Each car's valve link moved mass dm[c]: from its supply reservoir into the valve's volume where
 * dir > 0, from that volume to the atmosphere (vented[c]) where dir < 0, nothing where dir = 0;
 * selects, so a vector loop over the cars. */
static void apply_valve_links(int n, const double *dir, const double *dm, double *m_supply, double *m_volume,
                              double *vented)
{
    for (int c = 0; c < n; ++c) {
        double m = m_volume[c], supply = m_supply[c];
        double filled = m + dm[c], emptied = m - dm[c], supply_out = supply - dm[c];
        m_supply[c] = dir[c] > 0.0 ? supply_out : supply;
        m_volume[c] = dir[c] > 0.0 ? filled : (dir[c] < 0.0 ? emptied : m);
        vented[c] = dir[c] < 0.0 ? dm[c] : 0.0;
    }
}

/* Phase 2, per car: EP valve (lagged demand, ports open in proportion to the error) filling the
 * pilot volume, its pilot stage bleeding (valves_start); relay valve following it, its membrane's
 * stroke lagged and sweeping the pilot volume; an isolated car's relay is cut off and vented. The EP
 * valve's target is the lagged demand, or the supply less ep_supply_margin where that is lower:
 * its piston balances the nozzle chamber, which the supply feeds, against the control pressure
 * and its preload, so a supply running down pulls the output down with it (and the valve exhausts
 * what lies above). The cars are independent: all EP valves first, then all relays (a car's relay
 * sees its own EP valve's result either way), so the cars' links overlap instead of forming one
 * chain. With `vector` (the
 * AVX2 build) each valve's one link (inlet, exhaust, or none: g = 0 moves nothing) is chosen by
 * selects and every arm of the link law computed, so each pass is three vector loops over the
 * cars (operands, links, masses), the same operations per car as air_car_valves_scalar's. */
static double air_car_valves(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                             const rb_plant_faults *f, int vector)
{
    if (!vector) return air_car_valves_scalar(p, s, in, f);
    const rb_plant_derived *d = &s->derived;
    const rb_plant_link_law law = rb_plant_link_law_of(d);
    const double patm = p->atmosphere;
    double ep_vented[RB_PLANT_MAX_CARS], relay_vented[RB_PLANT_MAX_CARS], p_pilot[RB_PLANT_MAX_CARS];
    const int n = p->n_cars;
    double dir[RB_PLANT_MAX_CARS], pi[RB_PLANT_MAX_CARS], pj[RB_PLANT_MAX_CARS], g[RB_PLANT_MAX_CARS];
    double ik[RB_PLANT_MAX_CARS], dm[RB_PLANT_MAX_CARS], bled[RB_PLANT_MAX_CARS];
    double k_pilot[RB_PLANT_MAX_CARS];
    valves_start(p, s, k_pilot, bled);
    double m_before[RB_PLANT_MAX_CARS];   /* the chambers' air before their links (plant_pilot.c) */
    memcpy(m_before, s->m_pilot, sizeof m_before);
    for (int c = 0; c < n; ++c) {   /* EP valves: inlet where dir > 0, exhaust where dir < 0 */
        double demand = in->pressure_demand[c] > patm ? in->pressure_demand[c] : patm;
        s->ep_demand_lag[c] += (demand - s->ep_demand_lag[c]) * d->ep_lag[c];
        double p_now = s->m_pilot[c] * k_pilot[c], p_supply = s->m_supply[c] * d->k_supply[c];
        double ceiling = p_supply - d->ep_supply_margin[c];
        double target = s->ep_demand_lag[c] < ceiling ? s->ep_demand_lag[c] : ceiling;
        double e = (target - p_now) * d->inv_ep_band[c];
        double ik_in = d->ik_ep_in[c], ik_out = d->ik_ep_out[c], g_open = d->g_ep[c] * clamp01(e > 0.0 ? e : -e);
        /* the emergency valve's choke instead: between the regulated source and the chamber */
        double em = s->emergency_open[c], source = rb_emergency_source(s, c, p_supply), e_em = source - p_now;
        dir[c] = em > 0.0 ? e_em : (f->ep_failed[c] > 0.0 ? 0.0 : e);
        pi[c] = em > 0.0 ? (e_em > 0.0 ? source : p_now) : (e > 0.0 ? p_supply : p_now);
        pj[c] = em > 0.0 ? (e_em > 0.0 ? p_now : source) : (e > 0.0 ? p_now : patm);
        ik[c] = em > 0.0 ? ik_out : (e > 0.0 ? ik_in : ik_out);
        g_open = em > 0.0 ? s->emergency_g[c] : g_open;
        g[c] = dir[c] > 0.0 ? g_open : (dir[c] < 0.0 ? g_open : 0.0);
    }
    links_select(&law, n, pi, pj, g, ik, dm);
    apply_valve_links(n, dir, dm, s->m_supply, s->m_pilot, ep_vented);
    rb_plant_pilot_energy(p, s, m_before);   /* the relays see the chambers at their new temperature */
    for (int c = 0; c < n; ++c) p_pilot[c] = s->m_pilot[c] * rb_plant_pilot_stiffness(s, c);
    for (int c = 0; c < n; ++c) {   /* relay valves: supply where dir > 0, exhaust where dir < 0 */
        double p_relay = s->m_relay[c] * d->k_relay[c], p_supply = s->m_supply[c] * d->k_supply[c];
        double isolated = f->isolated[c];
        double e = ((isolated > 0.0 ? patm : relay_control(f, c, p_pilot[c])) - p_relay) * d->inv_relay_band[c];
        double u = relay_stroke(s, c, e);
        double ik_in = d->ik_relay_supply[c], ik_out = d->ik_relay_exhaust[c];
        double g_in = d->g_relay_supply[c] * clamp01(u);
        double g_out = d->g_relay_exhaust[c] * (isolated > 0.0 ? 1.0 : clamp01(-u));
        dir[c] = isolated > 0.0 ? -1.0 : u;   /* an isolated car's relay: vented, fully open */
        pi[c] = dir[c] > 0.0 ? p_supply : p_relay;
        pj[c] = dir[c] > 0.0 ? p_relay : patm;
        ik[c] = dir[c] > 0.0 ? ik_in : ik_out;
        g[c] = dir[c] > 0.0 ? g_in : (dir[c] < 0.0 ? g_out : 0.0);
    }
    links_select(&law, n, pi, pj, g, ik, dm);
    apply_valve_links(n, dir, dm, s->m_supply, s->m_relay, relay_vented);
    double vented = 0.0;   /* booked car by car: bleed, EP, relay */
    for (int c = 0; c < p->n_cars; ++c) vented = ((vented + bled[c]) + ep_vented[c]) + relay_vented[c];
    return vented;
}

/* The orifice flow's factor sqrt(T_wall / T) of air at T (the conductances are the wall
 * temperature's). */
static double flow_factor(double wall, double t) { return sqrt(wall / t); }

/* The cylinders a little above their relay's pressure (within the link's laminar range) with the
 * hold valve open and the vent and any leak shut, marked by flowing_back[a] (a brake held on dry
 * rail: its relay's exhaust keeps the relay just below them): air flows back through the hold
 * valve, at the cylinder's temperature, by the capped link law. Every axle's arm in vector loops (a
 * car's constants for its axles), the results taken where marked: the general path's operations
 * for such an axle (air_cylinders; its vent link of 0 adds -0 times gamma T), so its results. */
static void cylinders_back(const rb_plant_params *p, rb_plant_state *s, const double *hold_open, const double *p_relay,
                           const double *temp, const double *flowing_back, double *done, double *taken)
{
    const rb_plant_derived *d = &s->derived;
    const double wall = p->temperature, gamma = d->gamma_cyl, h_laminar = d->h_laminar;
    for (int c = 0; c < p->n_cars; ++c) {
        const double g_hold = d->g_hold[c], ik_rate = d->ik_hold_rate[c], ik_cap = d->ik_hold[c], r_cyl = d->r_cyl[c];
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            const double m = s->m_cyl[a], mt = s->mt_cyl[a], pr = p_relay[a], t = temp[a], p_cyl = mt * r_cyl;
            const double g = g_hold * hold_open[a] * flow_factor(wall, t), y = h_laminar * g / ik_rate;
            const double dm = rb_plant_link_mass_of_fill(pr, p_cyl, g, ik_rate, rb_one_minus_exp_neg_select(y));
            const double cap = (pr - p_cyl) * ik_cap, back = dm > cap ? dm : cap;   /* pr < p_cyl: the larger */
            const double mt_new = (mt + gamma * t * back) + d->axle_heat_cyl[a] * (wall - t);
            const double marked = flowing_back[a];
            taken[a] = marked > 0.0 ? back : taken[a];
            s->m_cyl[a] = marked > 0.0 ? m + back : m;
            s->mt_cyl[a] = marked > 0.0 ? mt_new : mt;
            done[a] = marked > 0.0 ? 1.0 : done[a];
        }
    }
}

/* Phase 3, per axle: WSP hold valve (relay -> cylinder) and vent valve (cylinder -> atmosphere),
 * each port's area weighted by the part of the step it is open, and cylinder leaks. The axles of a
 * car draw on their relay volume's pressure at the start of the phase (the link limit shares that
 * volume among its links, so together they never overshoot). The cylinders' energy balance
 * (wall_time > 0): the air taken brings its upstream enthalpy (the relay's air at the wall's
 * temperature, or the cylinder's own when it flows back), the air vented leaves with the
 * cylinder's, the wall exchanges heat; temperatures from the start of the phase.
 * The WSP valves' open parts come from wsp_valves_at_rest and car_wsp_valves (with the supply).
 * Most axles most of the time have the vent and any leak shut and either the hold valve open with
 * the cylinder near the relay's pressure (a released or applied brake; their step is the hold
 * link's linear law with its factor from init) or the hold valve shut (WSP holding the pressure:
 * nothing flows), done for every axle in one branch-free vector loop that also marks the other
 * axles; only those then take the general scalar path, which starts again from their unchanged
 * state (the same operations as for every axle before, so the same results).
 * start: each cylinder's pressure at the start of the phase (the step's, as no earlier phase
 * changes a cylinder), for the step-mean pressure of the brakes. */
static double air_cylinders(const rb_plant_params *p, rb_plant_state *s, const wsp_valve_parts *valves,
                            double *start)
{
    const rb_plant_derived *d = &s->derived;
    const double patm = p->atmosphere, wall = p->temperature, gamma = d->gamma_cyl;
    const int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    const double *hold_open = valves->hold_open, *outlet = valves->outlet;
    double taken[RB_PLANT_MAX_AXLES];
    double temp[RB_PLANT_MAX_AXLES], p_relay[RB_PLANT_MAX_AXLES];
    double done[RB_PLANT_MAX_AXLES];   /* 1: by the vector pass, 0: the axle takes the general path */
    int64_t any_general = 0;           /* negative if some axle does (rb_plant_sign_bits) */
    double flowing_back[RB_PLANT_MAX_AXLES];
    int64_t any_back = 0;
    double vented = 0.0;
    for (int c = 0; c < p->n_cars; ++c) {   /* each car's relay pressure for each of its axles */
        const double pr = s->m_relay[c] * d->k_relay[c];
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) p_relay[a] = pr;
    }
    const double laminar = d->orifice.laminar_only ? 0.0 : 1.0;
    const int thermal = gamma > 1.0;
    for (int a = 0; a < n_axles; ++a) {   /* an open hold link near equal pressures, or a shut one: a vector loop */
        const double m = s->m_cyl[a], mt = s->mt_cyl[a], pr = p_relay[a];
        const double mean_t = mt / m, t = thermal ? mean_t : wall, p_cyl = mt * d->axle_r_cyl[a];
        double simple = laminar;   /* 1: this path, 0: the general one (double selects: SSE2 has no
                                      64-bit integer compare) */
        simple = hold_open[a] == 1.0 ? simple : 0.0;
        simple = p_cyl <= pr ? simple : 0.0;
        simple = p_cyl >= RB_ORIFICE_LAMINAR_RATIO * pr ? simple : 0.0;
        /* a hold valve shut all the step (WSP holding: most axles in a slide): the general path's
           link of g = 0 takes +0 whatever the pressures, so in_mass 0 gives its results (each
           select on a compare of its own: a select on `held` made of one stopped the vectoriser) */
        simple = hold_open[a] == 0.0 ? 1.0 : simple;
        simple = outlet[a] > 0.0 ? 0.0 : simple;
        const double linear = (pr - p_cyl) * d->axle_hold_laminar[a];   /* loaded either way: no branch */
        const double flowing = pr - p_cyl < 0.01 ? 0.0 : linear;
        const double in_mass = hold_open[a] == 0.0 ? 0.0 : flowing;
        const double mt_in = mt + gamma * wall * in_mass;   /* relay air in at the wall's temperature */
        /* the general path's wall term less gamma t dm with dm = 0, +0 for a finite t: the same */
        const double mt_new = mt_in + d->axle_heat_cyl[a] * (wall - t);
        temp[a] = t;
        start[a] = p_cyl;
        taken[a] = simple > 0.0 ? in_mass : 0.0;
        s->m_cyl[a] = simple > 0.0 ? m + in_mass : m;
        s->mt_cyl[a] = simple > 0.0 ? mt_new : mt;
        done[a] = simple;
        /* the open hold link near equal pressures the other way, vent and leak shut: cylinders_back */
        double back = laminar;
        back = hold_open[a] == 1.0 ? back : 0.0;
        back = p_cyl > pr ? back : 0.0;
        back = pr >= RB_ORIFICE_LAMINAR_RATIO * p_cyl ? back : 0.0;
        back = outlet[a] > 0.0 ? 0.0 : back;
        flowing_back[a] = back;
        any_back |= rb_plant_sign_bits(0.0 - back);   /* -1 where marked (0 - 0 is +0) */
    }
    if (any_back < 0) cylinders_back(p, s, hold_open, p_relay, temp, flowing_back, done, taken);
    for (int a = 0; a < n_axles; ++a) any_general |= rb_plant_sign_bits(done[a] - 1.0);   /* -1 if not done */
    if (any_general < 0)
        for (int a = 0; a < n_axles; ++a) {
            if (done[a] > 0.0) continue;
            const int c = a / RB_AXLES_PER_CAR;
            const double r_cyl = d->r_cyl[c], pr = p_relay[a];
            double p_cyl = s->mt_cyl[a] * r_cyl;
            if (hold_open[a] == 1.0 && p_cyl <= pr && p_cyl >= RB_ORIFICE_LAMINAR_RATIO * pr && laminar > 0.0) {
                taken[a] = pr - p_cyl < 0.01 ? 0.0 : (pr - p_cyl) * d->hold_laminar[c];
                s->m_cyl[a] += taken[a];
                s->mt_cyl[a] += gamma * wall * taken[a];
            } else {
                int from_relay = pr >= p_cyl;
                double t_up = from_relay ? wall : temp[a], root_up = from_relay ? 1.0 : flow_factor(wall, temp[a]);
                taken[a] = rb_plant_link_mass_capped(d, pr, p_cyl, d->g_hold[c] * hold_open[a] * root_up,
                                                     d->ik_hold_rate[c], d->ik_hold[c]);
                s->m_cyl[a] += taken[a];
                s->mt_cyl[a] += gamma * t_up * taken[a];   /* enthalpy in: m T rises by gamma T_up dm */
            }
            double dm = 0.0;
            if (outlet[a] > 0.0) {
                dm = rb_plant_link_mass_capped(d, s->mt_cyl[a] * r_cyl, patm, outlet[a] * flow_factor(wall, temp[a]),
                                               d->ik_vent_rate[c], d->ik_vent[c]);
                s->m_cyl[a] -= dm;
                vented += dm;
            }
            s->mt_cyl[a] += d->axle_heat_cyl[a] * (wall - temp[a]) - gamma * temp[a] * dm;
        }
    if (!thermal)   /* isothermal: m T stays m times the wall's temperature, exactly */
        for (int a = 0; a < n_axles; ++a) s->mt_cyl[a] = s->m_cyl[a] * wall;
    for (int c = 0; c < p->n_cars; ++c) {
        double to_cylinders = 0.0;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) to_cylinders += taken[a];
        s->m_relay[c] -= to_cylinders;
    }
    return vented;
}

/* ------------------------------------------------------------------ mechanics */

/* The traction control's slide control of the ED brake, per motor car with one (rb_plant_car.
 * ed_slide_*): the deepest braking slip of the car's axles, (v - omega r) / v, against its
 * thresholds; the fraction of the asked ED force it lets through falls at the cut rate while an
 * axle slides and comes back at the restore rate once none does (as traction control units reduce
 * and restore the motor torque of a sliding axle). The blending BCU sees the achieved ED force and
 * gives the rest to the friction brake. */
static void ed_slide_control(const rb_plant_params *p, rb_plant_state *s, double dt)
{
    const rb_plant_derived *d = &s->derived;
    for (int c = 0; c < p->n_cars; ++c) {
        const rb_plant_car *car = &p->car[c];
        if (!(car->ed_slide_slip > 0.0) || !car->vehicle.motor) continue;
        double v = s->v[c] > p->creep_speed_min ? s->v[c] : p->creep_speed_min, deepest = 0.0;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            double slip = (s->v[c] - s->omega[a] * d->axle_radius[a]) / v;
            deepest = slip > deepest ? slip : deepest;
        }
        double k = s->ed_slide_factor[c];
        if (deepest > car->ed_slide_slip) k -= car->ed_cut_rate * dt;
        else if (deepest < car->ed_slide_release) k += car->ed_restore_rate * dt;
        s->ed_slide_factor[c] = k < 0.0 ? 0.0 : (k > 1.0 ? 1.0 : k);
    }
}

static void step_mechanics(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                           const rb_plant_faults *f, const double *cylinder, double dt)
{
    const rb_plant_derived *d = &s->derived;
    const int n_cars = p->n_cars;
    double coupler[RB_PLANT_MAX_CARS + 1] = {0.0}, other[RB_PLANT_MAX_CARS];
    double inv_vr[RB_PLANT_MAX_CARS], ed_axle[RB_PLANT_MAX_CARS];
    rb_wheelset_inputs w;
    if (n_cars < 1) return;   /* (rb_plant_check: never; tells the compiler the loops fill w) */
    for (int c = 0; c + 1 < n_cars; ++c)  /* tension positive */
        coupler[c + 1] = rb_coupler_force_law(&p->coupler, s->x[c] - s->x[c + 1] - d->car_length[c], s->v[c] - s->v[c + 1]);
    /* ED force: the target min(demand, limit) where ED force is asked for (the limit, >= 0, is a
       call: a scalar loop, skipped without any demand), then the lag (a vector loop) */
    double ed_target[RB_PLANT_MAX_CARS], ed_lag_dt[RB_PLANT_MAX_CARS];
    const double *ed_lag = d->ed_lag;   /* the plant's step: from init */
    int64_t asked = 0;
    for (int c = 0; c < n_cars; ++c) {
        ed_target[c] = 0.0;
        asked |= rb_plant_sign_bits(0.0 - in->ed_demand[c]);   /* demand > 0 (0 - 0 is +0; a NaN: checked below) */
    }
    if (asked < 0)
        for (int c = 0; c < n_cars; ++c) {
            const rb_plant_car *car = &p->car[c];
            double v = s->v[c], ed = in->ed_demand[c] > 0.0 ? in->ed_demand[c] : 0.0;
            double ed_max = ed > 0.0 && car->vehicle.motor && !f->ed_lost[c] && v > 0.0 ? rb_ed_brake_force_max(&car->vehicle.ed, v) : 0.0;
            ed_target[c] = ed < ed_max ? ed : ed_max;
        }
    if (dt != d->h) {
        for (int c = 0; c < n_cars; ++c) ed_lag_dt[c] = dt / (p->car[c].ed_tau + dt);
        ed_lag = ed_lag_dt;
    }
    for (int c = 0; c < n_cars; ++c) s->ed_asked[c] += (ed_target[c] - s->ed_asked[c]) * ed_lag[c];
    ed_slide_control(p, s, dt);
    for (int c = 0; c < n_cars; ++c) s->ed_force[c] = s->ed_slide_factor[c] * s->ed_asked[c];
    for (int c = 0; c < n_cars; ++c) {   /* the cars' other forces and creep reference: vector loops */
        double v = s->v[c];
        double share = rb_running_resistance_law(&p->resistance, v) * d->mass_share[c];   /* loaded either way */
        double resistance = v > 0.0 ? share : 0.0;
        other[c] = coupler[c] - coupler[c + 1] - resistance;   /* tension pulls c back */
        double vr = v > p->creep_speed_min ? v : p->creep_speed_min;
        inv_vr[c] = 1.0 / vr;
        ed_axle[c] = s->ed_force[c] / RB_AXLES_PER_CAR * d->radius[c];
    }
    if (f != &no_faults)   /* (the constant record has no ED lost) */
        for (int c = 0; c < n_cars; ++c)
            if (f->ed_lost[c]) ed_axle[c] = 0.0;
    if (p->n_gradients > 0)
        for (int c = 0; c < n_cars; ++c) other[c] -= rb_plant_gradient_force(p, s, c);
    if (p->n_zones > 0)   /* without zones every axle keeps the condition init gave it */
        for (int c = 0; c < n_cars; ++c)
            for (int k = 0; k < RB_AXLES_PER_CAR; ++k)
                rb_plant_zone_update(p, s, c * RB_AXLES_PER_CAR + k, s->x[c] - p->car[c].axle_position[k]);
    for (int c = 0; c < n_cars; ++c) {   /* each car's figures for each of its axles */
        double others = other[c];
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) others += s->force[a];
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            w.speed[a] = s->v[c];
            w.inv_creep_speed[a] = inv_vr[c];
            w.others[a] = others;
            w.ed_torque[a] = ed_axle[c];
        }
    }
    rb_plant_wheelsets(p, s, &w, cylinder, dt);
    for (int c = 0; c < n_cars; ++c) {
        double rail = 0.0;
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) rail += s->force[a];
        s->a[c] = (rail + other[c]) * d->inv_mass[c];
    }
    for (int c = 0; c < n_cars; ++c) {
        s->v[c] += dt * s->a[c];
        if (s->v[c] < 0.0) s->v[c] = 0.0;   /* brakes hold a stopped train */
        s->x[c] += dt * s->v[c];
    }
    if (s->rail_active) rb_rail_step(p, s, in, dt);
}

/* (exported functions are not inlined into the step under -fPIC: the step calls the static one) */
void rb_plant_step_mechanics(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in,
                             const rb_plant_faults *f, const double *cylinder, double dt)
{
    step_mechanics(p, s, in, f, cylinder, dt);
}

static void update_sensors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f)
{
    if (!f->sensor_faults) {   /* every sensor sound: what the loop below would write */
        if (s->sensors_written) {
            memset(s->sensor_lost, 0, sizeof s->sensor_lost);
            memset(s->noise, 0, sizeof s->noise);
            s->sensors_written = 0;
        }
        return;
    }
    s->sensors_written = 1;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        s->sensor_lost[a] = f->noise_sd[a] < 0.0;
        s->noise[a] = f->noise_sd[a] > 0.0 ? f->noise_sd[a] * gaussian(&s->rng) : 0.0;
    }
}

/* (exported functions are not inlined into the step under -fPIC: the step calls the static one) */
void rb_plant_update_sensors(const rb_plant_params *p, rb_plant_state *s, const rb_plant_faults *f)
{
    update_sensors(p, s, f);
}

static void step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in, int vector)
{
    const rb_plant_derived *d = &s->derived;
    rb_plant_faults gathered;
    const rb_plant_faults *f = &no_faults;
    double start[RB_PLANT_MAX_AXLES], mean[RB_PLANT_MAX_AXLES];
    const int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    if (p->n_faults > 0) {
        gather_faults(p, s, &gathered);
        f = &gathered;
    }
    rb_emergency_plant_update(p, s, in);
    if (f->emergency_faults) apply_emergency_faults(p, s, in, f);
    for (int k = 0; k < p->substeps; ++k) {
        /* air, in phases */
        wsp_valve_parts wsp;
        wsp_valves_at_rest(p, s, in, f, &wsp);
        air_supply(p, s, in, f, &wsp);
        double valves = air_car_valves(p, s, in, f, vector);
        s->m_vented += valves;
        s->m_valves_vented += valves;
        s->m_vented += air_cylinders(p, s, &wsp, start);   /* start: each cylinder's pressure before it, Pa */
        /* mechanics, braked by the step-mean cylinder pressure */
        for (int a = 0; a < n_axles; ++a) mean[a] = 0.5 * (start[a] + s->mt_cyl[a] * d->axle_r_cyl[a]);
        step_mechanics(p, s, in, f, mean, d->h);
        rb_plant_discs(p, s, d->h);
    }
    update_sensors(p, s, f);
    s->step += 1;
    s->time = (double)s->step * p->dt;
}

/* The step with every phase of this file inlined (flatten), once for the portable build and once
 * for AVX2 where the build and CPU have it (s->kernel, as the wheelset kernel's): the same
 * operations in the same order (no fused multiply-add), so the same results bit for bit
 * (core/tests/test_plant_kernel.c); the vector build only widens the loops over the axles and
 * encodes the scalar ones more compactly. */
RB_FLATTEN static void step_portable(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in)
{
    step(p, s, in, 0);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2"), flatten))
static void step_avx2(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in)
{
    step(p, s, in, 1);
}
#endif

void rb_plant_step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in)
{
#if RB_PLANT_HAVE_AVX2
    if (s->kernel == RB_PLANT_KERNEL_AVX2) {
        step_avx2(p, s, in);
        return;
    }
#endif
    step_portable(p, s, in);
}

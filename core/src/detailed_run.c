/* Detailed model: train line, BCU cycles, mechanics sub-steps, outputs and KPIs. */
#include "detailed_internal.h"
#include "emergency_circuit.h"
#include "plant_internal.h"
#include "run_internal.h"

#include <math.h>
#include <string.h>

#define LOCK_SPEED (10.0 / 3.6)   /* m/s: slip counts above 10 km/h, as in run.c */

size_t rb_detailed_state_size(void) { return sizeof(rb_detailed_state); }
void rb_detailed_stats(const rb_detailed_state *s, rb_ode_stats *stats) { *stats = s->stats; }

/* Buffer row layout (per sub-step): per car supply, control, relay, vented; then per axle cylinder. */
enum { B_SUPPLY, B_CONTROL, B_RELAY, B_VENTED, B_CARS };
static double *buf(rb_detailed_state *s, int i, int what, int c) { return &s->buffer[i][what * RB_PLANT_MAX_CARS + c]; }
static double *buf_cyl(rb_detailed_state *s, int i, int a) { return &s->buffer[i][B_CARS * RB_PLANT_MAX_CARS + a]; }

/* ------------------------------------------------------------------ train line */

/* Nodes: MR, pipe per car, each car's supply reservoir (held at its pressure over a cycle).
   Links: MR -> compressor car's pipe, pipe chain, charge (check valve + choke) per car. */
static void build_line(const rb_plant_params *p, const rb_detailed_params *d, rb_detailed_state *s)
{
    int n = p->n_cars;
    double T = p->temperature;
    memset(s->line_node, 0, sizeof s->line_node);
    memset(s->line_link, 0, sizeof s->line_link);
    for (int i = 0; i <= n; ++i) {
        rb_net_node *nd = &s->line_node[i];
        nd->kind = RB_NODE_VOLUME;
        nd->pressure = p->initial_pressure;
        nd->temperature = nd->wall_temperature = T;
        nd->volume = i == 0 ? p->main_reservoir_volume : p->car[i - 1].pipe_volume;
        nd->heat_conductance = rb_wall_conductance(nd->volume, T, d->thermal_time, p->initial_pressure);
    }
    for (int c = 0; c < n; ++c) {
        rb_net_node *nd = &s->line_node[n + 1 + c];
        nd->kind = RB_NODE_RESERVOIR;
        nd->pressure = p->initial_pressure;
        nd->temperature = T;
    }
    for (int j = 0; j < 2 * n; ++j) {
        rb_net_link *l = &s->line_link[j];
        l->kind = RB_LINK_FIXED;
        l->orifice.discharge_coefficient = p->discharge_coefficient;
        l->orifice.critical_ratio = p->critical_ratio;
        if (j == 0) { l->from = 0; l->to = 1 + p->compressor_car; l->orifice.area = p->main_reservoir_area; }
        else if (j < n) { l->from = j; l->to = j + 1; l->orifice.area = p->car[j - 1].pipe_area; }
        else { l->from = 1 + (j - n); l->to = n + 1 + (j - n); l->orifice.area = p->car[j - n].charge_area;
               l->opening.n = 1; }
    }
}

static void line_system(const rb_plant_params *p, rb_detailed_state *s, rb_det_system *sys)
{
    int n = p->n_cars;
    memset(sys, 0, sizeof *sys);
    rb_network net = {s->line_node, (size_t)(2 * n + 1), s->line_link, (size_t)(2 * n), NULL, 0, NULL, 0, NULL, 0};
    sys->net = net;
    sys->n_acc = n;
    memset(sys->acc_of_link, -1, sizeof sys->acc_of_link);
    for (int c = 0; c < n; ++c) sys->acc_of_link[n + c] = (signed char)c;
}

static double car_mass(const rb_detailed_car *k)
{
    double m = 0.0;
    for (int i = 0; i < CN_ATM; ++i) m += k->y[2 * i];
    return m;
}

static double air_in_line(const rb_plant_params *p, const rb_detailed_state *s)
{
    double m = 0.0;
    for (int i = 0; i <= p->n_cars; ++i) m += s->line_y[2 * i];
    return m;
}

static double air_in_volumes(const rb_plant_params *p, const rb_detailed_state *s)
{
    double m = air_in_line(p, s);
    for (int c = 0; c < p->n_cars; ++c) m += car_mass(&s->car[c]);
    return m;
}

/* Adds dm of air at temperature T_in to a rigid volume with state (m, T): mass and energy. */
static void add_air(double *m, double *T, double dm, double T_in)
{
    double m_new = *m + dm;
    *T = (*m * *T + RB_AIR_GAMMA * T_in * dm) / m_new;
    *m = m_new;
}

/* Line node (0: MR, 1 + c: car c's MR pipe) a compressor on car c delivers into, as the plant's
   (plant_train.c): the main reservoir on compressor_car, else the car's pipe. */
static int compressor_node(const rb_plant_params *p, int c) { return c == p->compressor_car ? 0 : 1 + c; }

static double node_volume(const rb_plant_params *p, int node)
{
    return node == 0 ? p->main_reservoir_volume : p->car[node - 1].pipe_volume;
}

/* The plant's compressors over dt, delivering at the air temperature: n_compressors = 0, the single
   one into the MR (compressor_flow); else each with its own governor reading the pressure of the
   node it feeds (the main reservoir or its car's MR pipe). */
static void compressors(const rb_plant_params *p, rb_detailed_state *s, double dt)
{
    double *y = s->line_y;
    int single = p->n_compressors == 0, any = 0;
    for (int i = 0; i < (single ? 1 : p->n_compressors); ++i) {
        int node = single ? 0 : compressor_node(p, p->compressor_position[i]);
        double fed = y[2 * node] * RB_AIR_R * y[2 * node + 1] / node_volume(p, node);
        if (fed < p->governor_on) s->compressor_running[i] = 1;
        if (fed > p->governor_off) s->compressor_running[i] = 0;
        if (s->compressor_running[i]) {
            double dm = (single ? p->compressor_flow : p->compressor_delivery[i]) * dt;
            add_air(&y[2 * node], &y[2 * node + 1], dm, p->temperature);
            s->m_compressed += dm;
        }
        any |= s->compressor_running[i];
    }
    s->compressor_on = any;
}

static rb_status advance_line(const rb_plant_params *p, const rb_detailed_params *d, rb_detailed_state *s,
                              double t0, double t1, rb_error *err)
{
    int n = p->n_cars;
    double *y = s->line_y;
    compressors(p, s, t1 - t0);
    for (int c = 0; c < n; ++c) {   /* supply reservoirs held; the check valve decides at the cycle start */
        const rb_detailed_car *k = &s->car[c];
        rb_net_node *res = &s->line_node[n + 1 + c];
        res->pressure = k->y[0] * RB_AIR_R * k->y[1] / p->car[c].supply_volume;
        res->temperature = k->y[1];
        double p_pipe = y[2 * (c + 1)] * RB_AIR_R * y[2 * (c + 1) + 1] / p->car[c].pipe_volume;
        s->line_link[n + c].opening.value[0] = p_pipe > res->pressure ? 1.0 : 0.0;
    }
    rb_det_system sys;
    line_system(p, s, &sys);
    rb_status st = rb_det_system_init(&sys, s->eval_work, sizeof s->eval_work / sizeof *s->eval_work,
                                      s->iwork + RB_DET_MAX_STATES, RB_DET_LINE_NODES, s->y0, s->scale, err);
    if (st) return st;
    for (int c = 0; c < n; ++c) y[sys.n_net + c] = 0.0;
    if ((st = rb_det_solve(&sys, d, t0, y, &t1, 1, s->y_out, &s->line_h, s->scale, s->work, s->iwork, &s->stats, err)))
        return st;
    for (int c = 0; c < n; ++c) {   /* the charged air enters the supply reservoir */
        rb_detailed_car *k = &s->car[c];
        double dm = y[sys.n_net + c];
        add_air(&k->y[0], &k->y[1], dm, dm > 0.0 ? y[2 * (c + 1) + 1] : k->y[1]);
        s->m_charged_total += dm;
    }
    return RB_OK;
}

/* ------------------------------------------------------------------ cars */

static double sub_time(const rb_detailed_state *s, double t0, int i) { return t0 + (i + 1) * s->dt_mech; }

/* Valve switchings due by time t act; returns the next pending switching time (or INFINITY). */
static double settle_valves(rb_detailed_car *k, double t)
{
    double next = INFINITY;
    k->emergency = k->emergency_switch <= t + 1e-12;
    if (!k->emergency) next = k->emergency_switch;
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
        if (k->hold[a] != k->hold_pending[a]) {
            if (k->hold_switch[a] <= t + 1e-12) k->hold[a] = k->hold_pending[a];
            else next = fmin(next, k->hold_switch[a]);
        }
        if (k->vent[a] != k->vent_pending[a]) {
            if (k->vent_switch[a] <= t + 1e-12) k->vent[a] = k->vent_pending[a];
            else next = fmin(next, k->vent_switch[a]);
        }
    }
    rb_det_apply_commands(k);
    return next;
}

/* Air in car k's volumes and vented by it (kg): what changes it is the load-weighing valve's
   regulated node (every other link stays inside the car or vents). */
static double car_air(const rb_detailed_car *k)
{
    double m = k->y[CS_VENTED];
    for (int i = 0; i < CN_ATM; ++i) m += k->y[2 * i];
    return m;
}

/* The regulated node gave the car `gained` kg over a solve: from the supply reservoir it draws on
   (where it took air back, its exhaust vented it). */
static void book_regulated(rb_detailed_car *k, double gained)
{
    if (gained > 0.0) k->y[2 * CN_SUPPLY] -= gained;
    else k->y[CS_VENTED] -= gained;
}

/* Car c over the cycle [t0, t0 + n_sub dt], restarting the solver at each valve switching; fills the
   sub-step buffer (control and relay pressures only on rows marked in full[]). */
static rb_status advance_car(const rb_plant_params *p, const rb_detailed_params *d, rb_detailed_state *s, int c,
                             double t0, const uint8_t *full, rb_error *err)
{
    rb_detailed_car *k = &s->car[c];
    rb_det_system sys;
    rb_det_car_system(k, d, &s->membrane, &sys);
    rb_status st = rb_det_system_init(&sys, s->eval_work, sizeof s->eval_work / sizeof *s->eval_work,
                                      s->iwork + RB_DET_MAX_STATES, RB_DET_CAR_NODES, s->y0, s->scale, err);
    if (st) return st;
    size_t n = sys.n_net + 1;
    double t = t0, t1 = sub_time(s, t0, s->n_sub - 1);
    int next_sub = 0;
    while (t < t1 - 1e-12) {
        double event = settle_valves(k, t), end = event < t1 - 1e-9 ? event : t1;
        size_t m = 0;
        int first = next_sub;
        while (next_sub < s->n_sub && sub_time(s, t0, next_sub) <= end + 1e-9)
            s->t_out[m++] = sub_time(s, t0, next_sub++);
        if (m == 0 || s->t_out[m - 1] < end - 1e-12) s->t_out[m++] = end;
        else s->t_out[m - 1] = end;   /* the same time to round-off */
        double before = car_air(k);
        if ((st = rb_det_solve(&sys, d, t, k->y, s->t_out, m, s->y_out, &k->h_last, s->scale, s->work, s->iwork,
                               &s->stats, err)))
            return st;
        book_regulated(k, car_air(k) - before);
        for (int i = first; i < next_sub; ++i) {
            const double *row = s->y_out + (size_t)(i - first) * n;
            *buf(s, i, B_SUPPLY, c) = row[0] * RB_AIR_R * row[1] / p->car[c].supply_volume;
            *buf(s, i, B_VENTED, c) = row[CS_VENTED];
            for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
                int i_cyl = 2 * (CN_CYL + a);
                *buf_cyl(s, i, c * RB_AXLES_PER_CAR + a) =
                    row[i_cyl] * RB_AIR_R * row[i_cyl + 1] / p->car[c].cylinder_volume;
                s->hold_at[i][c * RB_AXLES_PER_CAR + a] = k->hold[a];
                s->vent_at[i][c * RB_AXLES_PER_CAR + a] = k->vent[a];
            }
            if (full[i]) {
                rb_network_rates(s->t_out[i - first], row, s->y0, &sys.ev);
                *buf(s, i, B_CONTROL, c) = sys.ev.p[CN_CONTROL];
                *buf(s, i, B_RELAY, c) = sys.ev.p[CN_RELAY];
            } else {
                *buf(s, i, B_CONTROL, c) = i > 0 ? *buf(s, i - 1, B_CONTROL, c) : s->out.pilot[c];
                *buf(s, i, B_RELAY, c) = i > 0 ? *buf(s, i - 1, B_RELAY, c) : s->out.relay[c];
            }
        }
        t = end;
    }
    settle_valves(k, t1);
    return RB_OK;
}

/* ------------------------------------------------------------------ outputs */

/* Outputs at the start of a cycle, air from the states. */
static void cycle_outputs(const rb_plant_params *p, const rb_detailed_params *d, rb_detailed_state *s, double t)
{
    rb_plant_get_outputs(p, &s->mech, &s->out);
    s->out.time = t;
    double vented = 0.0;
    for (int c = 0; c < p->n_cars; ++c) {
        rb_detailed_car *k = &s->car[c];
        rb_det_system sys;
        rb_det_car_system(k, d, &s->membrane, &sys);
        rb_error err;
        if (rb_det_system_init(&sys, s->eval_work, sizeof s->eval_work / sizeof *s->eval_work,
                               s->iwork + RB_DET_MAX_STATES, RB_DET_CAR_NODES, s->y0, NULL, &err))
            continue;   /* checked at init: cannot fail */
        rb_network_rates(t, k->y, s->y_out, &sys.ev);
        s->out.supply[c] = sys.ev.p[CN_SUPPLY];
        s->out.pilot[c] = sys.ev.p[CN_CONTROL];
        s->out.relay[c] = sys.ev.p[CN_RELAY];
        for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
            int i = c * RB_AXLES_PER_CAR + a;
            s->out.cylinder[i] = sys.ev.p[CN_CYL + a];
            s->out.hold[i] = k->hold[a];
            s->out.vent[i] = k->vent[a];
        }
        vented += k->y[CS_VENTED];
    }
    int n = p->n_cars;
    s->out.main_reservoir = s->line_y[0] * RB_AIR_R * s->line_y[1] / p->main_reservoir_volume;
    s->out.pipe_end = s->line_y[2 * n] * RB_AIR_R * s->line_y[2 * n + 1] / p->car[n - 1].pipe_volume;
    s->out.compressor_on = s->compressor_on;
    s->out.air_in_system = air_in_volumes(p, s);
    s->out.air_vented = vented;
    s->out.air_compressed = s->m_compressed;
    s->out.air_drawn = s->m_line_initial + s->m_compressed - air_in_line(p, s);
}

/* Outputs after sub-step i of the cycle: mechanics now, air from the buffer. */
static void substep_outputs(const rb_plant_params *p, rb_detailed_state *s, int i, double t)
{
    rb_plant_outputs keep = s->out;
    rb_plant_get_outputs(p, &s->mech, &s->out);
    s->out.time = t;
    s->out.main_reservoir = keep.main_reservoir;
    s->out.pipe_end = keep.pipe_end;
    s->out.compressor_on = keep.compressor_on;
    s->out.air_in_system = keep.air_in_system;
    s->out.air_compressed = keep.air_compressed;
    s->out.air_drawn = keep.air_drawn;
    s->out.air_vented = 0.0;
    for (int c = 0; c < p->n_cars; ++c) {
        s->out.supply[c] = *buf(s, i, B_SUPPLY, c);
        s->out.pilot[c] = *buf(s, i, B_CONTROL, c);
        s->out.relay[c] = *buf(s, i, B_RELAY, c);
        s->out.air_vented += *buf(s, i, B_VENTED, c);
    }
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        s->out.cylinder[a] = *buf_cyl(s, i, a);
        s->out.hold[a] = s->hold_at[i][a];
        s->out.vent[a] = s->vent_at[i][a];
    }
}

/* ------------------------------------------------------------------ init and run */

rb_status rb_detailed_init(const rb_plant_params *p, const rb_detailed_params *d, const rb_bcu_params *bcu,
                           const rb_wsp_params *wsp, const rb_scenario *sc, rb_detailed_state *s, rb_error *err)
{
    rb_status st;
    if (!s || !sc || !bcu) return rb_fail(err, RB_EINVAL, "state, scenario and bcu must not be NULL");
    if ((st = rb_detailed_check(d, err)) || (st = rb_run_check_scenario(sc, err))) return st;
    memset(s, 0, sizeof *s);
    if ((st = rb_plant_init(p, &s->mech, err))) return st;
    s->max_disc_surface_temperature = p->ambient_temperature;
    s->mech.derived.slip_probe_ahead = 0.0;   /* the reference's mechanics as they were: probed at each
                                                 fine step's start (its lag is a tenth of the 1 ms one) */
    if (p->n_faults > 0)
        return rb_fail(err, RB_EINVAL, "n_faults = %d: the detailed model does not model faults (needs 0)",
                       p->n_faults);
    if ((st = rb_bcu_init(bcu, wsp, &s->bcu, err))) return st;
    if (bcu->n_cars != p->n_cars)
        return rb_fail(err, RB_EINVAL, "bcu.n_cars = %d: must equal the plant's n_cars = %d", bcu->n_cars, p->n_cars);
    s->n_sub = (int)ceil(bcu->cycle / d->mechanics_dt - 1e-9);
    if (s->n_sub > RB_DET_MAX_SUBSTEPS)
        return rb_fail(err, RB_EINVAL, "detailed.mechanics_dt = %g s: at most %d sub-steps per BCU cycle of %g s",
                       d->mechanics_dt, RB_DET_MAX_SUBSTEPS, bcu->cycle);
    s->dt_mech = bcu->cycle / s->n_sub;
    if ((st = rb_membrane_init(&s->membrane, d->membrane_x, d->membrane_volume, d->membrane_points, err))) return st;
    for (int c = 0; c < p->n_cars; ++c) {
        double current;
        if ((st = rb_detailed_epv_current(p, d, p->initial_pressure, bcu->pressure_max[c], &current, err))) return st;
        rb_det_build_car(p, d, c, &s->car[c]);
        rb_det_system sys;
        rb_det_car_system(&s->car[c], d, &s->membrane, &sys);
        if ((st = rb_det_system_init(&sys, s->eval_work, sizeof s->eval_work / sizeof *s->eval_work,
                                     s->iwork + RB_DET_MAX_STATES, RB_DET_CAR_NODES, s->car[c].y, NULL, err)))
            return st;
    }
    build_line(p, d, s);
    rb_det_system line;
    line_system(p, s, &line);
    if ((st = rb_det_system_init(&line, s->eval_work, sizeof s->eval_work / sizeof *s->eval_work,
                                 s->iwork + RB_DET_MAX_STATES, RB_DET_LINE_NODES, s->line_y, NULL, err)))
        return st;
    s->compressor_on = p->initial_pressure < p->governor_on;
    for (int i = 0; i < RB_MAX_COMPRESSORS; ++i) s->compressor_running[i] = (uint8_t)s->compressor_on;
    s->m_initial = air_in_volumes(p, s);
    s->m_line_initial = air_in_line(p, s);
    s->substep = s->n_sub;   /* a cycle starts first */
    s->cycle = -1;
    cycle_outputs(p, d, s, 0.0);
    return RB_OK;
}

static double now(const rb_detailed_state *s, const rb_bcu_params *bcu)
{
    return s->cycle < 0 ? 0.0 : s->cycle * bcu->cycle + s->substep * s->dt_mech;
}

/* Car c's emergency circuit at a new cycle: when its valve acts (the loop's opening time is kept
   in the mechanics' plant state), and the load-weighing valve's regulated output (the demand within
   its limit, at most the supply at the cycle's start). */
static void emergency_cycle(const rb_plant_params *p, rb_detailed_state *s, int c)
{
    rb_detailed_car *k = &s->car[c];
    const rb_plant_car *car = &p->car[c];
    k->emergency_switch = rb_emergency_switch_time(car, s->mech.loop_open_time);
    k->emergency_cut = k->emergency_switch < INFINITY;
    double target = rb_emergency_target(car, s->in.pressure_demand[c], p->atmosphere);
    double supply = s->out.supply[c];
    k->node[CN_REGULATED].pressure = target < supply ? target : supply;
}

/* EP currents (static inverse + trimmed) and WSP valve commands of a new cycle. */
static void apply_bcu(const rb_plant_params *p, const rb_detailed_params *d, const rb_bcu_params *bcu,
                      rb_detailed_state *s, double t)
{
    const double trim_band = 0.2e5, trim_limit = 0.3e5;   /* Pa: integrate near the target only; limit */
    for (int c = 0; c < p->n_cars; ++c) {
        rb_detailed_car *k = &s->car[c];
        double demand = s->in.pressure_demand[c], error = demand - s->out.pilot[c];
        if (demand <= p->atmosphere) k->trim = 0.0;
        else if (d->trim_time > 0.0 && fabs(error) < trim_band)
            k->trim = fmax(-trim_limit, fmin(trim_limit, k->trim + error * bcu->cycle / d->trim_time));
        rb_error err;
        double target = demand > p->atmosphere ? demand + k->trim : demand;
        if (rb_detailed_epv_current(p, d, p->initial_pressure, target, &k->current, &err))
            k->current = d->current_max;   /* beyond the valve's reach (checked for pressure_max at init) */
        for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
            int i = c * RB_AXLES_PER_CAR + a;
            uint8_t hold = s->in.hold[i] != 0, vent = s->in.vent[i] != 0;
            double at = t + p->car[c].valve_delay;   /* the valve acts after its response delay */
            if (hold != k->hold_pending[a]) { k->hold_pending[a] = hold; k->hold_switch[a] = at; }
            if (vent != k->vent_pending[a]) { k->vent_pending[a] = vent; k->vent_switch[a] = at; }
        }
        emergency_cycle(p, s, c);
        rb_det_apply_commands(k);
    }
}

static rb_status start_cycle(const rb_plant_params *p, const rb_detailed_params *d, const rb_bcu_params *bcu,
                             const rb_scenario *sc, rb_detailed_state *s, double *series, size_t max_rows,
                             rb_error *err)
{
    s->cycle++;
    s->substep = 0;
    double t0 = s->cycle * bcu->cycle;
    int nch = rb_run_channel_count(p->n_cars);
    cycle_outputs(p, d, s, t0);
    if (series && t0 >= s->next_record - 1e-9) {
        if (s->rows >= max_rows) return rb_fail(err, RB_ESIZE, "max_rows = %zu: the series needs more rows", max_rows);
        rb_run_record_row(p, &s->out, bcu, &s->bcu, sc, series + s->rows++ * (size_t)nch);
        s->next_record += sc->record_interval;
    }
    rb_brake_demand dem = rb_scenario_demand(sc, t0);
    if (!s->braking && (dem.emergency > 0.5 || dem.service > 0.0)) {
        s->braking = 1;
        s->brake_time = t0;
        s->brake_position = s->out.position;
        s->brake_speed = s->out.speed;
    }
    rb_bcu_step(bcu, &s->bcu, &dem, &s->out, &s->in);
    s->mech.loop_open_time = rb_emergency_loop(s->mech.loop_open_time, s->in.emergency, t0);
    apply_bcu(p, d, bcu, s, t0);
    /* rows recorded inside the cycle get exact control and relay pressures */
    uint8_t full[RB_DET_MAX_SUBSTEPS] = {0};
    double next = s->next_record;
    for (int i = 0; i + 1 < s->n_sub; ++i)
        if (sub_time(s, t0, i) >= next - 1e-9) { full[i] = 1; next += sc->record_interval; }
    rb_status st;
    if ((st = advance_line(p, d, s, t0, sub_time(s, t0, s->n_sub - 1), err))) return st;
    for (int c = 0; c < p->n_cars; ++c)
        if ((st = advance_car(p, d, s, c, t0, full, err))) return st;
    return RB_OK;
}

static void track_slip(const rb_plant_params *p, rb_detailed_state *s)
{
    if (!s->braking) return;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        int c = a / RB_AXLES_PER_CAR;
        double v = s->mech.v[c];
        if (v <= LOCK_SPEED) continue;
        double slip = fabs(s->mech.omega[a] * p->car[c].vehicle.wheelset.wheel_radius - v) / v;
        if (slip > s->max_slip) s->max_slip = slip;
    }
}

rb_status rb_detailed_advance(const rb_plant_params *p, const rb_detailed_params *d, const rb_bcu_params *bcu,
                              const rb_scenario *sc, rb_detailed_state *s, double t_until, double *series,
                              size_t max_rows, int *finished, rb_error *err)
{
    int nch = rb_run_channel_count(p->n_cars);
    rb_status st;
    while (!s->finished && now(s, bcu) < t_until - 1e-9) {
        if (s->substep >= s->n_sub && (st = start_cycle(p, d, bcu, sc, s, series, max_rows, err))) return st;
        int i = s->substep;
        rb_plant_faults f;
        rb_plant_gather_faults(p, &s->mech, &f);
        rb_plant_step_mechanics(p, &s->mech, &s->in, &f, &s->buffer[i][B_CARS * RB_PLANT_MAX_CARS], s->dt_mech);
        rb_plant_discs(p, &s->mech, s->dt_mech);   /* the discs heat and the pads fade as in the plant */
        for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a)
            if (s->mech.disc_temperature[a] > s->max_disc_surface_temperature)
                s->max_disc_surface_temperature = s->mech.disc_temperature[a];
        rb_plant_update_sensors(p, &s->mech, &f);
        s->substep++;
        double t = now(s, bcu);
        track_slip(p, s);
        s->stopped = s->braking && s->mech.v[0] <= sc->stop_speed;
        int last = s->stopped || t >= sc->max_time - 1e-9;
        if (series && (last || (i + 1 < s->n_sub && t >= s->next_record - 1e-9))) {
            substep_outputs(p, s, i, t);
            if (s->rows >= max_rows)
                return rb_fail(err, RB_ESIZE, "max_rows = %zu: the series needs more rows", max_rows);
            rb_run_record_row(p, &s->out, bcu, &s->bcu, sc, series + s->rows++ * (size_t)nch);
            if (!last) s->next_record += sc->record_interval;
        }
        if (last) {
            substep_outputs(p, s, i, t);
            s->finished = 1;
        }
    }
    if (finished) *finished = s->finished;
    return RB_OK;
}

void rb_detailed_kpis(const rb_plant_params *p, const rb_detailed_state *s, rb_kpis *k)
{
    memset(k, 0, sizeof *k);
    k->stopped = s->stopped;
    if (s->braking) {
        k->stopping_distance_m = s->mech.x[0] - s->brake_position;
        k->stopping_time_s = s->out.time - s->brake_time;
        k->mean_deceleration = k->stopping_time_s > 0.0 ? (s->brake_speed - s->mech.v[0]) / k->stopping_time_s : 0.0;
    }
    k->max_slip = s->max_slip;
    k->max_disc_surface_temperature = s->max_disc_surface_temperature;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) k->brake_energy += s->mech.brake_energy[a];
    double vented = 0.0;
    for (int c = 0; c < p->n_cars; ++c) vented += s->car[c].y[CS_VENTED];
    k->air_consumed_kg = vented;
    k->safety_timer_trips = s->bcu.wsp_default.trips;
    k->air_balance_error = fabs(air_in_volumes(p, s) + vented - s->m_compressed - s->m_initial) / s->m_initial;
}

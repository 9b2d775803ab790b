/* Detailed model: each car's valve network, the EP valve drive, and solver restarts. */
#include "detailed_internal.h"

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif


#define CHECK_POS(field) \
    if ((s = rb_check_positive(err, "detailed." #field, d->field))) return s
#define CHECK_NONNEG(field) \
    if ((s = rb_check_nonnegative(err, "detailed." #field, d->field))) return s

rb_status rb_detailed_check(const rb_detailed_params *d, rb_error *err)
{
    rb_status s;
    if (!d) return rb_fail(err, RB_EINVAL, "detailed = NULL: valve parameters are required");
    CHECK_POS(pilot_volume); CHECK_POS(pilot_orifice_area); CHECK_POS(nozzle_diameter);
    CHECK_POS(armature_mass); CHECK_NONNEG(armature_spring_rate); CHECK_NONNEG(armature_damping);
    CHECK_POS(airgap_open); CHECK_POS(flapper_travel); CHECK_POS(current_max);
    if (!(d->flapper_travel < d->airgap_open))
        return rb_fail(err, RB_EINVAL, "detailed.flapper_travel = %g m: must be below airgap_open = %g m",
                       d->flapper_travel, d->airgap_open);
    if ((s = rb_force_table_check(&d->solenoid, err))) return s;
    CHECK_POS(piston_area); CHECK_POS(piston_mass); CHECK_NONNEG(piston_spring_rate);
    CHECK_NONNEG(piston_damping); CHECK_NONNEG(piston_friction); CHECK_POS(piston_friction_velocity);
    CHECK_POS(piston_travel); CHECK_NONNEG(seat_lap);
    CHECK_POS(epv_inlet_diameter); CHECK_POS(epv_exhaust_diameter);
    CHECK_POS(membrane_mass); CHECK_NONNEG(membrane_spring_rate); CHECK_NONNEG(membrane_damping);
    CHECK_POS(membrane_travel); CHECK_POS(relay_inlet_diameter); CHECK_POS(relay_exhaust_diameter);
    CHECK_POS(thermal_time); CHECK_NONNEG(trim_time);
    if ((s = rb_check_range(err, "detailed.rtol", d->rtol, 1e-10, 0.1))) return s;
    CHECK_POS(atol);
    return rb_check_range(err, "detailed.mechanics_dt", d->mechanics_dt, 1e-6, 0.01);
}

static void volume_node(rb_net_node *n, double pressure, double volume, double T, double thermal_time)
{
    memset(n, 0, sizeof *n);
    n->kind = RB_NODE_VOLUME;
    n->pressure = pressure;
    n->temperature = n->wall_temperature = T;
    n->volume = volume;
    n->heat_conductance = rb_wall_conductance(volume, T, thermal_time, RB_WALL_REFERENCE_PRESSURE);
}

static void link(rb_net_link *l, int kind, int from, int to, double area, const rb_plant_params *p)
{
    memset(l, 0, sizeof *l);
    l->kind = kind;
    l->from = from;
    l->to = to;
    l->orifice.area = area;
    l->orifice.discharge_coefficient = p->discharge_coefficient;
    l->orifice.critical_ratio = p->critical_ratio;
    l->direction = 1.0;
    l->shape = 0.5 * M_PI;   /* flat seats */
}

static void driven(rb_net_link *l, int body, double diameter, double offset, double direction)
{
    l->body = body;
    l->diameter = diameter;
    l->offset = offset;
    l->direction = direction;
}

static void body(rb_net_body *b, double mass, double rate, double preload, double damping, double travel_min,
                 double travel_max, double atmosphere)
{
    memset(b, 0, sizeof *b);
    b->mass = mass;
    b->spring_rate = rate;
    b->spring_preload = preload;
    b->damping = damping;
    b->friction_velocity = 1e-3;
    b->x_min = travel_min;
    b->x_max = travel_max;
    b->stop_stiffness = 1e7;   /* critically damped penalty stops, as the valve models' default */
    b->stop_damping = 2.0 * sqrt(b->stop_stiffness * mass);
    b->ambient_pressure = atmosphere;
    b->force_table = -1;
}

static void face(rb_net_body *b, int node, int membrane, double area, double direction)
{
    int f = b->n_faces++;
    b->face_node[f] = node;
    b->face_membrane[f] = membrane;
    b->face_area[f] = area;
    b->face_direction[f] = direction;
}

void rb_det_build_car(const rb_plant_params *p, const rb_detailed_params *d, int c, rb_detailed_car *k)
{
    const rb_plant_car *car = &p->car[c];
    double pa = p->atmosphere, T = p->temperature, tt = d->thermal_time;
    memset(k, 0, sizeof *k);
    volume_node(&k->node[CN_SUPPLY], p->initial_pressure, car->supply_volume, T, tt);
    volume_node(&k->node[CN_PILOT], pa, d->pilot_volume, T, tt);
    volume_node(&k->node[CN_CONTROL], pa, car->pilot_volume, T, tt);
    volume_node(&k->node[CN_RELAY], pa, car->relay_volume, T, tt);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) volume_node(&k->node[CN_CYL + a], pa, car->cylinder_volume, T, tt);
    k->node[CN_ATM].kind = RB_NODE_RESERVOIR;
    k->node[CN_ATM].pressure = pa;
    k->node[CN_ATM].temperature = T;

    rb_net_link *l = k->link;
    link(&l[CL_PILOT_ORIFICE], RB_LINK_FIXED, CN_SUPPLY, CN_PILOT, d->pilot_orifice_area, p);
    link(&l[CL_NOZZLE], RB_LINK_FLAPPER, CN_PILOT, CN_ATM, 0.0, p);
    driven(&l[CL_NOZZLE], CB_ARMATURE, d->nozzle_diameter, d->flapper_travel, -1.0);
    link(&l[CL_EPV_INLET], RB_LINK_SEAT, CN_SUPPLY, CN_CONTROL, 0.0, p);
    driven(&l[CL_EPV_INLET], CB_PISTON, d->epv_inlet_diameter, d->seat_lap, 1.0);
    link(&l[CL_EPV_EXHAUST], RB_LINK_SEAT, CN_CONTROL, CN_ATM, 0.0, p);
    driven(&l[CL_EPV_EXHAUST], CB_PISTON, d->epv_exhaust_diameter, -d->seat_lap, -1.0);
    link(&l[CL_RELAY_INLET], RB_LINK_SEAT, CN_SUPPLY, CN_RELAY, 0.0, p);
    driven(&l[CL_RELAY_INLET], CB_MEMBRANE, d->relay_inlet_diameter, 0.0, 1.0);
    link(&l[CL_RELAY_EXHAUST], RB_LINK_SEAT, CN_RELAY, CN_ATM, 0.0, p);
    driven(&l[CL_RELAY_EXHAUST], CB_MEMBRANE, d->relay_exhaust_diameter, 0.0, -1.0);
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
        link(&l[CL_HOLD + a], RB_LINK_FIXED, CN_RELAY, CN_CYL + a, car->hold_area, p);
        link(&l[CL_VENT + a], RB_LINK_FIXED, CN_CYL + a, CN_ATM, car->vent_area, p);
        l[CL_HOLD + a].opening.n = l[CL_VENT + a].opening.n = 1;
    }
    /* the emergency valve's choke between the load-weighing valve's regulated output and the
       control chamber (emergency_circuit.c); the EP valve's seats are cut off while the loop is
       open. The air the regulated node gives is taken from the supply after each solve
       (detailed_run.c), what it takes back is vented (its exhaust). */
    k->node[CN_REGULATED] = k->node[CN_ATM];
    link(&l[CL_EMERGENCY], RB_LINK_FIXED, CN_CONTROL, CN_REGULATED, car->emergency_area, p);
    l[CL_EMERGENCY].opening.n = 1;
    l[CL_EPV_INLET].opening.n = l[CL_EPV_EXHAUST].opening.n = 1;
    l[CL_RELAY_INLET].opening.n = 1;   /* shut by a failed relay valve or an isolated car */
    k->emergency_switch = INFINITY;
    memset(k->hold_stuck, -1, sizeof k->hold_stuck);
    memset(k->vent_stuck, -1, sizeof k->vent_stuck);
    k->vent_area = car->vent_area;

    rb_net_body *b = &k->body[CB_ARMATURE];
    body(b, d->armature_mass, d->armature_spring_rate, d->armature_preload, d->armature_damping, 0.0,
         d->flapper_travel, pa);
    face(b, CN_PILOT, -1, 0.25 * M_PI * d->nozzle_diameter * d->nozzle_diameter, -1.0);
    b->force_table = 0;
    b->airgap_initial = d->airgap_open;
    b->current.n = 1;
    b = &k->body[CB_PISTON];
    body(b, d->piston_mass, d->piston_spring_rate, d->piston_preload, d->piston_damping, -d->piston_travel,
         d->piston_travel, pa);
    b->friction = d->piston_friction;
    b->friction_velocity = d->piston_friction_velocity;
    face(b, CN_PILOT, -1, d->piston_area, 1.0);
    face(b, CN_CONTROL, -1, d->piston_area, -1.0);
    b = &k->body[CB_MEMBRANE];
    body(b, d->membrane_mass, d->membrane_spring_rate, d->membrane_preload, d->membrane_damping,
         -d->membrane_travel, d->membrane_travel, pa);
    face(b, CN_CONTROL, 0, 0.0, 1.0);
    face(b, CN_RELAY, 0, 0.0, -1.0);
    rb_det_apply_commands(k);
}

/* Each axle's outlet: the vent port (open or shut) and a leak beside it, one orifice of their summed
   area opened to the part that is open (no leak: the vent port alone, opening 1 or 0). */
static void cylinder_outlet(rb_detailed_car *k, int a, int vent)
{
    double area = k->vent_area + k->leak[a], open = (vent ? k->vent_area : 0.0) + k->leak[a];
    k->link[CL_VENT + a].orifice.area = area;
    k->link[CL_VENT + a].opening.value[0] = area > 0.0 ? open / area : 0.0;
}

void rb_det_apply_commands(rb_detailed_car *k)
{
    for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
        int hold = k->hold_stuck[a] >= 0 ? k->hold_stuck[a] : k->hold[a];
        int vent = k->vent_stuck[a] >= 0 ? k->vent_stuck[a] : k->vent[a];
        k->link[CL_HOLD + a].opening.value[0] = hold ? 0.0 : 1.0;
        cylinder_outlet(k, a, vent);
    }
    k->body[CB_ARMATURE].current.value[0] = k->current;
    k->link[CL_EPV_INLET].opening.value[0] = k->link[CL_EPV_EXHAUST].opening.value[0] =
        k->emergency_cut || k->ep_failed ? 0.0 : 1.0;
    k->link[CL_EMERGENCY].opening.value[0] = k->emergency ? 1.0 : 0.0;
    k->link[CL_RELAY_INLET].opening.value[0] = k->relay_shut ? 0.0 : 1.0;
}

void rb_det_car_system(rb_detailed_car *k, const rb_detailed_params *d, const rb_membrane *membrane,
                       rb_det_system *sys)
{
    static const int vented[] = {CL_NOZZLE, CL_EPV_EXHAUST, CL_RELAY_EXHAUST, CL_VENT, CL_VENT + 1,
                                 CL_VENT + 2, CL_VENT + 3};
    memset(sys, 0, sizeof *sys);
    rb_network net = {k->node, RB_DET_CAR_NODES, k->link, RB_DET_CAR_LINKS, k->body, RB_DET_CAR_BODIES,
                      &d->solenoid, 1, membrane, 1};
    sys->net = net;
    sys->n_acc = 1;
    memset(sys->acc_of_link, -1, sizeof sys->acc_of_link);
    for (size_t i = 0; i < sizeof vented / sizeof *vented; ++i) sys->acc_of_link[vented[i]] = 0;
}

rb_status rb_det_system_init(rb_det_system *sys, double *work, size_t work_size, int *iwork, size_t iwork_size,
                             double *y0, double *scale, rb_error *err)
{
    rb_status s = rb_network_eval_init(&sys->net, &sys->ev, work, work_size, iwork, iwork_size, y0, scale, err);
    if (s) return s;
    sys->n_net = rb_network_state_count(&sys->net);
    for (int i = 0; i < sys->n_acc; ++i) {
        y0[sys->n_net + i] = 0.0;
        if (scale) scale[sys->n_net + i] = 1.0;
    }
    return RB_OK;
}

static void system_rates(double t, const double *y, double *dydt, void *user)
{
    rb_det_system *sys = user;
    rb_network_rates(t, y, dydt, &sys->ev);
    for (int i = 0; i < sys->n_acc; ++i) dydt[sys->n_net + i] = 0.0;
    for (size_t j = 0; j < sys->net.n_links; ++j)
        if (sys->acc_of_link[j] >= 0) dydt[sys->n_net + sys->acc_of_link[j]] += sys->ev.mdot[j];
}

static void on_step(double t, const double *y, void *user)
{
    rb_det_system *sys = user;
    (void)y;
    sys->h_step = sys->h_final;
    sys->h_final = t - sys->t_prev;
    sys->t_prev = t;
}

rb_status rb_det_solve(rb_det_system *sys, const rb_detailed_params *d, double t0, double *y, const double *t_out,
                       size_t n_out, double *y_out, double *h, const double *scale, double *work, int *iwork,
                       rb_ode_stats *total, rb_error *err)
{
    size_t n = sys->n_net + (size_t)sys->n_acc;
    rb_ode_options opt = {d->rtol, d->atol, scale, *h, 0.0, 200000};
    rb_ode_stats st = {0, 0, 0};
    sys->t_prev = t0;
    sys->h_step = sys->h_final = 0.0;
    rb_status s = rb_ode_solve(system_rates, sys, n, t0, y, t_out, n_out, y_out, on_step, &opt, work,
                               rb_ode_workspace_size(n), iwork, &st, err);
    if (s && sys->ev.volume_error)
        return rb_fail(err, RB_EINVAL, "detailed: node %d volume fell to <= 0 m^3", sys->ev.volume_error - 1);
    if (s) return s;
    /* The last step was cut to reach t_end: the one before it says more about the dynamics. */
    double next = fmax(sys->h_step, sys->h_final);
    if (next > 0.0) *h = next;
    total->steps += st.steps;
    total->rejected += st.rejected;
    total->rhs_calls += st.rhs_calls;
    return RB_OK;
}

/* ------------------------------------------------------------------ EP valve drive */

rb_status rb_detailed_epv_current(const rb_plant_params *p, const rb_detailed_params *d, double supply,
                                  double pressure, double *current, rb_error *err)
{
    double pa = p->atmosphere, T = p->temperature, cd = p->discharge_coefficient, b = p->critical_ratio;
    *current = 0.0;
    if (pressure <= pa) return RB_OK;
    /* piston at rest between its seats: pilot - control = preload / area */
    double pilot = pressure + d->piston_preload / d->piston_area;
    double q = rb_orifice_mass_flow_fast(supply, T, pilot, T, d->pilot_orifice_area, cd, b);
    if (!(q > 0.0))
        return rb_fail(err, RB_EINVAL, "pressure = %g Pa: needs a pilot pressure %g Pa, not below the supply %g Pa",
                       pressure, pilot, supply);
    /* nozzle curtain passing the orifice's flow (flow is proportional to area) */
    double area = q / rb_orifice_mass_flow_fast(pilot, T, pa, T, 1.0, cd, b);
    double D = d->nozzle_diameter, gap = area / (M_PI * D);
    if (area >= 0.25 * M_PI * D * D || gap >= d->flapper_travel) return RB_OK;  /* open nozzle suffices */
    double x = d->flapper_travel - gap;
    double need = d->armature_preload + d->armature_spring_rate * x + (pilot - pa) * 0.25 * M_PI * D * D;
    double airgap = d->airgap_open - x, lo = 0.0, hi = d->current_max;
    if (rb_force_table_eval(&d->solenoid, airgap, hi) < need)
        return rb_fail(err, RB_EINVAL,
                       "pressure = %g Pa: the EP valve needs %g N of solenoid force at airgap %g m, more than "
                       "the %g N of current_max = %g A",
                       pressure, need, airgap, rb_force_table_eval(&d->solenoid, airgap, hi), hi);
    for (int i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi);
        if (rb_force_table_eval(&d->solenoid, airgap, mid) < need) lo = mid;
        else hi = mid;
    }
    *current = hi;
    return RB_OK;
}

rb_status rb_detailed_valve_run(const rb_plant_params *p, const rb_detailed_params *d, double current,
                                double t_end, double pressures[4], double positions[3], rb_error *err)
{
    enum { N = RB_DET_CAR_STATES };
    rb_status s;
    rb_detailed_car k;
    rb_membrane mb;
    rb_det_system sys;
    double work[N * N + 10 * N], eval_work[8 * RB_DET_CAR_NODES + RB_DET_CAR_LINKS + 2 * RB_DET_CAR_BODIES];
    double y[N], scale[N], y_out[N], dydt[N], h = 0.0;
    int iwork[N], eval_iwork[RB_DET_CAR_NODES];
    rb_ode_stats st = {0, 0, 0};
    if ((s = rb_plant_check(p, err)) || (s = rb_detailed_check(d, err))) return s;
    if ((s = rb_check_range(err, "current", current, 0.0, d->current_max))) return s;
    if ((s = rb_check_range(err, "t_end", t_end, 1e-3, 100.0))) return s;
    if ((s = rb_membrane_init(&mb, d->membrane_x, d->membrane_volume, d->membrane_points, err))) return s;
    rb_det_build_car(p, d, 0, &k);
    k.current = current;
    rb_det_apply_commands(&k);
    rb_det_car_system(&k, d, &mb, &sys);
    if ((s = rb_det_system_init(&sys, eval_work, sizeof eval_work / sizeof *eval_work, eval_iwork,
                                RB_DET_CAR_NODES, y, scale, err)))
        return s;
    if ((s = rb_det_solve(&sys, d, 0.0, y, &t_end, 1, y_out, &h, scale, work, iwork, &st, err))) return s;
    rb_network_rates(t_end, y, dydt, &sys.ev);
    pressures[0] = sys.ev.p[CN_PILOT];
    pressures[1] = sys.ev.p[CN_CONTROL];
    pressures[2] = sys.ev.p[CN_RELAY];
    pressures[3] = sys.ev.p[CN_CYL];
    for (int b = 0; b < RB_DET_CAR_BODIES; ++b) positions[b] = sys.ev.x[b];
    return RB_OK;
}

/* The air one car's valves use while WSP cycles its brakes (car 0 of plant, a constant EP current):
   from the released state, filled for `settle` s, then `cycles` WSP cycles of every axle, each
   phase[0] s venting (hold shut, vent open), phase[1] s holding (both shut) and phase[2] s refilling
   (hold open). air: over the cycles, the masses (kg) through [0] the EP pilot stage's feed orifice
   (its nozzle's bleed), [1] the EP valve's exhaust, [2] the relay valve's exhaust, [3] the relay
   valve's inlet, [4] the cylinders' vents (accumulators of the network's link flows). */
rb_status rb_detailed_valve_air(const rb_plant_params *p, const rb_detailed_params *d, double current,
                                double settle, const double phase[3], int cycles, double air[5], rb_error *err)
{
    enum { ACC = 5, N = RB_DET_CAR_STATES - 1 + ACC };
    static const int acc_link[ACC] = {CL_PILOT_ORIFICE, CL_EPV_EXHAUST, CL_RELAY_EXHAUST, CL_RELAY_INLET, CL_VENT};
    rb_status s;
    rb_detailed_car k;
    rb_membrane mb;
    rb_det_system sys;
    double work[N * N + 10 * N], eval_work[8 * RB_DET_CAR_NODES + RB_DET_CAR_LINKS + 2 * RB_DET_CAR_BODIES];
    double y[N], scale[N], y_out[N], h = 0.0, t = 0.0, start[ACC] = {0.0};
    int iwork[N], eval_iwork[RB_DET_CAR_NODES];
    rb_ode_stats st = {0, 0, 0};
    if (!phase || !air) return rb_fail(err, RB_EINVAL, "phase and air are required");
    if ((s = rb_plant_check(p, err)) || (s = rb_detailed_check(d, err))) return s;
    if ((s = rb_check_range(err, "current", current, 0.0, d->current_max))) return s;
    if ((s = rb_valve_air_cycle_check(settle, phase, cycles, err))) return s;
    if ((s = rb_membrane_init(&mb, d->membrane_x, d->membrane_volume, d->membrane_points, err))) return s;
    rb_det_build_car(p, d, 0, &k);
    k.current = current;
    rb_det_apply_commands(&k);
    rb_det_car_system(&k, d, &mb, &sys);
    sys.n_acc = ACC;
    memset(sys.acc_of_link, -1, sizeof sys.acc_of_link);
    for (int i = 0; i < ACC; ++i) sys.acc_of_link[acc_link[i]] = (signed char)i;
    for (int a = 1; a < RB_AXLES_PER_CAR; ++a) sys.acc_of_link[CL_VENT + a] = ACC - 1;
    if ((s = rb_det_system_init(&sys, eval_work, sizeof eval_work / sizeof *eval_work, eval_iwork,
                                RB_DET_CAR_NODES, y, scale, err)))
        return s;
    for (int c = -1; c < cycles; ++c)
        for (int ph = c < 0 ? 2 : 0; ph < 3; ++ph) {   /* the settling fill first: hold open */
            double t_end = t + (c < 0 ? settle : phase[ph]);
            for (int a = 0; a < RB_AXLES_PER_CAR; ++a) {
                k.hold[a] = ph < 2;
                k.vent[a] = ph == 0;
            }
            rb_det_apply_commands(&k);
            if (t_end > t && (s = rb_det_solve(&sys, d, t, y, &t_end, 1, y_out, &h, scale, work, iwork, &st, err)))
                return s;
            t = t_end;
            if (c < 0) memcpy(start, &y[sys.n_net], sizeof start);
        }
    for (int i = 0; i < ACC; ++i) air[i] = y[sys.n_net + i] - start[i];
    return RB_OK;
}

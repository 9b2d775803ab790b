/* Whole simulation of a pneumatic network with moving bodies (see rb_network.h).
 * States: (m, T) of each volume node, then (x, v) of each body. */
#include "railbrake/rb_network.h"

#include <math.h>
#include <string.h>

typedef rb_network_eval net_ctx;

static const double CP = RB_AIR_GAMMA * RB_AIR_R / (RB_AIR_GAMMA - 1.0);

static void face_volume(const net_ctx *c, const rb_net_body *b, int f, double x, double *vol, double *area)
{
    int mi = b->face_membrane[f];
    if (mi < 0) {
        *vol = b->face_area[f] * x;
        *area = b->face_area[f];
        return;
    }
    double v0, a0;
    rb_membrane_eval(&c->net->membranes[mi], 0.0, &v0, &a0);
    rb_membrane_eval(&c->net->membranes[mi], x, vol, area);
    *vol -= v0;
}

static double link_area(const net_ctx *c, const rb_net_link *l, double t)
{
    double open = rb_schedule_eval(&l->opening, t);
    if (l->kind == RB_LINK_FIXED) return open * l->orifice.area;
    double s = l->direction * (c->x[l->body] - l->offset);
    switch (l->kind) {
    case RB_LINK_FLAPPER: return open * rb_flapper_nozzle_area(l->diameter, s);
    case RB_LINK_SEAT: return open * rb_seat_area(l->diameter, s, l->shape);
    default: return open * rb_spool_edge_area(l->diameter, s, l->shape);
    }
}

/* Node states (p, T, V, dV/dt) at time t from y. */
static void node_states(net_ctx *c, double t, const double *y)
{
    const rb_network *n = c->net;
    for (size_t k = 0; k < n->n_bodies; ++k) {
        c->x[k] = y[2 * c->n_volumes + 2 * k];
        c->v[k] = y[2 * c->n_volumes + 2 * k + 1];
    }
    for (size_t i = 0; i < n->n_nodes; ++i) {
        c->V[i] = n->nodes[i].volume + n->nodes[i].volume_rate * t;
        c->dV[i] = n->nodes[i].volume_rate;
    }
    for (size_t k = 0; k < n->n_bodies; ++k) {
        const rb_net_body *b = &n->bodies[k];
        for (int f = 0; f < b->n_faces; ++f) {
            double vol, area;
            face_volume(c, b, f, c->x[k], &vol, &area);
            c->V[b->face_node[f]] += b->face_direction[f] * vol;
            c->dV[b->face_node[f]] += b->face_direction[f] * area * c->v[k];
        }
    }
    for (size_t i = 0; i < n->n_nodes; ++i) {
        int s = c->state_of_node[i];
        if (s < 0) {
            c->p[i] = n->nodes[i].pressure;
            c->T[i] = n->nodes[i].temperature;
        } else {
            if (!(c->V[i] > 0.0)) c->volume_error = (int)i + 1;
            c->T[i] = y[s + 1];
            c->p[i] = y[s] * RB_AIR_R * y[s + 1] / c->V[i];
        }
    }
}

static void link_flows(net_ctx *c, double t)
{
    const rb_network *n = c->net;
    for (size_t i = 0; i < n->n_nodes; ++i) c->m_in[i] = c->h_in[i] = c->m_out[i] = 0.0;
    for (size_t j = 0; j < n->n_links; ++j) {
        const rb_net_link *l = &n->links[j];
        int a = l->from, b = l->to;
        double md;
        if (l->kind == RB_LINK_FIXED && l->orifice.sonic_conductance > 0.0)
            md = rb_schedule_eval(&l->opening, t) *
                 rb_orifice_mass_flow_iso_fast(c->p[a], c->T[a], c->p[b], c->T[b],
                                               l->orifice.sonic_conductance, l->orifice.critical_ratio);
        else
            md = rb_orifice_mass_flow_fast(c->p[a], c->T[a], c->p[b], c->T[b], link_area(c, l, t),
                                           l->orifice.discharge_coefficient, l->orifice.critical_ratio);
        c->mdot[j] = md;
        int up = md >= 0.0 ? a : b, down = md >= 0.0 ? b : a;
        double q = fabs(md);
        c->m_out[up] += q;
        c->m_in[down] += q;
        c->h_in[down] += CP * c->T[up] * q;
    }
}

static double body_force(const net_ctx *c, size_t k, double t)
{
    const rb_net_body *b = &c->net->bodies[k];
    double x = c->x[k], v = c->v[k];
    double f = b->force - b->spring_preload - b->spring_rate * x - b->damping * v;
    if (b->friction > 0.0) f -= b->friction * tanh(v / b->friction_velocity);
    for (int i = 0; i < b->n_faces; ++i) {
        double vol, area;
        face_volume(c, b, i, x, &vol, &area);
        f += b->face_direction[i] * (c->p[b->face_node[i]] - b->ambient_pressure) * area;
    }
    if (b->force_table >= 0)
        f += rb_force_table_eval(&c->net->tables[b->force_table], b->airgap_initial - x,
                                 rb_schedule_eval(&b->current, t));
    if (x < b->x_min) f += b->stop_stiffness * (b->x_min - x) - b->stop_damping * v;
    if (x > b->x_max) f -= b->stop_stiffness * (x - b->x_max) + b->stop_damping * v;
    return f;
}

void rb_network_rates(double t, const double *y, double *dydt, void *user)
{
    net_ctx *c = user;
    const rb_network *n = c->net;
    node_states(c, t, y);
    link_flows(c, t);
    for (size_t i = 0; i < n->n_nodes; ++i) {
        int s = c->state_of_node[i];
        if (s < 0) continue;
        const rb_net_node *nd = &n->nodes[i];
        double heat = nd->heat_conductance * (nd->wall_temperature - c->T[i]), dp;
        rb_volume_rates(y[s], y[s + 1], c->V[i], c->dV[i], c->m_in[i], c->h_in[i], c->m_out[i], heat,
                        &dydt[s], &dydt[s + 1], &dp);
        if (!(c->V[i] > 0.0)) dydt[s] = NAN;
    }
    for (size_t k = 0; k < n->n_bodies; ++k) {
        size_t s = 2 * c->n_volumes + 2 * k;
        dydt[s] = c->v[k];
        dydt[s + 1] = body_force(c, k, t) / n->bodies[k].mass;
    }
}

static size_t count_volumes(const rb_network *net)
{
    size_t nv = 0;
    for (size_t i = 0; i < net->n_nodes; ++i) nv += net->nodes[i].kind == RB_NODE_VOLUME;
    return nv;
}

static size_t n_states(const rb_network *net) { return 2 * count_volumes(net) + 2 * net->n_bodies; }

size_t rb_network_state_count(const rb_network *net) { return n_states(net); }

size_t rb_network_eval_size(const rb_network *net, size_t *n_int)
{
    if (n_int) *n_int = net->n_nodes;
    return 8 * net->n_nodes + net->n_links + 2 * net->n_bodies;
}

size_t rb_network_workspace_size(const rb_network *net, size_t n_out, size_t *n_int)
{
    size_t n = n_states(net);
    if (n_int) *n_int = n + net->n_nodes;
    return rb_ode_workspace_size(n) + n * (n_out + 2) + rb_network_eval_size(net, NULL);
}

static rb_status check_node(const rb_net_node *nd, size_t i, rb_error *err)
{
    if (nd->kind != RB_NODE_RESERVOIR && nd->kind != RB_NODE_VOLUME)
        return rb_fail(err, RB_EINVAL, "node %zu kind = %d: must be 0 (reservoir) or 1 (volume)", i, nd->kind);
    if (!isfinite(nd->pressure) || !(nd->pressure > 0.0))
        return rb_fail(err, RB_EINVAL, "node %zu pressure = %g Pa: must be finite and > 0", i, nd->pressure);
    if (!isfinite(nd->temperature) || !(nd->temperature > 0.0))
        return rb_fail(err, RB_EINVAL, "node %zu temperature = %g K: must be finite and > 0", i, nd->temperature);
    if (nd->kind == RB_NODE_RESERVOIR) return RB_OK;
    if (!isfinite(nd->volume) || !(nd->volume > 0.0))
        return rb_fail(err, RB_EINVAL, "node %zu volume = %g m^3: must be finite and > 0", i, nd->volume);
    if (!isfinite(nd->volume_rate) || !isfinite(nd->wall_temperature) ||
        !isfinite(nd->heat_conductance) || nd->heat_conductance < 0.0 ||
        (nd->heat_conductance > 0.0 && !(nd->wall_temperature > 0.0)))
        return rb_fail(err, RB_EINVAL,
                       "node %zu heat_conductance = %g W/K, wall_temperature = %g K, volume_rate = %g: "
                       "need finite values, conductance >= 0 and wall temperature > 0",
                       i, nd->heat_conductance, nd->wall_temperature, nd->volume_rate);
    return RB_OK;
}

static rb_status check_link(const rb_network *net, const rb_net_link *l, size_t j, rb_error *err)
{
    rb_status s;
    if (l->from < 0 || l->to < 0 || (size_t)l->from >= net->n_nodes || (size_t)l->to >= net->n_nodes ||
        l->from == l->to)
        return rb_fail(err, RB_EINVAL, "link %zu nodes %d -> %d: must be two different nodes in [0, %zu)",
                       j, l->from, l->to, net->n_nodes);
    if ((s = rb_orifice_check(&l->orifice, err))) return s;
    if (l->kind == RB_LINK_FIXED) return RB_OK;
    if (l->kind < 0 || l->kind > RB_LINK_SPOOL)
        return rb_fail(err, RB_EINVAL, "link %zu kind = %d: must lie in [0, 3]", j, l->kind);
    if (l->body < 0 || (size_t)l->body >= net->n_bodies)
        return rb_fail(err, RB_EINVAL, "link %zu body = %d: must lie in [0, %zu)", j, l->body, net->n_bodies);
    if ((s = rb_check_positive(err, "link diameter", l->diameter))) return s;
    if (fabs(l->direction) != 1.0)
        return rb_fail(err, RB_EINVAL, "link %zu direction = %g: must be +1 or -1", j, l->direction);
    return RB_OK;
}

static rb_status check_body(const rb_network *net, const rb_net_body *b, size_t k, rb_error *err)
{
    rb_status s;
    if ((s = rb_check_positive(err, "body mass", b->mass))) return s;
    if ((s = rb_check_nonnegative(err, "body friction", b->friction))) return s;
    if (b->friction > 0.0 && (s = rb_check_positive(err, "body friction_velocity", b->friction_velocity))) return s;
    if (!(b->x_min < b->x_max))
        return rb_fail(err, RB_EINVAL, "body %zu stops x_min = %g, x_max = %g m: need x_min < x_max", k, b->x_min, b->x_max);
    if (b->n_faces < 0 || b->n_faces > RB_BODY_FACES)
        return rb_fail(err, RB_EINVAL, "body %zu n_faces = %d: must lie in [0, %d]", k, b->n_faces, RB_BODY_FACES);
    for (int f = 0; f < b->n_faces; ++f) {
        int nd = b->face_node[f], mi = b->face_membrane[f];
        if (nd < 0 || (size_t)nd >= net->n_nodes || net->nodes[nd].kind != RB_NODE_VOLUME)
            return rb_fail(err, RB_EINVAL, "body %zu face %d node = %d: must be a volume node", k, f, nd);
        if (mi >= 0 && (size_t)mi >= net->n_membranes)
            return rb_fail(err, RB_EINVAL, "body %zu face %d membrane = %d: out of range", k, f, mi);
        if (mi < 0 && (s = rb_check_nonnegative(err, "face area", b->face_area[f]))) return s;
    }
    if (b->force_table >= 0) {
        if ((size_t)b->force_table >= net->n_tables)
            return rb_fail(err, RB_EINVAL, "body %zu force_table = %d: out of range", k, b->force_table);
        if ((s = rb_force_table_check(&net->tables[b->force_table], err))) return s;
    }
    return RB_OK;
}

rb_status rb_network_check(const rb_network *net, rb_error *err)
{
    rb_status s;
    if (!net || (net->n_nodes && !net->nodes) || (net->n_links && !net->links) ||
        (net->n_bodies && !net->bodies))
        return rb_fail(err, RB_EINVAL, "network: arrays must not be NULL");
    if (n_states(net) == 0) return rb_fail(err, RB_EINVAL, "network: no volume or body to simulate");
    for (size_t i = 0; i < net->n_nodes; ++i)
        if ((s = check_node(&net->nodes[i], i, err))) return s;
    for (size_t j = 0; j < net->n_links; ++j)
        if ((s = check_link(net, &net->links[j], j, err))) return s;
    for (size_t k = 0; k < net->n_bodies; ++k)
        if ((s = check_body(net, &net->bodies[k], k, err))) return s;
    return RB_OK;
}

/* Absolute-tolerance scales: the mass of each volume at 1 bar, 300 K for temperatures, the stroke
   of each body and that stroke per millisecond for its velocity. */
static void set_scales(const net_ctx *c, const double *y, double *scale)
{
    const rb_network *n = c->net;
    for (size_t i = 0; i < n->n_nodes; ++i) {
        int s = c->state_of_node[i];
        if (s < 0) continue;
        scale[s] = 1e5 * c->V[i] / (RB_AIR_R * 300.0);
        scale[s + 1] = 300.0;
    }
    (void)y;
    for (size_t k = 0; k < n->n_bodies; ++k) {
        double stroke = n->bodies[k].x_max - n->bodies[k].x_min;
        if (!isfinite(stroke) || stroke > 1.0) stroke = 1e-3;
        scale[2 * c->n_volumes + 2 * k] = stroke;
        scale[2 * c->n_volumes + 2 * k + 1] = stroke * 1e3;
    }
}

/* Fills the outputs of one time from the state y. */
static void record(net_ctx *c, double t, const double *y, size_t r, double *node_p, double *node_T,
                   double *node_m, double *link_mdot, double *body_x, double *body_v)
{
    const rb_network *n = c->net;
    node_states(c, t, y);
    link_flows(c, t);
    for (size_t i = 0; i < n->n_nodes; ++i) {
        int s = c->state_of_node[i];
        node_p[r * n->n_nodes + i] = c->p[i];
        node_T[r * n->n_nodes + i] = c->T[i];
        node_m[r * n->n_nodes + i] = s < 0 ? 0.0 : y[s];
    }
    for (size_t j = 0; j < n->n_links; ++j) link_mdot[r * n->n_links + j] = c->mdot[j];
    for (size_t k = 0; k < n->n_bodies; ++k) {
        body_x[r * n->n_bodies + k] = c->x[k];
        body_v[r * n->n_bodies + k] = c->v[k];
    }
}

rb_status rb_network_eval_init(const rb_network *net, rb_network_eval *c, double *work, size_t work_size,
                               int *iwork, size_t iwork_size, double *y, double *scale, rb_error *err)
{
    rb_status s;
    if ((s = rb_network_check(net, err))) return s;
    size_t n_int = 0;   /* set by rb_network_eval_size; 0 if an earlier test fails first */
    if (!c || !work || !iwork || !y || work_size < rb_network_eval_size(net, &n_int) || iwork_size < n_int)
        return rb_fail(err, RB_ESIZE, "network evaluation: storage of %zu doubles and %zu ints is required",
                       rb_network_eval_size(net, NULL), n_int);
    memset(c, 0, sizeof *c);
    c->net = net;
    c->n_volumes = count_volumes(net);
    c->state_of_node = iwork;
    double *q = work;
    double **arrays[] = {&c->p, &c->T, &c->V, &c->dV, &c->m_in, &c->h_in, &c->m_out};
    for (size_t a = 0; a < 7; ++a, q += net->n_nodes) *arrays[a] = q;
    q += net->n_nodes;
    c->mdot = q; q += net->n_links;
    c->x = q; c->v = q + net->n_bodies;
    int next = 0;
    for (size_t i = 0; i < net->n_nodes; ++i) {
        const rb_net_node *nd = &net->nodes[i];
        c->state_of_node[i] = nd->kind == RB_NODE_VOLUME ? next : -1;
        if (nd->kind != RB_NODE_VOLUME) continue;
        y[next] = 0.0;
        y[next + 1] = nd->temperature;
        next += 2;
    }
    for (size_t k = 0; k < net->n_bodies; ++k) {
        y[next++] = net->bodies[k].x_initial;
        y[next++] = 0.0;
    }
    /* Initial masses from the initial pressures and the volumes at the initial positions. */
    node_states(c, 0.0, y);
    for (size_t i = 0; i < net->n_nodes; ++i) {
        int si = c->state_of_node[i];
        if (si < 0) continue;
        if (!(c->V[i] > 0.0))
            return rb_fail(err, RB_EINVAL, "node %zu volume = %g m^3 at the initial positions: must be > 0", i, c->V[i]);
        y[si] = net->nodes[i].pressure * c->V[i] / (RB_AIR_R * net->nodes[i].temperature);
    }
    if (scale) set_scales(c, y, scale);
    return RB_OK;
}

rb_status rb_network_simulate(const rb_network *net, const double *t_out, size_t n_out,
                              const rb_ode_options *opt, double *work, size_t work_size, int *iwork,
                              double *node_p, double *node_T, double *node_m, double *link_mdot,
                              double *body_x, double *body_v, rb_ode_stats *stats, rb_error *err)
{
    rb_status s;
    if ((s = rb_network_check(net, err))) return s;
    if (!t_out || n_out == 0 || !work || !iwork || !node_p || !node_T || !node_m ||
        (net->n_links && !link_mdot) || (net->n_bodies && (!body_x || !body_v)))
        return rb_fail(err, RB_EINVAL, "network: t_out, workspaces and outputs are required");
    size_t need = rb_network_workspace_size(net, n_out, NULL), n = n_states(net);
    if (work_size < need)
        return rb_fail(err, RB_ESIZE, "network work_size = %zu: needs >= %zu doubles", work_size, need);
    double *w = work + rb_ode_workspace_size(n), *y = w, *y_out = y + n;
    double *scale = y_out + n * n_out, *q = scale + n;
    net_ctx c;
    if ((s = rb_network_eval_init(net, &c, q, rb_network_eval_size(net, NULL), iwork + n, net->n_nodes, y,
                                  scale, err)))
        return s;
    rb_ode_options o = *opt;
    o.atol_scale = scale;
    s = rb_ode_solve(rb_network_rates, &c, n, 0.0, y, t_out, n_out, y_out, NULL, &o, work,
                     rb_ode_workspace_size(n), iwork, stats, err);
    if (s && c.volume_error)
        return rb_fail(err, RB_EINVAL, "node %d volume fell to <= 0 m^3 during the simulation", c.volume_error - 1);
    if (s) return s;
    for (size_t r = 0; r < n_out; ++r)
        record(&c, t_out[r], y_out + r * n, r, node_p, node_T, node_m, link_mdot, body_x, body_v);
    return RB_OK;
}

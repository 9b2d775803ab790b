/* The reference BCU server: the simulation's own BCU (rb_bcu_step, the scenario's demand profile)
 * driven by plant frames received over UDP, answering with BCU frames. A working peer for the HIL
 * runner, and the example a user replaces with a real unit. */
#define _POSIX_C_SOURCE 200809L
#include "railbrake/rb_hil.h"

#include <poll.h>
#include <string.h>

size_t rb_hil_bcu_size(void) { return sizeof(rb_hil_bcu); }

rb_status rb_hil_bcu_open(const rb_bcu_params *bcu, const rb_wsp_params *wsp, const rb_scenario *scenario,
                          const char *host, int port, rb_hil_bcu *b, rb_error *err)
{
    rb_status s;
    if (!b || !scenario) return rb_fail(err, RB_EINVAL, "server and scenario must not be NULL");
    if (scenario->n_demand < 1 || scenario->n_demand > RB_MAX_DEMAND_STEPS)
        return rb_fail(err, RB_EINVAL, "n_demand = %d: must be in [1, %d]", scenario->n_demand, RB_MAX_DEMAND_STEPS);
    memset(b, 0, sizeof *b);
    b->udp.fd = -1;
    if ((s = rb_bcu_init(bcu, wsp, &b->state, err))) return s;
    if ((s = rb_udp_open(&b->udp, host, port, err))) return s;
    b->start_ns = rb_monotonic_ns();
    return RB_OK;
}

int rb_hil_bcu_port(const rb_hil_bcu *b) { return rb_udp_local_port(&b->udp); }

void rb_hil_bcu_counters(const rb_hil_bcu *b, uint64_t counts[RB_HIL_BCU_COUNTERS])
{
    uint64_t c[RB_HIL_BCU_COUNTERS] = {b->received, b->malformed, b->stale, b->sent, b->send_errors, b->cycles};
    memcpy(counts, c, sizeof c);
}

void rb_hil_bcu_close(rb_hil_bcu *b)
{
    if (b) rb_udp_close(&b->udp);
}

/* What the BCU measures, rebuilt from a plant frame (no ED force is reported: 0). */
static void outputs_from_frame(const rb_plant_frame *f, rb_plant_outputs *o)
{
    memset(o, 0, sizeof *o);
    o->time = (double)f->header.step * RB_HIL_DT;
    o->speed = f->train_speed;
    o->position = f->position;
    o->main_reservoir = f->main_reservoir_pressure;
    for (int a = 0; a < f->header.n_axles; ++a) {
        o->wheel_speed[a] = o->wheel_speed_measured[a] = f->wheel_speed[a];
        o->cylinder[a] = f->cylinder_pressure[a];
    }
    for (int c = 0; c < f->header.n_cars; ++c) o->supply[c] = f->supply_pressure[c];
}

static void send_commands(const rb_bcu_params *p, rb_hil_bcu *b, const rb_brake_demand *d, uint64_t step)
{
    rb_bcu_frame f;
    size_t size = 0;
    const rb_plant_inputs *in = &b->state.command;
    int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    f.header.sequence = b->sequence++;
    f.header.step = step;
    f.header.n_cars = (uint8_t)p->n_cars;
    f.header.n_axles = (uint8_t)n_axles;
    f.brake_demand = d->emergency > 0.5 ? 2.0f : (float)d->service;
    for (int c = 0; c < p->n_cars; ++c) f.pressure_demand[c] = (float)in->pressure_demand[c];
    memcpy(f.hold, in->hold, (size_t)n_axles);
    memcpy(f.vent, in->vent, (size_t)n_axles);
    if (rb_bcu_frame_encode(&f, b->buffer, sizeof b->buffer, &size, NULL) == RB_OK &&
        rb_udp_send(&b->udp, b->buffer, size) == (long)size)
        b->sent++;
    else
        b->send_errors++;
}

/* One datagram: a valid plant frame of this train, newer than the last, runs the BCU. */
static void take_datagram(const rb_bcu_params *p, const rb_scenario *sc, rb_hil_bcu *b, long size,
                          const uint8_t from[16])
{
    rb_plant_frame f;
    if ((size_t)size > sizeof b->buffer || rb_plant_frame_decode(b->buffer, (size_t)size, &f, NULL) != RB_OK ||
        f.header.n_cars != p->n_cars || f.header.n_axles != p->n_cars * RB_AXLES_PER_CAR) {
        b->malformed++;
        return;
    }
    b->received++;
    if (b->have_frame && f.header.step <= b->last_step) {
        b->stale++;   /* duplicated or reordered: the BCU does not go back in time */
        return;
    }
    if (!b->have_frame) b->state.next_cycle = b->state.last_cycle = (double)f.header.step * RB_HIL_DT;
    b->have_frame = 1;
    b->last_step = f.header.step;
    b->last_frame_ns = rb_monotonic_ns();
    memcpy(b->udp.peer, from, sizeof b->udp.peer);   /* answer whoever sends the plant frames */
    b->udp.have_peer = 1;
    outputs_from_frame(&f, &b->out);
    rb_brake_demand d = rb_scenario_demand(sc, b->out.time);
    double next = b->state.next_cycle;
    rb_plant_inputs in;
    rb_bcu_step(p, &b->state, &d, &b->out, &in);
    if (b->state.next_cycle != next) {   /* a BCU cycle ran: send its commands */
        b->cycles++;
        send_commands(p, b, &d, f.header.step);
    }
}

static void drain(const rb_bcu_params *p, const rb_scenario *sc, rb_hil_bcu *b)
{
    for (int i = 0; i < RB_HIL_MAX_DATAGRAMS; ++i) {
        uint8_t from[16];
        long n = rb_udp_recv_from(&b->udp, b->buffer, sizeof b->buffer, from);
        if (n == 0) return;
        if (n < 0) b->malformed++;   /* an error or an empty datagram */
        else take_datagram(p, sc, b, n, from);
    }
}

static int over(const rb_hil_bcu *b, double duration, double idle_timeout, int64_t now)
{
    if (duration > 0.0 && (double)(now - b->start_ns) * 1e-9 >= duration) return 1;
    return b->have_frame && idle_timeout > 0.0 && (double)(now - b->last_frame_ns) * 1e-9 >= idle_timeout;
}

rb_status rb_hil_bcu_serve(const rb_bcu_params *bcu, const rb_scenario *scenario, rb_hil_bcu *b, double for_s,
                           double duration, double idle_timeout, int *finished, rb_error *err)
{
    rb_status s;
    if (!bcu || !scenario || !b) return rb_fail(err, RB_EINVAL, "bcu, scenario and server must not be NULL");
    if ((s = rb_check_range(err, "for_s", for_s, 0.0, 3600.0))) return s;
    int64_t until = rb_monotonic_ns() + (int64_t)(for_s * 1e9);
    for (;;) {
        int64_t now = rb_monotonic_ns();
        if ((b->finished = over(b, duration, idle_timeout, now))) break;
        int64_t left_ms = (until - now) / 1000000;
        struct pollfd pfd = {b->udp.fd, POLLIN, 0};
        if (poll(&pfd, 1, left_ms < 0 ? 0 : left_ms > 100 ? 100 : (int)left_ms) > 0) drain(bcu, scenario, b);
        if (rb_monotonic_ns() >= until) break;
    }
    if (finished) *finished = b->finished;
    return RB_OK;
}

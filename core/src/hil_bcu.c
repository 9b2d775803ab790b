/* The reference BCU server: the simulation's own BCU (rb_bcu_step, the scenario's demand profile)
 * driven by plant frames received over UDP, answering with BCU frames. A working peer for the HIL
 * runner, and the example a user replaces with a real unit. */
#define _POSIX_C_SOURCE 200809L
#include "railbrake/rb_hil.h"

#include <math.h>
#include <poll.h>
#include <string.h>

size_t rb_hil_bcu_size(void) { return sizeof(rb_hil_bcu); }

rb_status rb_hil_bcu_open(const rb_bcu_params *bcu, const rb_wsp_params *wsp, const rb_scenario *scenario,
                          uint32_t config, const uint8_t *secret, const uint8_t *cookie_secret, const char *host,
                          int port, rb_hil_bcu *b, rb_error *err)
{
    rb_status s;
    if (!b || !scenario) return rb_fail(err, RB_EINVAL, "server and scenario must not be NULL");
    if (!secret || !cookie_secret) return rb_fail(err, RB_EINVAL, "secret and cookie_secret must not be NULL");
    if (scenario->n_demand < 1 || scenario->n_demand > RB_MAX_DEMAND_STEPS)
        return rb_fail(err, RB_EINVAL, "n_demand = %d: must be in [1, %d]", scenario->n_demand, RB_MAX_DEMAND_STEPS);
    memset(b, 0, sizeof *b);
    b->udp.fd = -1;
    if (wsp) b->wsp = *wsp;
    else rb_wsp_default_params(&b->wsp);
    b->config = config;
    memcpy(b->secret, secret, RB_HIL_KEY_SIZE);
    memcpy(b->cookie_secret, cookie_secret, RB_HIL_KEY_SIZE);
    if ((s = rb_bcu_init(bcu, &b->wsp, &b->state, err))) return s;
    if ((s = rb_udp_open(&b->udp, host, port, err))) return s;
    b->start_ns = rb_monotonic_ns();
    return RB_OK;
}

int rb_hil_bcu_port(const rb_hil_bcu *b) { return rb_udp_local_port(&b->udp); }

void rb_hil_bcu_counters(const rb_hil_bcu *b, uint64_t counts[RB_HIL_BCU_COUNTERS])
{
    uint64_t c[RB_HIL_BCU_COUNTERS] = {b->received, b->malformed, b->stale, b->sent, b->send_errors, b->cycles,
                                       b->foreign, b->refused, b->forged, b->challenges};
    memcpy(counts, c, sizeof c);
}

int rb_hil_bcu_refusal(const rb_hil_bcu *b, uint32_t *config, int *cars, int *axles, char *from, size_t from_size)
{
    if (!b->refused) return 0;
    if (config) *config = b->refused_config;
    if (cars) *cars = b->refused_cars;
    if (axles) *axles = b->refused_axles;
    if (from && from_size) rb_udp_format(b->refused_from, from, from_size);
    return 1;
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
    f.header.session = b->session;
    f.header.config = b->config;
    f.header.sequence = b->sequence++;
    f.header.step = step;
    f.header.nonce = b->nonce;
    f.header.plant_nonce = b->plant_nonce;
    f.header.n_cars = (uint8_t)p->n_cars;
    f.header.n_axles = (uint8_t)n_axles;
    f.brake_demand = d->emergency > 0.5 ? 2.0f : (float)d->service;
    for (int c = 0; c < p->n_cars; ++c) f.pressure_demand[c] = (float)in->pressure_demand[c];
    memcpy(f.hold, in->hold, (size_t)n_axles);
    memcpy(f.vent, in->vent, (size_t)n_axles);
    if (rb_bcu_frame_encode(&f, b->key, b->buffer, sizeof b->buffer, &size, NULL) == RB_OK &&
        rb_udp_send(&b->udp, b->buffer, size) == (long)size)
        b->sent++;
    else
        b->send_errors++;
}

/* A plant of another configuration: counted, remembered (the first), and told at most every 0.1 s
 * with a frame that carries this BCU's digest and the plant's session (released commands). */
static void refuse(const rb_bcu_params *p, rb_hil_bcu *b, const rb_plant_frame *f, const uint8_t *hello_key,
                   const uint8_t from[16], int64_t now)
{
    if (!b->refused++) {
        b->refused_config = f->header.config;
        b->refused_cars = f->header.n_cars;
        b->refused_axles = f->header.n_axles;
        memcpy(b->refused_from, from, sizeof b->refused_from);
    }
    if (b->last_refusal_ns && now - b->last_refusal_ns < 100000000) return;
    b->last_refusal_ns = now;
    rb_bcu_frame r;
    size_t size = 0;
    memset(&r, 0, sizeof r);
    r.header.session = f->header.session;
    r.header.config = b->config;
    r.header.sequence = b->sequence++;
    r.header.step = f->header.step;
    r.header.plant_nonce = f->header.plant_nonce;
    r.header.n_cars = (uint8_t)p->n_cars;
    r.header.n_axles = (uint8_t)(p->n_cars * RB_AXLES_PER_CAR);
    for (int c = 0; c < p->n_cars; ++c) r.pressure_demand[c] = (float)p->atmosphere;
    if (rb_bcu_frame_encode(&r, hello_key, b->buffer, sizeof b->buffer, &size, NULL) == RB_OK &&
        rb_udp_send_to(&b->udp, from, b->buffer, size) == (long)size)
        b->sent++;
    else
        b->send_errors++;
}

/* The time slot a BCU nonce belongs to: a nonce is good in its slot and the next (one to two
 * RB_HIL_NONCE_LIFETIME), so a challenge delayed longer cannot open a session. */
static int64_t slot(int64_t now) { return now / (int64_t)(RB_HIL_NONCE_LIFETIME * 1e9); }

/* This BCU's nonce for the plant at `from` in `session` offering `plant_nonce`: a keyed hash
 * (SipHash-2-4 under the BCU's own random secret) of session, address, plant nonce, epoch and time
 * slot, never 0. Nothing is stored per plant. */
static uint64_t cookie(const rb_hil_bcu *b, uint32_t session, const uint8_t from[16], uint64_t plant_nonce,
                       int64_t time_slot)
{
    uint8_t input[4 + 16 + 8 + 8 + 8];
    for (int i = 0; i < 4; ++i) input[i] = (uint8_t)(session >> (8 * i));
    memcpy(input + 4, from, 16);
    for (int i = 0; i < 8; ++i) {
        input[20 + i] = (uint8_t)(plant_nonce >> (8 * i));
        input[28 + i] = (uint8_t)(b->epoch >> (8 * i));
        input[36 + i] = (uint8_t)((uint64_t)time_slot >> (8 * i));
    }
    uint64_t nonce = rb_siphash24(b->cookie_secret, input, sizeof input);
    return nonce ? nonce : 1u;
}

/* A hello: the challenge that gives the plant this BCU's nonce, echoing the plant's (under the hello key). */
static void challenge(const rb_bcu_params *p, rb_hil_bcu *b, const rb_frame_header *h, const uint8_t *hello_key,
                      const uint8_t from[16], int64_t now)
{
    rb_frame_header c = {h->session, b->config, 0, h->step, cookie(b, h->session, from, h->plant_nonce, slot(now)),
                         h->plant_nonce, (uint8_t)p->n_cars, (uint8_t)(p->n_cars * RB_AXLES_PER_CAR),
                         RB_FRAME_CHALLENGE};
    size_t size = 0;
    if (rb_challenge_frame_encode(&c, hello_key, b->buffer, sizeof b->buffer, &size, NULL) == RB_OK &&
        rb_udp_send_to(&b->udp, from, b->buffer, size) == (long)size)
        b->challenges++;
    else
        b->send_errors++;
}

/* The session key is agreed (the plant's first frame under the key of this BCU's nonce): a new plant
 * opens a session and the BCU starts afresh; the plant of the session (saying hello again after a
 * silence) keeps it. Frames are numbered from 0 under each key. */
static void open_session(const rb_bcu_params *p, rb_hil_bcu *b, const rb_frame_header *h, const uint8_t *key,
                         const uint8_t from[16])
{
    int same = b->session == h->session && rb_udp_same_address(from, b->udp.peer);
    if (b->session && !same) rb_bcu_init(p, &b->wsp, &b->state, NULL);   /* checked at open: cannot fail */
    if (!same) b->have_frame = 0;
    b->session = h->session;
    memcpy(b->udp.peer, from, sizeof b->udp.peer);
    b->udp.have_peer = 1;
    b->nonce = h->nonce;
    b->plant_nonce = h->plant_nonce;
    memcpy(b->key, key, RB_HIL_KEY_SIZE);
    b->epoch++;
    b->sequence = 0;
}

/* May the plant at `from` agree a session key now: the plant of the session, or any plant when
 * none is served or the session has been silent for RB_HIL_SESSION_IDLE s. */
static int may_open(const rb_hil_bcu *b, const rb_frame_header *h, const uint8_t from[16], int64_t now)
{
    if (!b->session || (double)(now - b->last_frame_ns) * 1e-9 >= RB_HIL_SESSION_IDLE) return 1;
    return h->session == b->session && rb_udp_same_address(from, b->udp.peer);
}

/* The key the frame must carry: the session's (both its nonces, from its plant), the hello key for
 * a hello (nonce 0 and a plant nonce), that of both nonces when the BCU's is the one it gives that
 * plant for that plant nonce now or in the slot before; 0 if none (an old handshake, another BCU's). */
static int key_for(const rb_hil_bcu *b, const rb_frame_header *h, const uint8_t from[16], int64_t now,
                   uint8_t key[RB_HIL_KEY_SIZE])
{
    if (b->session && h->session == b->session && h->nonce == b->nonce && h->plant_nonce == b->plant_nonce &&
        rb_udp_same_address(from, b->udp.peer)) {
        memcpy(key, b->key, RB_HIL_KEY_SIZE);
        return 1;
    }
    if (h->plant_nonce == 0) return 0;
    if (h->nonce == 0) {
        rb_hil_session_key(b->secret, h->session, 0, 0, key);
        return 1;
    }
    if (h->nonce != cookie(b, h->session, from, h->plant_nonce, slot(now)) &&
        h->nonce != cookie(b, h->session, from, h->plant_nonce, slot(now) - 1))
        return 0;
    rb_hil_session_key(b->secret, h->session, h->plant_nonce, h->nonce, key);
    return 1;
}

/* A frame of the session whose step runs far ahead of the wall time since the last is forged or
 * corrupt: not applied. */
static int step_jump(const rb_hil_bcu *b, const rb_frame_header *h, int64_t now)
{
    uint64_t ahead = RB_HIL_MAX_STEP_JUMP + (uint64_t)((now - b->last_frame_ns) / 1000000);
    return b->have_frame && h->step > b->last_step && h->step - b->last_step > ahead;
}

/* A frame under the session key, newer than the last, runs the BCU. */
static void serve_frame(const rb_bcu_params *p, const rb_scenario *sc, rb_hil_bcu *b, const rb_plant_frame *f,
                        int64_t now)
{
    b->received++;
    if (b->have_frame && f->header.step <= b->last_step) {
        b->stale++;   /* duplicated, reordered or replayed: the BCU does not go back in time, and a */
        return;       /* replay does not keep an idle session from another plant */
    }
    int first = !b->have_frame;
    if (first) b->state.next_cycle = b->state.last_cycle = (double)f->header.step * RB_HIL_DT;
    b->have_frame = 1;
    b->last_step = f->header.step;
    b->last_frame_ns = now;
    outputs_from_frame(f, &b->out);
    rb_brake_demand d = rb_scenario_demand(sc, b->out.time);
    double next = b->state.next_cycle;
    rb_plant_inputs in;
    rb_bcu_step(p, &b->state, &d, &b->out, &in);
    if (first) {   /* a cycle at once, then on the plant's grid of cycles from its step 0, as in MIL */
        double grid = ceil(b->out.time / p->cycle - 1e-9) * p->cycle;
        b->state.next_cycle = grid > b->out.time + 1e-9 ? grid : grid + p->cycle;
    }
    if (b->state.next_cycle != next) {   /* a BCU cycle ran: send its commands */
        b->cycles++;
        send_commands(p, b, &d, f->header.step);
    }
}

/* One datagram: its structure, its key (session, hello, or this BCU's nonce), its tag, its values,
 * then a hello is challenged, a plant of another configuration refused, the session's frames served. */
static void take_datagram(const rb_bcu_params *p, const rb_scenario *sc, rb_hil_bcu *b, long size,
                          const uint8_t from[16])
{
    rb_frame_header h;
    rb_plant_frame f;
    uint8_t key[RB_HIL_KEY_SIZE];
    int64_t now = rb_monotonic_ns();
    int from_peer = b->session && rb_udp_same_address(from, b->udp.peer);
    if ((size_t)size > sizeof b->buffer || rb_frame_check(b->buffer, (size_t)size, &h, NULL) != RB_OK ||
        h.type != RB_FRAME_PLANT) {
        if (b->session && !from_peer) b->foreign++;
        else b->malformed++;
        return;
    }
    if (!key_for(b, &h, from, now, key)) {
        b->foreign++;
        return;
    }
    if (!rb_frame_authentic(b->buffer, (size_t)size, key)) {
        b->forged++;
        return;
    }
    if (rb_plant_frame_decode(b->buffer, (size_t)size, &f, NULL) != RB_OK) {
        b->malformed++;
        return;
    }
    if (!b->first_datagram_ns) b->first_datagram_ns = now;   /* a plant frame: the idle clock runs */
    if (f.header.config != b->config || f.header.n_cars != p->n_cars ||
        f.header.n_axles != p->n_cars * RB_AXLES_PER_CAR) {
        if (b->session && !from_peer) b->foreign++;
        else if (h.nonce == 0) refuse(p, b, &f, key, from, now);
        else b->malformed++;
        return;
    }
    if (h.nonce == 0) {
        challenge(p, b, &h, key, from, now);
        return;
    }
    int current = b->session && h.session == b->session && h.nonce == b->nonce &&
                  h.plant_nonce == b->plant_nonce && from_peer;
    if (!current) {
        if (!may_open(b, &h, from, now)) {
            b->foreign++;
            return;
        }
        open_session(p, b, &h, key, from);
    } else if (step_jump(b, &h, now)) {
        b->foreign++;
        return;
    }
    serve_frame(p, sc, b, &f, now);
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

/* The idle clock runs from the last session frame, or from the first plant frame of any
 * configuration while no session frame came (a plant of another configuration does not keep the
 * BCU up forever; garbage does not start the clock). */
static int over(const rb_hil_bcu *b, double duration, double idle_timeout, int64_t now)
{
    if (duration > 0.0 && (double)(now - b->start_ns) * 1e-9 >= duration) return 1;
    int64_t since = b->have_frame ? b->last_frame_ns : b->first_datagram_ns;
    return since && idle_timeout > 0.0 && (double)(now - since) * 1e-9 >= idle_timeout;
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

/* The HIL plant runner: each 1 ms step reads every waiting BCU frame, lets the watchdog decide
 * between the newest valid commands and the safe state, steps the plant, sends the plant frame,
 * records decimated channels and sleeps until the next absolute deadline. */
#include "railbrake/rb_hil.h"
#include "railbrake/rb_bounds.h"
#include "channels_internal.h"
#include "run_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

size_t rb_hil_runner_size(void) { return sizeof(rb_hil_runner); }
size_t rb_hil_config_size(void) { return sizeof(rb_hil_config); }
size_t rb_hil_result_size(void) { return sizeof(rb_hil_result); }
size_t rb_hil_event_size(void) { return sizeof(rb_hil_event); }
size_t rb_hil_snapshot_size(void) { return sizeof(rb_hil_snapshot); }

/* ---- recorded channels */

enum { GLOBAL_CHANNELS = 8, CAR_CHANNELS = 2, AXLE_CHANNELS = 5 };
static const rb_channel_name global_names[GLOBAL_CHANNELS] = {
    {"time", "s"}, {"speed", "m/s"}, {"position", "m"}, {"deceleration", "m/s^2"},
    {"main_reservoir", "Pa"}, {"brake_demand", "1"}, {"safe_state", "1"}, {"bcu_frames", "1"}};
static const rb_channel_name car_names[CAR_CHANNELS] = {{"pressure_demand", "Pa"}, {"supply", "Pa"}};
static const rb_channel_name axle_names[AXLE_CHANNELS] = {
    {"wheel_speed", "m/s"}, {"slip", "1"}, {"cylinder", "Pa"}, {"hold", "1"}, {"vent", "1"}};

static const rb_channel_layout layout = {global_names, car_names, axle_names,
                                         GLOBAL_CHANNELS, CAR_CHANNELS, AXLE_CHANNELS};

int rb_hil_channel_count(int n_cars) { return rb_channel_count(&layout, n_cars); }

rb_status rb_hil_channel_info(int index, int n_cars, char *name, size_t name_size, char *unit,
                              size_t unit_size, rb_error *err)
{
    return rb_channel_info(&layout, index, n_cars, name, name_size, unit, unit_size, err);
}

static void record(const rb_plant_params *p, const rb_hil_runner *r, double *row)
{
    const rb_plant_outputs *o = &r->out;
    int n = p->n_cars, na = n * RB_AXLES_PER_CAR;
    double g[GLOBAL_CHANNELS] = {o->time, o->speed, o->position, o->deceleration, o->main_reservoir,
                                 r->applied_demand, (double)r->safe, (double)r->watchdog.received};
    memcpy(row, g, sizeof g);
    row += GLOBAL_CHANNELS;
    for (int c = 0; c < n; ++c) {
        row[c] = r->applied.pressure_demand[c];
        row[n + c] = o->supply[c];
    }
    row += CAR_CHANNELS * n;
    for (int a = 0; a < na; ++a) {
        row[a] = o->wheel_speed[a];
        row[na + a] = o->slip[a];
        row[2 * na + a] = o->cylinder[a];
        row[3 * na + a] = o->hold[a];
        row[4 * na + a] = o->vent[a];
    }
}

/* ---- safe state */

rb_status rb_hil_safe_bcu(const rb_bcu_params *bcu, rb_bcu_params *safe, rb_error *err)
{
    rb_status st;
    if (!bcu || !safe) return rb_fail(err, RB_EINVAL, "bcu and safe must not be NULL");
    if ((st = rb_bcu_check(bcu, err))) return st;
    *safe = *bcu;
    safe->wsp_enabled = 0;   /* nobody drives the WSP valves: de-energised */
    safe->wsp = NULL;
    safe->wsp_context = NULL;
    safe->ed_in_emergency = 0;   /* the electric brake is the BCU's too */
    safe->ed_in_service = 0;
    return RB_OK;
}

/* The BCU's emergency demand law on the plant's outputs, every BCU cycle (from entering the safe
 * state on); valves de-energised: hold = 0 passes air, vent = 0 stays shut. */
static void safe_commands(const rb_hil_config *c, rb_hil_runner *r, int entering)
{
    static const rb_brake_demand emergency = {1.0, 0.0};
    if (entering) r->safe_bcu.next_cycle = r->out.time;
    rb_bcu_step(&c->safe, &r->safe_bcu, &emergency, &r->out, &r->safe_in);
    memset(r->safe_in.ed_demand, 0, sizeof r->safe_in.ed_demand);
    memset(r->safe_in.hold, 0, sizeof r->safe_in.hold);
    memset(r->safe_in.vent, 0, sizeof r->safe_in.vent);
}

/* ---- opening */

static rb_status check_config(const rb_plant_params *plant, const rb_hil_config *c, rb_error *err)
{
    rb_status s;
    if (!c) return rb_fail(err, RB_EINVAL, "config must not be NULL");
    if (fabs(plant->dt - RB_HIL_DT) > 1e-12)
        return rb_fail(err, RB_EINVAL, "plant.dt = %g s: the HIL interface steps at %g s", plant->dt, RB_HIL_DT);
    if ((s = rb_check_range(err, "hold_time", c->hold_time, 0.0, 60.0))) return s;
    if ((s = rb_check_range(err, "late_time", c->late_time, 0.0, 60.0))) return s;
    if ((s = rb_check_range(err, "duration", c->duration, RB_HIL_DT, 86400.0))) return s;
    if ((s = rb_check_nonnegative(err, "stop_speed", c->stop_speed))) return s;
    if ((s = rb_check_range(err, "record_interval", c->record_interval, RB_HIL_DT, 60.0))) return s;
    if ((s = rb_check_range(err, "adhesion_interval", c->adhesion_interval, 0.0, 60.0))) return s;
    if ((s = rb_check_range(err, "chunk_time", c->chunk_time, 0.0, 60.0))) return s;
    if (c->session == 0) return rb_fail(err, RB_EINVAL, "session = 0: a run needs a non-zero session id");
    if ((s = rb_bcu_check(&c->safe, err))) return s;
    if (c->safe.n_cars != plant->n_cars)
        return rb_fail(err, RB_EINVAL, "safe.n_cars = %d: the plant has %d cars", c->safe.n_cars, plant->n_cars);
    if (c->safe.wsp_enabled || c->safe.wsp) return rb_fail(err, RB_EINVAL, "safe: WSP must be off (rb_hil_safe_bcu)");
    return RB_OK;
}

static uint64_t to_steps(double seconds) { return (uint64_t)llround(seconds / RB_HIL_DT); }

/* the shortest silence after which the plant says hello again, whatever its hold time: longer
 * than the slowest BCU cycle of the ICD (20 ms) many times over */
#define REHELLO_MIN_STEPS 100u

static void say_hello(const rb_hil_config *c, rb_hil_runner *r, uint64_t previous);

rb_status rb_hil_runner_open(const rb_plant_params *plant, const rb_hil_config *config, const char *bind_host,
                             int bind_port, const char *bcu_host, int bcu_port, rb_hil_runner *r, rb_error *err)
{
    rb_status s;
    if (!plant || !r) return rb_fail(err, RB_EINVAL, "plant and runner must not be NULL");
    if ((s = check_config(plant, config, err))) return s;
    memset(r, 0, sizeof *r);
    r->udp.fd = -1;
    if ((s = rb_plant_init(plant, &r->plant, err))) return s;
    if ((s = rb_plant_bounds_check(plant, err))) return s;
    if ((s = rb_udp_open(&r->udp, bind_host, bind_port, err))) return s;
    if ((s = rb_udp_set_peer(&r->udp, bcu_host, bcu_port, err))) {
        rb_udp_close(&r->udp);
        return s;
    }
    rb_watchdog_init(&r->watchdog, to_steps(config->hold_time));
    r->late_steps = to_steps(config->late_time);
    r->record_every = to_steps(config->record_interval);
    r->duration_steps = to_steps(config->duration);
    rb_plant_get_outputs(plant, &r->plant, &r->out);
    r->kpi.plant = r->plant;
    r->kpi.out = r->out;
    if ((s = rb_bcu_init(&config->safe, NULL, &r->safe_bcu, err))) {
        rb_udp_close(&r->udp);
        return s;
    }
    rb_hil_session_key(config->secret, config->session, 0, 0, r->hello_key);
    r->rehello_steps = r->watchdog.hold_steps > REHELLO_MIN_STEPS ? r->watchdog.hold_steps : REHELLO_MIN_STEPS;
    r->nonce_steps = to_steps(RB_HIL_NONCE_LIFETIME);
    say_hello(config, r, 0);
    r->n_faults = plant->n_faults;
    memcpy(r->fault, plant->fault, sizeof r->fault);
    r->safe = 1;   /* until the first valid frame */
    safe_commands(config, r, 1);
    r->applied = r->safe_in;
    r->applied_demand = 2.0f;
    return RB_OK;
}

int rb_hil_runner_port(const rb_hil_runner *r) { return rb_udp_local_port(&r->udp); }

void rb_hil_runner_close(rb_hil_runner *r)
{
    if (r) rb_udp_close(&r->udp);
}

/* ---- the watchdog's log */

static void log_event(rb_hil_runner *r, int kind, const char *text)
{
    rb_hil_event *e = &r->log[r->events % RB_HIL_LOG_SIZE];
    e->step = r->step;
    e->kind = kind;
    size_t n = strlen(text) < sizeof e->text ? strlen(text) : sizeof e->text - 1;   /* truncates long messages */
    memcpy(e->text, text, n);
    e->text[n] = '\0';
    r->events++;
}

int rb_hil_runner_event(const rb_hil_runner *r, uint64_t index, rb_hil_event *event)
{
    if (index >= r->events || index + RB_HIL_LOG_SIZE < r->events) return 0;
    *event = r->log[index % RB_HIL_LOG_SIZE];
    return 1;
}

/* ---- faults changed while the plant runs: a mailbox the loop looks into once a step */

int rb_hil_runner_post_fault(rb_hil_runner *r, const rb_hil_fault_command *command)
{
    if (!r || !command || __atomic_load_n(&r->mailbox, __ATOMIC_ACQUIRE) != 0) return 0;
    r->command = *command;
    __atomic_store_n(&r->mailbox, 1, __ATOMIC_RELEASE);
    return 1;
}

int rb_hil_runner_fault_answer(rb_hil_runner *r, uint64_t *step, char *text, size_t text_size)
{
    if (!r || __atomic_load_n(&r->mailbox, __ATOMIC_ACQUIRE) != 2) return -1;
    int status = r->answer_status;
    if (step) *step = r->answer_step;
    if (text && text_size) snprintf(text, text_size, "%s", r->answer_text);
    __atomic_store_n(&r->mailbox, 0, __ATOMIC_RELEASE);
    return status;
}

static int same_place(const rb_fault *a, const rb_fault *b)
{
    return a->kind == b->kind && a->car == b->car && a->axle == b->axle;
}

static void describe_fault(const rb_fault *f, char *text, size_t size, const char *what)
{
    if (f->axle < 0)
        snprintf(text, size, "%s on car %d: %s", rb_fault_kind_name(f->kind), f->car + 1, what);
    else
        snprintf(text, size, "%s on car %d, axle %d: %s", rb_fault_kind_name(f->kind), f->car + 1, f->axle + 1, what);
}

static int inject_fault(rb_hil_runner *r, const rb_fault *f, char *text, size_t size)
{
    for (int i = 0; i < r->n_faults; ++i)
        if (same_place(&r->fault[i], f) && r->fault[i].start_time <= r->plant.time) {
            describe_fault(f, text, size, "already active, not injected again");
            return RB_EINVAL;
        }
    if (r->n_faults >= RB_MAX_FAULTS) {
        snprintf(text, size, "%d faults already: the plant holds at most %d", r->n_faults, RB_MAX_FAULTS);
        return RB_EINVAL;
    }
    r->fault[r->n_faults] = *f;
    r->fault[r->n_faults++].start_time = r->plant.time;   /* acts from this step on */
    describe_fault(f, text, size, "injected");
    return RB_OK;
}

static int clear_fault(rb_hil_runner *r, const rb_fault *f, char *text, size_t size)
{
    int kept = 0;
    for (int i = 0; i < r->n_faults; ++i)
        if (!same_place(&r->fault[i], f)) r->fault[kept++] = r->fault[i];
    if (kept == r->n_faults) {
        describe_fault(f, text, size, "not present, nothing cleared");
        return RB_EINVAL;
    }
    r->n_faults = kept;
    describe_fault(f, text, size, "cleared");
    return RB_OK;
}

/* Applies a posted change before the step's plant update; p: the runner's own parameters. */
static void take_fault_command(rb_plant_params *p, rb_hil_runner *r)
{
    if (__atomic_load_n(&r->mailbox, __ATOMIC_ACQUIRE) != 1) return;
    const rb_hil_fault_command *c = &r->command;
    rb_error err;
    rb_fault f = c->fault;
    f.start_time = 0.0;
    int status;
    if (rb_fault_check(&f, p->n_cars, "fault", &err)) {
        snprintf(r->answer_text, sizeof r->answer_text, "%s", err.message);
        status = RB_EINVAL;
    } else if (c->action == RB_HIL_FAULT_INJECT) {
        status = inject_fault(r, &f, r->answer_text, sizeof r->answer_text);
    } else if (c->action == RB_HIL_FAULT_CLEAR) {
        status = clear_fault(r, &f, r->answer_text, sizeof r->answer_text);
    } else {
        snprintf(r->answer_text, sizeof r->answer_text, "action = %d: must be %d (inject) or %d (clear)", c->action,
                 RB_HIL_FAULT_INJECT, RB_HIL_FAULT_CLEAR);
        status = RB_EINVAL;
    }
    if (status == RB_OK) {
        p->n_faults = r->n_faults;
        memcpy(p->fault, r->fault, sizeof p->fault);
        log_event(r, c->action == RB_HIL_FAULT_INJECT ? RB_HIL_EVENT_FAULT_ON : RB_HIL_EVENT_FAULT_OFF,
                  r->answer_text);
    }
    r->answer_status = status;
    r->answer_step = r->step;
    __atomic_store_n(&r->mailbox, 2, __ATOMIC_RELEASE);
}

/* ---- the live view: a seqlock the loop writes after each step */

static void write_snapshot(const rb_plant_params *p, rb_hil_runner *r)
{
    rb_hil_snapshot *v = &r->snapshot;
    const rb_plant_outputs *o = &r->out;
    int n = p->n_cars, na = n * RB_AXLES_PER_CAR;
    __atomic_store_n(&r->snapshot_sequence, r->snapshot_sequence + 1, __ATOMIC_RELAXED);   /* odd: writing */
    __atomic_thread_fence(__ATOMIC_RELEASE);
    v->step = r->step;
    v->time = o->time; v->speed = o->speed; v->position = o->position; v->main_reservoir = o->main_reservoir;
    v->brake_demand = r->applied_demand;
    v->safe = r->safe; v->n_cars = n; v->n_axles = na;
    v->received = r->watchdog.received; v->lost = r->watchdog.lost; v->late = r->watchdog.late;
    v->malformed = r->watchdog.malformed; v->foreign = r->foreign; v->forged = r->forged;
    v->overruns = r->pacer.overruns;
    memcpy(v->supply, o->supply, (size_t)n * sizeof *v->supply);
    memcpy(v->pressure_demand, r->applied.pressure_demand, (size_t)n * sizeof *v->pressure_demand);
    memcpy(v->wheel_speed, o->wheel_speed, (size_t)na * sizeof *v->wheel_speed);
    memcpy(v->slip, o->slip, (size_t)na * sizeof *v->slip);
    memcpy(v->cylinder, o->cylinder, (size_t)na * sizeof *v->cylinder);
    for (int a = 0; a < na; ++a) { v->hold[a] = (uint8_t)(o->hold[a] != 0); v->vent[a] = (uint8_t)(o->vent[a] != 0); }
    __atomic_store_n(&r->snapshot_sequence, r->snapshot_sequence + 1, __ATOMIC_RELEASE);   /* even: done */
}

int rb_hil_runner_snapshot(const rb_hil_runner *r, rb_hil_snapshot *out, int tries)
{
    if (!r || !out) return 0;
    for (int i = 0; i < tries; ++i) {
        uint32_t before = __atomic_load_n(&r->snapshot_sequence, __ATOMIC_ACQUIRE);
        if (before & 1u) continue;
        memcpy(out, &r->snapshot, sizeof *out);
        __atomic_thread_fence(__ATOMIC_ACQUIRE);
        if (__atomic_load_n(&r->snapshot_sequence, __ATOMIC_RELAXED) == before) return 1;
    }
    return 0;
}

/* ---- one step */

static void malformed(rb_hil_runner *r, const char *why)
{
    rb_watchdog_malformed(&r->watchdog);
    log_event(r, RB_HIL_EVENT_MALFORMED, why);
}

/* Decodes a datagram into f; returns 1 and the reason in text when it is malformed for this plant. */
static int frame_problem(const rb_plant_params *p, const rb_hil_runner *r, long size, rb_bcu_frame *f,
                         char *text, size_t capacity)
{
    rb_error err;
    int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    if (rb_bcu_frame_decode(r->buffer, (size_t)size, f, &err))
        snprintf(text, capacity, "%.*s", (int)capacity - 1, err.message);
    else if (f->header.n_cars != p->n_cars || f->header.n_axles != n_axles)
        snprintf(text, capacity, "n_cars = %d, n_axles = %d: the plant has %d cars and %d axles",
                 f->header.n_cars, f->header.n_axles, p->n_cars, n_axles);
    else if (f->header.step > r->step)
        snprintf(text, capacity, "step = %llu: echoes a plant step not sent yet (last %llu)",
                 (unsigned long long)f->header.step, (unsigned long long)r->step);
    else
        return 0;
    return 1;
}

/* A datagram not from the BCU's address and this run's session: counted as foreign, the first one
 * logged; it touches no other counter and no command. */
static void foreign(rb_hil_runner *r, const uint8_t from[16], const char *why)
{
    if (!r->foreign++) {
        char text[2 * RB_HIL_LOG_TEXT], address[24];
        rb_udp_format(from, address, sizeof address);
        snprintf(text, sizeof text, "datagram from %.23s %.40s: ignored, further ones only counted", address, why);
        log_event(r, RB_HIL_EVENT_FOREIGN, text);
    }
}

/* A frame of this session whose tag does not authenticate (no key, or a key it does not hold). */
static void forged(rb_hil_runner *r, const rb_frame_header *h)
{
    if (!r->forged++) {
        char text[RB_HIL_LOG_TEXT];
        snprintf(text, sizeof text, "type %u sequence %u nonce 0x%016llx: tag does not authenticate, "
                 "ignored, further ones only counted", h->type, h->sequence, (unsigned long long)h->nonce);
        log_event(r, RB_HIL_EVENT_FORGED, text);
    }
}

/* The BCU answers in this session for another configuration: it refuses this plant; the run ends. */
static void mismatch(rb_hil_runner *r, const rb_hil_config *c, const rb_frame_header *h)
{
    char text[RB_HIL_LOG_TEXT];
    r->mismatch = 1;
    r->bcu_config = h->config;
    r->bcu_cars = h->n_cars;
    r->bcu_axles = h->n_axles;
    r->finished = 1;
    snprintf(text, sizeof text, "the BCU is set up for configuration 0x%08x (%d cars, %d axles), the plant runs "
             "0x%08x: run ended", (unsigned)h->config, h->n_cars, h->n_axles, (unsigned)c->config);
    log_event(r, RB_HIL_EVENT_MISMATCH, text);
}

/* Begins a round of hellos with a fresh plant nonce (the one before stays good for a challenge on
 * its way: a nonce lives one to two RB_HIL_NONCE_LIFETIME). The session key stays good meanwhile. */
static void say_hello(const rb_hil_config *c, rb_hil_runner *r, uint64_t previous)
{
    r->nonce = 0;
    r->previous_hello_nonce = previous;
    r->hello_nonce = rb_hil_plant_nonce(c->secret, c->session, ++r->hellos);
    r->hello_step = r->step;
}

/* Before each step's frame: a plant that has had no valid BCU frame for the hold time (at least
 * 0.1 s) since the key was agreed says hello again, whatever the reason (a lost link, a BCU that
 * restarted, a key the BCU no longer holds); a round of hellos renews its nonce each lifetime. */
static void keep_handshake(const rb_hil_config *c, rb_hil_runner *r)
{
    if (r->nonce) {
        uint64_t since = r->keyed_step;
        if (r->watchdog.have_valid && r->watchdog.last_valid_step > since) since = r->watchdog.last_valid_step;
        if (r->step >= since + r->rehello_steps) say_hello(c, r, 0);
    } else if (r->step >= r->hello_step + r->nonce_steps) {
        say_hello(c, r, r->hello_nonce);
    }
}

/* The BCU's challenge: while saying hello, one that echoes a hello nonce the plant offers gives the
 * session key of both nonces (the BCU numbers its frames from 0 under it); any other (a replayed or
 * delayed challenge of an earlier exchange) is refused. Once agreed, the hello nonces are retired. */
static void take_challenge(const rb_hil_config *c, rb_hil_runner *r, const rb_frame_header *h)
{
    char text[RB_HIL_LOG_TEXT];
    r->challenges++;
    if (r->nonce && h->plant_nonce == r->key_plant_nonce) return;   /* more answers to the hellos just keyed */
    int offered = h->plant_nonce && (h->plant_nonce == r->hello_nonce || h->plant_nonce == r->previous_hello_nonce);
    if (r->nonce || h->nonce == 0 || !offered) {
        if (!r->challenges_refused++) {
            snprintf(text, sizeof text, "challenge for plant nonce 0x%016llx: not a hello on offer, refused "
                     "(further ones only counted)", (unsigned long long)h->plant_nonce);
            log_event(r, RB_HIL_EVENT_KEYED, text);
        }
        return;
    }
    r->nonce = r->key_nonce = h->nonce;
    r->key_plant_nonce = h->plant_nonce;
    r->hello_nonce = r->previous_hello_nonce = 0;
    r->keyed_step = r->step;
    rb_hil_session_key(c->secret, c->session, r->key_plant_nonce, r->key_nonce, r->key);
    rb_watchdog_rekey(&r->watchdog);
    snprintf(text, sizeof text, "BCU nonce 0x%016llx, plant nonce 0x%016llx: session key agreed",
             (unsigned long long)r->key_nonce, (unsigned long long)r->key_plant_nonce);
    log_event(r, RB_HIL_EVENT_KEYED, text);
}

/* The key a BCU frame of this session must carry: the hello key for challenges and refusals, the
 * session key for commands under both its nonces (also while saying hello again); NULL otherwise. */
static const uint8_t *key_for(const rb_hil_runner *r, const rb_frame_header *h)
{
    if (h->type == RB_FRAME_CHALLENGE || h->nonce == 0) return r->hello_key;
    return r->key_nonce && h->nonce == r->key_nonce && h->plant_nonce == r->key_plant_nonce ? r->key : NULL;
}

static const char *const outcome_text[] = {"applied", "late", "out of order: older than the newest, not applied",
                                           "duplicate: received before, not applied",
                                           "replayed: older than the replay window, not applied"};

/* An authenticated command frame in the BCU's sequence: applied only when newer than every other
 * and on time. */
static void take_commands(const rb_plant_params *p, rb_hil_runner *r, const rb_bcu_frame *f)
{
    char text[RB_HIL_LOG_TEXT];
    rb_watchdog *w = &r->watchdog;
    uint64_t lost = w->lost, misordered = w->duplicate + w->out_of_order + w->replayed;
    int outcome = rb_watchdog_frame(w, f->header.sequence, f->header.step, r->step, r->late_steps);
    if (w->lost > lost) {
        snprintf(text, sizeof text, "%llu BCU frame(s) lost before sequence %u",
                 (unsigned long long)(w->lost - lost), f->header.sequence);
        log_event(r, RB_HIL_EVENT_LOST, text);
    }
    if (outcome == RB_SEQ_LATE) {
        snprintf(text, sizeof text, "sequence %u echoes step %llu: %llu ms old, not applied", f->header.sequence,
                 (unsigned long long)f->header.step, (unsigned long long)(r->step - f->header.step));
        log_event(r, RB_HIL_EVENT_LATE, text);
    } else if (outcome != RB_SEQ_APPLY && misordered == 0) {
        snprintf(text, sizeof text, "sequence %u: %s (further ones only counted)", f->header.sequence,
                 outcome_text[outcome]);
        log_event(r, RB_HIL_EVENT_ORDER, text);
    }
    if (outcome != RB_SEQ_APPLY) return;
    int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    r->had_valid = 1;
    r->last_demand = f->brake_demand;
    memset(&r->last, 0, sizeof r->last);
    for (int k = 0; k < p->n_cars; ++k) r->last.pressure_demand[k] = f->pressure_demand[k];
    r->last.emergency = f->brake_demand > 1.0f ? 1.0 : 0.0;   /* above 1: emergency, the BCU opens the loop */
    memcpy(r->last.hold, f->hold, (size_t)n_axles);
    memcpy(r->last.vent, f->vent, (size_t)n_axles);
}

/* One datagram: where from, its structure, its session, its tag, then what it says. Each check
 * that fails counts it once (foreign, malformed, forged) and nothing of it applies. */
static void take_datagram(const rb_plant_params *p, const rb_hil_config *c, rb_hil_runner *r, long size,
                          const uint8_t from[16])
{
    rb_frame_header h;
    rb_bcu_frame f;
    rb_error err;
    char text[RB_HIL_LOG_TEXT];
    if (!rb_udp_same_address(from, r->udp.peer)) {
        foreign(r, from, "(not the BCU's address)");
        return;
    }
    if ((size_t)size > sizeof r->buffer) {
        snprintf(text, sizeof text, "size = %ld: larger than any frame", size);
        malformed(r, text);
        return;
    }
    if (rb_frame_check(r->buffer, (size_t)size, &h, &err)) {
        malformed(r, err.message);
        return;
    }
    if (h.type == RB_FRAME_PLANT) {
        malformed(r, "type = 1: a plant frame, expected 2 (BCU) or 3 (challenge)");
        return;
    }
    if (h.session != c->session) {
        foreign(r, from, "(another session)");
        return;
    }
    const uint8_t *key = key_for(r, &h);
    if (!key || !rb_frame_authentic(r->buffer, (size_t)size, key)) {
        forged(r, &h);
        return;
    }
    if (h.type == RB_FRAME_CHALLENGE) {
        take_challenge(c, r, &h);
    } else if (h.config != c->config) {
        mismatch(r, c, &h);
    } else if (h.nonce == 0) {
        malformed(r, "nonce = 0: commands come under the agreed session key");
    } else if (frame_problem(p, r, size, &f, text, sizeof text)) {
        malformed(r, text);
    } else {
        take_commands(p, r, &f);
    }
}

static void receive(const rb_plant_params *p, const rb_hil_config *c, rb_hil_runner *r)
{
    for (int i = 0; i < RB_HIL_MAX_DATAGRAMS && !r->mismatch; ++i) {
        uint8_t from[16];
        long n = rb_udp_recv_from(&r->udp, r->buffer, sizeof r->buffer, from);
        if (n == 0) return;
        r->datagrams++;
        if (n == RB_UDP_EMPTY) {
            if (rb_udp_same_address(from, r->udp.peer)) malformed(r, "size = 0: empty datagram");
            else foreign(r, from, "(not the BCU's address)");
        } else if (n < 0) {
            malformed(r, "receive error");
        } else {
            take_datagram(p, c, r, n, from);
        }
    }
}

/* The BCU is lost while the safe state applies after a valid frame came, or once the hold time
 * passed without one: counted, with what it cost (locks, distance) accumulated after each step. */
static void note_loss(rb_hil_runner *r, int safe)
{
    int lost = safe && (r->had_valid || r->step > r->watchdog.hold_steps);
    if (lost && !r->lost && !r->losses++) {
        r->lost_step = r->step;
        r->last_valid_step = r->had_valid ? r->watchdog.last_valid_step : 0;
    }
    r->lost = lost;
}

static void choose_commands(const rb_hil_config *c, rb_hil_runner *r)
{
    int safe = rb_watchdog_tick(&r->watchdog, r->step);
    if (safe != r->safe) {
        log_event(r, safe ? RB_HIL_EVENT_SAFE_ON : RB_HIL_EVENT_SAFE_OFF,
                  safe ? "no valid BCU frame within the hold time: safe state" : "valid BCU frames: safe state left");
    }
    note_loss(r, safe);
    if (safe) safe_commands(c, r, !r->safe);
    r->safe = safe;
    r->applied = safe ? r->safe_in : r->last;
    r->applied_demand = safe ? 2.0f : r->last_demand;
}

/* After the step: what the loss cost (rb_run_accumulate's lock definition). */
static void account_loss(const rb_plant_params *p, rb_hil_runner *r, double position_before)
{
    if (!r->lost) {
        r->lock_events_before = r->kpi.lock_events;
        return;
    }
    r->lost_steps++;
    r->lost_distance += r->out.position - position_before;
    r->lost_lock_events += r->kpi.lock_events - r->lock_events_before;
    r->lock_events_before = r->kpi.lock_events;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a)
        if (r->kpi.lock_time[a] > 0.0) r->lost_lock_time += p->dt;
}

static void send_frame(const rb_plant_params *p, const rb_hil_config *c, rb_hil_runner *r)
{
    rb_plant_frame f;
    size_t size = 0;
    const rb_plant_outputs *o = &r->out;
    int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    f.header.session = c->session;
    f.header.config = c->config;
    f.header.sequence = r->sequence++;
    f.header.step = r->step;
    f.header.nonce = r->nonce;
    f.header.plant_nonce = r->nonce ? r->key_plant_nonce : r->hello_nonce;
    f.header.n_cars = (uint8_t)p->n_cars;
    f.header.n_axles = (uint8_t)n_axles;
    f.train_speed = (float)o->speed;
    f.position = (float)o->position;
    f.main_reservoir_pressure = (float)o->main_reservoir;
    for (int a = 0; a < n_axles; ++a) {
        f.wheel_speed[a] = (float)o->wheel_speed_measured[a];
        f.cylinder_pressure[a] = (float)o->cylinder[a];
    }
    for (int k = 0; k < p->n_cars; ++k) f.supply_pressure[k] = (float)o->supply[k];
    if (rb_plant_frame_encode(&f, r->nonce ? r->key : r->hello_key, r->buffer, sizeof r->buffer, &size, NULL) == RB_OK &&
        rb_udp_send(&r->udp, r->buffer, size) == (long)size)
        r->frames_sent++;
    else
        r->send_errors++;
}

static int braking_applied(const rb_plant_params *p, const rb_plant_inputs *in, double atmosphere)
{
    for (int c = 0; c < p->n_cars; ++c)
        if (in->pressure_demand[c] > atmosphere + 1e3) return 1;
    return 0;
}

/* Braking begins with the first step whose commands apply pressure (as in rb_run: from the
 * outputs before that step). */
static void check_braking(const rb_plant_params *p, rb_hil_runner *r)
{
    if (r->braking || !braking_applied(p, &r->applied, p->atmosphere)) return;
    r->braking = 1;
    r->brake_time = r->out.time;
    r->brake_position = r->out.position;
    r->kpi.braking = 1;
    r->kpi.brake_time = r->out.time;
    r->kpi.brake_position = r->out.position;
    r->kpi.brake_speed = r->out.speed;
    r->kpi.out = r->out;
    rb_run_start_kpis(p, &r->kpi);
    r->next_peak = r->out.time;
}

/* The available peak adhesion for adhesion_utilisation, sampled as rb_run_accumulate samples it
 * (every adhesion_interval above 10 km/h, the mean over the axles of cars not isolated) but one
 * axle per step: a whole sweep costs about 40 us per axle, more than the 1 ms step for 16 cars. */
#define PEAK_SPEED (10.0 / 3.6)   /* m/s, as LOCK_SPEED in run.c */

static void sample_peak_adhesion(const rb_plant_params *p, const rb_hil_config *c, rb_hil_runner *r)
{
    int n = p->n_cars * RB_AXLES_PER_CAR, a = r->peak_axle;
    if (a == 0 && (r->out.time < r->next_peak - 1e-9 || r->out.speed <= PEAK_SPEED)) return;
    if (!rb_run_car_isolated(p, a / RB_AXLES_PER_CAR)) {
        r->peak_sum += rb_plant_peak_adhesion(p, &r->plant, a);
        r->peak_count++;
    }
    if (++r->peak_axle < n) return;
    if (r->peak_count > 0) {
        r->kpi.peak_sum += r->peak_sum / r->peak_count;
        r->kpi.peak_samples++;
    }
    r->peak_axle = r->peak_count = 0;
    r->peak_sum = 0.0;
    r->next_peak += c->adhesion_interval;
}

/* The MIL run's KPI accumulation (rb_run_accumulate) on this loop's plant after each braking step;
 * it reads the plant state (forces, air masses): a copy, 8 kB for 8 cars, with the accumulation
 * 0.7 us a step. Its own peak-adhesion sampling is off (next_adhesion infinite): see above. */
static void accumulate_kpis(const rb_plant_params *p, const rb_hil_config *c, rb_hil_runner *r)
{
    rb_scenario sc;
    if (!r->braking) return;
    memset(&sc, 0, sizeof sc);
    sc.adhesion_interval = c->adhesion_interval;
    r->kpi.plant = r->plant;
    r->kpi.out = r->out;
    r->kpi.in = r->applied;   /* the BCU's commands in force: the cylinder demand */
    r->kpi.stopped = r->stopped;
    r->kpi.next_adhesion = HUGE_VAL;
    rb_run_accumulate(p, &sc, &r->kpi);
    sample_peak_adhesion(p, c, r);
}

void rb_hil_runner_kpis(const rb_plant_params *plant, const rb_hil_runner *r, rb_kpis *k)
{
    rb_run_kpis(plant, &r->kpi, k);
}

static void check_stop(const rb_hil_config *c, rb_hil_runner *r)
{
    r->stopped = r->braking && r->out.speed <= c->stop_speed;
    if (r->stopped || r->step >= r->duration_steps) r->finished = 1;
}

/* Writes a row when one is due (the loop stops before a step once the caller's array is full). */
static void record_due(const rb_plant_params *p, rb_hil_runner *r, double *series, size_t max_rows, size_t *rows)
{
    if (!series || *rows >= max_rows || (r->step % r->record_every != 0 && !r->finished)) return;
    record(p, r, series + *rows * (size_t)rb_hil_channel_count(p->n_cars));
    (*rows)++;
}

rb_status rb_hil_runner_advance(const rb_plant_params *plant, const rb_hil_config *config, rb_hil_runner *r,
                                uint64_t steps, double *series, size_t max_rows, size_t *rows, int *finished,
                                rb_error *err)
{
    rb_status s;
    size_t written = 0;
    if (!plant || !config || !r) return rb_fail(err, RB_EINVAL, "plant, config and runner must not be NULL");
    if (series && max_rows < 1) return rb_fail(err, RB_ESIZE, "max_rows = %zu: must be >= 1", max_rows);
    rb_plant_params *p = &r->params;   /* the caller's, with this run's faults */
    *p = *plant;
    p->n_faults = r->n_faults;
    memcpy(p->fault, r->fault, sizeof p->fault);
    if (!r->started) {
        if (config->paced && (s = rb_pacer_start(&r->pacer, (int64_t)(RB_HIL_DT * 1e9), err))) return s;
        r->started = 1;
        send_frame(p, config, r);
        record_due(p, r, series, max_rows, &written);
        if (config->paced) rb_pacer_wait(&r->pacer);
    }
    int64_t call_start = rb_monotonic_ns();
    for (uint64_t i = 0; i < steps && !r->finished; ++i) {
        if (series && written >= max_rows) break;
        if (config->chunk_time > 0.0 && (double)(rb_monotonic_ns() - call_start) * 1e-9 >= config->chunk_time) break;
        take_fault_command(p, r);
        receive(p, config, r);       /* frames echo at most r->step, the last step sent */
        if (r->mismatch) break;      /* the BCU refuses this plant: nothing to wait for */
        choose_commands(config, r);
        keep_handshake(config, r);
        check_braking(p, r);
        double position = r->out.position;
        rb_plant_step(p, &r->plant, &r->applied);
        r->step++;
        rb_plant_get_outputs(p, &r->plant, &r->out);
        check_stop(config, r);
        accumulate_kpis(p, config, r);
        account_loss(p, r, position);
        if (!r->finished) send_frame(p, config, r);
        record_due(p, r, series, max_rows, &written);
        write_snapshot(p, r);
        if (config->paced && !r->finished) rb_pacer_wait(&r->pacer);
    }
    if (rows) *rows = written;
    if (finished) *finished = r->finished;
    return RB_OK;
}

void rb_hil_runner_result(const rb_hil_runner *r, rb_hil_result *res)
{
    const rb_watchdog *w = &r->watchdog;
    memset(res, 0, sizeof *res);
    res->steps = r->step;
    res->frames_sent = r->frames_sent;
    res->send_errors = r->send_errors;
    res->datagrams = r->datagrams;
    res->received = w->received;
    res->lost = w->lost;
    res->late = w->late;
    res->malformed = w->malformed;
    res->safe_state_steps = w->safe_state_steps;
    res->overruns = r->pacer.overruns;
    res->wakeup_p50_us = rb_latency_quantile(&r->pacer.wakeup, 0.5);
    res->wakeup_p99_us = rb_latency_quantile(&r->pacer.wakeup, 0.99);
    res->wakeup_max_us = r->pacer.wakeup.max_us;
    res->wakeup_mean_us = rb_latency_mean(&r->pacer.wakeup);
    res->work_mean_us = rb_latency_mean(&r->pacer.work);
    res->work_p99_us = rb_latency_quantile(&r->pacer.work, 0.99);
    res->work_max_us = r->pacer.work.max_us;
    res->time = r->out.time;
    res->braking = r->braking;
    if (r->braking) {
        res->stopping_distance = r->out.position - r->brake_position;
        res->stopping_time = r->out.time - r->brake_time;
    }
    res->stopped = r->stopped;
    res->finished = r->finished;
    res->events = r->events;
    res->foreign = r->foreign;
    res->forged = r->forged;
    res->duplicate = w->duplicate;
    res->out_of_order = w->out_of_order;
    res->replayed = w->replayed;
    res->challenges = r->challenges;
    res->stale_challenges = r->challenges_refused;
    res->hellos = r->hellos;
    res->losses = r->losses;
    res->lost_step = r->lost_step;
    res->last_valid_step = r->last_valid_step;
    res->lost_steps = r->lost_steps;
    res->lost_lock_events = r->lost_lock_events;
    res->lost_lock_time = r->lost_lock_time;
    res->lost_distance = r->lost_distance;
    res->mismatch = r->mismatch;
    res->bcu_config = r->bcu_config;
    res->bcu_cars = r->bcu_cars;
    res->bcu_axles = r->bcu_axles;
}

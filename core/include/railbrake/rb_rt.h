/* Real-time support for the hardware-in-the-loop runner (POSIX): an absolute-deadline pacer with
 * latency statistics, a watchdog on the BCU link, and non-blocking UDP endpoints.
 * None of this runs inside a plant step; all state lives in caller-owned structs. */
#ifndef RAILBRAKE_RT_H
#define RAILBRAKE_RT_H

#include <stdint.h>

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Latency histogram: 1 us bins up to RB_RT_HIST_US, larger values in the last bin (max kept exactly). */
#define RB_RT_HIST_US 20000

typedef struct {
    uint64_t count;
    double sum_us;
    double max_us;
    uint32_t bins[RB_RT_HIST_US + 1];
} rb_latency_stats;

void rb_latency_reset(rb_latency_stats *s);
void rb_latency_add(rb_latency_stats *s, double us);
/* q in [0, 1]: the smallest bin edge below which a fraction q of the samples lie, in us. */
double rb_latency_quantile(const rb_latency_stats *s, double q);
double rb_latency_mean(const rb_latency_stats *s);

typedef struct {
    int64_t period_ns;
    int64_t next_deadline_ns;   /* CLOCK_MONOTONIC */
    uint64_t overruns;          /* periods whose work ended after the next deadline */
    rb_latency_stats wakeup;    /* wake-up time minus deadline */
    rb_latency_stats work;      /* time from wake-up to the end of the period's work */
    int64_t woke_ns;
} rb_pacer;

int64_t rb_monotonic_ns(void);
rb_status rb_pacer_start(rb_pacer *p, int64_t period_ns, rb_error *err);
/* Marks the end of this period's work, sleeps until the next absolute deadline, records latency.
 * Returns 1 if the work overran the deadline (the pacer then skips to the next future deadline). */
int rb_pacer_wait(rb_pacer *p);

/* What the system granted: bit 0 locked memory (mlockall), bit 1 real-time priority (SCHED_FIFO). */
#define RB_RT_MEMORY_LOCKED 1
#define RB_RT_FIFO_PRIORITY 2
int rb_rt_request(int priority);

/* Watchdog on the BCU link: commands are held for hold_steps after the last valid frame, then the
 * safe state applies until valid frames come back. It also places each authenticated frame in the
 * BCU's sequence (numbered from 0 per session key) with a window of the last RB_RT_WINDOW numbers
 * (as the anti-replay window of RFC 4303, section 3.4.3), so that received + lost is exactly the
 * count of frames sent up to the newest received, whatever the network duplicates or reorders. */
#define RB_RT_WINDOW 64

typedef enum {
    RB_SEQ_APPLY = 0,      /* newer than any before, on time: its commands apply */
    RB_SEQ_LATE,           /* newer than any before, echoing an old plant step: received, not applied */
    RB_SEQ_OUT_OF_ORDER,   /* older than the newest, not seen before: received (no longer lost), not applied */
    RB_SEQ_DUPLICATE,      /* seen before (within the window): not received again, not applied */
    RB_SEQ_REPLAYED        /* older than the window, or than the session key: cannot be new, not applied */
} rb_seq_outcome;

typedef struct {
    uint64_t hold_steps;
    uint64_t last_valid_step;
    int have_valid;
    int have_sequence;          /* a frame under the current session key came */
    uint64_t highest;           /* newest sequence number (extended past 32 bits) */
    uint64_t window;            /* bit i: sequence highest - i was received */
    uint64_t received, lost, late, malformed, safe_state_steps;
    uint64_t duplicate, out_of_order, replayed;
    int safe;
} rb_watchdog;

void rb_watchdog_init(rb_watchdog *w, uint64_t hold_steps);
/* A new session key: the BCU numbers its frames from 0 again (the counters go on). */
void rb_watchdog_rekey(rb_watchdog *w);
/* An authenticated, valid frame: sequence, the plant step it echoes, the current step, and the
 * lateness limit in steps. Returns what to do with it (rb_seq_outcome) and counts it. */
int rb_watchdog_frame(rb_watchdog *w, uint32_t sequence, uint64_t echoed_step, uint64_t step,
                      uint64_t late_steps);
void rb_watchdog_malformed(rb_watchdog *w);
/* Called once per step; returns 1 while the safe state must apply. */
int rb_watchdog_tick(rb_watchdog *w, uint64_t step);

/* UDP endpoint, non-blocking. host is a numeric IPv4 address. */
typedef struct {
    int fd;
    uint8_t peer[16];   /* struct sockaddr_in of the peer, when known */
    int have_peer;
} rb_udp;

rb_status rb_udp_open(rb_udp *u, const char *bind_host, int bind_port, rb_error *err);
rb_status rb_udp_set_peer(rb_udp *u, const char *host, int port, rb_error *err);
/* Local port actually bound (useful with port 0). */
int rb_udp_local_port(const rb_udp *u);
/* Returns bytes sent, or -1. */
long rb_udp_send(rb_udp *u, const uint8_t *data, size_t size);
/* Returns bytes received (0 if none waiting), or -1 on error; learns the peer if it has none. */
long rb_udp_recv(rb_udp *u, uint8_t *buf, size_t capacity);
/* As rb_udp_recv, without learning the peer: the sender's struct sockaddr_in goes to from. An empty
 * datagram returns RB_UDP_EMPTY (0 means nothing is waiting). */
#define RB_UDP_EMPTY (-2)
long rb_udp_recv_from(rb_udp *u, uint8_t *buf, size_t capacity, uint8_t from[16]);
/* 1 when two struct sockaddr_in (as rb_udp_recv_from gives them) name the same IPv4 address and port. */
int rb_udp_same_address(const uint8_t a[16], const uint8_t b[16]);
/* "a.b.c.d:port" of a struct sockaddr_in. */
void rb_udp_format(const uint8_t address[16], char *text, size_t size);
/* Sends to `to` (a struct sockaddr_in) instead of the peer. */
long rb_udp_send_to(rb_udp *u, const uint8_t to[16], const uint8_t *data, size_t size);
void rb_udp_close(rb_udp *u);

#ifdef __cplusplus
}
#endif
#endif

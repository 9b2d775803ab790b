/* Hardware-in-the-loop: the plant paced at 1 kHz on the wall clock exchanging frames
 * (rb_hil_frame.h, docs/hil-interface.md) with an external brake control unit over UDP, and the
 * reference BCU server that closes the loop in software with the same rb_bcu_step logic.
 *
 * Both run whole loops in C; the caller calls them in chunks (for progress and Ctrl-C) while all
 * state, including the pacer's absolute deadlines, lives in caller-owned structs. Guide: docs/hil.md. */
#ifndef RAILBRAKE_HIL_H
#define RAILBRAKE_HIL_H

#include <stdint.h>

#include "railbrake/rb_bcu.h"
#include "railbrake/rb_hil_frame.h"
#include "railbrake/rb_plant.h"
#include "railbrake/rb_rt.h"
#include "railbrake/rb_run.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_HIL_DT 1e-3                 /* s: the plant step, fixed by the interface (step = 1 ms) */
#define RB_HIL_MAX_DATAGRAMS 1024      /* datagrams read per step at most (a flood cannot stall the loop) */
#define RB_HIL_LOG_SIZE 32             /* watchdog events kept (the latest) */
#define RB_HIL_LOG_TEXT 120

/* ---- the plant runner */

/* What a live view shows of the running loop (rb_hil_runner_snapshot): written by the loop after
 * every step under a sequence counter (a seqlock: the loop never waits, a reader retries). */
typedef struct {
    uint64_t step;
    double time, speed, position, main_reservoir;   /* s, m/s, m, Pa */
    double brake_demand;                            /* applied (2: the safe state's) */
    int safe, n_cars, n_axles;
    uint64_t received, lost, late, malformed, foreign, forged, overruns;
    double supply[RB_PLANT_MAX_CARS], pressure_demand[RB_PLANT_MAX_CARS];                /* Pa */
    double wheel_speed[RB_PLANT_MAX_AXLES], slip[RB_PLANT_MAX_AXLES], cylinder[RB_PLANT_MAX_AXLES];
    uint8_t hold[RB_PLANT_MAX_AXLES], vent[RB_PLANT_MAX_AXLES];
} rb_hil_snapshot;

typedef struct {
    double hold_time;          /* s: last valid commands held this long, then the safe state */
    double late_time;          /* s: a BCU frame echoing a plant step older than this is late */
    double duration;           /* s: the run ends here at the latest */
    double stop_speed;         /* m/s: the run ends once braking has begun and the train is below */
    double record_interval;    /* s: decimation of the recorded channels (a multiple of 1 ms) */
    int paced;                 /* 1: 1 kHz on the wall clock; 0: as fast as possible (tests) */
    rb_bcu_params safe;        /* the BCU whose emergency demand law the safe state runs (WSP and ED off) */
    double adhesion_interval;  /* s: sampling of the available peak adhesion for the KPIs (0: every step) */
    uint32_t session;          /* this run's session id (non-zero, random: chosen by the caller) */
    uint32_t config;           /* rb_hil_config_digest of this plant */
    uint8_t secret[RB_HIL_KEY_SIZE];   /* shared with the BCU (its key file): session keys derive from it */
    double chunk_time;         /* s of wall time one rb_hil_runner_advance call lasts at most (0: no limit),
                                  so a caller writing each chunk's rows keeps up with the wall clock */
} rb_hil_config;

typedef enum {
    RB_HIL_EVENT_MALFORMED = 0,
    RB_HIL_EVENT_LATE,
    RB_HIL_EVENT_LOST,
    RB_HIL_EVENT_SAFE_ON,
    RB_HIL_EVENT_SAFE_OFF,
    RB_HIL_EVENT_FOREIGN,      /* the first datagram not from the BCU's address and session */
    RB_HIL_EVENT_MISMATCH,     /* the BCU answers for another configuration: the run ends */
    RB_HIL_EVENT_FORGED,       /* the first frame of the session whose tag does not authenticate */
    RB_HIL_EVENT_KEYED,        /* the BCU's challenge: the session key is agreed */
    RB_HIL_EVENT_ORDER,        /* the first duplicate, out-of-order or replayed frame */
    RB_HIL_EVENT_FAULT_ON,     /* a fault injected while the plant runs (rb_hil_runner_post_fault) */
    RB_HIL_EVENT_FAULT_OFF     /* ... cleared */
} rb_hil_event_kind;

/* A fault changed while the plant runs: injected (acting from the step it is applied in on) or
 * cleared (every fault of that kind on that car and axle, also one the scenario scheduled). */
typedef enum { RB_HIL_FAULT_INJECT = 1, RB_HIL_FAULT_CLEAR = 2 } rb_hil_fault_action;
typedef struct {
    int action;                /* rb_hil_fault_action */
    rb_fault fault;            /* kind, car, axle (-1: every axle of the car), value; start_time unused */
} rb_hil_fault_command;

typedef struct {
    uint64_t step;
    int kind;                  /* rb_hil_event_kind */
    char text[RB_HIL_LOG_TEXT];
} rb_hil_event;

typedef struct {
    uint64_t steps, frames_sent, send_errors, datagrams;
    uint64_t received, lost, late, malformed, safe_state_steps;   /* watchdog accounting */
    uint64_t overruns;
    uint64_t foreign;          /* datagrams not from the BCU's address and session: touch nothing else */
    uint64_t forged;           /* frames of the session whose tag does not authenticate: touch nothing else */
    uint64_t duplicate, out_of_order, replayed;   /* rb_seq_outcome: not applied */
    uint64_t challenges;       /* authenticated challenges from the BCU */
    uint64_t stale_challenges; /* ... refused: not echoing a hello nonce the plant offers (replayed, delayed) */
    uint64_t hellos;           /* rounds of hellos begun (a fresh plant nonce each) */
    /* the BCU lost: the safe state applied after a valid frame, or no valid frame within the hold time */
    uint64_t losses;           /* times the BCU was lost */
    uint64_t lost_step;        /* step of the first loss */
    uint64_t last_valid_step;  /* step of the last valid frame before it (0: none came) */
    uint64_t lost_steps;       /* steps in the safe state after a loss */
    uint64_t lost_lock_events; /* wheel locks (rb_run.h's definition) that began while the BCU was lost */
    double lost_lock_time;     /* axle-seconds locked while the BCU was lost */
    double lost_distance;      /* m run while the BCU was lost */
    double wakeup_p50_us, wakeup_p99_us, wakeup_max_us, wakeup_mean_us;
    double work_mean_us, work_p99_us, work_max_us;   /* wake-up to end of the step's work */
    double time;                                     /* s, simulated */
    double stopping_distance, stopping_time;         /* m, s: from the start of braking */
    int braking, stopped, finished;
    uint64_t events;                                 /* events logged since the start */
    int mismatch;                                    /* 1: the BCU is set up for another configuration */
    uint32_t bcu_config;                             /* ... its digest, */
    int bcu_cars, bcu_axles;                         /* ... cars and axles */
} rb_hil_result;

typedef struct {
    rb_plant_state plant;
    rb_plant_outputs out;
    rb_plant_inputs applied, last;   /* commands applied this step; the last valid BCU commands */
    rb_bcu_state safe_bcu;           /* the safe state's emergency demand law, run on the plant's outputs */
    rb_plant_inputs safe_in;
    float last_demand, applied_demand; /* brake_demand of the last valid frame; applied (2 when safe) */
    rb_watchdog watchdog;
    rb_pacer pacer;
    rb_udp udp;
    uint32_t sequence;
    uint64_t step, record_every, late_steps, duration_steps;
    int started, finished, stopped, braking, safe;
    double brake_time, brake_position;
    uint64_t frames_sent, send_errors, datagrams, foreign, forged, challenges;
    uint8_t hello_key[RB_HIL_KEY_SIZE], key[RB_HIL_KEY_SIZE];   /* the hello key; the session key */
    uint64_t nonce;                  /* the BCU's nonce the plant's frames carry (0: saying hello) */
    uint64_t key_nonce, key_plant_nonce;   /* the nonces of `key` (0: none agreed yet) */
    uint64_t hello_nonce, previous_hello_nonce;   /* offered while saying hello (renewed each lifetime) */
    uint64_t hello_step, keyed_step; /* steps the hello nonce was drawn, the key agreed */
    uint64_t rehello_steps, nonce_steps;   /* no valid frame for this long: hello again; a hello nonce's life */
    uint64_t challenges_refused, hellos;
    int had_valid, lost;             /* a valid frame came; the BCU is lost now */
    uint64_t losses, lost_step, last_valid_step, lost_steps, lost_lock_events, lock_events_before;
    double lost_lock_time, lost_distance;
    int mismatch;
    uint32_t bcu_config;
    int bcu_cars, bcu_axles;
    uint64_t events;
    rb_run_state kpi;                /* the KPIs of rb_run.h, accumulated as in a MIL run (rb_run_accumulate) */
    double next_peak, peak_sum;      /* the available peak adhesion, one axle per step (hil_runner.c) */
    int peak_axle, peak_count;
    rb_hil_event log[RB_HIL_LOG_SIZE];
    uint8_t buffer[2048];
    /* faults: the caller's plant parameters, copied at each rb_hil_runner_advance, with this run's
       fault list (the scenario's, changed by the commands posted) */
    rb_plant_params params;
    int n_faults;
    rb_fault fault[RB_MAX_FAULTS];
    /* the fault mailbox between a control thread and the loop (lock-free: whoever owns the state
       writes the rest; 0 empty, 1 posted, 2 answered) */
    int mailbox;
    rb_hil_fault_command command;
    int answer_status;
    uint64_t answer_step;
    char answer_text[RB_ERROR_MESSAGE_SIZE];
    /* the live view: odd while the loop writes it */
    uint32_t snapshot_sequence;
    rb_hil_snapshot snapshot;
} rb_hil_runner;

size_t rb_hil_runner_size(void);
/* Sizes of the structs a binding lays out itself (checked by src/railbrake/_core.py at import). */
size_t rb_hil_config_size(void);
size_t rb_hil_result_size(void);
size_t rb_hil_event_size(void);
/* The safe state's BCU from the BCU's parameters: the same demand law, WSP and ED off (in the safe
 * state the plant runs it each BCU cycle on its own outputs with an emergency demand: no more than
 * the BCU's own emergency demand at that speed; hold and vent de-energised). */
rb_status rb_hil_safe_bcu(const rb_bcu_params *bcu, rb_bcu_params *safe, rb_error *err);
/* Checks the parameters (plant->dt must be RB_HIL_DT), initialises the plant, opens the UDP endpoint
 * on bind_host:bind_port and sends to bcu_host:bcu_port (numeric IPv4). */
rb_status rb_hil_runner_open(const rb_plant_params *plant, const rb_hil_config *config, const char *bind_host,
                             int bind_port, const char *bcu_host, int bcu_port, rb_hil_runner *r, rb_error *err);
/* Runs up to `steps` plant steps (the first call also sends the frame of step 0 and starts the
 * pacer). Every rb_hil_channel_count(n_cars) values of a recorded row go to series (max_rows rows);
 * *rows gets the rows written by this call. *finished = 1 at the stop or the end of the duration. */
rb_status rb_hil_runner_advance(const rb_plant_params *plant, const rb_hil_config *config, rb_hil_runner *r,
                                uint64_t steps, double *series, size_t max_rows, size_t *rows, int *finished,
                                rb_error *err);
/* The KPIs of rb_run.h for the run so far, accumulated by the same code as a MIL run; the
 * safety-timer trips are the external BCU's and unknown here (0). */
void rb_hil_runner_kpis(const rb_plant_params *plant, const rb_hil_runner *r, rb_kpis *k);
void rb_hil_runner_result(const rb_hil_runner *r, rb_hil_result *res);
/* Event number `index` (0-based since the start) if it is still in the log: returns 1 and copies it. */
int rb_hil_runner_event(const rb_hil_runner *r, uint64_t index, rb_hil_event *event);
void rb_hil_runner_close(rb_hil_runner *r);
/* A fault change from another thread while rb_hil_runner_advance runs (or between its calls): the
 * loop applies it at the start of its next step, without waiting for anything, and answers.
 * Returns 1 when posted, 0 when the previous change has not been answered and fetched yet (one
 * poster at a time). */
int rb_hil_runner_post_fault(rb_hil_runner *r, const rb_hil_fault_command *command);
/* The answer to the change posted: -1 while not applied yet; else RB_OK (applied at plant step
 * *step, text what changed) or RB_EINVAL (refused, nothing changed, text why). Empties the mailbox. */
int rb_hil_runner_fault_answer(rb_hil_runner *r, uint64_t *step, char *text, size_t text_size);
/* The loop's latest snapshot, from any thread: 1 and a consistent copy, 0 when none could be read
 * between two of the loop's writes within `tries` attempts (the loop is never held up). */
int rb_hil_runner_snapshot(const rb_hil_runner *r, rb_hil_snapshot *out, int tries);
size_t rb_hil_snapshot_size(void);
/* Local UDP port of the plant (useful after binding port 0). */
int rb_hil_runner_port(const rb_hil_runner *r);

/* Recorded channels: count, and name and SI unit of channel `index`. */
int rb_hil_channel_count(int n_cars);
rb_status rb_hil_channel_info(int index, int n_cars, char *name, size_t name_size, char *unit,
                              size_t unit_size, rb_error *err);

/* ---- the reference BCU server */

typedef struct {
    rb_bcu_state state;
    rb_wsp_params wsp;               /* kept to restart the BCU for a new session */
    rb_plant_outputs out;            /* rebuilt from the newest plant frame */
    rb_udp udp;
    uint32_t sequence;
    uint32_t config;                 /* this BCU's rb_hil_config_digest */
    uint32_t session;                /* the session served (0: none yet) */
    uint8_t secret[RB_HIL_KEY_SIZE];         /* shared with the plant (the key file) */
    uint8_t cookie_secret[RB_HIL_KEY_SIZE];  /* this BCU's own, random: its nonces derive from it */
    uint8_t key[RB_HIL_KEY_SIZE];            /* the session key */
    uint64_t nonce, plant_nonce;     /* the nonces of the session key (the BCU's, the plant's) */
    uint64_t epoch;                  /* session keys agreed so far: a nonce is good until the next one */
    uint64_t last_step;
    int have_frame, finished;
    int64_t start_ns, last_frame_ns, first_datagram_ns, last_refusal_ns;
    uint64_t received, malformed, stale, sent, send_errors, cycles, foreign, refused, forged, challenges;
    /* the first refused plant: its configuration digest, cars and axles (refused > 0) */
    uint32_t refused_config;
    int refused_cars, refused_axles;
    uint8_t refused_from[16];
    uint8_t buffer[2048];
} rb_hil_bcu;

size_t rb_hil_bcu_size(void);
/* config: rb_hil_config_digest of the train this BCU is set up for; secret: the key file's 16
 * bytes (shared with the plant); cookie_secret: 16 random bytes of this BCU's own (its nonces). */
rb_status rb_hil_bcu_open(const rb_bcu_params *bcu, const rb_wsp_params *wsp, const rb_scenario *scenario,
                          uint32_t config, const uint8_t *secret, const uint8_t *cookie_secret, const char *host,
                          int port, rb_hil_bcu *b, rb_error *err);
/* Local UDP port (useful after binding port 0). */
int rb_hil_bcu_port(const rb_hil_bcu *b);
/* Serves plant frames for up to `for_s` seconds of wall time, waiting with poll(). A hello (a plant
 * frame of BCU nonce 0 with a plant nonce, that authenticates under the hello key) is answered, at
 * any time, with a challenge echoing the plant nonce and carrying this BCU's nonce for that plant (a
 * keyed hash of session, address, plant nonce, epoch and time slot: nothing is stored; it is good for
 * one to two RB_HIL_NONCE_LIFETIME and until the next session key is agreed, so no recorded or
 * delayed handshake can be replayed). The first plant frame under the key of both nonces opens the
 * session (its sender and session id), or gives the session's plant its new key; later frames
 * count only from that sender in that session (others: foreign, touching no other counter), unless
 * the session has been silent for RB_HIL_SESSION_IDLE s, when a new one may open (the BCU restarts).
 * Each session frame newer than the last (and at most RB_HIL_MAX_STEP_JUMP steps plus the wall time
 * since the last ahead: a forged step cannot silence the BCU) runs rb_bcu_step at the frame's time;
 * when a BCU cycle ran, its commands go back to the plant. A frame of another configuration is
 * refused and answered, at most every 0.1 s, with a frame carrying this BCU's digest, so the plant
 * can say why. *finished = 1 once duration (s of wall time, <= 0: none) has passed or idle_timeout s
 * passed without a session frame since the last one (or since the first plant frame of any
 * configuration, if none was). */
rb_status rb_hil_bcu_serve(const rb_bcu_params *bcu, const rb_scenario *scenario, rb_hil_bcu *b, double for_s,
                           double duration, double idle_timeout, int *finished, rb_error *err);
#define RB_HIL_SESSION_IDLE 1.0       /* s of silence after which another plant may open a session */
#define RB_HIL_MAX_STEP_JUMP 1000u     /* steps a plant frame may run ahead of the last, beyond the wall time */
/* Counters in the order of RB_HIL_BCU_COUNTERS: received, malformed, stale, sent, send_errors, cycles,
 * foreign, refused, forged (the tag does not authenticate), challenges (sent). */
#define RB_HIL_BCU_COUNTERS 10
void rb_hil_bcu_counters(const rb_hil_bcu *b, uint64_t counts[RB_HIL_BCU_COUNTERS]);
/* The first refused plant (another configuration): 1 and its digest, cars, axles and IPv4 address
 * "a.b.c.d:port" in from; 0 if none was refused. */
int rb_hil_bcu_refusal(const rb_hil_bcu *b, uint32_t *config, int *cars, int *axles, char *from, size_t from_size);
void rb_hil_bcu_close(rb_hil_bcu *b);

#ifdef __cplusplus
}
#endif
#endif

/* Frames exchanged between the real-time plant and an external brake control unit (BCU) over UDP.
 * The interface control document is docs/hil-interface.md; this header and hil_frame.c are the one
 * implementation of the layout, used by the C runner and (through the binding) by Python.
 *
 * Every frame: 48-byte header, payload, 4-byte CRC-32 (IEEE 802.3) over header and payload, then
 * an 8-byte SipHash-2-4 tag over header and payload under the session key (version 4).
 * All fields little-endian; physical values are IEEE-754 float32 in SI units (scaling 1).
 *
 * Version 2 adds the session: the plant opens one per run (a random non-zero id) and carries, with
 * it, the digest of its configuration (rb_hil_config_digest: train, cars, axles, step); a BCU
 * answers only the plant that opened its session, echoing the session id with its own digest,
 * and the plant takes commands only from the BCU's address in its session.
 *
 * Version 3 authenticates every frame: both sides hold a 128-bit secret (a key file); the session
 * key is derived from it, the session id and the BCU's nonce (rb_hil_session_key). A plant opens
 * with hello frames (nonce 0, key of nonce 0); the BCU answers with a challenge frame carrying its
 * nonce; from then on both use the key of that nonce.
 *
 * Version 4 keys the session to fresh nonces from both sides: each hello carries a plant nonce
 * (new for each round of hellos, renewed every RB_HIL_NONCE_LIFETIME s), the challenge echoes it
 * beside the BCU's nonce, and the session key derives from both. A challenge that does not echo a
 * hello nonce the plant still offers (a replayed or delayed one of an earlier exchange) is refused. */
#ifndef RAILBRAKE_HIL_FRAME_H
#define RAILBRAKE_HIL_FRAME_H

#include <stdint.h>

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_FRAME_MAGIC 0x4B524252u   /* "RBRK" in little-endian bytes */
#define RB_FRAME_VERSION 4u
#define RB_FRAME_MAX_CARS 16
#define RB_FRAME_MAX_AXLES 64
#define RB_FRAME_HEADER_SIZE 48
#define RB_FRAME_CRC_SIZE 4
#define RB_FRAME_MAC_SIZE 8
#define RB_FRAME_TRAILER_SIZE (RB_FRAME_CRC_SIZE + RB_FRAME_MAC_SIZE)
#define RB_HIL_KEY_SIZE 16
/* s: a hello nonce, and a BCU nonce not yet used, is good for one to two of these (the ICD's design value) */
#define RB_HIL_NONCE_LIFETIME 0.5

/* challenge: BCU -> plant, header only, carrying the BCU's nonce and echoing the plant's (under the hello key) */
typedef enum { RB_FRAME_PLANT = 1, RB_FRAME_BCU = 2, RB_FRAME_CHALLENGE = 3 } rb_frame_type;

typedef struct {
    uint32_t session;      /* the plant's run (non-zero); BCU frames echo the session they serve */
    uint32_t config;       /* digest of the sender's configuration (rb_hil_config_digest) */
    uint32_t sequence;     /* increments by one per frame sent */
    uint64_t step;         /* plant step count (1 ms steps); BCU frames echo the last plant step seen */
    uint64_t nonce;        /* the BCU's nonce the session key is derived with (0: hello, the hello key) */
    uint64_t plant_nonce;  /* the plant's nonce of that key (a hello: the one it offers; 0: a refusal) */
    uint8_t n_cars;
    uint8_t n_axles;
    uint8_t type;          /* rb_frame_type: filled by rb_frame_check, ignored by the encoders */
} rb_frame_header;

/* Plant -> BCU: what the BCU's sensors would read. */
typedef struct {
    rb_frame_header header;
    float train_speed;                           /* m/s */
    float position;                              /* m */
    float main_reservoir_pressure;               /* Pa absolute */
    float wheel_speed[RB_FRAME_MAX_AXLES];       /* peripheral speed, m/s */
    float cylinder_pressure[RB_FRAME_MAX_AXLES]; /* Pa absolute */
    float supply_pressure[RB_FRAME_MAX_CARS];    /* brake supply reservoir, Pa absolute */
} rb_plant_frame;

/* BCU -> plant: commands. */
typedef struct {
    rb_frame_header header;
    float brake_demand;                          /* 0 (release) .. 1 (full service); > 1 emergency */
    float pressure_demand[RB_FRAME_MAX_CARS];    /* brake-cylinder pressure demand per car, Pa absolute */
    uint8_t hold[RB_FRAME_MAX_AXLES];            /* WSP hold valve closed (1) / open (0) */
    uint8_t vent[RB_FRAME_MAX_AXLES];            /* WSP vent valve open (1) / closed (0) */
} rb_bcu_frame;

/* Size in bytes of an encoded frame for n_cars and n_axles (a challenge: header and trailer). */
size_t rb_plant_frame_size(int n_cars, int n_axles);
size_t rb_bcu_frame_size(int n_cars, int n_axles);
size_t rb_challenge_frame_size(void);

/* Encode into buf (capacity bytes), tagged under key (RB_HIL_KEY_SIZE bytes: the session key,
 * rb_hil_session_key); *written gets the frame size. */
rb_status rb_plant_frame_encode(const rb_plant_frame *f, const uint8_t *key, uint8_t *buf, size_t capacity,
                                size_t *written, rb_error *err);
rb_status rb_bcu_frame_encode(const rb_bcu_frame *f, const uint8_t *key, uint8_t *buf, size_t capacity,
                              size_t *written, rb_error *err);
rb_status rb_challenge_frame_encode(const rb_frame_header *h, const uint8_t *key, uint8_t *buf, size_t capacity,
                                    size_t *written, rb_error *err);

/* The frame's structure (magic, version, type, counts, sizes, session, CRC) without its tag or
 * values: the header (type included) goes to h, so the receiver can pick the session key. */
rb_status rb_frame_check(const uint8_t *buf, size_t size, rb_frame_header *h, rb_error *err);
/* 1 if the frame's tag is the SipHash-2-4 of header and payload under key (compared in constant
 * time), else 0. size must be at least RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE. */
int rb_frame_authentic(const uint8_t *buf, size_t size, const uint8_t *key);

/* Decode and validate (structure as rb_frame_check, finite values, ranges, booleans); the tag is
 * not checked here: rb_frame_authentic with the session's key first. */
rb_status rb_plant_frame_decode(const uint8_t *buf, size_t size, rb_plant_frame *f, rb_error *err);
rb_status rb_bcu_frame_decode(const uint8_t *buf, size_t size, rb_bcu_frame *f, rb_error *err);

uint32_t rb_crc32(const uint8_t *data, size_t size);
/* SipHash-2-4 of data under a 128-bit key (hil_mac.c). */
uint64_t rb_siphash24(const uint8_t key[RB_HIL_KEY_SIZE], const uint8_t *data, size_t size);
/* The session key: SipHash-2-4 in counter mode (NIST SP 800-108) over the secret both sides hold,
 * the plant's session id, the plant's nonce and the BCU's nonce (both 0: the hello key, of hello,
 * challenge and refusal frames). */
void rb_hil_session_key(const uint8_t secret[RB_HIL_KEY_SIZE], uint32_t session, uint64_t plant_nonce,
                        uint64_t bcu_nonce, uint8_t key[RB_HIL_KEY_SIZE]);
/* The plant's hello nonce number `count` of `session`: SipHash-2-4 under the secret of a label,
 * the session and the count (fresh for each count, unpredictable without the secret, never 0). */
uint64_t rb_hil_plant_nonce(const uint8_t secret[RB_HIL_KEY_SIZE], uint32_t session, uint64_t count);

/* The configuration digest both sides compare: CRC-32 of
 * "railbrake-hil/2 train=<train> cars=<n_cars> axles=<n_axles> step_us=<dt in us>". A BCU set up
 * for another train, car count or step refuses the plant's frames (and says why). */
uint32_t rb_hil_config_digest(const char *train, int n_cars, int n_axles, double dt);

#ifdef __cplusplus
}
#endif
#endif

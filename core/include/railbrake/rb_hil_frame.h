/* Frames exchanged between the real-time plant and an external brake control unit (BCU) over UDP.
 * The interface control document is docs/hil-interface.md; this header and hil_frame.c are the one
 * implementation of the layout, used by the C runner and (through the binding) by Python.
 *
 * Every frame: 32-byte header, payload, 4-byte CRC-32 (IEEE 802.3) over header and payload.
 * All fields little-endian; physical values are IEEE-754 float32 in SI units (scaling 1).
 *
 * Version 2 adds the session: the plant opens one per run (a random non-zero id) and carries, with
 * it, the digest of its configuration (rb_hil_config_digest: train, cars, axles, step); a BCU
 * answers only the plant that opened its session, echoing the session id with its own digest,
 * and the plant takes commands only from the BCU's address in its session. */
#ifndef RAILBRAKE_HIL_FRAME_H
#define RAILBRAKE_HIL_FRAME_H

#include <stdint.h>

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RB_FRAME_MAGIC 0x4B524252u   /* "RBRK" in little-endian bytes */
#define RB_FRAME_VERSION 2u
#define RB_FRAME_MAX_CARS 16
#define RB_FRAME_MAX_AXLES 64
#define RB_FRAME_HEADER_SIZE 32
#define RB_FRAME_CRC_SIZE 4

typedef enum { RB_FRAME_PLANT = 1, RB_FRAME_BCU = 2 } rb_frame_type;

typedef struct {
    uint32_t session;      /* the plant's run (non-zero); BCU frames echo the session they serve */
    uint32_t config;       /* digest of the sender's configuration (rb_hil_config_digest) */
    uint32_t sequence;     /* increments by one per frame sent */
    uint64_t step;         /* plant step count (1 ms steps); BCU frames echo the last plant step seen */
    uint8_t n_cars;
    uint8_t n_axles;
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

/* Size in bytes of an encoded frame for n_cars and n_axles. */
size_t rb_plant_frame_size(int n_cars, int n_axles);
size_t rb_bcu_frame_size(int n_cars, int n_axles);

/* Encode into buf (capacity bytes); *written gets the frame size. */
rb_status rb_plant_frame_encode(const rb_plant_frame *f, uint8_t *buf, size_t capacity,
                                size_t *written, rb_error *err);
rb_status rb_bcu_frame_encode(const rb_bcu_frame *f, uint8_t *buf, size_t capacity,
                              size_t *written, rb_error *err);

/* Decode and validate (magic, version, type, sizes, counts, CRC, finite values, booleans). */
rb_status rb_plant_frame_decode(const uint8_t *buf, size_t size, rb_plant_frame *f, rb_error *err);
rb_status rb_bcu_frame_decode(const uint8_t *buf, size_t size, rb_bcu_frame *f, rb_error *err);

uint32_t rb_crc32(const uint8_t *data, size_t size);

/* The configuration digest both sides compare: CRC-32 of
 * "railbrake-hil/2 train=<train> cars=<n_cars> axles=<n_axles> step_us=<dt in us>". A BCU set up
 * for another train, car count or step refuses the plant's frames (and says why). */
uint32_t rb_hil_config_digest(const char *train, int n_cars, int n_axles, double dt);

#ifdef __cplusplus
}
#endif
#endif

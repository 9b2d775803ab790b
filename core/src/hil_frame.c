/* Encoding and validation of the HIL frames (docs/hil-interface.md). Byte order is written out
 * explicitly so the layout does not depend on the host. */
#include "railbrake/rb_hil_frame.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

uint32_t rb_crc32(const uint8_t *data, size_t size)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < size; ++i) {
        crc ^= data[i];
        for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

uint32_t rb_hil_config_digest(const char *train, int n_cars, int n_axles, double dt)
{
    char text[256];
    int n = snprintf(text, sizeof text, "railbrake-hil/2 train=%.180s cars=%d axles=%d step_us=%lld",
                     train ? train : "", n_cars, n_axles, (long long)llround(dt * 1e6));
    return rb_crc32((const uint8_t *)text, n < 0 ? 0 : (size_t)n < sizeof text ? (size_t)n : sizeof text - 1);
}

/* ---- little-endian writer/reader over a bounded buffer */

typedef struct { uint8_t *p; size_t at; } writer;
typedef struct { const uint8_t *p; size_t at; } reader;

static void put_u8(writer *w, uint8_t v) { w->p[w->at++] = v; }
static void put_u16(writer *w, uint16_t v) { put_u8(w, (uint8_t)v); put_u8(w, (uint8_t)(v >> 8)); }
static void put_u32(writer *w, uint32_t v) { put_u16(w, (uint16_t)v); put_u16(w, (uint16_t)(v >> 16)); }
static void put_u64(writer *w, uint64_t v) { put_u32(w, (uint32_t)v); put_u32(w, (uint32_t)(v >> 32)); }
static void put_f32(writer *w, float v) { uint32_t u; memcpy(&u, &v, 4); put_u32(w, u); }

static uint8_t get_u8(reader *r) { return r->p[r->at++]; }
static uint16_t get_u16(reader *r) { uint16_t lo = get_u8(r); return (uint16_t)(lo | (uint16_t)get_u8(r) << 8); }
static uint32_t get_u32(reader *r) { uint32_t lo = get_u16(r); return lo | (uint32_t)get_u16(r) << 16; }
static uint64_t get_u64(reader *r) { uint64_t lo = get_u32(r); return lo | (uint64_t)get_u32(r) << 32; }
static float get_f32(reader *r) { uint32_t u = get_u32(r); float v; memcpy(&v, &u, 4); return v; }

size_t rb_plant_frame_size(int n_cars, int n_axles)
{
    return RB_FRAME_HEADER_SIZE + 4u * (3u + 2u * (size_t)n_axles + (size_t)n_cars) + RB_FRAME_TRAILER_SIZE;
}

size_t rb_bcu_frame_size(int n_cars, int n_axles)
{
    return RB_FRAME_HEADER_SIZE + 4u * (1u + (size_t)n_cars) + 2u * (size_t)n_axles + RB_FRAME_TRAILER_SIZE;
}

size_t rb_challenge_frame_size(void) { return RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE; }

static size_t frame_size(int type, int n_cars, int n_axles)
{
    return type == RB_FRAME_PLANT ? rb_plant_frame_size(n_cars, n_axles)
         : type == RB_FRAME_BCU ? rb_bcu_frame_size(n_cars, n_axles) : rb_challenge_frame_size();
}

static rb_status check_counts(const rb_frame_header *h, rb_error *err)
{
    if (h->n_cars < 1 || h->n_cars > RB_FRAME_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "n_cars = %d: must lie in [1, %d]", h->n_cars, RB_FRAME_MAX_CARS);
    if (h->n_axles < 1 || h->n_axles > RB_FRAME_MAX_AXLES)
        return rb_fail(err, RB_EINVAL, "n_axles = %d: must lie in [1, %d]", h->n_axles, RB_FRAME_MAX_AXLES);
    return RB_OK;
}

static void put_header(writer *w, const rb_frame_header *h, rb_frame_type type, uint16_t payload)
{
    put_u32(w, RB_FRAME_MAGIC);
    put_u8(w, (uint8_t)RB_FRAME_VERSION);
    put_u8(w, (uint8_t)type);
    put_u16(w, payload);
    put_u32(w, h->session);
    put_u32(w, h->config);
    put_u32(w, h->sequence);
    put_u64(w, h->step);
    put_u8(w, h->n_cars);
    put_u8(w, h->n_axles);
    put_u16(w, 0);  /* reserved */
    put_u64(w, h->nonce);
    put_u64(w, h->plant_nonce);
}

/* Checks key, counts and capacity, then writes the header. */
static rb_status begin_frame(writer *w, const rb_frame_header *h, rb_frame_type type, const uint8_t *key,
                             uint8_t *buf, size_t capacity, rb_error *err)
{
    if (!buf || !key) return rb_fail(err, RB_EINVAL, "buffer and key must not be NULL");
    rb_status s = check_counts(h, err);
    if (s) return s;
    size_t size = frame_size(type, h->n_cars, h->n_axles);
    if (capacity < size) return rb_fail(err, RB_ESIZE, "capacity = %zu: the frame needs %zu bytes", capacity, size);
    w->p = buf;
    w->at = 0;
    put_header(w, h, type, (uint16_t)(size - RB_FRAME_HEADER_SIZE - RB_FRAME_TRAILER_SIZE));
    return RB_OK;
}

/* CRC over header and payload (corruption), then the tag over the same bytes (authenticity). */
static void put_trailer(writer *w, const uint8_t *key, size_t *written)
{
    size_t body = w->at;
    put_u32(w, rb_crc32(w->p, body));
    put_u64(w, rb_siphash24(key, w->p, body));
    if (written) *written = w->at;
}

rb_status rb_plant_frame_encode(const rb_plant_frame *f, const uint8_t *key, uint8_t *buf, size_t capacity,
                                size_t *written, rb_error *err)
{
    if (!f) return rb_fail(err, RB_EINVAL, "frame must not be NULL");
    writer w = {NULL, 0};
    rb_status s = begin_frame(&w, &f->header, RB_FRAME_PLANT, key, buf, capacity, err);
    if (s) return s;
    put_f32(&w, f->train_speed);
    put_f32(&w, f->position);
    put_f32(&w, f->main_reservoir_pressure);
    for (int i = 0; i < f->header.n_axles; ++i) put_f32(&w, f->wheel_speed[i]);
    for (int i = 0; i < f->header.n_axles; ++i) put_f32(&w, f->cylinder_pressure[i]);
    for (int i = 0; i < f->header.n_cars; ++i) put_f32(&w, f->supply_pressure[i]);
    put_trailer(&w, key, written);
    return RB_OK;
}

rb_status rb_bcu_frame_encode(const rb_bcu_frame *f, const uint8_t *key, uint8_t *buf, size_t capacity,
                              size_t *written, rb_error *err)
{
    if (!f) return rb_fail(err, RB_EINVAL, "frame must not be NULL");
    writer w = {NULL, 0};
    rb_status s = begin_frame(&w, &f->header, RB_FRAME_BCU, key, buf, capacity, err);
    if (s) return s;
    put_f32(&w, f->brake_demand);
    for (int i = 0; i < f->header.n_cars; ++i) put_f32(&w, f->pressure_demand[i]);
    for (int i = 0; i < f->header.n_axles; ++i) put_u8(&w, f->hold[i]);
    for (int i = 0; i < f->header.n_axles; ++i) put_u8(&w, f->vent[i]);
    put_trailer(&w, key, written);
    return RB_OK;
}

rb_status rb_challenge_frame_encode(const rb_frame_header *h, const uint8_t *key, uint8_t *buf, size_t capacity,
                                    size_t *written, rb_error *err)
{
    if (!h) return rb_fail(err, RB_EINVAL, "header must not be NULL");
    writer w = {NULL, 0};
    rb_status s = begin_frame(&w, h, RB_FRAME_CHALLENGE, key, buf, capacity, err);
    if (s) return s;
    put_trailer(&w, key, written);
    return RB_OK;
}

/* Header, sizes and CRC; leaves the reader after the header. */
static rb_status read_header(reader *r, size_t size, rb_frame_header *h, rb_error *err)
{
    if (size < RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE)
        return rb_fail(err, RB_EINVAL, "size = %zu: shorter than header, CRC and tag", size);
    uint32_t magic = get_u32(r);
    if (magic != RB_FRAME_MAGIC) return rb_fail(err, RB_EINVAL, "magic = 0x%08x: expected 0x%08x", magic, RB_FRAME_MAGIC);
    unsigned version = get_u8(r), type = get_u8(r);
    if (version != RB_FRAME_VERSION) return rb_fail(err, RB_EINVAL, "version = %u: expected %u", version, RB_FRAME_VERSION);
    if (type < RB_FRAME_PLANT || type > RB_FRAME_CHALLENGE)
        return rb_fail(err, RB_EINVAL, "type = %u: expected 1 (plant), 2 (BCU) or 3 (challenge)", type);
    h->type = (uint8_t)type;
    unsigned payload = get_u16(r);
    h->session = get_u32(r);
    h->config = get_u32(r);
    h->sequence = get_u32(r);
    h->step = get_u64(r);
    h->n_cars = get_u8(r);
    h->n_axles = get_u8(r);
    (void)get_u16(r);
    h->nonce = get_u64(r);
    h->plant_nonce = get_u64(r);
    rb_status s = check_counts(h, err);
    if (s) return s;
    size_t expected = frame_size((int)type, h->n_cars, h->n_axles);
    size_t expected_payload = expected - RB_FRAME_HEADER_SIZE - RB_FRAME_TRAILER_SIZE;
    if (size != expected)
        return rb_fail(err, RB_EINVAL, "size = %zu: expected %zu for type %u, %d cars and %d axles", size, expected,
                       type, h->n_cars, h->n_axles);
    if (payload != expected_payload)
        return rb_fail(err, RB_EINVAL, "payload_size = %u: expected %zu for type %u, %d cars and %d axles", payload,
                       expected_payload, type, h->n_cars, h->n_axles);
    if (h->session == 0) return rb_fail(err, RB_EINVAL, "session = 0: a plant opens a non-zero session");
    size_t body = size - RB_FRAME_TRAILER_SIZE;
    reader crc_at = {r->p, body};
    uint32_t crc = get_u32(&crc_at), computed = rb_crc32(r->p, body);
    if (crc != computed) return rb_fail(err, RB_EINVAL, "crc = 0x%08x: computed 0x%08x", crc, computed);
    return RB_OK;
}

rb_status rb_frame_check(const uint8_t *buf, size_t size, rb_frame_header *h, rb_error *err)
{
    if (!buf || !h) return rb_fail(err, RB_EINVAL, "buffer and header must not be NULL");
    reader r = {buf, 0};
    return read_header(&r, size, h, err);
}

int rb_frame_authentic(const uint8_t *buf, size_t size, const uint8_t *key)
{
    if (!buf || !key || size < RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE) return 0;
    size_t body = size - RB_FRAME_TRAILER_SIZE;
    uint64_t tag = rb_siphash24(key, buf, body);
    uint8_t diff = 0;   /* every byte compared: the time does not tell how much of a forged tag matched */
    for (int i = 0; i < RB_FRAME_MAC_SIZE; ++i)
        diff |= (uint8_t)(buf[body + RB_FRAME_CRC_SIZE + (size_t)i] ^ (uint8_t)(tag >> (8 * i)));
    return diff == 0;
}

static rb_status check_float(rb_error *err, const char *name, int index, float v)
{
    if (!isfinite(v)) return rb_fail(err, RB_EINVAL, "%s[%d] = %g: must be finite", name, index, (double)v);
    return RB_OK;
}

/* The header of a frame of the wanted type. */
static rb_status read_typed_header(reader *r, size_t size, rb_frame_type type, rb_frame_header *h, rb_error *err)
{
    rb_status s = read_header(r, size, h, err);
    if (s) return s;
    if (h->type != (uint8_t)type) return rb_fail(err, RB_EINVAL, "type = %u: expected %u", h->type, (unsigned)type);
    return RB_OK;
}

rb_status rb_plant_frame_decode(const uint8_t *buf, size_t size, rb_plant_frame *f, rb_error *err)
{
    if (!buf || !f) return rb_fail(err, RB_EINVAL, "buffer and frame must not be NULL");
    reader r = {buf, 0};
    rb_plant_frame out;
    memset(&out, 0, sizeof out);
    rb_status s = read_typed_header(&r, size, RB_FRAME_PLANT, &out.header, err);
    if (s) return s;
    out.train_speed = get_f32(&r);
    out.position = get_f32(&r);
    out.main_reservoir_pressure = get_f32(&r);
    if ((s = check_float(err, "train_speed", 0, out.train_speed))) return s;
    if ((s = check_float(err, "position", 0, out.position))) return s;
    if ((s = check_float(err, "main_reservoir_pressure", 0, out.main_reservoir_pressure))) return s;
    for (int i = 0; i < out.header.n_axles; ++i)
        if ((s = check_float(err, "wheel_speed", i, out.wheel_speed[i] = get_f32(&r)))) return s;
    for (int i = 0; i < out.header.n_axles; ++i)
        if ((s = check_float(err, "cylinder_pressure", i, out.cylinder_pressure[i] = get_f32(&r)))) return s;
    for (int i = 0; i < out.header.n_cars; ++i)
        if ((s = check_float(err, "supply_pressure", i, out.supply_pressure[i] = get_f32(&r)))) return s;
    *f = out;
    return RB_OK;
}

rb_status rb_bcu_frame_decode(const uint8_t *buf, size_t size, rb_bcu_frame *f, rb_error *err)
{
    if (!buf || !f) return rb_fail(err, RB_EINVAL, "buffer and frame must not be NULL");
    reader r = {buf, 0};
    rb_bcu_frame out;
    memset(&out, 0, sizeof out);
    rb_status s = read_typed_header(&r, size, RB_FRAME_BCU, &out.header, err);
    if (s) return s;
    out.brake_demand = get_f32(&r);
    if (!(out.brake_demand >= 0.0f && out.brake_demand <= 2.0f))
        return rb_fail(err, RB_EINVAL, "brake_demand = %g: must lie in [0, 2]", (double)out.brake_demand);
    for (int i = 0; i < out.header.n_cars; ++i) {
        out.pressure_demand[i] = get_f32(&r);
        if (!(out.pressure_demand[i] >= 0.0f && out.pressure_demand[i] <= 2e6f))
            return rb_fail(err, RB_EINVAL, "pressure_demand[%d] = %g: must lie in [0, 2e6] Pa", i,
                           (double)out.pressure_demand[i]);
    }
    for (int k = 0; k < 2; ++k) {
        uint8_t *bits = k ? out.vent : out.hold;
        for (int i = 0; i < out.header.n_axles; ++i) {
            bits[i] = get_u8(&r);
            if (bits[i] > 1) return rb_fail(err, RB_EINVAL, "%s[%d] = %u: must be 0 or 1", k ? "vent" : "hold", i, bits[i]);
        }
    }
    *f = out;
    return RB_OK;
}

/* SipHash-2-4 (J.-P. Aumasson, D. J. Bernstein, "SipHash: a fast short-input PRF", INDOCRYPT 2012,
 * https://cr.yp.to/siphash/siphash-20120918.pdf), written from the paper's specification (section 2),
 * and the session keys of the HIL link derived with it (docs/hil-interface.md, authentication).
 * Checked against the paper's test vectors in core/tests/test_hil_frame.c. */
#include "railbrake/rb_hil_frame.h"

#include <string.h>

static uint64_t rotl(uint64_t x, int b) { return (x << b) | (x >> (64 - b)); }

static int host_little_endian(void)
{
    const union { uint16_t u; uint8_t b[2]; } probe = {1};
    return probe.b[0] == 1;   /* a constant: the compiler keeps one branch */
}

/* A little-endian 64-bit word (one load on a little-endian host). */
static uint64_t load_le64(const uint8_t *p)
{
    uint64_t v = 0;
    if (host_little_endian()) {
        memcpy(&v, p, 8);
        return v;
    }
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

typedef struct { uint64_t v0, v1, v2, v3; } sip_state;

static void sip_round(sip_state *s)
{
    s->v0 += s->v1; s->v1 = rotl(s->v1, 13); s->v1 ^= s->v0; s->v0 = rotl(s->v0, 32);
    s->v2 += s->v3; s->v3 = rotl(s->v3, 16); s->v3 ^= s->v2;
    s->v0 += s->v3; s->v3 = rotl(s->v3, 21); s->v3 ^= s->v0;
    s->v2 += s->v1; s->v1 = rotl(s->v1, 17); s->v1 ^= s->v2; s->v2 = rotl(s->v2, 32);
}

/* c = 2 compression rounds per message word */
static void compress(sip_state *s, uint64_t m)
{
    s->v3 ^= m;
    sip_round(s);
    sip_round(s);
    s->v0 ^= m;
}

uint64_t rb_siphash24(const uint8_t key[RB_HIL_KEY_SIZE], const uint8_t *data, size_t size)
{
    uint64_t k0 = load_le64(key), k1 = load_le64(key + 8);
    sip_state s = {k0 ^ 0x736f6d6570736575ULL, k1 ^ 0x646f72616e646f6dULL, k0 ^ 0x6c7967656e657261ULL,
                   k1 ^ 0x7465646279746573ULL};
    size_t whole = size - size % 8;
    for (size_t i = 0; i < whole; i += 8) compress(&s, load_le64(data + i));
    /* the last word: the remaining bytes, the message length mod 256 in the top byte */
    uint64_t last = (uint64_t)(size & 0xff) << 56;
    for (size_t i = 0; i < size % 8; ++i) last |= (uint64_t)data[whole + i] << (8 * i);
    compress(&s, last);
    s.v2 ^= 0xff;
    for (int r = 0; r < 4; ++r) sip_round(&s);   /* d = 4 finalization rounds */
    return s.v0 ^ s.v1 ^ s.v2 ^ s.v3;
}

static size_t put_le(uint8_t *at, uint64_t v, int bytes)
{
    for (int i = 0; i < bytes; ++i) at[i] = (uint8_t)(v >> (8 * i));
    return (size_t)bytes;
}

/* A counter-mode KDF (NIST SP 800-108r1, section 4.1) with SipHash-2-4 as the PRF: two 64-bit
 * blocks over label, counter, session and both nonces make the 128-bit session key. */
void rb_hil_session_key(const uint8_t secret[RB_HIL_KEY_SIZE], uint32_t session, uint64_t plant_nonce,
                        uint64_t bcu_nonce, uint8_t key[RB_HIL_KEY_SIZE])
{
    static const char label[] = "railbrake-hil/4 session key";
    uint8_t input[sizeof label + 1 + 4 + 8 + 8];
    size_t n = sizeof label;
    memcpy(input, label, n);   /* with its NUL: the label ends unambiguously */
    size_t counter_at = n++;
    n += put_le(input + n, session, 4);
    n += put_le(input + n, plant_nonce, 8);
    n += put_le(input + n, bcu_nonce, 8);
    for (int block = 0; block < 2; ++block) {
        input[counter_at] = (uint8_t)(block + 1);
        put_le(key + 8 * block, rb_siphash24(secret, input, n), 8);
    }
}

uint64_t rb_hil_plant_nonce(const uint8_t secret[RB_HIL_KEY_SIZE], uint32_t session, uint64_t count)
{
    static const char label[] = "railbrake-hil/4 plant nonce";
    uint8_t input[sizeof label + 4 + 8];
    size_t n = sizeof label;
    memcpy(input, label, n);
    n += put_le(input + n, session, 4);
    n += put_le(input + n, count, 8);
    uint64_t nonce = rb_siphash24(secret, input, n);
    return nonce ? nonce : 1u;
}

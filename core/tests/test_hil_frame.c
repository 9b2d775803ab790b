/* HIL frames: round trip, CRC and SipHash-2-4 reference values, the tag, and every corruption rejected
 * without a crash. */
#include "rb_test.h"
#include "railbrake/rb_hil_frame.h"

#include <stdlib.h>

static const uint8_t KEY[RB_HIL_KEY_SIZE] = {7, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

static rb_plant_frame sample_plant(void)
{
    rb_plant_frame f;
    memset(&f, 0, sizeof f);
    f.header.session = 0xfeedbeefu;
    f.header.config = 0x12345678u;
    f.header.sequence = 41;
    f.header.step = 1234567890123ull;
    f.header.n_cars = 8;
    f.header.n_axles = 32;
    f.train_speed = 83.3f;
    f.position = 1520.25f;
    f.main_reservoir_pressure = 9.5e5f;
    for (int i = 0; i < 32; ++i) { f.wheel_speed[i] = 80.0f + 0.1f * i; f.cylinder_pressure[i] = 3e5f + i; }
    for (int i = 0; i < 8; ++i) f.supply_pressure[i] = 8e5f - i;
    return f;
}

static void test_crc_reference(void)
{
    /* CRC-32/IEEE check value of "123456789". */
    CHECK(rb_crc32((const uint8_t *)"123456789", 9) == 0xCBF43926u);
}

/* SipHash-2-4 against the published test vectors: key 00 01 .. 0f, messages 00 01 .. (i - 1) of
 * length i = 0..63 (Aumasson and Bernstein's reference vectors, siphash24.c / vectors.h of
 * https://github.com/veorq/SipHash; i = 15 is the worked example of the paper's appendix A). */
static void test_siphash_vectors(void)
{
    static const uint64_t vectors[64] = {
        0x726fdb47dd0e0e31ULL, 0x74f839c593dc67fdULL, 0x0d6c8009d9a94f5aULL, 0x85676696d7fb7e2dULL,
        0xcf2794e0277187b7ULL, 0x18765564cd99a68dULL, 0xcbc9466e58fee3ceULL, 0xab0200f58b01d137ULL,
        0x93f5f5799a932462ULL, 0x9e0082df0ba9e4b0ULL, 0x7a5dbbc594ddb9f3ULL, 0xf4b32f46226bada7ULL,
        0x751e8fbc860ee5fbULL, 0x14ea5627c0843d90ULL, 0xf723ca908e7af2eeULL, 0xa129ca6149be45e5ULL,
        0x3f2acc7f57c29bdbULL, 0x699ae9f52cbe4794ULL, 0x4bc1b3f0968dd39cULL, 0xbb6dc91da77961bdULL,
        0xbed65cf21aa2ee98ULL, 0xd0f2cbb02e3b67c7ULL, 0x93536795e3a33e88ULL, 0xa80c038ccd5ccec8ULL,
        0xb8ad50c6f649af94ULL, 0xbce192de8a85b8eaULL, 0x17d835b85bbb15f3ULL, 0x2f2e6163076bcfadULL,
        0xde4daaaca71dc9a5ULL, 0xa6a2506687956571ULL, 0xad87a3535c49ef28ULL, 0x32d892fad841c342ULL,
        0x7127512f72f27cceULL, 0xa7f32346f95978e3ULL, 0x12e0b01abb051238ULL, 0x15e034d40fa197aeULL,
        0x314dffbe0815a3b4ULL, 0x027990f029623981ULL, 0xcadcd4e59ef40c4dULL, 0x9abfd8766a33735cULL,
        0x0e3ea96b5304a7d0ULL, 0xad0c42d6fc585992ULL, 0x187306c89bc215a9ULL, 0xd4a60abcf3792b95ULL,
        0xf935451de4f21df2ULL, 0xa9538f0419755787ULL, 0xdb9acddff56ca510ULL, 0xd06c98cd5c0975ebULL,
        0xe612a3cb9ecba951ULL, 0xc766e62cfcadaf96ULL, 0xee64435a9752fe72ULL, 0xa192d576b245165aULL,
        0x0a8787bf8ecb74b2ULL, 0x81b3e73d20b49b6fULL, 0x7fa8220ba3b2eceaULL, 0x245731c13ca42499ULL,
        0xb78dbfaf3a8d83bdULL, 0xea1ad565322a1a0bULL, 0x60e61c23a3795013ULL, 0x6606d7e446282b93ULL,
        0x6ca4ecb15c5f91e1ULL, 0x9f626da15c9625f3ULL, 0xe51b38608ef25f57ULL, 0x958a324ceb064572ULL};
    uint8_t key[16], message[64];
    for (int i = 0; i < 16; ++i) key[i] = (uint8_t)i;
    for (int i = 0; i < 64; ++i) message[i] = (uint8_t)i;
    int matched = 0;
    for (int n = 0; n < 64; ++n) matched += rb_siphash24(key, message, (size_t)n) == vectors[n];
    CHECK(matched == 64);
}

/* Session keys: a function of secret, session and both nonces, each of which changes the key;
 * plant nonces: fresh for each count and session, never 0. */
static void test_session_keys(void)
{
    uint8_t a[16], b[16], c[16], d[16], e[16], other[16];
    memcpy(other, KEY, 16);
    other[15] ^= 1;
    rb_hil_session_key(KEY, 5, 0, 0, a);
    rb_hil_session_key(KEY, 5, 0, 0, b);
    CHECK(memcmp(a, b, 16) == 0);
    rb_hil_session_key(KEY, 6, 0, 0, b);
    rb_hil_session_key(KEY, 5, 0, 1, c);
    rb_hil_session_key(other, 5, 0, 0, d);
    rb_hil_session_key(KEY, 5, 1, 0, e);
    CHECK(memcmp(a, b, 16) != 0 && memcmp(a, c, 16) != 0 && memcmp(a, d, 16) != 0 && memcmp(a, e, 16) != 0);
    CHECK(memcmp(c, e, 16) != 0);      /* plant and BCU nonce do not commute */
    CHECK(memcmp(a, a + 8, 8) != 0);   /* the two counter blocks differ */
    uint64_t n1 = rb_hil_plant_nonce(KEY, 5, 1), n2 = rb_hil_plant_nonce(KEY, 5, 2);
    CHECK(n1 != 0 && n2 != 0 && n1 != n2 && n1 == rb_hil_plant_nonce(KEY, 5, 1));
    CHECK(n1 != rb_hil_plant_nonce(KEY, 6, 1) && n1 != rb_hil_plant_nonce(other, 5, 1));
}

/* The tag: any changed bit of header or payload, or another key, fails it; a challenge is header only. */
static void test_tag(void)
{
    rb_plant_frame f = sample_plant();
    uint8_t buf[1024], other[16];
    size_t n = 0;
    memcpy(other, KEY, 16);
    other[0] ^= 0x80;
    CHECK(rb_plant_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_frame_authentic(buf, n, KEY) == 1 && rb_frame_authentic(buf, n, other) == 0);
    int failed = 0;
    for (size_t i = 0; i < n - RB_FRAME_TRAILER_SIZE; ++i) {
        buf[i] ^= 0x01;
        failed += !rb_frame_authentic(buf, n, KEY);
        buf[i] ^= 0x01;
    }
    CHECK(failed == (int)(n - RB_FRAME_TRAILER_SIZE));
    rb_frame_header h = f.header, back;
    h.nonce = 0x1122334455667788ULL;
    h.plant_nonce = 0x99aabbccddeeff00ULL;
    CHECK(rb_challenge_frame_encode(&h, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(n == rb_challenge_frame_size() && n == RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE);
    CHECK(rb_frame_check(buf, n, &back, NULL) == RB_OK && back.type == RB_FRAME_CHALLENGE);
    CHECK(back.nonce == h.nonce && back.plant_nonce == h.plant_nonce && back.session == h.session && rb_frame_authentic(buf, n, KEY));
    rb_error err;
    CHECK(rb_plant_frame_encode(&f, NULL, buf, sizeof buf, &n, &err) == RB_EINVAL && strstr(err.message, "key"));
}

static void test_plant_round_trip_and_corruption(void)
{
    rb_plant_frame f = sample_plant(), back;
    uint8_t buf[1024];
    size_t n = 0;
    CHECK(rb_plant_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(n == rb_plant_frame_size(8, 32));
    CHECK(rb_plant_frame_decode(buf, n, &back, NULL) == RB_OK);
    CHECK(back.header.step == f.header.step && back.header.sequence == 41);
    CHECK(back.header.session == 0xfeedbeefu && back.header.config == 0x12345678u);
    CHECK(memcmp(back.wheel_speed, f.wheel_speed, 32 * sizeof(float)) == 0);
    CHECK(back.supply_pressure[7] == f.supply_pressure[7]);

    int rejected = 0;
    for (size_t i = 0; i < n; ++i) {          /* any single flipped bit is caught */
        buf[i] ^= 0x10;
        rejected += rb_plant_frame_decode(buf, n, &back, NULL) != RB_OK || !rb_frame_authentic(buf, n, KEY);
        buf[i] ^= 0x10;
    }
    CHECK(rejected == (int)n);
    rb_error err;
    CHECK(rb_plant_frame_decode(buf, n - 1, &back, &err) != RB_OK);
    CHECK(strstr(err.message, "size") != NULL);
    CHECK(rb_plant_frame_encode(&f, KEY, buf, 10, &n, &err) == RB_ESIZE);
    /* only payload_size wrong: the message says which field, not "size = N: expected N" */
    CHECK(rb_plant_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    buf[6] ^= 1;
    uint32_t crc = rb_crc32(buf, n - RB_FRAME_TRAILER_SIZE);
    for (int k = 0; k < 4; ++k) buf[n - RB_FRAME_TRAILER_SIZE + (size_t)k] = (uint8_t)(crc >> (8 * k));
    CHECK(rb_plant_frame_decode(buf, n, &back, &err) != RB_OK);
    CHECK(strstr(err.message, "payload_size = ") == err.message);
    /* a session of 0 is no session */
    f.header.session = 0;
    CHECK(rb_plant_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_plant_frame_decode(buf, n, &back, &err) != RB_OK && strstr(err.message, "session = 0"));
}

static void test_config_digest(void)
{
    uint32_t d = rb_hil_config_digest("velaro-8", 8, 32, 1e-3);
    CHECK(d == rb_crc32((const uint8_t *)"railbrake-hil/2 train=velaro-8 cars=8 axles=32 step_us=1000", 59));
    CHECK(d != rb_hil_config_digest("velaro-8", 4, 16, 1e-3));
    CHECK(d != rb_hil_config_digest("crh380a-8", 8, 32, 1e-3));
    CHECK(d != rb_hil_config_digest("velaro-8", 8, 32, 2e-3));
}

static void test_bcu_validation(void)
{
    rb_bcu_frame f, back;
    memset(&f, 0, sizeof f);
    f.header.session = 7;
    f.header.n_cars = 2;
    f.header.n_axles = 8;
    f.brake_demand = 1.5f;
    f.pressure_demand[1] = 4e5f;
    f.vent[3] = 1;
    uint8_t buf[1024];
    size_t n;
    CHECK(rb_bcu_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, NULL) == RB_OK);
    CHECK(back.vent[3] == 1 && back.hold[3] == 0 && back.pressure_demand[1] == 4e5f);

    rb_error err;
    f.brake_demand = NAN;
    CHECK(rb_bcu_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "brake_demand") != NULL);
    f.brake_demand = 1.0f;
    f.hold[0] = 7;
    CHECK(rb_bcu_frame_encode(&f, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "hold[0]") != NULL);
    /* A plant frame is not a BCU frame. */
    rb_plant_frame p = sample_plant();
    CHECK(rb_plant_frame_encode(&p, KEY, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "type") != NULL);
}

static void test_garbage_never_crashes(void)
{
    uint8_t buf[600];
    rb_bcu_frame back;
    unsigned seed = 12345u;
    int accepted = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        size_t n = (size_t)(trial % 600);
        for (size_t i = 0; i < n; ++i) { seed = seed * 1103515245u + 12345u; buf[i] = (uint8_t)(seed >> 16); }
        accepted += rb_bcu_frame_decode(buf, n, &back, NULL) == RB_OK;
    }
    CHECK(accepted == 0);
}

int main(void)
{
    test_crc_reference();
    test_siphash_vectors();
    test_session_keys();
    test_tag();
    test_config_digest();
    test_plant_round_trip_and_corruption();
    test_bcu_validation();
    test_garbage_never_crashes();
    return rb_test_summary("test_hil_frame");
}

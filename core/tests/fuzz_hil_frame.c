/* Fuzz target for the HIL frame decoder (core/src/hil_frame.c, docs/hil-interface.md).
 *
 * LLVMFuzzerTestOneInput decodes the input as a plant frame and as a BCU frame; whatever decodes
 * must hold what the ICD promises (counts in range, finite values, BCU values in their ranges,
 * booleans 0/1) and must re-encode to the very same bytes. Any violation aborts; the sanitizers
 * catch the rest.
 *
 * Built two ways (Makefile `fuzz-frames`): with clang's libFuzzer (-DRB_LIBFUZZER
 * -fsanitize=fuzzer,address,undefined), or, where clang is missing, with gcc and the mutational loop
 * below (seeds: valid frames of several sizes; mutations: bit flips, byte values, truncation,
 * extension, splices, and a recomputed CRC half of the time so the checks behind the CRC are
 * reached). core/tests/test_hil_frame_fuzz.c runs that loop as a bounded smoke test (ctest, also
 * under the sanitizers). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "railbrake/rb_hil_frame.h"

#define FUZZ_MAX 1024

static const uint8_t KEY[RB_HIL_KEY_SIZE] = {3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5, 8, 9, 7, 9, 3};

/* Re-encoded bytes equal the input's but for the reserved u16 (not kept) and the trailer (the CRC
 * covers the reserved bytes; the input's tag need not authenticate: the decoder leaves that to
 * rb_frame_authentic). */
static int same_bytes(const uint8_t *again, const uint8_t *data, size_t size)
{
    return memcmp(again, data, 30) == 0 &&
           memcmp(again + 32, data + 32, size - 32 - RB_FRAME_TRAILER_SIZE) == 0;
}

static void fail(const char *what)
{
    fprintf(stderr, "hil_frame_fuzz: %s\n", what);
    abort();
}

static void check_plant(const uint8_t *data, size_t size)
{
    rb_plant_frame f;
    if (rb_plant_frame_decode(data, size, &f, NULL) != RB_OK) return;
    const rb_frame_header *h = &f.header;
    if (h->n_cars < 1 || h->n_cars > RB_FRAME_MAX_CARS || h->n_axles < 1 || h->n_axles > RB_FRAME_MAX_AXLES)
        fail("plant frame accepted with counts out of range");
    if (h->session == 0) fail("plant frame accepted with session 0");
    if (size != rb_plant_frame_size(h->n_cars, h->n_axles)) fail("plant frame accepted with a wrong size");
    if (!isfinite(f.train_speed) || !isfinite(f.position) || !isfinite(f.main_reservoir_pressure))
        fail("plant frame accepted with a non-finite value");
    for (int i = 0; i < h->n_axles; ++i)
        if (!isfinite(f.wheel_speed[i]) || !isfinite(f.cylinder_pressure[i])) fail("non-finite axle value");
    uint8_t again[FUZZ_MAX];
    size_t n = 0;
    if (rb_plant_frame_encode(&f, KEY, again, sizeof again, &n, NULL) != RB_OK || n != size)
        fail("accepted plant frame does not re-encode");
    if (!same_bytes(again, data, size))
        fail("accepted plant frame re-encodes to other bytes");
}

static void check_bcu(const uint8_t *data, size_t size)
{
    rb_bcu_frame f;
    if (rb_bcu_frame_decode(data, size, &f, NULL) != RB_OK) return;
    const rb_frame_header *h = &f.header;
    if (h->n_cars < 1 || h->n_cars > RB_FRAME_MAX_CARS || h->n_axles < 1 || h->n_axles > RB_FRAME_MAX_AXLES)
        fail("BCU frame accepted with counts out of range");
    if (!(f.brake_demand >= 0.0f && f.brake_demand <= 2.0f)) fail("brake_demand out of range accepted");
    for (int i = 0; i < h->n_cars; ++i)
        if (!(f.pressure_demand[i] >= 0.0f && f.pressure_demand[i] <= 2e6f)) fail("pressure_demand out of range");
    for (int i = 0; i < h->n_axles; ++i)
        if (f.hold[i] > 1 || f.vent[i] > 1) fail("hold/vent not 0 or 1 accepted");
    uint8_t again[FUZZ_MAX];
    size_t n = 0;
    if (rb_bcu_frame_encode(&f, KEY, again, sizeof again, &n, NULL) != RB_OK || n != size)
        fail("accepted BCU frame does not re-encode");
    if (!same_bytes(again, data, size))
        fail("accepted BCU frame re-encodes to other bytes");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > FUZZ_MAX) return 0;
    check_plant(data, size);
    check_bcu(data, size);
    return 0;
}

/* ---- the mutational loop (no libFuzzer) */

static uint64_t rng = 88172645463325252ULL;
static uint32_t next_random(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

/* A valid frame: plant or BCU, n_cars 1..16, random values (some outside the ranges). */
static size_t seed_frame(uint8_t *buf)
{
    int n_cars = 1 + (int)(next_random() % RB_FRAME_MAX_CARS);
    int n_axles = next_random() % 4 ? 4 * n_cars : 1 + (int)(next_random() % RB_FRAME_MAX_AXLES);
    size_t size = 0;
    rb_frame_header h = {1 + next_random(), next_random(), next_random(), (uint64_t)next_random() << (next_random() % 32),
                         next_random(), next_random(), (uint8_t)n_cars, (uint8_t)n_axles, 0};
    if (next_random() % 2) {
        rb_plant_frame f;
        memset(&f, 0, sizeof f);
        f.header = h;
        f.train_speed = (float)(next_random() % 100);
        for (int i = 0; i < n_axles; ++i) f.wheel_speed[i] = (float)(next_random() % 100), f.cylinder_pressure[i] = 3e5f;
        for (int i = 0; i < n_cars; ++i) f.supply_pressure[i] = 5e5f;
        rb_plant_frame_encode(&f, KEY, buf, FUZZ_MAX, &size, NULL);
    } else {
        rb_bcu_frame f;
        memset(&f, 0, sizeof f);
        f.header = h;
        f.brake_demand = (float)(next_random() % 3);
        for (int i = 0; i < n_cars; ++i) f.pressure_demand[i] = (float)(next_random() % 3000000);
        for (int i = 0; i < n_axles; ++i) f.hold[i] = (uint8_t)(next_random() % 2), f.vent[i] = (uint8_t)(next_random() % 2);
        rb_bcu_frame_encode(&f, KEY, buf, FUZZ_MAX, &size, NULL);
    }
    return size;
}

static void put_special(uint8_t *buf, size_t size)
{
    static const float special[] = {NAN, INFINITY, -INFINITY, -1.0f, 3e6f, 2.5f};
    if (size <= RB_FRAME_HEADER_SIZE + 4) return;
    size_t at = RB_FRAME_HEADER_SIZE + 4 * (next_random() % ((size - RB_FRAME_HEADER_SIZE) / 4));
    if (at + 4 <= size) memcpy(buf + at, &special[next_random() % 6], 4);
}

static size_t mutate(uint8_t *buf, size_t size)
{
    int rounds = 1 + (int)(next_random() % 4);
    for (int k = 0; k < rounds; ++k) {
        switch (next_random() % 6) {
        case 0:
            if (size) buf[next_random() % size] ^= (uint8_t)(1u << (next_random() % 8));
            break;
        case 1:
            if (size) buf[next_random() % size] = (uint8_t)next_random();
            break;
        case 2:
            size = size ? next_random() % size : 0;
            break;
        case 3: {
            size_t extra = next_random() % 16;
            for (size_t i = 0; i < extra && size < FUZZ_MAX; ++i) buf[size++] = (uint8_t)next_random();
            break;
        }
        case 4:
            if (size >= 8) {
                uint32_t v = next_random();
                memcpy(buf + 4 * (next_random() % (size / 4)), &v, 4);
            }
            break;
        default:
            put_special(buf, size);
        }
    }
    if (size >= RB_FRAME_HEADER_SIZE + RB_FRAME_TRAILER_SIZE && next_random() % 2) {   /* reach behind the CRC */
        size_t body = size - RB_FRAME_TRAILER_SIZE;
        uint32_t crc = rb_crc32(buf, body);
        for (int i = 0; i < 4; ++i) buf[body + (size_t)i] = (uint8_t)(crc >> (8 * i));
    }
    return size;
}

/* Runs `iterations` mutated inputs; returns how many decoded as a frame of either type. */
long rb_hil_frame_fuzz_loop(long iterations, uint64_t seed);
long rb_hil_frame_fuzz_loop(long iterations, uint64_t seed)
{
    uint8_t buf[FUZZ_MAX];
    long accepted = 0;
    rng ^= seed * 0x9E3779B97F4A7C15ULL;
    if (!rng) rng = 1;
    for (long i = 0; i < iterations; ++i) {
        size_t size = mutate(buf, seed_frame(buf));
        rb_plant_frame p;
        rb_bcu_frame b;
        accepted += rb_plant_frame_decode(buf, size, &p, NULL) == RB_OK || rb_bcu_frame_decode(buf, size, &b, NULL) == RB_OK;
        LLVMFuzzerTestOneInput(buf, size);
    }
    return accepted;
}

#if !defined(RB_LIBFUZZER) && !defined(RB_FUZZ_NO_MAIN)
int main(int argc, char **argv)
{
    long iterations = argc > 1 ? atol(argv[1]) : 1000000;
    uint64_t seed = argc > 2 ? strtoull(argv[2], NULL, 10) : 1;
    long accepted = rb_hil_frame_fuzz_loop(iterations, seed);
    printf("hil_frame_fuzz: %ld inputs, %ld decoded as a frame, 0 violations\n", iterations, accepted);
    /* the line tools/fuzz_record.py keeps for docs/robustness.md (a violation aborts before it) */
    printf("fuzz-result {\"target\": \"frames\", \"inputs\": %ld, \"decoded\": %ld, \"violations\": 0, "
           "\"seed\": %llu, \"engine\": \"mutational loop\"}\n", iterations, accepted, (unsigned long long)seed);
    return 0;
}
#endif

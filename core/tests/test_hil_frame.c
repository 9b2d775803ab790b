/* HIL frames: round trip, CRC reference value, and every corruption rejected without a crash. */
#include "rb_test.h"
#include "railbrake/rb_hil_frame.h"

#include <stdlib.h>

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

static void test_plant_round_trip_and_corruption(void)
{
    rb_plant_frame f = sample_plant(), back;
    uint8_t buf[1024];
    size_t n = 0;
    CHECK(rb_plant_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(n == rb_plant_frame_size(8, 32));
    CHECK(rb_plant_frame_decode(buf, n, &back, NULL) == RB_OK);
    CHECK(back.header.step == f.header.step && back.header.sequence == 41);
    CHECK(back.header.session == 0xfeedbeefu && back.header.config == 0x12345678u);
    CHECK(memcmp(back.wheel_speed, f.wheel_speed, 32 * sizeof(float)) == 0);
    CHECK(back.supply_pressure[7] == f.supply_pressure[7]);

    int rejected = 0;
    for (size_t i = 0; i < n; ++i) {          /* any single flipped bit is caught */
        buf[i] ^= 0x10;
        rejected += rb_plant_frame_decode(buf, n, &back, NULL) != RB_OK;
        buf[i] ^= 0x10;
    }
    CHECK(rejected == (int)n);
    rb_error err;
    CHECK(rb_plant_frame_decode(buf, n - 1, &back, &err) != RB_OK);
    CHECK(strstr(err.message, "size") != NULL);
    CHECK(rb_plant_frame_encode(&f, buf, 10, &n, &err) == RB_ESIZE);
    /* only payload_size wrong: the message says which field, not "size = N: expected N" */
    CHECK(rb_plant_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
    buf[6] ^= 1;
    uint32_t crc = rb_crc32(buf, n - 4);
    for (int k = 0; k < 4; ++k) buf[n - 4 + (size_t)k] = (uint8_t)(crc >> (8 * k));
    CHECK(rb_plant_frame_decode(buf, n, &back, &err) != RB_OK);
    CHECK(strstr(err.message, "payload_size = ") == err.message);
    /* a session of 0 is no session */
    f.header.session = 0;
    CHECK(rb_plant_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
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
    CHECK(rb_bcu_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, NULL) == RB_OK);
    CHECK(back.vent[3] == 1 && back.hold[3] == 0 && back.pressure_demand[1] == 4e5f);

    rb_error err;
    f.brake_demand = NAN;
    CHECK(rb_bcu_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "brake_demand") != NULL);
    f.brake_demand = 1.0f;
    f.hold[0] = 7;
    CHECK(rb_bcu_frame_encode(&f, buf, sizeof buf, &n, NULL) == RB_OK);
    CHECK(rb_bcu_frame_decode(buf, n, &back, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "hold[0]") != NULL);
    /* A plant frame is not a BCU frame. */
    rb_plant_frame p = sample_plant();
    CHECK(rb_plant_frame_encode(&p, buf, sizeof buf, &n, NULL) == RB_OK);
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
    test_config_digest();
    test_plant_round_trip_and_corruption();
    test_bcu_validation();
    test_garbage_never_crashes();
    return rb_test_summary("test_hil_frame");
}

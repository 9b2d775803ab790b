/* HIL runner and reference BCU on loopback: the closed loop against the model-in-the-loop run,
 * the safe state against the BCU's demand law, hostile frames, pacing. */
#define _GNU_SOURCE   /* sendmmsg: the flooder sends in batches */
#include "plant_fixture.h"
#include "rb_test.h"
#include "railbrake/rb_hil.h"

#include <math.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

static rb_plant_params plant;
static rb_bcu_params bcu;
static rb_hil_config config;
static rb_hil_runner runner;
static rb_hil_bcu server;
static rb_run_state mil;
static const rb_scenario scenario = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1};
#define SESSION 0x5e55104du

static uint32_t digest(int n_cars) { return rb_hil_config_digest("fixture", n_cars, 4 * n_cars, 1e-3); }

static void setup(int n_cars, double speed)
{
    rb_plant_params *p = &plant;
    fill_plant(p, n_cars, speed);
    memset(&bcu, 0, sizeof bcu);
    bcu.n_cars = n_cars; bcu.cycle = 0.01; bcu.atmosphere = p->atmosphere;
    bcu.service_decel = 1.0; bcu.emergency_decel = 1.2; bcu.wsp_enabled = 1;
    rb_bcu_pressure_map(p, p->atmosphere + 3.8e5, &bcu);
    memset(&config, 0, sizeof config);
    config.hold_time = 0.05; config.late_time = 0.02; config.duration = 10.0;
    config.stop_speed = 0.05; config.record_interval = 0.01; config.adhesion_interval = scenario.adhesion_interval;
    config.session = SESSION; config.config = digest(n_cars);
    CHECK(rb_hil_safe_state(&bcu, &config.safe, NULL) == RB_OK);
}

/* The safe state is the BCU's emergency demand: offset + gain * decel * mass (capped), valves off. */
static void test_safe_state(void)
{
    setup(2, 50.0);
    for (int c = 0; c < 2; ++c) {
        double expected = bcu.pressure_offset[c] + bcu.pressure_gain[c] * bcu.emergency_decel * bcu.car_mass[c];
        CHECK_CLOSE(config.safe.pressure_demand[c], fmin(expected, bcu.pressure_max[c]), 1e-12, 0);
        CHECK(config.safe.pressure_demand[c] > bcu.atmosphere + 1e5);
    }
    for (int a = 0; a < 8; ++a) CHECK(config.safe.hold[a] == 0 && config.safe.vent[a] == 0);
    rb_error err;
    plant.dt = 2e-3;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "plant.dt") != NULL);
    plant.dt = 1e-3;
    config.hold_time = -1.0;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "hold_time") != NULL);
}

/* Plant and reference BCU interleaved step by step (unpaced): the loop closes over UDP with one
 * step of transport delay and float32 frames, so the speed follows the MIL run closely. */
static void test_loop_matches_mil(void)
{
    setup(1, 100 / 3.6);
    rb_error err;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(bcu.n_cars), "127.0.0.1", 0, &server, &err) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_hil_bcu_port(&server), &runner,
                             &err) == RB_OK);
    int finished = 0, bcu_finished = 0;
    for (int i = 0; i < 3000 && !finished; ++i) {
        CHECK(rb_hil_runner_advance(&plant, &config, &runner, 1, NULL, 0, NULL, &finished, &err) == RB_OK);
        rb_hil_bcu_serve(&bcu, &scenario, &server, 0.0, 0.0, 1.0, &bcu_finished, &err);
    }
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(rb_run_init(&plant, &bcu, NULL, &scenario, &mil, &err) == RB_OK);
    CHECK(rb_run_advance(&plant, &bcu, &scenario, &mil, res.time, NULL, 0, NULL, &err) == RB_OK);
    printf("loop at %.3f s: HIL %.5f m/s, MIL %.5f m/s; received %llu, safe steps %llu, BCU cycles %llu\n",
           res.time, runner.out.speed, mil.out.speed, (unsigned long long)res.received,
           (unsigned long long)res.safe_state_steps, (unsigned long long)server.cycles);
    CHECK_CLOSE(res.time, 3.0, 0, 1e-9);
    CHECK_CLOSE(runner.out.speed, mil.out.speed, 2e-3, 0);
    CHECK(res.malformed == 0 && res.lost == 0 && res.late == 0);
    CHECK(res.received + 1 == server.sent && server.cycles == 301);   /* the last answer is in flight */
    CHECK(res.safe_state_steps == 1);          /* step 0 only: no BCU frame yet */
    CHECK(server.malformed == 0 && server.received == res.frames_sent);
    CHECK(res.braking && !bcu_finished);
    /* the KPIs by the MIL run's own accumulation: the same to the loop's transport delay */
    rb_kpis hil_k, mil_k;
    rb_hil_runner_kpis(&plant, &runner, &hil_k);
    rb_run_kpis(&plant, &mil, &mil_k);
    printf("KPIs HIL / MIL: distance %.4f / %.4f m, adhesion utilisation %.4f / %.4f, air vented %.3g / %.3g kg\n",
           hil_k.stopping_distance_m, mil_k.stopping_distance_m, hil_k.adhesion_utilisation,
           mil_k.adhesion_utilisation, hil_k.air_consumed_kg, mil_k.air_consumed_kg);
    CHECK_CLOSE(hil_k.stopping_distance_m, res.stopping_distance, 1e-12, 0);
    CHECK_CLOSE(hil_k.stopping_distance_m, mil_k.stopping_distance_m, 1e-3, 0);
    CHECK_CLOSE(hil_k.mean_deceleration, mil_k.mean_deceleration, 2e-2, 0);
    CHECK_CLOSE(hil_k.adhesion_utilisation, mil_k.adhesion_utilisation, 2e-2, 0);
    CHECK_CLOSE(hil_k.air_consumed_kg, mil_k.air_consumed_kg, 2e-2, 1e-9);
    CHECK(hil_k.air_balance_error < 1e-9 && hil_k.adhesion_utilisation > 0.0);
    rb_hil_runner_close(&runner);
    rb_hil_bcu_close(&server);
}

static void send_raw(rb_udp *peer, const uint8_t *data, size_t size)
{
    CHECK(rb_udp_send(peer, data, size) == (long)size);
}

static void valid_frame(uint8_t *buf, size_t *size, uint32_t sequence, uint64_t step, int n_cars, float demand)
{
    rb_bcu_frame f;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){SESSION, config.config, sequence, step, (uint8_t)n_cars, (uint8_t)(4 * n_cars)};
    for (int c = 0; c < n_cars; ++c) f.pressure_demand[c] = demand;
    CHECK(rb_bcu_frame_encode(&f, buf, 1024, size, NULL) == RB_OK);
}

static void step_runner(int steps)
{
    int finished;
    CHECK(rb_hil_runner_advance(&plant, &config, &runner, (uint64_t)steps, NULL, 0, NULL, &finished, NULL) == RB_OK);
}

/* Garbage is counted as malformed and never applied; the safe state follows the hold time. */
static void test_hostile_frames(void)
{
    setup(1, 30.0);
    rb_udp peer;
    uint8_t buf[1024];
    size_t size;
    CHECK(rb_udp_open(&peer, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_udp_local_port(&peer), &runner,
                             NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&peer, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    step_runner(1);
    valid_frame(buf, &size, 1, 1, 1, 2e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    /* bad CRC, wrong counts, NaN, random bytes, an echo from the future, an oversize datagram */
    valid_frame(buf, &size, 2, 1, 1, 2e5f);
    buf[30] ^= 0x40;
    send_raw(&peer, buf, size);
    valid_frame(buf, &size, 3, 1, 2, 2e5f);
    send_raw(&peer, buf, size);
    valid_frame(buf, &size, 4, 1, 1, NAN);
    send_raw(&peer, buf, size);
    for (size_t i = 0; i < 100; ++i) buf[i] = (uint8_t)(i * 37 + 11);
    send_raw(&peer, buf, 100);
    valid_frame(buf, &size, 5, 1000, 1, 2e5f);
    send_raw(&peer, buf, size);
    static uint8_t big[4000];
    send_raw(&peer, big, sizeof big);
    send_raw(&peer, big, 0);
    step_runner(1);
    CHECK(runner.watchdog.malformed == 7 && runner.watchdog.received == 1);
    CHECK(runner.events == 8);   /* safe state left, then the seven */
    rb_hil_event e;
    CHECK(rb_hil_runner_event(&runner, 1, &e) == 1 && strstr(e.text, "crc") != NULL);
    CHECK(rb_hil_runner_event(&runner, 3, &e) == 1 && strstr(e.text, "pressure_demand") != NULL);
    /* still held: the last valid frame came at step 1; hold 50 steps */
    step_runner(47);
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    step_runner(3);
    CHECK(runner.safe && runner.applied.pressure_demand[0] == config.safe.pressure_demand[0]);
    CHECK(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_SAFE_ON);
    /* a sequence gap counts as lost; an old echo as late (not applied) */
    valid_frame(buf, &size, 9, runner.step, 1, 3e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(runner.watchdog.lost == 7 && !runner.safe && runner.applied.pressure_demand[0] == 3e5);
    valid_frame(buf, &size, 10, 1, 1, 4e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(runner.watchdog.late == 1 && runner.applied.pressure_demand[0] == 3e5);
    rb_hil_runner_close(&runner);
    rb_udp_close(&peer);
}

static size_t session_frame(uint8_t *buf, uint32_t session, uint64_t step, int n_cars)
{
    rb_plant_frame f;
    size_t size = 0;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){session, digest(n_cars), (uint32_t)step, step, (uint8_t)n_cars,
                                 (uint8_t)(4 * n_cars)};
    f.train_speed = 30.0f;
    for (int a = 0; a < 4 * n_cars; ++a) f.wheel_speed[a] = 30.0f, f.cylinder_pressure[a] = 1.01325e5f;
    for (int c = 0; c < n_cars; ++c) f.supply_pressure[c] = 5.5e5f;
    CHECK(rb_plant_frame_encode(&f, buf, 1024, &size, NULL) == RB_OK);
    return size;
}

static size_t plant_frame(uint8_t *buf, uint64_t step, int n_cars) { return session_frame(buf, SESSION, step, n_cars); }

/* The reference BCU drops garbage, refuses frames of another train (answering with its own digest),
 * ignores repeated steps (stale), and answers each due BCU cycle to the plant of its session. */
static void test_bcu_server_input(void)
{
    setup(1, 30.0);
    rb_udp plant_side;
    uint8_t buf[1024];
    int finished = 0;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(bcu.n_cars), "127.0.0.1", 0, &server, NULL) == RB_OK);
    CHECK(rb_udp_open(&plant_side, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&plant_side, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    send_raw(&plant_side, (const uint8_t *)"garbage", 7);
    send_raw(&plant_side, buf, plant_frame(buf, 0, 2));           /* two cars: not this train */
    send_raw(&plant_side, buf, plant_frame(buf, 0, 1));
    send_raw(&plant_side, buf, plant_frame(buf, 0, 1));           /* the same step again */
    send_raw(&plant_side, buf, plant_frame(buf, 5, 1));           /* inside the first BCU cycle */
    send_raw(&plant_side, buf, plant_frame(buf, 10, 1));          /* the next cycle */
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 0.05, 0.0, 1.0, &finished, NULL) == RB_OK);
    uint64_t c[RB_HIL_BCU_COUNTERS];
    rb_hil_bcu_counters(&server, c);
    CHECK(c[0] == 4 && c[1] == 1 && c[2] == 1);                   /* received, malformed, stale */
    CHECK(c[3] == 3 && c[5] == 2 && c[6] == 0 && c[7] == 1);      /* sent, cycles, foreign, refused */
    rb_bcu_frame answer;
    long n = rb_udp_recv(&plant_side, buf, sizeof buf);            /* the refusal: this BCU's digest */
    CHECK(n > 0 && rb_bcu_frame_decode(buf, (size_t)n, &answer, NULL) == RB_OK);
    CHECK(answer.header.config == digest(1) && answer.header.session == SESSION && answer.header.n_cars == 1);
    uint32_t refused_config = 0;
    int cars = 0, axles = 0;
    char from[32];
    CHECK(rb_hil_bcu_refusal(&server, &refused_config, &cars, &axles, from, sizeof from) == 1);
    CHECK(refused_config == digest(2) && cars == 2 && axles == 8 && strncmp(from, "127.0.0.1:", 10) == 0);
    n = rb_udp_recv(&plant_side, buf, sizeof buf);
    CHECK(n > 0 && rb_bcu_frame_decode(buf, (size_t)n, &answer, NULL) == RB_OK);
    CHECK(answer.header.step == 0 && answer.brake_demand == 2.0f);
    CHECK(answer.pressure_demand[0] == (float)config.safe.pressure_demand[0]);   /* emergency, no WSP action */
    CHECK(!finished);
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 2.0, 0.0, 0.1, &finished, NULL) == RB_OK);
    CHECK(finished);                                              /* idle for 0.1 s after the last frame */
    rb_udp_close(&plant_side);
    rb_hil_bcu_close(&server);
}

/* Hostile peers against the BCU: a CRC-valid plant frame with step 2^64 - 1 from another address,
 * or from the plant's own address and session, or a frame of another session, is foreign: the BCU
 * keeps serving its plant, no other counter moves. */
static void test_bcu_keeps_its_plant(void)
{
    setup(1, 30.0);
    rb_udp plant_side, hostile;
    uint8_t buf[1024];
    int finished = 0;
    uint64_t c[RB_HIL_BCU_COUNTERS], before[RB_HIL_BCU_COUNTERS];
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(1), "127.0.0.1", 0, &server, NULL) == RB_OK);
    CHECK(rb_udp_open(&plant_side, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_open(&hostile, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&plant_side, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&hostile, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    send_raw(&plant_side, buf, plant_frame(buf, 0, 1));
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 0.02, 0.0, 5.0, &finished, NULL) == RB_OK);
    rb_hil_bcu_counters(&server, before);
    send_raw(&hostile, buf, plant_frame(buf, UINT64_MAX, 1));              /* another address */
    send_raw(&hostile, buf, session_frame(buf, 0x0badf00du, UINT64_MAX, 1));
    send_raw(&plant_side, buf, plant_frame(buf, UINT64_MAX, 1));           /* spoofed: a forged jump */
    send_raw(&plant_side, buf, session_frame(buf, 0x0badf00du, 20, 1));    /* another session */
    send_raw(&hostile, (const uint8_t *)"garbage", 7);
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 0.02, 0.0, 5.0, &finished, NULL) == RB_OK);
    rb_hil_bcu_counters(&server, c);
    CHECK(c[6] == before[6] + 5);
    for (int k = 0; k < 6; ++k) CHECK(c[k] == before[k]);
    CHECK(c[7] == 0 && server.udp.have_peer && server.session == SESSION);
    /* the plant's next frames are served: received, a cycle, an answer to the plant */
    for (uint64_t step = 10; step <= 30; step += 10) send_raw(&plant_side, buf, plant_frame(buf, step, 1));
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 0.02, 0.0, 5.0, &finished, NULL) == RB_OK);
    rb_hil_bcu_counters(&server, c);
    CHECK(c[0] == before[0] + 3 && c[2] == before[2] && c[5] == before[5] + 3);
    int answers = 0;
    for (long n; (n = rb_udp_recv_from(&plant_side, buf, sizeof buf, (uint8_t[16]){0})) > 0;) answers++;
    CHECK(answers == 4);    /* the first cycle and the three since */
    CHECK(rb_udp_recv_from(&hostile, buf, sizeof buf, (uint8_t[16]){0}) == 0);   /* nothing to the hostile */
    rb_udp_close(&plant_side);
    rb_udp_close(&hostile);
    rb_hil_bcu_close(&server);
}

/* Foreign datagrams at the plant (another address, another session) are counted as foreign and
 * touch nothing else: no lost frames from their sequence numbers, no command applied. */
static void test_plant_takes_only_its_bcu(void)
{
    setup(1, 30.0);
    rb_udp bcu_side, hostile;
    uint8_t buf[1024];
    size_t size;
    CHECK(rb_udp_open(&bcu_side, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_open(&hostile, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_udp_local_port(&bcu_side), &runner,
                             NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&bcu_side, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&hostile, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    step_runner(1);
    valid_frame(buf, &size, 1, 1, 1, 2e5f);
    send_raw(&bcu_side, buf, size);
    step_runner(1);
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    valid_frame(buf, &size, 0x80000000u, runner.step, 1, 6e5f);      /* a recent echo, a huge sequence jump */
    send_raw(&hostile, buf, size);
    send_raw(&hostile, (const uint8_t *)"garbage", 7);
    rb_bcu_frame f;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){0x0badf00du, digest(1), 2, runner.step, 1, 4};
    f.pressure_demand[0] = 6e5f;
    CHECK(rb_bcu_frame_encode(&f, buf, sizeof buf, &size, NULL) == RB_OK);
    send_raw(&bcu_side, buf, size);                                   /* the BCU's address, another session */
    step_runner(1);
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(res.foreign == 3 && res.received == 1 && res.lost == 0 && res.late == 0 && res.malformed == 0);
    CHECK(runner.applied.pressure_demand[0] == 2e5);
    CHECK(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_FOREIGN);
    CHECK(strstr(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].text, "not the BCU's address") != NULL);
    valid_frame(buf, &size, 2, runner.step, 1, 3e5f);
    send_raw(&bcu_side, buf, size);
    step_runner(1);
    rb_hil_runner_result(&runner, &res);
    CHECK(res.received == 2 && res.lost == 0 && runner.applied.pressure_demand[0] == 3e5);
    rb_hil_runner_close(&runner);
    rb_udp_close(&bcu_side);
    rb_udp_close(&hostile);
}

/* A BCU set up for another train: it refuses the plant and says so (refusal), the plant learns
 * why from the refusal frame and ends its run; the BCU reaches its idle timeout without valid frames. */
static void test_mismatch(void)
{
    setup(1, 30.0);
    rb_error err;
    int finished = 0, bcu_finished = 0;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, rb_hil_config_digest("other", 1, 4, 1e-3), "127.0.0.1", 0,
                          &server, &err) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_hil_bcu_port(&server), &runner,
                             &err) == RB_OK);
    for (int i = 0; i < 100 && !finished; ++i) {
        CHECK(rb_hil_runner_advance(&plant, &config, &runner, 1, NULL, 0, NULL, &finished, &err) == RB_OK);
        rb_hil_bcu_serve(&bcu, &scenario, &server, 0.0, 0.0, 0.2, &bcu_finished, &err);
    }
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(finished && res.mismatch && res.bcu_config == rb_hil_config_digest("other", 1, 4, 1e-3));
    CHECK(res.steps < 5 && res.received == 0);
    CHECK(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_MISMATCH);
    CHECK(server.refused >= 1 && server.received == 0 && server.session == 0);
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 2.0, 0.0, 0.2, &bcu_finished, NULL) == RB_OK);
    CHECK(bcu_finished);
    rb_hil_runner_close(&runner);
    rb_hil_bcu_close(&server);
}

/* Paced without any BCU: 1 ms periods, the safe state on every step, the run ends at its duration. */
static void test_paced_without_bcu(void)
{
    setup(1, 30.0);
    config.paced = 1;
    config.duration = 0.1;
    static double series[200 * 64];
    size_t rows = 0;
    int finished = 0;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, NULL) == RB_OK);
    int64_t start = rb_monotonic_ns();
    CHECK(rb_hil_runner_advance(&plant, &config, &runner, 1000, series, 200, &rows, &finished, NULL) == RB_OK);
    double elapsed = (double)(rb_monotonic_ns() - start) * 1e-9;
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    printf("paced 100 steps: %.4f s, wake-up p50 %.0f us, p99 %.0f us, max %.0f us, overruns %llu\n", elapsed,
           res.wakeup_p50_us, res.wakeup_p99_us, res.wakeup_max_us, (unsigned long long)res.overruns);
    CHECK(finished && res.steps == 100 && res.safe_state_steps == 100);
    CHECK(elapsed >= 0.099);
    CHECK(rows == 11);
    int nch = rb_hil_channel_count(1);
    CHECK_CLOSE(series[10 * nch], 0.1, 0, 1e-12);
    CHECK(series[10 * nch + 6] == 1.0);    /* safe_state channel */
    char name[64], unit[16];
    CHECK(rb_hil_channel_info(8, 1, name, sizeof name, unit, sizeof unit, NULL) == RB_OK);
    CHECK(strcmp(name, "pressure_demand_c1") == 0 && strcmp(unit, "Pa") == 0);
    CHECK(series[10 * nch + 8] == config.safe.pressure_demand[0]);
    rb_hil_runner_close(&runner);
}

/* A flood from another process (C: thousands of frames per ms) while the plant runs paced: the
 * loop keeps its steps, every sequence number ends up received or lost, no frame is malformed. */
static void test_flood(void)
{
    enum { FLOOD = 131072 };
    setup(1, 30.0);
    config.paced = 1;
    config.duration = 0.4;
    config.hold_time = 0.1;
    rb_udp peer;
    CHECK(rb_udp_open(&peer, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_udp_local_port(&peer), &runner,
                             NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&peer, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    fflush(stdout);
    pid_t child = fork();
    if (child == 0) {   /* the flooder: valid frames echoing step 0, in batches of 256 per system call */
        enum { BATCH = 256 };
        static uint8_t bufs[BATCH][128];
        struct mmsghdr msgs[BATCH];
        struct iovec iov[BATCH];
        size_t size = 0;
        int64_t start = rb_monotonic_ns();
        for (uint32_t i = 0; i < FLOOD; i += BATCH) {
            for (int k = 0; k < BATCH; ++k) {
                valid_frame(bufs[k], &size, i + (uint32_t)k, 0, 1, 2e5f);
                iov[k] = (struct iovec){bufs[k], size};
                memset(&msgs[k], 0, sizeof msgs[k]);
                msgs[k].msg_hdr.msg_name = peer.peer;
                msgs[k].msg_hdr.msg_namelen = 16;
                msgs[k].msg_hdr.msg_iov = &iov[k];
                msgs[k].msg_hdr.msg_iovlen = 1;
            }
            sendmmsg(peer.fd, msgs, BATCH, 0);
        }
        printf("flood: %.0f frames per ms\n", FLOOD / ((double)(rb_monotonic_ns() - start) * 1e-6));
        fflush(stdout);
        _exit(0);
    }
    int finished = 0, status = 0;
    CHECK(rb_hil_runner_advance(&plant, &config, &runner, 1000, NULL, 0, NULL, &finished, NULL) == RB_OK);
    waitpid(child, &status, 0);
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    printf("flood: received %llu, lost %llu, late %llu, malformed %llu, overruns %llu, work max %.0f us\n",
           (unsigned long long)res.received, (unsigned long long)res.lost, (unsigned long long)res.late,
           (unsigned long long)res.malformed, (unsigned long long)res.overruns, res.work_max_us);
    CHECK(finished && res.steps == 400 && res.malformed == 0);
    /* frames lost before the last one received are counted; the tail after it cannot be known */
    CHECK(res.received + res.lost <= FLOOD && res.received + res.lost > 0);
    CHECK(res.late > 0);                       /* echoes of step 0 grow old: counted, not applied */
    CHECK(runner.safe);                        /* only late frames since: safe state after the hold time */
    rb_hil_runner_close(&runner);
    rb_udp_close(&peer);
}

int main(void)
{
    test_safe_state();
    test_loop_matches_mil();
    test_hostile_frames();
    test_bcu_server_input();
    test_bcu_keeps_its_plant();
    test_plant_takes_only_its_bcu();
    test_mismatch();
    test_paced_without_bcu();
    test_flood();
    return rb_test_summary("test_hil");
}

/* HIL runner and reference BCU on loopback: the closed loop against the model-in-the-loop run,
 * the safe state against the BCU's demand law, the handshake and the tag, hostile and spoofed
 * frames, the sequence under duplication, reordering and replay, the BCU's loss, pacing. */
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
static const rb_scenario scenario = {1, {0.0}, {0.0}, {1.0}, 300.0, 0.05, 1e9, 0.1, 0, {0}};
#define SESSION 0x5e55104du
#define NONCE 0x0123456789abcdefULL
#define PLANT_NONCE 0x0fedcba987654321ULL   /* the fake plant's hello nonce (BCU tests) */
static const uint8_t SECRET[RB_HIL_KEY_SIZE] = {0x52, 0x42, 0x52, 0x4b, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
static const uint8_t WRONG[RB_HIL_KEY_SIZE] = {0x52, 0x42, 0x52, 0x4b, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13};
static const uint8_t COOKIE[RB_HIL_KEY_SIZE] = {9, 9, 9, 9, 8, 8, 8, 8, 7, 7, 7, 7, 6, 6, 6, 6};
static uint8_t session_key[RB_HIL_KEY_SIZE];   /* the fake BCU's (NONCE), as the plant derives it */
static uint64_t agreed_plant_nonce;            /* the plant's nonce of session_key */

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
    memcpy(config.secret, SECRET, sizeof SECRET);
    CHECK(rb_hil_safe_bcu(&bcu, &config.safe, NULL) == RB_OK);
}

/* The BCU's emergency demand of car c by its linear map: offset + gain * decel * mass, capped. */
static double emergency_demand(int c)
{
    return fmin(bcu.pressure_offset[c] + bcu.pressure_gain[c] * bcu.emergency_decel * bcu.car_mass[c],
                bcu.pressure_max[c]);
}

/* The safe state is the BCU's emergency demand (WSP and ED off), valves de-energised. */
static void test_safe_state(void)
{
    setup(2, 50.0);
    CHECK(config.safe.wsp_enabled == 0 && config.safe.ed_in_emergency == 0);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, NULL) == RB_OK);
    for (int c = 0; c < 2; ++c) {
        CHECK_CLOSE(runner.applied.pressure_demand[c], emergency_demand(c), 1e-12, 0);
        CHECK(runner.applied.pressure_demand[c] > bcu.atmosphere + 1e5);
    }
    for (int a = 0; a < 8; ++a) CHECK(runner.applied.hold[a] == 0 && runner.applied.vent[a] == 0);
    rb_hil_runner_close(&runner);
    rb_error err;
    plant.dt = 2e-3;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "plant.dt") != NULL);
    plant.dt = 1e-3;
    config.hold_time = -1.0;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "hold_time") != NULL);
    config.hold_time = 0.05;
    config.safe.wsp_enabled = 1;
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "WSP") != NULL);
}

/* Plant and reference BCU interleaved step by step (unpaced): the loop closes over UDP with one
 * step of transport delay and float32 frames, so the speed follows the MIL run closely. */
static void test_loop_matches_mil(void)
{
    setup(1, 100 / 3.6);
    rb_error err;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(bcu.n_cars), SECRET, COOKIE, "127.0.0.1", 0, &server,
                          &err) == RB_OK);
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
    printf("loop at %.3f s: HIL %.5f m/s, MIL %.5f m/s; received %llu, safe steps %llu, BCU cycles %llu, sent %llu, "
           "received %llu of %llu frames, challenges %llu / %llu\n",
           res.time, runner.out.speed, mil.out.speed, (unsigned long long)res.received,
           (unsigned long long)res.safe_state_steps, (unsigned long long)server.cycles,
           (unsigned long long)server.sent, (unsigned long long)server.received,
           (unsigned long long)res.frames_sent, (unsigned long long)res.challenges,
           (unsigned long long)server.challenges);
    CHECK_CLOSE(res.time, 3.0, 0, 1e-9);
    CHECK_CLOSE(runner.out.speed, mil.out.speed, 2e-3, 0);
    CHECK(res.malformed == 0 && res.lost == 0 && res.late == 0 && res.forged == 0 && res.foreign == 0);
    CHECK(res.duplicate == 0 && res.out_of_order == 0 && res.replayed == 0);
    /* the hellos of steps 0 and 1 are challenged (the plant reads the first challenge in step 2);
     * step 2's frame under the agreed key opens the session and runs a cycle at once, then the
     * cycles follow the plant's grid from step 0 as in MIL (10, 20, ... 3000: its answer in flight) */
    CHECK(res.received + 1 == server.sent && server.cycles == server.sent && server.cycles == 301);
    CHECK(res.challenges == 2 && server.challenges == 2 && res.safe_state_steps == 2 && res.losses == 0);
    CHECK(server.malformed == 0 && server.forged == 0 && server.received + 2 == res.frames_sent);
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

/* The reference BCU runs the WSP controller of the parameters it is opened with: on low adhesion
 * each controller's loop vents, in its own sequence (HIL frames carry no body deceleration: the
 * estimates fall at ref_decel_max), and no wheel locks within the 3 s. */
static int loop_vents(int controller, int conditioning, uint8_t *sequence, int steps)
{
    setup(1, 100 / 3.6);
    plant.condition[0].polach.mu0 = 0.08;   /* emergency 1.2 m/s^2 on adhesion below 0.08 */
    rb_wsp_params wsp;
    rb_wsp_default_params(&wsp);
    wsp.controller = controller;
    wsp.conditioning_mode = conditioning;
    rb_error err;
    CHECK(rb_hil_bcu_open(&bcu, &wsp, &scenario, digest(bcu.n_cars), SECRET, COOKIE, "127.0.0.1", 0, &server,
                          &err) == RB_OK);
    CHECK(server.state.wsp_default.p.controller == controller);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_hil_bcu_port(&server), &runner,
                             &err) == RB_OK);
    int finished = 0, bcu_finished = 0, vents = 0;
    double slowest = 1e9;
    for (int i = 0; i < steps && !finished; ++i) {
        CHECK(rb_hil_runner_advance(&plant, &config, &runner, 1, NULL, 0, NULL, &finished, &err) == RB_OK);
        rb_hil_bcu_serve(&bcu, &scenario, &server, 0.0, 0.0, 1.0, &bcu_finished, &err);
        sequence[i] = 0;
        for (int a = 0; a < 4; ++a) {
            vents += runner.applied.vent[a];
            sequence[i] |= (uint8_t)(runner.applied.vent[a] << a);
            if (runner.out.wheel_speed[a] < slowest) slowest = runner.out.wheel_speed[a];
        }
    }
    CHECK(slowest > 0.5 * runner.out.speed);   /* no wheel locked */
    rb_hil_runner_close(&runner);
    rb_hil_bcu_close(&server);
    return vents;
}

static void test_loop_with_each_controller(void)
{
    enum { STEPS = 3000 };
    static uint8_t seen[4][STEPS];
    const int modes[4][2] = {{RB_WSP_THRESHOLD, 0}, {RB_WSP_SLIP_SETPOINT, 0}, {RB_WSP_DECEL_SLIP_SPEED, 0},
                             {RB_WSP_DECEL_SLIP_SPEED, 1}};
    for (int m = 0; m < 4; ++m) {
        int vents = loop_vents(modes[m][0], modes[m][1], seen[m], STEPS);
        printf("HIL loop, controller %d, conditioning %d: %d axle-steps vented in 3 s\n", modes[m][0], modes[m][1],
               vents);
        CHECK(vents > 100);
        for (int k = 0; k < m; ++k) CHECK(memcmp(seen[k], seen[m], STEPS) != 0);
    }
}

static void send_raw(rb_udp *peer, const uint8_t *data, size_t size)
{
    CHECK(rb_udp_send(peer, data, size) == (long)size);
}

/* A BCU frame of the session under key (the agreed one: session_key). */
static void keyed_frame(uint8_t *buf, size_t *size, uint32_t sequence, uint64_t step, int n_cars, float demand,
                        const uint8_t *key)
{
    rb_bcu_frame f;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){SESSION, config.config, sequence, step, NONCE, agreed_plant_nonce,
                                 (uint8_t)n_cars, (uint8_t)(4 * n_cars), 0};
    for (int c = 0; c < n_cars; ++c) f.pressure_demand[c] = demand;
    CHECK(rb_bcu_frame_encode(&f, key, buf, 1024, size, NULL) == RB_OK);
}

static void valid_frame(uint8_t *buf, size_t *size, uint32_t sequence, uint64_t step, int n_cars, float demand)
{
    keyed_frame(buf, size, sequence, step, n_cars, demand, session_key);
}

static void step_runner(int steps)
{
    int finished;
    CHECK(rb_hil_runner_advance(&plant, &config, &runner, (uint64_t)steps, NULL, 0, NULL, &finished, NULL) == RB_OK);
}

/* The fake BCU's challenge of nonce NONCE echoing plant_nonce (under the hello key). */
static size_t challenge_frame(uint8_t *buf, size_t capacity, uint64_t plant_nonce)
{
    uint8_t hello_key[RB_HIL_KEY_SIZE];
    size_t size = 0;
    rb_frame_header h = {SESSION, config.config, 0, 0, NONCE, plant_nonce, (uint8_t)plant.n_cars,
                         (uint8_t)(4 * plant.n_cars), 0};
    rb_hil_session_key(SECRET, SESSION, 0, 0, hello_key);
    CHECK(rb_challenge_frame_encode(&h, hello_key, buf, capacity, &size, NULL) == RB_OK);
    return size;
}

/* A fake BCU at `peer` answers the plant's hello with a challenge of nonce NONCE echoing the
 * plant's hello nonce, then the plant takes frames under session_key (of both nonces). */
static void handshake(rb_udp *peer)
{
    uint8_t buf[256];
    step_runner(1);
    CHECK(runner.nonce == 0 && runner.hello_nonce != 0);
    agreed_plant_nonce = runner.hello_nonce;
    send_raw(peer, buf, challenge_frame(buf, sizeof buf, agreed_plant_nonce));
    step_runner(1);
    CHECK(runner.nonce == NONCE && runner.key_plant_nonce == agreed_plant_nonce);
    rb_hil_session_key(SECRET, SESSION, agreed_plant_nonce, NONCE, session_key);
}

/* Opens the runner against a fake BCU endpoint (peer) and agrees the session key. */
static void open_against(rb_udp *peer)
{
    CHECK(rb_udp_open(peer, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", rb_udp_local_port(peer), &runner,
                             NULL) == RB_OK);
    CHECK(rb_udp_set_peer(peer, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    handshake(peer);
}

/* Garbage is counted as malformed and never applied; the safe state follows the hold time. */
static void test_hostile_frames(void)
{
    setup(1, 30.0);
    rb_udp peer;
    uint8_t buf[1024];
    size_t size;
    open_against(&peer);
    valid_frame(buf, &size, 0, 1, 1, 2e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    uint64_t events = runner.events, last_valid = runner.step - 1;
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
    CHECK(runner.events == events + 7);
    rb_hil_event e;
    CHECK(rb_hil_runner_event(&runner, events, &e) == 1 && strstr(e.text, "crc") != NULL);
    CHECK(rb_hil_runner_event(&runner, events + 2, &e) == 1 && strstr(e.text, "pressure_demand") != NULL);
    /* still held: the last valid frame came at last_valid; hold 50 steps */
    step_runner((int)(last_valid + 50 - runner.step));
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    step_runner(2);
    CHECK(runner.safe && runner.applied.pressure_demand[0] == emergency_demand(0));
    CHECK(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_SAFE_ON);
    /* no valid frame for the hold time (at least 0.1 s): the plant says hello again with a fresh
     * nonce (a restarted BCU has another nonce; a key the BCU dropped is no use) */
    uint64_t first_hello = agreed_plant_nonce;
    CHECK(runner.nonce == NONCE);
    step_runner((int)(last_valid + 101 - runner.step));
    CHECK(runner.nonce == 0 && runner.hello_nonce != 0 && runner.hello_nonce != first_hello);
    /* the challenge of the first exchange, replayed: refused, no key taken; the real one is taken */
    send_raw(&peer, buf, challenge_frame(buf, sizeof buf, first_hello));
    step_runner(1);
    CHECK(runner.nonce == 0 && runner.challenges_refused == 1);
    handshake(&peer);
    /* under the new key the BCU numbers from 0: a sequence gap counts as lost; an old echo as late */
    valid_frame(buf, &size, 8, runner.step, 1, 3e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(runner.watchdog.lost == 8 && !runner.safe && runner.applied.pressure_demand[0] == 3e5);
    valid_frame(buf, &size, 9, 1, 1, 4e5f);
    send_raw(&peer, buf, size);
    step_runner(1);
    CHECK(runner.watchdog.late == 1 && runner.applied.pressure_demand[0] == 3e5);
    rb_hil_runner_close(&runner);
    rb_udp_close(&peer);
}

/* A plant frame of `session` under nonce (0: hello) and the key derived from secret. */
static size_t keyed_plant_frame(uint8_t *buf, uint32_t session, uint64_t step, int n_cars, uint64_t nonce,
                                const uint8_t *secret)
{
    rb_plant_frame f;
    uint8_t key[RB_HIL_KEY_SIZE];
    size_t size = 0;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){session, digest(n_cars), (uint32_t)step, step, nonce, PLANT_NONCE,
                                 (uint8_t)n_cars, (uint8_t)(4 * n_cars), 0};
    f.train_speed = 30.0f;
    for (int a = 0; a < 4 * n_cars; ++a) f.wheel_speed[a] = 30.0f, f.cylinder_pressure[a] = 1.01325e5f;
    for (int c = 0; c < n_cars; ++c) f.supply_pressure[c] = 5.5e5f;
    rb_hil_session_key(secret, session, nonce ? PLANT_NONCE : 0, nonce, key);
    CHECK(rb_plant_frame_encode(&f, key, buf, 1024, &size, NULL) == RB_OK);
    return size;
}

static size_t hello(uint8_t *buf, uint64_t step, int n_cars)
{
    return keyed_plant_frame(buf, SESSION, step, n_cars, 0, SECRET);
}

/* Reads the BCU's answer to a hello: its nonce (0 if no authentic challenge echoing PLANT_NONCE came). */
static uint64_t read_challenge(rb_udp *plant_side)
{
    uint8_t buf[256], hello_key[RB_HIL_KEY_SIZE];
    rb_frame_header h;
    long n = rb_udp_recv(plant_side, buf, sizeof buf);
    rb_hil_session_key(SECRET, SESSION, 0, 0, hello_key);
    if (n <= 0 || rb_frame_check(buf, (size_t)n, &h, NULL) || h.type != RB_FRAME_CHALLENGE ||
        !rb_frame_authentic(buf, (size_t)n, hello_key) || h.plant_nonce != PLANT_NONCE)
        return 0;
    return h.nonce;
}

static void serve(double seconds, int *finished)
{
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, seconds, 0.0, 5.0, finished, NULL) == RB_OK);
}

/* The BCU and a plant endpoint that said hello and took the challenge: returns the nonce. */
static uint64_t bcu_handshake(rb_udp *plant_side)
{
    uint8_t buf[1024];
    int finished = 0;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(1), SECRET, COOKIE, "127.0.0.1", 0, &server, NULL) == RB_OK);
    CHECK(rb_udp_open(plant_side, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_set_peer(plant_side, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    send_raw(plant_side, buf, hello(buf, 0, 1));
    serve(0.02, &finished);
    uint64_t nonce = read_challenge(plant_side);
    CHECK(nonce != 0 && server.challenges == 1 && server.session == 0);   /* no session before the key */
    return nonce;
}

/* The reference BCU drops garbage, refuses a plant of another train (answering with its own digest
 * under the hello key), challenges a hello, opens the session with the first frame under the key of
 * its nonce, ignores repeated steps (stale), and answers each due BCU cycle. */
static void test_bcu_server_input(void)
{
    setup(1, 30.0);
    rb_udp plant_side;
    uint8_t buf[1024], hello_key[RB_HIL_KEY_SIZE];
    int finished = 0;
    uint64_t nonce = bcu_handshake(&plant_side);
    rb_hil_session_key(SECRET, SESSION, 0, 0, hello_key);
    send_raw(&plant_side, (const uint8_t *)"garbage", 7);
    send_raw(&plant_side, buf, hello(buf, 0, 2));                                     /* two cars: not this train */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 0, 1, nonce, WRONG));  /* no key: forged */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 0, 1, nonce, SECRET));
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 0, 1, nonce, SECRET)); /* the same step again */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 5, 1, nonce, SECRET)); /* inside the first cycle */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 10, 1, nonce, SECRET));/* the next cycle */
    serve(0.05, &finished);
    uint64_t c[RB_HIL_BCU_COUNTERS];
    rb_hil_bcu_counters(&server, c);
    CHECK(c[0] == 4 && c[1] == 1 && c[2] == 1);                   /* received, malformed, stale */
    CHECK(c[3] == 3 && c[5] == 2 && c[6] == 0 && c[7] == 1);      /* sent, cycles, foreign, refused */
    CHECK(c[8] == 1 && c[9] == 1);                                /* forged, challenges */
    CHECK(server.session == SESSION && server.nonce == nonce && server.epoch == 1);
    rb_bcu_frame answer;
    long n = rb_udp_recv(&plant_side, buf, sizeof buf);            /* the refusal: this BCU's digest */
    CHECK(n > 0 && rb_bcu_frame_decode(buf, (size_t)n, &answer, NULL) == RB_OK);
    CHECK(rb_frame_authentic(buf, (size_t)n, hello_key) && answer.header.nonce == 0);
    CHECK(answer.header.config == digest(1) && answer.header.session == SESSION && answer.header.n_cars == 1);
    uint32_t refused_config = 0;
    int cars = 0, axles = 0;
    char from[32];
    CHECK(rb_hil_bcu_refusal(&server, &refused_config, &cars, &axles, from, sizeof from) == 1);
    CHECK(refused_config == digest(2) && cars == 2 && axles == 8 && strncmp(from, "127.0.0.1:", 10) == 0);
    n = rb_udp_recv(&plant_side, buf, sizeof buf);
    CHECK(n > 0 && rb_bcu_frame_decode(buf, (size_t)n, &answer, NULL) == RB_OK);
    CHECK(rb_frame_authentic(buf, (size_t)n, server.key) && answer.header.nonce == nonce);
    CHECK(answer.header.step == 0 && answer.header.sequence == 0 && answer.brake_demand == 2.0f);
    CHECK(answer.pressure_demand[0] == (float)emergency_demand(0));   /* emergency, no WSP action */
    CHECK(!finished);
    CHECK(rb_hil_bcu_serve(&bcu, &scenario, &server, 2.0, 0.0, 0.1, &finished, NULL) == RB_OK);
    CHECK(finished);                                              /* idle for 0.1 s after the last frame */
    rb_udp_close(&plant_side);
    rb_hil_bcu_close(&server);
}

/* The BCU's nonce lives one to two RB_HIL_NONCE_LIFETIME: a first keyed frame delayed longer opens
 * no session (foreign), a hello without a plant nonce gets no challenge, and a fresh hello gets a
 * challenge with another nonce that opens the session. */
static void test_bcu_nonce_lifetime(void)
{
    setup(1, 30.0);
    rb_udp plant_side;
    uint8_t buf[1024];
    int finished = 0;
    uint64_t old = bcu_handshake(&plant_side);
    usleep((useconds_t)(2.05 * RB_HIL_NONCE_LIFETIME * 1e6));
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 0, 1, old, SECRET));   /* delayed past its life */
    serve(0.02, &finished);
    CHECK(server.session == 0 && server.foreign == 1 && server.received == 0);
    rb_plant_frame f;   /* a version 3 style hello: no plant nonce */
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){SESSION, digest(1), 1, 1, 0, 0, 1, 4, 0};
    uint8_t hello_key[RB_HIL_KEY_SIZE];
    size_t size = 0;
    rb_hil_session_key(SECRET, SESSION, 0, 0, hello_key);
    CHECK(rb_plant_frame_encode(&f, hello_key, buf, sizeof buf, &size, NULL) == RB_OK);
    send_raw(&plant_side, buf, size);
    serve(0.02, &finished);
    CHECK(server.challenges == 1 && server.foreign == 2);
    send_raw(&plant_side, buf, hello(buf, 2, 1));
    serve(0.02, &finished);
    uint64_t fresh = read_challenge(&plant_side);
    CHECK(fresh != 0 && fresh != old && server.challenges == 2);
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 3, 1, fresh, SECRET));
    serve(0.02, &finished);
    CHECK(server.session == SESSION && server.nonce == fresh && server.plant_nonce == PLANT_NONCE);
    CHECK(server.received == 1);
    rb_udp_close(&plant_side);
    rb_hil_bcu_close(&server);
}

/* Hostile peers against the BCU: without the key, from another address, in another session, with an
 * old or foreign nonce, or spoofing the plant's address and session: foreign or forged, never served;
 * a third peer's hellos without the key get no challenge, so it cannot open a session before the
 * plant; the BCU keeps serving its plant. */
static void test_bcu_keeps_its_plant(void)
{
    setup(1, 30.0);
    rb_udp plant_side, hostile;
    uint8_t buf[1024];
    int finished = 0;
    uint64_t c[RB_HIL_BCU_COUNTERS], before[RB_HIL_BCU_COUNTERS];
    CHECK(rb_udp_open(&hostile, "127.0.0.1", 0, NULL) == RB_OK);
    /* before the plant: a third peer without the key says hello, then sends keyed-looking frames */
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, digest(1), SECRET, COOKIE, "127.0.0.1", 0, &server, NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&hostile, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    send_raw(&hostile, buf, keyed_plant_frame(buf, SESSION, 0, 1, 0, WRONG));
    send_raw(&hostile, buf, keyed_plant_frame(buf, SESSION, 1, 1, 77, WRONG));
    serve(0.02, &finished);
    CHECK(server.forged == 1 && server.foreign == 1 && server.challenges == 0 && server.session == 0);
    CHECK(rb_udp_recv_from(&hostile, buf, sizeof buf, (uint8_t[16]){0}) == 0);   /* nothing answered */
    rb_hil_bcu_close(&server);
    uint64_t nonce = bcu_handshake(&plant_side);
    CHECK(rb_udp_set_peer(&hostile, "127.0.0.1", rb_hil_bcu_port(&server), NULL) == RB_OK);
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 0, 1, nonce, SECRET));
    serve(0.02, &finished);
    rb_hil_bcu_counters(&server, before);
    send_raw(&hostile, buf, keyed_plant_frame(buf, SESSION, UINT64_MAX, 1, nonce, SECRET));   /* another address */
    send_raw(&hostile, buf, keyed_plant_frame(buf, 0x0badf00du, 20, 1, nonce, SECRET));      /* ... another session */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 20, 1, nonce, WRONG));        /* spoofed: no key */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, 0x0badf00du, 20, 1, nonce, SECRET));   /* another session */
    send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, 20, 1, nonce + 1, SECRET));   /* an old nonce */
    send_raw(&hostile, (const uint8_t *)"garbage", 7);
    serve(0.02, &finished);
    rb_hil_bcu_counters(&server, c);
    CHECK(c[6] == before[6] + 5 && c[8] == before[8] + 1);        /* foreign, forged */
    for (int k = 0; k < 6; ++k) CHECK(c[k] == before[k]);
    CHECK(c[7] == 0 && server.udp.have_peer && server.session == SESSION && server.epoch == 1);
    /* the plant's next frames are served: received, a cycle, an answer to the plant */
    for (uint64_t step = 10; step <= 30; step += 10)
        send_raw(&plant_side, buf, keyed_plant_frame(buf, SESSION, step, 1, nonce, SECRET));
    serve(0.02, &finished);
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

/* Foreign datagrams at the plant (another address, another session) count as foreign, a spoofer
 * with the BCU's address and session but without the key as forged; they touch nothing else: no
 * lost frames from their sequence numbers, no command applied. */
static void test_plant_takes_only_its_bcu(void)
{
    setup(1, 30.0);
    rb_udp bcu_side, hostile;
    uint8_t buf[1024];
    size_t size;
    open_against(&bcu_side);
    CHECK(rb_udp_open(&hostile, "127.0.0.1", 0, NULL) == RB_OK);
    CHECK(rb_udp_set_peer(&hostile, "127.0.0.1", rb_udp_local_port(&runner.udp), NULL) == RB_OK);
    valid_frame(buf, &size, 0, 1, 1, 2e5f);
    send_raw(&bcu_side, buf, size);
    step_runner(1);
    CHECK(!runner.safe && runner.applied.pressure_demand[0] == 2e5);
    valid_frame(buf, &size, 0x80000000u, runner.step, 1, 6e5f);      /* a recent echo, a huge sequence jump */
    send_raw(&hostile, buf, size);
    send_raw(&hostile, (const uint8_t *)"garbage", 7);
    rb_bcu_frame f;
    memset(&f, 0, sizeof f);
    f.header = (rb_frame_header){0x0badf00du, digest(1), 2, runner.step, NONCE, agreed_plant_nonce, 1, 4, 0};
    f.pressure_demand[0] = 6e5f;
    CHECK(rb_bcu_frame_encode(&f, session_key, buf, sizeof buf, &size, NULL) == RB_OK);
    send_raw(&bcu_side, buf, size);                                   /* the BCU's address, another session */
    uint8_t wrong_key[RB_HIL_KEY_SIZE];
    rb_hil_session_key(WRONG, SESSION, agreed_plant_nonce, NONCE, wrong_key);
    keyed_frame(buf, &size, 1, runner.step, 1, 6e5f, wrong_key);      /* the BCU's address and session, no key */
    send_raw(&bcu_side, buf, size);
    step_runner(1);
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(res.foreign == 3 && res.forged == 1 && res.received == 1 && res.lost == 0 && res.late == 0);
    CHECK(res.malformed == 0 && res.duplicate == 0 && res.replayed == 0 && res.out_of_order == 0);
    CHECK(runner.applied.pressure_demand[0] == 2e5);
    CHECK(runner.log[(runner.events - 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_FORGED);
    valid_frame(buf, &size, 1, runner.step, 1, 3e5f);
    send_raw(&bcu_side, buf, size);
    step_runner(1);
    rb_hil_runner_result(&runner, &res);
    CHECK(res.received == 2 && res.lost == 0 && runner.applied.pressure_demand[0] == 3e5);
    rb_hil_runner_close(&runner);
    rb_udp_close(&bcu_side);
    rb_udp_close(&hostile);
}

/* A spoofer at the BCU's own address, in the session, with the session's nonce but without the key:
 * forged release commands every step, a forged challenge (to make the plant change keys) and forged
 * hellos-key frames change nothing: the cylinder pressures equal those of the undisturbed run, and
 * every forgery is counted. */
static void run_with_spoofer(int spoof, double *cylinders, int steps, rb_hil_result *res)
{
    setup(1, 30.0);
    rb_udp bcu_side;
    uint8_t buf[1024], wrong_key[RB_HIL_KEY_SIZE], wrong_hello[RB_HIL_KEY_SIZE];
    size_t size;
    open_against(&bcu_side);
    rb_hil_session_key(WRONG, SESSION, agreed_plant_nonce, NONCE, wrong_key);
    rb_hil_session_key(WRONG, SESSION, 0, 0, wrong_hello);
    for (int i = 0; i < steps; ++i) {
        if (i % 10 == 0) {
            valid_frame(buf, &size, (uint32_t)(i / 10), runner.step, 1, 3.5e5f);
            send_raw(&bcu_side, buf, size);
        }
        if (spoof) {
            keyed_frame(buf, &size, (uint32_t)(i / 10 + 1), runner.step, 1, 1.0e5f, wrong_key);
            send_raw(&bcu_side, buf, size);
            rb_frame_header h = {SESSION, config.config, 0, runner.step, NONCE + 1, runner.hello_nonce, 1, 4, 0};
            CHECK(rb_challenge_frame_encode(&h, wrong_hello, buf, sizeof buf, &size, NULL) == RB_OK);
            send_raw(&bcu_side, buf, size);
        }
        step_runner(1);
        cylinders[i] = runner.out.cylinder[0];
    }
    rb_hil_runner_result(&runner, res);
    rb_hil_runner_close(&runner);
    rb_udp_close(&bcu_side);
}

static void test_spoofer_changes_nothing(void)
{
    enum { STEPS = 400 };
    static double quiet[STEPS], spoofed[STEPS];
    rb_hil_result a, b;
    run_with_spoofer(0, quiet, STEPS, &a);
    run_with_spoofer(1, spoofed, STEPS, &b);
    CHECK(memcmp(quiet, spoofed, sizeof quiet) == 0);
    printf("spoofer: cylinder %.0f Pa after %d steps, forged %llu\n", quiet[STEPS - 1], STEPS, (unsigned long long)b.forged);
    CHECK(quiet[STEPS - 1] > 2e5);                      /* braking as commanded, not released by the spoofer */
    CHECK(a.forged == 0 && b.forged == 2 * STEPS && b.challenges == a.challenges);
    CHECK(a.received == b.received && b.lost == 0 && b.malformed == 0 && b.foreign == 0);
}

/* The sequence window alone: a BCU's frames 0..N-1 duplicated, pair-swapped and replayed from long
 * ago, in a random order of faults: received + lost = N exactly, duplicates and replays are never
 * received, and no frame is applied unless newer than every frame before it. */
static void test_sequence_window(void)
{
    enum { N = 5000 };
    rb_watchdog w;
    unsigned seed = 2026u;
    uint32_t arrivals[4 * N];
    int n = 0;
    rb_watchdog_init(&w, 100);
    for (uint32_t seq = 0; seq < N; ++seq) {
        seed = seed * 1103515245u + 12345u;
        unsigned fault = (seed >> 16) % 8;
        if (fault == 0) continue;                                    /* lost */
        arrivals[n++] = seq;
        if (fault == 1) arrivals[n++] = seq;                         /* duplicated */
        if (fault == 2 && n >= 2) {                                  /* swapped with the one before */
            uint32_t t = arrivals[n - 1]; arrivals[n - 1] = arrivals[n - 2]; arrivals[n - 2] = t;
        }
        if (fault == 3 && seq > 200) arrivals[n++] = seq - 100 - (seed >> 20) % 100;   /* replayed */
    }
    uint64_t applied = 0, newest = 0;
    int applied_out_of_order = 0, have = 0;
    uint32_t last = 0;
    for (int i = 0; i < n; ++i) {
        int outcome = rb_watchdog_frame(&w, arrivals[i], 10, 10, 5);
        if (outcome == RB_SEQ_APPLY) {
            applied_out_of_order += have && arrivals[i] <= newest;
            newest = arrivals[i];
            have = 1;
            applied++;
        }
        if (arrivals[i] > last) last = arrivals[i];
    }
    printf("sequence window: %d arrivals of %u frames: received %llu, lost %llu, duplicate %llu, out of order %llu, "
           "replayed %llu, applied %llu\n", n, last + 1, (unsigned long long)w.received, (unsigned long long)w.lost,
           (unsigned long long)w.duplicate, (unsigned long long)w.out_of_order, (unsigned long long)w.replayed,
           (unsigned long long)applied);
    CHECK(w.received + w.lost == (uint64_t)last + 1);
    CHECK(applied_out_of_order == 0 && applied + w.out_of_order == w.received);
    CHECK(w.duplicate > 0 && w.out_of_order > 0 && w.replayed > 0 && w.lost > 0);
    uint64_t received = w.received;
    rb_watchdog_rekey(&w);                                          /* a new key: numbered from 0 again */
    CHECK(rb_watchdog_frame(&w, 3, 10, 10, 5) == RB_SEQ_APPLY && w.received == received + 1);
    CHECK(rb_watchdog_frame(&w, 1, 10, 10, 5) == RB_SEQ_OUT_OF_ORDER);
    CHECK(rb_watchdog_frame(&w, 1, 10, 10, 5) == RB_SEQ_DUPLICATE);
    CHECK(rb_watchdog_frame(&w, 0xFFFFFFF0u, 10, 10, 5) == RB_SEQ_REPLAYED);   /* before the key's first */
}

/* The same faults over UDP against the runner: its counters add up and only newer frames apply. */
static void test_sequence_faults_on_the_wire(void)
{
    setup(1, 30.0);
    rb_udp bcu_side;
    uint8_t buf[1024];
    size_t size;
    config.hold_time = 1.0;
    config.late_time = 1.0;
    open_against(&bcu_side);
    /* frames 0..39 answering the current step; sent as: 0, 2, 1 (swap), 3, 3 (duplicate), 5, 4, 6..39,
     * then 0 and 2 again (replays inside the window), 20 lost */
    uint32_t order[48];
    int n = 0;
    uint32_t head[] = {0, 2, 1, 3, 3, 5, 4};
    for (int i = 0; i < 7; ++i) order[n++] = head[i];
    for (uint32_t s = 6; s < 40; ++s) if (s != 20) order[n++] = s;
    order[n++] = 0;
    order[n++] = 2;
    int applied_older = 0;
    float newest = 0.0f;
    for (int i = 0; i < n; ++i) {
        valid_frame(buf, &size, order[i], runner.step, 1, 1e5f + 1e3f * (float)order[i]);
        send_raw(&bcu_side, buf, size);
        step_runner(1);
        float demand = (float)runner.applied.pressure_demand[0];
        applied_older += demand < newest;
        if (demand > newest) newest = demand;
    }
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(res.received + res.lost == 40 && res.lost == 1);
    CHECK(res.out_of_order == 2 && res.duplicate == 3 && res.replayed == 0 && applied_older == 0);
    CHECK(runner.applied.pressure_demand[0] == (double)(1e5f + 39e3f));
    rb_hil_runner_close(&runner);
    rb_udp_close(&bcu_side);
}

/* The BCU falls silent: the safe state applies after the hold time, and the loss is counted with
 * when it happened and what it cost (the distance run in the safe state, its locks). */
static void test_bcu_lost(void)
{
    setup(1, 30.0);
    rb_udp bcu_side;
    uint8_t buf[1024];
    size_t size;
    open_against(&bcu_side);
    for (uint32_t s = 0; s < 20; ++s) {
        valid_frame(buf, &size, s, runner.step, 1, 2e5f);
        send_raw(&bcu_side, buf, size);
        step_runner(1);
    }
    uint64_t last_valid = runner.watchdog.last_valid_step;
    double position = runner.out.position;
    step_runner(50);
    rb_hil_result res;
    rb_hil_runner_result(&runner, &res);
    CHECK(res.losses == 0 && !runner.safe);
    step_runner(200);
    rb_hil_runner_result(&runner, &res);
    CHECK(res.losses == 1 && res.last_valid_step == last_valid && res.lost_step == last_valid + 51);
    CHECK(res.lost_steps == res.steps - res.lost_step);   /* the steps from lost_step on */
    double run = runner.out.position - position, lost_run = res.lost_distance;
    /* between the loss and now the train ran lost_distance; before it, about 51 steps at speed */
    CHECK(lost_run > 0.0 && lost_run < run && run - lost_run > 50 * 1e-3 * runner.out.speed);
    CHECK(runner.applied.pressure_demand[0] == emergency_demand(0));
    rb_hil_runner_close(&runner);
    rb_udp_close(&bcu_side);
}

/* A BCU set up for another train: it refuses the plant and says so (refusal), the plant learns
 * why from the refusal frame and ends its run; the BCU reaches its idle timeout without valid frames. */
static void test_mismatch(void)
{
    setup(1, 30.0);
    rb_error err;
    int finished = 0, bcu_finished = 0;
    CHECK(rb_hil_bcu_open(&bcu, NULL, &scenario, rb_hil_config_digest("other", 1, 4, 1e-3), SECRET, COOKIE,
                          "127.0.0.1", 0, &server, &err) == RB_OK);
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
    CHECK(series[10 * nch + 8] == emergency_demand(0));
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
    config.paced = 0;
    open_against(&peer);   /* unpaced for the handshake, then paced (the pacer starts at the next call) */
    config.paced = 1;
    runner.started = 0;
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

/* Posts a fault change and runs one step: the loop applies it at that step's start and answers. */
static int change_fault(int action, int kind, int car, int axle, char *text)
{
    rb_hil_fault_command c;
    memset(&c, 0, sizeof c);
    c.action = action;
    c.fault.kind = kind; c.fault.car = car; c.fault.axle = axle;
    uint64_t step = 0, before = runner.step;
    CHECK(rb_hil_runner_post_fault(&runner, &c) == 1);
    CHECK(rb_hil_runner_post_fault(&runner, &c) == 0);              /* one change at a time */
    CHECK(rb_hil_runner_fault_answer(&runner, &step, text, RB_ERROR_MESSAGE_SIZE) == -1);   /* not applied yet */
    step_runner(1);
    int status = rb_hil_runner_fault_answer(&runner, &step, text, RB_ERROR_MESSAGE_SIZE);
    CHECK(step == before);
    CHECK(rb_hil_runner_fault_answer(&runner, &step, text, RB_ERROR_MESSAGE_SIZE) == -1);   /* fetched once */
    return status;
}

/* A vent valve stuck open injected while the plant runs vents its cylinder below its neighbour's
 * (the safe state holds every other valve de-energised); cleared, the valve follows its command
 * again and the cylinder refills. Bad changes are refused and change nothing. */
static void test_faults_at_run_time(void)
{
    char text[RB_ERROR_MESSAGE_SIZE];
    setup(2, 50.0);
    CHECK(rb_hil_runner_open(&plant, &config, "127.0.0.1", 0, "127.0.0.1", 9, &runner, NULL) == RB_OK);
    step_runner(1000);   /* the cylinders fill to the emergency demand */
    double filled = runner.out.cylinder[1];
    CHECK(filled > plant.atmosphere + 1e5 && runner.out.vent[1] == 0);
    uint64_t events = runner.events;
    CHECK(change_fault(RB_HIL_FAULT_INJECT, RB_FAULT_VENT_STUCK_OPEN, 0, 1, text) == RB_OK);
    CHECK(strstr(text, "vent_stuck_open on car 1, axle 2: injected") != NULL);
    CHECK(runner.events == events + 1 && runner.log[events % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_FAULT_ON);
    CHECK(runner.out.vent[1] == 1 && runner.out.vent[0] == 0);
    rb_hil_snapshot view;   /* the live view holds what the step gave */
    CHECK(rb_hil_runner_snapshot(&runner, &view, 10) == 1);
    CHECK(view.step == runner.step && view.time == runner.out.time && view.speed == runner.out.speed);
    CHECK(view.vent[1] == 1 && view.vent[0] == 0 && view.cylinder[1] == runner.out.cylinder[1] && view.safe == 1);
    CHECK(view.n_cars == 2 && view.n_axles == 8 && view.pressure_demand[0] == runner.applied.pressure_demand[0]);
    runner.snapshot_sequence |= 1u;   /* a write in progress: no copy is handed out */
    CHECK(rb_hil_runner_snapshot(&runner, &view, 10) == 0);
    runner.snapshot_sequence++;
    step_runner(500);
    CHECK(runner.out.vent[1] == 1);
    /* the open hold valve feeds what the vent drains: the cylinder settles between the two */
    CHECK(runner.out.cylinder[1] < runner.out.cylinder[0] - 0.2 * (filled - plant.atmosphere));
    /* refused: injected twice, cleared where absent, a car the train lacks, an unknown action */
    CHECK(change_fault(RB_HIL_FAULT_INJECT, RB_FAULT_VENT_STUCK_OPEN, 0, 1, text) == RB_EINVAL);
    CHECK(strstr(text, "already active") != NULL);
    CHECK(change_fault(RB_HIL_FAULT_CLEAR, RB_FAULT_VENT_STUCK_OPEN, 0, 2, text) == RB_EINVAL);
    CHECK(strstr(text, "not present") != NULL);
    CHECK(change_fault(RB_HIL_FAULT_INJECT, RB_FAULT_HOLD_STUCK_OPEN, 2, 0, text) == RB_EINVAL);
    CHECK(strstr(text, "fault.car = 2") != NULL);
    CHECK(change_fault(7, RB_FAULT_HOLD_STUCK_OPEN, 0, 0, text) == RB_EINVAL);
    CHECK(strstr(text, "action = 7") != NULL);
    CHECK(runner.n_faults == 1 && runner.events == events + 1);
    double vented = runner.out.cylinder[1];
    CHECK(change_fault(RB_HIL_FAULT_CLEAR, RB_FAULT_VENT_STUCK_OPEN, 0, 1, text) == RB_OK);
    CHECK(strstr(text, "cleared") != NULL && runner.n_faults == 0);
    CHECK(runner.log[(events + 1) % RB_HIL_LOG_SIZE].kind == RB_HIL_EVENT_FAULT_OFF);
    step_runner(1000);
    CHECK(runner.out.vent[1] == 0);
    CHECK(runner.out.cylinder[1] > vented + 0.5 * (filled - vented));
    rb_hil_runner_close(&runner);
}

int main(void)
{
    test_faults_at_run_time();
    test_safe_state();
    test_loop_matches_mil();
    test_loop_with_each_controller();
    test_hostile_frames();
    test_bcu_server_input();
    test_bcu_keeps_its_plant();
    test_bcu_nonce_lifetime();
    test_plant_takes_only_its_bcu();
    test_spoofer_changes_nothing();
    test_sequence_window();
    test_sequence_faults_on_the_wire();
    test_bcu_lost();
    test_mismatch();
    test_paced_without_bcu();
    test_flood();
    return rb_test_summary("test_hil");
}

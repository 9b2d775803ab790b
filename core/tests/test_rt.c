/* Real-time support: latency statistics, watchdog state machine, UDP loopback, pacer lower bound. */
#include "rb_test.h"
#include "railbrake/rb_rt.h"

static rb_latency_stats stats;  /* large: keep it off the stack */
static rb_pacer pacer;

static void test_latency_quantiles(void)
{
    rb_latency_reset(&stats);
    for (int i = 0; i < 1000; ++i) rb_latency_add(&stats, i % 100 + 0.5);   /* uniform 0.5 .. 99.5 us */
    CHECK_CLOSE(rb_latency_quantile(&stats, 0.5), 50.0, 0, 1.0);
    CHECK_CLOSE(rb_latency_quantile(&stats, 0.99), 99.0, 0, 1.0);
    CHECK_CLOSE(stats.max_us, 99.5, 0, 1e-12);
    CHECK_CLOSE(rb_latency_mean(&stats), 50.0, 1e-12, 0);
    rb_latency_add(&stats, 1e6);  /* beyond the histogram: max kept exactly */
    CHECK(stats.max_us == 1e6);
}

static void test_watchdog(void)
{
    rb_watchdog w;
    rb_watchdog_init(&w, 50);
    CHECK(rb_watchdog_tick(&w, 0) == 1);           /* no BCU yet: safe state */
    rb_watchdog_frame(&w, 0, 10, 10, 5);            /* the BCU numbers its frames from 0 */
    CHECK(rb_watchdog_tick(&w, 10) == 0);
    rb_watchdog_frame(&w, 3, 11, 11, 5);            /* sequences 1 and 2 lost */
    CHECK(w.lost == 2);
    CHECK(rb_watchdog_tick(&w, 61) == 0);           /* held for 50 steps */
    CHECK(rb_watchdog_tick(&w, 62) == 1);           /* then safe */
    rb_watchdog_frame(&w, 4, 20, 70, 5);            /* echoes an old step: late, no refresh */
    CHECK(w.late == 1 && rb_watchdog_tick(&w, 70) == 1);
    rb_watchdog_frame(&w, 5, 70, 70, 5);
    CHECK(rb_watchdog_tick(&w, 71) == 0);
    rb_watchdog_malformed(&w);
    CHECK(w.malformed == 1 && w.received == 4);
}

static void test_udp_loopback(void)
{
    rb_udp a, b;
    rb_error err;
    CHECK(rb_udp_open(&a, "127.0.0.1", 0, &err) == RB_OK);
    CHECK(rb_udp_open(&b, "127.0.0.1", 0, &err) == RB_OK);
    CHECK(rb_udp_set_peer(&a, "127.0.0.1", rb_udp_local_port(&b), &err) == RB_OK);
    uint8_t msg[3] = {1, 2, 3}, buf[8];
    CHECK(rb_udp_recv(&b, buf, sizeof buf) == 0);   /* nothing waiting: no block */
    CHECK(rb_udp_send(&a, msg, 3) == 3);
    long n = 0;
    for (int i = 0; i < 1000 && n == 0; ++i) n = rb_udp_recv(&b, buf, sizeof buf);
    CHECK(n == 3 && buf[2] == 3);
    CHECK(b.have_peer && rb_udp_send(&b, msg, 3) == 3);  /* learnt the peer */
    CHECK(rb_udp_set_peer(&a, "localhost", 1, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "host") != NULL);
    CHECK(rb_udp_open(&a, "127.0.0.1", 70000, &err) == RB_EINVAL);
    rb_udp_close(&a);
    rb_udp_close(&b);
}

static void test_pacer_never_runs_early(void)
{
    CHECK(rb_pacer_start(&pacer, 1000000, NULL) == RB_OK);
    int64_t start = rb_monotonic_ns();
    for (int i = 0; i < 50; ++i) rb_pacer_wait(&pacer);
    CHECK(rb_monotonic_ns() - start >= 49 * 1000000LL);   /* absolute deadlines: no early periods */
    CHECK(pacer.wakeup.count == 50);
    rb_error err;
    CHECK(rb_pacer_start(&pacer, 5, &err) == RB_EINVAL);
}

int main(void)
{
    test_latency_quantiles();
    test_watchdog();
    test_udp_loopback();
    test_pacer_never_runs_early();
    return rb_test_summary("test_rt");
}

/* Absolute-deadline pacing and latency statistics (POSIX clock_nanosleep on CLOCK_MONOTONIC).
 * Absolute deadlines keep the long-run rate exact: a late wake-up does not shift later periods. */
#define _POSIX_C_SOURCE 200809L
#include "railbrake/rb_rt.h"

#include <sched.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

int64_t rb_monotonic_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void rb_latency_reset(rb_latency_stats *s) { memset(s, 0, sizeof *s); }

void rb_latency_add(rb_latency_stats *s, double us)
{
    if (us < 0.0) us = 0.0;
    size_t bin = us >= RB_RT_HIST_US ? RB_RT_HIST_US : (size_t)us;
    s->bins[bin]++;
    s->count++;
    s->sum_us += us;
    if (us > s->max_us) s->max_us = us;
}

double rb_latency_quantile(const rb_latency_stats *s, double q)
{
    if (s->count == 0) return 0.0;
    uint64_t need = (uint64_t)(q * (double)s->count + 0.5), seen = 0;
    if (need < 1) need = 1;
    for (size_t i = 0; i <= RB_RT_HIST_US; ++i) {
        seen += s->bins[i];
        if (seen >= need) return i == RB_RT_HIST_US ? s->max_us : (double)(i + 1);
    }
    return s->max_us;
}

double rb_latency_mean(const rb_latency_stats *s) { return s->count ? s->sum_us / (double)s->count : 0.0; }

rb_status rb_pacer_start(rb_pacer *p, int64_t period_ns, rb_error *err)
{
    if (!p) return rb_fail(err, RB_EINVAL, "pacer = NULL");
    if (period_ns < 10000 || period_ns > 1000000000LL)
        return rb_fail(err, RB_EINVAL, "period_ns = %lld: must lie in [10000, 1e9]", (long long)period_ns);
    memset(p, 0, sizeof *p);
    p->period_ns = period_ns;
    p->woke_ns = rb_monotonic_ns();
    p->next_deadline_ns = p->woke_ns + period_ns;
    return RB_OK;
}

int rb_pacer_wait(rb_pacer *p)
{
    int64_t done = rb_monotonic_ns();
    rb_latency_add(&p->work, (double)(done - p->woke_ns) / 1e3);
    int overrun = done > p->next_deadline_ns;
    if (overrun) {
        p->overruns++;
        while (p->next_deadline_ns < done) p->next_deadline_ns += p->period_ns;
    }
    struct timespec ts = {(time_t)(p->next_deadline_ns / 1000000000LL), (long)(p->next_deadline_ns % 1000000000LL)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) != 0) { /* EINTR: sleep again */ }
    p->woke_ns = rb_monotonic_ns();
    rb_latency_add(&p->wakeup, (double)(p->woke_ns - p->next_deadline_ns) / 1e3);
    p->next_deadline_ns += p->period_ns;
    return overrun;
}

int rb_rt_request(int priority)
{
    int granted = 0;
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) granted |= RB_RT_MEMORY_LOCKED;
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = priority;
    if (priority > 0 && sched_setscheduler(0, SCHED_FIFO, &sp) == 0) granted |= RB_RT_FIFO_PRIORITY;
    return granted;
}

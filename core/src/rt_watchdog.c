/* Watchdog on the BCU link: places each frame in the BCU's sequence (received, lost, late,
 * out of order, duplicate, replayed); holds the last commands for hold_steps after the last valid
 * frame, then asks for the safe state. */
#include "railbrake/rb_rt.h"

#include <string.h>

void rb_watchdog_init(rb_watchdog *w, uint64_t hold_steps)
{
    memset(w, 0, sizeof *w);
    w->hold_steps = hold_steps;
}

void rb_watchdog_rekey(rb_watchdog *w) { w->have_sequence = 0; }

/* The first frame under a key: the numbers before it were sent and not (yet) received; bits for
 * numbers below 0 are set, so nothing there counts as out of order. */
static void first_sequence(rb_watchdog *w, uint32_t sequence)
{
    w->have_sequence = 1;
    w->highest = sequence;
    w->lost += sequence;
    w->window = 1u | (sequence < RB_RT_WINDOW - 1 ? ~0ULL << (sequence + 1) : 0u);
}

/* A sequence number behind the newest: out of order (fills a gap), duplicate, or replayed. */
static int behind(rb_watchdog *w, uint64_t distance)
{
    if (distance >= RB_RT_WINDOW) {
        w->replayed++;
        return RB_SEQ_REPLAYED;
    }
    uint64_t bit = 1ULL << distance;
    if (w->window & bit) {
        w->duplicate++;
        return RB_SEQ_DUPLICATE;
    }
    w->window |= bit;
    w->received++;
    w->lost--;   /* counted as lost when the gap opened: it came after all */
    w->out_of_order++;
    return RB_SEQ_OUT_OF_ORDER;
}

int rb_watchdog_frame(rb_watchdog *w, uint32_t sequence, uint64_t echoed_step, uint64_t step,
                      uint64_t late_steps)
{
    if (!w->have_sequence) {
        first_sequence(w, sequence);
    } else {
        /* the 32-bit number extended to the one nearest the newest (serial number arithmetic) */
        int64_t ahead = (int32_t)(sequence - (uint32_t)w->highest);
        if (ahead <= 0) {
            if ((int64_t)w->highest + ahead < 0) {
                w->replayed++;
                return RB_SEQ_REPLAYED;
            }
            return behind(w, (uint64_t)(-ahead));
        }
        w->lost += (uint64_t)ahead - 1u;
        w->window = (uint64_t)ahead >= RB_RT_WINDOW ? 1u : (w->window << ahead) | 1u;
        w->highest += (uint64_t)ahead;
    }
    w->received++;
    if (echoed_step + late_steps < step) {
        w->late++;
        return RB_SEQ_LATE;   /* a stale command does not refresh the watchdog */
    }
    w->have_valid = 1;
    w->last_valid_step = step;
    return RB_SEQ_APPLY;
}

void rb_watchdog_malformed(rb_watchdog *w) { w->malformed++; }

int rb_watchdog_tick(rb_watchdog *w, uint64_t step)
{
    w->safe = !w->have_valid || step > w->last_valid_step + w->hold_steps;
    if (w->safe) w->safe_state_steps++;
    return w->safe;
}

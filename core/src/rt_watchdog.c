/* Watchdog on the BCU link: counts lost, late and malformed frames; holds the last commands for
 * hold_steps after the last valid frame, then asks for the safe state. */
#include "railbrake/rb_rt.h"

#include <string.h>

void rb_watchdog_init(rb_watchdog *w, uint64_t hold_steps)
{
    memset(w, 0, sizeof *w);
    w->hold_steps = hold_steps;
}

void rb_watchdog_frame(rb_watchdog *w, uint32_t sequence, uint64_t echoed_step, uint64_t step,
                       uint64_t late_steps)
{
    w->received++;
    if (w->have_valid && sequence != w->last_sequence + 1u) {
        uint32_t gap = sequence - w->last_sequence - 1u;   /* wraps correctly in uint32 */
        if (gap < 0x80000000u) w->lost += gap;
    }
    w->last_sequence = sequence;
    if (echoed_step + late_steps < step) {
        w->late++;
        return;   /* a stale command does not refresh the watchdog */
    }
    w->have_valid = 1;
    w->last_valid_step = step;
}

void rb_watchdog_malformed(rb_watchdog *w) { w->malformed++; }

int rb_watchdog_tick(rb_watchdog *w, uint64_t step)
{
    w->safe = !w->have_valid || step > w->last_valid_step + w->hold_steps;
    if (w->safe) w->safe_state_steps++;
    return w->safe;
}

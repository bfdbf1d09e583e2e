/* rtloop: periodic loop on absolute monotonic deadlines (docs/method/lockstep.md §1).
 * Bounded work per call: no loops that depend on how late we are (missed
 * deadlines are skipped arithmetically). The clock is the platform's
 * (rtclock.h), so this module stays freestanding.
 */
#include "rtloop.h"
#include "rtclock.h"

int64_t rtloop_now_ns(void)
{
    return rtclock_now_ns();
}

int rtloop_init(rtloop *l, int64_t period_ns)
{
    if (period_ns < RTLOOP_MIN_PERIOD_NS || period_ns > RTLOOP_MAX_PERIOD_NS)
        return RTLOOP_ERR_RANGE;
    l->period_ns = period_ns;
    l->next_ns = rtloop_now_ns() + period_ns;
    l->wake_ns = 0;
    l->cycles = 0;
    l->overruns = 0;
    loopstats_reset(&l->cycle);
    loopstats_reset(&l->latency);
    return 0;
}

void rtloop_wait(rtloop *l)
{
    int64_t now;
    rtclock_sleep_until_ns(l->next_ns);
    now = rtloop_now_ns();
    l->wake_ns = now;
    loopstats_add(&l->latency, now > l->next_ns ? (double)(now - l->next_ns) * 1e-3 : 0.0);
}

void rtloop_end_cycle(rtloop *l)
{
    const int64_t now = rtloop_now_ns();
    loopstats_add(&l->cycle, (double)(now - l->wake_ns) * 1e-3);
    l->cycles++;
    l->next_ns += l->period_ns;
    if (now >= l->next_ns) {
        const int64_t missed = (now - l->next_ns) / l->period_ns + 1;
        l->overruns++;
        l->next_ns += missed * l->period_ns;
    }
}

void rtloop_record(rtloop *l, int64_t start_ns)
{
    const int64_t now = rtloop_now_ns();
    loopstats_add(&l->cycle, (double)(now - start_ns) * 1e-3);
    l->cycles++;
}

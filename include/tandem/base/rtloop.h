/* rtloop: the periodic real-time loop of every daemon (docs/method/lockstep.md §1).
 *
 * Absolute deadlines on the platform's monotonic clock (rtclock.h; on Linux
 * CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME)), so the period does
 * not drift with the work done in each cycle. Measures
 * wake-up latency (how late the thread woke after its deadline) and cycle
 * time (wake-up to end of work) into fixed histograms, and counts overruns
 * (work that ran past the next deadline; the loop then skips the missed
 * deadlines instead of bursting to catch up).
 *
 * The clock comes from the platform layer (include/tandem/base/rtclock.h): Linux links
 * src/platform/posix/rtclock_posix.c, a bare board its own timer
 * (src/platform/board/rtclock_board.c shows the shape).
 */
#ifndef TANDEM_RTLOOP_H
#define TANDEM_RTLOOP_H

#include <stdint.h>
#include "loopstats.h"

#define RTLOOP_ERR_RANGE (-1) /* period outside [RTLOOP_MIN_PERIOD_NS, RTLOOP_MAX_PERIOD_NS] */

#define RTLOOP_MIN_PERIOD_NS 50000LL       /* 20 kHz */
#define RTLOOP_MAX_PERIOD_NS 10000000000LL /* 10 s */

typedef struct rtloop {
    int64_t period_ns;
    int64_t next_ns; /* next absolute deadline */
    int64_t wake_ns; /* when the current cycle woke */
    int64_t cycles;
    int64_t overruns;
    loopstats cycle;   /* wake-up to rtloop_end_cycle, us */
    loopstats latency; /* deadline to wake-up, us */
} rtloop;

int64_t rtloop_now_ns(void);
/* 0, or RTLOOP_ERR_RANGE if the period is outside
 * [RTLOOP_MIN_PERIOD_NS, RTLOOP_MAX_PERIOD_NS]. */
int rtloop_init(rtloop *l, int64_t period_ns);
/* Sleeps until the next deadline and records the wake-up latency. */
void rtloop_wait(rtloop *l);
/* Records the cycle time, counts an overrun and skips missed deadlines. */
void rtloop_end_cycle(rtloop *l);
/* Cycle accounting for loops driven by something else (lockstep):
 * record a cycle that started at start_ns and ends now. */
void rtloop_record(rtloop *l, int64_t start_ns);

#endif

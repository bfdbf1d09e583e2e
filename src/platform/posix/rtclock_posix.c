/* rtclock on Linux/POSIX (include/tandem/base/rtclock.h): CLOCK_MONOTONIC read and an
 * absolute clock_nanosleep, so the loop's period does not drift with the
 * work done in each cycle. */
#define _POSIX_C_SOURCE 200809L /* clock_nanosleep: here, not in the core's flags */
#include "rtclock.h"
#include <time.h>

int64_t rtclock_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + (int64_t)ts.tv_nsec;
}

void rtclock_sleep_until_ns(int64_t t_ns)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(t_ns / 1000000000LL);
    ts.tv_nsec = (long)(t_ns % 1000000000LL);
    /* One call: if a signal interrupts it (EINTR) the cycle simply starts
     * early, and the caller sees its stop flag at once. */
    (void)clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
}

/* rtclock: the one thing the core's real-time loop needs from the platform,
 * a monotonic clock and a sleep until an absolute time on that clock.
 *
 * The core (src/core/) implements no clock itself, so it compiles freestanding
 * (ISO C99 + libm, no POSIX). Each platform links one implementation:
 *   src/platform/posix/rtclock_posix.c   Linux: CLOCK_MONOTONIC, clock_nanosleep
 *   src/platform/board/rtclock_board.c   a bare board: a free-running hardware
 *                                    counter and a wait-for-interrupt idle
 *
 * Contract (what rtloop relies on):
 *   rtclock_now_ns     never goes backwards, counts nanoseconds from an
 *                      arbitrary origin, does not wrap within 292 years
 *                      (int64_t), resolution at least 1 us, callable from
 *                      the control task at any time, bounded time;
 *   rtclock_sleep_until_ns  returns no earlier than t_ns, or early when
 *                      something else must run (a signal, an interrupt
 *                      the task should see); the caller re-reads the clock
 *                      and never assumes it slept the full time. A t_ns in
 *                      the past returns at once.
 */
#ifndef TANDEM_RTCLOCK_H
#define TANDEM_RTCLOCK_H

#include <stdint.h>

int64_t rtclock_now_ns(void);
void rtclock_sleep_until_ns(int64_t t_ns);

#endif

/* rtclock on a bare board (include/tandem/base/rtclock.h) over board_timer.h: extends
 * the 32-bit free-running counter to 64 bits and converts ticks to ns.
 *
 * The extension needs rtclock_now_ns to be called at least once per
 * counter wrap (2^32 ticks: 171 s at 25 MHz, 26 s at 168 MHz); the control
 * loop calls it twice per period, so a period shorter than the wrap time
 * keeps the clock right. Single control task, no interrupt handler calls
 * it: no locking.
 */
#include "rtclock.h"
#include "board_timer.h"

static uint32_t last_count; /* counter at the previous read */
static int64_t ticks_high;  /* wraps seen, times 2^32 */

static int64_t ticks_now(void)
{
    const uint32_t c = board_timer_count();
    if (c < last_count)
        ticks_high += (int64_t)1 << 32;
    last_count = c;
    return ticks_high + (int64_t)c;
}

int64_t rtclock_now_ns(void)
{
    const int64_t hz = (int64_t)board_timer_hz();
    const int64_t t = ticks_now();
    /* split so ticks * 1e9 cannot overflow int64 */
    return (t / hz) * 1000000000LL + ((t % hz) * 1000000000LL) / hz;
}

void rtclock_sleep_until_ns(int64_t t_ns)
{
    while (rtclock_now_ns() < t_ns)
        board_timer_idle();
}

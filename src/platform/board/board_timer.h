/* board_timer: what a bare board provides for rtclock_board.c, the three
 * things every VME CPU board and microcontroller has: a free-running
 * up-counter (a 68040 board's timer chip, a Cortex-M's DWT cycle counter
 * or a 32-bit general-purpose timer), its rate, and an idle that returns
 * on the next interrupt (68040 STOP, Cortex-M WFI). The board's start-up
 * code starts the counter and arms a periodic or compare interrupt no
 * slower than the control period so the idle returns in time.
 */
#ifndef TANDEM_BOARD_TIMER_H
#define TANDEM_BOARD_TIMER_H

#include <stdint.h>

/* Counter rate in Hz, 1 MHz .. 4 GHz (resolution at least 1 us). */
uint32_t board_timer_hz(void);
/* The counter: counts up by one every 1/board_timer_hz s, wraps at 2^32. */
uint32_t board_timer_count(void);
/* Waits for the next interrupt (any); may return at once. */
void board_timer_idle(void);

#endif

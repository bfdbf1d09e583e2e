/* guard: plausibility of a message's step against what the receiver
 * knows, so that no single message can latch a receiver.
 *
 * A receiver that keeps "the newest step seen" and refuses anything older
 * is taken over by one message with step = INT64_MAX: every real message
 * after it is "older". A step gate instead accepts a step only
 *   - inside a window ahead of the last accepted one (a real stream moves
 *     a few steps per message), or
 *   - when nothing was accepted for resync_ns of local (receiver) time:
 *     the sender restarted or the world was reset, so the gate follows the
 *     new stream; a forged step can then cost at most resync_ns.
 * Messages that fail change no state; the caller counts them.
 */
#ifndef TANDEM_GUARD_H
#define TANDEM_GUARD_H

#include <stdint.h>

enum {
    GUARD_OK = 0,
    GUARD_ERR_NEGATIVE = -1, /* step < 0 */
    GUARD_ERR_BEHIND = -2,   /* older than the last accepted step */
    GUARD_ERR_JUMP = -3      /* further ahead than the window */
};

typedef struct step_gate {
    int64_t last_step;  /* -1: nothing accepted yet */
    int64_t last_rx_ns; /* local arrival time of last_step */
    int64_t window;     /* largest forward jump taken */
    int64_t resync_ns;  /* silence after which any step >= 0 is taken */
} step_gate;

void step_gate_init(step_gate *g, int64_t window, int64_t resync_ns);
/* GUARD_OK or why not; equal steps are fine (a re-announced step). */
int step_gate_check(const step_gate *g, int64_t step, int64_t now_ns);
void step_gate_accept(step_gate *g, int64_t step, int64_t now_ns);
/* check + accept; returns the check's result. */
int step_gate_pass(step_gate *g, int64_t step, int64_t now_ns);

/* 1 if lo <= v <= hi and v is finite, for every one of n values. */
int all_within(const double *v, int n, double lo, double hi);

#endif

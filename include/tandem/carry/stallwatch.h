/* stallwatch: detects a cell that has stopped making progress (issue: no
 * silent stall).
 *
 * The supervisor feeds it once per cycle: the cycle's time, whether a
 * transition completed, whether work is pending (a transition enabled or
 * running) and whether an obstruction is known to be in the cell (the
 * stick). The watch counts time without a completion while work is pending
 * and nothing obstructs the cell; past limit_s it reports a stall. An
 * obstruction restarts the count (a blocked arm may wait as long as the
 * block lasts; once it is out the arm must finish within limit_s again).
 * A completion ends a stall; `stalls` counts the stalls seen.
 */
#ifndef TANDEM_STALLWATCH_H
#define TANDEM_STALLWATCH_H

typedef struct stallwatch {
    double limit_s;        /* time without progress that is a stall (> 0) */
    double idle_s;         /* time counted so far */
    double last_t_s;       /* time of the previous update, < 0 before the first */
    int    stalled;        /* 1 while stalled */
    int    stalls;         /* stalls begun */
} stallwatch;

enum { STALLWATCH_OK = 0, STALLWATCH_ERR_ARG = -1 };

/* limit_s finite and > 0. */
int stallwatch_init(stallwatch *w, double limit_s);
/* One cycle at time t_s (non-decreasing). Returns 1 on the update at which
 * a stall begins, 0 otherwise, STALLWATCH_ERR_ARG on bad input (state
 * unchanged). */
int stallwatch_update(stallwatch *w, double t_s, int completed, int work_pending, int obstructed);

#endif

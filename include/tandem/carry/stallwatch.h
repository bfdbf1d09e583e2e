/* stallwatch: detects a cell that has stopped making progress (issue: no
 * silent stall).
 *
 * The supervisor feeds it once per cycle: the cycle's time, whether a
 * transition completed, whether work is pending (a transition enabled or
 * running) and whether an obstruction is known to be in the cell (the
 * stick). The watch counts time without a completion while work is pending
 * and nothing obstructs the cell; past limit_s it reports a stall. An
 * obstruction restarts the count (a blocked arm may wait as long as the
 * block lasts; once it is out the arm must finish within limit_s again)
 * -- but only for obstruct_max_s: an obstruction that never ends (or a
 * stick the cell wrongly believes in) cannot hold the cell for ever;
 * past it the obstructed time counts as idle. A completion ends a stall;
 * `stalls` counts the stalls seen.
 */
#ifndef TANDEM_STALLWATCH_H
#define TANDEM_STALLWATCH_H

typedef struct stallwatch {
    double limit_s;        /* time without progress that is a stall (> 0) */
    double obstruct_max_s; /* longest obstruction that excuses it (> 0) */
    double obstructed_s;   /* length of the obstruction going on */
    double idle_s;         /* time counted so far */
    double last_t_s;       /* time of the previous update, < 0 before the first */
    int stalled;           /* 1 while stalled */
    int stalls;            /* stalls begun */
} stallwatch;

enum { STALLWATCH_OK = 0, STALLWATCH_ERR_ARG = -1 };

/* obstruct_max_s unless set, s: longer than any block the scenarios make
 * (60 s). Written as an integer so that tandem-supervisor's help shows it
 * as written (OPTION_DEF). */
#define STALLWATCH_OBSTRUCT_MAX_S 120

/* limit_s finite and > 0; obstruct_max_s STALLWATCH_OBSTRUCT_MAX_S. */
int stallwatch_init(stallwatch *w, double limit_s);
/* obstruct_max_s finite and > 0. */
int stallwatch_set_obstruct_max(stallwatch *w, double obstruct_max_s);
/* One cycle at time t_s (non-decreasing). Returns 1 on the update at which
 * a stall begins, 0 otherwise, STALLWATCH_ERR_ARG on bad input (state
 * unchanged). */
int stallwatch_update(stallwatch *w, double t_s, int completed, int work_pending, int obstructed);

#endif

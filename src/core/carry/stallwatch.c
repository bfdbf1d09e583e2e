/* stallwatch: progress watchdog of the supervisor: time without a
 * completion while work is pending and nothing obstructs the cell, past a
 * limit, is a stall (no equation of docs/method/; issue: no silent stall; see
 * stallwatch.h). */
#include "stallwatch.h"

#include <math.h>

int stallwatch_init(stallwatch *w, double limit_s)
{
    if (!w || !isfinite(limit_s) || limit_s <= 0.0)
        return STALLWATCH_ERR_ARG;
    w->limit_s = limit_s;
    w->obstruct_max_s = STALLWATCH_OBSTRUCT_MAX_S;
    w->obstructed_s = 0.0;
    w->idle_s = 0.0;
    w->last_t_s = -1.0;
    w->stalled = 0;
    w->stalls = 0;
    return STALLWATCH_OK;
}

int stallwatch_set_obstruct_max(stallwatch *w, double obstruct_max_s)
{
    if (!w || !isfinite(obstruct_max_s) || obstruct_max_s <= 0.0)
        return STALLWATCH_ERR_ARG;
    w->obstruct_max_s = obstruct_max_s;
    return STALLWATCH_OK;
}

int stallwatch_update(stallwatch *w, double t_s, int completed, int work_pending, int obstructed)
{
    double dt;
    if (!w || !isfinite(t_s) || (w->last_t_s >= 0.0 && t_s < w->last_t_s))
        return STALLWATCH_ERR_ARG;
    dt = w->last_t_s >= 0.0 ? t_s - w->last_t_s : 0.0;
    w->last_t_s = t_s;
    w->obstructed_s = obstructed && !completed && work_pending ? w->obstructed_s + dt : 0.0;
    if (obstructed && w->obstructed_s > w->obstruct_max_s)
        obstructed = 0; /* too long: no longer an excuse */
    if (completed || obstructed || !work_pending) {
        /* progress, an obstruction to wait for, or nothing to do */
        w->idle_s = 0.0;
        if (completed || !work_pending)
            w->stalled = 0;
        return 0;
    }
    w->idle_s += dt;
    if (!w->stalled && w->idle_s > w->limit_s) {
        w->stalled = 1;
        w->stalls++;
        return 1;
    }
    return 0;
}

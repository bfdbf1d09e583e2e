/* guard: step plausibility gates (see guard.h). */
#include "guard.h"
#include <math.h>

void step_gate_init(step_gate *g, int64_t window, int64_t resync_ns)
{
    g->last_step = -1;
    g->last_rx_ns = 0;
    g->window = window;
    g->resync_ns = resync_ns;
}

int step_gate_check(const step_gate *g, int64_t step, int64_t now_ns)
{
    if (step < 0)
        return GUARD_ERR_NEGATIVE;
    if (g->last_step < 0 || now_ns - g->last_rx_ns > g->resync_ns)
        return GUARD_OK;
    if (step < g->last_step)
        return GUARD_ERR_BEHIND;
    /* written as a difference of non-negative numbers: cannot overflow */
    if (step - g->last_step > g->window)
        return GUARD_ERR_JUMP;
    return GUARD_OK;
}

void step_gate_accept(step_gate *g, int64_t step, int64_t now_ns)
{
    g->last_step = step;
    g->last_rx_ns = now_ns;
}

int step_gate_pass(step_gate *g, int64_t step, int64_t now_ns)
{
    const int rc = step_gate_check(g, step, now_ns);
    if (rc == GUARD_OK)
        step_gate_accept(g, step, now_ns);
    return rc;
}

int all_within(const double *v, int n, double lo, double hi)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i]) || v[i] < lo || v[i] > hi)
            return 0;
    return 1;
}

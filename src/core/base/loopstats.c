/* loopstats: fixed-histogram cycle statistics (docs/method/lockstep.md §7 health message).
 * A histogram instead of a sample buffer keeps memory constant however long
 * a daemon runs; the percentile error is at most one bin (1 us).
 */
#include "loopstats.h"
#include <math.h>

void loopstats_reset(loopstats *s)
{
    int i;
    for (i = 0; i < LOOPSTATS_BINS; i++)
        s->hist[i] = 0;
    s->count = 0;
    s->sum_us = 0.0;
    s->min_us = 0.0;
    s->max_us = 0.0;
}

int loopstats_add(loopstats *s, double sample_us)
{
    double bin;
    if (!isfinite(sample_us) || sample_us < 0.0)
        return LOOPSTATS_ERR_ARG;
    bin = sample_us / LOOPSTATS_BIN_US;
    if (bin >= (double)(LOOPSTATS_BINS - 1))
        bin = (double)(LOOPSTATS_BINS - 1);
    if (s->hist[(int)bin] < UINT32_MAX)
        s->hist[(int)bin]++;
    if (s->count == 0 || sample_us < s->min_us)
        s->min_us = sample_us;
    if (s->count == 0 || sample_us > s->max_us)
        s->max_us = sample_us;
    s->count++;
    s->sum_us += sample_us;
    return 0;
}

double loopstats_mean(const loopstats *s)
{
    return s->count > 0 ? s->sum_us / (double)s->count : 0.0;
}

double loopstats_percentile(const loopstats *s, double p)
{
    double need, seen = 0.0, edge;
    int i;
    if (s->count == 0)
        return 0.0;
    if (p < 0.0)
        p = 0.0;
    if (p > 1.0)
        p = 1.0;
    need = p * (double)s->count;
    for (i = 0; i < LOOPSTATS_BINS; i++) {
        seen += (double)s->hist[i];
        if (seen >= need && seen > 0.0)
            break;
    }
    if (i >= LOOPSTATS_BINS - 1)
        return s->max_us;
    edge = (double)(i + 1) * LOOPSTATS_BIN_US;
    return edge < s->max_us ? edge : s->max_us;
}

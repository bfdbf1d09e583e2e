/* loopstats: cycle-time statistics of a periodic loop with no allocation.
 *
 * min / mean / max exactly, percentiles from a fixed histogram
 * (LOOPSTATS_BINS bins of LOOPSTATS_BIN_US each; the last bin collects
 * everything longer). docs/method/lockstep.md §7: every daemon reports min/mean/max/p99
 * cycle time and overruns in its health message.
 */
#ifndef TANDEM_LOOPSTATS_H
#define TANDEM_LOOPSTATS_H

#include <stdint.h>

#define LOOPSTATS_ERR_ARG (-1) /* sample negative or not finite (ignored) */

#define LOOPSTATS_BINS 2048
#define LOOPSTATS_BIN_US 1.0 /* 1 us resolution up to ~2 ms, then overflow */

typedef struct loopstats {
    uint32_t hist[LOOPSTATS_BINS];
    int64_t count;
    double sum_us;
    double min_us;
    double max_us;
} loopstats;

void loopstats_reset(loopstats *s);
/* Negative or non-finite samples are ignored (returns LOOPSTATS_ERR_ARG). */
int loopstats_add(loopstats *s, double sample_us);
double loopstats_mean(const loopstats *s);
/* Upper edge of the bin holding the p-quantile, p in [0, 1]; 0 if empty.
 * Clamped to max_us, so it never overstates the largest sample. */
double loopstats_percentile(const loopstats *s, double p);

#endif

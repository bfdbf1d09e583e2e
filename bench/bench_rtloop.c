/* bench_rtloop: wake-up latency of the core's rtloop at a given period,
 * for comparison with cyclictest run at the same period (tools/bench.sh).
 *   bench_rtloop [PERIOD_US] [LOOPS] [PRIO]
 * Prints p50 / p99 / max wake-up latency in microseconds. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "rtloop.h"

int main(int argc, char **argv)
{
    const long period_us = argc > 1 ? atol(argv[1]) : 1000;
    const long loops = argc > 2 ? atol(argv[2]) : 10000;
    const int prio = argc > 3 ? atoi(argv[3]) : 0;
    int dma_latency_fd = -1; /* the latency hint holds while it is open */
    rtloop l;
    long i;
    daemon_rt_setup("bench_rtloop", prio,
                    &dma_latency_fd); /* the same set-up as every daemon's --rt */
    if (rtloop_init(&l, (int64_t)period_us * 1000) != 0) {
        fprintf(stderr, "bench_rtloop: bad period\n");
        return 2;
    }
    for (i = 0; i < loops; i++) {
        rtloop_wait(&l);
        rtloop_end_cycle(&l);
    }
    printf("rtloop   period %ld us, %ld loops: latency p50 %.0f us  p99 %.0f us  max %.0f us  "
           "overruns %lld\n",
           period_us, loops, loopstats_percentile(&l.latency, 0.5),
           loopstats_percentile(&l.latency, 0.99), l.latency.max_us, (long long)l.overruns);
    return 0;
}

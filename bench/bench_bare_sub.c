/* bench_bare_sub: a bare LCM subscriber, no tandem code: the baseline a
 * flood is measured against (docs/security.md, "Flooding").
 *   bench_bare_sub [SECONDS] [CHANNEL]
 * subscribes to CHANNEL (default ARM1_ACTION) with lcm_subscribe alone,
 * handles messages for SECONDS (default 60) and prints how many arrived
 * and its resident memory. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <lcm/lcm.h>

typedef struct bare {
    long messages;
    long long bytes;
} bare;

static volatile sig_atomic_t stop;
static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

static void on_msg(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    bare *b = u;
    (void)ch;
    b->messages++;
    b->bytes += rb->data_size;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* VmRSS of this process in kB, -1 if /proc does not say. */
static long rss_kb(void)
{
    char line[256];
    long kb = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "VmRSS:", 6) == 0)
            kb = atol(line + 6);
    fclose(f);
    return kb;
}

int main(int argc, char **argv)
{
    const double seconds = argc > 1 ? atof(argv[1]) : 60.0;
    const char *channel = argc > 2 ? argv[2] : "ARM1_ACTION";
    bare b = { 0, 0 };
    double t0;
    lcm_t *lcm = lcm_create(NULL);
    if (!lcm)
        return 1;
    lcm_subscribe(lcm, channel, on_msg, &b);
    printf("bench_bare_sub: %s, rss %ld kB at start\n", channel, rss_kb());
    fflush(stdout);
    t0 = now_s();
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal); /* stopped early: still says what it saw */
    while (!stop && now_s() - t0 < seconds)
        lcm_handle_timeout(lcm, 100);
    printf("bench_bare_sub: %ld messages (%.1f MB) in %.0f s, rss %ld kB at the end\n", b.messages,
           (double)b.bytes * 1e-6, now_s() - t0, rss_kb());
    lcm_destroy(lcm);
    return 0;
}

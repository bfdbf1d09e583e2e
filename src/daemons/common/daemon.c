/* daemon: shared daemon shell (see daemon.h). */
#include "daemon.h"
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#ifdef __linux__
#include <sys/prctl.h>
#endif
#include <sys/select.h>
#include <sys/time.h>
#include <time.h>
#include <sys/stat.h> /* futimens */
#include <unistd.h>
#include "rx.h"
#include "shell_status.h"
#include "tandem_clock_ack_t.h"
#include "tandem_health_t.h"
#include "tandem_sim_clock_t.h"

static volatile sig_atomic_t stop_flag;

static void on_signal(int sig)
{
    (void)sig;
    stop_flag = 1;
}

int daemon_stop_requested(void)
{
    return stop_flag != 0;
}
void daemon_request_stop(void)
{
    stop_flag = 1;
}

int64_t daemon_utime_now(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
}

int parse_double_opt(const char *prog, const char *opt, const char *s, double lo, double hi,
                     double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (s[0] == '\0' || *end != '\0' || errno != 0 || !isfinite(v)) {
        fprintf(stderr, "%s: %s: '%s' is not a number\n", prog, opt, s);
        return DAEMON_ERR_NUMBER;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "%s: %s: %g is outside [%g, %g]\n", prog, opt, v, lo, hi);
        return DAEMON_ERR_RANGE;
    }
    *out = v;
    return 0;
}

int parse_int_opt(const char *prog, const char *opt, const char *s, long lo, long hi, long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (s[0] == '\0' || *end != '\0' || errno != 0) {
        fprintf(stderr, "%s: %s: '%s' is not an integer\n", prog, opt, s);
        return DAEMON_ERR_NUMBER;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "%s: %s: %ld is outside [%ld, %ld]\n", prog, opt, v, lo, hi);
        return DAEMON_ERR_RANGE;
    }
    *out = v;
    return 0;
}

void daemon_defaults(daemon *d, const char *name, double period_s)
{
    const char *env = getenv("LCM_DEFAULT_URL");
    /* Line-buffered even into a pipe (tandem-run reads every daemon's
     * stdout through one): a line not flushed by hand would otherwise reach
     * the console seconds after the event it reports, behind later lines of
     * the other daemons. This is the first call of every daemon's main,
     * before anything is written, as setvbuf requires. */
    setvbuf(stdout, NULL, _IOLBF, BUFSIZ);
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", name);
    d->lcm_url = (env && env[0]) ? env : DAEMON_DEFAULT_LCM_URL;
    d->period_s = period_s;
    d->step = -1;
    d->pending_step = -1;
    d->queue_capacity = DAEMON_QUEUE_CAPACITY;
    d->dma_latency_fd = -1;
    d->heartbeat_fd = -1;
    d->answered_step = -1;
    d->drop_seed = 1;
    rx_init(&d->rx);
    /* a clock may jump 10 s ahead of the last one we saw (a slow
     * participant); after 1 s without a clock any step is taken (reset) */
    step_gate_init(&d->clock_gate, 10000, 1000000000LL);
    snprintf(d->status, sizeof d->status, "starting");
}

int daemon_check_table(const char *prog, const char *table, const char *validator, int rc,
                       const char *(*strerror_fn)(int))
{
    if (rc == 0)
        return 0;
    fprintf(stderr, "%s: %s is invalid (%s: %s, %d)\n", prog, table, validator, strerror_fn(rc),
            rc);
    return DAEMON_ERR_TABLE;
}

void daemon_rt_setup(const char *name, int prio, int *dma_latency_fd)
{
    struct sched_param sp;
#ifdef PR_SET_TIMERSLACK
    /* A periodic control loop wants its wake-up on time: the default 50 us
     * timer slack of normal threads would be added to every cycle. */
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
#endif
    if (prio <= 0)
        return;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = prio;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
        fprintf(stderr,
                "%s: warning: SCHED_FIFO priority %d not permitted (%s); "
                "running with normal scheduling\n",
                name, prio, strerror(errno));
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
        fprintf(stderr, "%s: warning: mlockall not permitted (%s); pages may fault\n", name,
                strerror(errno));
    /* Like cyclictest: hold the CPU out of deep idle states while we run
     * (the kernel honours this only while the file stays open). */
    if (*dma_latency_fd < 0) {
        const int32_t zero = 0;
        *dma_latency_fd = open("/dev/cpu_dma_latency", O_WRONLY);
        if (*dma_latency_fd >= 0 &&
            write(*dma_latency_fd, &zero, sizeof zero) != (ssize_t)sizeof zero) {
            close(*dma_latency_fd);
            *dma_latency_fd = -1;
        }
    }
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    daemon *d = user;
    tandem_sim_clock_t m;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_sim_clock_t, rb, &m))
        return;
    if (!isfinite(m.sim_time_s) ||
        step_gate_pass(&d->clock_gate, m.step, rtloop_now_ns()) != GUARD_OK) {
        d->msgs.rejected++;
        tandem_sim_clock_t_decode_cleanup(&m);
        return;
    }
    d->step = m.step;
    d->sim_time_s = m.sim_time_s;
    d->clock_rx_ns = rtloop_now_ns();
    if (d->lockstep && m.mode == TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP && m.step % d->period_steps == 0)
        d->pending_step = m.step;
    tandem_sim_clock_t_decode_cleanup(&m);
}

void daemon_heartbeat_open(daemon *d)
{
    const char *dir = getenv(DAEMON_HEARTBEAT_ENV);
    char path[512];
    d->heartbeat_fd = -1;
    if (!dir || !dir[0])
        return;
    if (snprintf(path, sizeof path, "%s/%ld", dir, (long)getpid()) >= (int)sizeof path)
        return;
    d->heartbeat_fd = open(path, O_WRONLY | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (d->heartbeat_fd < 0)
        fprintf(stderr, "%s: heartbeat file %s: %s (no heartbeat for the launcher)\n", d->name,
                path, strerror(errno));
}

int daemon_start(daemon *d)
{
    struct sigaction sa;
    size_t i;
    long steps;
    int rc;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);

    steps = lround(d->period_s / DAEMON_SIM_DT_S);
    d->period_steps = (int32_t)(steps < 1 ? 1 : steps);
    snprintf(d->health_channel, sizeof d->health_channel, "HEALTH_%s", d->name);
    for (i = 0; d->health_channel[i]; i++)
        d->health_channel[i] = (char)(d->health_channel[i] == '-'
                                          ? '_'
                                          : toupper((unsigned char)d->health_channel[i]));

    if (auth_bus_start(&d->bus, d->name) != 0)
        return DAEMON_ERR_AUTH;
    rx_set_drop(&d->rx, d->drop_rate, (uint64_t)d->drop_seed);
    names_watch_init(&d->names, d->name); /* before LCM's receive thread starts */
    names_watch_fleet(&d->names, d->fleet_robots);
    d->lcm = lcm_create(d->lcm_url);
    if (!d->lcm) {
        fprintf(stderr, "%s: cannot open LCM at '%s'\n", d->name, d->lcm_url);
        return DAEMON_ERR_LCM;
    }
    rc = renew_start(&d->renew, d->lcm_url, d->queue_capacity);
    if (rc != RENEW_OK)
        fprintf(stderr, "%s: %s (%d): a flood of channel names is bounded on the control thread\n",
                d->name, renew_strerror(rc), rc);
    if (!d->clock_source)
        daemon_subscribe(d, "SIM_CLOCK", on_clock, d);
    daemon_rt_setup(d->name, d->rt_prio, &d->dma_latency_fd);
    if (rtloop_init(&d->loop, (int64_t)llround(d->period_s * 1e9)) != 0) {
        fprintf(stderr, "%s: period %g s out of range\n", d->name, d->period_s);
        return DAEMON_ERR_RANGE;
    }
    daemon_heartbeat_open(d); /* at start-up: the loop only touches it */
    d->last_health_ns = rtloop_now_ns();
    return 0;
}

void daemon_queue_for_burst(daemon *d, long burst)
{
    if (burst > DAEMON_QUEUE_CAPACITY / 2 && burst <= INT_MAX / 2)
        d->queue_capacity = (int)(2 * burst);
}

lcm_subscription_t *daemon_subscribe(daemon *d, const char *channel, lcm_msg_handler_t handler,
                                     void *user)
{
    lcm_subscription_t *s = rx_subscribe(d, channel, handler, user);
    /* LCM keeps 30 messages per subscription by default and drops the rest
     * silently: a busy moment must not lose inputs, nor a whole team's
     * burst; but what LCM keeps must stay bounded under a flood
     * (d->queue_capacity: DAEMON_QUEUE_CAPACITY, or what its burst takes) */
    if (s)
        lcm_subscription_set_queue_capacity(s, d->queue_capacity);
    return s;
}

int daemon_subscribe_numbered(daemon *d, const char *prefix, int first, int last,
                              const char *suffix, lcm_msg_handler_t handler, void *user,
                              lcm_subscription_t **subs, int cap)
{
    char ch[RX_CHANNEL_NAME];
    int k, n = 0;
    if (last - first + 1 > DAEMON_EXPLICIT_MAX || first < 0) {
        snprintf(ch, sizeof ch, "%s[0-9]+%s", prefix, suffix);
        subs[0] = daemon_subscribe(d, ch, handler, user);
        return subs[0] ? 1 : 0;
    }
    for (k = first; k <= last && n < cap; k++) {
        snprintf(ch, sizeof ch, "%s%d%s", prefix, k, suffix);
        if ((subs[n] = daemon_subscribe(d, ch, handler, user)) != NULL)
            n++;
    }
    return n;
}

int64_t daemon_drain_budget_ns(const daemon *d)
{
    const int64_t b = (int64_t)(d->period_s * 0.25e9);
    return b > 50000 ? b : 50000; /* at least 50 us: a few messages always get through */
}

/* 1 when LCM has a message waiting on fd. */
static int readable(int fd)
{
    fd_set fds;
    struct timeval tv = { 0, 0 };
    FD_ZERO(&fds);
    FD_SET(fd, &fds);
    return select(fd + 1, &fds, NULL, NULL, &tv) > 0;
}

/* Handles what lcm holds, without blocking, for at most DAEMON_DRAIN_MAX
 * messages and budget_ns: 1 if some is left. */
static int drain_lcm(lcm_t *lcm, int64_t budget_ns)
{
    const int fd = lcm_get_fileno(lcm);
    const int64_t t0 = rtloop_now_ns();
    int n;
    for (n = 0; n < DAEMON_DRAIN_MAX; n++) {
        if (!readable(fd) || lcm_handle(lcm) != 0)
            return 0;
        if (rtloop_now_ns() - t0 >= budget_ns)
            break;
    }
    return readable(fd);
}

/* This thread's CPU time (not the wall clock: on a loaded machine a
 * drain's wall time holds other processes' turns too). */
static int64_t thread_cpu_ns(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0)
        return 0;
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Receive work that began at thread CPU time c0 ends now: the most of it
 * in one go is the health's rx_cpu_max_us. */
static void rx_cpu_note(daemon *d, int64_t c0)
{
    const int64_t cpu_ns = thread_cpu_ns() - c0;
    if (cpu_ns > d->rx.drain_cpu_max_ns)
        d->rx.drain_cpu_max_ns = cpu_ns;
}

void daemon_drain(daemon *d)
{
    const int64_t c0 = thread_cpu_ns();
    /* out of budget: what is still queued waits for the next cycle */
    if (drain_lcm(d->lcm, daemon_drain_budget_ns(d)))
        d->rx.deferred++;
    rx_cpu_note(d, c0);
}

void daemon_publish_health(daemon *d)
{
    tandem_health_t h;
    memset(&h, 0, sizeof h);
    h.seq = d->health_seq++;
    h.utime = daemon_utime_now();
    h.step = d->step;
    h.name = d->name;
    h.pid = (int32_t)getpid();
    h.period_us = d->period_s * 1e6;
    h.cycles = d->loop.cycles;
    h.cycle_min_us = d->loop.cycle.min_us;
    h.cycle_mean_us = loopstats_mean(&d->loop.cycle);
    h.cycle_max_us = d->loop.cycle.max_us;
    h.cycle_p99_us = loopstats_percentile(&d->loop.cycle, 0.99);
    h.wake_latency_p99_us = loopstats_percentile(&d->loop.latency, 0.99);
    h.overruns = d->loop.overruns;
    h.msgs_received = d->msgs.received;
    h.msgs_rejected = d->msgs.rejected;
    h.msgs_stale = d->msgs.stale;
    h.safe_hold = (int8_t)d->safe_hold;
    h.status = d->status;
    h.lockstep_repeats = d->repeats;
    h.lockstep_input_waits = d->input_waits;
    h.msgs_duplicate = d->msgs.duplicate;
    rx_fill_health(&d->rx, &h);
    auth_bus_fill_health(&d->bus, &h);
    AUTH_PUBLISH(tandem_health_t, &d->bus, d->lcm, d->health_channel, &h);
}

void lockstep_ack(auth_bus *bus, lcm_t *lcm, const char *name, int64_t seq, int64_t step,
                  int32_t period_steps, int leaving)
{
    tandem_clock_ack_t a;
    a.seq = seq;
    a.utime = daemon_utime_now();
    a.step = step;
    a.name = (char *)name;
    a.period_steps = period_steps;
    a.leaving = (int8_t)leaving;
    a.pid = (int32_t)getpid();
    AUTH_PUBLISH(tandem_clock_ack_t, bus, lcm, "SIM_ACK", &a);
}

static void ack(daemon *d, int64_t step, int leaving)
{
    lockstep_ack(&d->bus, d->lcm, d->name, d->ack_seq++, step, d->period_steps, leaving);
}

/* Resident memory in kB (/proc/self/statm), 0 if it cannot be read. Read
 * with open/read into a stack buffer: it runs in the loop's health tick,
 * where stdio's buffer would be an allocation. */
static long rss_kb(void)
{
    char text[96];
    long size = 0, resident = 0;
    ssize_t n;
    const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return 0;
    n = read(fd, text, sizeof text - 1);
    close(fd);
    if (n <= 0)
        return 0;
    text[n] = 0;
    if (sscanf(text, "%ld %ld", &size, &resident) != 2)
        return 0;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* 1 if glib was told to free what it frees (DAEMON_GLIB_SLICE_ENV). */
static int slice_freed(void)
{
    const char *v = getenv(DAEMON_GLIB_SLICE_ENV);
    return v && strstr(v, DAEMON_GLIB_SLICE_VALUE) != NULL;
}

void names_watch_env(char **argv)
{
    if (slice_freed() || setenv(DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE, 1) != 0)
        return;
    execv("/proc/self/exe", argv);
    /* not run again: names_watch_init says what that costs */
    unsetenv(DAEMON_GLIB_SLICE_ENV);
}

void names_watch_init(names_watch *w, const char *who)
{
    const char *env = getenv(DAEMON_NAMES_SLACK_ENV);
    /* What a renewed LCM handle frees must go back to the system, or the
     * bound on its table of channel names is not one: what LCM's receive
     * thread freed in a malloc arena of its own stayed resident (16 of 20
     * MB did); with one arena malloc_trim returns it. glib 2.74's slice
     * allocator also keeps freed slices for itself: it reads G_SLICE as
     * the library loads, so the launchers set G_SLICE=always-malloc for
     * their children (DAEMON_GLIB_SLICE_ENV). */
#ifdef __GLIBC__
    mallopt(M_ARENA_MAX, 1);
#endif
    memset(w, 0, sizeof *w);
    w->who = who;
    w->slack_kb = DAEMON_NAMES_SLACK_KB;
    if (env && env[0]) {
        char *end;
        const long v = strtol(env, &end, 10);
        if (*end == '\0' && v >= DAEMON_NAMES_SLACK_MIN_KB && v <= DAEMON_NAMES_SLACK_MAX_KB)
            w->slack_kb = v;
        else
            fprintf(stderr, "%s: %s=%s is not a number of kB in [%ld, %ld]: %ld kB\n", who,
                    DAEMON_NAMES_SLACK_ENV, env, DAEMON_NAMES_SLACK_MIN_KB,
                    DAEMON_NAMES_SLACK_MAX_KB, w->slack_kb);
    }
    if (!slice_freed())
        fprintf(stderr,
                "%s: %s is not %s: glib keeps what a renewed LCM handle frees, so the bound on "
                "LCM's table of channel names grows with each renewal (docs/security.md §5)\n",
                who, DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE);
}

int lcm_renew(lcm_t **lcm, const char *url, lcm_move_fn move, void *subs, int64_t budget_ns)
{
    lcm_t *const old = *lcm, *const fresh = lcm_create(url);
    if (!fresh)
        return DAEMON_ERR_LCM;
    move(subs, old, fresh);
    *lcm = fresh; /* a handler that publishes, publishes on the new one */
    drain_lcm(old, budget_ns);
    lcm_destroy(old);
#ifdef __GLIBC__
    malloc_trim(0); /* the freed names back to the system, not only to malloc */
#endif
    return DAEMON_OK;
}

/* 1 when w's check is due (now) and resident memory is its slack above
 * its base, *rss the resident memory; a lower reading is the new base. */
static int names_over(names_watch *w, int64_t now, long *rss)
{
    if (now - w->check_ns < DAEMON_NAMES_CHECK_NS)
        return 0;
    w->check_ns = now;
    if ((*rss = rss_kb()) <= 0)
        return 0;
    if (w->base_kb == 0 || *rss < w->base_kb) {
        w->base_kb = *rss;
        return 0;
    }
    return *rss - w->base_kb >= (w->slack_kb > 0 ? w->slack_kb : DAEMON_NAMES_SLACK_KB);
}

void names_watch_fleet(names_watch *w, int robots)
{
    const char *env = getenv(DAEMON_NAMES_SLACK_ENV);
    if ((env && env[0]) || robots <= 0)
        return;
    w->slack_kb = DAEMON_NAMES_SLACK_KB + (long)robots * DAEMON_NAMES_SLACK_ROBOT_KB;
}

int names_watch_tick(names_watch *w, int64_t now, lcm_t **lcm, const char *url, lcm_move_fn move,
                     void *subs, int64_t budget_ns)
{
    long rss;
    if (!*lcm || !names_over(w, now, &rss))
        return 0;
    if (lcm_renew(lcm, url, move, subs, budget_ns) != DAEMON_OK) {
        fprintf(stderr,
                "%s: resident memory %ld kB (from %ld): a new LCM handle does not open, the old "
                "one kept\n",
                w->who, rss, w->base_kb);
        w->base_kb = rss; /* said once per slack's growth, not at 10 Hz */
        return 0;
    }
    w->renewals++;
    fprintf(stderr,
            "%s: resident memory %ld kB, %ld kB above its base: LCM handle renewed (a flood of "
            "channel names?), ",
            w->who, rss, rss - w->base_kb);
    w->base_kb = rss_kb();
    fprintf(stderr, "now %ld kB\n", w->base_kb);
    return 1;
}

static int rx_move(void *user, lcm_t *old, lcm_t *fresh)
{
    daemon *d = user;
    return rx_move_subscriptions(&d->rx, old, fresh, d->queue_capacity);
}

/* A new handle the worker made takes the old one's place: its
 * subscriptions are moved, what the old one holds is handed on within
 * the drain budget, and the worker closes it. 1 when swapped. */
static int swap_renewed(daemon *d)
{
    lcm_t *fresh, *const old = d->lcm;
    lcm_subscription_t *const *staged;
    int n_staged;
    if (!renew_take(&d->renew, &fresh, &staged, &n_staged))
        return 0;
    rx_commit_subscriptions(&d->rx, old, fresh, staged, n_staged, d->queue_capacity);
    d->lcm = fresh; /* a handler that publishes, publishes on the new one */
    drain_lcm(old, daemon_drain_budget_ns(d));
    renew_retire(&d->renew, old);
    d->names.renewals++;
    /* read again once the worker has closed the old one: the lowest
     * reading from then on is the base */
    d->names.base_kb = 0;
    fprintf(stderr,
            "%s: LCM handle renewed (renewal %lld); the old one is closed beside the loop\n",
            d->name, (long long)d->names.renewals);
    return 1;
}

int daemon_renew_lcm(daemon *d)
{
    const struct timespec ms = { 0, 1000000L };
    int64_t failures;
    int i;
    if (!d->renew.started) {
        if (lcm_renew(&d->lcm, d->lcm_url, rx_move, d, daemon_drain_budget_ns(d)) != DAEMON_OK)
            return DAEMON_ERR_LCM;
        d->names.renewals++;
        return DAEMON_OK;
    }
    failures = renew_failures(&d->renew);
    for (i = 0; i < DAEMON_RENEW_WAIT_MS; i++) {
        if (swap_renewed(d))
            return DAEMON_OK;
        if (renew_failures(&d->renew) != failures)
            return DAEMON_ERR_LCM;
        renew_request(&d->renew, &d->rx, d->lcm); /* nothing while one is under way */
        nanosleep(&ms, NULL);
    }
    return DAEMON_ERR_LCM;
}

int daemon_names_watch(daemon *d)
{
    const int64_t c0 = thread_cpu_ns();
    int renewed;
    long rss;
    if (!d->renew.started)
        renewed = names_watch_tick(&d->names, rtloop_now_ns(), &d->lcm, d->lcm_url, rx_move, d,
                                   daemon_drain_budget_ns(d));
    else if (!(renewed = swap_renewed(d)) && d->lcm &&
             names_over(&d->names, rtloop_now_ns(), &rss) &&
             renew_request(&d->renew, &d->rx, d->lcm))
        fprintf(stderr,
                "%s: resident memory %ld kB, %ld kB above its base: a new LCM handle is being "
                "made beside the loop (a flood of channel names?)\n",
                d->name, rss, rss - d->names.base_kb);
    if (renewed) /* what a renewal took from this thread is receive work too */
        rx_cpu_note(d, c0);
    return renewed;
}

static int bus_move(void *subs, lcm_t *old, lcm_t *fresh)
{
    return auth_bus_move(subs, old, fresh);
}

int bus_names_watch(names_watch *w, auth_bus *bus, lcm_t **lcm, const char *url)
{
    /* a tool waits on the bus anyway: 50 ms for what the old handle holds */
    return names_watch_tick(w, rtloop_now_ns(), lcm, url, bus_move, bus, 50000000LL);
}

void daemon_health_tick(daemon *d, int64_t now_ns)
{
    if (now_ns - d->last_health_ns < 1000000000LL)
        return;
    d->last_health_ns = now_ns;
    daemon_publish_health(d);
    /* a metadata update of a file already open: nothing to wait for */
    if (d->heartbeat_fd >= 0)
        (void)futimens(d->heartbeat_fd, NULL);
}

static void health_tick(daemon *d)
{
    const int64_t now = rtloop_now_ns();
    daemon_names_watch(d);
    /* lockstep: a cell waits together, but 5 s without any clock means the
     * simulator is gone: say so (the daemon holds; nothing moves anyway) */
    if (d->lockstep && d->clock_rx_ns > 0 && now - d->clock_rx_ns > DAEMON_SIM_SILENT_NS &&
        strncmp(d->status, "no simulator", 12) != 0) {
        snprintf(d->status, sizeof d->status, "no simulator clock for %.0f s",
                 (double)(now - d->clock_rx_ns) * 1e-9);
        fprintf(stderr, "%s: %s\n", d->name, d->status);
    }
    daemon_health_tick(d, now);
}

static int run_realtime(daemon *d, daemon_cycle_fn fn, void *user)
{
    int status = DAEMON_CONTINUE;
    d->loop.next_ns = rtloop_now_ns() + d->loop.period_ns;
    while (!stop_flag && status == DAEMON_CONTINUE) {
        rtloop_wait(&d->loop);
        daemon_drain(d);
        status = fn(d, user);
        rtloop_end_cycle(&d->loop);
        health_tick(d);
    }
    return status;
}

/* Lockstep: the last outputs again (a lost one is found at the next
 * repeat), at most once in DAEMON_REPEAT_GAP_NS. */
static void repeat_outputs(daemon *d, void *user)
{
    const int64_t now = rtloop_now_ns();
    if (!d->repeat_fn || (d->repeat_ns > 0 && now - d->repeat_ns < DAEMON_REPEAT_GAP_NS))
        return;
    d->repeat_fn(d, user);
    d->repeat_ns = now;
}

static int run_lockstep(daemon *d, daemon_cycle_fn fn, void *user)
{
    int status = DAEMON_CONTINUE;
    while (!stop_flag && status == DAEMON_CONTINUE) {
        int64_t t0;
        /* Blocking here is the point of lockstep: nothing happens until the
         * simulator publishes the next step. */
        lcm_handle_timeout(d->lcm, 100);
        health_tick(d);
        if (d->pending_step < 0)
            continue;
        if (d->pending_step == d->answered_step) {
            /* the simulator announced this step again: our ack, or one of
             * our outputs, was lost. Publish them again and answer again;
             * the cycle must not run twice. */
            repeat_outputs(d, user);
            d->repeats++;
            ack(d, d->pending_step, 0);
            d->pending_step = -1;
            continue;
        }
        /* the step's inputs already here (a fleet's: hundreds of
         * messages) are taken before its cycle looks for them */
        daemon_drain(d);
        t0 = rtloop_now_ns();
        d->skip_ack = 0;
        status = fn(d, user);
        rtloop_record(&d->loop, t0);
        if (status != DAEMON_CONTINUE)
            break; /* leaving: daemon_finish says so to the simulator */
        if (!d->skip_ack) {
            ack(d, d->pending_step, 0);
            d->answered_step = d->pending_step;
        } else {
            /* waiting for an input: a mate may wait for ours just the same
             * (each for the other's lost message), so ours go out again */
            d->input_waits++;
            repeat_outputs(d, user);
            /* and say we are here: the step answered last again, which
             * the simulator takes as a sign of life and nothing more */
            if (d->answered_step >= 0)
                ack(d, d->answered_step, 0);
        }
        d->pending_step = -1;
    }
    return status;
}

int daemon_run(daemon *d, daemon_cycle_fn fn, void *user)
{
    int status;
    snprintf(d->status, sizeof d->status, "running");
    status = d->lockstep ? run_lockstep(d, fn, user) : run_realtime(d, fn, user);
    return status == DAEMON_CONTINUE ? DAEMON_STOPPED : status;
}

/* At exit, off the control cycle: who spoke out of turn, if anyone. */
static void daemon_report_unauthorised(const daemon *d)
{
    char why[AUTH_CHANNEL_MAX + 160];
    auth_bus_report_unauthorised(&d->bus, why, sizeof why);
    if (why[0])
        fprintf(stderr, "%s: %s\n", d->name, why);
}

void daemon_finish(daemon *d)
{
    if (!d->lcm)
        return;
    snprintf(d->status, sizeof d->status, "stopped");
    daemon_publish_health(d);
    daemon_report_unauthorised(d);
    /* a participant says it leaves; the simulator, whose clock the
     * participants answer, is none (SIM_ACK is not its channel) */
    if (d->lockstep && !d->clock_source)
        ack(d, d->step, 1);
    renew_stop(&d->renew);
    lcm_destroy(d->lcm);
    d->lcm = NULL;
    auth_bus_free(&d->bus);
    if (d->heartbeat_fd >= 0)
        close(d->heartbeat_fd);
    d->heartbeat_fd = -1;
}

/* tandem-status: one console line a second about the whole running system,
 * and a clear warning when it falls behind real time or a daemon holds
 * safe, from what the daemons already publish (HEALTH_*, SIM_STATUS,
 * ARM_EVENTS, PETRI_MARKING, ROVERk_STATE / ROVERS_STATE): also arm
 * faults, a stalled carry task, daemons running --insecure and messages
 * the daemons refused as unauthenticated (docs/method/lockstep.md §4-5). It checks what it
 * reads like the daemons do (auth_bus.h). tools/tandem-run starts it.
 *
 *   t=  12.3 s  sim/wall 0.98x  overruns +0 (12)  safe hold: -  blocked: -  delivered 2  at goal 0/3
 */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <lcm/lcm.h>
#include "daemon.h"
#include "options.h"
#include "tandem_action_event_t.h"
#include "tandem_health_t.h"
#include "tandem_petri_marking_t.h"
#include "tandem_rover_state_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_sim_status_t.h"

#define MAX_DAEMONS 160
#define MAX_ROBOTS 128
#define REPEAT_WARNING_S 10.0 /* a lasting problem is re-announced this often */
#define SILENT_S 3.0          /* a daemon without health this long is reported */

typedef struct {
    char name[DAEMON_NAME_MAX];
    int64_t overruns, overruns_shown;
    int safe_hold, warned_safe;
    double last_wall_s;
    char status[96];
    int auth_on;                       /* -1 until its first health */
    int64_t auth_kind[AUTH_BUS_KINDS]; /* auth_bus_health_refusals */
    int64_t auth_rejected, auth_rejected_shown;
    double auth_warned_s;
    double period_us, cycle_p99_us, cycle_max_us; /* its loop statistics (--loops) */
    double rx_cpu_max_us;                         /* the most CPU one receive drain took */
    int64_t rx_deferred, msgs_received;
} daemon_view;

static struct {
    daemon_view d[MAX_DAEMONS];
    int n_daemons;
    double sim_s, sim_wall_s;   /* newest SIM_STATUS and when it came */
    double sim_s0, sim_wall0_s; /* the one the last line started from */
    int have_sim, paused, lockstep;
    int32_t delivered, dropped, spawned;
    int blocked[3];                    /* arm 1, 2: 1 while BLOCKED */
    int8_t rover_mode[MAX_ROBOTS + 1]; /* -1 unknown */
    int stalled, stalled_warned;       /* supervisor: no progress for its stall limit */
    int faulted;                       /* bit k-1: arm k reports a joint fault */
    int loops;                         /* --loops: a line per daemon too */
    double behind_ratio;
    double behind_warned_s; /* wall time of the last behind warning, <0 none */
} S;

static volatile sig_atomic_t stop;
static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static daemon_view *find_daemon(const char *name)
{
    int i;
    for (i = 0; i < S.n_daemons; i++)
        if (!strcmp(S.d[i].name, name))
            return &S.d[i];
    if (S.n_daemons == MAX_DAEMONS)
        return NULL;
    snprintf(S.d[S.n_daemons].name, sizeof S.d[0].name, "%s", name);
    S.d[S.n_daemons].auth_on = -1;
    return &S.d[S.n_daemons++];
}

/* --heartbeat-dir DIR: DIR/PID's modification time is the wall time of
 * that process's last health message (how tools/tandem-run tells a hung
 * daemon from a live one: a stopped or spinning process sends none). */
static void note_heartbeat(const char *dir, const tandem_health_t *h)
{
    char path[1200];
    FILE *f;
    if (!dir || h->pid <= 0)
        return;
    snprintf(path, sizeof path, "%s/%ld", dir, (long)h->pid);
    if ((f = fopen(path, "w")) != NULL) {
        fprintf(f, "%s %lld\n", h->name, (long long)h->seq);
        fclose(f);
    }
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *h, void *u)
{
    daemon_view *d = find_daemon(h->name);
    (void)rb;
    (void)ch;
    note_heartbeat(u, h);
    if (!d)
        return;
    d->overruns = h->overruns;
    d->safe_hold = h->safe_hold;
    d->last_wall_s = wall_s();
    snprintf(d->status, sizeof d->status, "%s", h->status);
    if (d->auth_on == 1 && !h->auth_on)
        d->auth_warned_s = 0.0; /* it restarted insecure: warn at once */
    d->auth_on = h->auth_on;
    d->auth_rejected = auth_bus_health_refusals(h, d->auth_kind);
    d->period_us = h->period_us;
    d->cycle_p99_us = h->cycle_p99_us;
    d->cycle_max_us = h->cycle_max_us;
    d->rx_cpu_max_us = h->rx_cpu_max_us;
    d->rx_deferred = h->rx_deferred;
    d->msgs_received = h->msgs_received;
}

static void on_sim(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *s, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    S.sim_s = s->sim_time_s;
    S.sim_wall_s = wall_s();
    if (!S.have_sim) {
        S.sim_s0 = S.sim_s;
        S.sim_wall0_s = S.sim_wall_s;
    }
    S.have_sim = 1;
    S.paused = s->paused;
    S.lockstep = s->n_participants > 0;
    S.delivered = s->workpieces_delivered;
    S.dropped = s->workpieces_dropped;
    S.spawned = s->workpieces_spawned;
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, const tandem_action_event_t *e,
                     void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (e->arm < 1 || e->arm > 2)
        return;
    if (e->event == TANDEM_ACTION_EVENT_T_BLOCKED)
        S.blocked[e->arm] = 1;
    else if (e->event != TANDEM_ACTION_EVENT_T_PROGRESS)
        S.blocked[e->arm] = 0;
}

static void on_marking(const lcm_recv_buf_t *rb, const char *ch, const tandem_petri_marking_t *m,
                       void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    S.stalled = m->stalled;
    S.faulted = m->arms_faulted;
}

static void rover_mode(int32_t robot, int8_t mode)
{
    if (robot >= 1 && robot <= MAX_ROBOTS)
        S.rover_mode[robot] = mode;
}

static void on_rover(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_state_t *s,
                     void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    rover_mode(s->robot, s->mode);
}

static void on_rovers(const lcm_recv_buf_t *rb, const char *ch, const tandem_rovers_state_t *b,
                      void *u)
{
    int i;
    (void)rb;
    (void)ch;
    (void)u;
    for (i = 0; i < b->n; i++)
        rover_mode(b->state[i].robot, b->state[i].mode);
}

/* Daemons without authentication, and messages the daemons refused as
 * unauthenticated since the last warning; both repeated every
 * REPEAT_WARNING_S while they last. */
static void auth_warnings(double now)
{
    int i;
    for (i = 0; i < S.n_daemons; i++) {
        daemon_view *d = &S.d[i];
        const int64_t *k = d->auth_kind;
        const int insecure = d->auth_on == 0;
        const int refused = d->auth_rejected > d->auth_rejected_shown;
        if ((!insecure && !refused) ||
            (d->auth_warned_s > 0.0 && now - d->auth_warned_s < REPEAT_WARNING_S))
            continue;
        if (insecure)
            printf("WARNING: %s runs --insecure: it neither signs nor checks bus messages\n",
                   d->name);
        if (refused)
            printf(
                "WARNING: %s refused %lld unauthenticated messages (unsigned %lld, bad MAC %lld, unknown sender "
                "%lld, replayed %lld, not allowed on the channel %lld, another cell's %lld, refused before the "
                "MAC %lld): something without the key, or an old log, is publishing on the bus\n",
                d->name, (long long)(d->auth_rejected - d->auth_rejected_shown), (long long)k[0],
                (long long)k[1], (long long)k[2], (long long)k[3], (long long)k[4], (long long)k[5],
                (long long)k[6]);
        d->auth_rejected_shown = d->auth_rejected;
        d->auth_warned_s = now;
    }
}

/* --loops: each daemon's cycle times since it started, the drains that
 * ran out of budget and its refusals (how a flood is felt). */
static void loop_lines(void)
{
    int i;
    for (i = 0; i < S.n_daemons && S.loops; i++) {
        const daemon_view *d = &S.d[i];
        printf(
            "  loop %-22s period %7.0f us  cycle p99 %7.0f us  max %8.0f us  overruns %lld  rx deferred %lld  "
            "rx cpu max %6.0f us  received %lld  refused %lld\n",
            d->name, d->period_us, d->cycle_p99_us, d->cycle_max_us, (long long)d->overruns,
            (long long)d->rx_deferred, d->rx_cpu_max_us, (long long)d->msgs_received,
            (long long)d->auth_rejected);
    }
}

/* Safe holds as a list of names; warns once when a daemon enters one. */
static void safe_holds(char *out, size_t cap, double now)
{
    int i;
    size_t len = 0;
    out[0] = '\0';
    for (i = 0; i < S.n_daemons; i++) {
        daemon_view *d = &S.d[i];
        int silent = now - d->last_wall_s > SILENT_S;
        if (d->safe_hold && !d->warned_safe)
            printf("WARNING: %s holds safe: %s\n", d->name, d->status);
        if (silent && d->warned_safe >= 0)
            printf("WARNING: no health from %s for %.0f s\n", d->name, now - d->last_wall_s);
        d->warned_safe = silent ? -1 : d->safe_hold;
        if ((d->safe_hold || silent) && len + strlen(d->name) + 10 < cap)
            len += (size_t)snprintf(out + len, cap - len, "%s%s%s", len ? "," : "", d->name,
                                    silent ? "(silent)" : "");
    }
    if (!out[0])
        snprintf(out, cap, "-");
}

static int64_t overruns_since_last(int64_t *total)
{
    int64_t delta = 0;
    int i;
    *total = 0;
    for (i = 0; i < S.n_daemons; i++) {
        delta += S.d[i].overruns - S.d[i].overruns_shown;
        S.d[i].overruns_shown = S.d[i].overruns;
        *total += S.d[i].overruns;
    }
    return delta;
}

/* sim/wall over the SIM_STATUS messages since the last line; -1 unknown. */
static double speed_ratio(void)
{
    double r = -1.0;
    if (S.have_sim && S.sim_wall_s - S.sim_wall0_s > 0.3)
        r = (S.sim_s - S.sim_s0) / (S.sim_wall_s - S.sim_wall0_s);
    if (S.have_sim && S.sim_wall_s - S.sim_wall0_s > 0.3) {
        S.sim_s0 = S.sim_s;
        S.sim_wall0_s = S.sim_wall_s;
    }
    return r;
}

static void warn_behind(double ratio, double now)
{
    int behind = ratio >= 0.0 && ratio < S.behind_ratio && !S.paused && !S.lockstep;
    if (!behind) {
        if (S.behind_warned_s >= 0.0)
            printf("back in real time (sim/wall %.2fx)\n", ratio);
        S.behind_warned_s = -1.0;
        return;
    }
    if (S.behind_warned_s < 0.0 || now - S.behind_warned_s >= REPEAT_WARNING_S) {
        printf(
            "WARNING: BEHIND REAL TIME: the simulation runs at %.2fx wall-clock speed; controllers "
            "will overrun and hold safe (machine overloaded? see HEALTH_* in make spy)\n",
            ratio);
        S.behind_warned_s = now;
    }
}

static void status_line(double now)
{
    char holds[512], blocked[32] = "-", ratio_s[24] = "  -  ";
    int64_t total, delta = overruns_since_last(&total);
    double ratio = speed_ratio();
    int k, known = 0, at_goal = 0;
    if (S.have_sim && now - S.sim_wall_s > SILENT_S)
        ratio = 0.0; /* the simulator went quiet */
    safe_holds(holds, sizeof holds, now);
    warn_behind(ratio, now);
    auth_warnings(now);
    if (ratio >= 0.0)
        snprintf(ratio_s, sizeof ratio_s, "%.2fx", ratio);
    if (S.stalled && !S.stalled_warned)
        printf(
            "WARNING: the carry task is stalled: work pending and nothing completed (supervisor)\n");
    S.stalled_warned = S.stalled;
    if (S.blocked[1] || S.blocked[2])
        snprintf(blocked, sizeof blocked, "%s%s%s", S.blocked[1] ? "arm1" : "",
                 S.blocked[1] && S.blocked[2] ? "," : "", S.blocked[2] ? "arm2" : "");
    for (k = 1; k <= MAX_ROBOTS; k++) {
        known += S.rover_mode[k] >= 0;
        at_goal += S.rover_mode[k] == TANDEM_ROVER_STATE_T_MODE_AT_GOAL;
    }
    printf("t=%7.1f s  sim/wall %s%s  overruns +%lld (%lld)  safe hold: %s  blocked: %s%s%s%s  "
           "delivered %d/%d dropped %d  at goal %d/%d\n",
           S.sim_s, ratio_s,
           S.lockstep ? " (lockstep)"
           : S.paused ? " (paused)"
                      : "",
           (long long)delta, (long long)total, holds, blocked, S.faulted & 1 ? "  FAULT arm1" : "",
           S.faulted & 2 ? "  FAULT arm2" : "", S.stalled ? "  STALLED" : "", (int)S.delivered,
           (int)S.spawned, (int)S.dropped, at_goal, known);
    loop_lines();
    fflush(stdout);
}

AUTH_TYPED_HANDLER(tandem_health_t, raw_on_health, on_health)
AUTH_TYPED_HANDLER(tandem_sim_status_t, raw_on_sim, on_sim)
AUTH_TYPED_HANDLER(tandem_action_event_t, raw_on_event, on_event)
AUTH_TYPED_HANDLER(tandem_petri_marking_t, raw_on_marking, on_marking)
AUTH_TYPED_HANDLER(tandem_rover_state_t, raw_on_rover, on_rover)
AUTH_TYPED_HANDLER(tandem_rovers_state_t, raw_on_rovers, on_rovers)

typedef struct status_options {
    options_bus net; /* --lcm-url, --key-file, --insecure */
    double every_s, behind_ratio;
    int loops;
    const char *heartbeat_dir;
} status_options;

static const option_entry status_table[] = {
    { .name = "every",
      .type = OPTION_DOUBLE,
      OPTION_AT(status_options, every_s),
      .min = 0.2,
      .max = 60.0,
      .meta = "S",
      .help = "seconds between lines",
      .def = "1" },
    { .name = "behind",
      .type = OPTION_DOUBLE,
      OPTION_AT(status_options, behind_ratio),
      .min = 0.0,
      .max = 1.0,
      .meta = "R",
      .help = "warn below this sim/wall ratio",
      .def = "0.9" },
    { .name = "loops",
      .type = OPTION_FLAG,
      OPTION_AT(status_options, loops),
      .help =
          "also a line per daemon: cycle time p99 and longest since it started, overruns, receive drains "
          "over budget (rx_deferred), the most CPU time one drain took (rx_cpu_max_us), messages received and refused" },
    { .name = "heartbeat-dir",
      .type = OPTION_STRING,
      OPTION_AT(status_options, heartbeat_dir),
      .meta = "DIR",
      .help =
          "on every health message write DIR/PID (its time is the daemon's last heartbeat; tandem-run "
          "kills a daemon whose heartbeat stops)" },
    OPTION_HELP_ENTRY(0),
    OPTION_VERSION_ENTRY,
    { .name = NULL }
};

int main(int argc, char **argv)
{
    auth_bus bus;
    status_options o = { { NULL, &bus }, 1.0, 0.9, 0, NULL };
    const option_program prog = {
        .name = "tandem-status",
        .usage =
            "usage: tandem-status [--lcm-url URL] [--every S] [--behind R] [--loops] [--key-file PATH | --insecure]\n"
            "One line per period about the running system: simulated / wall-clock time\n"
            "ratio, controller overruns (new and total), daemons holding safe, blocked arms,\n"
            "workpieces delivered, rovers at the goal. Prints a WARNING line when the\n"
            "simulation falls behind real time, a daemon holds safe or goes silent, runs\n"
            "--insecure, or refuses unauthenticated messages.\n\n",
        .groups = { { options_bus_tool, &o.net }, { status_table, &o } },
        .n_groups = 2,
    };
    const char *url;
    double every, next;
    int rc;
    lcm_t *lcm;
    names_watch names;
    names_watch_env(argv);
    S.behind_warned_s = -1.0;
    memset(S.rover_mode, -1, sizeof S.rover_mode);
    auth_bus_init(&bus);
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    url = o.net.url;
    every = o.every_s;
    S.behind_ratio = o.behind_ratio;
    S.loops = o.loops;
    auth_bus_identity(&bus, AUTH_ROLE_MONITOR, 0,
                      0); /* reads only: a monitor's key file is enough */
    if (auth_bus_start(&bus, "tandem-status") != 0)
        return 1;
    names_watch_init(&names, "tandem-status");
    if (!(lcm = lcm_create(url))) {
        fprintf(stderr, "tandem-status: cannot open LCM\n");
        return 1;
    }
    auth_bus_subscribe(&bus, lcm, "HEALTH_.*", raw_on_health, (void *)o.heartbeat_dir);
    auth_bus_subscribe(&bus, lcm, "SIM_STATUS", raw_on_sim, NULL);
    auth_bus_subscribe(&bus, lcm, "ARM_EVENTS", raw_on_event, NULL);
    auth_bus_subscribe(&bus, lcm, "PETRI_MARKING", raw_on_marking, NULL);
    auth_bus_subscribe(&bus, lcm, "ROVER[0-9]+_STATE", raw_on_rover, NULL);
    auth_bus_subscribe(&bus, lcm, "ROVERS_STATE", raw_on_rovers, NULL);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    next = wall_s() + every;
    while (!stop) {
        double now = wall_s();
        if (now >= next) {
            status_line(now);
            next += every;
            if (next < now)
                next = now + every;
        }
        /* at most 0.1 s: a flood of names that reaches no subscription
         * wakes nothing, and the bound is looked at as often as the
         * daemons look at theirs (DAEMON_NAMES_CHECK_NS) */
        lcm_handle_timeout(lcm, next - now < 0.1 ? (int)((next - now) * 1000.0) + 1 : 100);
        bus_names_watch(&names, &bus, &lcm, url); /* a flood of channel names: a new handle */
    }
    auth_bus_close(&bus, lcm);
    return 0;
}

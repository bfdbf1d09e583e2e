/* harness: child daemons on a private LCM bus (see harness.h). */
#include "harness.h"
#include <math.h>
#include <dirent.h>
#include <stdarg.h>
#include <signal.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "daemon.h"
#include "tandem_action_row_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_health_t.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The test's key, made once per process; then h's bus on it. */
static int harness_key(harness *h)
{
    static int ready;
    char path[600];
    if (!ready && auth_bus_ephemeral_key(path, sizeof path) != 0)
        return -1;
    ready = 1;
    auth_bus_init(&h->bus);
    auth_bus_sign_as_owner(&h->bus, 1);
    return auth_bus_start(&h->bus, "harness") != 0 ? -1 : 0;
}

int harness_open(harness *h, int port_offset)
{
    memset(h, 0, sizeof *h);
    if (harness_key(h) != 0)
        return -1;
    proc_init(&h->procs, &h->bus, NULL);
    snprintf(h->url, sizeof h->url, "udpm://239.255.76.67:%d?ttl=0",
             20000 + (int)(getpid() % 20000) + port_offset);
    h->lcm = lcm_create(h->url);
    return h->lcm ? 0 : -1;
}

/* Every child started, so none outlives a test that failed before its
 * harness_close (cmocka leaves the test function on a failed assert). */
#define HARNESS_MAX_SPAWNED 512
static pid_t spawned[HARNESS_MAX_SPAWNED];
static int n_spawned;

/* 1 if pid is our child and still running (a pid already reaped is not
 * our child any more: ECHILD, left alone). */
static int running_child(pid_t pid)
{
    return waitpid(pid, NULL, WNOHANG) == 0;
}

/* The parent of process pid (from /proc), -1 if there is none. */
static int parent_of(long pid)
{
    char path[64], buf[512], *p;
    FILE *f;
    int ppid = -1;
    snprintf(path, sizeof path, "/proc/%ld/stat", pid);
    if (!(f = fopen(path, "r")))
        return -1;
    p = fgets(buf, sizeof buf, f) ? strrchr(buf, ')') : NULL; /* the name may hold spaces */
    fclose(f);
    if (!p || sscanf(p + 1, " %*c %d", &ppid) != 1)
        return -1;
    return ppid;
}

/* The processes whose parent is pid; up to cap. */
static int children_of(pid_t pid, pid_t *out, int cap)
{
    DIR *d = opendir("/proc");
    struct dirent *e;
    int n = 0;
    while (d && n < cap && (e = readdir(d)) != NULL) {
        const long p = atol(e->d_name);
        if (p > 0 && parent_of(p) == (int)pid)
            out[n++] = (pid_t)p;
    }
    if (d)
        closedir(d);
    return n;
}

static void kill_leftovers(void)
{
    pid_t grand[256];
    int i, k, left = 0, n_grand = 0;
    for (i = 0; i < n_spawned; i++)
        if (running_child(spawned[i])) {
            /* a scenario's daemons: found now, while they are still its children */
            n_grand += children_of(spawned[i], grand + n_grand, 256 - n_grand);
            kill(spawned[i], SIGTERM); /* a scenario stops its own daemons */
            left++;
        }
    for (k = 0; k < 30 && left > 0; k++) {
        struct timespec ts = { 0, 100000000L };
        nanosleep(&ts, NULL);
        for (i = 0, left = 0; i < n_spawned; i++)
            left += running_child(spawned[i]);
    }
    for (i = 0; i < n_spawned; i++)
        if (running_child(spawned[i])) {
            kill(spawned[i], SIGKILL);
            waitpid(spawned[i], NULL, 0);
        }
    for (i = 0; i < n_grand; i++)
        if (parent_of(grand[i]) == 1) /* our grandchild left behind (reparented to init) */
            kill(grand[i], SIGKILL);
}

void harness_track_child(pid_t pid)
{
    if (pid <= 0 || n_spawned == HARNESS_MAX_SPAWNED)
        return;
    if (n_spawned == 0)
        atexit(kill_leftovers);
    spawned[n_spawned++] = pid;
}

pid_t harness_spawn(harness *h, const char *const argv[])
{
    const pid_t pid = proc_spawn(&h->procs, argv, h->url, NULL, NULL);
    harness_track_child(pid);
    return pid;
}

int harness_wait(harness *h, pid_t pid, double timeout_s)
{
    const double t0 = now_s();
    int status;
    while (now_s() - t0 < timeout_s) {
        const int r = proc_poll(&h->procs, pid, &status);
        if (r != 0)
            return r > 0 ? status : -1;
        harness_pump(h, 10);
    }
    return -1;
}

int harness_read_output(harness *h, pid_t pid, char *buf, int cap)
{
    return proc_read(&h->procs, pid, buf, cap);
}

void harness_pump(harness *h, int ms)
{
    const double t_end = now_s() + ms * 1e-3;
    while (now_s() < t_end) {
        int left = (int)((t_end - now_s()) * 1e3);
        lcm_handle_timeout(h->lcm, left > 0 ? left : 1);
    }
}

void harness_kill_all(harness *h)
{
    proc_kill_all(&h->procs, 3.0);
}

void harness_close(harness *h)
{
    harness_kill_all(h);
    if (h->lcm)
        lcm_destroy(h->lcm);
    h->lcm = NULL;
    auth_bus_free(&h->bus);
}

static harness_health *health_slot(harness *h, const char *name)
{
    int i;
    for (i = 0; i < h->n_health; i++)
        if (!strcmp(h->health[i].name, name))
            return &h->health[i];
    if (h->n_health == HARNESS_MAX_HEALTH)
        return NULL;
    snprintf(h->health[h->n_health].name, sizeof h->health[0].name, "%s", name);
    return &h->health[h->n_health++];
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    harness_health *d = health_slot(u, m->name);
    (void)rb;
    (void)ch;
    if (!d)
        return;
    d->pid = m->pid;
    d->auth_on = m->auth_on;
    auth_bus_health_refusals(m, d->refused);
    d->msgs_rejected = m->msgs_rejected;
    d->msgs_lost = m->msgs_lost;
}

AUTH_TYPED_HANDLER(tandem_health_t, raw_on_health, on_health)

void harness_watch_health(harness *h)
{
    auth_bus_subscribe(&h->bus, h->lcm, "HEALTH_.*", raw_on_health, h);
}

harness_health harness_health_of(harness *h, const char *name)
{
    harness_health none;
    int i;
    for (i = 0; i < h->n_health; i++)
        if (!strcmp(h->health[i].name, name))
            return h->health[i];
    memset(&none, 0, sizeof none);
    return none;
}

int64_t harness_refused(const harness_health *d)
{
    int64_t n = 0;
    int i;
    for (i = 0; i < AUTH_BUS_KINDS; i++)
        n += d->refused[i];
    return n;
}

void harness_print_refused(const harness_health *d)
{
    printf(
        "  %-18s refused %6lld: unsigned %lld, bad MAC %lld, unknown sender %lld, replayed %lld, "
        "not allowed %lld, other cell %lld, before the MAC %lld (lost on the way in: %lld)\n",
        d->name, (long long)harness_refused(d), (long long)d->refused[0], (long long)d->refused[1],
        (long long)d->refused[2], (long long)d->refused[3], (long long)d->refused[4],
        (long long)d->refused[5], (long long)d->refused[6], (long long)d->msgs_lost);
}

int harness_sh(const char *fmt, ...)
{
    char cmd[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    /* NOLINTNEXTLINE(cert-env33-c): the harness's own commands (its callers' literals) */
    return system(cmd);
}

void harness_ack(harness *h, const char *name, int64_t step, int32_t period_steps)
{
    lockstep_ack(&h->bus, h->lcm, name, 0, step, period_steps, 0);
}

/* unshare(2) is declared only under _GNU_SOURCE, which would also declare
 * glibc's daemon() and clash with the daemon shell's type of that name. */
#ifdef __linux__
extern int unshare(int flags);
#define HARNESS_CLONE_NEWNET 0x40000000
#endif

int harness_private_net(void)
{
#ifndef __linux__
    return -1;
#else
    if (getenv("TANDEM_SHARED_NET") || unshare(HARNESS_CLONE_NEWNET) != 0)
        return -1;
    /* a new namespace has only a loopback, down, and no route for the
     * multicast group LCM's udpm provider joins */
    /* NOLINTNEXTLINE(cert-env33-c): the test sets up its private network namespace by ip(8) */
    if (system("ip link set lo up && ip route add 224.0.0.0/4 dev lo") != 0) {
        fprintf(stderr, "harness: cannot set up loopback multicast in the new namespace\n");
        return -1;
    }
    return 0;
#endif
}

void harness_send_joint_row(harness *h, int arm, int action_id, const double q[6])
{
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    char ch[24];
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
    seg.orientation_quat[0] = 1.0;
    memcpy(seg.q_rad, q, sizeof seg.q_rad);
    row.action_id = action_id;
    row.arm = (int8_t)arm;
    row.n_segments = 1;
    row.segments = &seg;
    snprintf(ch, sizeof ch, "ARM%d_ACTION", arm);
    AUTH_PUBLISH(tandem_action_row_t, &h->bus, h->lcm, ch, &row);
}

int harness_slurp(const char *path, char *buf, int cap)
{
    FILE *f = fopen(path, "r");
    int n;
    if (!f)
        return -1;
    n = (int)fread(buf, 1, (size_t)(cap - 1), f);
    buf[n] = '\0';
    fclose(f);
    return n;
}

double harness_json_value(const char *text, const char *key)
{
    char pat[128];
    const char *p;
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    p = strstr(text, pat);
    if (!p)
        return NAN;
    p += strlen(pat);
    if (strncmp(p, "true", 4) == 0)
        return 1.0;
    if (strncmp(p, "false", 5) == 0)
        return 0.0;
    return strncmp(p, "null", 4) == 0 ? NAN : strtod(p, NULL);
}

/* argv (n bytes, NUL separated) has `opt` followed by `value`. */
static int has_option(const char *argv, size_t n, const char *opt, const char *value)
{
    const char *p = argv, *end = argv + n;
    while (p < end) {
        const char *next = p + strlen(p) + 1;
        if (!strcmp(p, opt) && next < end && !strcmp(next, value))
            return 1;
        p = next;
    }
    return 0;
}

pid_t harness_child_named(pid_t parent, const char *prog, const char *opt, const char *value)
{
    char path[96], list[1024], cmd[512];
    const char *p = list;
    FILE *f;
    snprintf(path, sizeof path, "/proc/%d/task/%d/children", (int)parent, (int)parent);
    if (harness_slurp(path, list, sizeof list) <= 0)
        return -1;
    for (;;) {
        char *end, *base;
        const long pid = strtol(p, &end, 10);
        size_t n;
        if (end == p)
            return -1;
        p = end;
        snprintf(path, sizeof path, "/proc/%ld/cmdline", pid);
        f = fopen(path, "rb");
        if (!f)
            continue;
        n = fread(cmd, 1, sizeof cmd - 1, f);
        fclose(f);
        cmd[n] = '\0'; /* argv[0] ends at its NUL */
        base = strrchr(cmd, '/');
        if (!strcmp(base ? base + 1 : cmd, prog) && (!opt || has_option(cmd, n, opt, value)))
            return (pid_t)pid;
    }
}

int harness_run(const char *const argv[], double timeout_s)
{
    return harness_run_output(argv, timeout_s, NULL, 0);
}

int harness_run_output(const char *const argv[], double timeout_s, char *buf, int cap)
{
    proc_set ps;
    pid_t pid;
    int st = -1, i;
    struct timespec ts = { 0, 50000000L };
    proc_init(&ps, NULL, NULL);
    pid = proc_spawn(&ps, argv, NULL, NULL, NULL);
    if (pid <= 0)
        return -1;
    for (i = 0; i < (int)(timeout_s * 20.0) && proc_poll(&ps, pid, &st) == 0; i++)
        nanosleep(&ts, NULL);
    if (st < 0)
        proc_kill_all(&ps, 2.0);
    if (buf && cap > 0)
        proc_read(&ps, pid, buf, cap);
    return st;
}

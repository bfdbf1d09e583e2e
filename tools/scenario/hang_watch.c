/* hang_watch: children silent on the health channels (see hang_watch.h). */
#include <string.h>
#include <sys/select.h>
#include "hang_watch.h"
#include "auth_bus.h"
#include "peer.h"
#include "scenario.h"
#include "tandem_health_t.h"

void hang_watch_init(hang_watch *w, double hang_s)
{
    memset(w, 0, sizeof *w);
    w->hang_s = hang_s > 0.0 ? hang_s : 0.0;
}

int hang_watch_add(hang_watch *w, const char *name, double now_s)
{
    const size_t len = name ? strlen(name) : 0;
    if (len == 0 || len >= sizeof w->name[0])
        return HANG_WATCH_ERR_NAME;
    if (w->n >= HANG_WATCH_MAX)
        return HANG_WATCH_ERR_FULL;
    memcpy(w->name[w->n], name, len + 1);
    hang_watch_started(w, w->n, now_s);
    return w->n++;
}

void hang_watch_started(hang_watch *w, int k, double now_s)
{
    if (k < 0 || k >= HANG_WATCH_MAX)
        return;
    w->last_s[k] = now_s;
    w->on[k] = 1;
    w->spoken[k] = 0;
}

void hang_watch_pid(hang_watch *w, int k, int pid)
{
    if (k < 0 || k >= HANG_WATCH_MAX)
        return;
    w->pid[k] = pid > 0 ? pid : 0;
    w->cpu_ns[k] = pid > 0 ? peer_cpu_ns(pid) : -1;
    w->cpu_for_s[k] = w->last_s[k];
    w->cpu_read_s[k] = w->last_s[k];
}

void hang_watch_down(hang_watch *w, int k)
{
    if (k >= 0 && k < HANG_WATCH_MAX)
        w->on[k] = 0;
}

void hang_watch_heard(hang_watch *w, const char *name, double now_s)
{
    int k;
    for (k = 0; k < w->n; k++)
        if (!strcmp(w->name[k], name) && now_s > w->last_s[k]) {
            w->last_s[k] = now_s;
            w->spoken[k] = 1;
        }
}

double hang_watch_silent_s(const hang_watch *w, int k, double now_s)
{
    return k >= 0 && k < w->n ? now_s - w->last_s[k] : 0.0;
}

int hang_watch_hung(const hang_watch *w, int k, double now_s)
{
    double limit, silent;
    long long cpu;
    if (w->hang_s <= 0.0 || k < 0 || k >= w->n || !w->on[k])
        return 0;
    limit = w->hang_s + (w->spoken[k] ? 0.0 : HANG_WATCH_START_S);
    silent = hang_watch_silent_s(w, k, now_s);
    if (silent <= limit)
        return 0;
    if (w->pid[k] <= 0 || w->cpu_ns[k] < 0 || peer_proc_of(w->pid[k]) == PEER_PROC_STOPPED)
        return 1; /* not known, or stopped: silence decides */
    cpu = peer_cpu_ns(w->pid[k]);
    /* it ran and said nothing (hangs), or got no CPU for far too long */
    return cpu < 0 || (double)(cpu - w->cpu_ns[k]) * 1e-9 > 0.25 * w->hang_s ||
           silent > HANG_WATCH_STARVED_X * limit;
}

/* Each child that spoke since its CPU time was read: read again (at most
 * once in HANG_WATCH_CPU_EVERY_S), the baseline of hang_watch_hung. */
static void note_cpu(hang_watch *w, double now_s)
{
    int k;
    for (k = 0; k < w->n; k++)
        if (w->pid[k] > 0 && w->last_s[k] > w->cpu_for_s[k] &&
            now_s - w->cpu_read_s[k] >= HANG_WATCH_CPU_EVERY_S) {
            w->cpu_ns[k] = peer_cpu_ns(w->pid[k]);
            w->cpu_for_s[k] = w->last_s[k];
            w->cpu_read_s[k] = now_s;
        }
}

int hang_watch_look(hang_watch *w, lcm_t *lcm, double now_s)
{
    const int fd = lcm_get_fileno(lcm);
    struct timeval tv = { 0, 0 };
    fd_set fds;
    int k;
    if (w->looked_s > 0.0 && now_s - w->looked_s > HANG_WATCH_AWAY_S)
        for (k = 0; k < w->n; k++)
            w->last_s[k] += now_s - w->looked_s;
    w->looked_s = now_s;
    note_cpu(w, now_s);
    FD_ZERO(&fds);
    FD_SET(fd, &fds);
    return select(fd + 1, &fds, NULL, NULL, &tv) == 0;
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    (void)rb;
    (void)ch;
    /* a daemon's goodbye ("stopped") is its last word, not a sign of life:
     * it is about to exit, and its exit is seen as an exit */
    if (strcmp(m->status, "stopped") != 0)
        hang_watch_heard(u, m->name, scenario_wall_s());
}

AUTH_TYPED_HANDLER(tandem_health_t, raw_on_health, on_health)

void hang_watch_subscribe(hang_watch *w, auth_bus *bus, lcm_t *lcm)
{
    w->bus = bus;
    if (w->hang_s > 0.0)
        w->subscribed = auth_bus_subscribe(bus, lcm, "HEALTH_.*", raw_on_health, w) != NULL;
}

void hang_watch_stop(hang_watch *w, lcm_t *lcm)
{
    /* by its user, not by a subscription that a renewed handle replaced */
    if (w->subscribed && w->bus)
        auth_bus_unsubscribe_user(w->bus, lcm, w);
    w->subscribed = 0;
}

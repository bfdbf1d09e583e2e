/* peer: is another process on the bus alive, only slow, or dead
 * (docs/method/lockstep.md §3). Linux /proc gives the state (R, S, D, T,
 * Z ...); without it kill(pid, 0) still tells gone from present. */
#include "peer.h"
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

/* /proc/<pid>/stat after the command name ("pid (comm) S ppid ..."; comm
 * may hold spaces and parentheses, so the fields follow the last ')'):
 * the state letter at out[0]. 0 if it cannot be read. */
static int proc_stat_tail(int32_t pid, char *out, size_t cap)
{
    char path[48], buf[1024];
    const char *rp;
    size_t n;
    FILE *f;
    snprintf(path, sizeof path, "/proc/%ld/stat", (long)pid);
    f = fopen(path, "r");
    if (!f)
        return 0;
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    rp = strrchr(buf, ')');
    if (!rp || rp[1] != ' ')
        return 0;
    snprintf(out, cap, "%s", rp + 2);
    return 1;
}

static char proc_state_letter(int32_t pid)
{
    char tail[1024];
    return proc_stat_tail(pid, tail, sizeof tail) ? tail[0] : 0;
}

int64_t peer_cpu_ns(int32_t pid)
{
    char tail[1024];
    unsigned long long ut, st;
    const long hz = sysconf(_SC_CLK_TCK);
    /* state ppid pgrp session tty tpgid flags minflt cminflt majflt cmajflt utime stime */
    if (pid <= 0 || hz <= 0 || !proc_stat_tail(pid, tail, sizeof tail) ||
        sscanf(tail, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &ut, &st) != 2)
        return -1;
    return (int64_t)((ut + st) * (1000000000ULL / (unsigned long long)hz));
}

peer_proc peer_proc_of(int32_t pid)
{
    char s;
    if (pid <= 0)
        return PEER_PROC_UNKNOWN;
    if (kill((pid_t)pid, 0) != 0 && errno == ESRCH)
        return PEER_PROC_GONE;
    s = proc_state_letter(pid);
    if (s == 'Z' || s == 'X' || s == 'x')
        return PEER_PROC_GONE;
    if (s == 'T' || s == 't')
        return PEER_PROC_STOPPED;
    return PEER_PROC_RUNNING;
}

void peer_heard(peer_watch *w, int32_t pid, int64_t now_ns)
{
    if (pid > 0)
        w->pid = pid;
    w->heard_ns = now_ns;
    w->heard_cpu_ns = peer_cpu_ns(w->pid);
}

int peer_dead(const peer_watch *w, int64_t now_ns, int64_t silent_ns)
{
    int64_t cpu;
    switch (peer_proc_of(w->pid)) {
    case PEER_PROC_GONE: return 1;
    case PEER_PROC_STOPPED: return 0;
    case PEER_PROC_UNKNOWN: return now_ns - w->heard_ns > silent_ns;
    default:
        if (now_ns - w->heard_ns <= silent_ns)
            return 0;
        cpu = peer_cpu_ns(w->pid);
        /* CPU time not known: the wall clock alone decides, as before */
        if (cpu < 0 || w->heard_cpu_ns < 0)
            return 1;
        return cpu - w->heard_cpu_ns > silent_ns / 4;
    }
}

int peer_rover_range(const char *name, long *lo, long *hi)
{
    static const char prefix[] = "tandem-rover-";
    char *end;
    if (strncmp(name, prefix, sizeof prefix - 1) != 0)
        return 0;
    *lo = strtol(name + sizeof prefix - 1, &end, 10);
    *hi = *lo;
    if (*end == '-')
        *hi = strtol(end + 1, &end, 10);
    return *end == '\0' && *lo >= 1 && *hi >= *lo;
}

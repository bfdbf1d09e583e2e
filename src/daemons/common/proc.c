/* proc: child processes of tandem-scenario and the integration tests. */
#include "proc.h"
#include "auth_bus.h"
#include "daemon.h"
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

static double mono_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* own_dir: the path of the running program is not known */
#define OWN_DIR_UNKNOWN (-1)

/* The directory of the running program: its sibling programs live there
 * (build/bin, or an installed bin/), whatever the working directory. */
static int own_dir(char *out, size_t cap)
{
    char *slash;
    const ssize_t n = readlink("/proc/self/exe", out, cap - 1);
    if (n <= 0)
        return OWN_DIR_UNKNOWN;
    out[n] = '\0';
    slash = strrchr(out, '/');
    if (!slash)
        return OWN_DIR_UNKNOWN;
    *slash = '\0';
    return 0;
}

void proc_init(proc_set *p, const auth_bus *bus, const char *bin_dir)
{
    const char *env = getenv("TANDEM_BIN");
    memset(p, 0, sizeof *p);
    auth_child_keys_init(&p->keys, bus);
    if (bin_dir || env)
        snprintf(p->bin, sizeof p->bin, "%s", bin_dir ? bin_dir : env);
    else if (own_dir(p->bin, sizeof p->bin) != 0)
        snprintf(p->bin, sizeof p->bin, "build/bin");
}

void proc_die_with_parent(pid_t parent)
{
#ifdef __linux__
    (void)prctl(PR_SET_PDEATHSIG, SIGTERM);
#endif
    if (getppid() != parent) /* it died before the signal was asked for */
        _exit(127);
}

pid_t proc_spawn(proc_set *p, const char *const argv[], const char *lcm_url, const char *out_path,
                 const char *err_path)
{
    const pid_t self = getpid();
    int fds[2] = { -1, -1 };
    pid_t pid;
    char path[512], key[600];
    int keyed;
    if (p->n >= PROC_MAX || !argv || !argv[0])
        return PROC_ERR_FULL;
    keyed = auth_child_key(&p->keys, argv, key, sizeof key);
    if (keyed < 0)
        return PROC_ERR_KEY;
    if (!out_path && pipe(fds) != 0)
        return PROC_ERR_SYS;
    snprintf(path, sizeof path, "%s/%s", p->bin, argv[0]);
    pid = fork();
    if (pid < 0)
        return PROC_ERR_SYS;
    if (pid == 0) {
        proc_die_with_parent(self);
        if (out_path) {
            int fd = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) {
                dup2(fd, 1);
                close(fd);
            }
        } else {
            dup2(fds[1], 1);
            close(fds[0]);
            close(fds[1]);
        }
        if (err_path) {
            int fd = open(err_path, O_WRONLY | O_CREAT | O_APPEND, 0644);
            if (fd >= 0) {
                dup2(fd, 2);
                close(fd);
            }
        }
        if (lcm_url)
            setenv("LCM_DEFAULT_URL", lcm_url, 1);
        if (keyed == AUTH_CHILD_OK)
            setenv(AUTH_BUS_KEY_ENV, key, 1);
        setenv(DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE, 1);
        execv(path, (char *const *)argv);
        fprintf(stderr, "proc: cannot exec %s: %s\n", path, strerror(errno));
        _exit(127);
    }
    if (!out_path) {
        close(fds[1]);
        fcntl(fds[0], F_SETFL, O_NONBLOCK);
    }
    p->pid[p->n] = pid;
    p->alive[p->n] = 1;
    p->out_fd[p->n] = out_path ? -1 : fds[0];
    p->status[p->n] = -1;
    p->n++;
    return pid;
}

static int index_of(const proc_set *p, pid_t pid)
{
    int i;
    for (i = 0; i < p->n; i++)
        if (p->pid[i] == pid)
            return i;
    return PROC_ERR_UNKNOWN;
}

int proc_poll(proc_set *p, pid_t pid, int *status)
{
    const int i = index_of(p, pid);
    int st;
    if (i < 0)
        return PROC_ERR_UNKNOWN;
    if (!p->alive[i]) {
        if (status)
            *status = p->status[i];
        return 1;
    }
    if (waitpid(pid, &st, WNOHANG) != pid)
        return 0;
    p->status[i] = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    p->alive[i] = 0;
    if (status)
        *status = p->status[i];
    return 1;
}

int proc_read(proc_set *p, pid_t pid, char *buf, int cap)
{
    const int i = index_of(p, pid);
    int n = 0;
    if (cap <= 0)
        return 0;
    if (i >= 0 && p->out_fd[i] >= 0) {
        for (;;) {
            ssize_t r = read(p->out_fd[i], buf + n, (size_t)(cap - 1 - n));
            if (r <= 0)
                break;
            n += (int)r;
        }
    }
    buf[n] = '\0';
    return n;
}

void proc_kill(proc_set *p, pid_t pid)
{
    int i;
    for (i = 0; i < p->n; i++)
        if (p->pid[i] == pid && p->alive[i]) {
            kill(pid, SIGKILL);
            waitpid(pid, &p->status[i], 0);
            p->alive[i] = 0;
        }
}

void proc_kill_all(proc_set *p, double grace_s)
{
    int i;
    double t0;
    for (i = 0; i < p->n; i++)
        if (p->alive[i])
            kill(p->pid[i], SIGTERM);
    t0 = mono_s();
    for (i = 0; i < p->n; i++) {
        while (p->alive[i] && proc_poll(p, p->pid[i], NULL) == 0 && mono_s() - t0 < grace_s) {
            struct timespec ts = { 0, 10000000L };
            nanosleep(&ts, NULL);
        }
        if (p->alive[i]) {
            kill(p->pid[i], SIGKILL);
            waitpid(p->pid[i], NULL, 0);
            p->alive[i] = 0;
        }
        if (p->out_fd[i] >= 0)
            close(p->out_fd[i]);
        p->out_fd[i] = -1;
    }
    p->n = 0;
    auth_child_keys_remove(&p->keys);
}

int proc_mkdir_p(const char *dir)
{
    char path[1024];
    size_t i;
    if ((size_t)snprintf(path, sizeof path, "%s", dir) >= sizeof path) {
        errno = ENAMETOOLONG;
        return PROC_ERR_SYS;
    }
    for (i = 1; path[i]; i++)
        if (path[i] == '/') {
            path[i] = '\0';
            mkdir(path, 0755); /* a step that exists, or fails: the last mkdir says */
            path[i] = '/';
        }
    return mkdir(path, 0755) != 0 && errno != EEXIST ? PROC_ERR_SYS : 0;
}

/* harness: child daemons on a private LCM bus (see harness.h). */
#include "harness.h"
#include "tandem_clock_ack_t.h"
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int harness_open(harness *h, int port_offset)
{
    const char *bin = getenv("TANDEM_BIN");
    memset(h, 0, sizeof *h);
    snprintf(h->bin, sizeof h->bin, "%s", bin ? bin : "build/bin");
    snprintf(h->url, sizeof h->url, "udpm://239.255.76.67:%d?ttl=0",
             20000 + (int)(getpid() % 20000) + port_offset);
    h->lcm = lcm_create(h->url);
    return h->lcm ? 0 : -1;
}

pid_t harness_spawn(harness *h, const char *const argv[])
{
    int fds[2];
    pid_t pid;
    char path[512];
    if (h->n >= HARNESS_MAX_PROCS || pipe(fds) != 0)
        return -1;
    snprintf(path, sizeof path, "%s/%s", h->bin, argv[0]);
    pid = fork();
    if (pid == 0) {
        dup2(fds[1], 1);
        close(fds[0]);
        close(fds[1]);
        setenv("LCM_DEFAULT_URL", h->url, 1);
        execv(path, (char *const *)argv);
        fprintf(stderr, "harness: cannot exec %s: %s\n", path, strerror(errno));
        _exit(127);
    }
    close(fds[1]);
    fcntl(fds[0], F_SETFL, O_NONBLOCK);
    h->pid[h->n] = pid;
    h->out_fd[h->n] = fds[0];
    h->n++;
    return pid;
}

int harness_wait(harness *h, pid_t pid, double timeout_s)
{
    const double t0 = now_s();
    int status;
    while (now_s() - t0 < timeout_s) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) {
            int i;
            for (i = 0; i < h->n; i++)
                if (h->pid[i] == pid)
                    h->pid[i] = 0;
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        harness_pump(h, 10);
    }
    return -1;
}

int harness_read_output(harness *h, pid_t pid, char *buf, int cap)
{
    int i, n = 0;
    for (i = 0; i < h->n; i++) {
        if (h->pid[i] != pid && h->pid[i] != 0)
            continue;
        if (h->pid[i] == 0 && h->out_fd[i] < 0)
            continue;
        for (;;) {
            ssize_t r = read(h->out_fd[i], buf + n, (size_t)(cap - 1 - n));
            if (r <= 0)
                break;
            n += (int)r;
        }
        if (h->pid[i] == pid)
            break;
    }
    buf[n] = '\0';
    return n;
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
    int i;
    for (i = 0; i < h->n; i++)
        if (h->pid[i] > 0)
            kill(h->pid[i], SIGTERM);
    for (i = 0; i < h->n; i++)
        if (h->pid[i] > 0) {
            if (harness_wait(h, h->pid[i], 3.0) < 0) {
                kill(h->pid[i], SIGKILL);
                waitpid(h->pid[i], NULL, 0);
            }
            h->pid[i] = 0;
        }
    for (i = 0; i < h->n; i++)
        close(h->out_fd[i]);
    h->n = 0;
}

void harness_close(harness *h)
{
    harness_kill_all(h);
    if (h->lcm)
        lcm_destroy(h->lcm);
    h->lcm = NULL;
}

void harness_ack(harness *h, const char *name, int64_t step, int32_t period_steps)
{
    tandem_clock_ack_t a;
    memset(&a, 0, sizeof a);
    a.step = step;
    a.name = (char *)name;
    a.period_steps = period_steps;
    tandem_clock_ack_t_publish(h->lcm, "SIM_ACK", &a);
}

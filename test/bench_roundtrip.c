/* bench_roundtrip: state -> controller -> command over the real LCM bus,
 * beside a bare LCM ping-pong of the same message sizes, in the same run.
 *
 *   tandem path: this process publishes ARM1_STATE + SIM_CLOCK (what the
 *     simulator sends each step) to a real `tandem-arm --lockstep`, which
 *     decodes, validates, runs computed torque (RNE) and publishes
 *     ARM1_COMMAND; we time until that command arrives.
 *   bare path: a forked echo process receives the same two payload sizes
 *     (state, clock) and answers the second with one of the command's size.
 * The two kinds of exchange alternate, so both see the same load.
 * Prints p50 / p99 / max in microseconds over N exchanges.
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "loopstats.h"
#include "rtloop.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_clock_t.h"

static volatile int got;

static void on_any(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb; (void)ch; (void)u;
    got = 1;
}

static void on_echo(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    static char reply[256];
    (void)ch;
    int size;
    memcpy(&size, rb->data, sizeof size);
    if (size <= 0 || size > (int)sizeof reply)
        return;
    lcm_publish((lcm_t *)u, "BENCH_PONG", reply, (unsigned)size);
}

static int wait_reply(lcm_t *l)
{
    int guard;
    for (guard = 0; guard < 1000 && !got; guard++)
        if (lcm_handle_timeout(l, 100) < 0)
            return -1;
    return got ? 0 : -1;
}

/* Bare path: the same two messages the simulator sends (a state-sized and
 * a clock-sized payload); the echo answers the second with a command-sized
 * payload. The first int of each payload is the reply size (0: none). */
static int bare_exchange(lcm_t *l, int state_size, int clock_size, int cmd_size, loopstats *s)
{
    char buf[512];
    const int none = 0;
    int64_t t0;
    memset(buf, 0, sizeof buf);
    got = 0;
    t0 = rtloop_now_ns();
    memcpy(buf, &none, sizeof none);
    lcm_publish(l, "BENCH_PING", buf, (unsigned)state_size);
    memcpy(buf, &cmd_size, sizeof cmd_size);
    lcm_publish(l, "BENCH_PING", buf, (unsigned)clock_size);
    if (wait_reply(l) != 0)
        return -1;
    if (s)
        loopstats_add(s, (double)(rtloop_now_ns() - t0) * 1e-3);
    return 0;
}

/* tandem path: ARM1_STATE + SIM_CLOCK to tandem-arm, wait for ARM1_COMMAND. */
static int tandem_exchange(lcm_t *l, tandem_arm_state_t *st, tandem_sim_clock_t *clk, int i, loopstats *s)
{
    int64_t t0;
    st->step = i;
    st->sim_time_s = i * 1e-3;
    clk->step = i;
    clk->sim_time_s = st->sim_time_s;
    got = 0;
    t0 = rtloop_now_ns();
    AUTH_PUBLISH(tandem_arm_state_t, l, "ARM1_STATE", st);
    AUTH_PUBLISH(tandem_sim_clock_t, l, "SIM_CLOCK", clk);
    if (wait_reply(l) != 0)
        return -1;
    if (s)
        loopstats_add(s, (double)(rtloop_now_ns() - t0) * 1e-3);
    return 0;
}

static void print_row(const char *name, const loopstats *s)
{
    printf("  %-34s p50 %7.1f us   p99 %7.1f us   max %8.1f us   (n=%lld)\n", name,
           loopstats_percentile(s, 0.50), loopstats_percentile(s, 0.99), s->max_us, (long long)s->count);
}


int main(int argc, char **argv)
{
    const int n = argc > 1 ? atoi(argv[1]) : 10000;
    const char *bin = argc > 2 ? argv[2] : "build/bin";
    char url[96], path[512];
    lcm_t *l;
    pid_t echo_pid, arm_pid;
    tandem_arm_state_t st;
    tandem_sim_clock_t clk;
    loopstats bare, tandem;
    int i, state_size, cmd_size, clock_size;
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", 40000 + (int)(getpid() % 10000));
    setenv("LCM_DEFAULT_URL", url, 1);
    memset(&st, 0, sizeof st);
    st.arm = 1;
    st.q_rad[1] = 0.6; st.q_rad[2] = 2.9; st.q_rad[4] = -0.4;
    state_size = tandem_arm_state_t_encoded_size(&st);
    {
        tandem_arm_command_t c;
        memset(&c, 0, sizeof c);
        cmd_size = tandem_arm_command_t_encoded_size(&c);
    }

    echo_pid = fork();
    if (echo_pid == 0) {
        lcm_t *e = lcm_create(url);
        lcm_subscribe(e, "BENCH_PING", on_echo, e);
        for (;;)
            lcm_handle(e);
    }
    snprintf(path, sizeof path, "%s/tandem-arm", bin);
    arm_pid = fork();
    if (arm_pid == 0) {
        execl(path, "tandem-arm", "--arm", "1", "--lockstep", (char *)NULL);
        perror("exec tandem-arm");
        _exit(127);
    }
    l = lcm_create(url);
    lcm_subscribe(l, "BENCH_PONG", on_any, NULL);
    lcm_subscribe(l, "ARM1_COMMAND", on_any, NULL);
    { struct timespec ts = { 0, 300000000L }; nanosleep(&ts, NULL); }
    loopstats_reset(&bare);
    loopstats_reset(&tandem);
    printf("round trip over LCM (%s), %d exchanges, state %d B, command %d B\n", url, n, state_size, cmd_size);

    memset(&clk, 0, sizeof clk);
    clk.mode = TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP;
    clock_size = tandem_sim_clock_t_encoded_size(&clk);
    /* Exchanges alternate bare / tandem so both see the same machine load. */
    for (i = 0; i < n + 100; i++) {
        if (bare_exchange(l, state_size, clock_size, cmd_size, i >= 100 ? &bare : NULL) != 0) {
            fprintf(stderr, "bench: no echo\n");
            break;
        }
        if (tandem_exchange(l, &st, &clk, i, i >= 100 ? &tandem : NULL) != 0) {
            fprintf(stderr, "bench: no command from tandem-arm\n");
            break;
        }
    }
    print_row("bare LCM ping-pong", &bare);
    print_row("tandem state->tandem-arm->command", &tandem);
    if (bare.count > 0 && tandem.count > 0)
        printf("  tandem / bare: p50 %.2fx   p99 %.2fx   (target: <= 1.20x)\n",
               loopstats_percentile(&tandem, 0.5) / loopstats_percentile(&bare, 0.5),
               loopstats_percentile(&tandem, 0.99) / loopstats_percentile(&bare, 0.99));
    kill(echo_pid, SIGKILL);
    kill(arm_pid, SIGTERM);
    waitpid(echo_pid, NULL, 0);
    waitpid(arm_pid, NULL, 0);
    lcm_destroy(l);
    return 0;
}

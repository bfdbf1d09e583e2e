/* Integration: logs of the secure bus (docs/method/lockstep.md §4-5). A short real-time run
 * (the simulator with both arms and two rovers, both arm controllers, the
 * supervisor, one rover host) is recorded with lcm-logger, together with
 * one message of each kind the run does not send (SIM_ACK, ARM1_JOINT_REF,
 * the batched ROVERS_*) and, last, a signed SIM_CONTROL QUIT. Then
 *  - every event decodes with lcm-spy's own decoder
 *    (tools/logcheck/SpyDecodeCheck.java) and with the Python types the
 *    viewer decodes with (tools/logcheck/decode_check.py), trailer and all,
 *    and tandem-log2csv lists the log;
 *  - lcm-logplayer plays the log onto a fresh simulator and arm using the
 *    same key: they refuse every message as a replay (viewing yes,
 *    commanding no), and the QUIT in the log does not stop the simulator.
 * Without java/javac or python3 the decoding checks are skipped (said so).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include "harness.h"
#include "tandem_arm_joint_ref_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_rovers_beacons_t.h"
#include "tandem_rovers_command_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_sim_control_t.h"

/* the host of rovers 1-2 is a principal of this cell, recording and
 * playing back: the roster of the test's bus (auth_bus_roster) */
#define ROSTER_ROVERS 2

static char dir[128], log_path[160], root[512], bin[512];
static struct timespec recorded_at; /* when the last message of the log was signed */

/* The source tree: the programs are in ROOT/build/bin (or build/san/bin). */
static int find_root(void)
{
    proc_set p;
    char *b;
    proc_init(&p, NULL, NULL);
    snprintf(bin, sizeof bin, "%s", p.bin);
    snprintf(root, sizeof root, "%s", p.bin);
    b = strstr(root, "/build/");
    if (b)
        *b = '\0';
    else if (!strncmp(root, "build/", 6)) /* build/bin, build/san/bin, build/cov/bin */
        snprintf(root, sizeof root, ".");
    return harness_sh("test -d '%s/lcmtypes' && test -d '%s/tools/logcheck'", root, root) == 0 ? 0
                                                                                               : -1;
}

static pid_t start_logger(const char *url)
{
    const pid_t pid = fork();
    if (pid == 0) {
        char url_opt[160];
        snprintf(url_opt, sizeof url_opt, "--lcm-url=%s", url);
        execlp("lcm-logger", "lcm-logger", "-f", url_opt, log_path, (char *)NULL);
        _exit(127);
    }
    return pid;
}

/* One of each message the real-time run does not send, signed as their
 * owners would; then QUIT. */
static void publish_the_rest(harness *h)
{
    tandem_clock_ack_t a;
    tandem_arm_joint_ref_t r;
    tandem_rovers_sensors_t rs;
    tandem_rovers_beacons_t rb;
    tandem_rovers_command_t rc;
    tandem_rovers_state_t rt;
    tandem_sim_control_t c;
    memset(&a, 0, sizeof a);
    a.name = "it_signed_log";
    a.period_steps = 1;
    a.leaving = 1;
    AUTH_PUBLISH(tandem_clock_ack_t, &h->bus, h->lcm, "SIM_ACK", &a);
    memset(&r, 0, sizeof r);
    r.arm = 2;
    r.step = -1; /* refused by the arm: only the log matters here */
    AUTH_PUBLISH(tandem_arm_joint_ref_t, &h->bus, h->lcm, "ARM2_JOINT_REF", &r);
    memset(&rs, 0, sizeof rs);
    memset(&rb, 0, sizeof rb);
    memset(&rc, 0, sizeof rc);
    memset(&rt, 0, sizeof rt);
    AUTH_PUBLISH(tandem_rovers_sensors_t, &h->bus, h->lcm, "ROVERS_SENSORS", &rs);
    AUTH_PUBLISH(tandem_rovers_beacons_t, &h->bus, h->lcm, "ROVERS_BEACONS", &rb);
    AUTH_PUBLISH(tandem_rovers_command_t, &h->bus, h->lcm, "ROVERS_COMMAND", &rc);
    AUTH_PUBLISH(tandem_rovers_state_t, &h->bus, h->lcm, "ROVERS_STATE", &rt);
    harness_pump(h, 200);
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_QUIT;
    AUTH_PUBLISH(tandem_sim_control_t, &h->bus, h->lcm, "SIM_CONTROL", &c);
    clock_gettime(CLOCK_MONOTONIC, &recorded_at);
}

/* A receiver takes messages signed up to AUTH_START_SLACK_US before it
 * started (the clock difference allowed between hosts): the log is played
 * to receivers started later than that, as a replay attack would be. On a
 * fast machine the decoding checks alone can take less. */
static void wait_past_start_slack(void)
{
    struct timespec now;
    double age_s;
    clock_gettime(CLOCK_MONOTONIC, &now);
    age_s = (double)(now.tv_sec - recorded_at.tv_sec) +
            1e-9 * (double)(now.tv_nsec - recorded_at.tv_nsec);
    if (age_s < 1e-6 * (double)AUTH_START_SLACK_US + 0.5) {
        const double wait_s = 1e-6 * (double)AUTH_START_SLACK_US + 0.5 - age_s;
        struct timespec ts;
        ts.tv_sec = (time_t)wait_s;
        ts.tv_nsec = (long)((wait_s - (double)ts.tv_sec) * 1e9);
        nanosleep(&ts, NULL);
    }
}

static int record(void **state)
{
    harness h;
    const char *sim[] = { "tandem-sim", "--rovers", "2", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", NULL };
    const char *sup[] = { "tandem-supervisor", NULL };
    const char *rovers[] = { "tandem-rover", "--id", "1-2", "--robots", "2", NULL };
    pid_t logger, ps;
    int rc;
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/it_signed_log_%d", (int)getpid());
    snprintf(log_path, sizeof log_path, "%s/run.lcmlog", dir);
    if (find_root() != 0 || harness_sh("mkdir -p '%s'", dir) != 0)
        return -1;
    if (harness_open(&h, 15) != 0)
        return -1;
    auth_bus_roster(&h.bus, ROSTER_ROVERS);
    logger = start_logger(h.url);
    harness_track_child(logger);
    harness_pump(&h, 300);
    ps = harness_spawn(&h, sim);
    harness_pump(&h, 300);
    harness_spawn(&h, arm1);
    harness_spawn(&h, arm2);
    harness_spawn(&h, sup);
    harness_spawn(&h, rovers);
    harness_pump(&h, 3000);
    publish_the_rest(&h);
    rc = harness_wait(&h, ps, 10.0); /* 0: the QUIT was obeyed (it was signed) */
    harness_pump(&h, 300);
    harness_close(&h);
    kill(logger, SIGINT);
    waitpid(logger, NULL, 0);
    return rc == 0 ? 0 : -1;
}

static void test_every_event_decodes(void **state)
{
    const char *cp_extra = access("/usr/share/java/jchart2d.jar", R_OK) == 0
                               ? ":/usr/share/java/jchart2d.jar"
                               : "";
    (void)state;
    assert_int_equal(harness_sh("'%s/tandem-log2csv' --list '%s'", bin, log_path), 0);
    if (harness_sh("command -v java >/dev/null && command -v javac >/dev/null") == 0) {
        assert_int_equal(
            harness_sh(
                "javac -nowarn -d '%s/java' -cp /usr/share/java/lcm.jar '%s/tools/logcheck/SpyDecodeCheck.java' "
                "2>&1 | grep -v '^Note:'; java -cp '/usr/share/java/lcm.jar:%s/build/lib/tandem_types.jar:%s/java%s' "
                "SpyDecodeCheck '%s' 2>/dev/null",
                dir, root, root, dir, cp_extra, log_path),
            0);
    } else {
        printf("it_signed_log: no java/javac here: lcm-spy's decoding not checked\n");
    }
    if (harness_sh("command -v python3 >/dev/null") == 0) {
        assert_int_equal(
            harness_sh("mkdir -p '%s/py' && lcm-gen -p --ppath '%s/py' '%s'/lcmtypes/*.lcm && "
                       "python3 '%s/tools/logcheck/decode_check.py' '%s/py' '%s'",
                       dir, dir, root, root, dir, log_path),
            0);
    } else {
        printf("it_signed_log: no python3 here: the viewer's decoding not checked\n");
    }
}

static void test_played_back_log_commands_nothing(void **state)
{
    harness h;
    const char *sim[] = { "tandem-sim", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", NULL };
    harness_health s0, a0, s1, a1;
    pid_t ps;
    int st;
    (void)state;
    wait_past_start_slack();
    assert_int_equal(harness_open(&h, 16), 0);
    auth_bus_roster(&h.bus, ROSTER_ROVERS);
    harness_watch_health(&h);
    ps = harness_spawn(&h, sim);
    assert_true(ps > 0);
    assert_true(harness_spawn(&h, arm1) > 0);
    harness_pump(&h, 2200);
    s0 = harness_health_of(&h, "tandem-sim");
    a0 = harness_health_of(&h, "tandem-arm-1");
    assert_true(s0.pid > 0 && a0.pid > 0);
    assert_int_equal(harness_refused(&s0), 0);
    assert_int_equal(harness_sh("lcm-logplayer --lcm-url='%s' '%s'", h.url, log_path), 0);
    harness_pump(&h, 2500);
    s1 = harness_health_of(&h, "tandem-sim");
    a1 = harness_health_of(&h, "tandem-arm-1");
    harness_print_refused(&s1);
    harness_print_refused(&a1);
    assert_int_equal(proc_poll(&h.procs, ps, &st), 0); /* the logged QUIT did not stop it */
    assert_true(s1.refused[3] - s0.refused[3] > 100);  /* commands, acks, the QUIT: replays */
    assert_true(a1.refused[3] - a0.refused[3] > 100);  /* states, clocks, rows, events */
    assert_int_equal(harness_refused(&s1) - harness_refused(&s0), s1.refused[3] - s0.refused[3]);
    assert_int_equal(harness_refused(&a1) - harness_refused(&a0), a1.refused[3] - a0.refused[3]);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_event_decodes),
        cmocka_unit_test(test_played_back_log_commands_nothing),
    };
    if (harness_private_net() != 0)
        printf(
            "it_signed_log: no private network namespace; using a private port on the shared one\n");
    if (record(NULL) != 0) {
        fprintf(stderr, "it_signed_log: could not record the run (lcm-logger, tandem programs)\n");
        return 1;
    }
    return cmocka_run_group_tests(tests, NULL, NULL);
}

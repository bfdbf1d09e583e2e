/* Integration: lost messages and dead daemons leave the run what it was.
 *
 * 1. Loss: the formation scenario with every daemon dropping 10 % of what
 *    it receives (--drop-rate) writes a truth.csv identical byte for byte
 *    to the lossless run, with the drops counted (the lockstep announces a
 *    step again until every input is in; copies are ignored).
 * 2. Restarts: a carry run whose arm 1 is killed (SIGKILL) in the middle
 *    of its first row and restarted, and whose supervisor is killed and
 *    restarted later, still delivers its workpiece, none dropped: the
 *    restarted arm is sent its row again, the restarted supervisor comes
 *    back from its journal.
 * 3. Left down: a rover killed without restart is taken as gone by its
 *    mates (they stop waiting for its team messages) and the team still
 *    reaches the goal. A rover's process killed and restarted resumes from
 *    its journal; the run is the same every time, and reaches the goal
 *    with loss too.
 * 4. Hung: a carry run whose supervisor is stopped (SIGSTOP: alive, but
 *    silent) is found hung by the scenario once its health has stopped
 *    for --hang-s, killed and restarted from its journal; the run still
 *    delivers, none dropped (hung_restarts 1). A stopped rover process
 *    in a formation run is restarted from its journal the same way, and
 *    the team reaches the goal.
 * 5. Loss is visible: states sent to tandem-arm with a gap of 10 in their
 *    sequence numbers show up in its HEALTH as 10 lost on ARM1_STATE.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>
#include "harness.h"
#include "auth_bus.h"
#include "tandem_arm_state_t.h"
#include "tandem_health_t.h"

static char dir[256];

static int formation_fault(const char *out, const char *drop, const char *kill, const char *fault)
{
    const char *argv[20] = { "tandem-scenario", "formation", "--formation", "line",
                             "--world",         "obstacles", "--robots",    "3",
                             "--seed",          "2",         "--out",       out };
    int n = 12;
    if (drop) {
        argv[n++] = "--drop-rate";
        argv[n++] = drop;
    }
    if (kill) {
        argv[n++] = "--kill";
        argv[n++] = kill;
    }
    if (fault) {
        argv[n++] = "--fault";
        argv[n++] = fault;
    }
    argv[n] = NULL;
    return harness_run(argv, 120.0);
}

static int formation(const char *out, const char *drop, const char *kill)
{
    return formation_fault(out, drop, kill, NULL);
}

static void test_loss_leaves_the_run_unchanged(void **state)
{
    static char a[1 << 20], b[1 << 20];
    char out0[300], out1[300], path[400];
    int na, nb;
    (void)state;
    snprintf(out0, sizeof out0, "%s/lossless", dir);
    snprintf(out1, sizeof out1, "%s/loss10", dir);
    assert_int_equal(formation(out0, NULL, NULL), 0);
    assert_int_equal(formation(out1, "0.10", NULL), 0);
    snprintf(path, sizeof path, "%s/truth.csv", out0);
    na = harness_slurp(path, a, sizeof a);
    snprintf(path, sizeof path, "%s/truth.csv", out1);
    nb = harness_slurp(path, b, sizeof b);
    printf("truth.csv: %d bytes lossless, %d bytes at 10 %% loss\n", na, nb);
    assert_true(na > 10000);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, (size_t)na);
}

static void test_killed_arm_and_supervisor_recover(void **state)
{
    char out[300], path[400], text[16384];
    const char *argv[] = {
        "tandem-scenario",   "carry",   "--workpieces",         "1",     "--no-serial", "--fault",
        "kill:arm1:2.5:3.5", "--fault", "kill:supervisor:9:10", "--out", out,           NULL
    };
    (void)state;
    snprintf(out, sizeof out, "%s/restart", dir);
    assert_int_equal(harness_run(argv, 240.0), 0);
    snprintf(path, sizeof path, "%s/summary.json", out);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    printf("kills %.0f restarts %.0f rows re-sent %.0f completions recovered %.0f\n",
           harness_json_value(text, "kills"), harness_json_value(text, "restarts"),
           harness_json_value(text, "rows_reissued"), harness_json_value(text, "dones_recovered"));
    assert_true(harness_json_value(text, "workpieces_delivered") == 1.0);
    assert_true(harness_json_value(text, "workpieces_dropped") == 0.0);
    assert_true(harness_json_value(text, "kills") == 2.0);
    assert_true(harness_json_value(text, "restarts") == 2.0);
    /* arm 1 died inside its first row: it had to be sent again */
    assert_true(harness_json_value(text, "rows_reissued") >= 1.0);
    assert_true(harness_json_value(text, "invariant_violations") == 0.0);
}

static void test_killed_rover_left_down(void **state)
{
    char out[300], path[400], text[8192];
    (void)state;
    snprintf(out, sizeof out, "%s/kill", dir);
    assert_int_equal(formation(out, "0.05", "2:8"), 0);
    snprintf(path, sizeof path, "%s/summary.json", out);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_true(harness_json_value(text, "killed_robot") == 2.0);
    assert_non_null(strstr(text, "\"reached_goal\": true"));
}

/* A rover's process killed and restarted: it resumes from its journal
 * (pose, filter, protocol), the team reaches the goal, and the run is
 * deterministic: the same truth.csv again. With 5 % loss the team still
 * gets there (not step-identical: which of a returning mate's first team
 * messages its mates hear first depends on the loss, and they do not
 * wait for a mate they took as gone). */
static void test_killed_rover_process_resumes(void **state)
{
    static char a[1 << 20], b[1 << 20], log[1 << 16];
    char out0[300], out1[300], path[400], text[8192];
    int na, nb;
    (void)state;
    snprintf(out0, sizeof out0, "%s/restart", dir);
    snprintf(out1, sizeof out1, "%s/restart_again", dir);
    assert_int_equal(formation_fault(out0, NULL, NULL, "kill:rover2:20:26"), 0);
    assert_int_equal(formation_fault(out1, NULL, NULL, "kill:rover2:20:26"), 0);
    snprintf(path, sizeof path, "%s/summary.json", out0);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_true(harness_json_value(text, "kills") == 1.0);
    assert_true(harness_json_value(text, "restarts") == 1.0);
    assert_true(harness_json_value(text, "loc_err_max_m") < 0.1); /* it knew where it was */
    assert_non_null(strstr(text, "\"reached_goal\": true"));
    snprintf(path, sizeof path, "%s/children.log", out0);
    assert_true(harness_slurp(path, log, sizeof log) > 0);
    assert_non_null(strstr(log, "robot 2 resumed from"));
    snprintf(path, sizeof path, "%s/truth.csv", out0);
    na = harness_slurp(path, a, sizeof a);
    snprintf(path, sizeof path, "%s/truth.csv", out1);
    nb = harness_slurp(path, b, sizeof b);
    assert_true(na > 10000);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, (size_t)na);
    snprintf(out1, sizeof out1, "%s/restart_loss", dir);
    assert_int_equal(formation_fault(out1, "0.05", NULL, "kill:rover2:20:26"), 0);
}

/* Waits (at most n ticks) for the scenario to end, killing what is left
 * if it does not; reads its summary.json into text. Returns its status. */
static int scenario_end(proc_set *ps, pid_t scen, int n, const struct timespec *tick,
                        const char *out, char *text, int cap)
{
    char path[400];
    int st = -1, i;
    for (i = 0; i < n && proc_poll(ps, scen, &st) == 0; i++)
        nanosleep(tick, NULL);
    if (st < 0)
        proc_kill_all(ps, 2.0);
    snprintf(path, sizeof path, "%s/summary.json", out);
    assert_true(harness_slurp(path, text, cap) > 0);
    return st;
}

static void test_hung_supervisor_restarted(void **state)
{
    char out[300], text[16384];
    const char *argv[] = { "tandem-scenario", "carry", "--workpieces", "1", "--no-serial",
                           "--hang-s",        "3",     "--out",        out, NULL };
    const struct timespec tick = { 0, 100000000L };
    proc_set ps;
    pid_t scen, sup = -1;
    int i;
    (void)state;
    snprintf(out, sizeof out, "%s/hung", dir);
    proc_init(&ps, NULL, NULL);
    scen = proc_spawn(&ps, argv, NULL, NULL, NULL);
    assert_true(scen > 0);
    /* into the run (a few seconds of wall time), then stop the supervisor */
    for (i = 0; i < 40; i++)
        nanosleep(&tick, NULL);
    for (i = 0; i < 100 && (sup = harness_child_named(scen, "tandem-supervisor", NULL, NULL)) <= 0;
         i++)
        nanosleep(&tick, NULL);
    assert_true(sup > 0);
    assert_int_equal(kill(sup, SIGSTOP), 0);
    assert_int_equal(scenario_end(&ps, scen, 2400, &tick, out, text, sizeof text), 0);
    printf("hung restarts %.0f kills %.0f restarts %.0f delivered %.0f\n",
           harness_json_value(text, "hung_restarts"), harness_json_value(text, "kills"),
           harness_json_value(text, "restarts"), harness_json_value(text, "workpieces_delivered"));
    assert_true(harness_json_value(text, "hung_restarts") == 1.0);
    assert_true(harness_json_value(text, "workpieces_delivered") == 1.0);
    assert_true(harness_json_value(text, "workpieces_dropped") == 0.0);
    /* the stopped process is gone (killed), not left behind */
    assert_true(kill(sup, 0) != 0);
}

static void test_hung_rover_restarted(void **state)
{
    char out[300], path[400], text[16384];
    const char *argv[] = { "tandem-scenario", "formation", "--formation", "line",   "--world",
                           "obstacles",       "--robots",  "3",           "--seed", "2",
                           "--hang-s",        "2",         "--out",       out,      NULL };
    const struct timespec tick = { 0, 10000000L };
    proc_set ps;
    pid_t scen, rover = -1;
    int i;
    (void)state;
    snprintf(out, sizeof out, "%s/hung_rover", dir);
    proc_init(&ps, NULL, NULL);
    scen = proc_spawn(&ps, argv, NULL, NULL, NULL);
    assert_true(scen > 0);
    /* the whole run takes about a second: stop robot 2's process once
     * its journal holds a few cycles (and before the goal) */
    snprintf(path, sizeof path, "%s/rover_2.journal", out);
    for (i = 0; i < 1000 && harness_slurp(path, text, sizeof text) < 4000; i++)
        nanosleep(&tick, NULL);
    rover = harness_child_named(scen, "tandem-rover", "--id", "2");
    assert_true(rover > 0);
    assert_int_equal(kill(rover, SIGSTOP), 0);
    assert_int_equal(scenario_end(&ps, scen, 24000, &tick, out, text, sizeof text), 0);
    printf("hung restarts %.0f kills %.0f restarts %.0f, at the goal %.1f s\n",
           harness_json_value(text, "hung_restarts"), harness_json_value(text, "kills"),
           harness_json_value(text, "restarts"), harness_json_value(text, "time_to_goal_s"));
    assert_true(harness_json_value(text, "hung_restarts") == 1.0);
    assert_true(kill(rover, 0) != 0);
}

typedef struct loss_seen {
    int64_t lost;
    double rate;
    int heard;
} loss_seen;

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    loss_seen *w = u;
    int i;
    (void)rb;
    (void)ch;
    for (i = 0; i < m->n_channels; i++)
        if (!strcmp(m->channel[i], "ARM1_STATE")) {
            w->lost = m->channel_lost[i];
            w->rate = m->loss_rate;
            w->heard = 1;
        }
}

static void test_loss_visible_in_health(void **state)
{
    harness h;
    loss_seen w;
    const char *arm[] = { "tandem-arm", "--arm", "1", NULL };
    tandem_health_t_subscription_t *sub;
    tandem_arm_state_t s;
    int64_t seq;
    int i;
    (void)state;
    memset(&w, 0, sizeof w);
    memset(&s, 0, sizeof s);
    assert_int_equal(harness_open(&h, 57), 0);
    sub = tandem_health_t_subscribe(h.lcm, "HEALTH_TANDEM_ARM_1", on_health, &w);
    assert_true(harness_spawn(&h, arm) > 0);
    harness_pump(&h, 300);
    s.arm = 1;
    s.holding_workpiece = -1;
    for (seq = 0, i = 0; i < 40; i++, seq++) {
        if (i == 20)
            seq += 10; /* ten states lost on the way */
        s.seq = seq;
        s.step = i;
        s.sim_time_s = i * 1e-3;
        AUTH_PUBLISH(tandem_arm_state_t, &h.bus, h.lcm, "ARM1_STATE", &s);
        harness_pump(&h, 2);
    }
    for (i = 0; i < 30 && !(w.heard && w.lost > 0); i++)
        harness_pump(&h, 100);
    printf("ARM1_STATE lost %lld, loss rate %.3f\n", (long long)w.lost, w.rate);
    assert_int_equal(w.lost, 10);
    assert_true(w.rate > 0.1 && w.rate < 0.3); /* 10 of 50 */
    tandem_health_t_unsubscribe(h.lcm, sub);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loss_leaves_the_run_unchanged),
        cmocka_unit_test(test_killed_arm_and_supervisor_recover),
        cmocka_unit_test(test_killed_rover_left_down),
        cmocka_unit_test(test_killed_rover_process_resumes),
        cmocka_unit_test(test_hung_supervisor_restarted),
        cmocka_unit_test(test_hung_rover_restarted),
        cmocka_unit_test(test_loss_visible_in_health),
    };
    snprintf(dir, sizeof dir, "/tmp/it_recovery_%d", (int)getpid());
    return cmocka_run_group_tests(tests, NULL, NULL);
}

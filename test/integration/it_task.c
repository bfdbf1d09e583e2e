/* Integration: a task other than the shipped carry, drawn as PNML, run by
 * the real daemons over LCM (docs/tasks.md §7). tandem-scenario carry
 * --task tasks/carry_buffer: the supervisor loads the buffer net and its
 * rows at start-up (token bound 2 from pb + pf = 2, its roles found from
 * the net's structure), the simulator gets the hand-over stand; both
 * workpieces are delivered through the buffer, none dropped, no
 * invariant violation, deadlock or stall, every criterion met. Then a
 * broken task: tandem-supervisor --task refuses it with exit 2, naming
 * the file and why, and tandem-scenario refuses it before any daemon
 * starts. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "harness.h"

static char dir[256];

/* Runs argv to its end (at most timeout_s), its output into text and
 * shown; the exit status, or -1 if it had to be killed. */
static int run(const char *const argv[], double timeout_s, char *text, int cap)
{
    int st;
    text[0] = '\0';
    st = harness_run_output(argv, timeout_s, text, cap);
    printf("%s", text);
    return st;
}

static void test_buffer_task_delivers_every_workpiece(void **state)
{
    char path[512], text[8192], log[65536];
    const char *argv[] = { "tandem-scenario", "carry", "--task", "tasks/carry_buffer", "--workpieces", "2",
                           "--no-serial", "--out", dir, NULL };
    (void)state;
    assert_int_equal(run(argv, 300.0, text, sizeof text), 0);
    snprintf(path, sizeof path, "%s/summary.json", dir);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_non_null(strstr(text, "\"task\": \"tasks/carry_buffer\""));
    assert_true(harness_json_value(text, "workpieces_delivered") == 2.0);
    assert_true(harness_json_value(text, "workpieces_dropped") == 0.0);
    assert_true(harness_json_value(text, "invariant_violations") == 0.0);
    assert_true(harness_json_value(text, "deadlocks") == 0.0);
    assert_true(harness_json_value(text, "stalls") == 0.0);
    assert_true(harness_json_value(text, "joint_limit_violations") == 0.0);
    assert_non_null(strstr(text, "\"exit_reason\": \"completed\""));
    /* the supervisor ran the buffer's net: its bound, and the buffer's
     * transitions fired (t3 into the buffer, t4 out of it) */
    snprintf(path, sizeof path, "%s/run_supervisor.log", dir);
    assert_true(harness_slurp(path, log, sizeof log) > 0);
    assert_non_null(strstr(log, "task carry_buffer (tasks/carry_buffer): 9 places, 7 transitions, token bound 2"));
    assert_non_null(strstr(log, "complete t3 arm 1 puts it in the buffer"));
    assert_non_null(strstr(log, "complete t4 arm 2 takes it from the buffer"));
}

/* The carry with the arc t7 -> p2 lost: arm 2 never comes home. */
static void test_broken_task_refused_before_anything_moves(void **state)
{
    char task[300], path[400], text[8192], out[300];
    const char *sup[] = { "tandem-supervisor", "--task", task, "--insecure", NULL };
    const char *scen[] = { "tandem-scenario", "carry", "--task", task, "--workpieces", "1", "--no-serial",
                           "--out", out, NULL };
    FILE *f;
    (void)state;
    snprintf(task, sizeof task, "%s_broken_task", dir);
    snprintf(out, sizeof out, "%s_broken_run", dir);
    mkdir(task, 0755);
    snprintf(path, sizeof path, "%s/rows.csv", task);
    assert_int_equal(harness_sh("cp tasks/carry/rows.csv %s", path), 0);
    snprintf(path, sizeof path, "%s/net.pnml", task);
    assert_int_equal(harness_sh("cp test/netc/carry_deadlock.pnml %s", path), 0);
    assert_int_equal(run(sup, 30.0, text, sizeof text), 2);
    assert_non_null(strstr(text, "deadlock"));
    assert_non_null(strstr(text, "firing sequence from the initial marking"));
    assert_non_null(strstr(text, "refused"));
    assert_int_equal(run(scen, 30.0, text, sizeof text), 2);
    assert_non_null(strstr(text, "--task"));
    /* no daemon was started: no logs */
    snprintf(path, sizeof path, "%s/run_sim.log", out);
    f = fopen(path, "r");
    assert_null(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_buffer_task_delivers_every_workpiece),
        cmocka_unit_test(test_broken_task_refused_before_anything_moves),
    };
    snprintf(dir, sizeof dir, "/tmp/it_task_%d", (int)getpid());
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Integration: a task other than the shipped carry, drawn as PNML, run by
 * the real daemons over LCM (docs/tasks.md §7). tandem-scenario carry
 * --task tasks/carry_buffer: the supervisor loads the buffer net and its
 * rows at start-up (token bound 1 from p6X + pbX + pfX + p7X + p8X = 1 for each of the
 * stand's two places X, its roles found from the net's structure), the
 * simulator gets the hand-over stand; both workpieces are delivered through
 * the buffer, one at each place, none dropped, no
 * invariant violation, deadlock or stall, every criterion met. Then a
 * broken task: tandem-supervisor --task refuses it with exit 2, naming
 * the file and why, and tandem-scenario refuses it before any daemon
 * starts. And tasks/carry_solo with arm 1 killed at 30 s and restarted at
 * 60 s (docs/tasks.md §8): the supervisor puts arm 1 down, arm 2 takes a
 * bar from its magazine and delivers it alone, arm 1 comes back and the
 * carry resumes; every workpiece delivered, every criterion met. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
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
    const char *argv[] = { "tandem-scenario",
                           "carry",
                           "--task",
                           "tasks/carry_buffer",
                           "--workpieces",
                           "2",
                           "--no-serial",
                           "--out",
                           dir,
                           NULL };
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
     * transitions fired (t3b* into the buffer, t4b* out of it), at both of
     * the stand's places */
    snprintf(path, sizeof path, "%s/run_supervisor.log", dir);
    assert_true(harness_slurp(path, log, sizeof log) > 0);
    assert_non_null(strstr(
        log, "task carry_buffer (tasks/carry_buffer): 17 places, 15 transitions, token bound 1"));
    assert_non_null(strstr(log, "complete t3bB arm 1 puts it in buffer place B"));
    assert_non_null(strstr(log, "complete t4bB arm 2 takes it from buffer place B"));
    assert_non_null(strstr(log, "complete t3bA arm 1 puts it in buffer place A"));
    assert_non_null(strstr(log, "complete t4bA arm 2 takes it from buffer place A"));
}

static void test_solo_task_arm2_carries_while_arm1_is_down(void **state)
{
    char out[300], path[400], text[8192];
    static char log[262144];
    const char *argv[] = { "tandem-scenario", "carry", "--task",  "tasks/carry_solo",
                           "--workpieces",    "4",     "--fault", "kill:arm1:30:60",
                           "--no-serial",     "--out", out,       NULL };
    (void)state;
    snprintf(out, sizeof out, "%s_solo", dir);
    assert_int_equal(run(argv, 400.0, text, sizeof text), 0);
    snprintf(path, sizeof path, "%s/summary.json", out);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_true(harness_json_value(text, "workpieces_delivered") == 4.0);
    assert_true(harness_json_value(text, "workpieces_dropped") == 0.0);
    assert_true(harness_json_value(text, "invariant_violations") == 0.0);
    assert_true(harness_json_value(text, "joint_limit_violations") == 0.0);
    assert_true(harness_json_value(text, "kills") == 1.0);
    assert_true(harness_json_value(text, "restarts") == 1.0);
    assert_non_null(strstr(text, "\"exit_reason\": \"completed\""));
    snprintf(path, sizeof path, "%s/run_supervisor.log", out);
    assert_true(harness_slurp(path, log, sizeof log) > 0);
    assert_non_null(strstr(log, "arm 1 DOWN (fault or silent): f1 fired"));
    assert_non_null(strstr(log, "complete s4 arm 2 releases it"));
    assert_non_null(strstr(log, "arm 1 up again: r1 fired"));
    assert_non_null(strstr(log, "complete s6 arm 1 back"));
    snprintf(path, sizeof path, "%s/run_stderr.log", out);
    assert_true(harness_slurp(path, log, sizeof log) > 0);
    assert_non_null(strstr(log, "in arm 2's magazine"));
}

/* Runs `cmd` (a program of this build and its arguments), stdout and
 * stderr into log and text; its exit status. */
static int run_logged(const char *cmd, const char *log, char *text, int cap)
{
    char exe[512];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    int st;
    assert_true(n > 0);
    exe[n] = '\0';
    *strrchr(exe, '/') = '\0'; /* the build's bin, where this test is */
    st = harness_sh("%s/%s > %s 2>&1", exe, cmd, log);
    assert_true(harness_slurp(log, text, cap) > 0);
    printf("%s", text);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The carry with the arc t7 -> p2 lost: arm 2 never comes home. */
static void test_broken_task_refused_before_anything_moves(void **state)
{
    char task[300], path[400], text[8192], out[300], cmd[1000];
    FILE *f;
    (void)state;
    snprintf(task, sizeof task, "%s_broken_task", dir);
    snprintf(out, sizeof out, "%s_broken_run", dir);
    mkdir(task, 0755);
    snprintf(path, sizeof path, "%s/rows.csv", task);
    assert_int_equal(harness_sh("cp tasks/carry/rows.csv %s", path), 0);
    snprintf(path, sizeof path, "%s/net.pnml", task);
    assert_int_equal(harness_sh("cp test/netc/carry_deadlock.pnml %s", path), 0);
    snprintf(cmd, sizeof cmd, "tandem-supervisor --task %s --insecure", task);
    snprintf(path, sizeof path, "%s_supervisor.log", dir);
    assert_int_equal(run_logged(cmd, path, text, sizeof text), 2);
    assert_non_null(strstr(text, "deadlock"));
    assert_non_null(strstr(text, "firing sequence from the initial marking"));
    assert_non_null(strstr(text, "22. complete tv"));
    assert_non_null(strstr(text, "refused: a dead marking is reachable (SUPERVISOR_ERR_TASK)"));
    snprintf(cmd, sizeof cmd, "tandem-scenario carry --task %s --workpieces 1 --no-serial --out %s",
             task, out);
    snprintf(path, sizeof path, "%s_scenario.log", dir);
    assert_int_equal(run_logged(cmd, path, text, sizeof text), 2);
    assert_non_null(strstr(text, "--task"));
    assert_non_null(strstr(text, "refused: a dead marking is reachable"));
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
        cmocka_unit_test(test_solo_task_arm2_carries_while_arm1_is_down),
    };
    snprintf(dir, sizeof dir, "/tmp/it_task_%d", (int)getpid());
    return cmocka_run_group_tests(tests, NULL, NULL);
}

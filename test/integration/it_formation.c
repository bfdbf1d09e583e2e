/* Integration: the seed-003 team is distributed. tandem-scenario formation
 * runs tandem-sim and three separate tandem-rover processes in lockstep on
 * a private bus; at t = 8 s robot 3's process is killed (SIGKILL) and its
 * body removed. The other two must drop it by heartbeat, re-slot, and
 * still reach the goal in formation without a collision (ground truth). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "harness.h"

static double json_number(const char *js, const char *key)
{
    char pat[64];
    const char *p;
    snprintf(pat, sizeof pat, "\"%s\":", key);
    p = strstr(js, pat);
    if (!p) return -1e9;
    p += strlen(pat);
    while (*p == ' ') p++;
    if (!strncmp(p, "true", 4)) return 1.0;
    if (!strncmp(p, "false", 5)) return 0.0;
    if (!strncmp(p, "null", 4)) return -1e9;
    return strtod(p, NULL);
}

static void test_kill_one_rover_mid_run(void **state)
{
    harness h;
    char dir[64], out[8192], js[4096], path[128];
    const char *argv[] = { "tandem-scenario", "formation", "--world", "open", "--formation", "line",
                           "--robots", "3", "--seed", "4", "--procs", "separate", "--kill", "3:8",
                           "--max-time", "60", "--lcm-url", NULL, "--out", dir, NULL };
    pid_t p;
    FILE *f;
    size_t n;
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/it_formation_%d", (int)getpid());
    assert_int_equal(harness_open(&h, 7), 0);
    argv[17] = h.url;
    p = harness_spawn(&h, argv);
    assert_true(p > 0);
    assert_int_equal(harness_wait(&h, p, 120.0), 0);
    harness_read_output(&h, p, out, sizeof out);
    printf("%s", out);
    snprintf(path, sizeof path, "%s/summary.json", dir);
    f = fopen(path, "r");
    assert_non_null(f);
    n = fread(js, 1, sizeof js - 1, f);
    fclose(f);
    js[n] = '\0';
    assert_true(json_number(js, "killed_robot") == 3.0);
    assert_true(json_number(js, "reached_goal") == 1.0);
    assert_true(json_number(js, "collisions") == 0.0);
    /* in formation: the two survivors' slots around their own average */
    assert_true(json_number(js, "rms_formation_err_m") < 0.5);
    assert_true(json_number(js, "wall_time_s") < 60.0);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kill_one_rover_mid_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Integration: a short lockstep carry through tandem-scenario (sim, both
 * arms, supervisor on a private udpm bus): two workpieces, one block of
 * arm 1 during an unsynchronised move (t1) and one during the
 * synchronised t3. Asserts both delivered, none dropped, no invariant
 * violation, no deadlock or re-plan, and that the t3 block stopped the
 * partner too (its s stopped advancing) with a bounded lead, that each
 * blocked arm moved on within 1 s of the stick coming out, and that the
 * run stayed physical (no joint-limit violation, 10 ms contact force at
 * most 1000 N, speeds within the motor limits).
 * Then a run whose supervisor is told a stall is 1 s: the run stops on
 * the stall and tandem-scenario exits 3 naming the failed criteria. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "erlaw.h"
#include "harness.h"

/* The 50 ms. A follower of the common reference tracks its rate
 * and brakes as a critically damped tracker at ERLAW_SYNC_OMEGA_RADPS
 * (erlaw.h: 0.88 / w = 29 ms from cruise, plus the blocked arm's own
 * stop and the one-step PROGRESS delay). */
#define PARTNER_STOP_MAX_S 0.050
/* lead <= g + v0 / (e w), v0 <= v_m + k0 / k_v with the SYNC row of
 * carry_table (0.2 m/s, k0 0.2, k_v 20), plus 1 mm for the measured s. */
#define SYNC_LEAD_BOUND_M \
    (ERLAW_FOLLOW_GAP_M + (0.2 + 0.2 / 20.0) / (exp(1.0) * ERLAW_SYNC_OMEGA_RADPS) + 0.001)

static char dir[256];

static void test_short_carry_with_blocks(void **state)
{
    proc_set ps;
    char path[512], text[8192], line[512];
    const char *argv[] = {
        "tandem-scenario", "carry",        "--workpieces", "2",     "--block", "1:3:1:2",
        "--block",         "1:5:5:1.5:t3", "--no-serial",  "--out", dir,       NULL
    };
    pid_t pid;
    int st = -1, i, rows = 0, t3_rows = 0;
    struct timespec ts = { 0, 50000000L };
    FILE *f;
    (void)state;
    proc_init(&ps, NULL, NULL);
    pid = proc_spawn(&ps, argv, NULL, NULL, NULL);
    assert_true(pid > 0);
    for (i = 0; i < 2400 && proc_poll(&ps, pid, &st) == 0; i++)
        nanosleep(&ts, NULL); /* at most 120 s */
    if (st < 0)
        proc_kill_all(&ps, 2.0);
    assert_int_equal(st, 0);
    proc_read(&ps, pid, text, sizeof text);
    printf("%s", text);
    snprintf(path, sizeof path, "%s/summary.json", dir);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_true(harness_json_value(text, "workpieces_delivered") == 2.0);
    assert_true(harness_json_value(text, "workpieces_dropped") == 0.0);
    assert_true(harness_json_value(text, "invariant_violations") == 0.0);
    assert_true(harness_json_value(text, "deadlocks") == 0.0);
    assert_true(harness_json_value(text, "replans") == 0.0);
    printf("resume latency max %.3f s, 10 ms contact force max %.1f N, max |qd|/qd_max %.3f\n",
           harness_json_value(text, "resume_latency_max_s"),
           harness_json_value(text, "max_contact_force_10ms_N"),
           harness_json_value(text, "max_joint_speed_ratio"));
    assert_true(harness_json_value(text, "resume_latency_max_s") > 0.0);
    assert_true(harness_json_value(text, "resume_latency_max_s") <= 1.0);
    assert_true(harness_json_value(text, "joint_limit_violations") == 0.0);
    assert_true(harness_json_value(text, "max_contact_force_10ms_N") > 0.5); /* the stick was met */
    assert_true(harness_json_value(text, "max_contact_force_10ms_N") <= 1000.0);
    assert_true(harness_json_value(text, "max_joint_speed_ratio") <= 1.0);
    assert_true(harness_json_value(text, "stalls") == 0.0);
    assert_non_null(strstr(text, "\"exit_reason\": \"completed\""));
    snprintf(path, sizeof path, "%s/blocks.csv", dir);
    f = fopen(path, "r");
    assert_non_null(f);
    while (fgets(line, sizeof line, f)) {
        double v[14];
        if (rows++ == 0)
            continue; /* header */
        assert_int_equal(sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf",
                                &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8],
                                &v[9], &v[10], &v[11], &v[12], &v[13]),
                         14);
        assert_true(v[3] >= 0.0 && v[4] > v[3]); /* the stick went in and out */
        if (v[6] == 1.0) {
            t3_rows++;
            printf("t3 block: blocked arm stopped at %.3f s, partner %.3f s later, lead %.4f m\n",
                   v[10], v[11], v[12]);
            assert_true(v[10] > 0.0);                 /* the blocked arm stopped */
            assert_true(v[11] <= PARTNER_STOP_MAX_S); /* and so did its partner */
            assert_true(v[12] <= SYNC_LEAD_BOUND_M);
        }
    }
    fclose(f);
    assert_int_equal(rows, 3);
    assert_int_equal(t3_rows, 1);
}

/* Any transition takes longer than 1 s: with --stall-s 1 the supervisor
 * reports a stall in the first one and the scenario stops on it. */
static void test_stall_stops_the_run_exit_3(void **state)
{
    proc_set ps;
    char out[300], path[512], text[8192];
    const char *argv[] = { "tandem-scenario",
                           "carry",
                           "--workpieces",
                           "1",
                           "--stall-s",
                           "1",
                           "--no-serial",
                           "--out",
                           out,
                           NULL };
    pid_t pid;
    int st = -1, i;
    struct timespec ts = { 0, 50000000L };
    (void)state;
    snprintf(out, sizeof out, "%s_stall", dir);
    proc_init(&ps, NULL, NULL);
    pid = proc_spawn(&ps, argv, NULL, NULL, NULL);
    assert_true(pid > 0);
    for (i = 0; i < 1200 && proc_poll(&ps, pid, &st) == 0; i++)
        nanosleep(&ts, NULL); /* at most 60 s */
    if (st < 0)
        proc_kill_all(&ps, 2.0);
    proc_read(&ps, pid, text, sizeof text);
    printf("%s", text);
    assert_int_equal(st, 3);
    assert_non_null(strstr(text, "FAILED"));
    assert_non_null(strstr(text, "stalls"));
    snprintf(path, sizeof path, "%s/summary.json", out);
    assert_true(harness_slurp(path, text, sizeof text) > 0);
    assert_non_null(strstr(text, "\"exit_reason\": \"stalled\""));
    assert_true(harness_json_value(text, "stalls") >= 1.0);
    assert_true(harness_json_value(text, "sim_time_s") <
                10.0); /* stopped at the stall, not at the time limit */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_short_carry_with_blocks),
        cmocka_unit_test(test_stall_stops_the_run_exit_3),
    };
    snprintf(dir, sizeof dir, "/tmp/it_carry_%d", (int)getpid());
    return cmocka_run_group_tests(tests, NULL, NULL);
}

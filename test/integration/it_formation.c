/* Integration: the seed-003 team is distributed. tandem-scenario formation
 * runs tandem-sim and three separate tandem-rover processes in lockstep on
 * a private bus; at t = 8 s robot 3's process is killed (SIGKILL) and its
 * body removed. The other two must drop it by heartbeat, re-slot, and
 * still reach the goal in formation without a collision (ground truth).
 * Second test: how the robots are spread over processes and how their
 * frames travel (one process per robot on ROVERk_* channels, or one
 * process for the team on the batched ROVERS_* channels) is transport
 * only: the two runs must be bit-identical in ground truth. Third: a
 * participant that is alive but slow is waited for, however long: robot
 * 2's process stopped (SIGSTOP) for longer than the lockstep timeout and
 * continued gives the undisturbed run's truth.csv, byte for byte; a killed
 * one is still dropped (the first test). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "harness.h"

static void test_kill_one_rover_mid_run(void **state)
{
    harness h;
    char dir[64], out[8192], js[4096], path[128];
    const char *argv[] = {
        "tandem-scenario", "formation", "--world",    "open", "--formation", "line",
        "--robots",        "3",         "--seed",     "4",    "--procs",     "separate",
        "--kill",          "3:8",       "--max-time", "60",   "--lcm-url",   NULL,
        "--out",           dir,         NULL
    };
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
    assert_true(harness_json_value(js, "killed_robot") == 3.0);
    assert_true(harness_json_value(js, "reached_goal") == 1.0);
    assert_true(harness_json_value(js, "collisions") == 0.0);
    /* in formation: the two survivors' slots around their own average */
    assert_true(harness_json_value(js, "rms_formation_err_m") < 0.5);
    assert_true(harness_json_value(js, "wall_time_s") < 60.0);
    harness_close(&h);
}

/* The pid of robot k's tandem-rover among the children of scenario pid p
 * (/proc/P/task/P/children and their command lines), -1 if none. */
static pid_t rover_child(pid_t p, int k)
{
    char path[96], kids[512], cmd[512], want[16];
    const char *c;
    FILE *f;
    size_t n;
    snprintf(path, sizeof path, "/proc/%d/task/%d/children", (int)p, (int)p);
    if (!(f = fopen(path, "r")))
        return -1;
    n = fread(kids, 1, sizeof kids - 1, f);
    fclose(f);
    kids[n] = '\0';
    snprintf(want, sizeof want, "%d", k);
    for (c = kids; *c;) {
        const long kid = strtol(c, (char **)&c, 10);
        const char *a;
        int id_next = 0, rover = 0;
        if (kid <= 0)
            break;
        snprintf(path, sizeof path, "/proc/%ld/cmdline", kid);
        if (!(f = fopen(path, "r")))
            continue;
        n = fread(cmd, 1, sizeof cmd - 1, f);
        fclose(f);
        cmd[n] = '\0';
        for (a = cmd; a < cmd + n; a += strlen(a) + 1) {
            if (strstr(a, "tandem-rover"))
                rover = 1;
            if (id_next && rover && strcmp(a, want) == 0)
                return (pid_t)kid;
            id_next = strcmp(a, "--id") == 0;
        }
    }
    return -1;
}

static void sleep_s(double s)
{
    struct timespec ts;
    ts.tv_sec = (time_t)s;
    ts.tv_nsec = (long)((s - (double)ts.tv_sec) * 1e9);
    nanosleep(&ts, NULL);
}

/* Once robot 2's process is running and truth.csv has grown, stops it
 * for stop_s (SIGSTOP, then SIGCONT). */
static void stop_rover_2(pid_t scen, const char *truth, double stop_s)
{
    struct stat st;
    pid_t r = -1;
    int i;
    for (i = 0; i < 2000 && (r < 0 || stat(truth, &st) != 0 || st.st_size < 5000); i++) {
        sleep_s(0.005);
        if (r < 0)
            r = rover_child(scen, 2);
    }
    assert_true(r > 0);
    assert_int_equal(kill(r, SIGSTOP), 0);
    sleep_s(stop_s);
    assert_int_equal(kill(r, SIGCONT), 0);
}

/* FNV-1a of a file's bytes, and their number in *size. */
static uint64_t file_hash(const char *path, long *size)
{
    uint64_t hash = 1469598103934665603ULL;
    FILE *f = fopen(path, "r");
    int c;
    assert_non_null(f);
    *size = 0;
    while ((c = fgetc(f)) != EOF) {
        hash = (hash ^ (uint64_t)(unsigned char)c) * 1099511628211ULL;
        (*size)++;
    }
    fclose(f);
    return hash;
}

/* Runs the obstacles world for 20 s; returns truth.csv's size and hash.
 * stop_s > 0: robot 2's process is stopped that long in the run. */
static uint64_t run_truth_hash(harness *h, const char *procs, const char *link, double stop_s,
                               long *size)
{
    char dir[64], path[128];
    const char *argv[] = { "tandem-scenario",
                           "formation",
                           "--world",
                           "obstacles",
                           "--robots",
                           "3",
                           "--seed",
                           "2",
                           "--procs",
                           procs,
                           "--link",
                           link,
                           "--max-time",
                           "20",
                           "--lockstep-timeout-ms",
                           "300",
                           "--lcm-url",
                           h->url,
                           "--out",
                           dir,
                           NULL };
    pid_t p;
    snprintf(dir, sizeof dir, "/tmp/it_formation_%s%s_%d", link, stop_s > 0.0 ? "_stop" : "",
             (int)getpid());
    snprintf(path, sizeof path, "%s/truth.csv", dir);
    remove(path);
    p = harness_spawn(h, argv);
    assert_true(p > 0);
    if (stop_s > 0.0)
        stop_rover_2(p, path, stop_s);
    /* 20 s is short of the goal: the run ends on its time limit and says
     * so with exit status 3 (a criterion failed) */
    assert_int_equal(harness_wait(h, p, 120.0), 3);
    return file_hash(path, size);
}

/* Four teams of 3 crossing in pairs (their paths meet at 5-7 s) for 8 s,
 * their robots on `hosts` tandem-rover processes: truth.csv's hash. */
static uint64_t fleet_truth_hash(harness *h, const char *hosts, long *size)
{
    char dir[64], path[128];
    const char *argv[] = { "tandem-scenario",
                           "formation",
                           "--teams",
                           "4",
                           "--robots-per-team",
                           "3",
                           "--procs",
                           "single",
                           "--hosts",
                           hosts,
                           "--max-time",
                           "8",
                           "--lcm-url",
                           h->url,
                           "--out",
                           dir,
                           NULL };
    pid_t p;
    snprintf(dir, sizeof dir, "/tmp/it_formation_hosts%s_%d", hosts, (int)getpid());
    snprintf(path, sizeof path, "%s/truth.csv", dir);
    remove(path);
    p = harness_spawn(h, argv);
    assert_true(p > 0);
    assert_int_equal(harness_wait(h, p, 120.0), 3); /* short of the goals */
    return file_hash(path, size);
}

/* Two runs' truth.csv (their sizes and hashes, a and b: what each was)
 * are the same and at least min_size bytes. */
static void assert_same_truth(const char *a, long size_a, uint64_t hash_a, const char *b,
                              long size_b, uint64_t hash_b, long min_size)
{
    printf("truth.csv: %ld bytes %s, %ld %s; hashes %016llx %016llx\n", size_a, a, size_b, b,
           (unsigned long long)hash_a, (unsigned long long)hash_b);
    assert_true(size_a > min_size);
    assert_int_equal(size_a, size_b);
    assert_true(hash_a == hash_b);
}

static void test_batched_link_is_the_same_run(void **state)
{
    harness h;
    long size_robot, size_batch;
    uint64_t robot, batch;
    (void)state;
    assert_int_equal(harness_open(&h, 8), 0);
    robot = run_truth_hash(&h, "separate", "robot", 0.0, &size_robot);
    batch = run_truth_hash(&h, "single", "batch", 0.0, &size_batch);
    /* 20 s of 20 Hz truth for 3 robots: over 10,000 bytes */
    assert_same_truth("per robot link", size_robot, robot, "batched", size_batch, batch, 10000);
    harness_close(&h);
}

/* Stopped for 1.5 s, five times the lockstep timeout (0.3 s): alive, so
 * waited for; the run must be the undisturbed one. */
static void test_stopped_rover_is_waited_for(void **state)
{
    harness h;
    long size_plain, size_stop;
    uint64_t plain, stopped;
    (void)state;
    assert_int_equal(harness_open(&h, 9), 0);
    plain = run_truth_hash(&h, "separate", "robot", 0.0, &size_plain);
    stopped = run_truth_hash(&h, "separate", "robot", 1.5, &size_stop);
    assert_same_truth("undisturbed", size_plain, plain, "with robot 2 stopped 1.5 s", size_stop,
                      stopped, 10000);
    harness_close(&h);
}

/* The fleet's robots on one host or on three (whole teams each: 1, 1
 * and 2 teams): the same run, mates on other hosts included. */
static void test_hosts_are_the_same_run(void **state)
{
    harness h;
    long size_one, size_three;
    uint64_t one, three;
    (void)state;
    assert_int_equal(harness_open(&h, 10), 0);
    one = fleet_truth_hash(&h, "1", &size_one);
    three = fleet_truth_hash(&h, "3", &size_three);
    /* 8 s of 20 Hz truth for 12 robots: over 50,000 bytes */
    assert_same_truth("on one host", size_one, one, "on three", size_three, three, 50000);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kill_one_rover_mid_run),
        cmocka_unit_test(test_batched_link_is_the_same_run),
        cmocka_unit_test(test_stopped_rover_is_waited_for),
        cmocka_unit_test(test_hosts_are_the_same_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

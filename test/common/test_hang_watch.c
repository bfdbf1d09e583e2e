/* Unit tests of hang_watch (tools/scenario/hang_watch.h): who is hung,
 * when, and what is forgiven. Times are given, not read, but for
 * hang_watch_look, which reads an in-memory bus. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <signal.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "hang_watch.h"
#include "peer.h"

/* Silent for hang_s after speaking: hung; a word resets the clock. */
static void test_silent_after_speaking_is_hung(void **state)
{
    hang_watch w;
    int k;
    (void)state;
    hang_watch_init(&w, 5.0);
    k = hang_watch_add(&w, "tandem-supervisor", 100.0);
    assert_int_equal(k, 0);
    hang_watch_heard(&w, "tandem-supervisor", 101.0);
    assert_false(hang_watch_hung(&w, k, 105.9));
    assert_true(hang_watch_hung(&w, k, 106.1));
    hang_watch_heard(&w, "tandem-supervisor", 106.0);
    assert_false(hang_watch_hung(&w, k, 110.9));
    assert_true(hang_watch_silent_s(&w, k, 111.0) > 4.9);
}

/* A child just started has HANG_WATCH_START_S more for its first word. */
static void test_start_grace(void **state)
{
    hang_watch w;
    int k;
    (void)state;
    hang_watch_init(&w, 2.0);
    k = hang_watch_add(&w, "tandem-rover-2", 0.0);
    assert_false(hang_watch_hung(&w, k, 2.0 + HANG_WATCH_START_S - 0.1));
    assert_true(hang_watch_hung(&w, k, 2.0 + HANG_WATCH_START_S + 0.1));
    hang_watch_started(&w, k, 50.0); /* restarted: the grace again */
    assert_false(hang_watch_hung(&w, k, 53.0));
}

/* Only the named child's words count; a child down on purpose, or the
 * watch off, is never hung. */
static void test_names_down_and_off(void **state)
{
    hang_watch w;
    int a, b;
    (void)state;
    hang_watch_init(&w, 1.0);
    a = hang_watch_add(&w, "tandem-arm-1", 0.0);
    b = hang_watch_add(&w, "tandem-arm-2", 0.0);
    hang_watch_heard(&w, "tandem-arm-1", 20.0);
    hang_watch_heard(&w, "tandem-arm-2", 10.0);
    assert_false(hang_watch_hung(&w, a, 20.5));
    assert_true(hang_watch_hung(&w, b, 20.5));
    hang_watch_down(&w, b);
    assert_false(hang_watch_hung(&w, b, 30.0));
    hang_watch_init(&w, 0.0);
    a = hang_watch_add(&w, "tandem-arm-1", 0.0);
    assert_false(hang_watch_hung(&w, a, 1e6));
}

static void test_bad_names(void **state)
{
    hang_watch w;
    char long_name[100];
    int i;
    (void)state;
    hang_watch_init(&w, 1.0);
    memset(long_name, 'x', sizeof long_name - 1);
    long_name[sizeof long_name - 1] = '\0';
    assert_int_equal(hang_watch_add(&w, "", 0.0), HANG_WATCH_ERR_NAME);
    assert_int_equal(hang_watch_add(&w, long_name, 0.0), HANG_WATCH_ERR_NAME);
    for (i = 0; i < HANG_WATCH_MAX; i++)
        assert_int_equal(hang_watch_add(&w, "d", 0.0), i);
    assert_int_equal(hang_watch_add(&w, "d", 0.0), HANG_WATCH_ERR_FULL);
    assert_non_null(strstr(hang_watch_strerror(HANG_WATCH_ERR_FULL), "HANG_WATCH_ERR_FULL"));
    assert_non_null(strstr(hang_watch_strerror(HANG_WATCH_ERR_NAME), "HANG_WATCH_ERR_NAME"));
}

/* The scenario away for longer than HANG_WATCH_AWAY_S between two looks:
 * the children's silence meanwhile is forgiven; an empty bus is read. */
static void test_look_forgives_own_absence(void **state)
{
    hang_watch w;
    lcm_t *lcm = lcm_create("memq://");
    int k;
    (void)state;
    assert_non_null(lcm);
    hang_watch_init(&w, 2.0);
    k = hang_watch_add(&w, "tandem-sim", 0.0);
    hang_watch_heard(&w, "tandem-sim", 1.0);
    assert_int_equal(hang_watch_look(&w, lcm, 1.2), 1);
    assert_int_equal(hang_watch_look(&w, lcm, 9.2), 1); /* away 8 s */
    assert_false(hang_watch_hung(&w, k, 9.3));
    assert_true(hang_watch_hung(&w, k, 11.3));
    lcm_destroy(lcm);
}

/* A child process that sleeps (sleep_s > 0) or spins for -sleep_s s of
 * CPU, then sleeps until killed. */
static pid_t child(double sleep_s)
{
    const pid_t p = fork();
    assert_true(p >= 0);
    if (p == 0) {
        /* gone by itself if a failed assertion leaves it unreaped, and
         * holding no pipe of the caller's open meanwhile */
        alarm(30);
        close(1);
        close(2);
        if (sleep_s < 0.0) {
            const clock_t until = clock() + (clock_t)(-sleep_s * CLOCKS_PER_SEC);
            while (clock() < until) {
            }
        }
        for (;;)
            pause();
    }
    return p;
}

static void reap(pid_t p)
{
    kill(p, SIGKILL);
    waitpid(p, NULL, 0);
}

/* With its process known, silence is not enough: a child that got no CPU
 * (a loaded machine; here one asleep) is hung only after
 * HANG_WATCH_STARVED_X times the limit; one that ran for more than a
 * quarter of hang_s since it spoke, or is stopped, after the limit. */
static void test_slow_is_not_hung(void **state)
{
    const double hang_s = 0.4;
    const double lim = HANG_WATCH_START_S + hang_s; /* never spoke */
    hang_watch w;
    pid_t sleeper = child(1.0), spinner = child(-0.3), stopped = child(1.0);
    int ks, kr, kt;
    (void)state;
    hang_watch_init(&w, hang_s);
    ks = hang_watch_add(&w, "sleeper", 0.0);
    kr = hang_watch_add(&w, "spinner", 0.0);
    kt = hang_watch_add(&w, "stopped", 0.0);
    hang_watch_pid(&w, ks, sleeper);
    hang_watch_pid(&w, kr, spinner);
    hang_watch_pid(&w, kt, stopped);
    assert_int_equal(kill(stopped, SIGSTOP), 0);
    { /* until the spinner has had its CPU (a loaded machine: up to 20 s) */
        const struct timespec ts = { 0, 20000000L };
        int i;
        for (i = 0; i < 1000 && peer_cpu_ns(spinner) < 250000000LL; i++)
            nanosleep(&ts, NULL);
    }
    assert_false(hang_watch_hung(&w, ks, lim + 0.1));
    assert_false(hang_watch_hung(&w, ks, HANG_WATCH_STARVED_X * lim - 0.1));
    assert_true(hang_watch_hung(&w, ks, HANG_WATCH_STARVED_X * lim + 0.1));
    assert_false(hang_watch_hung(&w, kr, lim - 0.1));
    assert_true(hang_watch_hung(&w, kr, lim + 0.1));
    assert_true(hang_watch_hung(&w, kt, lim + 0.1));
    reap(sleeper);
    reap(spinner);
    reap(stopped);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_silent_after_speaking_is_hung),
        cmocka_unit_test(test_start_grace),
        cmocka_unit_test(test_names_down_and_off),
        cmocka_unit_test(test_bad_names),
        cmocka_unit_test(test_look_forgives_own_absence),
        cmocka_unit_test(test_slow_is_not_hung),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

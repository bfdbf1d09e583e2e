/* Unit tests of peer (src/daemons/common/peer.c): alive, slow or dead, as
 * the lockstep decides it (docs/method/lockstep.md §3 item 5). A stopped
 * process is never dead however long it is silent; a gone one is dead at
 * once; a running one silent past the timeout is dead only if it had the
 * processor meanwhile; no pid known: the wall clock alone. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "peer.h"

#define SEC 1000000000LL

static pid_t child_sleeping(void)
{
    const pid_t p = fork();
    if (p == 0) {
        for (;;)
            pause();
    }
    assert_true(p > 0);
    return p;
}

static pid_t child_spinning(void)
{
    const pid_t p = fork();
    if (p == 0) {
        volatile unsigned long n = 0;
        for (;;)
            n++;
    }
    assert_true(p > 0);
    return p;
}

static void wait_state(pid_t p, peer_proc want)
{
    int i;
    for (i = 0; i < 400 && peer_proc_of((int32_t)p) != want; i++) {
        struct timespec ts = { 0, 5000000L };
        nanosleep(&ts, NULL);
    }
    assert_int_equal(peer_proc_of((int32_t)p), want);
}

static void test_own_process_runs(void **state)
{
    (void)state;
    assert_int_equal(peer_proc_of((int32_t)getpid()), PEER_PROC_RUNNING);
    assert_int_equal(peer_proc_of(0), PEER_PROC_UNKNOWN);
    assert_true(peer_cpu_ns((int32_t)getpid()) >= 0);
}

static void test_stopped_is_waited_for(void **state)
{
    peer_watch w = { 0, 0, 0 };
    const pid_t p = child_sleeping();
    (void)state;
    peer_heard(&w, (int32_t)p, 0);
    kill(p, SIGSTOP);
    wait_state(p, PEER_PROC_STOPPED);
    assert_int_equal(peer_dead(&w, 1000 * SEC, SEC), 0); /* silent 1000 timeouts: still alive */
    kill(p, SIGCONT);
    wait_state(p, PEER_PROC_RUNNING);
    /* sleeping, no CPU used since heard: slow (or waiting), not hung */
    assert_int_equal(peer_dead(&w, 1000 * SEC, SEC), 0);
    kill(p, SIGKILL);
    wait_state(p, PEER_PROC_GONE);              /* a zombie is gone */
    assert_int_equal(peer_dead(&w, 0, SEC), 1); /* at once, not after the timeout */
    waitpid(p, NULL, 0);
    assert_int_equal(peer_proc_of((int32_t)p), PEER_PROC_GONE);
}

static void test_running_silent_hangs(void **state)
{
    peer_watch w = { 0, 0, 0 };
    const pid_t p = child_spinning();
    int i, early, hung, long_timeout;
    (void)state;
    peer_heard(&w, (int32_t)p, 0);
    /* until it has had 0.1 s of CPU (a loaded machine gives it less than
     * the wall time), at most 20 s */
    for (i = 0; i < 2000 && peer_cpu_ns((int32_t)p) - w.heard_cpu_ns < SEC / 10; i++) {
        struct timespec ts = { 0, 10000000L };
        nanosleep(&ts, NULL);
    }
    early = peer_dead(&w, SEC / 10, SEC / 5);            /* not yet silent for the timeout */
    hung = peer_dead(&w, 1000 * SEC, SEC / 5);           /* silent, and had > 50 ms of CPU */
    long_timeout = peer_dead(&w, 1000 * SEC, 100 * SEC); /* had far less than 25 s of CPU */
    kill(p, SIGKILL);
    waitpid(p, NULL, 0);
    assert_int_equal(early, 0);
    assert_int_equal(hung, 1);
    assert_int_equal(long_timeout, 0);
}

static void test_unknown_pid_wall_clock(void **state)
{
    peer_watch w = { 0, 0, 0 };
    (void)state;
    peer_heard(&w, 0, 5 * SEC);
    assert_int_equal(peer_dead(&w, 6 * SEC, 2 * SEC), 0);
    assert_int_equal(peer_dead(&w, 8 * SEC, 2 * SEC), 1);
}

static void test_rover_range(void **state)
{
    long lo = 0, hi = 0;
    (void)state;
    assert_int_equal(peer_rover_range("tandem-rover-3", &lo, &hi), 1);
    assert_true(lo == 3 && hi == 3);
    assert_int_equal(peer_rover_range("tandem-rover-1-8", &lo, &hi), 1);
    assert_true(lo == 1 && hi == 8);
    assert_int_equal(peer_rover_range("tandem-rover-0", &lo, &hi), 0);
    assert_int_equal(peer_rover_range("tandem-rover-4-2", &lo, &hi), 0);
    assert_int_equal(peer_rover_range("tandem-arm-1", &lo, &hi), 0);
    assert_int_equal(peer_rover_range("tandem-rover-2x", &lo, &hi), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_own_process_runs),     cmocka_unit_test(test_stopped_is_waited_for),
        cmocka_unit_test(test_running_silent_hangs), cmocka_unit_test(test_unknown_pid_wall_clock),
        cmocka_unit_test(test_rover_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests of the daemons' start-up table check (daemon_check_table,
 * src/daemons/common/daemon.c) on the tables the daemons check: the shipped
 * ones pass, a broken copy is refused with DAEMON_ERR_TABLE, and the
 * defaults the command line starts from (daemon_defaults) are the documented ones,
 * and a line printed after daemon_defaults reaches a pipe without a flush;
 * a renewed LCM handle (the bound on LCM's table of channel names) hears
 * every channel the old one did, and a renewal that cannot open keeps the
 * old one. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "arm_model.h"
#include "carry_net.h"
#include "cartctl.h"
#include "cell.h"
#include "daemon.h"
#include "petri.h"
#include "rover_ctl.h"
#include "arm_status.h"
#include "carry_status.h"
#include "rover_status.h"

static void test_shipped_tables_pass(void **state)
{
    cartctl_gains cg;
    rover_ctl_params rp;
    (void)state;
    cartctl_gains_default(&cg);
    rover_ctl_params_default(&rp);
    assert_int_equal(daemon_check_table("t", "arm_model_puma560", "arm_model_validate",
                                        arm_model_validate(&arm_model_puma560), arm_model_strerror),
                     0);
    assert_int_equal(daemon_check_table("t", "arm_model_seed002", "arm_model_validate",
                                        arm_model_validate(&arm_model_seed002), arm_model_strerror),
                     0);
    assert_int_equal(daemon_check_table("t", "cell_default", "cell_layout_validate",
                                        cell_layout_validate(&cell_default), cell_strerror),
                     0);
    assert_int_equal(daemon_check_table("t", "cartctl_gains_default", "cartctl_gains_validate",
                                        cartctl_gains_validate(&cg), cartctl_strerror),
                     0);
    assert_int_equal(daemon_check_table("t", "carry_net", "petri_net_validate",
                                        petri_net_validate(&carry_net), petri_strerror),
                     0);
    assert_int_equal(
        daemon_check_table("t", "carry_table", "carry_table_validate",
                           carry_table_validate(carry_table, CARRY_N_TRANSITIONS, &carry_net),
                           carry_net_strerror),
        0);
    assert_int_equal(daemon_check_table("t", "rover_ctl_params", "rover_ctl_params_validate",
                                        rover_ctl_params_validate(&rp), rover_ctl_strerror),
                     0);
    assert_int_equal(daemon_check_table("t", "rover_snapshot field table",
                                        "rover_snapshot_validate", rover_snapshot_validate(),
                                        rover_ctl_strerror),
                     0);
}

static void test_broken_table_refused(void **state)
{
    static arm_model m;
    cartctl_gains cg;
    (void)state;
    m = arm_model_puma560;
    m.q_min_rad[2] = m.q_max_rad[2]; /* an empty joint range */
    assert_int_equal(daemon_check_table("t", "arm_model_puma560", "arm_model_validate",
                                        arm_model_validate(&m), arm_model_strerror),
                     DAEMON_ERR_TABLE);
    cartctl_gains_default(&cg);
    cg.k_null = -1.0;
    assert_int_equal(daemon_check_table("t", "cartctl_gains_default", "cartctl_gains_validate",
                                        cartctl_gains_validate(&cg), cartctl_strerror),
                     DAEMON_ERR_TABLE);
    /* a table is named by the caller; any non-zero code is a refusal */
    assert_int_equal(
        daemon_check_table("t", "x", "x_validate", PETRI_ERR_INVARIANT, petri_strerror),
        DAEMON_ERR_TABLE);
}

static void test_defaults(void **state)
{
    static daemon d;
    (void)state;
    daemon_defaults(&d, "test-daemon", 0.05);
    assert_string_equal(d.name, "test-daemon");
    assert_true(d.period_s == 0.05);
    assert_true(d.drop_rate == 0.0);
    assert_int_equal(d.drop_seed, 1);
    assert_int_equal(d.rt_prio, 0);
    assert_int_equal(d.lockstep, 0);
}

/* A drain may take a quarter of the period, never less than 50 us; the
 * receive path's tables are each daemon's own. */
static void test_drain_budget_and_own_rx(void **state)
{
    static daemon a, b;
    (void)state;
    daemon_defaults(&a, "a", 0.001);
    daemon_defaults(&b, "b", 0.05);
    assert_int_equal(daemon_drain_budget_ns(&a), 250000);
    assert_int_equal(daemon_drain_budget_ns(&b), 12500000);
    a.period_s = 1e-5;
    assert_int_equal(daemon_drain_budget_ns(&a), 50000);
    rx_set_drop(&a.rx, 0.5, 7);
    assert_true(a.rx.drop_p == 0.5 && b.rx.drop_p == 0.0);
    assert_int_equal(a.rx.deferred, 0);
}

/* tandem-run reads every daemon's stdout through a pipe, where stdio's
 * default is full buffering: a line printed without fflush (the
 * supervisor's "row N -> arm K") showed up seconds late. After
 * daemon_defaults the line must be in the pipe at once. */
static void test_stdout_line_buffered(void **state)
{
    daemon d;
    int fds[2], saved;
    char buf[64];
    ssize_t n;
    (void)state;
    fflush(stdout);
    setvbuf(stdout, NULL, _IOFBF, BUFSIZ); /* what a pipe gets by default */
    assert_int_equal(pipe(fds), 0);
    assert_int_equal(fcntl(fds[0], F_SETFL, O_NONBLOCK), 0);
    saved = dup(1);
    assert_true(saved >= 0);
    assert_true(dup2(fds[1], 1) == 1);
    daemon_defaults(&d, "tandem-test", 0.01);
    printf("row 1 -> arm 2\n");
    n = read(fds[0], buf, sizeof buf - 1);
    fflush(stdout);
    assert_true(dup2(saved, 1) == 1);
    close(saved);
    close(fds[0]);
    close(fds[1]);
    assert_int_equal((int)n, 15);
    buf[n] = 0;
    assert_string_equal(buf, "row 1 -> arm 2\n");
}

/* A refused table is said in words: the module's text of the code, then
 * the code (stderr is unbuffered, so the line is in the pipe at once). */
static void test_refusal_names_the_code(void **state)
{
    int fds[2], saved;
    char buf[256], want[256];
    ssize_t n;
    (void)state;
    assert_int_equal(pipe(fds), 0);
    assert_int_equal(fcntl(fds[0], F_SETFL, O_NONBLOCK), 0);
    saved = dup(2);
    assert_true(saved >= 0);
    assert_true(dup2(fds[1], 2) == 2);
    daemon_check_table("t", "carry_net", "petri_net_validate", PETRI_ERR_INVARIANT, petri_strerror);
    n = read(fds[0], buf, sizeof buf - 1);
    assert_true(dup2(saved, 2) == 2);
    close(saved);
    close(fds[0]);
    close(fds[1]);
    assert_true(n > 0);
    buf[n] = 0;
    snprintf(want, sizeof want, "t: carry_net is invalid (petri_net_validate: %s, %d)\n",
             petri_strerror(PETRI_ERR_INVARIANT), PETRI_ERR_INVARIANT);
    assert_string_equal(buf, want);
}

static int heard;
static void on_heard(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    heard++;
}

/* Messages of ch that reached d's receive path: handed on, or refused
 * there (these test messages are junk, unsigned). */
static int64_t seen_on(const daemon *d, const char *ch)
{
    int i;
    for (i = 0; i < d->rx.n_chans; i++)
        if (strcmp(d->rx.chans[i].name, ch) == 0)
            return d->rx.chans[i].copies + d->rx.chans[i].auth_rejected + d->rx.chans[i].rejected;
    return -1;
}

/* Every subscription of d delivers once on its handle, and only there. */
static void assert_each_heard_once(daemon *d, const char *const *chans, int n)
{
    static const char junk[32];
    int i;
    for (i = 0; i < n; i++) {
        const int64_t before = seen_on(d, chans[i]);
        assert_true(before >= 0);
        assert_int_equal(lcm_publish(d->lcm, chans[i], junk, sizeof junk), 0);
        /* not heard: no message to handle, a timeout (0) */
        assert_true(lcm_handle_timeout(d->lcm, 1000) > 0);
        assert_int_equal(seen_on(d, chans[i]), before + 1);
    }
}

/* A renewed handle keeps every subscription, on its own thread
 * (lcm_renew) or made beside it by the worker (renew.h): with the
 * worker, a channel subscribed after the request was staged is
 * subscribed at the swap, and the old handle is closed by the worker. */
static void renew_case(int with_worker)
{
    static daemon d;
    const char *chans[3] = { "ARM1_ACTION", "SIM_CLOCK", "ARM2_ACTION" };
    lcm_t *old;
    lcm_subscription_t *first[2];
    int i;
    daemon_defaults(&d, "test-renew", 0.001);
    d.lcm_url = "memq://";
    d.lcm = lcm_create(d.lcm_url);
    assert_non_null(d.lcm);
    if (with_worker)
        assert_int_equal(renew_start(&d.renew, d.lcm_url, DAEMON_QUEUE_CAPACITY), RENEW_OK);
    for (i = 0; i < 2; i++) {
        first[i] = daemon_subscribe(&d, chans[i], on_heard, NULL);
        assert_non_null(first[i]);
    }
    /* subscribing again (a model re-created after a reset) is the same
     * subscription, not a second delivery */
    assert_true(daemon_subscribe(&d, chans[0], on_heard, NULL) == first[0]);
    assert_int_equal(d.rx.n_subs, 2);
    if (with_worker) {
        assert_int_equal(renew_request(&d.renew, &d.rx, d.lcm), 1);
        assert_int_equal(renew_request(&d.renew, &d.rx, d.lcm), 0); /* one at a time */
    }
    assert_non_null(daemon_subscribe(&d, chans[2], on_heard, NULL));
    old = d.lcm;
    assert_int_equal(daemon_renew_lcm(&d), DAEMON_OK);
    assert_true(d.lcm != old); /* the new one opens before the old one closes */
    assert_int_equal(d.names.renewals, 1);
    /* again after the renewal: the renewed handle's subscription */
    assert_non_null(daemon_subscribe(&d, chans[0], on_heard, NULL));
    assert_int_equal(d.rx.n_subs, 3);
    for (i = 0; i < 3; i++)
        assert_true(d.rx.subs[i].lcm == d.lcm);
    assert_each_heard_once(&d, chans, 3);
    if (with_worker) {
        for (i = 0; i < DAEMON_RENEW_WAIT_MS && renew_pending(&d.renew); i++) {
            const struct timespec ms = { 0, 1000000L };
            lcm_subscription_t *const *staged;
            int n_staged;
            /* hands a retired one left waiting; nothing new is made */
            assert_int_equal(renew_take(&d.renew, &old, &staged, &n_staged), 0);
            nanosleep(&ms, NULL);
        }
        assert_false(renew_pending(&d.renew));
        assert_int_equal(d.renew.closed, 1);
    }
    /* a handle that cannot open: the old one kept, nothing counted */
    old = d.lcm;
    d.lcm_url = d.renew.url = "nosuchprovider://";
    assert_int_equal(daemon_renew_lcm(&d), DAEMON_ERR_LCM);
    assert_true(d.lcm == old);
    assert_int_equal(d.names.renewals, 1);
    assert_each_heard_once(&d, chans, 3);
    renew_stop(&d.renew);
    lcm_destroy(d.lcm);
}

static void test_renewed_lcm_keeps_subscriptions(void **state)
{
    (void)state;
    renew_case(0);
}

static void test_renewed_beside_the_loop(void **state)
{
    (void)state;
    renew_case(1);
}

/* A flood in the queue: one drain stops at its budget (a quarter of the
 * period), counts the drain as deferred and leaves the rest queued; the
 * CPU it took (health rx_cpu_max_us) is within the budget and one
 * message's handling, not the queue's. */
static void test_drain_stops_at_budget(void **state)
{
    static daemon d;
    static const char junk[256];
    int i;
    (void)state;
    daemon_defaults(&d, "test-drain", 0.004); /* budget 1 ms */
    d.lcm_url = "memq://";
    d.lcm = lcm_create(d.lcm_url);
    assert_non_null(d.lcm);
    assert_non_null(daemon_subscribe(&d, "ARM1_ACTION", on_heard, NULL));
    for (i = 0; i < 50000; i++) /* refused unsigned, a few us each: far past 1 ms */
        assert_int_equal(lcm_publish(d.lcm, "ARM1_ACTION", junk, sizeof junk), 0);
    daemon_drain(&d);
    assert_int_equal(d.rx.deferred, 1);
    assert_true(seen_on(&d, "ARM1_ACTION") > 0 && seen_on(&d, "ARM1_ACTION") < 50000);
    assert_true(d.rx.drain_cpu_max_ns > 0);
    assert_true(d.rx.drain_cpu_max_ns < 2 * daemon_drain_budget_ns(&d));
    lcm_destroy(d.lcm);
}

static int three_cycles(daemon *d, void *user)
{
    int *n = user;
    (void)d;
    return ++*n >= 3 ? 7 : DAEMON_CONTINUE;
}

/* With DAEMON_HEARTBEAT_ENV set, the loop itself touches DIR/PID (the
 * launcher's liveness check, which a flood on the bus cannot starve):
 * a file made an hour old before the run is fresh after it. */
static void test_heartbeat_file_touched_by_the_loop(void **state)
{
    static daemon d;
    char dir[] = "/tmp/tandem-hb-XXXXXX", path[128];
    struct stat st;
    struct timespec old[2];
    int n = 0, fd;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/%ld", dir, (long)getpid());
    fd = open(path, O_WRONLY | O_CREAT, 0600);
    assert_true(fd >= 0);
    old[0].tv_sec = old[1].tv_sec = time(NULL) - 3600;
    old[0].tv_nsec = old[1].tv_nsec = 0;
    assert_int_equal(futimens(fd, old), 0);
    close(fd);
    assert_int_equal(setenv(DAEMON_HEARTBEAT_ENV, dir, 1), 0);
    daemon_defaults(&d, "test-heartbeat", 0.01);
    d.lcm_url = "memq://";
    d.lcm = lcm_create(d.lcm_url);
    assert_non_null(d.lcm);
    assert_int_equal(rtloop_init(&d.loop, 10000000), 0);
    daemon_heartbeat_open(&d); /* as daemon_start does */
    assert_int_equal(daemon_run(&d, three_cycles, &n), 7);
    assert_true(d.heartbeat_fd >= 0);
    daemon_finish(&d);
    assert_int_equal(d.heartbeat_fd, -1);
    unsetenv(DAEMON_HEARTBEAT_ENV);
    assert_int_equal(stat(path, &st), 0);
    assert_true(st.st_mtime >= time(NULL) - 5);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shipped_tables_pass),
        cmocka_unit_test(test_broken_table_refused),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_stdout_line_buffered),
        cmocka_unit_test(test_refusal_names_the_code),
        cmocka_unit_test(test_drain_budget_and_own_rx),
        cmocka_unit_test(test_renewed_lcm_keeps_subscriptions),
        cmocka_unit_test(test_renewed_beside_the_loop),
        cmocka_unit_test(test_drain_stops_at_budget),
        cmocka_unit_test(test_heartbeat_file_touched_by_the_loop),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

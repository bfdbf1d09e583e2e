/* Integration: tandem-sim and the arm controllers over a real udpm LCM bus
 * in lockstep. (1) 2000 steps twice with the same seed give bit-identical
 * state hashes; (2) malformed and out-of-range messages are counted,
 * ignored, and do not move an arm. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "harness.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_health_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

static void ignore(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
}

/* One lockstep run of 2000 steps: the simulator's state hash, and how
 * many times it renewed its LCM handle (*renewals). flood: beside it a
 * flood of new channel names (tandem-flood --random-channels) and a bound
 * of 1 MB on what they may cost (TANDEM_NAMES_SLACK_KB), so that the
 * simulator and both arms renew their handles during the run. */
static unsigned long long run_and_hash(int seed, int offset, int flood, long *renewals)
{
    harness h;
    char seed_s[16], out[4096];
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "2", "--steps",
                          "2000",       "--seed",     seed_s,     NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", "--lockstep", NULL };
    const char *names[] = { "tandem-flood",      "--kind", "junk",
                            "--random-channels", "--rate", "30000",
                            "--duration",        "120",    NULL };
    pid_t ps;
    char *p;
    unsigned long long hash = 0;
    snprintf(seed_s, sizeof seed_s, "%d", seed);
    assert_int_equal(harness_open(&h, offset), 0);
    if (flood) {
        setenv("TANDEM_NAMES_SLACK_KB", "1024", 1);
        assert_true(harness_spawn(&h, names) > 0);
    }
    /* the participants' answers, read as a rover reads them: the
     * simulator answers nobody, so none may come signed by it */
    assert_non_null(auth_bus_subscribe(&h.bus, h.lcm, "SIM_ACK", ignore, NULL));
    ps = harness_spawn(&h, sim);
    assert_true(harness_spawn(&h, arm1) > 0);
    assert_true(harness_spawn(&h, arm2) > 0);
    unsetenv("TANDEM_NAMES_SLACK_KB");
    /* 2000 steps take seconds; under the sanitizers on a loaded machine
     * the flood's renewals (every MB of the quarantine's growth) made it
     * 133 s, so the wait outlasts the flood (120 s), after which the run
     * goes on at full speed: the check is the state hash, not the time */
    assert_int_equal(harness_wait(&h, ps, 300.0), 0);
    harness_read_output(&h, ps, out, sizeof out);
    p = strstr(out, "state_hash=");
    assert_non_null(p);
    assert_true(strstr(out, "stopped at step 2000") != NULL);
    harness_pump(&h, 300); /* what the simulator sent as it stopped */
    assert_int_equal(auth_bus_counts_get(&h.bus)->unauthorised, 0);
    hash = strtoull(p + strlen("state_hash="), NULL, 16);
    p = strstr(out, "lcm_renewals=");
    assert_non_null(p);
    *renewals = strtol(p + strlen("lcm_renewals="), NULL, 10);
    harness_close(&h);
    return hash;
}

static void test_same_seed_same_state(void **state)
{
    unsigned long long a, b;
    long ra, rb;
    (void)state;
    a = run_and_hash(7, 1, 0, &ra);
    b = run_and_hash(7, 2, 0, &rb);
    printf("state hashes: %016llx %016llx\n", a, b);
    assert_true(a != 0);
    assert_true(a == b);
    assert_int_equal(ra, 0);
}

/* A flood of channel names makes the simulator (and the arms) renew
 * their LCM handles in the middle of the run (daemon_names_watch): the
 * run must end exactly as without it. Fails if the simulator keeps its
 * handle (no renewal), or if a renewal loses a subscription (the run
 * stalls or ends elsewhere) or latches a command. */
static void test_renewed_handles_same_state(void **state)
{
    unsigned long long a, b;
    long ra, rb;
    (void)state;
    a = run_and_hash(7, 3, 0, &ra);
    b = run_and_hash(7, 4, 1, &rb);
    printf(
        "state hashes: %016llx, under a flood of names %016llx (%ld renewals of the simulator's handle)\n",
        a, b, rb);
    assert_true(a == b);
    assert_true(rb >= 1);
}

/* ---- bad input ------------------------------------------------------------ */

typedef struct watch {
    tandem_sim_status_t status;
    int have_status;
    long long arm1_rejected;
    double q_first[6], q_last[6];
    int have_q;
    int64_t last_step;
} watch;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *m,
                      void *u)
{
    watch *w = u;
    (void)rb;
    (void)ch;
    w->status = *m;
    w->have_status = 1;
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    watch *w = u;
    (void)rb;
    (void)ch;
    w->arm1_rejected = m->msgs_rejected;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    watch *w = u;
    (void)rb;
    (void)ch;
    if (!w->have_q)
        memcpy(w->q_first, m->q_rad, sizeof w->q_first);
    memcpy(w->q_last, m->q_rad, sizeof w->q_last);
    w->have_q = 1;
    w->last_step = m->step;
}

static void publish_bad_inputs(harness *h)
{
    tandem_arm_command_t c;
    tandem_arm_state_t s;
    tandem_sim_control_t sc;
    const char junk[] = "definitely not an LCM message";
    int i;
    /* 1: garbage bytes (fingerprint mismatch) to the sim and to the controller */
    auth_bus_publish_raw(&h->bus, h->lcm, "ARM1_COMMAND", junk, (int)sizeof junk);
    auth_bus_publish_raw(&h->bus, h->lcm, "ARM1_STATE", junk, (int)sizeof junk);
    auth_bus_publish_raw(&h->bus, h->lcm, "SIM_CONTROL", junk, 4);
    /* 2: a command with a NaN torque */
    memset(&c, 0, sizeof c);
    c.arm = 1;
    c.step = 1000000;
    c.tau_Nm[2] = NAN;
    AUTH_PUBLISH(tandem_arm_command_t, &h->bus, h->lcm, "ARM1_COMMAND", &c);
    /* 3: torques far beyond the motor limits */
    c.tau_Nm[2] = 0.0;
    for (i = 0; i < 6; i++)
        c.tau_Nm[i] = 1e6;
    AUTH_PUBLISH(tandem_arm_command_t, &h->bus, h->lcm, "ARM1_COMMAND", &c);
    /* 4: the wrong arm id on arm 1's channel */
    memset(&c, 0, sizeof c);
    c.arm = 2;
    c.step = 1000000;
    AUTH_PUBLISH(tandem_arm_command_t, &h->bus, h->lcm, "ARM1_COMMAND", &c);
    /* 5: an unknown mode */
    c.arm = 1;
    c.mode = 42;
    AUTH_PUBLISH(tandem_arm_command_t, &h->bus, h->lcm, "ARM1_COMMAND", &c);
    /* 6: a state with NaN joints to the controller */
    memset(&s, 0, sizeof s);
    s.arm = 1;
    s.step = 1000000;
    s.q_rad[0] = NAN;
    AUTH_PUBLISH(tandem_arm_state_t, &h->bus, h->lcm, "ARM1_STATE", &s);
    /* 7: an out-of-range simulator command */
    memset(&sc, 0, sizeof sc);
    sc.command = 99;
    AUTH_PUBLISH(tandem_sim_control_t, &h->bus, h->lcm, "SIM_CONTROL", &sc);
}

static void test_bad_messages_counted_and_ignored(void **state)
{
    harness h;
    watch w;
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "2", "--steps", "6000", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", "--lockstep", NULL };
    tandem_sim_status_t_subscription_t *s_status;
    tandem_health_t_subscription_t *s_health;
    tandem_arm_state_t_subscription_t *s_state;
    pid_t ps;
    int i;
    double drift = 0.0;
    (void)state;
    memset(&w, 0, sizeof w);
    assert_int_equal(harness_open(&h, 3), 0);
    s_status = tandem_sim_status_t_subscribe(h.lcm, "SIM_STATUS", on_status, &w);
    s_health = tandem_health_t_subscribe(h.lcm, "HEALTH_TANDEM_ARM_1", on_health, &w);
    s_state = tandem_arm_state_t_subscribe(h.lcm, "ARM1_STATE", on_state, &w);
    ps = harness_spawn(&h, sim);
    harness_spawn(&h, arm1);
    harness_spawn(&h, arm2);
    /* let the arms settle, then inject */
    for (i = 0; i < 200 && w.last_step < 1000; i++)
        harness_pump(&h, 20);
    assert_true(w.last_step >= 1000);
    memcpy(w.q_first, w.q_last, sizeof w.q_first);
    publish_bad_inputs(&h);
    assert_int_equal(harness_wait(&h, ps, 60.0), 0);
    harness_pump(&h, 1200); /* the arm's next health message */
    assert_true(w.have_status);
    printf("sim rejected %lld, arm 1 rejected %lld\n", (long long)w.status.msgs_rejected,
           w.arm1_rejected);
    /* sim: 2 garbage + NaN + huge + wrong arm + bad mode + bad control = 7 */
    assert_true(w.status.msgs_rejected >= 7);
    /* controller: garbage + NaN state = 2 */
    assert_true(w.arm1_rejected >= 2);
    for (i = 0; i < 6; i++)
        drift = fmax(drift, fabs(w.q_last[i] - w.q_first[i]));
    printf("arm 1 joint drift after bad input: %.2e rad\n", drift);
    assert_true(drift < 1e-3);
    tandem_sim_status_t_unsubscribe(h.lcm, s_status);
    tandem_health_t_unsubscribe(h.lcm, s_health);
    tandem_arm_state_t_unsubscribe(h.lcm, s_state);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_seed_same_state),
        cmocka_unit_test(test_renewed_handles_same_state),
        cmocka_unit_test(test_bad_messages_counted_and_ignored),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

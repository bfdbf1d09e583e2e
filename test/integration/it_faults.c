/* Integration: one message must not take over an arm. tandem-sim and both
 * arm controllers run in lockstep on a real udpm bus (in a network
 * namespace of their own when permitted); after the arms settle the test
 * sends what used to latch them:
 *   - ARM2_COMMAND with step = INT64_MAX and 40 N m on joint 1 (under the
 *     simulator's 2x-motor-limit plausibility bound),
 *   - ARM1_STATE with step = INT64_MAX and otherwise valid numbers,
 *   - an ARM1_ACTION row with NaN speeds and gains (a 0.6 rad joint move),
 *   - an ARM2_JOINT_REF 0.8 rad away from the idle arm,
 *   - messages whose array or string lengths are negative or huge (they
 *     made lcm-gen's decoder ask for huge allocations).
 * Each must be counted as rejected, move no arm (joint drift < 1e-3 rad)
 * and latch nothing: arm 1 never reports safe hold and does not go on
 * rejecting the real states after the forged one. */
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
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_joint_ref_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_health_t.h"
#include "tandem_sim_status_t.h"
#include "tandem_wire_types.h"

#define NAN_ROW_ID 4242

typedef struct watch {
    tandem_arm_state_t last[2];
    int have[2];
    double q_at_inject[2][6];
    double drift[2];
    int injected;
    long long sim_rejected, sim_stale_commands;
    long long arm_rejected[2];
    int health_after[2], safe_hold_after[2];
    int rejected_event;
    int arm1_state_channel; /* ARM1_STATE listed in arm 1's health, received > 0 */
} watch;

static watch W;

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    const int k = m->arm - 1;
    int i;
    (void)rb;
    (void)ch;
    (void)u;
    if (k < 0 || k > 1 || m->step > 100000000)
        return; /* the forged one */
    W.last[k] = *m;
    W.have[k] = 1;
    if (W.injected)
        for (i = 0; i < 6; i++)
            W.drift[k] = fmax(W.drift[k], fabs(m->q_rad[i] - W.q_at_inject[k][i]));
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *m,
                      void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    W.sim_rejected = m->msgs_rejected;
    W.sim_stale_commands = m->stale_commands;
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    const int k = strcmp(ch, "HEALTH_TANDEM_ARM_1") == 0 ? 0 : 1;
    int i;
    (void)rb;
    (void)u;
    W.arm_rejected[k] = m->msgs_rejected;
    if (W.injected) {
        W.health_after[k]++;
        W.safe_hold_after[k] += m->safe_hold;
    }
    for (i = 0; k == 0 && i < m->n_channels; i++)
        if (strcmp(m->channel[i], "ARM1_STATE") == 0 && m->channel_received[i] > 0)
            W.arm1_state_channel = 1;
}

/* Checked subscription (auth_bus_subscribe: authentication, then the
 * wire check): the test itself receives the malformed ARM_EVENTS it sends,
 * and lcm-gen's decoder would crash. */
static void on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_action_event_t m;
    (void)ch;
    (void)u;
    if (wire_check(&wire_t_tandem_action_event_t, rb->data, rb->data_size) != WIRE_OK ||
        tandem_action_event_t_decode(rb->data, 0, (int)rb->data_size, &m) < 0)
        return;
    if (m.action_id == NAN_ROW_ID && m.event == TANDEM_ACTION_EVENT_T_REJECTED)
        W.rejected_event = 1;
    tandem_action_event_t_decode_cleanup(&m);
}

static void send_forged_steps(harness *h)
{
    tandem_arm_command_t c;
    tandem_arm_state_t s = W.last[0];
    memset(&c, 0, sizeof c);
    c.arm = 2;
    c.step = INT64_MAX;
    c.mode = TANDEM_ARM_COMMAND_T_MODE_TORQUE;
    c.tau_Nm[0] = 40.0;
    AUTH_PUBLISH(tandem_arm_command_t, &h->bus, h->lcm, "ARM2_COMMAND", &c);
    s.step = INT64_MAX;
    AUTH_PUBLISH(tandem_arm_state_t, &h->bus, h->lcm, "ARM1_STATE", &s);
}

static void send_nan_row(harness *h)
{
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
    seg.orientation_quat[0] = 1.0;
    memcpy(seg.q_rad, W.last[0].q_rad, sizeof seg.q_rad);
    seg.q_rad[0] += 0.6;
    row.action_id = NAN_ROW_ID;
    row.transition = 1;
    row.arm = 1;
    row.v_m = row.a_m = row.u_m = NAN;
    row.k_p = row.k_v = row.k0 = NAN;
    row.n_segments = 1;
    row.segments = &seg;
    AUTH_PUBLISH(tandem_action_row_t, &h->bus, h->lcm, "ARM1_ACTION", &row);
}

static void send_far_joint_ref(harness *h)
{
    tandem_arm_joint_ref_t r;
    memset(&r, 0, sizeof r);
    r.arm = 2;
    r.step = W.last[1].step;
    memcpy(r.q_rad, W.last[1].q_rad, sizeof r.q_rad);
    r.q_rad[0] += 0.8;
    AUTH_PUBLISH(tandem_arm_joint_ref_t, &h->bus, h->lcm, "ARM2_JOINT_REF", &r);
}

/* Encodes a valid message, then overwrites a length field with `bad`
 * (big-endian, `size` bytes at `offset`) and publishes the bytes. */
static void publish_patched(harness *h, const char *ch, uint8_t *buf, int len, int offset, int size,
                            int64_t bad)
{
    int i;
    for (i = 0; i < size; i++)
        buf[offset + i] = (uint8_t)((uint64_t)bad >> (8 * (size - 1 - i)));
    auth_bus_publish_raw(&h->bus, h->lcm, ch, buf, len);
}

static void send_bad_lengths(harness *h)
{
    uint8_t buf[512];
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    tandem_clock_ack_t a;
    tandem_action_event_t e;
    int n;
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    row.arm = 1;
    row.n_segments = 1;
    row.segments = &seg;
    n = tandem_action_row_t_encode(buf, 0, sizeof buf, &row);
    /* n_segments follows 8 (hash) + 3x8 + 2x4 + 3x1 + 2x4 + 8x8 = 115 bytes */
    publish_patched(h, "ARM1_ACTION", buf, n, 115, 1, -128);
    memset(&a, 0, sizeof a);
    a.name = "x";
    a.period_steps = 1;
    n = tandem_clock_ack_t_encode(buf, 0, sizeof buf, &a);
    publish_patched(h, "SIM_ACK", buf, n, 32, 4, INT32_MAX); /* name's length */
    memset(&e, 0, sizeof e);
    e.detail = "";
    n = tandem_action_event_t_encode(buf, 0, sizeof buf, &e);
    publish_patched(h, "ARM_EVENTS", buf, n, 71, 4, -5); /* detail's length */
}

static void test_no_message_latches(void **state)
{
    harness h;
    const char *sim[] = { "tandem-sim", "--lockstep",   "--expect", "2", "--steps",
                          "14000",      "--timeout-ms", "30000",    NULL }; /* a loaded machine */
    const char *arm1[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", "--lockstep", NULL };
    pid_t ps;
    int i;
    long long rej0[2];
    tandem_arm_state_t_subscription_t *sub_state;
    tandem_sim_status_t_subscription_t *sub_status;
    tandem_health_t_subscription_t *sub_health;
    (void)state;
    memset(&W, 0, sizeof W);
    assert_int_equal(harness_open(&h, 5), 0);
    sub_state = tandem_arm_state_t_subscribe(h.lcm, "ARM[12]_STATE", on_state, NULL);
    sub_status = tandem_sim_status_t_subscribe(h.lcm, "SIM_STATUS", on_status, NULL);
    sub_health = tandem_health_t_subscribe(h.lcm, "HEALTH_TANDEM_ARM_[12]", on_health, NULL);
    auth_bus_subscribe(&h.bus, h.lcm, "ARM_EVENTS", on_event, NULL);
    ps = harness_spawn(&h, sim);
    assert_true(harness_spawn(&h, arm1) > 0);
    assert_true(harness_spawn(&h, arm2) > 0);
    for (i = 0; i < 500 && !(W.have[0] && W.have[1] && W.last[0].step >= 1500); i++)
        harness_pump(&h, 20);
    assert_true(W.last[0].step >= 1500);
    harness_pump(&h, 1100); /* a health message before the injection */
    rej0[0] = W.arm_rejected[0];
    rej0[1] = W.arm_rejected[1];
    memcpy(W.q_at_inject[0], W.last[0].q_rad, sizeof W.q_at_inject[0]);
    memcpy(W.q_at_inject[1], W.last[1].q_rad, sizeof W.q_at_inject[1]);
    W.injected = 1;
    send_forged_steps(&h);
    send_nan_row(&h);
    send_far_joint_ref(&h);
    send_bad_lengths(&h);
    assert_int_equal(harness_wait(&h, ps, 120.0), 0);
    harness_pump(&h, 300);
    printf(
        "drift arm 1 %.2e rad, arm 2 %.2e rad; rejected: sim %lld, arm 1 %lld (+%lld), arm 2 %lld (+%lld); "
        "stale commands %lld; health after: %d, %d (safe hold %d, %d)\n",
        W.drift[0], W.drift[1], W.sim_rejected, W.arm_rejected[0], W.arm_rejected[0] - rej0[0],
        W.arm_rejected[1], W.arm_rejected[1] - rej0[1], W.sim_stale_commands, W.health_after[0],
        W.health_after[1], W.safe_hold_after[0], W.safe_hold_after[1]);
    assert_true(W.drift[0] < 1e-3);
    assert_true(W.drift[1] < 1e-3);
    /* sim: the forged command and the malformed ack */
    assert_true(W.sim_rejected >= 2);
    /* arm 1: forged state, NaN row, malformed row, malformed event; and it
     * does not go on rejecting the real states (1000 a second when latched) */
    assert_true(W.arm_rejected[0] - rej0[0] >= 4);
    assert_true(W.arm_rejected[0] - rej0[0] < 20);
    assert_true(W.arm_rejected[1] - rej0[1] >= 1); /* the far joint reference */
    assert_true(W.rejected_event);
    assert_true(W.health_after[0] >= 1);
    assert_int_equal(W.safe_hold_after[0], 0);
    assert_true(W.arm1_state_channel);
    /* the typed subscriptions own their handles: give them back (the
     * sanitizer build's leak check) */
    tandem_arm_state_t_unsubscribe(h.lcm, sub_state);
    tandem_sim_status_t_unsubscribe(h.lcm, sub_status);
    tandem_health_t_unsubscribe(h.lcm, sub_health);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_message_latches),
    };
    if (harness_private_net() != 0)
        printf("it_faults: no private network namespace; using a private port on the shared one\n");
    return cmocka_run_group_tests(tests, NULL, NULL);
}

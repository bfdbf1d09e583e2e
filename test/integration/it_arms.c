/* Integration: the PUMA pair in tandem-sim against the dynamics core and
 * under tandem-arm, over udpm in lockstep (this test is a participant, so
 * it sees every step and acts at exact steps).
 *  1. Model vs simulator: RNE torques of a smooth 2 s joint trajectory fed
 *     open loop (no feedback) into the ODE arm track it within 1 degree.
 *  2. Both arms hold their pose under gravity within 0.1 mm for 10 s.
 *  3. Both arms move home -> hand-over pose -> home under tandem-arm. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "arm_dyn.h"
#include "arm_kin.h"
#include "cell.h"
#include "jtraj.h"
#include "vec3.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_clock_t.h"

typedef struct obs {
    tandem_arm_state_t arm[2];
    int have[2];
    int64_t clock_step;
    int clock_new;
    int done[2];
} obs;

static obs O;
static tandem_arm_state_t_subscription_t *sub_state[2];
static tandem_sim_clock_t_subscription_t *sub_clock;
static tandem_action_event_t_subscription_t *sub_event;

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (m->arm == 1 || m->arm == 2) {
        O.arm[m->arm - 1] = *m;
        O.have[m->arm - 1] = 1;
    }
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_clock_t *m, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    O.clock_step = m->step;
    O.clock_new = 1;
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, const tandem_action_event_t *m,
                     void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (m->event == TANDEM_ACTION_EVENT_T_DONE && (m->arm == 1 || m->arm == 2))
        O.done[m->arm - 1] = 1;
}

/* Waits for the next SIM_CLOCK; returns its step or -1 on timeout. */
static int64_t next_step(harness *h)
{
    int i;
    O.clock_new = 0;
    for (i = 0; i < 500 && !O.clock_new; i++)
        lcm_handle_timeout(h->lcm, 10);
    return O.clock_new ? O.clock_step : -1;
}

static void subscribe_all(harness *h)
{
    memset(&O, 0, sizeof O);
    sub_state[0] = tandem_arm_state_t_subscribe(h->lcm, "ARM1_STATE", on_state, NULL);
    sub_state[1] = tandem_arm_state_t_subscribe(h->lcm, "ARM2_STATE", on_state, NULL);
    sub_clock = tandem_sim_clock_t_subscribe(h->lcm, "SIM_CLOCK", on_clock, NULL);
    sub_event = tandem_action_event_t_subscribe(h->lcm, "ARM_EVENTS", on_event, NULL);
}

static void close_all(harness *h)
{
    tandem_arm_state_t_unsubscribe(h->lcm, sub_state[0]);
    tandem_arm_state_t_unsubscribe(h->lcm, sub_state[1]);
    tandem_sim_clock_t_unsubscribe(h->lcm, sub_clock);
    tandem_action_event_t_unsubscribe(h->lcm, sub_event);
    harness_close(h);
}

static void test_rne_open_loop_tracks_within_1deg(void **state)
{
    harness h;
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "1", NULL };
    const double dq[6] = { 0.4, -0.25, 0.3, 0.5, 0.35, 0.6 };
    double q1[6], err_max = 0.0;
    jtraj tr;
    int64_t k;
    int i;
    (void)state;
    assert_int_equal(harness_open(&h, 11), 0);
    subscribe_all(&h);
    harness_spawn(&h, sim);
    /* join at step 0: answer it once the home state is known */
    for (i = 0; i < 100 && !O.have[0]; i++)
        harness_pump(&h, 20);
    assert_true(O.have[0]);
    for (i = 0; i < 6; i++)
        q1[i] = O.arm[0].q_rad[i] + dq[i];
    assert_int_equal(jtraj_plan(&tr, &arm_model_puma560, O.arm[0].q_rad, q1, 1.0, 100.0), 0);
    tr.duration_s = 2.0;
    for (k = 0; k <= 2000;) {
        double qd_[6], qd[6], qdd[6], tau[6];
        tandem_arm_command_t c;
        const double t = (double)k * 1e-3;
        jtraj_at(&tr, t, qd_, qd, qdd);
        for (i = 0; i < 6; i++)
            err_max = fmax(err_max, fabs(O.arm[0].q_rad[i] - qd_[i]));
        /* the torque held over [k, k+1]: the trajectory's at mid-step */
        jtraj_at(&tr, t + 0.5e-3, qd_, qd, qdd);
        assert_int_equal(arm_rne(&arm_model_puma560, qd_, qd, qdd, NULL, NULL, tau), 0);
        memset(&c, 0, sizeof c);
        c.arm = 1;
        c.step = k;
        c.mode = TANDEM_ARM_COMMAND_T_MODE_TORQUE;
        memcpy(c.tau_Nm, tau, sizeof tau);
        AUTH_PUBLISH(tandem_arm_command_t, &h.bus, h.lcm, "ARM1_COMMAND", &c);
        harness_ack(&h, "it_arms", k, 1);
        k = next_step(&h);
        assert_true(k >= 0);
    }
    printf("open-loop RNE torques vs ODE arm: max joint error over 2 s = %.4f deg\n",
           err_max * 57.29577951308232);
    assert_true(err_max * 57.29577951308232 < 1.0);
    close_all(&h);
}

static void handover_q(int a, const double q_home[6], double q[6])
{
    double Tw[16], Tinv[16], pw[3], p[3], R[9], T[16];
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    arm_tool tool;
    arm_ik_result r;
    int b;
    arm_tool_offset(&tool, off);
    cell_grasp_point(&cell_default, a, cell_default.handover_center_m, pw);
    cell_world_from_arm(&cell_default, a, Tw);
    tf_inverse(Tinv, Tw);
    tf_apply(p, Tinv, pw);
    cell_tool_down_R(&cell_default, a, R);
    tf_from_rot_pos(T, R, p);
    assert_int_equal(arm_ik(&arm_model_puma560, &tool, T, &r), 0);
    b = arm_ik_nearest(&r, q_home);
    assert_true(b >= 0);
    memcpy(q, r.branch[b].q_rad, sizeof(double) * 6);
}

static double dist3(const double a[3], const double b[3])
{
    double d[3];
    vec3_sub(d, a, b);
    return vec3_norm(d);
}

/* Steps until both arms reported DONE (or the limit); returns steps taken. */
static int64_t run_until_done(harness *h, int64_t k, int64_t limit)
{
    const int64_t k0 = k;
    O.done[0] = O.done[1] = 0;
    while (k - k0 < limit && !(O.done[0] && O.done[1])) {
        harness_ack(h, "it_arms", k, 1);
        k = next_step(h);
        assert_true(k >= 0);
    }
    return k;
}

static void test_hold_and_move_under_tandem_arm(void **state)
{
    harness h;
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "3", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", "--lockstep", NULL };
    double p0[2][3], drift = 0.0, q_home[2][6], q_ho[2][6], target[2][3];
    int64_t k;
    int a, i;
    (void)state;
    assert_int_equal(harness_open(&h, 12), 0);
    subscribe_all(&h);
    harness_spawn(&h, sim);
    harness_spawn(&h, arm1);
    harness_spawn(&h, arm2);
    for (i = 0; i < 100 && !(O.have[0] && O.have[1]); i++)
        harness_pump(&h, 20);
    assert_true(O.have[0] && O.have[1]);
    for (a = 0; a < 2; a++) {
        memcpy(p0[a], O.arm[a].tool_position_m, sizeof p0[a]);
        memcpy(q_home[a], O.arm[a].q_rad, sizeof q_home[a]);
    }
    /* 10 s of holding under gravity */
    for (k = 0; k < 10000;) {
        harness_ack(&h, "it_arms", k, 1);
        k = next_step(&h);
        assert_true(k >= 0);
        for (a = 0; a < 2; a++)
            drift = fmax(drift, dist3(O.arm[a].tool_position_m, p0[a]));
    }
    printf("hold under gravity, 10 s: max tool drift %.3e mm\n", drift * 1e3);
    assert_true(drift < 1e-4);

    /* home -> hand-over -> home */
    for (a = 0; a < 2; a++) {
        handover_q(a, q_home[a], q_ho[a]);
        cell_grasp_point(&cell_default, a, cell_default.handover_center_m, target[a]);
        harness_send_joint_row(&h, a + 1, 100 + a, q_ho[a]);
    }
    k = run_until_done(&h, k, 20000);
    assert_true(O.done[0] && O.done[1]);
    for (a = 0; a < 2; a++) {
        const double e = dist3(O.arm[a].tool_position_m, target[a]);
        printf("arm %d at the hand-over pose: tool error %.2f mm\n", a + 1, e * 1e3);
        assert_true(e < 2e-3);
        harness_send_joint_row(&h, a + 1, 200 + a, q_home[a]);
    }
    k = run_until_done(&h, k, 20000);
    assert_true(O.done[0] && O.done[1]);
    for (a = 0; a < 2; a++) {
        const double e = dist3(O.arm[a].tool_position_m, p0[a]);
        printf("arm %d back home: tool error %.2f mm\n", a + 1, e * 1e3);
        assert_true(e < 2e-3);
    }
    close_all(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rne_open_loop_tracks_within_1deg),
        cmocka_unit_test(test_hold_and_move_under_tandem_arm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

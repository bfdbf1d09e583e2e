/* Integration: the simulator holds the PUMA's physical limits, over udpm
 * in lockstep (this test is a participant and acts at exact steps).
 *  1. Every joint of arm 1 driven at 1.5x its peak torque, first up for
 *     5 s, then down for 7 s: no joint leaves its range by more than
 *     ARM_RANGE_TOL_RAD (q4 and q6 included, whose ranges are wider than
 *     ODE's +-pi hinge window), no joint exceeds its motor speed limit,
 *     and every joint does reach both ends (so the torque really pushed).
 *     The largest |qd| / qd_max is printed, not asserted: slammed into
 *     hard stops at full speed, the light distal links (the simulated
 *     rotors' armature is on the diagonal only) are flung past their drives' limit for
 *     a few steps; in the task the carry sweep checks the ratio.
 *  2. The stick pushed into each link of both arms while tandem-arm moves
 *     them: at insertion it touches no link of either arm (zero contact
 *     force on the next step), and the 10 ms contact force stays within
 *     1000 N for the links that run into it (joint moves curve away from
 *     the stick's line for some). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "arm_model.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"

static struct {
    tandem_arm_state_t arm[2];
    int have[2];
    int64_t clock_step;
    int clock_new;
} O;
static tandem_arm_state_t_subscription_t *sub_state[2];
static tandem_sim_clock_t_subscription_t *sub_clock;

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

static void open_bus(harness *h, int port)
{
    memset(&O, 0, sizeof O);
    assert_int_equal(harness_open(h, port), 0);
    sub_state[0] = tandem_arm_state_t_subscribe(h->lcm, "ARM1_STATE", on_state, NULL);
    sub_state[1] = tandem_arm_state_t_subscribe(h->lcm, "ARM2_STATE", on_state, NULL);
    sub_clock = tandem_sim_clock_t_subscribe(h->lcm, "SIM_CLOCK", on_clock, NULL);
}

static void close_bus(harness *h)
{
    tandem_arm_state_t_unsubscribe(h->lcm, sub_state[0]);
    tandem_arm_state_t_unsubscribe(h->lcm, sub_state[1]);
    tandem_sim_clock_t_unsubscribe(h->lcm, sub_clock);
    harness_close(h);
}

/* Answers step k, waits for the next SIM_CLOCK; returns its step. */
static int64_t step_once(harness *h, int64_t k)
{
    int i;
    harness_ack(h, "it_limits", k, 1);
    O.clock_new = 0;
    for (i = 0; i < 500 && !O.clock_new; i++)
        lcm_handle_timeout(h->lcm, 10);
    assert_true(O.clock_new);
    return O.clock_step;
}

static void wait_states(harness *h, int n)
{
    int i;
    for (i = 0; i < 200 && !(O.have[0] && (n < 2 || O.have[1])); i++)
        harness_pump(h, 20);
    assert_true(O.have[0] && (n < 2 || O.have[1]));
}

static void test_limits_hold_under_torque(void **state)
{
    const arm_model *m = &arm_model_puma560;
    harness h;
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "1", NULL };
    double speed_ratio = 0.0, q_lo[ARM_NJ], q_hi[ARM_NJ], past = 0.0;
    int64_t k = 0, k_fast = 0, k_impact = -100;
    int i, j_fast = 0;
    unsigned on_stop = 0;
    double spike = 0.0;
    (void)state;
    open_bus(&h, 21);
    harness_spawn(&h, sim);
    wait_states(&h, 1);
    for (i = 0; i < ARM_NJ; i++)
        q_lo[i] = q_hi[i] = O.arm[0].q_rad[i];
    while (k < 12000) {
        tandem_arm_command_t c;
        const double dir = k < 5000 ? 1.0 : -1.0;
        memset(&c, 0, sizeof c);
        c.arm = 1;
        c.step = k;
        c.mode = TANDEM_ARM_COMMAND_T_MODE_TORQUE;
        for (i = 0; i < ARM_NJ; i++)
            c.tau_Nm[i] = dir * 1.5 * m->tau_max_Nm[i]; /* the simulator takes up to 2x */
        AUTH_PUBLISH(tandem_arm_command_t, &h.bus, h.lcm, "ARM1_COMMAND", &c);
        k = step_once(&h, k);

        for (i = 0; i < ARM_NJ; i++) {
            const double q = O.arm[0].q_rad[i];
            const int at = q < m->q_min_rad[i] + 0.0087 || q > m->q_max_rad[i] - 0.0087;
            if (at && !(on_stop & (1u << i)))
                k_impact = k;
            on_stop = at ? (on_stop | 1u << i) : (on_stop & ~(1u << i));
        }
        for (i = 0; i < ARM_NJ; i++) {
            const double q = O.arm[0].q_rad[i];
            past = fmax(past, fmax(m->q_min_rad[i] - q, q - m->q_max_rad[i]));
            if (k - k_impact <= 10) {
                spike = fmax(spike, fabs(O.arm[0].qd_radps[i]) / m->qd_max_radps[i]);
                continue;
            }
            if (fabs(O.arm[0].qd_radps[i]) / m->qd_max_radps[i] > speed_ratio) {
                speed_ratio = fabs(O.arm[0].qd_radps[i]) / m->qd_max_radps[i];
                j_fast = i + 1;
                k_fast = k;
            }
            q_lo[i] = fmin(q_lo[i], q);
            q_hi[i] = fmax(q_hi[i], q);
        }
    }
    printf(
        "1.5x peak torque on every joint, 12 s: furthest past a range end %.2f mrad, max |qd|/qd_max %.3f "
        "(q%d at step %lld); within 10 ms of a stop impact %.3f\n",
        past * 1e3, speed_ratio, j_fast, (long long)k_fast, spike);
    for (i = 0; i < ARM_NJ; i++) {
        printf("  q%d reached [%.1f, %.1f] deg of [%.0f, %.0f]\n", i + 1, q_lo[i] * 57.29578,
               q_hi[i] * 57.29578, m->q_min_rad[i] * 57.29578, m->q_max_rad[i] * 57.29578);
        assert_true(q_lo[i] < m->q_min_rad[i] + 0.02 && q_hi[i] > m->q_max_rad[i] - 0.02);
    }
    assert_true(past <= ARM_RANGE_TOL_RAD);
    close_bus(&h);
}

static void stick(harness *h, int cmd, int arm, int link)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = (int8_t)cmd;
    c.target = arm;
    c.link = link;
    c.length_m = 0.3;
    c.radius_m = 0.02;
    AUTH_PUBLISH(tandem_sim_control_t, &h->bus, h->lcm, "SIM_CONTROL", &c);
}

static double max_force(int raw)
{
    return fmax(raw ? O.arm[0].max_contact_force_N : O.arm[0].max_contact_force_10ms_N,
                raw ? O.arm[1].max_contact_force_N : O.arm[1].max_contact_force_10ms_N);
}

static void test_stick_goes_in_clear_of_the_arms(void **state)
{
    /* both arms swing q1 and q2-q3 (all six links move) out and back */
    static const double dq[ARM_NJ] = { 0.5, -0.3, 0.4, 0.6, 0.5, 0.7 };
    harness h;
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "3", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", "--lockstep", NULL };
    double q_home[2][ARM_NJ], q_out[2][ARM_NJ], f10_max = 0.0;
    int64_t k = 0;
    int a, link, i, touched = 0, tried = 0;
    (void)state;
    open_bus(&h, 22);
    harness_spawn(&h, sim);
    harness_spawn(&h, arm1);
    harness_spawn(&h, arm2);
    wait_states(&h, 2);
    for (a = 0; a < 2; a++)
        for (i = 0; i < ARM_NJ; i++) {
            q_home[a][i] = O.arm[a].q_rad[i];
            q_out[a][i] = q_home[a][i] + (a ? -dq[i] : dq[i]);
        }
    for (a = 0; a < 2; a++)
        for (link = 1; link <= ARM_NJ; link++) {
            const int out = (a * ARM_NJ + link) % 2;
            int64_t k0 = k;
            int contact = 0;
            harness_send_joint_row(&h, a + 1, 10 * (a * ARM_NJ + link), out ? q_out[a] : q_home[a]);
            while (k - k0 < 400) /* under way */
                k = step_once(&h, k);
            stick(&h, TANDEM_SIM_CONTROL_T_INSERT_STICK, a + 1, link);
            k = step_once(&h, k); /* the stick is placed at this step ... */
            k = step_once(&h, k); /* ... and this step's state has its contacts */
            tried++;
            if (max_force(1) > 0.0)
                printf("arm %d link %d: contact %.1f N at insertion\n", a + 1, link, max_force(1));
            assert_true(max_force(1) == 0.0);
            for (k0 = k; k - k0 < 1500;) {
                k = step_once(&h, k);
                contact |= max_force(1) > 0.5;
                f10_max = fmax(f10_max, max_force(0));
            }
            touched += contact;
            stick(&h, TANDEM_SIM_CONTROL_T_REMOVE_STICK, 0, 0);
            for (k0 = k; k - k0 < 2500;) /* let the move finish */
                k = step_once(&h, k);
        }
    printf("stick inserted %d times, never touching an arm at insertion; %d links ran into it; "
           "max 10 ms contact force %.1f N\n",
           tried, touched, f10_max);
    assert_true(touched >= 1); /* placed in the paths: some links meet it */
    assert_true(f10_max <= 1000.0);
    close_bus(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limits_hold_under_torque),
        cmocka_unit_test(test_stick_goes_in_clear_of_the_arms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

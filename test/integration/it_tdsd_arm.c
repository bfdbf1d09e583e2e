/* Integration : tandem-arm executes a use_tdsd Cartesian action row
 * on the simulated PUMA 560 (tandem-sim, lockstep; this test is a
 * participant and sees every step). The line is the wrist line of
 * test_tdsd_seg: radially inwards 0.20 m, tool down tilted 3 deg sideways,
 * so the forearm passes ~3 deg from the tool axis (|q5| ~ 3 deg) and q4
 * swings ~155 deg (to ~162 deg, inside its 170 deg limit). Checks: DONE, the tool within 3 mm of the target, the
 * tool within a few mm of the straight line all the way, every measured
 * joint speed within its motor limit. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "arm_kin.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_clock_t.h"

#define DEG (3.14159265358979323846 / 180.0)

static struct {
    tandem_arm_state_t arm;
    int have;
    int64_t clock_step;
    int clock_new;
    int done, rejected;
} O;

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (m->arm == 1) {
        O.arm = *m;
        O.have = 1;
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
    if (m->arm != 1)
        return;
    if (m->event == TANDEM_ACTION_EVENT_T_DONE)
        O.done = 1;
    if (m->event == TANDEM_ACTION_EVENT_T_REJECTED)
        O.rejected = 1;
}

static int64_t next_step(harness *h)
{
    int i;
    O.clock_new = 0;
    for (i = 0; i < 500 && !O.clock_new; i++)
        lcm_handle_timeout(h->lcm, 10);
    return O.clock_new ? O.clock_step : -1;
}

/* Base-frame wrist line of test_tdsd_seg and its start joints. */
static void wrist_line(double A[3], double B[3], double R1[9], double q0[ARM_NJ])
{
    static const double R_down[9] = { 1, 0, 0, 0, -1, 0, 0, 0, -1 };
    static const double q_near_home[ARM_NJ] = { 1.67, 0.71, 2.86, 0.0, -0.42, -1.47 };
    const double ux = 0.1 / sqrt(0.26), uy = 0.5 / sqrt(0.26);
    const double r0 = sqrt(0.26) + 0.05, r1 = sqrt(0.26) - 0.15;
    const double radial[3] = { ux, uy, 0.0 }, off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    double Rt[9], T[16];
    arm_tool tool;
    arm_ik_result r;
    int b;
    vec3_set(A, ux * r0, uy * r0, 0.30);
    vec3_set(B, ux * r1, uy * r1, 0.30);
    rot_from_axis_angle(Rt, radial, 3.0 * DEG);
    rot_mul(R1, Rt, R_down);
    arm_tool_offset(&tool, off);
    tf_from_rot_pos(T, R1, A);
    assert_int_equal(arm_ik(&arm_model_puma560, &tool, T, &r), 0);
    b = arm_ik_nearest(&r, q_near_home);
    assert_true(b >= 0);
    memcpy(q0, r.branch[b].q_rad, sizeof(double) * ARM_NJ);
}

static void to_world(const double Tw[16], const double p[3], double out[3])
{
    tf_apply(out, Tw, p);
}

static double line_distance(const double p[3], const double A[3], const double B[3])
{
    double d[3], u[3], w[3], x[3];
    vec3_sub(d, B, A);
    vec3_normalize(u, d);
    vec3_sub(w, p, A);
    vec3_cross(x, w, u);
    return vec3_norm(x);
}

static void test_tdsd_row_near_wrist_singularity(void **state)
{
    harness h;
    tandem_arm_state_t_subscription_t *s_state;
    tandem_sim_clock_t_subscription_t *s_clock;
    tandem_action_event_t_subscription_t *s_event;
    char q0s[160];
    const char *sim[] = { "tandem-sim", "--lockstep", "--expect", "2", "--arm-q0", q0s, NULL };
    const char *arm[] = { "tandem-arm", "--arm", "1", "--lockstep", NULL };
    double A[3], B[3], R1[9], q0[ARM_NJ], Tw[16], Aw[3], Bw[3], Rw[9], Rwb[9], d[3];
    double max_ratio = 0.0, max_dev = 0.0, min_q5 = INFINITY, q4_lo = INFINITY, q4_hi = -INFINITY;
    int worst = 0, i;
    int64_t k, k_start, k_done = -1;
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    (void)state;
    wrist_line(A, B, R1, q0);
    cell_world_from_arm(&cell_default, 0, Tw);
    to_world(Tw, A, Aw);
    to_world(Tw, B, Bw);
    tf_rot(Rwb, Tw);
    rot_mul(Rw, Rwb, R1);
    snprintf(q0s, sizeof q0s, "%.9f,%.9f,%.9f,%.9f,%.9f,%.9f", q0[0], q0[1], q0[2], q0[3], q0[4],
             q0[5]);

    assert_int_equal(harness_open(&h, 31), 0);
    memset(&O, 0, sizeof O);
    s_state = tandem_arm_state_t_subscribe(h.lcm, "ARM1_STATE", on_state, NULL);
    s_clock = tandem_sim_clock_t_subscribe(h.lcm, "SIM_CLOCK", on_clock, NULL);
    s_event = tandem_action_event_t_subscribe(h.lcm, "ARM_EVENTS", on_event, NULL);
    harness_spawn(&h, sim);
    harness_spawn(&h, arm);
    for (i = 0; i < 100 && !O.have; i++)
        harness_pump(&h, 20);
    assert_true(O.have);
    /* 0.3 s hold for the servo to settle, then the row */
    for (k = 0; k < 300;) {
        harness_ack(&h, "it_tdsd_arm", k, 1);
        k = next_step(&h);
        assert_true(k >= 0);
    }
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN;
    vec3_copy(seg.position_m, Bw);
    rot_to_quat(seg.orientation_quat, Rw);
    row.action_id = 500;
    row.transition = 1;
    row.arm = 1;
    row.use_tdsd = 1;
    row.v_m = 0.25;
    row.a_m = 0.5;
    row.u_m = 4.0; /* carry_net's FREE row */
    row.k_p = 100.0;
    row.k_v = 20.0;
    row.k0 = 0.2;
    row.k1 = 5.0;
    row.k2 = 50.0;
    row.n_segments = 1;
    row.segments = &seg;
    AUTH_PUBLISH(tandem_action_row_t, &h.bus, h.lcm, "ARM1_ACTION", &row);
    k_start = k;
    while (k - k_start < 10000 && !O.done && !O.rejected) {
        harness_ack(&h, "it_tdsd_arm", k, 1);
        k = next_step(&h);
        assert_true(k >= 0);
        for (i = 0; i < ARM_NJ; i++) {
            const double r = fabs(O.arm.qd_radps[i]) / arm_model_puma560.qd_max_radps[i];
            if (r > max_ratio) {
                max_ratio = r;
                worst = i;
            }
        }
        max_dev = fmax(max_dev, line_distance(O.arm.tool_position_m, Aw, Bw));
        min_q5 = fmin(min_q5, fabs(O.arm.q_rad[4]));
        q4_lo = fmin(q4_lo, O.arm.q_rad[3]);
        q4_hi = fmax(q4_hi, O.arm.q_rad[3]);
        if (O.done && k_done < 0)
            k_done = k;
    }
    vec3_sub(d, O.arm.tool_position_m, Bw);
    printf("use_tdsd row on the ODE PUMA 560 (wrist line, tilt 3 deg): done %d after %.3f s, "
           "final tool error %.3f mm, max deviation from the line %.3f mm, min |q5| %.2f deg, "
           "q4 swept %.1f deg, max measured joint speed %.3f x limit (q%d)\n",
           O.done, (double)(k - k_start) * 1e-3, vec3_norm(d) * 1e3, max_dev * 1e3, min_q5 / DEG,
           (q4_hi - q4_lo) / DEG, max_ratio, worst + 1);
    tandem_arm_state_t_unsubscribe(h.lcm, s_state);
    tandem_sim_clock_t_unsubscribe(h.lcm, s_clock);
    tandem_action_event_t_unsubscribe(h.lcm, s_event);
    harness_close(&h); /* before the checks: a failed one would leave the children */
    assert_false(O.rejected);
    assert_true(O.done);
    assert_true(vec3_norm(d) < 3e-3);
    assert_true(max_dev < 5e-3);
    assert_true(min_q5 < 4.0 * DEG);
    assert_true((q4_hi - q4_lo) > 90.0 * DEG);
    assert_true(max_ratio <= 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tdsd_row_near_wrist_singularity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

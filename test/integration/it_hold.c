/* Integration: protective stops (docs/method/carry.md §7.4). tandem-arm,
 * in real time against tandem-sim, is frozen with SIGSTOP in the middle of
 * a joint move, an event-referenced Cartesian segment and a TDSD segment,
 * for 0.05, 0.5 and 2 s, and continued. While it is frozen the simulator
 * brakes the arm (its commands go stale); after SIGCONT the arm must take
 * the motion up again from where it stands, never faster than planned:
 *   - no joint faster than in the same move flown without a freeze
 *     (its planned speed, measured) by more than 10 %,
 *   - no joint torque at its limit,
 *   - the goal not overshot by more than the tracking tolerance,
 * and the row must still finish (DONE). On a time-referenced joint move
 * picked up where the clock says, joint 1 ran at its speed limit and
 * torque limit and overshot by 0.35 rad. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "harness.h"
#include "arm_kin.h"
#include "arm_model.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_state_t.h"

/* a joint at more than this share of its peak torque is "at its limit" */
#define TAU_LIMIT_SHARE 0.95
/* speed after the freeze, against the fastest before it */
#define SPEED_RATIO_MAX 1.10
/* the goal passed by more than this (joint: rad; tool: m) */
#define JOINT_OVERSHOOT_RAD 0.02
#define TOOL_OVERSHOOT_M 0.005

typedef enum { MOTION_JOINT, MOTION_CARTESIAN, MOTION_TDSD } motion;
static const char *const MOTION_NAMES[] = { "joint move", "Cartesian segment", "TDSD segment" };

static struct {
    tandem_arm_state_t st;
    int have;
    int done;
    int32_t done_id;
} O;

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (m->arm == 1) {
        O.st = *m;
        O.have = 1;
    }
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, const tandem_action_event_t *m,
                     void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    if (m->arm == 1 && m->event == TANDEM_ACTION_EVENT_T_DONE) {
        O.done = 1;
        O.done_id = m->action_id;
    }
}

/* What one run saw, before and after the freeze. */
typedef struct {
    double qd_before[ARM_NJ], qd_after[ARM_NJ];
    double tau_share_max; /* max |tau| / tau_max after the freeze */
    double overshoot;     /* past the goal: rad (joint 0) or m (tool) */
    int done;
} hold_obs;

static void observe(hold_obs *o, int after, const double *goal_q, const double goal_x[3],
                    const double dir_x[3])
{
    const arm_model *m = &arm_model_puma560;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        double *qd = after ? o->qd_after : o->qd_before;
        qd[i] = fmax(qd[i], fabs(O.st.qd_radps[i]));
        if (after && getenv("IT_HOLD_TRACE") &&
            fabs(O.st.tau_applied_Nm[i]) / m->tau_max_Nm[i] > 0.5)
            printf("  t %.3f joint %d tau %.1f qd %.3f q %.4f\n", O.st.sim_time_s, i + 1,
                   O.st.tau_applied_Nm[i], O.st.qd_radps[i], O.st.q_rad[i]);
        if (after)
            o->tau_share_max = fmax(o->tau_share_max,
                                    fabs(O.st.tau_applied_Nm[i]) / m->tau_max_Nm[i]);
    }
    if (goal_q)
        o->overshoot = fmax(o->overshoot, O.st.q_rad[0] - goal_q[0]);
    else {
        double d[3];
        vec3_sub(d, O.st.tool_position_m, goal_x);
        o->overshoot = fmax(o->overshoot, vec3_dot(d, dir_x));
    }
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Pumps the bus for dur_s, observing. */
static void watch(harness *h, hold_obs *o, int after, double dur_s, const double *goal_q,
                  const double goal_x[3], const double dir_x[3])
{
    const double t_end = now_s() + dur_s;
    while (now_s() < t_end && !(after && O.done)) {
        harness_pump(h, 2);
        if (O.have)
            observe(o, after, goal_q, goal_x, dir_x);
    }
}

/* The row of one motion from where arm 1 stands: joint 1 over 1 rad, or
 * the tool 0.25 m sideways at its present orientation. */
static void send_row(harness *h, motion mo, int32_t id, double goal_q[ARM_NJ], double goal_x[3],
                     double dir_x[3])
{
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    double Tb[16], Tw[16], Tt[16], R[9], off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    arm_tool tool;
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    row.action_id = id;
    row.transition = 1;
    row.arm = 1;
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
    memcpy(goal_q, O.st.q_rad, sizeof(double) * ARM_NJ);
    if (mo == MOTION_JOINT) {
        seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
        seg.orientation_quat[0] = 1.0;
        goal_q[0] += 1.0;
        memcpy(seg.q_rad, goal_q, sizeof seg.q_rad);
    } else {
        arm_tool_offset(&tool, off);
        assert_int_equal(arm_fk(&arm_model_puma560, &tool, O.st.q_rad, Tt), 0);
        cell_world_from_arm(&cell_default, 0, Tb);
        tf_mul(Tw, Tb, Tt);
        tf_rot(R, Tw);
        tf_pos(goal_x, Tw);
        vec3_set(dir_x, 0.0, 1.0, 0.0);
        vec3_axpy(goal_x, goal_x, 0.25, dir_x);
        seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN;
        vec3_copy(seg.position_m, goal_x);
        rot_to_quat(seg.orientation_quat, R);
        row.use_tdsd = mo == MOTION_TDSD;
    }
    O.done = 0;
    AUTH_PUBLISH(tandem_action_row_t, &h->bus, h->lcm, "ARM1_ACTION", &row);
}

/* One motion frozen for freeze_s after run_s of it (freeze_s 0: not
 * frozen; its joint speeds into qd_plan). */
static int one_hold(harness *h, pid_t arm, motion mo, double freeze_s, int32_t id,
                    double qd_plan[ARM_NJ])
{
    hold_obs o;
    double goal_q[ARM_NJ], goal_x[3] = { 0 }, dir_x[3] = { 0 };
    const double run_s = mo == MOTION_JOINT ? 2.0 : 0.8;
    double ratio = 0.0;
    int i, ok;
    memset(&o, 0, sizeof o);
    send_row(h, mo, id, goal_q, goal_x, dir_x);
    watch(h, &o, 0, run_s, mo == MOTION_JOINT ? goal_q : NULL, goal_x, dir_x);
    if (freeze_s > 0.0) {
        kill(arm, SIGSTOP);
        watch(h, &o, 0, freeze_s, mo == MOTION_JOINT ? goal_q : NULL, goal_x, dir_x);
        kill(arm, SIGCONT);
    }
    watch(h, &o, 1, 20.0, mo == MOTION_JOINT ? goal_q : NULL, goal_x, dir_x);
    o.done = O.done && O.done_id == id;
    for (i = 0; i < ARM_NJ; i++) {
        if (freeze_s <= 0.0)
            qd_plan[i] = fmax(o.qd_before[i], o.qd_after[i]);
        else if (qd_plan[i] > 0.05)
            ratio = fmax(ratio, o.qd_after[i] / qd_plan[i]);
    }
    ok = o.done && ratio <= SPEED_RATIO_MAX && o.tau_share_max < TAU_LIMIT_SHARE &&
         o.overshoot <= (mo == MOTION_JOINT ? JOINT_OVERSHOOT_RAD : TOOL_OVERSHOOT_M);
    printf(
        "%-17s frozen %.2f s: speed after / planned %.2f, peak torque %.0f %% of limit, overshoot %.4f %s, %s%s\n",
        MOTION_NAMES[mo], freeze_s, ratio, 100.0 * o.tau_share_max, o.overshoot,
        mo == MOTION_JOINT ? "rad" : "m", o.done ? "DONE" : "not done", ok ? "" : "  <- FAILS");
    return ok;
}

/* Back where the runs start (a joint row to q), done or not. */
static void go_home(harness *h, const double q[ARM_NJ], int32_t id)
{
    hold_obs o;
    double x[3] = { 0 };
    O.done = 0;
    harness_send_joint_row(h, 1, id, q);
    memset(&o, 0, sizeof o);
    watch(h, &o, 1, 20.0, NULL, x, x);
    assert_true(O.done && O.done_id == id);
}

static void test_no_lurch_after_a_freeze(void **state)
{
    static const double FREEZE_S[] = { 0.0, 0.05, 0.5, 2.0 };
    harness h;
    const char *sim[] = { "tandem-sim", NULL };
    const char *arm[] = { "tandem-arm", "--arm", "1", "--speed-frac", "0.2", NULL };
    tandem_arm_state_t_subscription_t *s_state;
    tandem_action_event_t_subscription_t *s_event;
    double q_home[ARM_NJ], qd_plan[ARM_NJ];
    pid_t arm_pid;
    int i, f, mo, failed = 0;
    int32_t id = 900;
    (void)state;
    assert_int_equal(harness_open(&h, 47), 0);
    memset(&O, 0, sizeof O);
    s_state = tandem_arm_state_t_subscribe(h.lcm, "ARM1_STATE", on_state, NULL);
    s_event = tandem_action_event_t_subscribe(h.lcm, "ARM_EVENTS", on_event, NULL);
    harness_spawn(&h, sim);
    arm_pid = harness_spawn(&h, arm);
    for (i = 0; i < 200 && !O.have; i++)
        harness_pump(&h, 20);
    assert_true(O.have);
    harness_pump(&h, 500);
    memcpy(q_home, O.st.q_rad, sizeof q_home);
    /* IT_HOLD_MOTION=0|1|2: one kind only (to look at it) */
    for (mo = MOTION_JOINT; mo <= MOTION_TDSD; mo++)
        if (!getenv("IT_HOLD_MOTION") || atoi(getenv("IT_HOLD_MOTION")) == mo)
            for (f = 0; f < 4; f++) {
                failed += !one_hold(&h, arm_pid, (motion)mo, FREEZE_S[f], id++, qd_plan);
                go_home(&h, q_home, id++);
            }
    tandem_arm_state_t_unsubscribe(h.lcm, s_state);
    tandem_action_event_t_unsubscribe(h.lcm, s_event);
    harness_close(&h);
    assert_int_equal(failed, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_lurch_after_a_freeze),
    };
    struct sched_param sp;
    if (harness_private_net() != 0)
        printf("it_hold: no private network namespace; using a private port on the shared one\n");
    /* the cell runs on the wall clock here: under SCHED_FIFO (inherited by
     * the daemons, as --rt gives them on a real cell) a loaded machine
     * does not add holds of its own to the ones the test makes */
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = 20;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
        printf("it_hold: no SCHED_FIFO (not permitted): load on this machine may add holds\n");
    return cmocka_run_group_tests(tests, NULL, NULL);
}

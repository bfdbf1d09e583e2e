/* arm_joint: tandem-arm in joint space: the joint and gripper segments of
 * an action row, external joint references (ARMk_JOINT_REF) between rows,
 * and the hold; the computed-torque servo with gravity compensation turns
 * the reference into torques.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "arm_daemon.h"
#include "msg_check.h"
#include "tandem_arm_command_t.h"

#define JOINT_DONE_TOL_RAD 0.005
#define JOINT_DONE_SPEED_RADPS 0.02
#define SERVO_SPEED_SHARE 0.9

void arm_on_joint_ref(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_daemon *ad = u;
    tandem_arm_joint_ref_t r;
    (void)ch;
    if (!DAEMON_DECODE(&ad->d.msgs, tandem_arm_joint_ref_t, rb, &r))
        return;
    if (ad->running || !ad->have_state || (ad->jref.have && r.step < ad->jref.ref.step) ||
        joint_ref_check(&r, ad->arm, ad->model, ad->st.q_rad, ad->st.step,
                        (int64_t)(ad->stale_s / DAEMON_SIM_DT_S)) != MSG_OK) {
        ad->d.msgs.rejected++;
        return;
    }
    ad->jref.ref = r;
    ad->jref.have = 1;
    ad->jref.rx_ns = rtloop_now_ns();
    arm_row_hold_at(ad, r.q_rad); /* stale refs: hold the last one */
}

static int joint_ref_fresh(const arm_daemon *ad)
{
    if (!ad->jref.have)
        return 0;
    if (ad->d.lockstep)
        return (double)(ad->st.step - ad->jref.ref.step) * DAEMON_SIM_DT_S <= ad->stale_s;
    return (double)(rtloop_now_ns() - ad->jref.rx_ns) * 1e-9 <= ad->stale_s;
}

/* The joint servo's velocity command is held to SERVO_SPEED_SHARE of the
 * motor limits: the drives stop at the limit, and a servo asking for all
 * of it has no headroom left to catch up with a lagging reference. */
static void servo_vlimit(const arm_daemon *ad, double q_d[ARM_NJ], double qd_d[ARM_NJ],
                         double qdd_d[ARM_NJ])
{
    double lim[ARM_NJ];
    int i;
    for (i = 0; i < ARM_NJ; i++)
        lim[i] = SERVO_SPEED_SHARE * ad->model->qd_max_radps[i];
    tdsd_servo_vlimit(&ad->gains, lim, ad->st.q_rad, q_d, qd_d, qdd_d);
}

/* After a protective stop (arm_hold.c): a joint move's reference is
 * referenced to time, and its clock ran on while the arm stood; picked up
 * there it would demand the whole lost way at once (joint 1 at its speed
 * and torque limits, 0.35 rad past its reference after a 2 s freeze). The
 * rest of the move is planned again from where the arm stands, at rest. */
void arm_joint_resume(arm_daemon *ad)
{
    const tandem_action_segment_t *g = arm_row_segment(ad);
    if (g && g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_JOINT)
        arm_row_plan_joint(ad, ad->st.q_rad, g->q_rad);
}

/* Reference for this cycle; returns 1 when the segment is complete. */
static int segment_reference(arm_daemon *ad, double q_d[ARM_NJ], double qd_d[ARM_NJ],
                             double qdd_d[ARM_NJ])
{
    const tandem_action_segment_t *g = &ad->seg[ad->cur_seg];
    const double t = ad->st.sim_time_s - ad->seg_t0_s;
    int i, done = 1;
    if (g->kind != TANDEM_ACTION_SEGMENT_T_MOVE_JOINT) {
        memcpy(q_d, ad->hold_q, sizeof ad->hold_q);
        memset(qd_d, 0, sizeof(double) * ARM_NJ);
        memset(qdd_d, 0, sizeof(double) * ARM_NJ);
        /* the fingers take 0.2 s to close or open, and are done only once
         * the state shows them so (a lost command is sent again) */
        return t >= 0.2 && ad->st.gripper_closed == (g->kind == TANDEM_ACTION_SEGMENT_T_GRASP);
    }
    jtraj_at(&ad->traj, t, q_d, qd_d, qdd_d);
    if (t < ad->traj.duration_s)
        return 0;
    for (i = 0; i < ARM_NJ; i++)
        if (fabs(ad->st.q_rad[i] - q_d[i]) > JOINT_DONE_TOL_RAD ||
            fabs(ad->st.qd_radps[i]) > JOINT_DONE_SPEED_RADPS)
            done = 0;
    if (done)
        arm_row_hold_at(ad, q_d);
    return done;
}

/* The cycle when no Cartesian segment sends the command: the current
 * joint or gripper segment, else a fresh external reference, else the
 * hold at hold_q. */
void arm_joint_cycle(arm_daemon *ad)
{
    double q_d[ARM_NJ], qd_d[ARM_NJ] = { 0 }, qdd_d[ARM_NJ] = { 0 }, tau[ARM_NJ];
    arm_payload payload;
    const arm_payload *pl;
    memcpy(q_d, ad->hold_q, sizeof q_d);
    if (ad->running) {
        if (ad->cur_seg < 0)
            arm_start_segment(ad);
        if (ad->running && segment_reference(ad, q_d, qd_d, qdd_d)) {
            arm_cart_fallback_cycle(ad, 1);
            arm_start_segment(ad);
            if (ad->running)
                segment_reference(ad, q_d, qd_d, qdd_d);
        }
    } else if (joint_ref_fresh(ad)) {
        memcpy(q_d, ad->jref.ref.q_rad, sizeof q_d);
        memcpy(qd_d, ad->jref.ref.qd_radps, sizeof qd_d);
        memcpy(qdd_d, ad->jref.ref.qdd_radps2, sizeof qdd_d);
        servo_vlimit(ad, q_d, qd_d, qdd_d);
    }
    /* the held bar as the Cartesian law models it: a joint move that
     * finishes a Cartesian segment must meet the joint done tolerance */
    pl = arm_cart_payload(ad, &payload);
    if (jointctl_torque(ad->model, pl, &ad->gains, ad->st.q_rad, ad->st.qd_radps, q_d, qd_d, qdd_d,
                        tau, NULL) != 0) {
        arm_hold_begin(ad, "servo failed");
        arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return;
    }
    snprintf(ad->d.status, sizeof ad->d.status, ad->running ? "action %d segment %d" : "holding",
             (int)ad->action_id, ad->cur_seg);
    arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
    /* idle: say so at 10 Hz, with the last row finished, so a supervisor
     * that lost a DONE (or restarted) knows where this arm stands */
    if (!ad->running && ad->status_cycles++ % (int64_t)(0.1 / ad->d.period_s + 0.5) == 0)
        arm_publish_event(ad, TANDEM_ACTION_EVENT_T_STATUS, "idle");
}

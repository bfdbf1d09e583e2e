/* arm_row: the running action row of tandem-arm and where the arm is held
 * between motions.
 *
 * This file is the one writer of the row's state (seg, n_seg, cur_seg,
 * running, action_id, transition, last_done_id), of the joint move's plan
 * and clock (traj, seg_t0_s) and of the hold point (hold_q, holding_set):
 * each change of them is one function here, which the controllers
 * (arm_joint.c, arm_carry.c, arm_tdsd.c), the protective stop
 * (arm_hold.c) and the inputs (tandem_arm.c) call. Written from each of
 * those files before, a row abandoned in one and advanced in another
 * could disagree about whether it ran (a REJECTED event said running).
 */
#include <string.h>
#include "arm_daemon.h"
#include "tandem_arm_command_t.h"

void arm_row_begin(arm_daemon *ad, const tandem_action_row_t *r)
{
    memcpy(ad->seg, r->segments, sizeof(r->segments[0]) * (size_t)r->n_segments);
    ad->n_seg = r->n_segments;
    ad->cur_seg = -1;
    ad->action_id = r->action_id;
    ad->transition = r->transition;
    ad->running = 1;
}

const tandem_action_segment_t *arm_row_segment(const arm_daemon *ad)
{
    if (!ad->running || ad->cur_seg < 0 || ad->cur_seg >= ad->n_seg)
        return NULL;
    return &ad->seg[ad->cur_seg];
}

void arm_row_hold_at(arm_daemon *ad, const double q_rad[ARM_NJ])
{
    memcpy(ad->hold_q, q_rad, sizeof ad->hold_q);
    ad->holding_set = 1;
}

void arm_row_plan_joint(arm_daemon *ad, const double q_from[ARM_NJ], const double q_goal[ARM_NJ])
{
    ad->seg_t0_s = ad->st.sim_time_s;
    /* q_from and q_goal are checked (a measured state, a validated row or
     * an IK solution inside the ranges): a refusal leaves a plan of no
     * duration, which the joint cycle reads as a segment done */
    jtraj_plan(&ad->traj, ad->model, q_from, q_goal, ad->speed_frac, JTRAJ_MOVE_QDD_RADPS2);
}

void arm_start_segment(arm_daemon *ad)
{
    const tandem_action_segment_t *g;
    ad->cur_seg++;
    if (ad->cur_seg >= ad->n_seg) {
        ad->running = 0;
        ad->last_done_id = ad->action_id;
        arm_publish_event(ad, TANDEM_ACTION_EVENT_T_DONE, "");
        return;
    }
    g = &ad->seg[ad->cur_seg];
    ad->seg_t0_s = ad->st.sim_time_s;
    if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_JOINT)
        arm_row_plan_joint(ad, ad->hold_q, g->q_rad);
    else if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        arm_cart_start(ad, g);
}

void arm_row_abandon(arm_daemon *ad)
{
    arm_row_hold_at(ad, ad->st.q_rad);
    ad->cur_seg = ad->n_seg;
    ad->running = 0;
}

void arm_row_replace_segment(arm_daemon *ad, const tandem_action_segment_t *g)
{
    if (ad->running && ad->cur_seg >= 0 && ad->cur_seg < ad->n_seg)
        ad->seg[ad->cur_seg] = *g;
}

int arm_row_gripper_request(const arm_daemon *ad)
{
    const tandem_action_segment_t *g = arm_row_segment(ad);
    if (!g ||
        (g->kind != TANDEM_ACTION_SEGMENT_T_GRASP && g->kind != TANDEM_ACTION_SEGMENT_T_RELEASE) ||
        !ad->have_state ||
        (ad->st.gripper_closed != 0) == (g->kind == TANDEM_ACTION_SEGMENT_T_GRASP))
        return TANDEM_ARM_COMMAND_T_GRIP_KEEP;
    return g->kind == TANDEM_ACTION_SEGMENT_T_GRASP ? TANDEM_ARM_COMMAND_T_GRIP_CLOSE
                                                    : TANDEM_ARM_COMMAND_T_GRIP_OPEN;
}

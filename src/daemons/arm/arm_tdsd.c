/* arm_tdsd: tandem-arm's TDSD Cartesian segments (docs/method/tdsd.md §7,
 * action_row_t.use_tdsd).
 *
 * A MOVE_CARTESIAN segment of a use_tdsd row is resolved by tdsd_seg (TDSD
 * at the joint reference along the row's profile, 0.9 qd_max) and the
 * joint reference is tracked by the computed-torque servo with its speed
 * limited to qd_max (tdsd_servo_vlimit). Synchronised rows (sync_group > 0)
 * keep the event-referenced law: TDSD has no shared s*. No PROGRESS
 * events; DONE as for every row.
 */
#include <stdio.h>
#include <string.h>
#include "arm_daemon.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_arm_command_t.h"

void arm_tdsd_row_accept(arm_daemon *ad, const tandem_action_row_t *r)
{
    arm_tdsd *td = &ad->tdsd;
    td->use = r->use_tdsd != 0 && r->sync_group <= 0;
    tdsd_seg_default_params(&td->par, r->v_m, r->a_m, r->u_m);
    td->seg_index = -1;
}

void arm_tdsd_resume(arm_daemon *ad)
{
    ad->tdsd.seg_index = -1; /* tdsd_start again, from the measured pose */
}

static void tdsd_start(arm_daemon *ad, const tandem_action_segment_t *g)
{
    arm_tdsd *td = &ad->tdsd;
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    double T_world_base[16], R1[9];
    arm_tool tool;
    arm_tool_offset(&tool, off);
    cell_world_from_arm(&cell_default, ad->arm - 1, T_world_base);
    rot_from_quat(R1, g->orientation_quat);
    td->action_id = ad->action_id;
    td->seg_index = ad->cur_seg;
    if (tdsd_seg_start(&td->seg, ad->model, &tool, T_world_base, ad->st.q_rad, g->position_m, R1,
                       &td->par) != 0) {
        arm_row_abandon(ad);
        td->seg_index = -1;
        arm_publish_event(ad, TANDEM_ACTION_EVENT_T_REJECTED, "bad tdsd segment");
    }
}

/* Runs the cycle when a TDSD Cartesian segment is current; 1 if it sent
 * the command. */
int arm_tdsd_cycle(arm_daemon *ad)
{
    arm_tdsd *td = &ad->tdsd;
    double qd_lim[ARM_NJ], tau[ARM_NJ];
    arm_payload payload, *pl = NULL;
    tdsd_seg_out o;
    if (!td->use)
        return 0;
    if (ad->running && ad->cur_seg < 0)
        arm_start_segment(ad);
    if (!ad->running || ad->cur_seg < 0 || ad->cur_seg >= ad->n_seg ||
        ad->seg[ad->cur_seg].kind != TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        return 0;
    if (td->seg_index != ad->cur_seg || td->action_id != ad->action_id) {
        tdsd_start(ad, &ad->seg[ad->cur_seg]);
        if (!ad->running)
            return 0;
    }
    tdsd_seg_step(&td->seg, ad->model, ad->d.period_s, &o); /* error: the reference holds */
    memcpy(qd_lim, ad->model->qd_max_radps, sizeof qd_lim);
    tdsd_servo_vlimit(&ad->gains, qd_lim, ad->st.q_rad, o.q_d, o.qd_d, o.qdd_d);
    if (ad->st.holding_workpiece >= 0) {
        const double com[3] = { 0.0, 0.0, 0.10 };
        arm_payload_point(&payload, 0.5, com);
        pl = &payload;
    }
    if (jointctl_torque(ad->model, pl, &ad->gains, ad->st.q_rad, ad->st.qd_radps, o.q_d, o.qd_d,
                        o.qdd_d, tau, NULL) != 0) {
        arm_hold_begin(ad, "servo failed");
        arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return 1;
    }
    snprintf(ad->d.status, sizeof ad->d.status, "action %d seg %d tdsd s %.3f/%.3f Q1 %.2f",
             (int)ad->action_id, ad->cur_seg, o.s_m, o.L_m, o.Q1);
    arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
    if (tdsd_seg_done(&td->seg, ad->st.q_rad, ad->st.qd_radps)) {
        arm_row_hold_at(ad, td->seg.q_ref);
        td->seg_index = -1;
        arm_start_segment(ad);
    }
    return 1;
}

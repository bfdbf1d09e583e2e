/* arm_hold: tandem-arm's protective stop (docs/method/carry.md §7.4).
 *
 * Every hold -- a stale state (the brakes), a joint fault (the brakes), a
 * servo that could not compute, this process frozen or late (a gap in its
 * commands, during which the simulator held or braked the arm) -- ends
 * the same way: from the state measured at the first good cycle the
 * servo brings the arm to rest at the deceleration joint moves are
 * planned with (a controlled stop: a stop at the servo's own bandwidth
 * took joint 1 to its torque limit from 0.4 rad/s), holds it there until
 * it is at rest, and then the running motion is planned
 * again from where the arm stands. The stop's profile and the rest test
 * are the core's (jtraj_stop_plan, jtraj_stop_at, jtraj_at_rest); this
 * file decides when a stop begins and ends, and what is planned again: a joint move from the measured joint
 * angles (jtraj, rest to rest), a TDSD segment from the measured pose, an
 * event-referenced segment from its measured progress with the profile
 * started afresh (cartseg_resume). So no motion is ever picked up where
 * a clock says it should be, and no joint is asked for more than the
 * planned speed and acceleration of the move it is in (a stop category 2
 * in ISO 10218 terms: controlled, power kept, resumed by itself once the
 * cause is gone).
 */
#include <stdio.h>
#include <string.h>
#include "arm_daemon.h"
#include "tandem_arm_command_t.h"

/* A gap in the commands longer than this is a hold: the servo's time
 * constant (1 / wn, 20 ms at 8 Hz) is longer, so shorter gaps are a
 * reference step it absorbs (2.5 mm at 0.25 m/s); longer ones the drives
 * spend holding the last torque or braking (the simulator brakes after
 * ARM_STALE_STEPS), and a time-referenced reference would jump. */
#define HOLD_GAP_S 0.010
/* More states than a gap's worth taken in one cycle are a backlog (this process
 * was not running while they queued, in the socket or in LCM), not the
 * arm as it is: the newest of them may be seconds old (a full socket
 * buffer keeps the oldest and drops the rest) and a stop referenced to it
 * pulled the arm back to where it had been, at its torque limit. The arm
 * stays on its brakes until states come at their rate again. */
#define HOLD_BURST_STATES ((int)(HOLD_GAP_S / DAEMON_SIM_DT_S + 0.5))
/* At rest: every joint slower than this for HOLD_REST_S. */
#define HOLD_REST_RADPS 0.02
#define HOLD_REST_S 0.05

void arm_hold_init(arm_daemon *ad)
{
    memset(&ad->hold, 0, sizeof ad->hold);
    ad->hold.last_cmd_step = -1;
}

void arm_hold_note_state(arm_daemon *ad)
{
    ad->hold.states_in_cycle++;
}

void arm_hold_note_command(arm_daemon *ad)
{
    ad->hold.last_cmd_step = ad->st.step;
}

void arm_hold_begin(arm_daemon *ad, const char *why)
{
    arm_hold *h = &ad->hold;
    /* the stop's reference is taken from the first good state after the
     * last cause, whichever it was */
    h->pinned = 0;
    h->rest_s = 0.0;
    if (h->active)
        return;
    h->active = 1;
    h->stops++;
    snprintf(h->why, sizeof h->why, "%s", why);
    fprintf(stderr, "%s: t %.3f s: protective stop (%s)\n", ad->d.name, ad->st.sim_time_s, why);
}

int arm_hold_check_gap(arm_daemon *ad)
{
    arm_hold *h = &ad->hold;
    const int burst = h->states_in_cycle > HOLD_BURST_STATES;
    h->states_in_cycle = 0;
    if (h->last_cmd_step >= 0 &&
        (double)(ad->st.step - h->last_cmd_step) * DAEMON_SIM_DT_S > HOLD_GAP_S)
        arm_hold_begin(ad, "commands interrupted");
    if (!burst)
        return 0;
    arm_hold_begin(ad, "states arriving in a burst");
    return 1;
}

/* The running segment planned again from the measured pose. */
static void motion_resume(arm_daemon *ad)
{
    const tandem_action_segment_t *g = arm_row_segment(ad);
    if (!g)
        return;
    if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_JOINT)
        arm_joint_resume(ad);
    else if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN && ad->tdsd.use)
        arm_tdsd_resume(ad);
    else if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        arm_cart_resume(ad);
}

/* This cycle's reference of the controlled stop, planned from the state
 * measured when the stop was taken up (jtraj_stop_plan: that state is
 * checked finite, so the plan is taken); hold_q follows it, so the arm
 * rests where it stopped. */
static void stop_reference(arm_daemon *ad, double q[ARM_NJ], double qd[ARM_NJ], double qdd[ARM_NJ])
{
    arm_hold *h = &ad->hold;
    if (!h->pinned) {
        jtraj_stop_plan(&h->stop, ad->st.q_rad, ad->st.qd_radps, JTRAJ_MOVE_QDD_RADPS2);
        h->stop_t_s = 0.0;
        h->pinned = 1;
    }
    h->stop_t_s += ad->d.period_s;
    jtraj_stop_at(&h->stop, h->stop_t_s, q, qd, qdd);
    arm_row_hold_at(ad, q);
}

int arm_hold_cycle(arm_daemon *ad)
{
    arm_hold *h = &ad->hold;
    double tau[ARM_NJ], q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
    arm_payload payload;
    if (!h->active)
        return 0;
    stop_reference(ad, q, qd, qdd);
    h->rest_s = jtraj_at_rest(ad->st.qd_radps, HOLD_REST_RADPS) ? h->rest_s + ad->d.period_s : 0.0;
    if (h->rest_s >= HOLD_REST_S) {
        h->active = 0;
        motion_resume(ad);
        fprintf(stderr,
                "%s: t %.3f s: at rest after the protective stop; motion planned again from here\n",
                ad->d.name, ad->st.sim_time_s);
    }
    snprintf(ad->d.status, sizeof ad->d.status, "protective stop (%s)%s", h->why,
             h->active ? "" : ": resuming");
    if (jointctl_torque(ad->model, arm_cart_payload(ad, &payload), &ad->gains, ad->st.q_rad,
                        ad->st.qd_radps, q, qd, qdd, tau, NULL) != 0) {
        arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return 1;
    }
    arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
    return 1;
}

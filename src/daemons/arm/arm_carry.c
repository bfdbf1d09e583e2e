/* arm_carry: tandem-arm's event-referenced Cartesian segments
 * (docs/method/carry.md §2-4, §8).
 *
 * MOVE_CARTESIAN runs cartseg: the event-referenced law (or, with
 * CONTROLLER_TIME, the time-referenced baseline) turned into torques by
 * operational-space computed torque. Synchronised segments (sync_group >
 * 0) publish PROGRESS every cycle and follow k_i s*, s* = min over this arm
 * and its partner (the partner's PROGRESS of the same transition and
 * group). BLOCKED / UNBLOCKED are reported when s stops while commanded
 * and the arm touches something (the links' contact force in ARMk_STATE).
 *
 * Joint ranges (event law): a segment whose goal the Cartesian move would
 * reach only with a joint within CARTSEG_GOAL_MARGIN_RAD of (or past) its
 * range end -- e.g. after a push turned the wrist over -- and a segment
 * that stalls with nothing touching the arm (a joint held at its range
 * barrier, cartctl) are finished by a joint-space move to the goal's
 * in-range solution (cartseg_joint_goal), still reporting s along the
 * segment; a contact during that move hands the segment back to the
 * Cartesian law, which then reports the block.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "arm_daemon.h"
#include "cell.h"
#include "sync_ref.h"
#include "vec3.h"
#include "tandem_arm_command_t.h"

#define CART_PROGRESS_EVERY 100 /* unsynchronised: 10 Hz */
#define CART_PARTNER_WINDOW_STEPS \
    500 /* partner progress older than the
                                         segment start by more: a past one */

void arm_cart_row_accept(arm_daemon *ad, const tandem_action_row_t *r)
{
    arm_carry *cx = &ad->cart;
    erlaw_gains g = { r->v_m, r->a_m, r->u_m, r->k_p, r->k_v, r->k0, r->k1, r->k2 };
    cx->g = g;
    cx->controller = r->controller;
    cx->sync_group = r->sync_group;
}

static void cart_publish_event(arm_daemon *ad, int ev, const char *detail)
{
    const arm_carry *cx = &ad->cart;
    tandem_action_event_t e;
    arm_event_fill(ad, &e, ev, detail);
    e.sync_group = cx->sync_group;
    e.s_m = cx->s_m;
    e.s_f_m = cx->s_f_m;
    e.s_norm = cx->k > 0.0 ? cx->s_m / cx->k : cx->s_m;
    AUTH_PUBLISH(tandem_action_event_t, &ad->d.bus, ad->d.lcm, "ARM_EVENTS", &e);
}

static void partner_take(arm_carry *cx, const tandem_action_event_t *e)
{
    cx->partner_valid = 1;
    cx->partner_transition = e->transition;
    cx->partner_group = e->sync_group;
    cx->partner_step = e->step;
    cx->partner_s_m = e->s_m;
    cx->partner_s_f_m = e->s_f_m;
}

/* Lockstep, at the cycle of step k: the partner's newest progress sent
 * before k (its progress of step k may or may not have arrived yet). */
void arm_cart_partner_at(arm_daemon *ad, int64_t k)
{
    arm_carry *cx = &ad->cart;
    const tandem_action_event_t *best = NULL;
    int i;
    for (i = 0; i < 4; i++) {
        const tandem_action_event_t *e = &cx->partner_ring[i];
        if (e->arm != 0 && e->step < k && (!best || e->step > best->step))
            best = e;
    }
    if (best && (!cx->partner_valid || best->step > cx->partner_step))
        partner_take(cx, best);
}

void arm_cart_on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_daemon *ad = u;
    arm_carry *cx = &ad->cart;
    tandem_action_event_t e;
    (void)ch;
    if (tandem_action_event_t_decode(rb->data, 0, rb->data_size, &e) < 0) {
        ad->d.msgs.received++;
        ad->d.msgs.rejected++;
        return;
    }
    if (e.arm != ad->arm && e.arm >= 1 && e.arm <= 2 && e.event == TANDEM_ACTION_EVENT_T_PROGRESS &&
        e.sync_group > 0) {
        ad->d.msgs.received++;
        if (!isfinite(e.s_m) || !isfinite(e.s_f_m) || e.s_f_m < 0.0 || e.s_m < 0.0 ||
            e.s_m > e.s_f_m + 1e-6) {
            ad->d.msgs.rejected++;
        } else {
            tandem_action_event_t *slot = &cx->partner_ring[(e.step & 3)];
            *slot = e;
            slot->detail = NULL;
            if (!ad->d.lockstep)
                partner_take(cx, slot);
        }
    }
    tandem_action_event_t_decode_cleanup(&e);
}

/* Finish the current Cartesian segment by a joint-space move to its
 * goal's in-range solution (see above). at_start: only if the Cartesian
 * move would end too near a range end; otherwise the segment is stuck. */
static void cart_joint_fallback(arm_daemon *ad, int at_start)
{
    arm_carry *cx = &ad->cart;
    const tandem_action_segment_t *g = &ad->seg[ad->cur_seg];
    tandem_action_segment_t joint;
    double R1[9], q_goal[ARM_NJ];
    int rc;
    rot_from_quat(R1, g->orientation_quat);
    rc = cartseg_joint_goal(ad->model, &cx->tool, cx->T_world_base, ad->st.q_rad, g->position_m, R1,
                            q_goal);
    if (at_start ? rc != 1 : rc < 0) {
        if (rc < 0)
            fprintf(stderr, "%s: segment %d: no goal solution inside the joint ranges\n",
                    ad->d.name, ad->cur_seg);
        return;
    }
    cx->cart_seg = *g;
    cx->fallback = 1;
    joint = *g;
    joint.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
    memcpy(joint.q_rad, q_goal, sizeof joint.q_rad);
    arm_row_replace_segment(ad, &joint);
    arm_row_hold_at(ad, ad->st.q_rad);
    arm_row_plan_joint(ad, ad->hold_q, q_goal);
    fprintf(
        stderr,
        "%s: t %.3f s: action %d segment %d %s: joint-space move to q = [%.3f %.3f %.3f %.3f %.3f %.3f]\n",
        ad->d.name, ad->st.sim_time_s, (int)ad->action_id, ad->cur_seg,
        at_start ? "would end near a joint range end" : "stalled with no contact", q_goal[0],
        q_goal[1], q_goal[2], q_goal[3], q_goal[4], q_goal[5]);
}

/* While a fallback joint move runs: s along the segment for PROGRESS
 * (the partner of a synchronised segment follows it), and a contact hands
 * the segment back to the Cartesian law (returns 1 then). done: the move
 * has ended. */
int arm_cart_fallback_cycle(arm_daemon *ad, int done)
{
    arm_carry *cx = &ad->cart;
    double x[3], v[3];
    if (!cx->fallback || !ad->running || ad->cur_seg < 0 || ad->cur_seg >= ad->n_seg)
        return 0;
    if (cartseg_tool_world(ad->model, &cx->tool, cx->T_world_base, ad->st.q_rad, ad->st.qd_radps, x,
                           v) == 0)
        cx->s_m = erlaw_line_s(&cx->seg.line, x);
    if (done)
        cx->s_m = cx->s_f_m;
    if (cx->sync_group > 0 || cx->cycles % CART_PROGRESS_EVERY == 0 || done)
        cart_publish_event(ad, TANDEM_ACTION_EVENT_T_PROGRESS, "");
    cx->cycles++;
    if (done) {
        cx->fallback = 0;
    } else if (ad->st.max_contact_force_10ms_N >= CARTSEG_CONTACT_N) {
        arm_row_replace_segment(ad, &cx->cart_seg);
        cx->fallback = 0;
        erlaw_block_reset(&cx->seg.blk, cx->s_m);
        fprintf(stderr,
                "%s: t %.3f s: contact during the joint-space move: back to the Cartesian law\n",
                ad->d.name, ad->st.sim_time_s);
        return 1;
    }
    return 0;
}

/* A synchronised pair starts a segment together, each at s = 0 within a
 * few milliseconds (the bias starts an arm from rest: 0.25 mm in 50 ms).
 * A partner already further along than this share of its segment means
 * this arm is taking the segment up part way: it was restarted (or its
 * row sent again) while the pair carried the bar. */
#define CART_TAKE_UP_MIN 0.02

/* A restarted arm takes a synchronised segment up at the pair's progress
 * (cartseg_take_up): started at s = 0 from where it stands, its s* would
 * drive the partner holding the other end of the bar back to the start
 * (0.11 m in 0.27 s, joint 4 faulting three times). The bar is rigid
 * between the arms, so the partner's normalised progress is ours. */
static void cart_take_up(arm_daemon *ad)
{
    arm_carry *cx = &ad->cart;
    double frac;
    if (cx->sync_group <= 0 || !cx->partner_valid || cx->partner_transition != ad->transition ||
        cx->partner_group != cx->sync_group || cx->partner_s_f_m <= 0.0 ||
        cx->partner_step < ad->st.step - CART_PARTNER_WINDOW_STEPS)
        return;
    frac = fmin(cx->partner_s_m / cx->partner_s_f_m, CARTSEG_TAKE_UP_MAX);
    if (frac < CART_TAKE_UP_MIN || cartseg_take_up(&cx->seg, frac) != 0)
        return;
    cx->s_m = frac * erlaw_channel_length(&cx->seg.line.ch);
    fprintf(
        stderr,
        "%s: t %.3f s: action %d segment %d taken up at the partner's progress (%.0f %% of the way)\n",
        ad->d.name, ad->st.sim_time_s, (int)ad->action_id, ad->cur_seg, 100.0 * frac);
}

void arm_cart_start(arm_daemon *ad, const tandem_action_segment_t *g)
{
    arm_carry *cx = &ad->cart;
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    double R1[9];
    const erlaw_ref ref = cx->controller == TANDEM_ACTION_ROW_T_CONTROLLER_TIME
                              ? ERLAW_REF_TIME
                              : ERLAW_REF_MEASURED;
    arm_tool_offset(&cx->tool, off);
    cell_world_from_arm(&cell_default, ad->arm - 1, cx->T_world_base);
    rot_from_quat(R1, g->orientation_quat);
    if (cartseg_start(&cx->seg, ad->model, &cx->tool, cx->T_world_base, ad->st.q_rad, g->position_m,
                      R1, &cx->g, ref) != 0) {
        /* cannot plan it (bad gains): hold here and skip the segment */
        arm_row_abandon(ad);
        cart_publish_event(ad, TANDEM_ACTION_EVENT_T_REJECTED, "bad segment");
        return;
    }
    cx->seg.block_detect = ad->block_detect;
    cx->start_step = ad->st.step;
    cx->cycles = 0;
    cx->s_m = 0.0;
    cx->k = 1.0;
    cx->fallback = 0;
    if (ref == ERLAW_REF_MEASURED)
        cart_take_up(ad);
    cx->s_f_m = erlaw_channel_length(&cx->seg.line.ch);
    if (ref == ERLAW_REF_MEASURED)
        cart_joint_fallback(ad, 1);
}

/* After a protective stop (arm_hold.c): the law takes the segment up from
 * the measured progress as from a start (cartseg_resume). */
void arm_cart_resume(arm_daemon *ad)
{
    arm_carry *cx = &ad->cart;
    double x[3], v[3];
    if (cx->fallback || cartseg_tool_world(ad->model, &cx->tool, cx->T_world_base, ad->st.q_rad,
                                           ad->st.qd_radps, x, v) != 0)
        return;
    cartseg_resume(&cx->seg, x);
}

/* cartseg_step's s_ext < 0: no external reference, the arm's own measured s */
#define CART_REF_OWN (-1.0)

/* Reference k_i s* of a synchronised event-referenced segment, or
 * CART_REF_OWN. Until the partner reports, s* = 0 (wait at the start). */
static double cart_sync_ref(arm_daemon *ad)
{
    arm_carry *cx = &ad->cart;
    sync_ref r;
    double l[2], s[2], s_star, ref[2];
    if (cx->sync_group <= 0 || cx->controller == TANDEM_ACTION_ROW_T_CONTROLLER_TIME)
        return CART_REF_OWN;
    if (!cx->partner_valid || cx->partner_transition != ad->transition ||
        cx->partner_group != cx->sync_group ||
        cx->partner_step < cx->start_step - CART_PARTNER_WINDOW_STEPS)
        return 0.0;
    if (cx->partner_s_f_m <= 0.0)
        return CART_REF_OWN; /* a partner's zero-length segment: it is done */
    l[0] = cx->s_f_m;
    l[1] = cx->partner_s_f_m;
    s[0] = cx->s_m;
    s[1] = cx->partner_s_m;
    if (sync_ref_init(&r, 2, l) != 0 || sync_ref_update(&r, s, &s_star, ref) != 0)
        return 0.0;
    cx->k = r.k[0];
    return ref[0];
}

/* The bar is held at one end: its centre is 0.10 m along the flange x
 * axis (towards +x for arm 1, -x for arm 2), at the tool point. */
const arm_payload *arm_cart_payload(const arm_daemon *ad, arm_payload *p)
{
    double com[3];
    if (ad->st.holding_workpiece < 0)
        return NULL;
    com[0] = (ad->arm == 1 ? 1.0 : -1.0) * cell_default.grasp_offset_m;
    com[1] = 0.0;
    com[2] = CELL_TOOL_LENGTH_M;
    arm_payload_point(p, cell_default.workpiece_mass_kg, com);
    return p;
}

/* Runs the cycle when a Cartesian segment is current; 1 if it sent the
 * command, 0 to let the joint-space path do it. */
int arm_cart_cycle(arm_daemon *ad)
{
    arm_carry *cx = &ad->cart;
    arm_payload pl;
    cartseg_out o;
    cartctl_state kin; /* the cycle's one kinematics pass */
    double x[3], v[3], s_ext;
    if (ad->running && ad->cur_seg < 0)
        arm_start_segment(ad);
    if (!ad->running || ad->cur_seg < 0 || ad->cur_seg >= ad->n_seg ||
        ad->seg[ad->cur_seg].kind != TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        return 0;
    if (cartctl_state_at(ad->model, &cx->tool, ad->st.q_rad, ad->st.qd_radps, &kin) != 0 ||
        cartseg_tool_world_at(&kin, cx->T_world_base, x, v) != 0)
        return 0;
    cx->s_m = erlaw_line_s(&cx->seg.line, x);
    s_ext = cart_sync_ref(ad);
    cartseg_set_contact(&cx->seg, ad->st.max_contact_force_10ms_N);
    if (cartseg_step_at(&cx->seg, ad->model, arm_cart_payload(ad, &pl), &kin, ad->st.q_rad,
                        ad->st.qd_radps, s_ext, ad->d.period_s, &o) != 0)
        return 0; /* joint-space hold at hold_q this cycle */
    /* done (within CARTSEG_DONE_TOL_M of s_f, at rest): the last PROGRESS
     * says s_f, so a synchronised partner's s* is not held up to 4 mm short
     * of its own goal, where it would wait for good */
    cx->s_m = o.done ? cx->s_f_m : o.s_m;
    if (o.block_changed)
        cart_publish_event(
            ad, o.blocked ? TANDEM_ACTION_EVENT_T_BLOCKED : TANDEM_ACTION_EVENT_T_UNBLOCKED, "");
    if (o.stuck) {
        cart_joint_fallback(ad, 0);
        if (cx->fallback)
            return 0; /* the joint-space path runs it from this cycle */
    }
    if (cx->sync_group > 0 || cx->cycles % CART_PROGRESS_EVERY == 0 || o.done)
        cart_publish_event(ad, TANDEM_ACTION_EVENT_T_PROGRESS, "");
    cx->cycles++;
    snprintf(ad->d.status, sizeof ad->d.status, "action %d seg %d s %.3f/%.3f%s",
             (int)ad->action_id, ad->cur_seg, o.s_m, o.s_f_m, o.blocked ? " BLOCKED" : "");
    arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_TORQUE, o.tau_Nm);
    if (o.done) {
        if (o.blocked)
            cart_publish_event(ad, TANDEM_ACTION_EVENT_T_UNBLOCKED, "");
        arm_row_hold_at(ad, ad->st.q_rad);
        arm_start_segment(ad);
    }
    return 1;
}

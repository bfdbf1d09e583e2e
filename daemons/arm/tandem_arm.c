/* tandem-arm: continuous controller of one PUMA 560 ("MVME165" board).
 *
 * 1 kHz: reads ARMk_STATE, runs the core controller, publishes
 * ARMk_COMMAND (joint torques). Executes action rows from the supervisor
 * (ARMk_ACTION) segment by segment and reports ARM_EVENTS; between rows it
 * tracks fresh joint references (ARMk_JOINT_REF) if any arrive. Safe hold
 * (SPEC.md §7): a stale state (> --stale-ms) engages the brakes; an invalid
 * row is rejected and the arm holds where it is with gravity compensation.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "msg_check.h"
#include "arm_kin.h"
#include "jointctl.h"
#include "jtraj.h"
#include "cartseg.h"
#include "tdsd_seg.h"
#include "cell.h"
#include "sync_ref.h"
#include "vec3.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_joint_ref_t.h"
#include "tandem_arm_state_t.h"

#define ROW_MAX_SEGMENTS 8
#define JOINT_DONE_TOL_RAD 0.005
#define JOINT_DONE_SPEED_RADPS 0.02
#define FAULT_CLEAR_S 0.5
#define SERVO_SPEED_SHARE 0.9

typedef struct arm_ctl {
    int    arm;                       /* 1 or 2 */
    const arm_model *model;
    jointctl_gains gains;
    double stale_s;
    double speed_frac;
    /* latest valid state */
    tandem_arm_state_t st;
    int    have_state;
    int64_t state_rx_ns;              /* wall time it arrived (real-time staleness) */
    /* what the arm is doing */
    double hold_q[ARM_NJ];
    int    holding_set;
    tandem_action_segment_t seg[ROW_MAX_SEGMENTS];
    int    n_seg, cur_seg;
    int32_t action_id, transition;
    int32_t last_done_id;             /* the last row finished (0: none yet) */
    int64_t status_cycles;            /* idle cycles, for the 10 Hz STATUS */
    int    running;
    jtraj  traj;
    double seg_t0_s;
    int    gripper;                   /* command to send this cycle */
    int    block_detect;              /* 0: eq. 6-7 alone, no blocked detector */
    int    fault;                     /* in a joint fault (braking) */
    double fault_clear_s;             /* healthy time since the fault's last sign */
    int64_t cmd_seq, ev_seq;
    char   state_ch[16], cmd_ch[16], action_ch[16];
} arm_ctl;

static arm_ctl C;
/* ARMk_STATE steps (guard.h): a state may be 1 s ahead of the last one;
 * after 1 s without a state the simulator is taken to have restarted. */
static step_gate state_gate;

/* External joint references (ARMk_JOINT_REF, e.g. a TDSD resolver in
 * tandem-scenario): tracked while fresh and no action row runs. */
static struct {
    tandem_arm_joint_ref_t ref;
    int     have;
    int64_t rx_ns;
    char    ch[20];
} JR;

static void usage(void)
{
    printf("usage: tandem-arm --arm 1|2 [options]\n"
           "Continuous controller of one PUMA 560: computed-torque joint control with\n"
           "gravity compensation; executes supervisor action rows; safe hold on stale\n"
           "or invalid input.\n\n"
           "  --arm N           which arm, 1 or 2 (required)\n"
           "  --wn HZ           joint servo natural frequency in Hz (default 8)\n"
           "  --stale-ms MS     state older than this engages the brakes (default 20)\n"
           "  --speed-frac F    joint moves use this fraction of the motor speed (default 0.5)\n"
           "  --arm-model NAME  puma560 (default) or seed002 (must match tandem-sim's)\n"
           "  --block-detect on|off  off: the event-referenced law (eq. 6-7) alone, no\n"
           "                    blocked detector and no BLOCKED events (default on)\n"
           DAEMON_COMMON_HELP);
}

/* Every event carries the running action and segment; Cartesian segments
 * add their progress (see cart_publish_event). */
static void event_fill(tandem_action_event_t *e, int ev, const char *detail)
{
    memset(e, 0, sizeof *e);
    e->seq = C.ev_seq++;
    e->utime = daemon_utime_now();
    e->step = C.st.step;
    e->action_id = C.action_id;
    e->transition = C.transition;
    e->arm = (int8_t)C.arm;
    e->event = (int8_t)ev;
    e->segment = (int8_t)C.cur_seg;
    e->detail = (char *)detail;
    if (ev == TANDEM_ACTION_EVENT_T_DONE)
        C.last_done_id = C.action_id;
    e->last_done_action_id = C.last_done_id;
    e->running = (int8_t)(C.running && ev != TANDEM_ACTION_EVENT_T_DONE);
    e->holding_workpiece = C.have_state ? C.st.holding_workpiece : -1;
}

static void publish_event(daemon *d, int ev, const char *detail)
{
    tandem_action_event_t e;
    event_fill(&e, ev, detail);
    AUTH_PUBLISH(tandem_action_event_t, d->lcm, "ARM_EVENTS", &e);
}

/* ---- inputs --------------------------------------------------------------- */

static int state_valid(const tandem_arm_state_t *s)
{
    return s->arm == C.arm && s->step >= 0 && all_finite(s->q_rad, ARM_NJ) &&
           all_finite(s->qd_radps, ARM_NJ) && isfinite(s->sim_time_s);
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_arm_state_t s;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_arm_state_t, rb, &s))
        return;
    if (!state_valid(&s) || step_gate_pass(&state_gate, s.step, rtloop_now_ns()) != GUARD_OK) {
        d->msgs.rejected++;
        return;
    }
    C.st = s;
    C.have_state = 1;
    C.state_rx_ns = rtloop_now_ns();
    if (!C.holding_set) {
        memcpy(C.hold_q, s.q_rad, sizeof C.hold_q);
        C.holding_set = 1;
    }
}

static void cart_row_accept(const tandem_action_row_t *r);
static void tdsd_row_accept(const tandem_action_row_t *r);
static void cart_start(daemon *d, const tandem_action_segment_t *g);
static int  cart_cycle(daemon *d);
static void send_command(daemon *d, int mode, const double tau[ARM_NJ]);

static int segment_valid(const tandem_action_segment_t *g)
{
    switch (g->kind) {
    case TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN:
        return all_finite(g->position_m, 3) && all_finite(g->orientation_quat, 4) &&
               fabs(g->orientation_quat[0] * g->orientation_quat[0] + g->orientation_quat[1] * g->orientation_quat[1] +
                    g->orientation_quat[2] * g->orientation_quat[2] + g->orientation_quat[3] * g->orientation_quat[3] - 1.0) < 1e-3;
    case TANDEM_ACTION_SEGMENT_T_MOVE_JOINT:
        return arm_q_finite(g->q_rad) == 0 && arm_q_outside_limits(C.model, g->q_rad) == 0;
    case TANDEM_ACTION_SEGMENT_T_GRASP:
    case TANDEM_ACTION_SEGMENT_T_RELEASE:
        return 1;
    default:
        return 0;   /* Cartesian segments: see the event-referenced controller */
    }
}

static tandem_action_row_t row_pending;
static tandem_action_segment_t row_pending_seg[ROW_MAX_SEGMENTS];
static int have_row_pending;
static void row_take(daemon *d);

static void on_action(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_action_row_t r;
    int i, ok;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_action_row_t, rb, &r))
        return;
    ok = action_row_check(&r, C.arm, ROW_MAX_SEGMENTS) == MSG_OK && !C.running && !have_row_pending;
    for (i = 0; ok && i < r.n_segments; i++)
        ok = segment_valid(&r.segments[i]);
    if (!ok) {
        d->msgs.rejected++;
        if (r.arm == C.arm) {
            const int32_t id = C.action_id, t = C.transition;
            C.action_id = r.action_id;
            C.transition = r.transition;
            publish_event(d, TANDEM_ACTION_EVENT_T_REJECTED, C.running ? "busy" : "invalid row");
            C.action_id = id;
            C.transition = t;
        }
        tandem_action_row_t_decode_cleanup(&r);
        return;
    }
    row_pending = r;
    memcpy(row_pending_seg, r.segments, sizeof(r.segments[0]) * (size_t)r.n_segments);
    row_pending.segments = row_pending_seg;
    have_row_pending = 1;
    tandem_action_row_t_decode_cleanup(&r);
    if (!d->lockstep)
        row_take(d);
}

/* A valid row starts here: at once in real time, in lockstep at the first
 * cycle after the step it was sent at (the supervisor answers that step
 * beside us, so whether it had arrived by then is a race). */
static void row_take(daemon *d)
{
    const tandem_action_row_t *r = &row_pending;
    have_row_pending = 0;
    memcpy(C.seg, r->segments, sizeof(r->segments[0]) * (size_t)r->n_segments);
    C.n_seg = r->n_segments;
    C.cur_seg = -1;
    C.action_id = r->action_id;
    C.transition = r->transition;
    C.running = 1;
    cart_row_accept(r);
    tdsd_row_accept(r);
    publish_event(d, TANDEM_ACTION_EVENT_T_STARTED, "");
}

static void on_joint_ref(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_arm_joint_ref_t r;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_arm_joint_ref_t, rb, &r))
        return;
    if (C.running || !C.have_state || (JR.have && r.step < JR.ref.step) ||
        joint_ref_check(&r, C.arm, C.model, C.st.q_rad, C.st.step,
                        (int64_t)(C.stale_s / DAEMON_SIM_DT_S)) != MSG_OK) {
        d->msgs.rejected++;
        return;
    }
    JR.ref = r;
    JR.have = 1;
    JR.rx_ns = rtloop_now_ns();
    memcpy(C.hold_q, r.q_rad, sizeof C.hold_q);   /* stale refs: hold the last one */
    C.holding_set = 1;
}

static int joint_ref_fresh(const daemon *d)
{
    if (!JR.have)
        return 0;
    if (d->lockstep)
        return (double)(C.st.step - JR.ref.step) * DAEMON_SIM_DT_S <= C.stale_s;
    return (double)(rtloop_now_ns() - JR.rx_ns) * 1e-9 <= C.stale_s;
}

/* ---- segments ------------------------------------------------------------- */

static void start_segment(daemon *d)
{
    const tandem_action_segment_t *g;
    C.cur_seg++;
    if (C.cur_seg >= C.n_seg) {
        C.running = 0;
        publish_event(d, TANDEM_ACTION_EVENT_T_DONE, "");
        return;
    }
    g = &C.seg[C.cur_seg];
    C.seg_t0_s = C.st.sim_time_s;
    if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_JOINT)
        jtraj_plan(&C.traj, C.model, C.hold_q, g->q_rad, C.speed_frac, 2.0);
    else if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        cart_start(d, g);
    else
        C.gripper = g->kind == TANDEM_ACTION_SEGMENT_T_GRASP ? TANDEM_ARM_COMMAND_T_GRIP_CLOSE
                                                            : TANDEM_ARM_COMMAND_T_GRIP_OPEN;
}

/* Reference for this cycle; returns 1 when the segment is complete. */
static int segment_reference(double q_d[ARM_NJ], double qd_d[ARM_NJ], double qdd_d[ARM_NJ])
{
    const tandem_action_segment_t *g = &C.seg[C.cur_seg];
    const double t = C.st.sim_time_s - C.seg_t0_s;
    int i, done = 1;
    if (g->kind != TANDEM_ACTION_SEGMENT_T_MOVE_JOINT) {
        memcpy(q_d, C.hold_q, sizeof C.hold_q);
        memset(qd_d, 0, sizeof(double) * ARM_NJ);
        memset(qdd_d, 0, sizeof(double) * ARM_NJ);
        return t >= 0.2;   /* the fingers take 0.2 s to close or open */
    }
    jtraj_at(&C.traj, t, q_d, qd_d, qdd_d);
    if (t < C.traj.duration_s)
        return 0;
    for (i = 0; i < ARM_NJ; i++)
        if (fabs(C.st.q_rad[i] - q_d[i]) > JOINT_DONE_TOL_RAD || fabs(C.st.qd_radps[i]) > JOINT_DONE_SPEED_RADPS)
            done = 0;
    if (done)
        memcpy(C.hold_q, q_d, sizeof C.hold_q);
    return done;
}

/* ---- Cartesian segments (SPEC 2.1-2.3, 2.6) ------------------------------
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
 * Cartesian law, which then reports the block. */

#define CART_PROGRESS_EVERY 100       /* unsynchronised: 10 Hz */
#define CART_PARTNER_WINDOW_STEPS 500 /* partner progress older than the
                                         segment start by more: a past one */

static struct {
    cartseg seg;
    arm_tool tool;
    double  T_world_base[16];
    erlaw_gains g;
    int     controller;               /* action_row_t CONTROLLER_* */
    int32_t sync_group;
    int64_t start_step;
    int64_t cycles;
    double  s_m, s_f_m, k;            /* last measured progress, length, k_i */
    int     partner_valid;
    int32_t partner_transition, partner_group;
    int64_t partner_step;
    double  partner_s_m, partner_s_f_m;
    /* the partner's last PROGRESS messages by step: lockstep uses the
     * newest sent before the step it answers, whatever the arrival order */
    tandem_action_event_t partner_ring[4];
    int     fallback;                 /* the segment runs as a joint-space move */
    tandem_action_segment_t cart_seg; /* ... in place of this Cartesian one */
} CX;

static void cart_row_accept(const tandem_action_row_t *r)
{
    erlaw_gains g = { r->v_m, r->a_m, r->u_m, r->k_p, r->k_v, r->k0, r->k1, r->k2 };
    CX.g = g;
    CX.controller = r->controller;
    CX.sync_group = r->sync_group;
}

static void cart_publish_event(daemon *d, int ev, const char *detail)
{
    tandem_action_event_t e;
    event_fill(&e, ev, detail);
    e.sync_group = CX.sync_group;
    e.s_m = CX.s_m;
    e.s_f_m = CX.s_f_m;
    e.s_norm = CX.k > 0.0 ? CX.s_m / CX.k : CX.s_m;
    AUTH_PUBLISH(tandem_action_event_t, d->lcm, "ARM_EVENTS", &e);
}

static void partner_take(const tandem_action_event_t *e)
{
    CX.partner_valid = 1;
    CX.partner_transition = e->transition;
    CX.partner_group = e->sync_group;
    CX.partner_step = e->step;
    CX.partner_s_m = e->s_m;
    CX.partner_s_f_m = e->s_f_m;
}

/* Lockstep, at the cycle of step k: the partner's newest progress sent
 * before k (its progress of step k may or may not have arrived yet). */
static void partner_at(int64_t k)
{
    const tandem_action_event_t *best = NULL;
    int i;
    for (i = 0; i < 4; i++) {
        const tandem_action_event_t *e = &CX.partner_ring[i];
        if (e->arm != 0 && e->step < k && (!best || e->step > best->step))
            best = e;
    }
    if (best && (!CX.partner_valid || best->step > CX.partner_step))
        partner_take(best);
}

static void cart_on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_action_event_t e;
    (void)ch;
    if (tandem_action_event_t_decode(rb->data, 0, rb->data_size, &e) < 0) {
        d->msgs.received++;
        d->msgs.rejected++;
        return;
    }
    if (e.arm != C.arm && e.arm >= 1 && e.arm <= 2 && e.event == TANDEM_ACTION_EVENT_T_PROGRESS &&
        e.sync_group > 0) {
        d->msgs.received++;
        if (!isfinite(e.s_m) || !isfinite(e.s_f_m) || e.s_f_m < 0.0 || e.s_m < 0.0 || e.s_m > e.s_f_m + 1e-6) {
            d->msgs.rejected++;
        } else {
            tandem_action_event_t *slot = &CX.partner_ring[(e.step & 3)];
            *slot = e;
            slot->detail = NULL;
            if (!d->lockstep)
                partner_take(slot);
        }
    }
    tandem_action_event_t_decode_cleanup(&e);
}

/* Finish the current Cartesian segment by a joint-space move to its
 * goal's in-range solution (see above). at_start: only if the Cartesian
 * move would end too near a range end; otherwise the segment is stuck. */
static void cart_joint_fallback(daemon *d, int at_start)
{
    tandem_action_segment_t *g = &C.seg[C.cur_seg];
    double R1[9], q_goal[ARM_NJ];
    int rc;
    rot_from_quat(R1, g->orientation_quat);
    rc = cartseg_joint_goal(C.model, &CX.tool, CX.T_world_base, C.st.q_rad, g->position_m, R1, q_goal);
    if (at_start ? rc != 1 : rc < 0) {
        if (rc < 0)
            fprintf(stderr, "%s: segment %d: no goal solution inside the joint ranges\n", d->name, C.cur_seg);
        return;
    }
    CX.cart_seg = *g;
    CX.fallback = 1;
    g->kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
    memcpy(g->q_rad, q_goal, sizeof g->q_rad);
    memcpy(C.hold_q, C.st.q_rad, sizeof C.hold_q);
    C.seg_t0_s = C.st.sim_time_s;
    jtraj_plan(&C.traj, C.model, C.hold_q, g->q_rad, C.speed_frac, 2.0);
    fprintf(stderr, "%s: t %.3f s: action %d segment %d %s: joint-space move to q = [%.3f %.3f %.3f %.3f %.3f %.3f]\n",
            d->name, C.st.sim_time_s, (int)C.action_id, C.cur_seg,
            at_start ? "would end near a joint range end" : "stalled with no contact", q_goal[0], q_goal[1],
            q_goal[2], q_goal[3], q_goal[4], q_goal[5]);
}

/* While a fallback joint move runs: s along the segment for PROGRESS
 * (the partner of a synchronised segment follows it), and a contact hands
 * the segment back to the Cartesian law (returns 1 then). done: the move
 * has ended. */
static int cart_fallback_cycle(daemon *d, int done)
{
    double x[3], v[3];
    if (!CX.fallback || !C.running || C.cur_seg < 0 || C.cur_seg >= C.n_seg)
        return 0;
    if (cartseg_tool_world(C.model, &CX.tool, CX.T_world_base, C.st.q_rad, C.st.qd_radps, x, v) == 0)
        CX.s_m = erlaw_line_s(&CX.seg.line, x);
    if (done)
        CX.s_m = CX.s_f_m;
    if (CX.sync_group > 0 || CX.cycles % CART_PROGRESS_EVERY == 0 || done)
        cart_publish_event(d, TANDEM_ACTION_EVENT_T_PROGRESS, "");
    CX.cycles++;
    if (done) {
        CX.fallback = 0;
    } else if (C.st.max_contact_force_10ms_N >= CARTSEG_CONTACT_N) {
        C.seg[C.cur_seg] = CX.cart_seg;
        CX.fallback = 0;
        erlaw_block_reset(&CX.seg.blk, CX.s_m);
        fprintf(stderr, "%s: t %.3f s: contact during the joint-space move: back to the Cartesian law\n", d->name,
                C.st.sim_time_s);
        return 1;
    }
    return 0;
}

static void cart_start(daemon *d, const tandem_action_segment_t *g)
{
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    double R1[9];
    const erlaw_ref ref = CX.controller == TANDEM_ACTION_ROW_T_CONTROLLER_TIME ? ERLAW_REF_TIME : ERLAW_REF_MEASURED;
    arm_tool_offset(&CX.tool, off);
    cell_world_from_arm(&cell_default, C.arm - 1, CX.T_world_base);
    rot_from_quat(R1, g->orientation_quat);
    if (cartseg_start(&CX.seg, C.model, &CX.tool, CX.T_world_base, C.st.q_rad, g->position_m, R1, &CX.g, ref) != 0) {
        /* cannot plan it (bad gains): hold here and skip the segment */
        memcpy(C.hold_q, C.st.q_rad, sizeof C.hold_q);
        C.cur_seg = C.n_seg;
        C.running = 0;
        cart_publish_event(d, TANDEM_ACTION_EVENT_T_REJECTED, "bad segment");
        return;
    }
    CX.seg.block_detect = C.block_detect;
    CX.start_step = C.st.step;
    CX.cycles = 0;
    CX.s_m = 0.0;
    CX.s_f_m = erlaw_channel_length(&CX.seg.line.ch);
    CX.k = 1.0;
    CX.fallback = 0;
    if (ref == ERLAW_REF_MEASURED)
        cart_joint_fallback(d, 1);
}

/* Reference k_i s* of a synchronised event-referenced segment, or -1
 * (own measured s). Until the partner reports, s* = 0 (wait at the start). */
static double cart_sync_ref(void)
{
    sync_ref r;
    double l[2], s[2], s_star, ref[2];
    if (CX.sync_group <= 0 || CX.controller == TANDEM_ACTION_ROW_T_CONTROLLER_TIME)
        return -1.0;
    if (!CX.partner_valid || CX.partner_transition != C.transition || CX.partner_group != CX.sync_group ||
        CX.partner_step < CX.start_step - CART_PARTNER_WINDOW_STEPS)
        return 0.0;
    l[0] = CX.s_f_m;
    l[1] = CX.partner_s_f_m;
    s[0] = CX.s_m;
    s[1] = CX.partner_s_m;
    if (sync_ref_init(&r, 2, l) != 0 || sync_ref_update(&r, s, &s_star, ref) != 0)
        return 0.0;
    CX.k = r.k[0];
    return ref[0];
}

/* The bar is held at one end: its centre is 0.10 m along the flange x
 * axis (towards +x for arm 1, -x for arm 2), at the tool point. */
static const arm_payload *cart_payload(arm_payload *p)
{
    double com[3];
    if (C.st.holding_workpiece < 0)
        return NULL;
    com[0] = (C.arm == 1 ? 1.0 : -1.0) * cell_default.grasp_offset_m;
    com[1] = 0.0;
    com[2] = CELL_TOOL_LENGTH_M;
    arm_payload_point(p, cell_default.workpiece_mass_kg, com);
    return p;
}

/* Runs the cycle when a Cartesian segment is current; 1 if it sent the
 * command, 0 to let the joint-space path do it. */
static int cart_cycle(daemon *d)
{
    arm_payload pl;
    cartseg_out o;
    double x[3], v[3], s_ext;
    if (C.running && C.cur_seg < 0)
        start_segment(d);
    if (!C.running || C.cur_seg < 0 || C.cur_seg >= C.n_seg ||
        C.seg[C.cur_seg].kind != TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        return 0;
    if (cartseg_tool_world(C.model, &CX.tool, CX.T_world_base, C.st.q_rad, C.st.qd_radps, x, v) != 0)
        return 0;
    CX.s_m = erlaw_line_s(&CX.seg.line, x);
    s_ext = cart_sync_ref();
    cartseg_set_contact(&CX.seg, C.st.max_contact_force_10ms_N);
    if (cartseg_step(&CX.seg, C.model, &CX.tool, cart_payload(&pl), C.st.q_rad, C.st.qd_radps, s_ext,
                     d->period_s, &o) != 0)
        return 0;   /* joint-space hold at hold_q this cycle */
    /* done (within CARTSEG_DONE_TOL_M of s_f, at rest): the last PROGRESS
     * says s_f, so a synchronised partner's s* is not held up to 4 mm short
     * of its own goal, where it would wait for good */
    CX.s_m = o.done ? CX.s_f_m : o.s_m;
    if (o.block_changed)
        cart_publish_event(d, o.blocked ? TANDEM_ACTION_EVENT_T_BLOCKED : TANDEM_ACTION_EVENT_T_UNBLOCKED, "");
    if (o.stuck) {
        cart_joint_fallback(d, 0);
        if (CX.fallback)
            return 0;   /* the joint-space path runs it from this cycle */
    }
    if (CX.sync_group > 0 || CX.cycles % CART_PROGRESS_EVERY == 0 || o.done)
        cart_publish_event(d, TANDEM_ACTION_EVENT_T_PROGRESS, "");
    CX.cycles++;
    snprintf(d->status, sizeof d->status, "action %d seg %d s %.3f/%.3f%s", (int)C.action_id, C.cur_seg,
             o.s_m, o.s_f_m, o.blocked ? " BLOCKED" : "");
    send_command(d, TANDEM_ARM_COMMAND_T_MODE_TORQUE, o.tau_Nm);
    if (o.done) {
        if (o.blocked)
            cart_publish_event(d, TANDEM_ACTION_EVENT_T_UNBLOCKED, "");
        memcpy(C.hold_q, C.st.q_rad, sizeof C.hold_q);
        start_segment(d);
    }
    return 1;
}

/* ---- TDSD Cartesian segments (SPEC 3, action_row_t.use_tdsd) ------------
 * A MOVE_CARTESIAN segment of a use_tdsd row is resolved by tdsd_seg (TDSD
 * at the joint reference along the row's profile, 0.9 qd_max) and the
 * joint reference is tracked by the computed-torque servo with its speed
 * limited to qd_max (tdsd_servo_vlimit). Synchronised rows (sync_group > 0)
 * keep the event-referenced law: TDSD has no shared s*. No PROGRESS
 * events; DONE as for every row. */

static struct {
    int      use;                     /* this row resolves Cartesian moves by TDSD */
    tdsd_seg_params par;
    tdsd_seg seg;
    int32_t  action_id;
    int      seg_index;               /* C.cur_seg the TDSD segment belongs to, -1 */
} TD;

static void tdsd_row_accept(const tandem_action_row_t *r)
{
    TD.use = r->use_tdsd != 0 && r->sync_group <= 0;
    tdsd_seg_default_params(&TD.par, r->v_m, r->a_m, r->u_m);
    TD.seg_index = -1;
}

static void tdsd_start(daemon *d, const tandem_action_segment_t *g)
{
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    double T_world_base[16], R1[9];
    arm_tool tool;
    arm_tool_offset(&tool, off);
    cell_world_from_arm(&cell_default, C.arm - 1, T_world_base);
    rot_from_quat(R1, g->orientation_quat);
    TD.action_id = C.action_id;
    TD.seg_index = C.cur_seg;
    if (tdsd_seg_start(&TD.seg, C.model, &tool, T_world_base, C.st.q_rad, g->position_m, R1, &TD.par) != 0) {
        memcpy(C.hold_q, C.st.q_rad, sizeof C.hold_q);
        C.cur_seg = C.n_seg;
        C.running = 0;
        TD.seg_index = -1;
        publish_event(d, TANDEM_ACTION_EVENT_T_REJECTED, "bad tdsd segment");
    }
}

/* Runs the cycle when a TDSD Cartesian segment is current; 1 if it sent
 * the command. */
static int tdsd_cycle(daemon *d)
{
    double qd_lim[ARM_NJ], tau[ARM_NJ];
    arm_payload payload, *pl = NULL;
    tdsd_seg_out o;
    if (!TD.use)
        return 0;
    if (C.running && C.cur_seg < 0)
        start_segment(d);
    if (!C.running || C.cur_seg < 0 || C.cur_seg >= C.n_seg ||
        C.seg[C.cur_seg].kind != TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
        return 0;
    if (TD.seg_index != C.cur_seg || TD.action_id != C.action_id) {
        tdsd_start(d, &C.seg[C.cur_seg]);
        if (!C.running)
            return 0;
    }
    tdsd_seg_step(&TD.seg, C.model, d->period_s, &o);   /* error: the reference holds */
    memcpy(qd_lim, C.model->qd_max_radps, sizeof qd_lim);
    tdsd_servo_vlimit(&C.gains, qd_lim, C.st.q_rad, o.q_d, o.qd_d, o.qdd_d);
    if (C.st.holding_workpiece >= 0) {
        const double com[3] = { 0.0, 0.0, 0.10 };
        arm_payload_point(&payload, 0.5, com);
        pl = &payload;
    }
    if (jointctl_torque(C.model, pl, &C.gains, C.st.q_rad, C.st.qd_radps, o.q_d, o.qd_d, o.qdd_d, tau, NULL) != 0) {
        send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return 1;
    }
    snprintf(d->status, sizeof d->status, "action %d seg %d tdsd s %.3f/%.3f Q1 %.2f", (int)C.action_id,
             C.cur_seg, o.s_m, o.L_m, o.Q1);
    send_command(d, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
    if (tdsd_seg_done(&TD.seg, C.st.q_rad, C.st.qd_radps)) {
        memcpy(C.hold_q, TD.seg.q_ref, sizeof C.hold_q);
        TD.seg_index = -1;
        start_segment(d);
    }
    return 1;
}

/* ---- the cycle ------------------------------------------------------------ */

static int state_stale(const daemon *d)
{
    if (!C.have_state)
        return 1;
    if (d->lockstep)
        return (double)(d->step - C.st.step) * DAEMON_SIM_DT_S > C.stale_s;
    return (double)(rtloop_now_ns() - C.state_rx_ns) * 1e-9 > C.stale_s;
}

static void send_command(daemon *d, int mode, const double tau[ARM_NJ])
{
    tandem_arm_command_t c;
    memset(&c, 0, sizeof c);
    c.seq = C.cmd_seq++;
    c.utime = daemon_utime_now();
    c.step = C.st.step;
    c.arm = (int8_t)C.arm;
    c.mode = (int8_t)mode;
    if (tau)
        memcpy(c.tau_Nm, tau, sizeof c.tau_Nm);
    c.gripper = (int8_t)C.gripper;
    AUTH_PUBLISH(tandem_arm_command_t, d->lcm, C.cmd_ch, &c);
    C.gripper = TANDEM_ARM_COMMAND_T_GRIP_KEEP;
}

/* The joint servo's velocity command is held to SERVO_SPEED_SHARE of the
 * motor limits: the drives stop at the limit, and a servo asking for all
 * of it has no headroom left to catch up with a lagging reference. */
static void servo_vlimit(double q_d[ARM_NJ], double qd_d[ARM_NJ], double qdd_d[ARM_NJ])
{
    double lim[ARM_NJ];
    int i;
    for (i = 0; i < ARM_NJ; i++)
        lim[i] = SERVO_SPEED_SHARE * C.model->qd_max_radps[i];
    tdsd_servo_vlimit(&C.gains, lim, C.st.q_rad, q_d, qd_d, qdd_d);
}

/* Joint range and speed watchdog; 1 while the arm holds on its brakes. */
static int joint_fault(daemon *d)
{
    const unsigned bits = arm_joint_faults(C.model, C.st.q_rad, C.st.qd_radps);
    if (bits) {
        char detail[64];
        C.fault_clear_s = 0.0;
        if (!C.fault) {
            snprintf(detail, sizeof detail, "range 0x%02x speed 0x%02x", ARM_FAULT_RANGE(bits), ARM_FAULT_SPEED(bits));
            publish_event(d, TANDEM_ACTION_EVENT_T_FAULT, detail);
            fprintf(stderr, "%s: FAULT %s: safe hold on the brakes\n", d->name, detail);
        }
        C.fault = 1;
    } else if (C.fault) {
        C.fault_clear_s += d->period_s;
        if (C.fault_clear_s >= FAULT_CLEAR_S) {
            C.fault = 0;
            publish_event(d, TANDEM_ACTION_EVENT_T_FAULT_CLEARED, "");
            fprintf(stderr, "%s: fault cleared\n", d->name);
        }
    }
    if (!C.fault)
        return 0;
    d->safe_hold = 1;
    snprintf(d->status, sizeof d->status, "safe hold: joint FAULT");
    send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
    return 1;
}

static void cycle(daemon *d, void *user)
{
    double q_d[ARM_NJ], qd_d[ARM_NJ] = { 0 }, qdd_d[ARM_NJ] = { 0 }, tau[ARM_NJ];
    arm_payload payload;
    const arm_payload *pl;
    (void)user;
    if (!C.have_state || (d->lockstep && C.st.step != d->pending_step)) {
        /* lockstep: join once the first state is here; a state lost on the
         * way is waited for (the simulator announces the step again) rather
         * than answered from the previous one, which would break determinism */
        d->skip_ack = 1;
        return;
    }
    if (state_stale(d)) {
        if (C.have_state)
            d->msgs.stale++;
        d->safe_hold = 1;
        snprintf(d->status, sizeof d->status, "safe hold: state stale");
        send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return;
    }
    d->safe_hold = 0;
    if (d->lockstep && have_row_pending && row_pending.step < d->pending_step)
        row_take(d);
    if (d->lockstep)
        partner_at(d->pending_step);
    if (joint_fault(d) || tdsd_cycle(d) || cart_cycle(d) || (cart_fallback_cycle(d, 0) && cart_cycle(d)))
        return;
    memcpy(q_d, C.hold_q, sizeof q_d);
    if (C.running) {
        if (C.cur_seg < 0)
            start_segment(d);
        if (C.running && segment_reference(q_d, qd_d, qdd_d)) {
            cart_fallback_cycle(d, 1);
            start_segment(d);
            if (C.running)
                segment_reference(q_d, qd_d, qdd_d);
        }
    } else if (joint_ref_fresh(d)) {
        memcpy(q_d, JR.ref.q_rad, sizeof q_d);
        memcpy(qd_d, JR.ref.qd_radps, sizeof qd_d);
        memcpy(qdd_d, JR.ref.qdd_radps2, sizeof qdd_d);
        servo_vlimit(q_d, qd_d, qdd_d);
    }
    /* the held bar as the Cartesian law models it: a joint move that
     * finishes a Cartesian segment must meet the joint done tolerance */
    pl = cart_payload(&payload);
    if (jointctl_torque(C.model, pl, &C.gains, C.st.q_rad, C.st.qd_radps, q_d, qd_d, qdd_d, tau, NULL) != 0) {
        send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return;
    }
    snprintf(d->status, sizeof d->status, C.running ? "action %d segment %d" : "holding",
             (int)C.action_id, C.cur_seg);
    send_command(d, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
    /* idle: say so at 10 Hz, with the last row finished, so a supervisor
     * that lost a DONE (or restarted) knows where this arm stands */
    if (!C.running && C.status_cycles++ % (int64_t)(0.1 / d->period_s + 0.5) == 0)
        publish_event(d, TANDEM_ACTION_EVENT_T_STATUS, "idle");
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        { "arm", required_argument, 0, 'a' },
        { "wn", required_argument, 0, 'w' },
        { "stale-ms", required_argument, 0, 's' },
        { "speed-frac", required_argument, 0, 'f' },
        { "arm-model", required_argument, 0, 'm' },
        { "block-detect", required_argument, 0, 'B' },
        DAEMON_COMMON_OPTIONS,
        { 0, 0, 0, 0 }
    };
    daemon d;
    int c, rc;
    long arm = 0;
    double hz = 8.0, ms = 20.0;
    char name[32];
    memset(&C, 0, sizeof C);
    C.speed_frac = 0.5;
    C.block_detect = 1;
    daemon_defaults(&d, "tandem-arm", 0.001);
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        rc = daemon_parse_common(&d, c, optarg);
        if (rc == 2) { usage(); return 0; }
        if (rc < 0) return 2;
        if (rc == 1) continue;
        switch (c) {
        case 'a': if (parse_int_opt("tandem-arm", "--arm", optarg, 1, 2, &arm) < 0) return 2; break;
        case 'w': if (parse_double_opt("tandem-arm", "--wn", optarg, 0.5, 50.0, &hz) < 0) return 2; break;
        case 's': if (parse_double_opt("tandem-arm", "--stale-ms", optarg, 1.0, 1000.0, &ms) < 0) return 2; break;
        case 'f': if (parse_double_opt("tandem-arm", "--speed-frac", optarg, 0.01, 1.0, &C.speed_frac) < 0) return 2; break;
        case 'm':
            if (!(C.model = arm_model_by_name(optarg))) {
                fprintf(stderr, "tandem-arm: --arm-model: '%s' is not puma560|seed002\n", optarg);
                return 2;
            }
            break;
        case 'B':
            if (strcmp(optarg, "on") && strcmp(optarg, "off")) {
                fprintf(stderr, "tandem-arm: --block-detect: '%s' is not on|off\n", optarg);
                return 2;
            }
            C.block_detect = !strcmp(optarg, "on");
            break;
        default: usage(); return 2;
        }
    }
    if (optind < argc || arm == 0) {
        fprintf(stderr, "tandem-arm: %s\n", arm == 0 ? "--arm 1|2 is required" : "unexpected argument");
        return 2;
    }
    C.arm = (int)arm;
    if (!C.model)
        C.model = &arm_model_puma560;
    C.gains.wn_radps = 6.283185307179586 * hz;
    C.gains.zeta = 1.0;
    C.stale_s = ms * 1e-3;
    step_gate_init(&state_gate, 1000, 1000000000LL);
    snprintf(name, sizeof name, "tandem-arm-%d", C.arm);
    snprintf(d.name, sizeof d.name, "%s", name);
    snprintf(C.state_ch, sizeof C.state_ch, "ARM%d_STATE", C.arm);
    snprintf(C.cmd_ch, sizeof C.cmd_ch, "ARM%d_COMMAND", C.arm);
    snprintf(C.action_ch, sizeof C.action_ch, "ARM%d_ACTION", C.arm);
    auth_bus_identity(AUTH_ROLE_ARM, C.arm, C.arm);
    if (daemon_start(&d) != 0)
        return 1;
    daemon_subscribe(&d, "ARM_EVENTS", cart_on_event, &d);
    daemon_subscribe(&d, C.state_ch, on_state, &d);
    daemon_subscribe(&d, C.action_ch, on_action, &d);
    snprintf(JR.ch, sizeof JR.ch, "ARM%d_JOINT_REF", C.arm);
    daemon_subscribe(&d, JR.ch, on_joint_ref, &d);
    rc = daemon_run(&d, cycle, NULL);
    daemon_finish(&d);
    return rc;
}

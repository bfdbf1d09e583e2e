/* supervisor_rows: tandem-supervisor's transitions and the arms' work:
 * each running transition's rows out on ARMk_ACTION (the poses resolved
 * from the cell layout and the detection), the arms' events in on
 * ARM_EVENTS (DONE completes a transition), and the recovery of rows lost
 * on the way or finished without their DONE.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "supervisor_daemon.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_action_row_t.h"

#define CLEAR_BACKOFF_M 0.10
#define RELEASE_LIFT_M 0.003 /* put the bar down from 3 mm */
#define ROW_RESEND_STEPS 300 /* an arm idle this long after a row was sent lost it */

/* ---- poses ---------------------------------------------------------------- */

/* Arm a's (0-based) grasp point on a bar centred at c with yaw. */
static void grasp_on_bar(int a, const double c[3], double yaw, double p[3])
{
    const double s = (a == 0 ? -1.0 : 1.0) * cell_default.grasp_offset_m;
    p[0] = c[0] + s * cos(yaw);
    p[1] = c[1] + s * sin(yaw);
    p[2] = c[2];
}

/* The poses at the stand's two places: on which place (0 the hand-over,
 * 1 place B), how high above it; the grasp point is that of the pose's
 * arm (carry_pose_arm). */
typedef struct {
    int pose, place;
    double lift_m;
} stand_pose;

static const stand_pose stand_poses[] = {
    { CARRY_POSE_HANDOVER_1, 0, 0.0 },
    { CARRY_POSE_HANDOVER_2, 0, 0.0 },
    { CARRY_POSE_ABOVE_HANDOVER_1, 0, CELL_STAND_CLEARANCE_M },
    { CARRY_POSE_ABOVE_HANDOVER_2, 0, CELL_STAND_CLEARANCE_M },
    { CARRY_POSE_STAND_B_1, 1, 0.0 },
    { CARRY_POSE_STAND_B_2, 1, 0.0 },
    { CARRY_POSE_ABOVE_STAND_B_1, 1, CELL_STAND_CLEARANCE_M },
    { CARRY_POSE_ABOVE_STAND_B_2, 1, CELL_STAND_CLEARANCE_M },
};
#define N_STAND_POSES ((int)(sizeof stand_poses / sizeof stand_poses[0]))

int sup_stand_poses_validate(void)
{
    int i, k;
    for (i = 0; i < N_STAND_POSES; i++) {
        const stand_pose *s = &stand_poses[i];
        if (carry_pose_arm(s->pose) < 0 || s->place < 0 || s->place > 1 || !(s->lift_m >= 0.0))
            return SUPERVISOR_ERR_POSE;
        for (k = 0; k < i; k++)
            if (stand_poses[k].pose == s->pose)
                return SUPERVISOR_ERR_POSE;
    }
    return 0;
}

static const double *stand_place_m(const cell_layout *c, int place)
{
    return place == 0 ? c->handover_center_m : c->stand_b_center_m;
}

/* A stand pose's point; 0, or -1 if pose is not one. */
static int stand_pose_point(int pose, double p[3])
{
    const cell_layout *c = &cell_default;
    int i;
    for (i = 0; i < N_STAND_POSES; i++) {
        const stand_pose *s = &stand_poses[i];
        if (s->pose != pose)
            continue;
        cell_grasp_point(c, carry_pose_arm(pose), stand_place_m(c, s->place), p);
        p[2] += s->lift_m;
        return 0;
    }
    return -1;
}

static int resolve_pose(const supervisor_daemon *sv, int pose, double p[3])
{
    const cell_layout *c = &cell_default;
    if (stand_pose_point(pose, p) == 0)
        return 0;
    switch (pose) {
    case CARRY_POSE_HOME_1: vec3_copy(p, c->home_tool_m[0]); return 0;
    case CARRY_POSE_HOME_2: vec3_copy(p, c->home_tool_m[1]); return 0;
    case CARRY_POSE_ABOVE_WORKPIECE:
    case CARRY_POSE_AT_WORKPIECE:
        grasp_on_bar(0, sv->pick_pos_m, sv->pick_yaw_rad, p);
        if (pose == CARRY_POSE_ABOVE_WORKPIECE)
            p[2] += c->approach_height_m;
        return 0;
    case CARRY_POSE_CLEAR_1:
    case CARRY_POSE_CLEAR_B_1:
        cell_grasp_point(c, 0, stand_place_m(c, pose == CARRY_POSE_CLEAR_1 ? 0 : 1), p);
        p[0] -= CLEAR_BACKOFF_M;
        return 0;
    case CARRY_POSE_ABOVE_MAGAZINE:
    case CARRY_POSE_AT_MAGAZINE:
        cell_grasp_point(c, 1, c->magazine_center_m, p);
        if (pose == CARRY_POSE_ABOVE_MAGAZINE)
            p[2] += c->approach_height_m;
        return 0;
    case CARRY_POSE_ABOVE_RELEASE:
    case CARRY_POSE_RELEASE_POSE:
        cell_grasp_point(c, 1, c->deliver_center_m, p);
        p[2] += pose == CARRY_POSE_ABOVE_RELEASE ? c->approach_height_m : RELEASE_LIFT_M;
        return 0;
    default: return SUPERVISOR_ERR_POSE;
    }
}

/* ---- rows out ------------------------------------------------------------- */

static void send_row(supervisor_daemon *sv, int t, int a)
{
    const carry_row *r = sup_row(sv, t);
    const carry_arm_plan *pl = &r->plan[a];
    tandem_action_segment_t seg[CARRY_MAX_SEGMENTS];
    tandem_action_row_t row;
    int i;
    if (sup_holding(sv))
        return; /* the journal cannot be written: the slot waits as it is (sup_recover_rows) */
    memset(&row, 0, sizeof row);
    memset(seg, 0, sizeof seg);
    for (i = 0; i < pl->n_segments; i++) {
        seg[i].kind = pl->seg[i].kind;
        /* tool-down in the world: flange x = world x, z = -world z */
        seg[i].orientation_quat[0] = 0.0;
        seg[i].orientation_quat[1] = 1.0;
        if (pl->seg[i].kind == CARRY_SEG_MOVE)
            resolve_pose(sv, pl->seg[i].pose, seg[i].position_m);
    }
    row.seq = sv->row_seq++;
    row.utime = daemon_utime_now();
    row.step = sv->d.step;
    row.action_id = sv->next_action_id++;
    row.transition = t + 1;
    row.arm = (int8_t)(a + 1);
    row.controller = (int8_t)sv->controller;
    row.use_tdsd = (int8_t)sv->use_tdsd;
    /* a synchronised row sent again after its partner finished its part:
     * there is no partner progress left to share (the partner says nothing
     * more once done), so the arm finishes alone; synchronised, it waited
     * at s* = 0 for good (arm 1 restarted 7 mm before the hand-over) */
    row.sync_group = sv->slot[t].state[1 - a] == ARM_SLOT_DONE ? 0 : r->sync_group;
    row.workpiece_id = sv->pick_id;
    row.v_m = r->lin.v_m;
    row.a_m = r->lin.a_m;
    row.u_m = r->lin.u_m;
    row.k_p = r->lin.k_p;
    row.k_v = r->lin.k_v;
    row.k0 = r->lin.k0;
    row.k1 = r->lin.k1;
    row.k2 = r->lin.k2;
    row.n_segments = pl->n_segments;
    row.segments = seg;
    sv->slot[t].state[a] = ARM_SLOT_SENT;
    sv->slot[t].action_id[a] = row.action_id;
    sv->slot[t].sent_step[a] = sv->d.step;
    sv->dirty = 1;
    AUTH_PUBLISH(tandem_action_row_t, &sv->d.bus, sv->d.lcm, a == 0 ? "ARM1_ACTION" : "ARM2_ACTION",
                 &row);
    printf("[%9.3f] t%d %-46s row %d -> arm %d\n", sv->d.sim_time_s, t + 1, "", (int)row.action_id,
           a + 1);
}

static void log_fire(const supervisor_daemon *sv, int t, const char *what)
{
    const carry_row *r = sup_row(sv, t);
    int i;
    printf("[%9.3f] %s %s  marking [", sv->d.sim_time_s, what, r ? r->name : "?");
    for (i = 0; i < sv->pn->n_places; i++)
        printf("%s%d", i ? " " : "", sv->net.st.m[i]);
    printf("] workpiece %d\n", (int)sv->wp_id);
    fflush(stdout);
}

void sup_start_transition(supervisor_daemon *sv, int t)
{
    const carry_row *r = sup_row(sv, t);
    int a;
    if (petri_start(&sv->net, t) != 0)
        return;
    sv->changed = 1;
    sv->dirty = 1;
    log_fire(sv, t, "start   ");
    memset(&sv->slot[t], 0, sizeof sv->slot[t]);
    for (a = 0; a < 2; a++) {
        if (!(r->arms & (a == 0 ? CARRY_ARM1 : CARRY_ARM2)) || r->plan[a].n_segments == 0)
            continue;
        sv->slot[t].state[a] = r->plan[a].after_partner ? ARM_SLOT_WAITING : ARM_SLOT_SENT;
    }
    for (a = 0; a < 2; a++)
        if (sv->slot[t].state[a] == ARM_SLOT_SENT)
            send_row(sv, t, a);
}

static void complete_transition(supervisor_daemon *sv, int t)
{
    if (petri_complete(&sv->net, t) != 0)
        return;
    sv->changed = 1;
    sv->dirty = 1;
    sv->completed = 1;
    sv->last_fired = t + 1;
    log_fire(sv, t, "complete");
}

/* ---- events in ------------------------------------------------------------ */

static void handle_event_row(supervisor_daemon *sv, const tandem_action_event_t *e);

static void see_arm(supervisor_daemon *sv, const tandem_action_event_t *e)
{
    arm_view *v = &sv->arm[e->arm - 1];
    if (v->heard && e->step < v->step)
        return; /* older than what we know */
    v->heard = 1;
    v->step = e->step;
    v->rx_ns = rtloop_now_ns();
    v->running = e->running != 0;
    v->action_id = e->action_id;
    v->last_done = e->last_done_action_id;
    v->holding = e->holding_workpiece;
}

void sup_on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    supervisor_daemon *sv = u;
    tandem_action_event_t e;
    (void)ch;
    if (!DAEMON_DECODE(&sv->d.msgs, tandem_action_event_t, rb, &e))
        return;
    if (e.arm < 1 || e.arm > 2 || e.transition < 0 || e.transition > sv->pn->n_transitions ||
        !isfinite(e.s_m) || !isfinite(e.s_f_m) || e.action_id < 0 || e.last_done_action_id < 0) {
        sv->d.msgs.rejected++;
    } else if (e.event == TANDEM_ACTION_EVENT_T_PROGRESS ||
               e.event == TANDEM_ACTION_EVENT_T_STARTED) {
        arm_view *v = &sv->arm[e.arm - 1];
        if (e.step > v->alive_step) {
            v->alive_step = e.step;
            v->alive_rx_ns = rtloop_now_ns();
        }
    } else if (sv->n_ev < EVENT_QUEUE) {
        sv->evq[sv->n_ev] = e;
        sv->evq[sv->n_ev].detail = NULL;
        sv->n_ev++;
    }
    tandem_action_event_t_decode_cleanup(&e);
}

static void handle_event(supervisor_daemon *sv, const tandem_action_event_t *e)
{
    see_arm(sv, e);
    handle_event_row(sv, e);
}

static void handle_event_row(supervisor_daemon *sv, const tandem_action_event_t *e)
{
    const int a = e->arm - 1, n = sv->pn->n_transitions;
    int t;
    for (t = 0; t < n; t++)
        if (t != sv->roles.source && petri_running(&sv->net, t) &&
            sv->slot[t].state[a] == ARM_SLOT_SENT && sv->slot[t].action_id[a] == e->action_id)
            break;
    if (e->event == TANDEM_ACTION_EVENT_T_BLOCKED) {
        sv->blockages++;
        sv->dirty = 1; /* a counter summary.json reports: kept over a restart */
        printf("[%9.3f] arm %d BLOCKED in t%d (s = %.3f of %.3f m)\n", sv->d.sim_time_s, a + 1,
               e->transition, e->s_m, e->s_f_m);
        return;
    }
    if (e->event == TANDEM_ACTION_EVENT_T_UNBLOCKED) {
        printf("[%9.3f] arm %d unblocked in t%d\n", sv->d.sim_time_s, a + 1, e->transition);
        return;
    }
    if (e->event == TANDEM_ACTION_EVENT_T_FAULT ||
        e->event == TANDEM_ACTION_EVENT_T_FAULT_CLEARED) {
        const int on = e->event == TANDEM_ACTION_EVENT_T_FAULT;
        sv->faults += on;
        sv->dirty = 1;
        sv->arms_faulted = on ? (sv->arms_faulted | 1 << a) : (sv->arms_faulted & ~(1 << a));
        sv->changed = 1;
        printf("[%9.3f] arm %d %s in t%d\n", sv->d.sim_time_s, a + 1,
               on ? "FAULT (safe hold)" : "fault cleared", e->transition);
        return;
    }
    if (t == n)
        return; /* not an action of ours (or already handled) */
    if (e->event == TANDEM_ACTION_EVENT_T_REJECTED) {
        sv->replans++;
        printf("[%9.3f] arm %d REJECTED the row of t%d: re-sending\n", sv->d.sim_time_s, a + 1,
               t + 1);
        send_row(sv, t, a);
        return;
    }
    if (e->event != TANDEM_ACTION_EVENT_T_DONE)
        return;
    sv->slot[t].state[a] = ARM_SLOT_DONE;
    if (sv->slot[t].state[1 - a] == ARM_SLOT_WAITING)
        send_row(sv, t, 1 - a);
    if (sv->slot[t].state[1 - a] != ARM_SLOT_SENT && sv->slot[t].state[1 - a] != ARM_SLOT_WAITING)
        complete_transition(sv, t);
}

/* The queued arm events, in arrival order; in lockstep only those sent
 * before the step this cycle answers (an arm answering the same step may
 * or may not have been heard yet), the rest wait for the next cycle. */
void sup_handle_events(supervisor_daemon *sv)
{
    int i, kept = 0;
    for (i = 0; i < sv->n_ev; i++) {
        if (sv->d.lockstep && sv->evq[i].step >= sv->d.pending_step) {
            sv->evq[kept++] = sv->evq[i];
            continue;
        }
        handle_event(sv, &sv->evq[i]);
    }
    sv->n_ev = kept;
}

/* ---- recovery ---------------------------------------------------------------- */

/* A row sent to arm a that the arm finished (its DONE lost) completes from
 * the arm's own word; one it is not running long after it was sent was
 * lost (the arm restarted, or the row never arrived): sent again. */
void sup_recover_rows(supervisor_daemon *sv)
{
    int t, a;
    for (t = 0; t < sv->pn->n_transitions; t++) {
        if (t == sv->roles.source || !petri_running(&sv->net, t))
            continue;
        for (a = 0; a < 2; a++) {
            const arm_view *v = &sv->arm[a];
            const int32_t id = sv->slot[t].action_id[a];
            /* a partner row held back while the journal could not be written */
            if (sv->slot[t].state[a] == ARM_SLOT_WAITING &&
                sv->slot[t].state[1 - a] == ARM_SLOT_DONE && !sup_holding(sv)) {
                send_row(sv, t, a);
                continue;
            }
            if (sv->slot[t].state[a] != ARM_SLOT_SENT || !v->heard)
                continue;
            if (v->last_done == id) {
                tandem_action_event_t e;
                memset(&e, 0, sizeof e);
                e.arm = (int8_t)(a + 1);
                e.event = TANDEM_ACTION_EVENT_T_DONE;
                e.action_id = id;
                e.transition = t + 1;
                sv->dones_recovered++;
                printf("[%9.3f] arm %d finished row %d of t%d (its DONE was lost)\n",
                       sv->d.sim_time_s, a + 1, (int)id, t + 1);
                handle_event_row(sv, &e);
            } else if (!v->running && v->step - sv->slot[t].sent_step[a] > ROW_RESEND_STEPS) {
                sv->rows_reissued++;
                printf(
                    "[%9.3f] arm %d is not running row %d of t%d (restarted, or the row was lost): sending it again\n",
                    sv->d.sim_time_s, a + 1, (int)id, t + 1);
                send_row(sv, t, a);
            }
        }
    }
}

/* A transition whose row grasps with arm a must not start while arm a
 * reports a workpiece in its gripper (after a restart without journal). */
int sup_grasp_blocked(const supervisor_daemon *sv, int t)
{
    const carry_row *r = sup_row(sv, t);
    int a, i;
    for (a = 0; a < 2; a++)
        for (i = 0; i < r->plan[a].n_segments; i++)
            if (r->plan[a].seg[i].kind == CARRY_SEG_GRASP && sv->arm[a].heard &&
                sv->arm[a].holding >= 0)
                return 1;
    return 0;
}

/* Real time: 1 s of wall time without a word. Lockstep: 1 s of simulated
 * time (the whole cell pauses together there, so wall time says nothing;
 * a simulator that stops sends no clock and the shell's health says so). */

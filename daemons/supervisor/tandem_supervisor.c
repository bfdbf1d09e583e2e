/* tandem-supervisor: the discrete-event controller of the carry task
 * ("MVME162", SPEC.md §2.4, §2.5).
 *
 * Holds the carry Petri net and its lookup table (carry_net). At start-up
 * it explores the net's reachability graph and refuses to run (exit 1,
 * printing the offending marking and the event path to it) if the net is
 * unsafe, unbounded, violates a P-invariant or can deadlock.
 *
 * Running: a vision detection in the pick zone puts a token in p1 only
 * while p1 is empty (the source transition with its inhibitor arc); every
 * enabled transition t1..t7 starts at once (its input tokens are taken)
 * and its row goes to the arm(s) on ARMk_ACTION, with the poses resolved
 * from the cell layout and the detection; an arm's plan marked
 * after_partner (t4: arm 1 releases only once arm 2 holds) is sent when
 * the partner's DONE arrives. When every arm of a transition has reported
 * DONE on ARM_EVENTS, the transition completes (its output tokens are
 * added). The marking goes out on PETRI_MARKING on every change and at
 * 10 Hz; every start and completion is logged on stdout.
 *
 * Watchdogs: an arm's FAULT event (joint out of range or over speed; the
 * arm holds on its brakes) is logged and shown in the marking message
 * until FAULT_CLEARED. A stall -- work pending, nothing completed for
 * --stall-s seconds while the stick is out (SIM_STATUS) -- is logged once,
 * flagged in PETRI_MARKING and in the health status (stallwatch).
 *
 * Recovery: with --journal PATH every change of the discrete state (marking,
 * running rows, the workpieces bound to tokens, action ids) is appended to
 * PATH and flushed; a supervisor started on an existing journal takes the
 * last snapshot back (unless it is from a later step than the simulator:
 * another run). The arms say what they are doing in every event, and at
 * 10 Hz when idle (STATUS: last row finished, holding): a row an arm
 * finished whose DONE never came completes from it; a row an arm is not
 * running 0.3 s after it was sent (the arm restarted, or the row was lost)
 * is sent again; a transition that grasps never starts for an arm that
 * already holds a workpiece. An arm or the simulator silent for 1 s of
 * wall time is shown (PETRI_MARKING, health status).
 *
 * --serial is the no-overlap reference for the pipelining figure: a new
 * workpiece is taken only when the previous one is delivered and both arms
 * are home with nothing running.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "journal.h"
#include "carry_net.h"
#include "cell.h"
#include "petri.h"
#include "stallwatch.h"
#include "vec3.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_petri_marking_t.h"
#include "tandem_sim_status_t.h"
#include "tandem_workpiece_detections_t.h"

#define PICK_ACCEPT_RADIUS_M 0.15
#define CLEAR_BACKOFF_M 0.10
#define RELEASE_LIFT_M 0.003        /* put the bar down from 3 mm */
#define EVENT_QUEUE 64
#define ROW_RESEND_STEPS 300        /* an arm idle this long after a row was sent lost it */
#define SILENT_NS 1000000000LL      /* wall time without a word: arm or simulator silent */
#define SILENT_STEPS 1000           /* the same in lockstep, in simulated steps */

enum { ARM_SLOT_NONE = 0, ARM_SLOT_WAITING, ARM_SLOT_SENT, ARM_SLOT_DONE };

typedef struct sup_slot {
    int     state[2];               /* ARM_SLOT_* per arm */
    int32_t action_id[2];
    int64_t sent_step[2];
} sup_slot;

/* What an arm last said about itself (its events and idle STATUS). */
typedef struct arm_view {
    int     heard;
    int64_t step, rx_ns;
    /* liveness from PROGRESS too (a running arm sends no STATUS; its
     * PROGRESS is not queued as an event): the newest step and wall time */
    int64_t alive_step, alive_rx_ns;
    int     running;
    int32_t action_id, last_done, holding;
} arm_view;

typedef struct supervisor {
    petri   net;
    sup_slot slot[CARRY_N_TRANSITIONS];
    int     controller;             /* action_row_t CONTROLLER_* */
    int     serial;
    int     use_tdsd;               /* --tdsd: rows ask for TDSD Cartesian moves */
    /* workpiece of the current cycle (p1 .. t2) and the one being carried */
    int32_t wp_id;
    double  wp_pos_m[3], wp_yaw_rad;
    int32_t last_taken_id;
    double  pick_pos_m[3], pick_yaw_rad;   /* latched when t1 takes p1 */
    int32_t pick_id;
    int     have_detection;
    int     p1_bound;               /* the p1 token has a detected pose */
    tandem_workpiece_t det;
    /* events queued by the LCM callback, handled in the cycle */
    tandem_action_event_t evq[EVENT_QUEUE];
    int     n_ev;
    int32_t next_action_id;
    int64_t row_seq, marking_seq;
    int64_t cycles;
    int     changed;
    int32_t deadlocks, replans, detections, blockages;
    int     was_dead;
    int     last_fired;
    /* watchdogs */
    stallwatch stall;
    int     completed;              /* a transition completed this cycle */
    int     stick_in;               /* SIM_STATUS: an obstruction is in the cell */
    int     arms_faulted;           /* bit a: arm a+1 in FAULT */
    int32_t faults;
    /* recovery */
    arm_view arm[2];
    int64_t sim_rx_ns;
    int     arms_silent, sim_silent;
    int32_t rows_reissued, dones_recovered;
    int     resumed, journal_checked;
    const char *journal_path;
    journal jr;
    int     dirty;                  /* the discrete state changed: journal it */
} supervisor;

static supervisor S;
static petri_explore_ws explore_ws;

static void usage(void)
{
    printf("usage: tandem-supervisor [options]\n"
           "Petri-net supervisor of the two-arm carry (SPEC 2.4-2.5): vision tokens,\n"
           "lookup-table rows to the arms, completion events, marking at 10 Hz.\n\n"
           "  --controller event|time  arms run the event-referenced law (default) or\n"
           "                    the time-referenced baseline\n"
           "  --serial          take a new workpiece only when the previous one is\n"
           "                    delivered and both arms are home (no pipelining)\n"
           "  --tdsd            rows set use_tdsd: the arms resolve unsynchronised\n"
           "                    Cartesian moves by TDSD (passes near singular poses)\n"
           "  --stall-s S       a stall: work pending and no transition completed for\n"
           "                    S s of simulated time while the stick is out (default 30)\n"
           "  --journal PATH    append the discrete state to PATH on every change; start\n"
           "                    from its last snapshot when PATH exists (restart)\n"
           DAEMON_COMMON_HELP);
}

/* ---- start-up check ------------------------------------------------------- */

static void print_offender(const char *what, int index)
{
    int8_t ev[256];
    int n, i;
    const petri_state *s = &explore_ws.states[index];
    printf("tandem-supervisor: the carry net %s; offending marking [", what);
    for (i = 0; i < carry_net.n_places; i++)
        printf("%s%d", i ? " " : "", s->m[i]);
    printf("] running 0x%x\n  reached by:", (unsigned)s->running);
    n = petri_explore_trace(&explore_ws, index, ev, (int)sizeof ev);
    for (i = 0; i < n; i++)
        printf(" %s t%d", ev[i] > 0 ? "start" : "complete", abs(ev[i]));
    printf("\n");
}

static int check_net(void)
{
    petri_report r;
    if (petri_explore(&explore_ws, &carry_net, 2, &r) != 0) {
        printf("tandem-supervisor: the carry net tables are invalid\n");
        return -1;
    }
    if (!r.complete) {
        printf("tandem-supervisor: reachability graph exceeds %d states\n", PETRI_MAX_STATES);
        return -1;
    }
    if (!r.safe) { print_offender("is not safe", r.unsafe_index); return -1; }
    if (!r.bounded) { print_offender("is unbounded", r.unbounded_index); return -1; }
    if (r.invariant_states) { print_offender("violates a P-invariant", r.invariant_index); return -1; }
    if (r.deadlock) { print_offender("can deadlock", r.dead_index); return -1; }
    printf("tandem-supervisor: net checked: %d reachable states, safe, live, invariants hold\n", r.n_states);
    return 0;
}

/* ---- poses ---------------------------------------------------------------- */

/* Arm a's (0-based) grasp point on a bar centred at c with yaw. */
static void grasp_on_bar(int a, const double c[3], double yaw, double p[3])
{
    const double s = (a == 0 ? -1.0 : 1.0) * cell_default.grasp_offset_m;
    p[0] = c[0] + s * cos(yaw);
    p[1] = c[1] + s * sin(yaw);
    p[2] = c[2];
}

static int resolve_pose(int pose, double p[3])
{
    const cell_layout *c = &cell_default;
    double h[3];
    switch (pose) {
    case CARRY_POSE_HOME_1: vec3_copy(p, c->home_tool_m[0]); return 0;
    case CARRY_POSE_HOME_2: vec3_copy(p, c->home_tool_m[1]); return 0;
    case CARRY_POSE_ABOVE_WORKPIECE:
    case CARRY_POSE_AT_WORKPIECE:
        grasp_on_bar(0, S.pick_pos_m, S.pick_yaw_rad, p);
        if (pose == CARRY_POSE_ABOVE_WORKPIECE)
            p[2] += c->approach_height_m;
        return 0;
    case CARRY_POSE_HANDOVER_1: cell_grasp_point(c, 0, c->handover_center_m, p); return 0;
    case CARRY_POSE_HANDOVER_2: cell_grasp_point(c, 1, c->handover_center_m, p); return 0;
    case CARRY_POSE_CLEAR_1:
        cell_grasp_point(c, 0, c->handover_center_m, h);
        vec3_copy(p, h);
        p[0] -= CLEAR_BACKOFF_M;
        return 0;
    case CARRY_POSE_ABOVE_RELEASE:
    case CARRY_POSE_RELEASE_POSE:
        cell_grasp_point(c, 1, c->deliver_center_m, p);
        p[2] += pose == CARRY_POSE_ABOVE_RELEASE ? c->approach_height_m : RELEASE_LIFT_M;
        return 0;
    default:
        return -1;
    }
}

/* ---- rows out ------------------------------------------------------------- */

static void send_row(daemon *d, int t, int a)
{
    const carry_row *r = carry_row_of(t);
    const carry_arm_plan *pl = &r->plan[a];
    tandem_action_segment_t seg[CARRY_MAX_SEGMENTS];
    tandem_action_row_t row;
    int i;
    memset(&row, 0, sizeof row);
    memset(seg, 0, sizeof seg);
    for (i = 0; i < pl->n_segments; i++) {
        seg[i].kind = pl->seg[i].kind;
        /* tool-down in the world: flange x = world x, z = -world z */
        seg[i].orientation_quat[0] = 0.0;
        seg[i].orientation_quat[1] = 1.0;
        if (pl->seg[i].kind == CARRY_SEG_MOVE)
            resolve_pose(pl->seg[i].pose, seg[i].position_m);
    }
    row.seq = S.row_seq++;
    row.utime = daemon_utime_now();
    row.step = d->step;
    row.action_id = S.next_action_id++;
    row.transition = t + 1;
    row.arm = (int8_t)(a + 1);
    row.controller = (int8_t)S.controller;
    row.use_tdsd = (int8_t)S.use_tdsd;
    row.sync_group = r->sync_group;
    row.workpiece_id = S.pick_id;
    row.v_m = r->lin.v_m; row.a_m = r->lin.a_m; row.u_m = r->lin.u_m;
    row.k_p = r->lin.k_p; row.k_v = r->lin.k_v;
    row.k0 = r->lin.k0; row.k1 = r->lin.k1; row.k2 = r->lin.k2;
    row.n_segments = pl->n_segments;
    row.segments = seg;
    S.slot[t].state[a] = ARM_SLOT_SENT;
    S.slot[t].action_id[a] = row.action_id;
    S.slot[t].sent_step[a] = d->step;
    S.dirty = 1;
    AUTH_PUBLISH(tandem_action_row_t, d->lcm, a == 0 ? "ARM1_ACTION" : "ARM2_ACTION", &row);
    printf("[%9.3f] t%d %-46s row %d -> arm %d\n", d->sim_time_s, t + 1, "", (int)row.action_id, a + 1);
}

static void log_fire(const daemon *d, int t, const char *what)
{
    const carry_row *r = carry_row_of(t);
    int i;
    printf("[%9.3f] %s %s  marking [", d->sim_time_s, what, r ? r->name : "?");
    for (i = 0; i < CARRY_N_PLACES; i++)
        printf("%s%d", i ? " " : "", S.net.st.m[i]);
    printf("] workpiece %d\n", (int)S.wp_id);
    fflush(stdout);
}

static void start_transition(daemon *d, int t)
{
    const carry_row *r = carry_row_of(t);
    int a;
    if (petri_start(&S.net, t) != 0)
        return;
    S.changed = 1;
    S.dirty = 1;
    log_fire(d, t, "start   ");
    memset(&S.slot[t], 0, sizeof S.slot[t]);
    for (a = 0; a < 2; a++) {
        if (!(r->arms & (a == 0 ? CARRY_ARM1 : CARRY_ARM2)) || r->plan[a].n_segments == 0)
            continue;
        S.slot[t].state[a] = r->plan[a].after_partner ? ARM_SLOT_WAITING : ARM_SLOT_SENT;
    }
    for (a = 0; a < 2; a++)
        if (S.slot[t].state[a] == ARM_SLOT_SENT)
            send_row(d, t, a);
}

static void complete_transition(daemon *d, int t)
{
    if (petri_complete(&S.net, t) != 0)
        return;
    S.changed = 1;
    S.dirty = 1;
    S.completed = 1;
    S.last_fired = t + 1;
    log_fire(d, t, "complete");
}

/* ---- events in ------------------------------------------------------------ */

static void handle_event_row(daemon *d, const tandem_action_event_t *e);

static void see_arm(const tandem_action_event_t *e)
{
    arm_view *v = &S.arm[e->arm - 1];
    if (v->heard && e->step < v->step)
        return;                     /* older than what we know */
    v->heard = 1;
    v->step = e->step;
    v->rx_ns = rtloop_now_ns();
    v->running = e->running != 0;
    v->action_id = e->action_id;
    v->last_done = e->last_done_action_id;
    v->holding = e->holding_workpiece;
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_action_event_t e;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_action_event_t, rb, &e))
        return;
    if (e.arm < 1 || e.arm > 2 || e.transition < 0 || e.transition > CARRY_N_TRANSITIONS ||
        !isfinite(e.s_m) || !isfinite(e.s_f_m) || e.action_id < 0 || e.last_done_action_id < 0) {
        d->msgs.rejected++;
    } else if (e.event == TANDEM_ACTION_EVENT_T_PROGRESS || e.event == TANDEM_ACTION_EVENT_T_STARTED) {
        arm_view *v = &S.arm[e.arm - 1];
        if (e.step > v->alive_step) {
            v->alive_step = e.step;
            v->alive_rx_ns = rtloop_now_ns();
        }
    } else if (S.n_ev < EVENT_QUEUE) {
        S.evq[S.n_ev] = e;
        S.evq[S.n_ev].detail = NULL;
        S.n_ev++;
    }
    tandem_action_event_t_decode_cleanup(&e);
}

static void handle_event(daemon *d, const tandem_action_event_t *e)
{
    see_arm(e);
    handle_event_row(d, e);
}

static void handle_event_row(daemon *d, const tandem_action_event_t *e)
{
    const int a = e->arm - 1;
    int t;
    for (t = 0; t < CARRY_T_VISION; t++)
        if (petri_running(&S.net, t) && S.slot[t].state[a] == ARM_SLOT_SENT && S.slot[t].action_id[a] == e->action_id)
            break;
    if (e->event == TANDEM_ACTION_EVENT_T_BLOCKED) {
        S.blockages++;
        printf("[%9.3f] arm %d BLOCKED in t%d (s = %.3f of %.3f m)\n", d->sim_time_s, a + 1, e->transition, e->s_m, e->s_f_m);
        return;
    }
    if (e->event == TANDEM_ACTION_EVENT_T_UNBLOCKED) {
        printf("[%9.3f] arm %d unblocked in t%d\n", d->sim_time_s, a + 1, e->transition);
        return;
    }
    if (e->event == TANDEM_ACTION_EVENT_T_FAULT || e->event == TANDEM_ACTION_EVENT_T_FAULT_CLEARED) {
        const int on = e->event == TANDEM_ACTION_EVENT_T_FAULT;
        S.faults += on;
        S.arms_faulted = on ? (S.arms_faulted | 1 << a) : (S.arms_faulted & ~(1 << a));
        S.changed = 1;
        printf("[%9.3f] arm %d %s in t%d\n", d->sim_time_s, a + 1, on ? "FAULT (safe hold)" : "fault cleared",
               e->transition);
        return;
    }
    if (t == CARRY_T_VISION)
        return;   /* not an action of ours (or already handled) */
    if (e->event == TANDEM_ACTION_EVENT_T_REJECTED) {
        S.replans++;
        printf("[%9.3f] arm %d REJECTED the row of t%d: re-sending\n", d->sim_time_s, a + 1, t + 1);
        send_row(d, t, a);
        return;
    }
    if (e->event != TANDEM_ACTION_EVENT_T_DONE)
        return;
    S.slot[t].state[a] = ARM_SLOT_DONE;
    if (S.slot[t].state[1 - a] == ARM_SLOT_WAITING)
        send_row(d, t, 1 - a);
    if (S.slot[t].state[1 - a] != ARM_SLOT_SENT && S.slot[t].state[1 - a] != ARM_SLOT_WAITING)
        complete_transition(d, t);
}

static void on_vision(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_workpiece_detections_t m;
    int i, best = -1;
    double best_d = PICK_ACCEPT_RADIUS_M;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_workpiece_detections_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++) {
        const tandem_workpiece_t *w = &m.workpieces[i];
        double dist;
        if (!all_finite(w->position_m, 3) || !isfinite(w->yaw_rad) || fabs(w->yaw_rad) > 0.5) {
            d->msgs.rejected++;
            continue;
        }
        dist = hypot(w->position_m[0] - cell_default.pick_center_m[0], w->position_m[1] - cell_default.pick_center_m[1]);
        if (w->id > S.last_taken_id && dist < best_d) {
            best_d = dist;
            best = i;
        }
    }
    if (best >= 0) {
        S.det = m.workpieces[best];
        S.have_detection = 1;
    }
    tandem_workpiece_detections_t_decode_cleanup(&m);
}

/* p1 takes a token only while it is empty (inhibitor arc); --serial also
 * waits for the previous workpiece to be delivered and both arms home.
 * The token of gamma0 in p1 is bound to the first detection. */
static void take_detection(daemon *d)
{
    int t;
    const int bind_only = S.net.st.m[CARRY_P1] && !S.p1_bound;
    if (!S.have_detection || S.det.id <= S.last_taken_id)
        return;
    if (!bind_only && !petri_enabled(&S.net, CARRY_T_VISION))
        return;
    if (S.serial) {
        for (t = 0; t < CARRY_T_VISION; t++)
            if (petri_running(&S.net, t))
                return;
        if (!S.net.st.m[CARRY_P2] || !S.net.st.m[CARRY_P3])
            return;
    }
    if (!bind_only && petri_fire(&S.net, CARRY_T_VISION) != 0)
        return;
    S.p1_bound = 1;
    S.wp_id = S.det.id;
    S.last_taken_id = S.det.id;
    vec3_copy(S.wp_pos_m, S.det.position_m);
    S.wp_yaw_rad = S.det.yaw_rad;
    S.detections++;
    S.have_detection = 0;
    S.changed = 1;
    S.dirty = 1;
    printf("[%9.3f] vision: workpiece %d at (%.3f %.3f %.3f) yaw %.3f -> p1\n", d->sim_time_s, (int)S.wp_id,
           S.wp_pos_m[0], S.wp_pos_m[1], S.wp_pos_m[2], S.wp_yaw_rad);
}

/* ---- marking out ---------------------------------------------------------- */

static void publish_marking(daemon *d)
{
    tandem_petri_marking_t m;
    int8_t mk[CARRY_N_PLACES], run[CARRY_N_TRANSITIONS];
    int i;
    memset(&m, 0, sizeof m);
    for (i = 0; i < CARRY_N_PLACES; i++)
        mk[i] = (int8_t)S.net.st.m[i];
    for (i = 0; i < CARRY_N_TRANSITIONS; i++)
        run[i] = (int8_t)petri_running(&S.net, i);
    m.seq = S.marking_seq++;
    m.utime = daemon_utime_now();
    m.step = d->step;
    m.n_places = CARRY_N_PLACES;
    m.marking = mk;
    m.n_transitions = CARRY_N_TRANSITIONS;
    m.running = run;
    m.last_fired = S.last_fired;
    m.fired_count = S.net.fired_count;
    m.invariants_ok = (int8_t)petri_invariants_hold(&S.net);
    m.dead = (int8_t)petri_dead(&S.net);
    m.invariant_violations = S.net.invariant_violations;
    m.deadlocks = S.deadlocks;
    m.replans = S.replans;
    m.detections = S.detections;
    m.blockages = S.blockages;
    m.workpiece_id = S.wp_id;
    m.stalled = (int8_t)S.stall.stalled;
    m.since_progress_s = S.stall.idle_s;
    m.stall_limit_s = S.stall.limit_s;
    m.stalls = S.stall.stalls;
    m.arms_faulted = (int8_t)S.arms_faulted;
    m.faults = S.faults;
    m.arms_silent = (int8_t)S.arms_silent;
    m.sim_silent = (int8_t)S.sim_silent;
    m.rows_reissued = S.rows_reissued;
    m.dones_recovered = S.dones_recovered;
    m.resumed = (int8_t)S.resumed;
    AUTH_PUBLISH(tandem_petri_marking_t, d->lcm, "PETRI_MARKING", &m);
}

/* ---- watchdogs ---------------------------------------------------------------- */

static void on_sim_status(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_sim_status_t m;
    (void)ch;
    if (!DAEMON_DECODE(&d->msgs, tandem_sim_status_t, rb, &m))
        return;
    S.stick_in = m.stick_inserted != 0;
    S.sim_rx_ns = rtloop_now_ns();
    tandem_sim_status_t_decode_cleanup(&m);
}

/* Work is pending while a transition runs or one of t1..t7 may start. */
static int work_pending(void)
{
    int t;
    for (t = 0; t < CARRY_T_VISION; t++)
        if (petri_running(&S.net, t) || (petri_enabled(&S.net, t) && (t != CARRY_T1 || S.p1_bound)))
            return 1;
    return 0;
}

static void watch_stall(daemon *d)
{
    if (stallwatch_update(&S.stall, d->sim_time_s, S.completed, work_pending(), S.stick_in) == 1) {
        S.changed = 1;
        printf("[%9.3f] STALLED: work pending, no transition completed for %.1f s with the stick out\n",
               d->sim_time_s, S.stall.limit_s);
    }
    S.completed = 0;
}

/* ---- recovery ---------------------------------------------------------------- */

/* A row sent to arm a that the arm finished (its DONE lost) completes from
 * the arm's own word; one it is not running long after it was sent was
 * lost (the arm restarted, or the row never arrived): sent again. */
static void recover_rows(daemon *d)
{
    int t, a;
    for (t = 0; t < CARRY_T_VISION; t++) {
        if (!petri_running(&S.net, t))
            continue;
        for (a = 0; a < 2; a++) {
            const arm_view *v = &S.arm[a];
            const int32_t id = S.slot[t].action_id[a];
            if (S.slot[t].state[a] != ARM_SLOT_SENT || !v->heard)
                continue;
            if (v->last_done == id) {
                tandem_action_event_t e;
                memset(&e, 0, sizeof e);
                e.arm = (int8_t)(a + 1);
                e.event = TANDEM_ACTION_EVENT_T_DONE;
                e.action_id = id;
                e.transition = t + 1;
                S.dones_recovered++;
                printf("[%9.3f] arm %d finished row %d of t%d (its DONE was lost)\n", d->sim_time_s, a + 1, (int)id, t + 1);
                handle_event_row(d, &e);
            } else if (!v->running && v->step - S.slot[t].sent_step[a] > ROW_RESEND_STEPS) {
                S.rows_reissued++;
                printf("[%9.3f] arm %d is not running row %d of t%d (restarted, or the row was lost): sending it again\n",
                       d->sim_time_s, a + 1, (int)id, t + 1);
                send_row(d, t, a);
            }
        }
    }
}

/* A transition whose row grasps with arm a must not start while arm a
 * reports a workpiece in its gripper (after a restart without journal). */
static int grasp_blocked(int t)
{
    const carry_row *r = carry_row_of(t);
    int a, i;
    for (a = 0; a < 2; a++)
        for (i = 0; i < r->plan[a].n_segments; i++)
            if (r->plan[a].seg[i].kind == CARRY_SEG_GRASP && S.arm[a].heard && S.arm[a].holding >= 0)
                return 1;
    return 0;
}

/* Real time: 1 s of wall time without a word. Lockstep: 1 s of simulated
 * time (the whole cell pauses together there, so wall time says nothing;
 * a simulator that stops sends no clock and the shell's health says so). */
static void watch_silence(daemon *d)
{
    const int64_t now = rtloop_now_ns();
    int a, arms = 0, sim;
    for (a = 0; a < 2; a++) {
        const arm_view *v = &S.arm[a];
        const int64_t step = v->alive_step > v->step ? v->alive_step : v->step;
        const int64_t rx = v->alive_rx_ns > v->rx_ns ? v->alive_rx_ns : v->rx_ns;
        if (v->heard && (d->lockstep ? d->step - step > SILENT_STEPS : now - rx > SILENT_NS))
            arms |= 1 << a;
    }
    sim = !d->lockstep && S.sim_rx_ns > 0 && now - S.sim_rx_ns > SILENT_NS;
    if (arms != S.arms_silent || sim != S.sim_silent) {
        printf("[%9.3f] silent: arm 1 %s, arm 2 %s, simulator %s\n", d->sim_time_s, arms & 1 ? "SILENT" : "ok",
               arms & 2 ? "SILENT" : "ok", sim ? "SILENT" : "ok");
        fflush(stdout);
        S.changed = 1;
    }
    S.arms_silent = arms;
    S.sim_silent = sim;
}

/* ---- journal ------------------------------------------------------------------ */

#define SNAP_HEAD 25
#define SNAP_LEN  (SNAP_HEAD + CARRY_N_PLACES + 6 * CARRY_N_TRANSITIONS)
#define SNAP_VERSION 1

static int snapshot(daemon *d, double *v)
{
    int n = 0, i, a;
    v[n++] = SNAP_VERSION; v[n++] = (double)d->step;
    v[n++] = S.net.st.running; v[n++] = (double)S.net.fired_count;
    v[n++] = S.next_action_id; v[n++] = S.wp_id;
    v[n++] = S.wp_pos_m[0]; v[n++] = S.wp_pos_m[1]; v[n++] = S.wp_pos_m[2]; v[n++] = S.wp_yaw_rad;
    v[n++] = S.pick_id; v[n++] = S.pick_pos_m[0]; v[n++] = S.pick_pos_m[1]; v[n++] = S.pick_pos_m[2];
    v[n++] = S.pick_yaw_rad; v[n++] = S.last_taken_id; v[n++] = S.p1_bound; v[n++] = S.detections;
    v[n++] = S.last_fired; v[n++] = S.blockages;
    v[n++] = S.rows_reissued; v[n++] = S.dones_recovered; v[n++] = S.replans; v[n++] = S.deadlocks;
    v[n++] = S.faults;
    for (i = 0; i < CARRY_N_PLACES; i++) v[n++] = S.net.st.m[i];
    for (i = 0; i < CARRY_N_TRANSITIONS; i++)
        for (a = 0; a < 2; a++) {
            v[n++] = S.slot[i].state[a];
            v[n++] = S.slot[i].action_id[a];
            v[n++] = (double)S.slot[i].sent_step[a];
        }
    return n;
}

static int restore(const double *v)
{
    int n = SNAP_HEAD, i, a;
    petri_state st;
    memset(&st, 0, sizeof st);
    st.running = (uint32_t)v[2];
    for (i = 0; i < CARRY_N_PLACES; i++) {
        if (v[n] < 0 || v[n] > PETRI_TOKEN_MAX) return -1;
        st.m[i] = (uint8_t)v[n++];
    }
    if (petri_set_state(&S.net, &st) != 0) return -1;
    S.net.fired_count = (long)v[3];
    S.next_action_id = (int32_t)v[4]; S.wp_id = (int32_t)v[5];
    vec3_set(S.wp_pos_m, v[6], v[7], v[8]); S.wp_yaw_rad = v[9];
    S.pick_id = (int32_t)v[10]; vec3_set(S.pick_pos_m, v[11], v[12], v[13]); S.pick_yaw_rad = v[14];
    S.last_taken_id = (int32_t)v[15]; S.p1_bound = v[16] != 0; S.detections = (int32_t)v[17];
    S.last_fired = (int)v[18]; S.blockages = (int32_t)v[19];
    S.rows_reissued = (int32_t)v[20]; S.dones_recovered = (int32_t)v[21]; S.replans = (int32_t)v[22];
    S.deadlocks = (int32_t)v[23]; S.faults = (int32_t)v[24];
    for (i = 0; i < CARRY_N_TRANSITIONS; i++)
        for (a = 0; a < 2; a++) {
            S.slot[i].state[a] = (int)v[n++];
            S.slot[i].action_id[a] = (int32_t)v[n++];
            S.slot[i].sent_step[a] = (int64_t)v[n++];
        }
    return 0;
}

/* At start-up: the last snapshot of --journal, if any (checked against the
 * simulator's step in the first cycle). */
static void journal_resume(void)
{
    static double v[JOURNAL_MAX_VALUES];
    const int n = journal_load_last(S.journal_path, v, JOURNAL_MAX_VALUES);
    if (n < 0)
        return;
    if (n != SNAP_LEN || v[0] != SNAP_VERSION || restore(v) != 0) {
        fprintf(stderr, "tandem-supervisor: journal %s: last snapshot does not fit this net; starting fresh\n",
                S.journal_path);
        petri_init(&S.net, &carry_net);
        return;
    }
    S.resumed = (int)v[1] + 1;     /* the snapshot's step + 1, checked in the first cycle */
    printf("tandem-supervisor: resumed from %s (step %lld, fired %ld, next row %d)\n", S.journal_path,
           (long long)v[1], S.net.fired_count, (int)S.next_action_id);
}

static void journal_cycle(daemon *d)
{
    static double v[JOURNAL_MAX_VALUES];
    if (!S.journal_path)
        return;
    if (!S.journal_checked && d->step >= 0) {
        S.journal_checked = 1;
        if (S.resumed && d->step + 1 < S.resumed) {
            printf("tandem-supervisor: the journal is from a later step than the simulator's: another run; starting fresh\n");
            memset(S.slot, 0, sizeof S.slot);
            petri_init(&S.net, &carry_net);
            S.resumed = 0;
        }
        S.resumed = S.resumed != 0;
        S.dirty = 1;
    }
    if (S.dirty && journal_append(&S.jr, v, snapshot(d, v)) != JOURNAL_OK) {
        fprintf(stderr, "tandem-supervisor: cannot write the journal %s\n", S.journal_path);
        d->safe_hold = 1;
    }
    S.dirty = 0;
}

/* ---- the cycle ------------------------------------------------------------ */

/* The queued arm events, in arrival order; in lockstep only those sent
 * before the step this cycle answers (an arm answering the same step may
 * or may not have been heard yet), the rest wait for the next cycle. */
static void handle_events(daemon *d)
{
    int i, kept = 0;
    for (i = 0; i < S.n_ev; i++) {
        if (d->lockstep && S.evq[i].step >= d->pending_step) {
            S.evq[kept++] = S.evq[i];
            continue;
        }
        handle_event(d, &S.evq[i]);
    }
    S.n_ev = kept;
}

static int cycle(daemon *d, void *user)
{
    const int per_10hz = (int)(0.1 / d->period_s + 0.5);
    int t, dead;
    (void)user;
    handle_events(d);
    recover_rows(d);
    take_detection(d);
    for (t = 0; t < CARRY_T_VISION; t++) {
        if (!petri_enabled(&S.net, t) || (t == CARRY_T1 && !S.p1_bound) || grasp_blocked(t))
            continue;
        if (t == CARRY_T1) {
            S.p1_bound = 0;   /* t1 takes the p1 token and its pose */
            vec3_copy(S.pick_pos_m, S.wp_pos_m);
            S.pick_yaw_rad = S.wp_yaw_rad;
            S.pick_id = S.wp_id;
        }
        start_transition(d, t);
    }
    dead = petri_dead(&S.net);
    if (dead && !S.was_dead) {
        S.deadlocks++;
        printf("[%9.3f] DEAD marking reached\n", d->sim_time_s);
    }
    S.was_dead = dead;
    watch_stall(d);
    watch_silence(d);
    journal_cycle(d);
    if (S.changed || S.cycles % (per_10hz > 0 ? per_10hz : 1) == 0)
        publish_marking(d);
    S.changed = 0;
    S.cycles++;
    snprintf(d->status, sizeof d->status, "%sfired %ld, workpiece %d%s%s%s%s", S.stall.stalled ? "STALLED: " : "",
             S.net.fired_count, (int)S.wp_id, S.arms_faulted ? ", arm FAULT" : "",
             S.arms_silent & 1 ? ", arm 1 SILENT" : "", S.arms_silent & 2 ? ", arm 2 SILENT" : "",
             S.sim_silent ? ", simulator SILENT" : "");
    return DAEMON_CONTINUE;
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        { "controller", required_argument, 0, 'c' },
        { "serial", no_argument, 0, 'S' },
        { "tdsd", no_argument, 0, 'T' },
        { "stall-s", required_argument, 0, 'L' },
        { "journal", required_argument, 0, 'J' },
        DAEMON_COMMON_OPTIONS,
        { 0, 0, 0, 0 }
    };
    daemon d;
    int c, rc;
    double stall_s = 30.0;
    memset(&S, 0, sizeof S);
    S.next_action_id = 1;
    S.controller = TANDEM_ACTION_ROW_T_CONTROLLER_EVENT;
    daemon_defaults(&d, "tandem-supervisor", 0.010);
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        rc = daemon_parse_common(&d, c, optarg);
        if (rc == 2) { usage(); return 0; }
        if (rc < 0) return 2;
        if (rc == 1) continue;
        switch (c) {
        case 'c':
            if (!strcmp(optarg, "event")) S.controller = TANDEM_ACTION_ROW_T_CONTROLLER_EVENT;
            else if (!strcmp(optarg, "time")) S.controller = TANDEM_ACTION_ROW_T_CONTROLLER_TIME;
            else {
                fprintf(stderr, "tandem-supervisor: --controller: '%s' is not event|time\n", optarg);
                return 2;
            }
            break;
        case 'S': S.serial = 1; break;
        case 'J': S.journal_path = optarg; break;
        case 'T': S.use_tdsd = 1; break;
        case 'L': if (parse_double_opt("tandem-supervisor", "--stall-s", optarg, 0.1, 1e6, &stall_s) < 0) return 2; break;
        default: usage(); return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "tandem-supervisor: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    if (check_net() != 0)
        return 1;
    if (petri_init(&S.net, &carry_net) != 0 || stallwatch_init(&S.stall, stall_s) != 0)
        return 1;
    if (S.journal_path) {
        journal_resume();
        if (journal_open(&S.jr, S.journal_path) != JOURNAL_OK) {
            fprintf(stderr, "tandem-supervisor: cannot open the journal %s\n", S.journal_path);
            return 1;
        }
    }
    fflush(stdout);
    auth_bus_identity(AUTH_ROLE_SUPERVISOR, 0, 0);
    if (daemon_start(&d) != 0)
        return 1;
    daemon_subscribe(&d, "ARM_EVENTS", on_event, &d);
    daemon_subscribe(&d, "VISION_DETECTIONS", on_vision, &d);
    daemon_subscribe(&d, "SIM_STATUS", on_sim_status, &d);
    S.changed = 1;
    rc = daemon_run(&d, cycle, NULL);
    daemon_finish(&d);
    journal_close(&S.jr);
    return rc;
}

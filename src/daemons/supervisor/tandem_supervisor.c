/* tandem-supervisor: the discrete-event controller of the carry task
 * ("MVME162", docs/method/carry.md §5-6).
 *
 * Holds the carry Petri net and its lookup table (carry_net), or with
 * --task DIR a task drawn as PNML with its rows (docs/tasks.md), read into
 * fixed tables and checked at start-up by the same checker as tandem-netc
 * (a refusal names the file, the place or transition and why: exit 2,
 * before anything moves). The task is known by the roles its net's
 * structure gives (taskdef.h): the source transition (vision), the place
 * it fills, the pick transition that takes it. At start-up it explores the
 * net's reachability graph and refuses to run (exit 1, printing the
 * offending marking and the event path to it) if the net is unsafe,
 * unbounded, violates a P-invariant or can deadlock.
 *
 * Running: a vision detection in the pick zone puts a token in the
 * source's place (p1 of the carry) only while it is empty (the source
 * transition with its inhibitor arc); every other enabled transition
 * starts at once (its input tokens are taken)
 * and its row goes to the arm(s) on ARMk_ACTION, with the poses resolved
 * from the cell layout and the detection; an arm's plan marked
 * after_partner (t4: arm 1 releases only once arm 2 holds) is sent when
 * the partner's DONE arrives. When every arm of a transition has reported
 * DONE on ARM_EVENTS, the transition completes (its output tokens are
 * added). The marking goes out on PETRI_MARKING on every change and at
 * 10 Hz; every start and completion is logged on stdout.
 *
 * The arms' health: a task whose net names arm K's health places
 * (armK_up, armK_down: taskdef_health) has them follow the arm's FAULT and
 * silence (follow_health); the net decides what runs while an arm is down
 * (docs/tasks.md §8: arm 2 alone from its magazine).
 *
 * Watchdogs: an arm's FAULT event (joint out of range or over speed; the
 * arm holds on its brakes) is logged and shown in the marking message
 * until FAULT_CLEARED. A stall -- work pending, nothing completed for
 * --stall-s seconds while the stick is out (SIM_STATUS), or with the stick
 * in for longer than --stall-obstructed-s -- is logged once, flagged in
 * PETRI_MARKING and in the health status (stallwatch).
 *
 * Recovery: with --journal PATH every change of the discrete state (marking,
 * running rows, the workpieces bound to tokens, action ids, counters) is
 * appended to PATH as an authenticated record and fsynced; a supervisor
 * started on an existing journal checks every record and every restored
 * value and takes the last snapshot back (unless it is from a later step
 * than the simulator: another run), or refuses to start (exit 1, naming
 * the record and why); --journal-reset starts fresh on purpose. While the
 * journal cannot be written the cell holds: no new rows (health safe_hold
 * and status say why) until a write succeeds again. The arms say what they are doing in every event, and at
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
 *
 * All of its state is one supervisor_daemon (supervisor_daemon.h), created
 * here in main and handed to the cycle and to every handler.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "supervisor_daemon.h"
#include "cell.h"
#include "linalg.h"
#include "options.h"
#include "carry_status.h"
#include "shell_status.h"
#include "vec3.h"
#include "tandem_action_row_t.h"

#define PICK_ACCEPT_RADIUS_M 0.15

STATUS_STRERROR(supervisor_strerror, SUPERVISOR_CODES)

/* ---- start-up check ------------------------------------------------------- */

static void print_offender(const supervisor_daemon *sv, const char *what, int index)
{
    int8_t ev[256];
    int n, i;
    const petri_state *s = &sv->explore_ws.states[index];
    printf("tandem-supervisor: the %s net %s; offending marking [",
           sv->task ? sv->task->task : "carry", what);
    for (i = 0; i < sv->pn->n_places; i++)
        printf("%s%d", i ? " " : "", s->m[i]);
    printf("] running 0x%x\n  reached by:", (unsigned)s->running);
    n = petri_explore_trace(&sv->explore_ws, index, ev, (int)sizeof ev);
    for (i = 0; i < n; i++)
        printf(" %s t%d", ev[i] > 0 ? "start" : "complete", abs(ev[i]));
    printf("\n");
}

static int check_net(supervisor_daemon *sv)
{
    petri_report r;
    if (petri_explore(&sv->explore_ws, sv->pn, sv->token_bound, &r) != 0) {
        printf("tandem-supervisor: the net's tables are invalid\n");
        return SUPERVISOR_ERR_NET;
    }
    if (!r.complete) {
        printf("tandem-supervisor: reachability graph exceeds %d states\n", PETRI_MAX_STATES);
        return SUPERVISOR_ERR_NET;
    }
    /* bound 1 (the carry): safe; a task with a buffer may hold more
     * tokens in a place, up to what its P-invariants allow */
    if (!r.bounded || r.invariant_states || r.deadlock) {
        if (!r.bounded)
            print_offender(sv, sv->token_bound == 1 ? "is not safe" : "exceeds its token bound",
                           r.unbounded_index);
        else if (r.invariant_states)
            print_offender(sv, "violates a P-invariant", r.invariant_index);
        else
            print_offender(sv, "can deadlock", r.dead_index);
        return SUPERVISOR_ERR_NET;
    }
    printf("tandem-supervisor: net checked: %d reachable states, %s, live, invariants hold\n",
           r.n_states, r.safe ? "safe" : "bounded");
    return 0;
}

/* ---- vision tokens -------------------------------------------------------- */

static void on_vision(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    supervisor_daemon *sv = u;
    tandem_workpiece_detections_t m;
    int i, best = -1;
    double best_d = PICK_ACCEPT_RADIUS_M;
    (void)ch;
    if (!DAEMON_DECODE(&sv->d.msgs, tandem_workpiece_detections_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++) {
        const tandem_workpiece_t *w = &m.workpieces[i];
        double dist;
        if (!linalg_all_finite(w->position_m, 3) || !isfinite(w->yaw_rad) ||
            fabs(w->yaw_rad) > 0.5) {
            sv->d.msgs.rejected++;
            continue;
        }
        dist = hypot(w->position_m[0] - cell_default.pick_center_m[0],
                     w->position_m[1] - cell_default.pick_center_m[1]);
        if (w->id > sv->last_taken_id && dist < best_d) {
            best_d = dist;
            best = i;
        }
    }
    if (best >= 0) {
        sv->det = m.workpieces[best];
        sv->have_detection = 1;
    }
    tandem_workpiece_detections_t_decode_cleanup(&m);
}

const carry_row *sup_row(const supervisor_daemon *sv, int t)
{
    return &sv->rows[t];
}

int sup_health_transition(const supervisor_daemon *sv, int t)
{
    return t >= 0 && t < PETRI_MAX_TRANSITIONS && (sv->health.mask >> t & 1u);
}

/* The arms' health places (taskdef_health, docs/tasks.md §8) follow what
 * the arms report: a FAULT or silence fires arm k's fault transition,
 * FAULT_CLEARED and its voice back its recovery, at once (start and
 * completion), as the source is fired. The net then lets no row start
 * for an arm that is down (inhibitor arcs from its down place). */
static void follow_health(supervisor_daemon *sv)
{
    int a;
    for (a = 0; a < 2; a++) {
        const int down = ((sv->arms_faulted | sv->arms_silent) >> a) & 1;
        const int t = down ? sv->health.fault[a] : sv->health.recover[a];
        /* up again only on the arm's own word: a supervisor restarted from
         * its journal with the arm down has not heard it yet */
        if (t < 0 || (!down && !sv->arm[a].heard) || !petri_enabled(&sv->net, t) ||
            petri_fire(&sv->net, t) != 0)
            continue;
        sv->changed = 1;
        sv->dirty = 1;
        printf("[%9.3f] arm %d %s: %s fired\n", sv->d.sim_time_s, a + 1,
               down ? "DOWN (fault or silent)" : "up again", sv->task->trans_name[t]);
    }
}

/* --serial: the cell is back where it started, nothing running and every
 * place but the source's at its initial marking (the carry: both arms
 * home, the previous workpiece delivered). */
static int cell_at_rest(const supervisor_daemon *sv)
{
    int i;
    if (sv->net.st.running)
        return 0;
    for (i = 0; i < sv->pn->n_places; i++)
        if (i != sv->roles.source_place && sv->net.st.m[i] != sv->pn->m0[i])
            return 0;
    return 1;
}

/* The source's place (p1 of the carry) takes a token only while it is
 * empty (inhibitor arc); --serial also waits for the previous workpiece
 * to be delivered and both arms home. The token of gamma0 there is bound
 * to the first detection. */
static void take_detection(supervisor_daemon *sv)
{
    const int bind_only = sv->net.st.m[sv->roles.source_place] && !sv->p1_bound;
    if (!sv->have_detection || sv->det.id <= sv->last_taken_id)
        return;
    if (!bind_only && !petri_enabled(&sv->net, sv->roles.source))
        return;
    if (sv->serial && !cell_at_rest(sv))
        return;
    if (!bind_only && petri_fire(&sv->net, sv->roles.source) != 0)
        return;
    sv->p1_bound = 1;
    sv->wp_id = sv->det.id;
    sv->last_taken_id = sv->det.id;
    vec3_copy(sv->wp_pos_m, sv->det.position_m);
    sv->wp_yaw_rad = sv->det.yaw_rad;
    sv->detections++;
    sv->have_detection = 0;
    sv->changed = 1;
    sv->dirty = 1;
    printf("[%9.3f] vision: workpiece %d at (%.3f %.3f %.3f) yaw %.3f -> p1\n", sv->d.sim_time_s,
           (int)sv->wp_id, sv->wp_pos_m[0], sv->wp_pos_m[1], sv->wp_pos_m[2], sv->wp_yaw_rad);
}

/* ---- the cycle ------------------------------------------------------------ */

static int cycle(daemon *d, void *user)
{
    supervisor_daemon *sv = user;
    const int per_10hz = (int)(0.1 / d->period_s + 0.5);
    int t, dead;
    sup_handle_events(sv);
    follow_health(sv);
    sup_recover_rows(sv);
    /* holding (the journal cannot be written): nothing new starts */
    if (!sup_holding(sv))
        take_detection(sv);
    for (t = 0; t < sv->pn->n_transitions; t++) {
        if (t == sv->roles.source || sup_health_transition(sv, t) || sup_holding(sv) ||
            !petri_enabled(&sv->net, t) || (t == sv->roles.pick && !sv->p1_bound) ||
            sup_grasp_blocked(sv, t))
            continue;
        if (t == sv->roles.pick) {
            sv->p1_bound = 0; /* the pick (t1) takes the token and its pose */
            vec3_copy(sv->pick_pos_m, sv->wp_pos_m);
            sv->pick_yaw_rad = sv->wp_yaw_rad;
            sv->pick_id = sv->wp_id;
        }
        sup_start_transition(sv, t);
    }
    dead = petri_dead(&sv->net);
    if (dead && !sv->was_dead) {
        sv->deadlocks++;
        printf("[%9.3f] DEAD marking reached\n", d->sim_time_s);
    }
    sv->was_dead = dead;
    sup_watch_stall(sv);
    sup_watch_silence(sv);
    sup_journal_cycle(sv);
    if (sv->changed || sv->cycles % (per_10hz > 0 ? per_10hz : 1) == 0)
        sup_publish_marking(sv);
    sv->changed = 0;
    sv->cycles++;
    if (sup_holding(sv)) {
        /* why the cell holds comes first: it is what an operator must fix */
        snprintf(d->status, sizeof d->status,
                 "HOLD: journal not written (%s): no new rows; fired %ld",
                 journal_strerror(sv->journal_rc), sv->net.fired_count);
        return DAEMON_CONTINUE;
    }
    snprintf(d->status, sizeof d->status, "%sfired %ld, workpiece %d%s%s%s%s",
             sv->stall.stalled ? "STALLED: " : "", sv->net.fired_count, (int)sv->wp_id,
             sv->arms_faulted ? ", arm FAULT" : "", sv->arms_silent & 1 ? ", arm 1 SILENT" : "",
             sv->arms_silent & 2 ? ", arm 2 SILENT" : "",
             sv->sim_silent ? ", simulator SILENT" : "");
    return DAEMON_CONTINUE;
}

/* ---- command line and start-up check of the tables -------------------------- */

static const char *const controller_names[] = { "event", "time", NULL };
static const int controller_values[] = { TANDEM_ACTION_ROW_T_CONTROLLER_EVENT,
                                         TANDEM_ACTION_ROW_T_CONTROLLER_TIME };

/* --stall-s's default, set by main and shown in help */
#define SUP_STALL_DEFAULT_S 30

/* Into the supervisor_daemon main made; the values it holds before are
 * the defaults. */
static const option_entry supervisor_options[] = {
    { .name = "controller",
      .type = OPTION_CHOICE,
      OPTION_AT(supervisor_daemon, controller),
      .choices = controller_names,
      .values = controller_values,
      .help = "arms run the event-referenced law or the time-referenced baseline",
      .def = "event" },
    { .name = "serial",
      .type = OPTION_FLAG,
      OPTION_AT(supervisor_daemon, serial),
      .help = "take a new workpiece only when the previous one is delivered and both arms are home "
              "(no pipelining)" },
    { .name = "tdsd",
      .type = OPTION_FLAG,
      OPTION_AT(supervisor_daemon, use_tdsd),
      .help =
          "rows set use_tdsd: the arms resolve unsynchronised Cartesian moves by TDSD (passes near "
          "singular poses)" },
    { .name = "stall-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(supervisor_daemon, stall_s),
      .min = 0.1,
      .max = 1e6,
      .meta = "S",
      .help = "a stall: work pending and no transition completed for S s of simulated time while "
              "the stick is out",
      .def = OPTION_DEF(SUP_STALL_DEFAULT_S) },
    { .name = "stall-obstructed-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(supervisor_daemon, stall_obstructed_s),
      .min = 0.1,
      .max = 1e6,
      .meta = "S",
      .help =
          "the stick in excuses a cell without progress for at most S s of simulated time; then "
          "--stall-s more is a stall",
      .def = OPTION_DEF(STALLWATCH_OBSTRUCT_MAX_S) },
    { .name = "journal",
      .type = OPTION_STRING,
      OPTION_AT(supervisor_daemon, journal_path),
      .meta = "PATH",
      .help =
          "append the discrete state to PATH on every change (authenticated with a key derived from the "
          "bus key, fsynced); start from its last record when PATH exists (restart); a journal that does "
          "not check out stops the start (exit 1); one that cannot be written holds the cell" },
    OPTION_JOURNAL_RESET_ENTRY(supervisor_daemon, journal_reset),
    { .name = "task",
      .type = OPTION_STRING,
      OPTION_AT(supervisor_daemon, task_dir),
      .meta = "DIR",
      .help =
          "run the task in DIR (one *.pnml and rows.csv, docs/tasks.md) instead of the shipped carry: "
          "read into fixed tables and checked as tandem-netc does (token bound from its P-invariants); "
          "refused (exit 2) naming the file, the place or transition and why" },
    { .name = NULL }
};

/* The tables the net and its rows are made of, checked before the
 * reachability graph is explored from them (check_net), the roles found
 * (taskdef_validate), and the option table. */
static int check_tables(supervisor_daemon *sv)
{
    const char *net = sv->task ? "task net" : "carry_net",
               *rows = sv->task ? "task rows" : "carry_table";
    if (daemon_check_table(sv->d.name, net, "petri_net_validate", petri_net_validate(sv->pn),
                           petri_strerror) != 0 ||
        daemon_check_table(sv->d.name, net, "taskdef_health_find",
                           sv->task ? taskdef_health_find(sv->task, &sv->health) : TASKDEF_OK,
                           taskdef_strerror) != 0 ||
        daemon_check_table(
            sv->d.name, rows, "carry_table_validate",
            carry_table_validate_health(sv->rows, sv->pn->n_transitions, sv->pn, sv->health.mask),
            carry_net_strerror) != 0 ||
        daemon_check_table(sv->d.name, net, "taskdef_validate",
                           taskdef_validate_health(sv->pn, sv->rows, sv->health.mask, &sv->roles),
                           taskdef_strerror) != 0 ||
        daemon_check_table(sv->d.name, "stand_poses", "sup_stand_poses_validate",
                           sup_stand_poses_validate(), supervisor_strerror) != 0 ||
        daemon_check_table(sv->d.name, "supervisor_options", "options_table_validate",
                           options_table_validate(supervisor_options), options_strerror) != 0)
        return DAEMON_ERR_TABLE;
    return 0;
}

/* --task DIR into sv->task, through the checker of tandem-netc: 0, or
 * SUPERVISOR_ERR_TASK after the checker named the file, the place or
 * transition and why. Without --task: the shipped carry, bound 1. */
static int load_task(supervisor_daemon *sv, netc_task *store)
{
    int rc;
    sv->pn = &carry_net;
    sv->rows = carry_table;
    sv->token_bound = 1;
    if (!sv->task_dir)
        return 0;
    netc_set_program("tandem-supervisor");
    rc = netc_task_load(store, sv->task_dir, NETC_BOUND_FROM_INVARIANTS, &sv->token_bound, stdout,
                        stderr);
    if (rc != NETC_OK) {
        fprintf(stderr, "tandem-supervisor: task %s refused: %s (%s)\n", sv->task_dir,
                netc_strerror(rc), supervisor_strerror(SUPERVISOR_ERR_TASK));
        return SUPERVISOR_ERR_TASK;
    }
    sv->task = store;
    sv->pn = &store->net;
    sv->rows = store->rows;
    printf("tandem-supervisor: task %s (%s): %d places, %d transitions, token bound %d\n",
           store->task, sv->task_dir, store->n_places, store->n_transitions, sv->token_bound);
    return 0;
}

int main(int argc, char **argv)
{
    static supervisor_daemon app;
    static netc_task task; /* --task's fixed tables */
    supervisor_daemon *sv = &app;
    daemon *d = &sv->d;
    const option_program prog = {
        .name = "tandem-supervisor",
        .usage =
            "usage: tandem-supervisor [options]\n"
            "Petri-net supervisor of the two-arm carry (docs/method/carry.md §5-6), or of a task drawn\n"
            "as PNML (--task, docs/tasks.md): vision tokens, lookup-table rows to the arms, completion\n"
            "events, marking at 10 Hz.\n\n",
        .epilog = "\nThe control period (--period-ms) is 10 ms unless given.\n",
        .groups = { { supervisor_options, sv }, { options_daemon_common, d } },
        .n_groups = 2,
    };
    int rc;
    sv->next_action_id = 1;
    taskdef_health_find(NULL, &sv->health); /* none: the shipped carry */
    sv->jr.fd = -1;                         /* no journal open (journal_close at the end) */
    sv->controller = TANDEM_ACTION_ROW_T_CONTROLLER_EVENT;
    sv->stall_s = SUP_STALL_DEFAULT_S;
    sv->stall_obstructed_s = STALLWATCH_OBSTRUCT_MAX_S;
    daemon_defaults(d, "tandem-supervisor", 0.010);
    if ((rc = options_parse(&prog, argc, argv, 1)) < 0)
        return options_exit_status(rc);
    if (load_task(sv, &task) != 0)
        return 2;
    if (check_tables(sv) != 0 || check_net(sv) != 0)
        return 1;
    sv->task_digest = taskdef_digest(sv->pn, sv->rows);
    if (petri_init(&sv->net, sv->pn) != 0 || stallwatch_init(&sv->stall, sv->stall_s) != 0 ||
        stallwatch_set_obstruct_max(&sv->stall, sv->stall_obstructed_s) != 0)
        return 1;
    fflush(stdout);
    auth_bus_identity(&sv->d.bus, AUTH_ROLE_SUPERVISOR, 0, 0);
    if (daemon_start(d) != 0)
        return 1;
    /* after daemon_start: the journal's key comes from the bus key */
    if (sup_journal_start(sv) != 0) {
        daemon_finish(d);
        return 1;
    }
    fflush(stdout);
    daemon_subscribe(d, "ARM_EVENTS", sup_on_event, sv);
    daemon_subscribe(d, "VISION_DETECTIONS", on_vision, sv);
    daemon_subscribe(d, "SIM_STATUS", sup_on_sim_status, sv);
    sv->changed = 1;
    rc = daemon_run(d, cycle, sv);
    daemon_finish(d);
    journal_close(&sv->jr);
    return rc;
}

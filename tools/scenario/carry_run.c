/* carry_run: one carry run (docs/method/carry.md §8). Spawns tandem-sim,
 * tandem-arm 1 and 2 and tandem-supervisor in lockstep on a private LCM
 * URL and joins the lockstep itself (it answers every step), so the stick
 * goes in and out at exact simulated times and every step is recorded
 * (timeseries.csv and joints.csv every 10 ms, transitions.csv). The run
 * stops when the supervisor reports a stall, a daemon dies, every
 * workpiece is delivered or dropped (and every block done), or the
 * simulated or wall time limit is reached. --fault kills and restarts a
 * daemon at exact steps.
 */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "carry_scen.h"
#include "hang_watch.h"
#include "shared_run.h"
#include "run_key.h"
#include "arm_model.h"
#include "daemon.h"
#include "proc.h"
#include "tandem_action_event_t.h"
#include "tandem_sim_control_t.h"

#define PROGRESS_EVERY_S 5.0 /* wall time between progress lines */
/* The simulator drops a lockstep participant that has not answered for
 * this long. A run with a dropped controller is not the seed's run, and a
 * daemon that really died is seen by its exit: so only after 10 minutes
 * (a loaded machine can starve a controller for tens of seconds). */
#define LOCKSTEP_TIMEOUT_MS "600000"

/* The daemons of a run and their command lines (kept for a --fault restart). */
typedef struct carry_daemons {
    char url[96], nbuf[32], sbuf[32], journal[700], err[1024];
    char path[CARRY_DAEMONS][1024];
    const char *sim_argv[16], *a1_argv[16], *a2_argv[16], *sup_argv[20];
    const char *const *argvs[CARRY_DAEMONS];
    pid_t pid[CARRY_DAEMONS];
    proc_set ps;
    /* --hang-s: silent daemons; a hung one's restart (HUNG_*), the step
     * announced when it was killed, and the leaves of killed daemons */
    hang_watch hw;
    int hung_stage[CARRY_DAEMONS];
    int64_t hung_step[CARRY_DAEMONS];
    scenario_leave leave[CARRY_DAEMONS];
} carry_daemons;

/* carry_daemons.hung_stage */
enum { HUNG_NONE = 0, HUNG_KILLED = 1, HUNG_RESTARTING = 2 };

static volatile sig_atomic_t interrupted;
static void on_sigint(int s)
{
    (void)s;
    interrupted = 1;
}

void carry_catch_signals(void)
{
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);
}

int carry_interrupted(void)
{
    return interrupted;
}

/* ---- recording --------------------------------------------------------------- */

static void record_step(carry_state *r, const carry_cfg *c, int64_t step)
{
    const carry_blocks *bl = c->blocks;
    int a, t;
    for (a = 0; a < 2; a++)
        r->s_hist[a][step & 15] = r->s[a];
    if (r->have_mk && c->tr_csv) {
        for (t = 0; t < NT && t < r->mk.n_transitions; t++) {
            if (r->mk.running[t] && !r->running_prev[t])
                r->run_start[t] = r->t_s;
            if (!r->mk.running[t] && r->running_prev[t])
                fprintf(c->tr_csv, "%d,%.3f,%.3f\n", t + 1, r->run_start[t], r->t_s);
            r->running_prev[t] = r->mk.running[t];
        }
    }
    if (c->ts_csv && step % 10 == 0) {
        int stick = carry_stick_in(bl);
        fprintf(c->ts_csv,
                "%.3f,%.5f,%.5f,%d,%.5f,%.5f,%d,%.4f,%.4f,%.3f,%.3f,%d,%d,%d,%.3f,%.3f\n", r->t_s,
                r->s[0], r->s_f[0], r->tr[0], r->s[1], r->s_f[1], r->tr[1], r->speed[0],
                r->speed[1], r->arm[0].max_contact_force_N, r->arm[1].max_contact_force_N,
                stick ? bl->b[bl->cur].arm : 0, r->delivered, r->dropped,
                r->arm[0].max_contact_force_10ms_N, r->arm[1].max_contact_force_10ms_N);
    }
    if (c->q_csv && step % 10 == 0) {
        int i;
        fprintf(c->q_csv, "%.3f", r->t_s);
        for (a = 0; a < 2; a++)
            for (i = 0; i < ARM_NJ; i++)
                fprintf(c->q_csv, ",%.5f", r->arm[a].q_rad[i]);
        fputc('\n', c->q_csv);
    }
}

/* One line on stderr every PROGRESS_EVERY_S of wall time. */
static void progress_line(const carry_state *r, const carry_cfg *c, double wall0)
{
    const carry_blocks *bl = c->blocks;
    const double wall = scenario_wall_s() - wall0;
    char blk[64] = "no block";
    if (carry_stick_in(bl))
        snprintf(blk, sizeof blk, "block %d/%d in (arm %d link %d)", bl->cur + 1, bl->n,
                 bl->b[bl->cur].arm, bl->b[bl->cur].link);
    else if (bl->cur < bl->n)
        snprintf(blk, sizeof blk, "block %d/%d armed", bl->cur + 1, bl->n);
    fprintf(
        stderr,
        "tandem-scenario carry %s: t %.1f s (%.1fx real time), delivered %d/%d, dropped %d, %s, "
        "max contact %.0f N (10 ms)%s\n",
        c->tag, r->t_s, scenario_realtime_factor(r->t_s, wall), r->delivered, c->workpieces,
        r->dropped, blk, r->max_force_10ms_N,
        r->max_force_10ms_N > CRIT_FORCE_10MS_N ? " IMPLAUSIBLE" : "");
}

/* ---- the daemons --------------------------------------------------------------- */

/* The options every daemon of a run gets besides its own (--drop-rate),
 * appended at argv[n] with the closing NULL. */
static void daemon_argv_finish(const carry_cfg *c, const char **argv, int n, int cap)
{
    scenario_argv_drop(&c->drop, (char **)argv, &n, cap);
}

/* The four command lines and the bus of run c. */
static void daemons_argv(carry_daemons *d, const carry_cfg *c)
{
    const char *const sim[] = {
        "tandem-sim", "--lockstep",   "--expect",         "4", "--workpieces", d->nbuf, "--seed",
        d->sbuf,      "--timeout-ms", LOCKSTEP_TIMEOUT_MS
    };
    const char *const a1[] = { "tandem-arm", "--arm",          "1",
                               "--lockstep", "--block-detect", c->block_detect };
    const char *const a2[] = { "tandem-arm", "--arm",          "2",
                               "--lockstep", "--block-detect", c->block_detect };
    const char *const sup[] = { "tandem-supervisor", "--lockstep",
                                "--stall-s",         c->stall_s,
                                "--controller",      c->controller_time ? "time" : "event",
                                "--journal",         d->journal };
    memset(d, 0, sizeof *d);
    memcpy(d->sim_argv, sim, sizeof sim);
    memcpy(d->a1_argv, a1, sizeof a1);
    memcpy(d->a2_argv, a2, sizeof a2);
    memcpy(d->sup_argv, sup, sizeof sup);
    d->argvs[0] = d->sim_argv;
    d->argvs[1] = d->a1_argv;
    d->argvs[2] = d->a2_argv;
    d->argvs[3] = d->sup_argv;
    snprintf(d->nbuf, sizeof d->nbuf, "%d", c->workpieces);
    snprintf(d->sbuf, sizeof d->sbuf, "%llu", (unsigned long long)c->seed);
    if (c->url)
        snprintf(d->url, sizeof d->url, "%s", c->url);
    else
        snprintf(d->url, sizeof d->url, "udpm://239.255.76.67:%d?ttl=0",
                 30000 + (int)(getpid() % 20000) + (c->serial ? 1 : 0));
}

/* Starts the four daemons (logs DIR/TAG_NAME.log, stderr DIR/TAG_stderr.log);
 * 0 ok, CARRY_SCEN_ERR_RUN: one did not start (the others stopped again). */
static int daemons_start(carry_daemons *d, const carry_cfg *c)
{
    int k, n_sim, n_sup;
    proc_init(&d->ps, run_key_bus(), NULL);
    snprintf(d->journal, sizeof d->journal, "%s/%s_supervisor.journal", c->out, c->tag);
    remove(d->journal); /* a fresh run; a restart reads it */
    n_sim = 10;
    if (c->handover_stand)
        d->sim_argv[n_sim++] = "--handover-stand";
    if (c->magazine)
        d->sim_argv[n_sim++] = "--magazine";
    daemon_argv_finish(c, d->sim_argv, n_sim, 16);
    daemon_argv_finish(c, d->a1_argv, 6, 16);
    daemon_argv_finish(c, d->a2_argv, 6, 16);
    n_sup = 8;
    if (c->serial)
        d->sup_argv[n_sup++] = "--serial";
    if (c->task) {
        d->sup_argv[n_sup++] = "--task";
        d->sup_argv[n_sup++] = c->task;
    }
    daemon_argv_finish(c, d->sup_argv, n_sup, 20);
    snprintf(d->err, sizeof d->err, "%s/%s_stderr.log", c->out, c->tag);
    remove(d->err);
    for (k = 0; k < CARRY_DAEMONS; k++) {
        snprintf(d->path[k], sizeof d->path[k], "%s/%s_%s.log", c->out, c->tag,
                 carry_daemon_fault_name[k]);
        if ((d->pid[k] = proc_spawn(&d->ps, d->argvs[k], d->url, d->path[k], d->err)) < 0) {
            fprintf(stderr, "tandem-scenario: cannot start %s\n", d->argvs[k][0]);
            proc_kill_all(&d->ps, 1.0);
            return CARRY_SCEN_ERR_RUN;
        }
    }
    hang_watch_init(&d->hw, c->hang_s);
    for (k = 0; k < CARRY_DAEMONS; k++) {
        hang_watch_add(&d->hw, carry_daemon_lock_name[k], scenario_wall_s());
        hang_watch_pid(&d->hw, k, d->pid[k]);
    }
    return 0;
}

/* The latest step the simulator announced. */
static int64_t clock_step(const carry_state *r)
{
    return r->pending > r->handled ? r->pending : r->handled;
}

/* SIGKILL to daemon k (a --fault, or hung) and its leave to the simulator
 * (sent again until taken), so the simulator does not wait out its
 * timeout; not watched for hanging while down. */
static void kill_daemon(carry_state *r, carry_daemons *d, int k)
{
    proc_kill(&d->ps, d->pid[k]);
    if (k == 1 || k == 2)
        r->arm_down[k - 1] = 1;
    scenario_leave_send(&d->leave[k], r->bus, r->lcm, carry_daemon_lock_name[k], clock_step(r), 1);
    hang_watch_down(&d->hw, k);
}

/* Daemon k started again (log `log`): watched again from now, no more
 * leaves; 0, or CARRY_SCEN_ERR_FAULT when it did not start. */
static int restart_daemon(carry_state *r, carry_daemons *d, int k, const char *log)
{
    d->pid[k] = proc_spawn(&d->ps, d->argvs[k], d->url, log, d->err);
    if (d->pid[k] < 0)
        return CARRY_SCEN_ERR_FAULT;
    scenario_leave_end(&d->leave[k]);
    if (k == 1 || k == 2)
        r->arm_down[k - 1] = 0;
    hang_watch_started(&d->hw, k, scenario_wall_s());
    hang_watch_pid(&d->hw, k, d->pid[k]);
    r->hold_since_s = scenario_wall_s();
    return 0;
}

/* --fault, at the step about to be answered: kill (SIGKILL, and the
 * simulator is told the daemon left so it does not wait out its timeout),
 * then restart at the first step after RESTART_T that every controller
 * answers (a multiple of 20 ms), holding that step until the new process
 * has answered it. 1: go on, 0: hold the step, CARRY_SCEN_ERR_FAULT. */
static int faults_step(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d)
{
    int i;
    for (i = 0; i < c->n_faults; i++) {
        scenario_fault *f = &c->faults[i];
        if (f->stage == SCENARIO_FAULT_ARMED && r->t_s >= f->kill_s) {
            kill_daemon(r, d, f->slot);
            fprintf(stderr, "tandem-scenario: fault: %s killed at %.3f s\n", f->daemon, r->t_s);
            res->kills++;
            scenario_fault_killed(f);
        }
        if (f->stage == SCENARIO_FAULT_KILLED && r->t_s >= f->restart_s && r->pending % 20 == 0) {
            char log[700];
            snprintf(log, sizeof log, "%s/%s_%s_restart%d.log", c->out, c->tag, f->daemon, i + 1);
            if (restart_daemon(r, d, f->slot, log) != 0)
                return CARRY_SCEN_ERR_FAULT;
            fprintf(stderr, "tandem-scenario: fault: %s restarted at %.3f s\n", f->daemon, r->t_s);
            f->stage = SCENARIO_FAULT_RESTARTING;
        }
        if (f->stage == SCENARIO_FAULT_RESTARTING) {
            if (r->ack_step[f->slot] < r->pending) {
                if (scenario_rejoin_overdue(r->hold_since_s)) {
                    fprintf(stderr, "tandem-scenario: fault: %s did not rejoin within 60 s\n",
                            f->daemon);
                    return CARRY_SCEN_ERR_FAULT;
                }
                return 0;
            }
            res->restarts++;
            f->stage = SCENARIO_FAULT_DONE;
        }
    }
    return 1;
}

/* A hung daemon k started again (log DIR/TAG_NAME_hungN.log) and said so;
 * 0, or CARRY_SCEN_ERR_FAULT. */
static int restart_hung(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d,
                        int k)
{
    char log[700];
    snprintf(log, sizeof log, "%s/%s_%s_hung%d.log", c->out, c->tag, carry_daemon_fault_name[k],
             res->hung_restarts + 1);
    if (restart_daemon(r, d, k, log) != 0)
        return CARRY_SCEN_ERR_FAULT;
    fprintf(stderr, "tandem-scenario: hung: %s restarted at %.3f s\n", carry_daemon_lock_name[k],
            r->t_s);
    return 0;
}

/* Hung before the first step: the simulator waits at step 0 for every
 * daemon to join, so there is no step to hold; the new process joins as
 * the first one would have. 0, or CARRY_SCEN_ERR_FAULT. */
static int restart_before_start(carry_state *r, const carry_cfg *c, carry_result *res,
                                carry_daemons *d, int k)
{
    if (restart_hung(r, c, res, d, k) != 0)
        return CARRY_SCEN_ERR_FAULT;
    res->restarts++;
    res->hung_restarts++;
    d->hung_stage[k] = HUNG_NONE;
    return 0;
}

/* --hang-s, between steps: a daemon alive but silent on its health
 * channel for hang_s of wall time is hung: killed (SIGKILL) and, but the
 * simulator, restarted by hung_step. The world cannot be started again:
 * a hung simulator ends the run. 0 go on, 1 stop, CARRY_SCEN_ERR_FAULT
 * (a restart before the first step failed). */
static int hung_watch(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d)
{
    const double now = scenario_wall_s();
    int k;
    if (!hang_watch_look(&d->hw, r->lcm, now))
        return 0; /* messages still to read: not now */
    for (k = 0; k < CARRY_DAEMONS; k++) {
        if (d->hung_stage[k] != HUNG_NONE || !hang_watch_hung(&d->hw, k, now) ||
            proc_poll(&d->ps, d->pid[k], NULL) != 0)
            continue; /* not hung, or exited (said as an exit) */
        fprintf(
            stderr,
            "tandem-scenario: hung: %s alive but without health for %.1f s (--hang-s %g): killed at "
            "%.3f s%s\n",
            carry_daemon_lock_name[k], hang_watch_silent_s(&d->hw, k, now), d->hw.hang_s, r->t_s,
            k == 0 ? "; the world cannot be restarted: run stopped" : ", restarting");
        res->kills++;
        kill_daemon(r, d, k);
        if (k == 0) {
            res->exit_reason = "simulator_hung";
            return 1;
        }
        d->hung_stage[k] = HUNG_KILLED;
        d->hung_step[k] = clock_step(r);
        if (clock_step(r) <= 0 && restart_before_start(r, c, res, d, k) != 0)
            return CARRY_SCEN_ERR_FAULT;
    }
    return 0;
}

/* A hung daemon's restart, at the step about to be answered, as a --fault
 * restart: at the first step after the kill that every controller
 * answers (a multiple of 20 ms), held until the new process has answered
 * it. 1: go on, 0: hold the step, CARRY_SCEN_ERR_FAULT. */
static int hung_step(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d)
{
    int k;
    for (k = 1; k < CARRY_DAEMONS; k++) {
        if (d->hung_stage[k] == HUNG_KILLED && r->pending > d->hung_step[k] &&
            r->pending % 20 == 0) {
            if (restart_hung(r, c, res, d, k) != 0)
                return CARRY_SCEN_ERR_FAULT;
            d->hung_stage[k] = HUNG_RESTARTING;
        }
        if (d->hung_stage[k] == HUNG_RESTARTING) {
            if (r->ack_step[k] < r->pending) {
                if (scenario_rejoin_overdue(r->hold_since_s)) {
                    fprintf(stderr, "tandem-scenario: hung: %s did not rejoin within 60 s\n",
                            carry_daemon_lock_name[k]);
                    return CARRY_SCEN_ERR_FAULT;
                }
                return 0;
            }
            res->restarts++;
            res->hung_restarts++;
            d->hung_stage[k] = HUNG_NONE;
        }
    }
    return 1;
}

/* ---- the lockstep loop ------------------------------------------------------------ */

static void state_init(carry_state *r)
{
    memset(r, 0, sizeof *r);
    r->pending = r->handled = -1;
    r->min_range_margin_rad = INFINITY;
    r->last_event[0] = r->last_event[1] = TANDEM_ACTION_EVENT_T_DONE; /* idle until a row starts */
    r->unblocked_step[0] = r->unblocked_step[1] = r->done_step[0] = r->done_step[1] = -1;
    r->t_deliv_first = r->t_deliv_last = r->end_at = -1.0;
    r->status_step = -1;
    r->stick_want = -1;
}

/* The wall-time limit: no simulated time gained for CARRY_STUCK_WALL_S of
 * wall time (the simulator hung; a hung daemon is the hang watch's). A run
 * that is only slow is waited for, however long it takes: lockstep makes
 * its result the same on a loaded machine. A fixed hour ended 20-workpiece
 * runs at 0.1x real time on a machine shared by three jobs, one
 * workpiece short. */
#define CARRY_STUCK_WALL_S 600.0
static int stuck_wall(carry_state *r)
{
    const double now = scenario_wall_s();
    if (r->progress_wall_s == 0.0 || r->t_s > r->progress_t_s) {
        r->progress_t_s = r->t_s;
        r->progress_wall_s = now;
        return 0;
    }
    return now - r->progress_wall_s > CARRY_STUCK_WALL_S;
}

/* Between steps: dead daemons, the wall-time limit, the progress line, a
 * stall. 0 go on, 1 stop, CARRY_SCEN_ERR_RUN (a daemon exited). */
static int run_watch(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d,
                     double wall0, double *next_progress)
{
    int k, rc = 0;
    for (k = 0; k < d->ps.n; k++) {
        int st;
        if (d->ps.alive[k] && proc_poll(&d->ps, d->ps.pid[k], &st) == 1) {
            fprintf(stderr, "tandem-scenario: a daemon exited early (status %d); see %s\n", st,
                    d->err);
            res->exit_reason = "daemon_exited";
            rc = CARRY_SCEN_ERR_RUN;
        }
    }
    if (rc != 0)
        return rc;
    for (k = 0; k < CARRY_DAEMONS; k++)
        res->leave_resends += scenario_leave_confirm(&d->leave[k], r->bus, r->lcm, clock_step(r));
    if ((k = hung_watch(r, c, res, d)) != 0) {
        if (k < 0)
            res->exit_reason = "restart_failed";
        return k;
    }
    if (stuck_wall(r)) {
        fprintf(stderr,
                "tandem-scenario: wall-time limit reached: no simulated time gained for %.0f s "
                "(at %.2f s)\n",
                CARRY_STUCK_WALL_S, r->t_s);
        res->exit_reason = "wall_time_limit";
        return 1;
    }
    if (scenario_progress_due(next_progress, PROGRESS_EVERY_S))
        progress_line(r, c, wall0);
    if (r->have_mk && r->mk.stalled) {
        fprintf(
            stderr,
            "tandem-scenario: the supervisor reports a stall at %.2f s (no transition completed "
            "for %.1f s, stick %s): run stopped\n",
            r->t_s, r->mk.since_progress_s, r->status_stick ? "in" : "out");
        res->exit_reason = "stalled";
        return 1;
    }
    return 0;
}

/* Deliveries so far, and the end of the run: 0.5 s after the last
 * workpiece is delivered or dropped and every block is done. */
static void note_deliveries(carry_state *r, const carry_cfg *c)
{
    if (r->delivered > r->last_delivered) {
        if (r->t_deliv_first < 0.0)
            r->t_deliv_first = r->t_s;
        r->t_deliv_last = r->t_s;
        r->last_delivered = r->delivered;
    }
    if (r->end_at < 0.0 && r->delivered + r->dropped >= c->workpieces &&
        (c->serial || c->blocks->cur >= c->blocks->n))
        r->end_at = r->t_s + 0.5;
}

/* The step announced, if any: --fault, the blocks, the record, the answer.
 * 0 go on, 1 stop, CARRY_SCEN_ERR_FAULT. */
static int run_answer(carry_state *r, const carry_cfg *c, carry_result *res, carry_daemons *d)
{
    int k;
    if (r->pending < 0)
        return 0;
    if (r->pending == r->handled) {
        /* the simulator announced the step again (an answer was late or
         * lost): answer again, but record and measure it only once, so
         * the results do not depend on the machine's timing */
        carry_ack(r, r->pending, 0);
        r->pending = -1;
        return 0;
    }
    k = faults_step(r, c, res, d);
    if (k == 1)
        k = hung_step(r, c, res, d);
    if (k < 0) {
        res->exit_reason = "restart_failed";
        return CARRY_SCEN_ERR_FAULT;
    }
    if (k == 0)
        return 0; /* hold the step: a restarted daemon joins */
    r->handled = r->pending;
    if (!c->serial) {
        carry_stick_confirm(r);
        carry_block_step(r, c->blocks);
    }
    record_step(r, c, r->pending);
    note_deliveries(r, c);
    carry_ack(r, r->pending, 0);
    r->pending = -1;
    if (r->end_at >= 0.0 && r->t_s >= r->end_at)
        return 1;
    if (r->t_s >= c->max_sim_s) {
        fprintf(stderr, "tandem-scenario: simulated-time limit %.0f s reached\n", c->max_sim_s);
        res->exit_reason = "sim_time_limit";
        return 1;
    }
    return 0;
}

/* The run's result from its state at the end. */
static void result_of(carry_result *res, const carry_state *r)
{
    /* the last SIM_STATUS may be up to 100 steps old: read the sim log */
    res->delivered = r->delivered;
    res->dropped = r->dropped;
    if (r->have_mk) {
        res->detected = r->mk.detections;
        res->blockages = r->mk.blockages;
        res->replans = r->mk.replans;
        res->deadlocks = r->mk.deadlocks;
        res->invariant_violations = r->mk.invariant_violations;
        res->stalls = r->mk.stalls;
        res->faults = r->mk.faults;
        res->rows_reissued = r->mk.rows_reissued;
        res->dones_recovered = r->mk.dones_recovered;
    }
    res->stick_resends = r->stick_resends;
    res->joint_limit_violations = r->limit_violations;
    res->joint_stop_onsets = r->stop_onsets;
    res->min_range_margin_rad = r->min_range_margin_rad;
    res->max_speed_ratio = r->max_speed_ratio;
    res->max_sync_backtrack_m = r->max_sync_backtrack_m;
    res->max_force_N = r->max_force_N;
    res->max_force_10ms_N = r->max_force_10ms_N;
    res->first_delivery_s = r->t_deliv_first;
    res->last_delivery_s = r->t_deliv_last;
    res->mean_cycle_s = r->last_delivered >= 2
                            ? (r->t_deliv_last - r->t_deliv_first) / (r->last_delivered - 1)
                            : NAN;
}

int carry_run_once(const carry_cfg *c, carry_result *res)
{
    carry_state R;
    carry_daemons d;
    names_watch names;
    const double wall0 = scenario_wall_s();
    double next_progress = wall0 + PROGRESS_EVERY_S;
    int rc = 0;
    memset(res, 0, sizeof *res);
    state_init(&R);
    res->exit_reason = "completed";
    daemons_argv(&d, c);
    names_watch_init(&names, "tandem-scenario");
    R.bus = run_key_bus();
    R.lcm = lcm_create(d.url);
    if (!R.lcm) {
        fprintf(stderr, "tandem-scenario: cannot open LCM at %s\n", d.url);
        return CARRY_SCEN_ERR_RUN;
    }
    carry_subscribe(&R);
    if (daemons_start(&d, c) != 0) {
        auth_bus_close(R.bus, R.lcm);
        return CARRY_SCEN_ERR_RUN;
    }
    hang_watch_subscribe(&d.hw, R.bus, R.lcm);
    R.hw = &d.hw;
    while (!interrupted && rc == 0) {
        lcm_handle_timeout(R.lcm, 200);
        bus_names_watch(&names, R.bus, &R.lcm, d.url); /* a flood of channel names: a new handle */
        rc = run_watch(&R, c, res, &d, wall0, &next_progress);
        if (rc == 0)
            rc = run_answer(&R, c, res, &d);
    }
    if (interrupted)
        res->exit_reason = "interrupted";
    carry_ack(&R, R.pending >= 0 ? R.pending : 0, 1);
    carry_send_control(&R, TANDEM_SIM_CONTROL_T_QUIT, 0, 0);
    hang_watch_stop(&d.hw, R.lcm);
    res->sim_s = R.t_s;
    proc_kill_all(&d.ps, 3.0);
    res->wall_s = scenario_wall_s() - wall0;
    result_of(res, &R);
    res->ok = rc >= 0;
    auth_bus_close(R.bus, R.lcm);
    R.lcm = NULL;
    return rc < 0 ? CARRY_SCEN_ERR_RUN : 0;
}

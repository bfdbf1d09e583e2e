/* tandem-scenario carry: the seed-000 experiment (docs/method/carry.md §8).
 *
 * Spawns tandem-sim, tandem-arm 1 and 2 and tandem-supervisor in lockstep
 * on a private LCM URL and joins the lockstep itself (it answers every
 * step), so the stick goes in and out at exact simulated times and every
 * step is recorded. A block ARM:LINK:START_S:DURATION_S[:t3] is armed at
 * START_S and inserted at the first step after it at which that arm's
 * tool moves (> 3 cm/s; in t3 > 10 cm/s) -- and, with ":t3", while the synchronised t3
 * runs -- so every block meets a moving link; it is removed DURATION_S
 * later. Blocks run one after the other (one stick).
 *
 * t3 blocks: the blocked arm's stop is the first step after contact at
 * which its s gained less than 0.1 mm over 10 ms; the partner's stop the
 * same test on its s; latency = partner stop - blocked stop; lead = the
 * partner's s minus its reference k_p s*.
 *
 * Then (unless --no-serial) the same task with --serial on the
 * supervisor (a new workpiece only when the previous one is delivered and
 * both arms are home), without blocks, for serial_cycle_s.
 *
 * Resume: when the stick comes out while the blocked arm runs a row (its
 * last event is not DONE), the arm has resumed at the first step at which
 * its tool is 5 mm from where it was at removal, or it reports UNBLOCKED
 * or DONE; resume_latency = that step - removal.
 *
 * Health of the run, from the arms' measured state every step: joint
 * range violations (onsets of a joint past its range by more than
 * ARM_RANGE_TOL_RAD), the largest |qd_i| / qd_max_i, and the contact force
 * raw (1 ms) and 10 ms-averaged. The run stops when the supervisor reports
 * a stall, a daemon dies, or the simulated or wall time limit is reached;
 * it exits 0 only when every success criterion holds (carry_criteria),
 * 3 otherwise with the failed criteria on its last line.
 *
 * Output: summary.json, timeseries.csv (10 ms), joints.csv (both arms'
 * joint angles, 10 ms), blocks.csv, transitions.csv, s.png, force.png,
 * gantt.png, and the daemons' logs.
 */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "scenario.h"
#include "arm_model.h"
#include "proc.h"
#include "prng.h"
#include "tandem_action_event_t.h"
#include "tandem_arm_state_t.h"
#include "daemon.h"
#include "options.h"
#include "tandem_clock_ack_t.h"
#include "tandem_petri_marking_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

#define MAX_BLOCKS 64
#define MAX_TRANS_LOG 4096
#define MOVING_MPS 0.03          /* a block waits for its arm to move this fast ... */
#define MOVING_T3_MPS 0.10       /* ... or, in t3, this fast (cruise) */
#define CONTACT_N 0.5
#define LURCH_WINDOW_S 2.0
#define STOP_MPS 0.01
#define BLOCK_SETTLED_S 0.5      /* contact force "settled": this long after contact */
#define NT 8
#define RESUME_MOVE_M 0.005      /* resumed: the tool is this far from where it was at removal */
#define PROGRESS_EVERY_S 5.0     /* wall time between progress lines */
/* The simulator drops a lockstep participant that has not answered for
 * this long. A run with a dropped controller is not the seed's run, and a
 * daemon that really died is seen by its exit: so only after 10 minutes
 * (a loaded machine can starve a controller for tens of seconds). */
#define LOCKSTEP_TIMEOUT_MS "600000"
/* success criteria (the figures a carry run must show) */
#define CRIT_FORCE_10MS_N 1000.0
#define CRIT_RESUME_S 1.0

typedef struct block {
    int    arm, link, need_t3;
    double start_s, dur_s;
    /* measured */
    double in_s, out_s, contact_s, self_stop_s, partner_stop_s;
    double max_force_N, force_sum_N, force_late_sum_N;
    long   force_n, force_late_n;
    double lead_max_m, lurch_mps;
    double out_pos_m[3], resume_s;   /* tool at removal; resumed at (< 0: not yet) */
    int    row_running_at_out;       /* the arm had a row to finish when the stick came out */
    int    during_t3, done;
} block;

typedef struct run_cfg {
    int    workpieces;
    int    controller_time;
    int    serial;
    double max_sim_s;
    const char *out;
    const char *tag;           /* "run" or "serial": log names */
    const char *url;           /* --lcm-url, or NULL: a private udpm port */
    const char *block_detect;  /* tandem-arm --block-detect on|off */
    const char *stall_s;       /* tandem-supervisor --stall-s */
    uint64_t seed;
    scenario_drop drop;        /* --drop-rate, to every daemon */
    scenario_fault *faults;    /* --fault (the main run only) */
    int    n_faults;
} run_cfg;

typedef struct run_result {
    int    detected, delivered, dropped, blockages, replans, deadlocks;
    long   invariant_violations;
    double max_contact_N, max_lurch_mps, mean_blocked_force_N;
    double first_delivery_s, last_delivery_s, mean_cycle_s;
    double sim_s, wall_s;
    int    ok;
    /* health of the run */
    long   joint_limit_violations, joint_stop_onsets;
    double max_speed_ratio, max_force_N, max_force_10ms_N, min_range_margin_rad;
    int    stalls, faults;
    int    kills, restarts, rows_reissued, dones_recovered;
    const char *exit_reason;
} run_result;

/* ---- state of one run ------------------------------------------------------ */

static struct {
    lcm_t   *lcm;
    int64_t  pending;            /* step to answer, -1 none */
    int64_t  handled;            /* last step recorded, -1 none */
    double   t_s;
    tandem_arm_state_t arm[2];
    int      have_arm[2];
    double   prev_tool[2][3];
    double   speed[2];
    double   s[2], s_f[2];
    int      tr[2];              /* transition of the last progress */
    int64_t  s_step[2];
    double   s_hist[2][16];      /* s at the last 16 steps, ring */
    tandem_petri_marking_t mk;
    int8_t   mk_marking[16], mk_running[16];
    int      have_mk;
    int      delivered, dropped, spawned;
    int64_t  ack_seq;
    int      running_prev[NT];
    double   run_start[NT];
    /* per arm: the last event other than PROGRESS, and when UNBLOCKED / DONE came */
    int      last_event[2];
    int64_t  unblocked_step[2], done_step[2];
    /* health of the run from the measured states */
    unsigned range_bits[2];      /* joints past their range at the last state */
    unsigned stop_bits[2];       /* joints at (or past) a range end at the last state */
    long     limit_violations, stop_onsets;
    double   max_speed_ratio, max_force_N, max_force_10ms_N;
    double   min_range_margin_rad; /* least distance of a joint from a range end */
    /* --fault: the last step each daemon answered (SIM_ACK) */
    int64_t  ack_step[4];
    double   hold_since_s;     /* wall time a restart began holding the step */
} R;

/* The daemons of a run: proc slot k, --fault name, lockstep name. */
static const char *const daemon_fault_name[4] = { "sim", "arm1", "arm2", "supervisor" };
static const char *const daemon_lock_name[4] = { "tandem-sim", "tandem-arm-1", "tandem-arm-2", "tandem-supervisor" };

static block blocks[MAX_BLOCKS];
static int n_blocks;
static FILE *f_ts, *f_tr, *f_q;

static void on_sim_ack(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_clock_ack_t m;
    int k;
    (void)ch; (void)u;
    if (tandem_clock_ack_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    for (k = 0; k < 4; k++)
        if (!m.leaving && !strcmp(m.name, daemon_lock_name[k]) && m.step > R.ack_step[k])
            R.ack_step[k] = m.step;
    tandem_clock_ack_t_decode_cleanup(&m);
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_clock_t m;
    (void)ch; (void)u;
    if (tandem_sim_clock_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    if (m.mode == TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP && m.step >= 0) {
        R.pending = m.step;
        R.t_s = m.sim_time_s;
    }
    tandem_sim_clock_t_decode_cleanup(&m);
}

/* Range violations (onsets per joint), joints on their range stops
 * (onsets of a joint within ARM_RANGE_TOL_RAD of a range end, or past
 * it), the least margin to a range end, speed ratio and contact forces. */
static void arm_health(int a, const tandem_arm_state_t *m)
{
    const arm_model *pm = &arm_model_puma560;
    const unsigned range = ARM_FAULT_RANGE(arm_joint_faults(pm, m->q_rad, m->qd_radps));
    unsigned stop = 0;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        const double margin = fmin(m->q_rad[i] - pm->q_min_rad[i], pm->q_max_rad[i] - m->q_rad[i]);
        if ((range & (1u << i)) && !(R.range_bits[a] & (1u << i)))
            R.limit_violations++;
        if (margin <= ARM_RANGE_TOL_RAD)
            stop |= 1u << i;
        if ((stop & (1u << i)) && !(R.stop_bits[a] & (1u << i)))
            R.stop_onsets++;
        R.min_range_margin_rad = fmin(R.min_range_margin_rad, margin);
        R.max_speed_ratio = fmax(R.max_speed_ratio, fabs(m->qd_radps[i]) / pm->qd_max_radps[i]);
    }
    R.range_bits[a] = range;
    R.stop_bits[a] = stop;
    R.max_force_N = fmax(R.max_force_N, m->max_contact_force_N);
    R.max_force_10ms_N = fmax(R.max_force_10ms_N, m->max_contact_force_10ms_N);
}

static void on_arm(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_arm_state_t m;
    int a;
    (void)ch; (void)u;
    if (tandem_arm_state_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    a = m.arm - 1;
    if (a == 0 || a == 1) {
        if (R.have_arm[a] && m.step > R.arm[a].step) {
            const double dt = (double)(m.step - R.arm[a].step) * 1e-3;
            const double dx = m.tool_position_m[0] - R.arm[a].tool_position_m[0];
            const double dy = m.tool_position_m[1] - R.arm[a].tool_position_m[1];
            const double dz = m.tool_position_m[2] - R.arm[a].tool_position_m[2];
            R.speed[a] = sqrt(dx * dx + dy * dy + dz * dz) / dt;
        }
        R.arm[a] = m;
        R.have_arm[a] = 1;
        arm_health(a, &m);
    }
    tandem_arm_state_t_decode_cleanup(&m);
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_action_event_t e;
    (void)ch; (void)u;
    if (tandem_action_event_t_decode(rb->data, 0, rb->data_size, &e) < 0)
        return;
    if ((e.arm == 1 || e.arm == 2) && e.event == TANDEM_ACTION_EVENT_T_PROGRESS) {
        R.s[e.arm - 1] = e.s_m;
        R.s_f[e.arm - 1] = e.s_f_m;
        R.tr[e.arm - 1] = e.transition;
        R.s_step[e.arm - 1] = e.step;
    } else if (e.arm == 1 || e.arm == 2) {
        R.last_event[e.arm - 1] = e.event;
        if (e.event == TANDEM_ACTION_EVENT_T_UNBLOCKED)
            R.unblocked_step[e.arm - 1] = e.step;
        if (e.event == TANDEM_ACTION_EVENT_T_DONE)
            R.done_step[e.arm - 1] = e.step;
    }
    tandem_action_event_t_decode_cleanup(&e);
}

static void on_marking(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_petri_marking_t m;
    int i;
    (void)ch; (void)u;
    if (tandem_petri_marking_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    if (m.n_places <= 16 && m.n_transitions <= 16) {
        R.mk = m;
        for (i = 0; i < m.n_places; i++)
            R.mk_marking[i] = m.marking[i];
        for (i = 0; i < m.n_transitions; i++)
            R.mk_running[i] = m.running[i];
        R.mk.marking = R.mk_marking;
        R.mk.running = R.mk_running;
        R.have_mk = 1;
    }
    tandem_petri_marking_t_decode_cleanup(&m);
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_status_t m;
    (void)ch; (void)u;
    if (tandem_sim_status_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    R.delivered = m.workpieces_delivered;
    R.dropped = m.workpieces_dropped;
    R.spawned = m.workpieces_spawned;
    tandem_sim_status_t_decode_cleanup(&m);
}

static void send_control(int cmd, int arm, int link)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.utime = 0;
    c.command = (int8_t)cmd;
    c.target = arm;
    c.link = link;
    c.length_m = cmd == TANDEM_SIM_CONTROL_T_INSERT_STICK ? 0.3 : 0.0;
    c.radius_m = cmd == TANDEM_SIM_CONTROL_T_INSERT_STICK ? 0.02 : 0.0;
    AUTH_PUBLISH(tandem_sim_control_t, R.lcm, "SIM_CONTROL", &c);
}

static void ack(int64_t step, int leaving)
{
    lockstep_ack(R.lcm, "tandem-scenario", R.ack_seq++, step, 1, leaving);
}

static int t3_running(void)
{
    return R.have_mk && R.mk.n_transitions > 2 && R.mk.running[2];
}

/* ---- blocks ---------------------------------------------------------------- */

static int cur_block;          /* index of the block armed or in, n_blocks when all done */
static double gap_after_s;     /* start of the next block counted from the end of this one */

static void block_step(void)
{
    block *b;
    int a, p;
    if (cur_block >= n_blocks)
        return;
    b = &blocks[cur_block];
    a = b->arm - 1;
    p = 1 - a;
    if (b->in_s < 0.0) {
        if (R.t_s >= b->start_s && R.speed[a] > (b->need_t3 ? MOVING_T3_MPS : MOVING_MPS) &&
            (!b->need_t3 || t3_running())) {
            send_control(TANDEM_SIM_CONTROL_T_INSERT_STICK, b->arm, b->link);
            b->in_s = R.t_s;
            b->during_t3 = t3_running();
        } else if (R.t_s > b->start_s + 300.0) {
            b->done = 1;          /* never met a moving arm: skipped */
            cur_block++;
        }
        return;
    }
    if (b->out_s < 0.0) {
        const double f = R.arm[a].max_contact_force_N;
        if (f > b->max_force_N)
            b->max_force_N = f;
        if (f > CONTACT_N && b->contact_s < 0.0)
            b->contact_s = R.t_s;
        if (b->contact_s >= 0.0 && R.t_s - b->contact_s > 0.1 && f > 0.0) {
            b->force_sum_N += f;
            b->force_n++;
        }
        /* after the arm's blocked detector (0.3 s still) has switched the
         * law to leaning with the bias only */
        if (b->contact_s >= 0.0 && R.t_s - b->contact_s > BLOCK_SETTLED_S && f > 0.0) {
            b->force_late_sum_N += f;
            b->force_late_n++;
        }
        if (b->during_t3 && b->contact_s >= 0.0 && R.tr[0] == 3 && R.tr[1] == 3 &&
            R.s_f[0] > 0.0 && R.s_f[1] > 0.0) {
            /* partner stop: its s advances by less than STOP_MPS * 10 ms
             * over the last 10 steps; lead over its reference k_p s* */
            const double l_max = fmax(R.s_f[0], R.s_f[1]);
            const double kb = R.s_f[a] / l_max, kp = R.s_f[p] / l_max;
            const double lead = R.s[p] - kp * (R.s[a] / kb);
            const double ds = R.s[p] - R.s_hist[p][(R.pending + 6) & 15];
            const double ds_self = R.s[a] - R.s_hist[a][(R.pending + 6) & 15];
            if (lead > b->lead_max_m)
                b->lead_max_m = lead;
            if (b->self_stop_s < 0.0 && ds_self < STOP_MPS * 0.010)
                b->self_stop_s = R.t_s;
            if (b->self_stop_s >= 0.0 && b->partner_stop_s < 0.0 && ds < STOP_MPS * 0.010)
                b->partner_stop_s = R.t_s;
        }
        if (R.t_s >= b->in_s + b->dur_s) {
            send_control(TANDEM_SIM_CONTROL_T_REMOVE_STICK, 0, 0);
            b->out_s = R.t_s;
            memcpy(b->out_pos_m, R.arm[a].tool_position_m, sizeof b->out_pos_m);
            b->row_running_at_out = R.last_event[a] != TANDEM_ACTION_EVENT_T_DONE;
            b->resume_s = b->row_running_at_out ? -1.0 : b->out_s;
        }
        return;
    }
    if (b->resume_s < 0.0) {
        const int64_t out_step = (int64_t)(b->out_s * 1000.0 + 0.5);
        double d[3];
        int i;
        for (i = 0; i < 3; i++)
            d[i] = R.arm[a].tool_position_m[i] - b->out_pos_m[i];
        if (sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) >= RESUME_MOVE_M ||
            R.unblocked_step[a] >= out_step || R.done_step[a] >= out_step)
            b->resume_s = R.t_s;
    }
    if (R.t_s <= b->out_s + LURCH_WINDOW_S || b->resume_s < 0.0) {
        if (R.speed[a] > b->lurch_mps && R.t_s <= b->out_s + LURCH_WINDOW_S)
            b->lurch_mps = R.speed[a];
        return;
    }
    b->done = 1;
    cur_block++;
    if (cur_block < n_blocks && blocks[cur_block].start_s < R.t_s)
        blocks[cur_block].start_s = R.t_s + gap_after_s;
}

/* ---- recording --------------------------------------------------------------- */

static void record_step(int64_t step)
{
    int a, t;
    for (a = 0; a < 2; a++)
        R.s_hist[a][step & 15] = R.s[a];
    if (R.have_mk && f_tr) {
        for (t = 0; t < NT && t < R.mk.n_transitions; t++) {
            if (R.mk.running[t] && !R.running_prev[t])
                R.run_start[t] = R.t_s;
            if (!R.mk.running[t] && R.running_prev[t])
                fprintf(f_tr, "%d,%.3f,%.3f\n", t + 1, R.run_start[t], R.t_s);
            R.running_prev[t] = R.mk.running[t];
        }
    }
    if (f_ts && step % 10 == 0) {
        int stick = cur_block < n_blocks && blocks[cur_block].in_s >= 0.0 && blocks[cur_block].out_s < 0.0;
        fprintf(f_ts, "%.3f,%.5f,%.5f,%d,%.5f,%.5f,%d,%.4f,%.4f,%.3f,%.3f,%d,%d,%d,%.3f,%.3f\n", R.t_s,
                R.s[0], R.s_f[0], R.tr[0], R.s[1], R.s_f[1], R.tr[1], R.speed[0], R.speed[1],
                R.arm[0].max_contact_force_N, R.arm[1].max_contact_force_N,
                stick ? blocks[cur_block].arm : 0, R.delivered, R.dropped,
                R.arm[0].max_contact_force_10ms_N, R.arm[1].max_contact_force_10ms_N);
    }
    if (f_q && step % 10 == 0) {
        int a, i;
        fprintf(f_q, "%.3f", R.t_s);
        for (a = 0; a < 2; a++)
            for (i = 0; i < ARM_NJ; i++)
                fprintf(f_q, ",%.5f", R.arm[a].q_rad[i]);
        fputc('\n', f_q);
    }
}

/* ---- one run --------------------------------------------------------------- */

/* One line on stderr every PROGRESS_EVERY_S of wall time. */
static void progress_line(const run_cfg *c, double wall0)
{
    const double wall = scenario_wall_s() - wall0;
    char blk[64] = "no block";
    if (cur_block < n_blocks && blocks[cur_block].in_s >= 0.0 && blocks[cur_block].out_s < 0.0)
        snprintf(blk, sizeof blk, "block %d/%d in (arm %d link %d)", cur_block + 1, n_blocks,
                 blocks[cur_block].arm, blocks[cur_block].link);
    else if (cur_block < n_blocks)
        snprintf(blk, sizeof blk, "block %d/%d armed", cur_block + 1, n_blocks);
    fprintf(stderr, "tandem-scenario carry %s: t %.1f s (%.1fx real time), delivered %d/%d, dropped %d, %s, "
                    "max contact %.0f N (10 ms)%s\n", c->tag, R.t_s, wall > 0.0 ? R.t_s / wall : 0.0, R.delivered,
            c->workpieces, R.dropped, blk, R.max_force_10ms_N,
            R.max_force_10ms_N > CRIT_FORCE_10MS_N ? " IMPLAUSIBLE" : "");
}

static volatile sig_atomic_t interrupted;
static void on_sigint(int s) { (void)s; interrupted = 1; }

/* The options every daemon of a run gets besides its own (--drop-rate),
 * appended at argv[n] with the closing NULL. */
static void daemon_argv_finish(const run_cfg *c, const char **argv, int n, int cap)
{
    scenario_argv_drop(&c->drop, (char **)argv, &n, cap);
}

/* --fault, at the step about to be answered: kill (SIGKILL, and the
 * simulator is told the daemon left so it does not wait out its timeout),
 * then restart at the first step after RESTART_T that every controller
 * answers (a multiple of 20 ms), holding that step until the new process
 * has answered it. 1: go on, 0: hold the step, -1: the restart failed. */
static int faults_step(const run_cfg *c, run_result *res, proc_set *ps, pid_t pid[4],
                       const char *const *argvs[4], const char *url, const char *err)
{
    int i;
    for (i = 0; i < c->n_faults; i++) {
        scenario_fault *f = &c->faults[i];
        if (f->stage == 0 && R.t_s >= f->kill_s) {
            proc_kill(ps, pid[f->slot]);
            lockstep_ack(R.lcm, daemon_lock_name[f->slot], 0, R.pending, 1, 1);
            fprintf(stderr, "tandem-scenario: fault: %s killed at %.3f s\n", f->daemon, R.t_s);
            res->kills++;
            f->stage = f->restart_s >= 0.0 ? 1 : 3;
        }
        if (f->stage == 1 && R.t_s >= f->restart_s && R.pending % 20 == 0) {
            char log[700];
            snprintf(log, sizeof log, "%s/%s_%s_restart%d.log", c->out, c->tag, f->daemon, i + 1);
            pid[f->slot] = proc_spawn(ps, argvs[f->slot], url, log, err);
            if (pid[f->slot] < 0)
                return -1;
            fprintf(stderr, "tandem-scenario: fault: %s restarted at %.3f s\n", f->daemon, R.t_s);
            R.hold_since_s = scenario_wall_s();
            f->stage = 2;
        }
        if (f->stage == 2) {
            if (R.ack_step[f->slot] < R.pending) {
                if (scenario_wall_s() - R.hold_since_s > 60.0) {
                    fprintf(stderr, "tandem-scenario: fault: %s did not rejoin within 60 s\n", f->daemon);
                    return -1;
                }
                return 0;
            }
            res->restarts++;
            f->stage = 3;
        }
    }
    return 1;
}

static int run_once(const run_cfg *c, run_result *res)
{
    char url[96], nbuf[32], sbuf[32], path[4][1024], err[1024];
    proc_set ps;
    const double wall0 = scenario_wall_s();
    double t_deliv_first = -1.0, t_deliv_last = -1.0, end_at = -1.0;
    int last_delivered = 0, k, rc = 0;
    char journal[700];
    const char *sim_argv[16] = { "tandem-sim", "--lockstep", "--expect", "4", "--workpieces", nbuf,
                                 "--seed", sbuf, "--timeout-ms", LOCKSTEP_TIMEOUT_MS };
    const char *a1_argv[16] = { "tandem-arm", "--arm", "1", "--lockstep", "--block-detect", c->block_detect };
    const char *a2_argv[16] = { "tandem-arm", "--arm", "2", "--lockstep", "--block-detect", c->block_detect };
    const char *sup_argv[20] = { "tandem-supervisor", "--lockstep", "--stall-s", c->stall_s, "--controller",
                                 c->controller_time ? "time" : "event", "--journal", journal };
    const char *const *argvs[4] = { sim_argv, a1_argv, a2_argv, sup_argv };
    pid_t pid[4];
    double next_progress = wall0 + PROGRESS_EVERY_S;
    memset(res, 0, sizeof *res);
    memset(&R, 0, sizeof R);
    R.pending = R.handled = -1;
    R.min_range_margin_rad = INFINITY;
    R.last_event[0] = R.last_event[1] = TANDEM_ACTION_EVENT_T_DONE;   /* idle until a row starts */
    R.unblocked_step[0] = R.unblocked_step[1] = R.done_step[0] = R.done_step[1] = -1;
    res->exit_reason = "completed";
    snprintf(nbuf, sizeof nbuf, "%d", c->workpieces);
    snprintf(sbuf, sizeof sbuf, "%llu", (unsigned long long)c->seed);
    if (c->url)
        snprintf(url, sizeof url, "%s", c->url);
    else
        snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", 30000 + (int)(getpid() % 20000) + (c->serial ? 1 : 0));
    R.lcm = lcm_create(url);
    if (!R.lcm) {
        fprintf(stderr, "tandem-scenario: cannot open LCM at %s\n", url);
        return -1;
    }
    auth_bus_subscribe(R.lcm, "SIM_CLOCK", on_clock, NULL);
    auth_bus_subscribe(R.lcm, "ARM1_STATE", on_arm, NULL);
    auth_bus_subscribe(R.lcm, "ARM2_STATE", on_arm, NULL);
    auth_bus_subscribe(R.lcm, "ARM_EVENTS", on_event, NULL);
    auth_bus_subscribe(R.lcm, "PETRI_MARKING", on_marking, NULL);
    auth_bus_subscribe(R.lcm, "SIM_STATUS", on_status, NULL);
    auth_bus_subscribe(R.lcm, "SIM_ACK", on_sim_ack, NULL);
    proc_init(&ps, NULL);
    snprintf(journal, sizeof journal, "%s/%s_supervisor.journal", c->out, c->tag);
    remove(journal);                  /* a fresh run; a restart reads it */
    daemon_argv_finish(c, sim_argv, 10, 16);
    daemon_argv_finish(c, a1_argv, 6, 16);
    daemon_argv_finish(c, a2_argv, 6, 16);
    if (c->serial) sup_argv[8] = "--serial";
    daemon_argv_finish(c, sup_argv, c->serial ? 9 : 8, 20);
    {
        snprintf(err, sizeof err, "%s/%s_stderr.log", c->out, c->tag);
        remove(err);
        for (k = 0; k < 4; k++) {
            snprintf(path[k], sizeof path[k], "%s/%s_%s.log", c->out, c->tag, daemon_fault_name[k]);
            if ((pid[k] = proc_spawn(&ps, argvs[k], url, path[k], err)) < 0) {
                fprintf(stderr, "tandem-scenario: cannot start %s\n", argvs[k][0]);
                proc_kill_all(&ps, 1.0);
                lcm_destroy(R.lcm);
                return -1;
            }
        }
    }
    while (!interrupted) {
        lcm_handle_timeout(R.lcm, 200);
        for (k = 0; k < ps.n; k++) {
            int st;
            if (ps.alive[k] && proc_poll(&ps, ps.pid[k], &st) == 1) {
                fprintf(stderr, "tandem-scenario: a daemon exited early (status %d); see %s\n", st, err);
                res->exit_reason = "daemon_exited";
                rc = -1;
            }
        }
        if (rc != 0)
            break;
        if (scenario_wall_s() - wall0 > 3600.0) {
            fprintf(stderr, "tandem-scenario: wall-time limit reached\n");
            res->exit_reason = "wall_time_limit";
            break;
        }
        if (scenario_wall_s() >= next_progress) {
            next_progress += PROGRESS_EVERY_S;
            progress_line(c, wall0);
        }
        if (R.have_mk && R.mk.stalled) {
            fprintf(stderr, "tandem-scenario: the supervisor reports a stall at %.2f s (no transition completed "
                            "for %.1f s with the stick out): run stopped\n", R.t_s, R.mk.stall_limit_s);
            res->exit_reason = "stalled";
            break;
        }
        if (R.pending < 0)
            continue;
        if (R.pending == R.handled) {
            /* the simulator announced the step again (an answer was late or
             * lost): answer again, but record and measure it only once, so
             * the results do not depend on the machine's timing */
            ack(R.pending, 0);
            R.pending = -1;
            continue;
        }
        k = faults_step(c, res, &ps, pid, argvs, url, err);
        if (k < 0) {
            rc = -1;
            res->exit_reason = "restart_failed";
            break;
        }
        if (k == 0)
            continue;                 /* hold the step: a restarted daemon joins */
        R.handled = R.pending;
        if (!c->serial)
            block_step();
        record_step(R.pending);
        if (R.delivered > last_delivered) {
            if (t_deliv_first < 0.0)
                t_deliv_first = R.t_s;
            t_deliv_last = R.t_s;
            last_delivered = R.delivered;
        }
        if (end_at < 0.0 && R.delivered + R.dropped >= c->workpieces && (c->serial || cur_block >= n_blocks))
            end_at = R.t_s + 0.5;
        ack(R.pending, 0);
        R.pending = -1;
        if (end_at >= 0.0 && R.t_s >= end_at)
            break;
        if (R.t_s >= c->max_sim_s) {
            fprintf(stderr, "tandem-scenario: simulated-time limit %.0f s reached\n", c->max_sim_s);
            res->exit_reason = "sim_time_limit";
            break;
        }
    }
    if (interrupted)
        res->exit_reason = "interrupted";
    ack(R.pending >= 0 ? R.pending : 0, 1);
    send_control(TANDEM_SIM_CONTROL_T_QUIT, 0, 0);
    res->sim_s = R.t_s;
    proc_kill_all(&ps, 3.0);
    res->wall_s = scenario_wall_s() - wall0;
    /* the last SIM_STATUS may be up to 100 steps old: read the sim log */
    res->delivered = R.delivered;
    res->dropped = R.dropped;
    if (R.have_mk) {
        res->detected = R.mk.detections;
        res->blockages = R.mk.blockages;
        res->replans = R.mk.replans;
        res->deadlocks = R.mk.deadlocks;
        res->invariant_violations = R.mk.invariant_violations;
        res->stalls = R.mk.stalls;
        res->faults = R.mk.faults;
        res->rows_reissued = R.mk.rows_reissued;
        res->dones_recovered = R.mk.dones_recovered;
    }
    res->joint_limit_violations = R.limit_violations;
    res->joint_stop_onsets = R.stop_onsets;
    res->min_range_margin_rad = R.min_range_margin_rad;
    res->max_speed_ratio = R.max_speed_ratio;
    res->max_force_N = R.max_force_N;
    res->max_force_10ms_N = R.max_force_10ms_N;
    res->first_delivery_s = t_deliv_first;
    res->last_delivery_s = t_deliv_last;
    res->mean_cycle_s = last_delivered >= 2 ? (t_deliv_last - t_deliv_first) / (last_delivered - 1) : NAN;
    res->ok = rc == 0;
    lcm_destroy(R.lcm);
    R.lcm = NULL;
    return rc;
}

/* ---- options, plots, summary ------------------------------------------------- */

static int parse_block(const char *s, block *b)
{
    char t3[8] = "";
    int n;
    memset(b, 0, sizeof *b);
    n = sscanf(s, "%d:%d:%lf:%lf:%7s", &b->arm, &b->link, &b->start_s, &b->dur_s, t3);
    if (n < 4 || b->arm < 1 || b->arm > 2 || b->link < 1 || b->link > 6 || !isfinite(b->start_s) ||
        b->start_s < 0.0 || !isfinite(b->dur_s) || b->dur_s <= 0.0 || b->dur_s > 3600.0 ||
        (n == 5 && strcmp(t3, "t3") != 0))
        return -1;
    b->need_t3 = n == 5;
    return 0;
}

static void random_blocks(int k, uint64_t seed)
{
    prng_state r;
    double t = 5.0;
    int i;
    prng_seed(&r, seed * 104729u + 3u);
    for (i = 0; i < k && n_blocks < MAX_BLOCKS; i++) {
        block *b = &blocks[n_blocks++];
        memset(b, 0, sizeof *b);
        b->arm = 1 + (int)(prng_uniform(&r) * 2.0);
        b->link = 2 + (int)(prng_uniform(&r) * 4.0);
        b->dur_s = 0.2 + 59.8 * prng_uniform(&r);
        b->need_t3 = i % 3 == 2;
        b->start_s = t;
        t += 2.0 + 10.0 * prng_uniform(&r);
    }
}

static void write_blocks_csv(const char *dir)
{
    FILE *f = scenario_fopen(dir, "blocks.csv");
    int i;
    if (!f)
        return;
    fprintf(f, "arm,link,armed_s,in_s,out_s,duration_s,during_t3,contact_s,max_force_N,mean_force_N,"
               "blocked_stop_s,partner_stop_latency_s,partner_lead_max_m,lurch_mps,mean_force_settled_N\n");
    for (i = 0; i < n_blocks; i++) {
        const block *b = &blocks[i];
        fprintf(f, "%d,%d,%.3f,%.3f,%.3f,%.3f,%d,%.3f,%.2f,%.2f,%.3f,%.4f,%.4f,%.3f,%.2f\n", b->arm, b->link, b->start_s,
                b->in_s, b->out_s, b->dur_s, b->during_t3, b->contact_s, b->max_force_N,
                b->force_n ? b->force_sum_N / (double)b->force_n : 0.0, b->self_stop_s,
                b->partner_stop_s >= 0.0 ? b->partner_stop_s - b->self_stop_s : NAN,
                b->lead_max_m, b->lurch_mps,
                b->force_late_n ? b->force_late_sum_N / (double)b->force_late_n : NAN);
    }
    fclose(f);
}

static void write_plots(const char *dir)
{
    FILE *g = scenario_fopen(dir, "plots.gp");
    int i;
    if (!g)
        return;
    fprintf(g, "set datafile separator ','\nset terminal pngcairo size 1200,500\nset key outside\n");
    for (i = 0; i < n_blocks; i++)
        if (blocks[i].in_s >= 0.0)
            fprintf(g, "set object %d rect from %.3f, graph 0 to %.3f, graph 1 fc rgb '%s' fs solid 0.25 noborder\n",
                    i + 1, blocks[i].in_s, blocks[i].out_s >= 0 ? blocks[i].out_s : blocks[i].in_s + blocks[i].dur_s,
                    blocks[i].arm == 1 ? "#ff8080" : "#8080ff");
    fprintf(g, "set output 's.png'\nset title 'path length s(t) of the running segment per arm (shaded: stick in, "
               "in the colour of the arm it blocks)'\n"
               "set xlabel 'sim time (s)'\nset ylabel 's (m)'\n"
               "plot 'timeseries.csv' every ::1 using 1:2 with lines lw 1.5 lc rgb '#c00000' title 'arm 1', "
               "'' every ::1 using 1:5 with lines lw 1.5 lc rgb '#0000c0' title 'arm 2'\n");
    /* the force sensor's 10 ms average, as a real stick's sensor reads it
     * (the raw 1 ms maximum is in the CSV) */
    fprintf(g, "set output 'force.png'\nset title 'largest link contact force, 10 ms average'\n"
               "set ylabel 'force (N)'\nset yrange [0:*]\n"
               "plot 'timeseries.csv' every ::1 using 1:15 with lines lc rgb '#c00000' title 'arm 1', "
               "'' every ::1 using 1:16 with lines lc rgb '#0000c0' title 'arm 2'\nset autoscale y\n");
    fprintf(g, "unset object\nset output 'gantt.png'\nset title 'transitions per arm (running intervals; t3, t4 involve both arms)'\n"
               "set ylabel ''\nset ytics ('arm 1' 1, 'arm 2' 2)\nset yrange [0.3:2.9]\nset xlabel 'sim time (s)'\n"
               "a1(t) = (t==1||t==2||t==3||t==4||t==6)\na2(t) = (t==3||t==4||t==5||t==7)\n"
               "plot 'transitions.csv' every ::1 using 2:(a1($1)?1:1/0):($3-$2):(0):1 with vectors nohead lw 14 lc variable notitle, "
               "'' every ::1 using 2:(a2($1)?2:1/0):($3-$2):(0):1 with vectors nohead lw 14 lc variable notitle, "
               "'' every ::1 using (($2+$3)/2):(a1($1)?1.3:1/0):(sprintf('t%%d',$1)) with labels font ',8' notitle, "
               "'' every ::1 using (($2+$3)/2):(a2($1)?2.3:1/0):(sprintf('t%%d',$1)) with labels font ',8' notitle\n");
    fclose(g);
    scenario_gnuplot(dir, "plots.gp");
}

/* Appends the failed success criteria to buf (space separated); returns
 * how many failed. */
static int carry_criteria(const run_cfg *c, const run_result *r, double resume_max_s, char *buf, size_t cap)
{
    const scenario_criterion k[] = {
        { strcmp(r->exit_reason, "completed") != 0, "exit_reason" },
        { r->delivered != c->workpieces, "workpieces_delivered" },
        { r->dropped != 0, "workpieces_dropped" },
        { r->joint_limit_violations != 0, "joint_limit_violations" },
        { !(r->max_speed_ratio <= 1.0), "max_joint_speed_ratio" },
        { !(r->max_force_10ms_N <= CRIT_FORCE_10MS_N), "max_contact_force_10ms_N" },
        { !(resume_max_s <= CRIT_RESUME_S), "resume_latency_max_s" },
        { r->stalls != 0, "stalls" },
        { r->invariant_violations != 0, "invariant_violations" },
        { r->deadlocks != 0, "deadlocks" },
    };
    return scenario_failed_criteria(k, (int)(sizeof k / sizeof k[0]), buf, cap);
}

/* What the command line sets; run() copies it out. */
typedef struct carry_options {
    run_cfg cfg;               /* workpieces, controller_time, out, url, n_faults */
    int    block_detect;       /* index in options_on_off */
    int    n_random, no_serial, serial_n;
    long   seed;
    double stall_s;
    const char *drop_arg;
    int    out_given;
} carry_options;

/* --block A:L:S:D[:t3], repeatable: into blocks[] */
static int option_block(const char *prog, void *dest, char *value)
{
    (void)dest;
    if (n_blocks >= MAX_BLOCKS || parse_block(value, &blocks[n_blocks]) != 0) {
        fprintf(stderr, "%s: --block: '%s' is not ARM:LINK:START_S:DURATION_S[:t3] "
                        "(arm 1-2, link 1-6, start >= 0, 0 < duration <= 3600)\n", prog, value);
        return OPTIONS_ERR_SAID;
    }
    n_blocks++;
    return 0;
}

/* --fault kill:D:T[:R], repeatable: into cfg->faults */
static int option_fault(const char *prog, void *dest, char *value)
{
    run_cfg *cfg = dest;
    int i;
    if (cfg->n_faults >= SCENARIO_MAX_FAULTS || scenario_parse_fault(&cfg->faults[cfg->n_faults], value) != 0)
        return OPTIONS_ERR_SAID;
    for (i = 1; i < 4 && strcmp(cfg->faults[cfg->n_faults].daemon, daemon_fault_name[i]); i++)
        ;
    if (i == 4) {
        fprintf(stderr, "%s: --fault: '%s' is not arm1|arm2|supervisor\n", prog, cfg->faults[cfg->n_faults].daemon);
        return OPTIONS_ERR_SAID;
    }
    cfg->faults[cfg->n_faults++].slot = i;
    return 0;
}

static const char *const controllers[] = { "event", "time", NULL };

static const option_entry carry_table[] = {
    { .name = "workpieces", .type = OPTION_INT, OPTION_AT(carry_options, cfg.workpieces), .min = 1, .max = 1000,
      .meta = "N", .help = "workpieces to carry", .def = "3" },
    { .name = "controller", .type = OPTION_CHOICE, OPTION_AT(carry_options, cfg.controller_time),
      .choices = controllers, .help = "time: the time-referenced baseline",
      .def = "event" },
    { .name = "block", .type = OPTION_CALL, .call = option_block, .repeatable = 1, .meta = "A:L:S:D[:t3]",
      .help = "push the stick into arm A (1-2), link L (1-6) at the first step after S s (>= 0) at which arm A "
              "moves (with :t3, during t3), for D s (0 < D <= 3600); run one after the other" },
    { .name = "random-blocks", .type = OPTION_INT, OPTION_AT(carry_options, n_random), .min = 0,
      .max = MAX_BLOCKS, .meta = "K", .help = "K seeded random blocks (links 2-5, 0.2-60 s, every third during t3)",
      .def = "0" },
    { .name = "seed", .type = OPTION_INT, OPTION_AT(carry_options, seed), .min = 0, .max = 2147483647.0,
      .meta = "S", .help = "seed of the sim and the random blocks", .def = "1" },
    { .name = "no-serial", .type = OPTION_FLAG, OPTION_AT(carry_options, no_serial),
      .help = "skip the serial reference run (serial_cycle_s = null)" },
    { .name = "serial-workpieces", .type = OPTION_INT, OPTION_AT(carry_options, serial_n), .min = 2, .max = 1000,
      .meta = "M", .help = "workpieces of the serial run", .def = "min(N, 3)" },
    { .name = "block-detect", .type = OPTION_CHOICE, OPTION_AT(carry_options, block_detect),
      .choices = options_on_off, .help = "off: the arms run eq. 6-7 alone (no blocked detector)", .def = "on" },
    { .name = "stall-s", .type = OPTION_DOUBLE, OPTION_AT(carry_options, stall_s), .min = 0.1, .max = 1e6,
      .meta = "S", .help = "the supervisor's stall limit (s); a stall stops the run", .def = "30" },
    { .name = "fault", .type = OPTION_CALL, OPTION_AT(carry_options, cfg), .call = option_fault, .repeatable = 1,
      .meta = "kill:D:T[:R]", .help = "kill daemon D (arm1, arm2, supervisor) at T s of simulated time, "
                                      "restart it at R s" },
    { .name = "drop-rate", .type = OPTION_STRING, OPTION_AT(carry_options, drop_arg), .meta = "P",
      .help = "every daemon drops received messages with probability P (0 <= P < 1)", .def = "0" },
    { .name = "lcm-url", .type = OPTION_STRING, OPTION_AT(carry_options, cfg.url), .min = 1, .max = 95,
      .meta = "URL", .help = "bus of the run", .def = "a private udpm port" },
    { .name = "out", .type = OPTION_STRING, OPTION_AT(carry_options, cfg.out), OPTION_SEEN(carry_options, out_given),
      .required = 1, .meta = "DIR", .help = "output directory" },
    { .name = "help", .type = OPTION_HELP, .help = "this text" },
    { .name = NULL }
};

static const option_program carry_program = {
    .name = "tandem-scenario carry",
    .usage = "usage: tandem-scenario carry [--workpieces N] [--controller event|time]\n"
             "         [--block ARM:LINK:START_S:DURATION_S[:t3]]... [--random-blocks K]\n"
             "         [--seed S] [--no-serial] [--serial-workpieces M]\n"
             "         [--block-detect on|off] [--stall-s S] [--fault kill:D:T[:R]]...\n"
             "         [--drop-rate P] [--lcm-url URL] --out DIR\n"
             "Two-arm carry in lockstep with the stick pushed into the arms (docs/method/carry.md §8).\n\n",
    .epilog = "Exit status: 0 when the run met every success criterion (all delivered,\n"
              "none dropped, no joint-limit violation, speeds within the motor limits,\n"
              "10 ms contact force <= 1000 N, resumed within 1 s of every removal, no\n"
              "stall, no invariant violation or deadlock, completed); 3 otherwise, with\n"
              "the failed criteria on the last line; 1 on errors, 2 on bad options.\n",
    .groups = { { carry_table, NULL } },   /* the base is run()'s carry_options */
    .n_groups = 1,
};

static int run(int argc, char **argv)
{
    run_cfg cfg;
    run_result res, ser;
    json_out j;
    int i, n_random, no_serial, serial_n, rc;
    long seed;
    double total_block_s = 0.0, max_force = 0.0, max_lurch = 0.0, fsum = 0.0, lat_max = NAN, lead_max = NAN;
    double resume_max = 0.0, settled_max = 0.0, stall_s;
    char stall_buf[32], failed[512];
    int n_failed, blocks_skipped = 0;
    long fn = 0;
    const char *drop_arg;
    static scenario_fault faults[SCENARIO_MAX_FAULTS];
    carry_options o;
    option_program prog = carry_program;
    memset(&o, 0, sizeof o);
    o.cfg.faults = faults;
    o.cfg.workpieces = 3;
    o.serial_n = -1;
    o.seed = 1;
    o.stall_s = 30.0;
    o.drop_arg = "0";
    n_blocks = 0;
    prog.groups[0].base = &o;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    cfg = o.cfg;
    cfg.block_detect = options_on_off[o.block_detect];
    n_random = o.n_random;
    no_serial = o.no_serial;
    serial_n = o.serial_n;
    seed = o.seed;
    stall_s = o.stall_s;
    drop_arg = o.drop_arg;
    if (n_random > 0 && n_blocks + n_random > MAX_BLOCKS) {
        fprintf(stderr, "tandem-scenario carry: too many blocks\n");
        return 2;
    }
    random_blocks(n_random, (uint64_t)seed);
    for (i = 0; i < n_blocks; i++) {
        blocks[i].in_s = blocks[i].out_s = blocks[i].contact_s = blocks[i].self_stop_s = blocks[i].partner_stop_s = -1.0;
        blocks[i].resume_s = -1.0;
        total_block_s += blocks[i].dur_s;
    }
    if (scenario_parse_drop(&cfg.drop, drop_arg, seed) != 0)
        return 2;
    if (scenario_mkdir(cfg.out) != 0)
        return 1;
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);
    cfg.seed = (uint64_t)seed;
    cfg.tag = "run";
    snprintf(stall_buf, sizeof stall_buf, "%g", stall_s);
    cfg.stall_s = stall_buf;
    cfg.max_sim_s = 60.0 * cfg.workpieces + 1.5 * total_block_s + 30.0 * n_blocks + 60.0;
    cur_block = 0;
    gap_after_s = 3.0;
    f_ts = scenario_fopen(cfg.out, "timeseries.csv");
    f_tr = scenario_fopen(cfg.out, "transitions.csv");
    f_q = scenario_fopen(cfg.out, "joints.csv");
    if (!f_ts || !f_tr || !f_q)
        return 1;
    fprintf(f_q, "t_s,q1_1,q1_2,q1_3,q1_4,q1_5,q1_6,q2_1,q2_2,q2_3,q2_4,q2_5,q2_6\n");
    fprintf(f_ts, "t_s,s1_m,sf1_m,tr1,s2_m,sf2_m,tr2,speed1_mps,speed2_mps,force1_N,force2_N,stick_arm,delivered,dropped,"
                  "force1_10ms_N,force2_10ms_N\n");
    fprintf(f_tr, "transition,start_s,end_s\n");
    fprintf(stderr, "tandem-scenario carry: %d workpieces, %s controller, %d blocks, seed %ld\n", cfg.workpieces,
            cfg.controller_time ? "time" : "event", n_blocks, seed);
    if (run_once(&cfg, &res) != 0 && !res.sim_s) {
        fprintf(stderr, "tandem-scenario carry: the run did not start\n");
        return 1;
    }
    fclose(f_ts);
    fclose(f_tr);
    fclose(f_q);
    f_ts = f_tr = f_q = NULL;
    memset(&ser, 0, sizeof ser);
    ser.mean_cycle_s = NAN;
    if (!no_serial && !interrupted) {
        run_cfg s = cfg;
        const int nb = n_blocks;
        s.serial = 1;
        s.tag = "serial";
        s.n_faults = 0;                 /* the reference runs without faults */
        s.workpieces = serial_n > 0 ? serial_n : (cfg.workpieces < 3 ? (cfg.workpieces < 2 ? 2 : cfg.workpieces) : 3);
        s.max_sim_s = 80.0 * s.workpieces + 60.0;
        n_blocks = 0;
        fprintf(stderr, "tandem-scenario carry: serial reference run, %d workpieces\n", s.workpieces);
        run_once(&s, &ser);
        n_blocks = nb;
    }
    for (i = 0; i < n_blocks; i++) {
        const block *b = &blocks[i];
        max_force = fmax(max_force, b->max_force_N);
        max_lurch = fmax(max_lurch, b->lurch_mps);
        fsum += b->force_sum_N;
        fn += b->force_n;
        if (b->in_s < 0.0)
            blocks_skipped++;
        if (b->out_s >= 0.0)   /* not resumed by the end: counted to the end */
            resume_max = fmax(resume_max, (b->resume_s >= 0.0 ? b->resume_s : res.sim_s) - b->out_s);
        if (b->force_late_n)
            settled_max = fmax(settled_max, b->force_late_sum_N / (double)b->force_late_n);
        if (b->during_t3 && b->partner_stop_s >= 0.0) {
            lat_max = isnan(lat_max) ? b->partner_stop_s - b->self_stop_s : fmax(lat_max, b->partner_stop_s - b->self_stop_s);
            lead_max = isnan(lead_max) ? b->lead_max_m : fmax(lead_max, b->lead_max_m);
        }
    }
    write_blocks_csv(cfg.out);
    if (json_open(&j, cfg.out, "summary.json") != 0)
        return 1;
    json_str(&j, "scenario", "carry");
    json_str(&j, "controller", cfg.controller_time ? "time" : "event");
    json_int(&j, "seed", seed);
    json_int(&j, "workpieces", cfg.workpieces);
    json_int(&j, "workpieces_detected", res.detected);
    json_int(&j, "workpieces_delivered", res.delivered);
    json_int(&j, "workpieces_dropped", res.dropped);
    json_int(&j, "blocks_requested", n_blocks);
    json_int(&j, "blockages", res.blockages);
    json_num(&j, "max_contact_force_N", max_force);
    json_num(&j, "mean_contact_force_blocked_N", fn ? fsum / (double)fn : 0.0);
    json_num(&j, "max_tool_speed_after_release_mps", max_lurch);
    for (i = 0; i < n_blocks; i++) {
        /* per block: arm, link, t3, mean contact force from 0.1 s after
         * contact and once settled (BLOCK_SETTLED_S), max */
        const block *b = &blocks[i];
        char k[64], v[64];
        snprintf(k, sizeof k, "block%d", i + 1);
        snprintf(v, sizeof v, "arm %d link %d%s", b->arm, b->link, b->during_t3 ? " t3" : "");
        json_str(&j, k, v);
        snprintf(k, sizeof k, "block%d_mean_force_N", i + 1);
        json_num(&j, k, b->force_n ? b->force_sum_N / (double)b->force_n : NAN);
        snprintf(k, sizeof k, "block%d_mean_force_settled_N", i + 1);
        json_num(&j, k, b->force_late_n ? b->force_late_sum_N / (double)b->force_late_n : NAN);
        snprintf(k, sizeof k, "block%d_max_force_N", i + 1);
        json_num(&j, k, b->max_force_N);
    }
    json_num(&j, "t3_partner_stop_latency_max_s", lat_max);
    json_num(&j, "t3_partner_lead_max_m", lead_max);
    json_int(&j, "invariant_violations", res.invariant_violations);
    json_int(&j, "deadlocks", res.deadlocks);
    json_int(&j, "replans", res.replans);
    json_num(&j, "mean_cycle_s", res.mean_cycle_s);
    json_num(&j, "serial_cycle_s", ser.mean_cycle_s);
    json_num(&j, "pipelining_ratio", res.mean_cycle_s / ser.mean_cycle_s);
    json_num(&j, "first_delivery_s", res.first_delivery_s);
    json_num(&j, "sim_time_s", res.sim_s);
    json_num(&j, "wall_time_s", res.wall_s + ser.wall_s);
    json_str(&j, "block_detect", cfg.block_detect);
    json_int(&j, "joint_limit_violations", res.joint_limit_violations);
    json_int(&j, "joint_stop_onsets", res.joint_stop_onsets);
    json_num(&j, "min_joint_range_margin_deg", res.min_range_margin_rad * 57.29577951308232);
    json_num(&j, "max_joint_speed_ratio", res.max_speed_ratio);
    json_int(&j, "stalls", res.stalls);
    json_int(&j, "faults", res.faults);
    json_num(&j, "resume_latency_max_s", resume_max);
    json_num(&j, "max_contact_force_10ms_N", res.max_force_10ms_N);
    json_num(&j, "max_contact_force_raw_N", res.max_force_N);
    json_num(&j, "settled_force_max_N", settled_max);
    json_int(&j, "blocks_skipped", blocks_skipped);
    json_num(&j, "drop_rate", cfg.drop.rate[0] ? atof(cfg.drop.rate) : 0.0);
    json_int(&j, "kills", res.kills);
    json_int(&j, "restarts", res.restarts);
    json_int(&j, "rows_reissued", res.rows_reissued);
    json_int(&j, "dones_recovered", res.dones_recovered);
    json_str(&j, "exit_reason", res.exit_reason);
    n_failed = carry_criteria(&cfg, &res, resume_max, failed, sizeof failed);
    json_str(&j, "failed_criteria", failed);
    json_close(&j);
    write_plots(cfg.out);
    printf("carry (%s): delivered %d/%d, dropped %d, blockages %d, max contact %.1f N, lurch %.3f m/s, "
           "invariant violations %ld, deadlocks %d, replans %d, mean cycle %.2f s, serial %.2f s\n",
           cfg.controller_time ? "time" : "event", res.delivered, cfg.workpieces, res.dropped, res.blockages,
           max_force, max_lurch, res.invariant_violations, res.deadlocks, res.replans, res.mean_cycle_s,
           ser.mean_cycle_s);
    if (n_failed) {
        printf("carry: FAILED %d criteria: %s\n", n_failed, failed);
        return 3;
    }
    printf("carry: all criteria met\n");
    return 0;
}

const scenario_def scenario_carry = {
    "carry", "two-arm carry with the stick (seed 000): event law vs time baseline", run
};

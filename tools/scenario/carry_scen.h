/* carry_scen: NOT A PUBLIC INTERFACE. What the files of `tandem-scenario
 * carry` (docs/method/carry.md §8) share with one another:
 *   scenario_carry.c  options, the driver (the run, the serial reference run)
 *   carry_bus.c       the run's state from the bus (handlers, arm health),
 *                     the stick's SIM_CONTROL, the scenario's lockstep answer
 *   carry_blocks.c    the stick: --block, random blocks, the block machine
 *   carry_run.c       one run: daemons, the lockstep loop, --fault, the
 *                     time series, the run's result
 *   carry_report.c    figures over the blocks, success criteria,
 *                     summary.json, blocks.csv, plots
 */
#ifndef TANDEM_CARRY_SCEN_H
#define TANDEM_CARRY_SCEN_H

#include <stdint.h>
#include <stdio.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "hang_watch.h"
#include "scenario.h"
#include "petri.h"
#include "tandem_arm_state_t.h"
#include "tandem_petri_marking_t.h"

#define MAX_BLOCKS 64
#define NT PETRI_MAX_TRANSITIONS /* transitions recorded (transitions.csv): any task's */
#define CARRY_DAEMONS 4          /* sim, arm 1, arm 2, supervisor */
/* success criteria (the figures a carry run must show) */
#define CRIT_FORCE_10MS_N 1000.0
#define CRIT_RESUME_S 1.0
/* A synchronised arm never goes back along its segment, but by the stick
 * or by a follower's overshoot when its reference stops (v0 / (e w) =
 * 2.5 mm from 0.2 m/s, docs/method/carry.md §4.2) and its 1 mm gap, with
 * margin; a partner driven back by a restarted arm went 0.11 m. */
#define CARRY_SYNC_BACKTRACK_MAX_M 0.005

/* Failures of a carry run's steps (0 = ok; each said on stderr but a
 * malformed --block, which the option parser reports). */
#define CARRY_SCEN_ERR_BLOCK (-1) /* --block not A:L:S:D[:t3] inside its ranges */
#define CARRY_SCEN_ERR_RUN (-2)   /* no LCM, a daemon did not start or exited early */
#define CARRY_SCEN_ERR_FAULT \
    (-3) /* --fault or a hung daemon: not restarted, or
                                      not back within 60 s */

typedef struct block {
    int arm, link, need_t3;
    double start_s, dur_s;
    /* measured */
    double in_s, out_s, contact_s, self_stop_s, partner_stop_s;
    double max_force_N, force_sum_N, force_late_sum_N;
    long force_n, force_late_n;
    double lead_max_m, lurch_mps;
    double out_pos_m[3], resume_s; /* tool at removal; resumed at (< 0: not yet) */
    double resume_from_s;          /* the resume latency counts from here: the removal,
                                      or the restart of an arm killed before it (--fault) */
    int row_running_at_out;        /* the arm had a row to finish when the stick came out */
    int stopped[2];                /* while the stick was in, it touched arm 1, arm 2 (> CONTACT_N)
                                      or that arm reported BLOCKED */
    int out_arm;                   /* the arm whose resume and lurch count (0-based) */
    int during_t3, done;
} block;

/* The blocks of a run, one after the other (one stick). */
typedef struct carry_blocks {
    block b[MAX_BLOCKS];
    int n;
    int cur;            /* index of the block armed or in, n when all done */
    double gap_after_s; /* start of the next block counted from the end of this one */
} carry_blocks;

typedef struct carry_cfg {
    int workpieces;
    int controller_time;
    int serial;
    double max_sim_s;
    const char *out;
    const char *tag;          /* "run" or "serial": log names */
    const char *url;          /* --lcm-url, or NULL: a private udpm port */
    const char *block_detect; /* tandem-arm --block-detect on|off */
    const char *stall_s;      /* tandem-supervisor --stall-s */
    const char *task;         /* --task DIR (tandem-supervisor --task), NULL: the shipped carry */
    int handover_stand;       /* the task sets workpieces down at the hand-over:
                                  tandem-sim --handover-stand */
    int magazine;             /* a row goes to arm 2's magazine: tandem-sim --magazine */
    double hang_s;            /* --hang-s: a daemon silent this long (wall) is hung; 0 off */
    uint64_t seed;
    scenario_drop drop;     /* --drop-rate, to every daemon */
    scenario_fault *faults; /* --fault (the main run only) */
    int n_faults;
    carry_blocks *blocks;          /* the stick's blocks (none in the serial run) */
    FILE *ts_csv, *tr_csv, *q_csv; /* timeseries, transitions, joints; NULL: not written */
} carry_cfg;

typedef struct carry_result {
    int detected, delivered, dropped, blockages, replans, deadlocks;
    long invariant_violations;
    double max_contact_N, max_lurch_mps, mean_blocked_force_N;
    double first_delivery_s, last_delivery_s, mean_cycle_s;
    double sim_s, wall_s;
    int ok;
    /* health of the run */
    long joint_limit_violations, joint_stop_onsets;
    double max_speed_ratio, max_force_N, max_force_10ms_N, min_range_margin_rad;
    double max_sync_backtrack_m;
    int stalls, faults;
    int kills, restarts, rows_reissued, dones_recovered;
    int stick_resends; /* stick commands sent again (lost on the way) */
    int hung_restarts; /* daemons found hung, killed and restarted */
    int leave_resends; /* a killed daemon's leave sent again (lost on the way) */
    const char *exit_reason;
} carry_result;

/* What one run knows from the bus, step by step. */
typedef struct carry_state {
    lcm_t *lcm;
    auth_bus *bus;   /* the process's bus (run_key_bus) */
    int64_t pending; /* step to answer, -1 none */
    int64_t handled; /* last step recorded, -1 none */
    double t_s;
    double progress_t_s, progress_wall_s; /* the last gain of simulated time, and its wall time */
    tandem_arm_state_t arm[2];
    int have_arm[2];
    double speed[2];
    double s[2], s_f[2];
    int tr[2]; /* transition of the last progress */
    int64_t s_step[2];
    /* synchronised segments: the furthest fraction of the way each arm has
     * reported in its segment (action, segment), and the most any arm
     * went back from it (m): a partner driven back by a restarted arm */
    int32_t sync_action[2];
    int sync_seg[2];
    double sync_frac_max[2];
    double max_sync_backtrack_m;
    double s_hist[2][16]; /* s at the last 16 steps, ring */
    tandem_petri_marking_t mk;
    int8_t mk_marking[PETRI_MAX_PLACES], mk_running[PETRI_MAX_TRANSITIONS];
    int have_mk;
    int delivered, dropped, spawned;
    /* the stick as the simulator last said (SIM_STATUS) and as wanted: a
     * command is sent again until the simulator's state shows it */
    int64_t status_step; /* step of the last SIM_STATUS, -1 none */
    int status_stick;    /* its stick_inserted */
    int stick_want;      /* -1 nothing asked, 0 out, 1 in */
    int stick_arm, stick_link;
    int64_t stick_sent_step;
    int arm_down[2]; /* arm k's daemon killed (--fault, hung) and not restarted yet */
    int stick_resends, stick_tries; /* in the run; for the command in hand */
    int64_t ack_seq;
    int running_prev[NT];
    double run_start[NT];
    /* per arm: the last event other than PROGRESS, and when UNBLOCKED / DONE came */
    int last_event[2];
    int64_t unblocked_step[2], done_step[2];
    /* health of the run from the measured states */
    unsigned range_bits[2]; /* joints past their range at the last state */
    unsigned stop_bits[2];  /* joints at (or past) a range end at the last state */
    long limit_violations, stop_onsets;
    double max_speed_ratio, max_force_N, max_force_10ms_N;
    double min_range_margin_rad; /* least distance of a joint from a range end */
    /* --hang-s: the daemons' signs of life (their answers, the clock) go here */
    hang_watch *hw;
    /* --fault: the last step each daemon answered (SIM_ACK) */
    int64_t ack_step[CARRY_DAEMONS];
    double hold_since_s; /* wall time a restart began holding the step */
    /* deliveries, and when the run ends (< 0: not yet) */
    double t_deliv_first, t_deliv_last, end_at;
    int last_delivered;
} carry_state;

/* The daemons of a run: proc slot k, --fault name, lockstep name. */
extern const char *const carry_daemon_fault_name[CARRY_DAEMONS];
extern const char *const carry_daemon_lock_name[CARRY_DAEMONS];

/* carry_bus.c */
/* Subscribes every handler of the run's state r on r->lcm. */
void carry_subscribe(carry_state *r);
void carry_send_control(carry_state *r, int cmd, int arm, int link);
/* The stick in (INSERT_STICK, arm, link) or out (REMOVE_STICK): sent now
 * and again (carry_stick_confirm) until SIM_STATUS shows it. */
void carry_stick_command(carry_state *r, int cmd, int arm, int link);
/* At every step: a stick command whose effect a SIM_STATUS later than it
 * does not show was lost: sent again. */
void carry_stick_confirm(carry_state *r);
void carry_ack(carry_state *r, int64_t step, int leaving);
/* The synchronised t3 is running (the supervisor's last marking). */
int carry_t3_running(const carry_state *r);

/* carry_blocks.c */
/* --block A:L:S:D[:t3]; 0 ok, CARRY_SCEN_ERR_BLOCK. */
int carry_block_parse(const char *s, block *b);
/* Appends k seeded random blocks (as many as fit). */
void carry_random_blocks(carry_blocks *bl, int k, uint64_t seed);
/* The stick of the block in progress is in. */
int carry_stick_in(const carry_blocks *bl);
/* The block machine at the step about to be answered. */
void carry_block_step(carry_state *r, carry_blocks *bl);

/* carry_run.c */
/* SIGINT and SIGTERM end the run (exit_reason "interrupted"). */
void carry_catch_signals(void);
int carry_interrupted(void);
/* One run with c's daemons; res always filled in. 0 ok, CARRY_SCEN_ERR_RUN
 * (the run failed to start, a daemon exited, or a --fault restart failed). */
int carry_run_once(const carry_cfg *c, carry_result *res);

/* carry_report.c */
/* Figures over all blocks of a run (carry_block_figures). */
typedef struct carry_block_figures {
    double max_force_N, max_lurch_mps, mean_force_N;
    double latency_max_s, lead_max_m; /* t3 blocks; NAN: none */
    double resume_max_s, settled_max_N;
    int skipped;
} carry_block_figures;
void carry_block_figures_of(carry_block_figures *f, const carry_blocks *bl, double sim_s);
/* Appends the failed success criteria to buf (space separated); returns
 * how many failed. */
int carry_criteria(const carry_cfg *c, const carry_result *r, double resume_max_s, char *buf,
                   size_t cap);
/* summary.json of the run and its serial reference; 0 ok, SCENARIO_ERR_IO. */
int carry_write_summary(const carry_cfg *c, long seed, const carry_result *res,
                        const carry_result *ser, const carry_block_figures *f, const char *failed);
void carry_write_blocks_csv(const char *dir, const carry_blocks *bl);
void carry_write_plots(const char *dir, const carry_blocks *bl);

#endif

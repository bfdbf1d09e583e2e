/* supervisor_daemon: the state of tandem-supervisor, one struct created in
 * main and handed to the cycle and to every handler (see
 * tandem_supervisor.c), and the calls between its files:
 * tandem_supervisor.c (start-up check, vision tokens, the cycle),
 * supervisor_rows.c (rows out, arm events in, recovery of lost rows),
 * supervisor_watch.c (marking out, stall and silence watchdogs),
 * supervisor_journal.c (--journal).
 */
#ifndef TANDEM_SUPERVISOR_DAEMON_H
#define TANDEM_SUPERVISOR_DAEMON_H

#include <stdint.h>
#include "daemon.h"
#include "journal.h"
#include "carry_net.h"
#include "netc.h"
#include "petri.h"
#include "taskdef.h"
#include "stallwatch.h"
#include "tandem_action_event_t.h"
#include "tandem_workpiece_detections_t.h"

#define EVENT_QUEUE 64

enum { ARM_SLOT_NONE = 0, ARM_SLOT_WAITING, ARM_SLOT_SENT, ARM_SLOT_DONE };

typedef struct sup_slot {
    int state[2]; /* ARM_SLOT_* per arm */
    int32_t action_id[2];
    int64_t sent_step[2];
} sup_slot;

/* What an arm last said about itself (its events and idle STATUS). */
typedef struct arm_view {
    int heard;
    int64_t step, rx_ns;
    /* liveness from PROGRESS too (a running arm sends no STATUS; its
     * PROGRESS is not queued as an event): the newest step and wall time */
    int64_t alive_step, alive_rx_ns;
    int running;
    int32_t action_id, last_done, holding;
} arm_view;

typedef struct supervisor_daemon {
    daemon d; /* the shell: bus, loop, counters, health */
    /* the task: the shipped carry_net and carry_table, or the net and rows
     * --task loaded into task's fixed tables; known by its roles (the
     * source, its place, the pick), not by the carry's indices */
    const char *task_dir; /* --task DIR, NULL: the shipped carry */
    netc_task *task;      /* --task's tables (static storage in main) */
    const petri_net *pn;
    const carry_row *rows; /* row t for transition t */
    taskdef_roles roles;
    taskdef_health health; /* the arms' health places, if the task has them */
    int token_bound;       /* the start-up check's bound per place */
    uint64_t task_digest;  /* taskdef_digest of pn and rows: journalled */
    petri net;
    sup_slot slot[PETRI_MAX_TRANSITIONS];
    int controller; /* action_row_t CONTROLLER_* */
    int serial;
    int use_tdsd; /* --tdsd: rows ask for TDSD Cartesian moves */
    /* workpiece of the current cycle (p1 .. t2) and the one being carried */
    int32_t wp_id;
    double wp_pos_m[3], wp_yaw_rad;
    int32_t last_taken_id;
    double pick_pos_m[3], pick_yaw_rad; /* latched when t1 takes p1 */
    int32_t pick_id;
    int have_detection;
    int p1_bound; /* the p1 token has a detected pose */
    tandem_workpiece_t det;
    /* events queued by the LCM callback, handled in the cycle */
    tandem_action_event_t evq[EVENT_QUEUE];
    int n_ev;
    int32_t next_action_id;
    int64_t row_seq, marking_seq;
    int64_t cycles;
    int changed;
    int32_t deadlocks, replans, detections, blockages;
    int was_dead;
    int last_fired;
    /* watchdogs */
    stallwatch stall;
    double stall_s;            /* --stall-s */
    double stall_obstructed_s; /* --stall-obstructed-s */
    int completed;             /* a transition completed this cycle */
    int stick_in;              /* SIM_STATUS: an obstruction is in the cell */
    int arms_faulted;          /* bit a: arm a+1 in FAULT */
    int32_t faults;
    /* recovery */
    arm_view arm[2];
    int64_t sim_rx_ns;
    int arms_silent, sim_silent;
    int32_t rows_reissued, dones_recovered;
    int resumed, journal_checked;
    const char *journal_path;
    int journal_reset; /* --journal-reset: start fresh, emptying the journal */
    journal jr;
    long journal_seq_resumed; /* seq of the record resumed from, 0 none */
    int journal_rc;           /* last append: JOURNAL_OK, or the failure the cell holds for */
    int journal_errno;        /* errno of the first failure of a run of failures */
    long journal_failures;    /* failed appends since the last good one */
    int dirty;                /* the discrete state changed: journal it */
    double journal_values[JOURNAL_MAX_VALUES]; /* a snapshot, written or read */
    petri_explore_ws explore_ws;               /* start-up check of the net */
} supervisor_daemon;

/* Start-up and internal failures of the supervisor's files (0 = ok;
 * supervisor_strerror names them). */
#define SUPERVISOR_ERR_NET \
    (-1)                             /* the carry net is unsound or its tables invalid
                                         (the offending marking printed) */
#define SUPERVISOR_ERR_POSE (-2)     /* a row names a pose the cell does not have */
#define SUPERVISOR_ERR_SNAPSHOT (-3) /* a journal snapshot this net cannot take */
#define SUPERVISOR_ERR_JOURNAL (-4)  /* the journal is refused or does not open (said) */
#define SUPERVISOR_ERR_TASK (-5)     /* --task refused: a file, the net or its rows (said) */
#define SUPERVISOR_ERR_OTHER_TASK \
    (-6) /* the journal was written for another task
                                          (taskdef_digest); --journal-reset */
/* their texts are their names (what the supervisor prints; status.h) */
#define SUPERVISOR_CODES(X)                               \
    X(0, "ok")                                            \
    X(SUPERVISOR_ERR_NET, "SUPERVISOR_ERR_NET")           \
    X(SUPERVISOR_ERR_POSE, "SUPERVISOR_ERR_POSE")         \
    X(SUPERVISOR_ERR_SNAPSHOT, "SUPERVISOR_ERR_SNAPSHOT") \
    X(SUPERVISOR_ERR_JOURNAL, "SUPERVISOR_ERR_JOURNAL")   \
    X(SUPERVISOR_ERR_TASK, "SUPERVISOR_ERR_TASK")         \
    X(SUPERVISOR_ERR_OTHER_TASK, "SUPERVISOR_ERR_OTHER_TASK")
const char *supervisor_strerror(int rc);

/* The row of transition t (t a transition of the task). */
const carry_row *sup_row(const supervisor_daemon *sv, int t);
/* 1 if t is an arm's fault or recovery (taskdef_health): fired by the
 * supervisor from the arms' health only, never started as a row. */
int sup_health_transition(const supervisor_daemon *sv, int t);

/* supervisor_rows.c */
void sup_start_transition(supervisor_daemon *sv, int t);
/* The stand poses' table (supervisor_rows.c): 0, or SUPERVISOR_ERR_POSE
 * (a pose of no arm, a place out of range, a negative lift, a pose twice). */
int sup_stand_poses_validate(void);
/* The queued arm events, in arrival order (lockstep: those sent before
 * the step this cycle answers). */
void sup_handle_events(supervisor_daemon *sv);
void sup_on_event(const lcm_recv_buf_t *rb, const char *ch, void *u);
void sup_recover_rows(supervisor_daemon *sv);
int sup_grasp_blocked(const supervisor_daemon *sv, int t);

/* supervisor_watch.c */
void sup_publish_marking(supervisor_daemon *sv);
void sup_on_sim_status(const lcm_recv_buf_t *rb, const char *ch, void *u);
void sup_watch_stall(supervisor_daemon *sv);
void sup_watch_silence(supervisor_daemon *sv);

/* supervisor_journal.c */
/* After daemon_start (the bus key is loaded): --journal-reset, or the last
 * record checked and taken back, and the journal opened for appending.
 * 0, or SUPERVISOR_ERR_JOURNAL after naming the file, record and why. */
int sup_journal_start(supervisor_daemon *sv);
/* The state appended when it changed; a failed write holds the cell. */
void sup_journal_cycle(supervisor_daemon *sv);
/* 1 while the journal cannot be written: no new rows go out. */
int sup_holding(const supervisor_daemon *sv);

#endif

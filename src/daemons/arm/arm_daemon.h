/* arm_daemon: the state of tandem-arm, one struct created in main and
 * handed to the cycle and to every handler (see tandem_arm.c), and the
 * calls between its files: tandem_arm.c (inputs, cycle dispatch, commands
 * and events out), arm_row.c (the running row and the hold point: the one
 * writer of both), arm_joint.c (joint-space segments and references),
 * arm_carry.c (event-referenced Cartesian segments), arm_tdsd.c (TDSD
 * Cartesian segments), arm_hold.c (protective stops).
 */
#ifndef TANDEM_ARM_DAEMON_H
#define TANDEM_ARM_DAEMON_H

#include <stdint.h>
#include "daemon.h"
#include "arm_kin.h"
#include "cartseg.h"
#include "jointctl.h"
#include "jtraj.h"
#include "tdsd_seg.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_joint_ref_t.h"
#include "tandem_arm_state_t.h"

#define ROW_MAX_SEGMENTS 8

/* External joint references (ARMk_JOINT_REF, e.g. a TDSD resolver in
 * tandem-scenario): tracked while fresh and no action row runs. */
typedef struct arm_joint_ref {
    tandem_arm_joint_ref_t ref;
    int have;
    int64_t rx_ns;
    char ch[20];
} arm_joint_ref;

/* A valid row waiting for the cycle that takes it (row_take). */
typedef struct arm_row_inbox {
    tandem_action_row_t row;
    tandem_action_segment_t seg[ROW_MAX_SEGMENTS];
    int have;
} arm_row_inbox;

/* The event-referenced Cartesian segment (arm_carry.c). */
typedef struct arm_carry {
    cartseg seg;
    arm_tool tool;
    double T_world_base[16];
    erlaw_gains g;
    int controller; /* action_row_t CONTROLLER_* */
    int32_t sync_group;
    int64_t start_step;
    int64_t cycles;
    double s_m, s_f_m, k; /* last measured progress, length, k_i */
    int partner_valid;
    int32_t partner_transition, partner_group;
    int64_t partner_step;
    double partner_s_m, partner_s_f_m;
    /* the partner's last PROGRESS messages by step: lockstep uses the
     * newest sent before the step it answers, whatever the arrival order */
    tandem_action_event_t partner_ring[4];
    int fallback;                     /* the segment runs as a joint-space move */
    tandem_action_segment_t cart_seg; /* ... in place of this Cartesian one */
} arm_carry;

/* The TDSD Cartesian segment (arm_tdsd.c). */
typedef struct arm_tdsd {
    int use; /* this row resolves Cartesian moves by TDSD */
    tdsd_seg_params par;
    tdsd_seg seg;
    int32_t action_id;
    int seg_index; /* cur_seg the TDSD segment belongs to, -1 */
} arm_tdsd;

/* Protective stop (arm_hold.c, docs/method/carry.md §7.4): after any hold
 * the arm is brought to rest where it stands and the motion is planned
 * again from there. */
typedef struct arm_hold {
    int active;            /* stopping or stopped; no motion runs */
    int pinned;            /* the stop planned from the measured state */
    jtraj_stop stop;       /* the controlled stop (jtraj.h) */
    double stop_t_s;       /* time into it */
    double rest_s;         /* time at rest since then */
    int64_t last_cmd_step; /* state step of the last command sent, -1 */
    int64_t stops;         /* protective stops so far */
    int states_in_cycle;   /* states of new steps since the last cycle */
    char why[40];
} arm_hold;

typedef struct arm_daemon {
    daemon d; /* the shell: bus, loop, counters, health */
    int arm;  /* 1 or 2 */
    const arm_model *model;
    jointctl_gains gains;
    double stale_s;
    double speed_frac;
    /* latest valid state */
    tandem_arm_state_t st;
    int have_state;
    int64_t state_rx_ns; /* wall time it arrived (real-time staleness) */
    /* ARMk_STATE steps (guard.h): a state may be 1 s ahead of the last one;
     * after 1 s without a state the simulator is taken to have restarted. */
    step_gate state_gate;
    /* what the arm is doing: written by arm_row.c alone */
    double hold_q[ARM_NJ];
    int holding_set;
    tandem_action_segment_t seg[ROW_MAX_SEGMENTS];
    int n_seg, cur_seg;
    int32_t action_id, transition;
    int32_t last_done_id; /* the last row finished (0: none yet) */
    int running;
    jtraj traj;
    double seg_t0_s;
    int64_t status_cycles; /* idle cycles, for the 10 Hz STATUS */
    int block_detect;      /* 0: eq. 6-7 alone, no blocked detector */
    int fault;             /* in a joint fault (braking) */
    double fault_clear_s;  /* healthy time since the fault's last sign */
    int64_t cmd_seq, ev_seq;
    tandem_arm_command_t last_cmd; /* the last command sent (lockstep: sent again
                                         when the simulator announces its step again) */
    int have_last_cmd;
    char state_ch[16], cmd_ch[16], action_ch[16];
    arm_row_inbox row_in;
    arm_joint_ref jref;
    arm_carry cart;
    arm_tdsd tdsd;
    arm_hold hold;
} arm_daemon;

/* tandem_arm.c: events and commands out */
void arm_event_fill(arm_daemon *ad, tandem_action_event_t *e, int ev, const char *detail);
void arm_publish_event(arm_daemon *ad, int ev, const char *detail);
void arm_send_command(arm_daemon *ad, int mode, const double tau[ARM_NJ]);

/* arm_row.c: the running row and the hold point, their one writer */
/* A checked row starts: its segments, none current yet, running. */
void arm_row_begin(arm_daemon *ad, const tandem_action_row_t *r);
/* The current segment of the running row, NULL if none. */
const tandem_action_segment_t *arm_row_segment(const arm_daemon *ad);
/* Next segment of the running row (DONE after the last one). */
void arm_start_segment(arm_daemon *ad);
/* The row given up (a segment that cannot be planned): held where the arm
 * stands, no segment current, not running. The caller says why (REJECTED). */
void arm_row_abandon(arm_daemon *ad);
/* The current segment run as g instead (a Cartesian one finished in joint
 * space, and back: arm_carry.c). */
void arm_row_replace_segment(arm_daemon *ad, const tandem_action_segment_t *g);
/* Where the arm is held between motions. */
void arm_row_hold_at(arm_daemon *ad, const double q_rad[ARM_NJ]);
/* A joint move from q_from to q_goal, timed from now. */
void arm_row_plan_joint(arm_daemon *ad, const double q_from[ARM_NJ], const double q_goal[ARM_NJ]);
/* The gripper request of this cycle's command: open or close while a
 * gripper segment runs and the state does not show the fingers so yet
 * (a level, not an edge: a lost command that carried the only OPEN left
 * both arms holding the bar, fighting through t5 and t6), else KEEP. */
int arm_row_gripper_request(const arm_daemon *ad);

/* arm_joint.c: joint-space segments and external joint references */
void arm_on_joint_ref(const lcm_recv_buf_t *rb, const char *ch, void *u);
/* A joint move planned again from the measured pose (after a safe hold). */
void arm_joint_resume(arm_daemon *ad);
/* Computes and sends this cycle's command in joint space. */
void arm_joint_cycle(arm_daemon *ad);

/* arm_carry.c: event-referenced Cartesian segments */
void arm_cart_row_accept(arm_daemon *ad, const tandem_action_row_t *r);
void arm_cart_on_event(const lcm_recv_buf_t *rb, const char *ch, void *u);
void arm_cart_partner_at(arm_daemon *ad, int64_t k);
void arm_cart_start(arm_daemon *ad, const tandem_action_segment_t *g);
int arm_cart_cycle(arm_daemon *ad);
int arm_cart_fallback_cycle(arm_daemon *ad, int done);
const arm_payload *arm_cart_payload(const arm_daemon *ad, arm_payload *p);

void arm_cart_resume(arm_daemon *ad);

/* arm_hold.c: protective stops */
void arm_hold_init(arm_daemon *ad);
/* A state of a new step arrived (counted for the backlog test). */
void arm_hold_note_state(arm_daemon *ad);
/* A command was sent at the state's step (for the gap test). */
void arm_hold_note_command(arm_daemon *ad);
/* A hold begins (why: a short phrase for the log); idempotent while one runs. */
void arm_hold_begin(arm_daemon *ad, const char *why);
/* A fresh state after a gap in this arm's commands (a frozen or late
 * process) begins a hold; so does a backlog of states taken in one
 * cycle, and then the arm must stay on its brakes this cycle (returns 1).
 * Call once per cycle before the controllers. */
int arm_hold_check_gap(arm_daemon *ad);
/* Runs the cycle while a hold is in effect; 1 if it sent the command. */
int arm_hold_cycle(arm_daemon *ad);

/* arm_tdsd.c: TDSD Cartesian segments */
void arm_tdsd_row_accept(arm_daemon *ad, const tandem_action_row_t *r);
int arm_tdsd_cycle(arm_daemon *ad);
/* After a protective stop: the segment started again from the measured pose. */
void arm_tdsd_resume(arm_daemon *ad);

#endif

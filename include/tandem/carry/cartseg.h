/* cartseg: one straight Cartesian segment of an action row, executed by an
 * arm controller (docs/method/carry.md §2-2.3, 2.6): the erlaw segment law (event-
 * referenced, synchronised via an external s* reference, or the
 * time-referenced baseline) in the world frame, the orientation held at
 * the segment's target, cartctl for the joint torques, the done predicate,
 * the blocked detector, and the in-range joint-space goal of a segment
 * the arm cannot finish as a Cartesian move.
 *
 * World <-> arm: T_world_base is the arm's mounting frame in the world
 * (arm_fk's base frame), tool is the tool offset. Pure core: no I/O.
 */
#ifndef TANDEM_CARTSEG_H
#define TANDEM_CARTSEG_H

#include "cartctl.h"
#include "erlaw.h"

#define CARTSEG_ERR_ARG \
    (-1) /* NULL, non-finite input or bad reference
                                    mode, or a failure below (kinematics,
                                    erlaw, cartctl)                        */
#define CARTSEG_ERR_NO_GOAL \
    (-2) /* cartseg_joint_goal: no IK solution keeps
                                    the margin (the pose unreachable or the
                                    arm's configuration unknown)           */

#define CARTSEG_DONE_TOL_M 0.004        /* s within 4 mm of s_f ...            */
#define CARTSEG_DONE_SPEED_MPS 0.008    /* ... and the tool slower than 8 mm/s */
#define CARTSEG_BLOCK_EPS_M 0.001       /* s must gain 1 mm ...                */
#define CARTSEG_BLOCK_TIME_S 0.30       /* ... within 300 ms, else blocked     */
#define CARTSEG_BLOCK_NEAR_GOAL_M 0.010 /* no block detection in the last 1 cm */
#define CARTSEG_BLOCK_DEV_M 0.010       /* or pushed 1 cm off the line: blocked */
/* A blocked arm is released when s gains 5 mm: held by the servos at the
 * pose where the block was met, the bias alone can move the tool along
 * the path by about k0 / k_p (2 mm with the carry rows) against a pinned
 * proximal link; 1 mm would flip it back to the full law. */
#define CARTSEG_UNBLOCK_EPS_M 0.005
/* While blocked the hold point follows the tool along the path only while
 * the tool moves along it (> 1 mm/s, sideways speed at most half of that). */
#define CARTSEG_HOLD_V_MPS 0.001
#define CARTSEG_HOLD_SIDE_FRAC 0.5
/* ... or while it keeps within this distance of it across the path. */
#define CARTSEG_HOLD_SLIP_M 0.004
/* ... or once it has rested this long at least half the bias's reach
 * (k0 / k_p) ahead of it along the path (nothing resists the bias along
 * the path, whatever holds the tool sideways: a released arm whose static
 * sideways error outgrew the allowance otherwise stayed held for good) --
 * again only if the tool went on mostly along the path since the last
 * such step (a pinned proximal link turns the tool sideways instead). */
#define CARTSEG_HOLD_REST_S 0.25
#define CARTSEG_HOLD_REST_MPS 0.001
/* Contact sensing (cartseg_set_contact): a contact force of at least
 * CARTSEG_CONTACT_N on the arm is an obstacle. A stall (or a push off the
 * line) is a block only if the arm touched something within the stall
 * window; without contact it is not an obstacle but a path the arm cannot
 * follow from where it is (a joint held at its range barrier, or a law too
 * weak for the model error at the start of a segment): cartseg_out.stuck,
 * and the caller re-plans (cartseg_joint_goal). A blocked arm with no
 * contact for CARTSEG_FREE_S is released at once (the obstacle is gone),
 * besides the release on progress. */
#define CARTSEG_CONTACT_N 0.05
#define CARTSEG_FREE_S 0.05
/* Joint-space goals keep every joint this far inside its range. */
#define CARTSEG_GOAL_MARGIN_RAD 0.0262 /* 1.5 deg */
/* Filter of the free servo's cross-track error (its static part, model
 * error / k_p, is kept up while blocked). */
#define CARTSEG_STATIC_ERR_TAU_S 0.5
#define CARTSEG_STATIC_ERR_DELAY_S 0.25

typedef struct cartseg {
    erlaw_line line;
    erlaw_block blk;
    cartctl_gains cg;
    erlaw_ref ref;
    double T_world_base[16];
    double R_d_base[9];    /* orientation held, base frame */
    double R_hold_base[9]; /* orientation held while blocked   */
    double p1_world[3];
    double dev_ref_m;                              /* least line deviation since the last block */
    double hold_off_m[3];                          /* static cross-track error, 0.25-0.5 s old  */
    double err_filt_m[3], err_snap_m[3], t_snap_s; /* its filter      */
    double t_rest_s;      /* blocked: time at rest ahead of the hold point */
    double rest_pos_m[3]; /* tool where the hold last moved after a rest */
    int rest_steps;       /* such moves in this block */
    int blocked;
    int block_detect;      /* 1 (cartseg_start's default): detector on; 0: eq. 6-7 alone */
    double contact_N;      /* measured contact force on the arm, < 0: no sensor */
    double t_no_contact_s; /* time since the arm last touched something */
} cartseg;

typedef struct cartseg_out {
    double tau_Nm[ARM_NJ];
    double x_world[3]; /* tool point */
    double u_world[3]; /* commanded tool acceleration (eq. 6) */
    double v_world[3]; /* tool velocity */
    double s_m, s_f_m, s_ref_m;
    double deviation_m; /* distance of the tool from the line */
    double bias;
    int done;
    int blocked;
    int block_changed; /* blocked flipped this cycle */
    int saturated;
    int stuck;              /* stalled with nothing touching the arm (event law,
                                  contact sensed): re-plan, see CARTSEG_CONTACT_N */
    unsigned range_limited; /* joints held at their range barrier (cartctl) */
} cartseg_out;

/* Tool point and velocity in the world. 0 / CARTSEG_ERR_ARG. */
int cartseg_tool_world(const arm_model *m, const arm_tool *tool, const double T_world_base[16],
                       const double q[ARM_NJ], const double qd[ARM_NJ], double x[3], double v[3]);
/* The same from the cycle's kinematics (cartctl_state_at), computed once
 * and handed on to cartseg_step_at. 0 / CARTSEG_ERR_ARG. */
int cartseg_tool_world_at(const cartctl_state *st, const double T_world_base[16], double x[3],
                          double v[3]);

/* Segment from the current tool point to p1_world with the tool
 * orientation R1_world held. ref: ERLAW_REF_MEASURED (event law; also used
 * with an external s* by passing s_ext to cartseg_step) or ERLAW_REF_TIME.
 * 0 / CARTSEG_ERR_ARG (bad input). */
int cartseg_start(cartseg *c, const arm_model *m, const arm_tool *tool,
                  const double T_world_base[16], const double q[ARM_NJ], const double p1_world[3],
                  const double R1_world[9], const erlaw_gains *g, erlaw_ref ref);

/* Protective-stop resume at the measured tool point x_world: the law
 * takes the motion up from there as from a start (erlaw_channel_resume);
 * a released block does the same by itself. 0 / CARTSEG_ERR_ARG. */
int cartseg_resume(cartseg *c, const double x_world[3]);

/* A segment taken up part way (a restarted arm of a synchronised pair,
 * docs/method/carry.md §7.4): the line is stretched back from the goal
 * through the start point so that the start lies done_frac of the way
 * along it (0 < done_frac <= CARTSEG_TAKE_UP_MAX), the progress the pair
 * had made, and the law resumes there. Call right after cartseg_start.
 * A start point on the goal (nothing left to stretch) is refused.
 * 0 / CARTSEG_ERR_ARG. */
#define CARTSEG_TAKE_UP_MAX 0.999
#define CARTSEG_TAKE_UP_MIN_M 1e-6
int cartseg_take_up(cartseg *c, double done_frac);

/* The arm's measured contact force this cycle (N, e.g. the largest 10 ms
 * average over its links); NAN or < 0: no contact sensor (the blocked
 * detector then goes by progress alone). cartseg_start sets "none". */
void cartseg_set_contact(cartseg *c, double force_N);

/* Joint-space goal of the segment start -> (p1_world, R1_world) for the
 * arm at q. The goal solution the Cartesian move would end at is the IK
 * solution nearest q (max |dq|, angles taken 2 pi-nearest to q). Returns
 * 0 when that solution keeps every joint at least CARTSEG_GOAL_MARGIN_RAD
 * inside its range (q_goal = it: the Cartesian move may run); 1 when it
 * does not (q_goal = the nearest solution, preferring the arm's shoulder
 * and elbow configuration, that keeps the margin: reach the goal by a
 * joint-space move); CARTSEG_ERR_NO_GOAL when no solution keeps the margin or on bad
 * input (q_goal = q). */
int cartseg_joint_goal(const arm_model *m, const arm_tool *tool, const double T_world_base[16],
                       const double q[ARM_NJ], const double p1_world[3], const double R1_world[9],
                       double q_goal[ARM_NJ]);

/* One cycle. s_ext_m >= 0 selects the external (synchronised) reference
 * k_i s*; pass a negative value otherwise. 0 / CARTSEG_ERR_ARG (tau then 0). */
int cartseg_step(cartseg *c, const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                 const double q[ARM_NJ], const double qd[ARM_NJ], double s_ext_m, double dt_s,
                 cartseg_out *out);
/* The same cycle with the kinematics st = cartctl_state_at(m, tool, q, qd)
 * already evaluated (the caller's one pass of the cycle; the tool is in
 * st). */
int cartseg_step_at(cartseg *c, const arm_model *m, const arm_payload *payload,
                    const cartctl_state *st, const double q[ARM_NJ], const double qd[ARM_NJ],
                    double s_ext_m, double dt_s, cartseg_out *out);

#endif

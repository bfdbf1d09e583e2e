/* tdsd_seg: one straight Cartesian segment of an action row resolved by
 * TDSD (docs/method/tdsd.md: action_row_t.use_tdsd) instead of the
 * event-referenced law, for an arm whose inner loop is the joint
 * computed-torque servo (jointctl).
 *
 * Each cycle tdsd_seg_step resolves the tool path at the joint *reference*
 * q_ref (closed loop on the kinematic model: position = priority 1,
 * orientation = priority 2, q4..q6 mid-range criterion = priority 3),
 * advances the path parameter s by lambda dt along the segment's jerk-
 * limited profile (sprofile, path length domain) and integrates the joint
 * rates into (q_ref, dq_ref, ddq_ref) for the servo. Because q_ref is a
 * consistent kinematic trajectory whose rates never exceed
 * speed_frac * qd_max, the reference passes singular poses on the path
 * (slowing down when the position task alone needs more speed) and the
 * servo only has to track it.
 *
 * Path: p(s) = p0 + (s / L) (p1 - p0), R(s) = Rot(k, (s / L) theta) R0 with
 * R1 R0^T = Rot(k, theta); L = max(|p1 - p0|, rot_len_m theta), so a pure
 * re-orientation also has a profile. Frames: the segment is given in the
 * world, kept in the arm's base frame (T_world_base).
 *
 * tdsd_servo_vlimit is the velocity-limited form of the jointctl law used
 * with it (see below). Pure core: no I/O, no allocation.
 */
#ifndef TANDEM_TDSD_SEG_H
#define TANDEM_TDSD_SEG_H

#include "arm_model.h"
#include "jointctl.h"
#include "sprofile.h"
#include "tdsd.h"

#define TDSD_SEG_ERR_ARG \
    (-1) /* NULL, non-finite input, invalid parameters
                                  or gains, a joint speed limit <= 0, or FK /
                                  the speed profile refused the segment     */

#define TDSD_SEG_DONE_POS_M 0.0005     /* reference on the target within 0.5 mm */
#define TDSD_SEG_DONE_ORI_RAD 0.008727 /* ... and 0.5 deg */
#define TDSD_SEG_DONE_Q_RAD 0.005      /* arm within 5 mrad of the reference */
#define TDSD_SEG_DONE_QD_RADPS 0.02    /* ... and slower than 0.02 rad/s */
#define TDSD_SEG_SETTLE_MAX_S 2.0      /* after the path: give up settling */

typedef struct tdsd_seg_params {
    double v_m, a_m, u_m;    /* profile: peak speed (m/s), acceleration
                                (m/s^2), da/ds (1/s^2), as action_row_t */
    double K_p, K_o;         /* 1/s, docs/method/tdsd.md §2 eq. 12, 13 */
    double k_V;              /* criterion gain (priority 3), >= 0 */
    unsigned criterion_mask; /* tdsd_midrange_grad joints; 0x38 = q4..q6 */
    double speed_frac;       /* resolver uses speed_frac * qd_max, (0, 1]:
                                the rest is the servo's catch-up margin */
    double T_recover_s;      /* path rate re-accelerates 0 -> 1 in this time */
    double rot_len_m;        /* profile length per radian of re-orientation */
    double v_floor_mps;      /* profile speed floor (leaves s = 0 / reaches L) */
} tdsd_seg_params;

/* The defaults used by tandem-arm (K_p 20/s, K_o 10/s, k_V 10, q4..q6,
 * speed_frac 0.9, T_recover 0.5 s, rot_len 0.2 m/rad, floor 1 cm/s) with
 * the row's v_m, a_m, u_m. */
void tdsd_seg_default_params(tdsd_seg_params *p, double v_m, double a_m, double u_m);

typedef struct tdsd_seg {
    tdsd_seg_params par;
    arm_tool tool;
    double T_world_base[16];
    double p0[3], p1[3]; /* base frame */
    double R0[9], R1[9];
    double rot_axis[3], rot_rad; /* R1 R0^T */
    double L_m;                  /* profile length */
    sprofile prof;
    double s_m;    /* path parameter, 0 .. L */
    double lambda; /* last path rate */
    double q_ref[ARM_NJ], dq_ref[ARM_NJ], ddq_ref[ARM_NJ];
    double t_s;          /* since the start */
    double t_path_end_s; /* when s reached L, -1 before */
    int settled;         /* reference on the target (see DONE_*) */
    double R_world_base[9];
    double KR0[9], kkR0[9]; /* K R0, k k^T R0 (K: the cross-product matrix of
                               rot_axis): R(s) = c R0 + s K R0 + (1 - c) k k^T R0 */
    tdsd_midrange crit;     /* the criterion's ranges (criterion_mask) */
    tdsd_input in;          /* the resolver's input; its constant part (mode, gains,
                      limits) set once by tdsd_seg_start */
} tdsd_seg;

typedef struct tdsd_seg_out {
    double q_d[ARM_NJ], qd_d[ARM_NJ], qdd_d[ARM_NJ]; /* servo reference */
    double s_m, L_m, lambda, Q1, Q2;
    double pos_err_m;    /* reference tool vs path point (model) */
    double ori_err_rad;  /* |e_o| of eq. 13 (sin of the angle) */
    double p_d_world[3]; /* path point */
    int path_done;       /* s reached L */
    int status;          /* tdsd_step status (dq = 0 on error) */
} tdsd_seg_out;

/* Segment from the pose at q (the arm's current joints, also the first
 * reference) to p1_world with tool orientation R1_world. 0 ok, TDSD_SEG_ERR_ARG bad
 * input (non-finite, params out of range, FK failure). */
int tdsd_seg_start(tdsd_seg *g, const arm_model *m, const arm_tool *tool,
                   const double T_world_base[16], const double q[ARM_NJ], const double p1_world[3],
                   const double R1_world[9], const tdsd_seg_params *par);

/* One cycle of dt_s: resolve at q_ref, advance s, integrate (m: the model
 * given to tdsd_seg_start). After the
 * path the resolver keeps running with s = L (the errors decay with K_p,
 * K_o). 0 ok, negative: the resolver's error (the reference then holds). */
int tdsd_seg_step(tdsd_seg *g, const arm_model *m, double dt_s, tdsd_seg_out *out);

/* 1 when the segment is complete for an arm at (q, qd): the path is done,
 * the reference settled on the target (or TDSD_SEG_SETTLE_MAX_S passed
 * since the path's end) and the arm is within TDSD_SEG_DONE_Q_RAD of the
 * reference, slower than TDSD_SEG_DONE_QD_RADPS. */
int tdsd_seg_done(const tdsd_seg *g, const double q[ARM_NJ], const double qd[ARM_NJ]);

/* Velocity-limited computed torque. jointctl's servo acceleration
 *     a = qdd_d + Kv (qd_d - qd) + Kp (q_d - q)
 * is, with Kp / Kv = wn / (2 zeta), a = qdd_d + Kv (v_c - qd) where
 *     v_c = qd_d + (Kp / Kv) (q_d - q)
 * is the speed the servo asks of the joint. When |v_c| > qd_lim_i (an arm
 * that lags its reference catching up), this rewrites the joint's
 * reference to q_d = q, qd_d = sign(v_c) qd_lim_i, qdd_d = 0, so that
 * jointctl_torque gives a = Kv (+-qd_lim_i - qd): the joint approaches its
 * limit from below and does not overshoot it (on the model); it then
 * catches up at the limit. Below the limit the law is unchanged.
 * Returns the number of joints limited, TDSD_SEG_ERR_ARG on bad input (nothing changed). */
int tdsd_servo_vlimit(const jointctl_gains *gains, const double qd_lim[ARM_NJ],
                      const double q[ARM_NJ], double q_d[ARM_NJ], double qd_d[ARM_NJ],
                      double qdd_d[ARM_NJ]);

#endif

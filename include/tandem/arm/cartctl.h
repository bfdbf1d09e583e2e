/* cartctl: operational-space computed torque for one arm (docs/method/carry.md §3: the
 * feedback linearisation that turns the event-referenced law's commanded
 * tool acceleration u into joint torques).
 *
 *   a     = [u_lin; kp_rot log(R_d R^T) - kv_rot w]   (tool accel, base frame)
 *   qdd   = J# (a - Jdot qd) - k_null P qd
 *   tau   = RNE(q, qd, qdd) (+ payload), clamped to the motor limits
 *
 * J# is the damped least-squares inverse V diag(s / (s^2 + lambda^2)) U^T
 * from one SVD of the 6x6 tool Jacobian, with lambda^2 = lambda_max^2
 * (1 - (s_min / sigma_band)^2) when s_min < sigma_band, 0 otherwise
 * (Maciejewski-Klein): exact inverse away from the wrist singularity,
 * bounded joint accelerations near it (tool-down poses keep q5 at
 * -10..-35 deg). P = I - J# J = V diag(lambda^2 / (s^2 + lambda^2)) V^T is
 * the (damped) null-space projector; -k_null P qd damps the motion J#
 * cannot see. Jdot qd is analytic (docs/method/puma.md §3); for a PUMA
 * table pose, J, Jdot qd and J qd come from one pass (§3a).
 *
 * Joint ranges: the task cannot ask a joint to run onto its stop. Each
 * joint's acceleration is bounded so that it comes to rest no closer than
 * range_margin_rad to a range end, as a critically damped spring at that
 * barrier b would bring it there (w = range_w_radps, d = distance to b):
 *   qdd_i >= -w^2 d_lo - 2 w qd_i,   qdd_i <= w^2 d_hi - 2 w qd_i.
 * The bounds act within CARTCTL_RANGE_BAND_RAD of a range end (farther
 * out, a fast move near the wrist singularity would meet them). A
 * joint whose qdd leaves its bounds is held at the bound and the other
 * joints are re-solved for the task in the least-squares sense (position
 * rows, and orientation rows weighted by CARTCTL_RANGE_ROT_WEIGHT_M), one
 * joint at a time, worst first; out->range_limited says which were held.
 * The tool then leaves its commanded path only as far as the ranges force
 * it to (a path that needs a joint beyond its range is not followed past
 * the barrier: the caller sees the tool stop and must re-plan).
 *
 * Fast path: the SVD is the hot spot of the cycle. J^-1 (Gauss-Jordan)
 * gives a lower bound on s_min (||J^-1 J^-T||_F^(-1/2)); when that bound
 * is >= sigma_band, lambda = 0 and J# = J^-1, P = 0, so qdd = J^-1 rhs is
 * the same law without the SVD. Otherwise the SVD decides as above.
 *
 * Everything is in the arm's base frame (arm_fk's frame); the daemon turns
 * world vectors into it.
 */
#ifndef TANDEM_CARTCTL_H
#define TANDEM_CARTCTL_H

#include "arm_dyn.h"
#include "arm_kin.h"

#define CARTCTL_ERR_ARG \
    (-1) /* NULL, non-finite input or invalid gains, or
                                 kinematics / dynamics failed below (a
                                 non-finite acceleration or torque)        */
#define CARTCTL_ERR_SINGULAR \
    (-2) /* cartctl_inverse_wrist: a diagonal block
                                     is singular (elbow or wrist singularity) */

typedef struct cartctl_gains {
    double kp_rot;           /* 1/s^2: orientation stiffness            */
    double kv_rot;           /* 1/s:   orientation damping              */
    double lambda_max;       /* DLS damping at s_min = 0                */
    double sigma_band;       /* damping fades in below this s_min       */
    double k_null;           /* 1/s: null-space joint damping           */
    double range_margin_rad; /* joints come to rest this far inside their ranges */
    double range_w_radps;    /* range barrier bandwidth; 0: no barrier  */
} cartctl_gains;

/* The range barrier acts on joints this close to a range end. */
#define CARTCTL_RANGE_BAND_RAD 0.15
/* Weight (m) of the orientation rows against the position rows when the
 * task is re-solved with a joint held at its range barrier. */
#define CARTCTL_RANGE_ROT_WEIGHT_M 0.1

/* Defaults used by tandem-arm (kp_rot 100, kv_rot 20, lambda_max 0.003,
 * sigma_band 0.003, k_null 5; the tool-down poses have s_min
 * 0.003-0.011; range_margin 1 deg (RANGE_MARGIN_DEFAULT_RAD), range_w 20 rad/s: never active on the
 * carry's planned moves, whose joints stay >= 3.6 deg from their ends). */
void cartctl_gains_default(cartctl_gains *g);
/* 0 if every gain is finite and >= 0, else CARTCTL_ERR_ARG. */
int cartctl_gains_validate(const cartctl_gains *g);

typedef struct cartctl_state {
    double T[16];      /* tool pose, base frame                   */
    double J[36];      /* tool Jacobian                           */
    double twist[6];   /* J qd: v (m/s), w (rad/s)                */
    double jdqd[6];    /* Jdot qd (arm_kin_jdot_qd)               */
    arm_joint_cs cs;   /* cos/sin theta_i, for the RNE            */
    int has_wrist;     /* 1: a spherical wrist (ARM_STRUCTURE_PUMA),
                            its centre in wrist_m                  */
    double wrist_m[3]; /* where joint axes 4, 5, 6 meet, base frame */
} cartctl_state;

typedef struct cartctl_out {
    double qdd[ARM_NJ]; /* commanded joint accelerations        */
    double a_cmd[6];    /* tool acceleration asked of J#        */
    double rot_err[3];  /* log(R_d R^T), rad                    */
    double sigma_min;   /* from the SVD; on the fast path (see
                                cartctl_qdd) a lower bound >= sigma_band */
    double lambda;
    int saturated;          /* 1 if a torque hit its limit          */
    unsigned range_limited; /* bit i: joint i held at its range barrier */
} cartctl_out;

/* Tool pose, Jacobian, twist and Jdot qd at (q, qd), from one kinematics
 * pass. 0 / CARTCTL_ERR_ARG. */
int cartctl_state_at(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                     const double qd[ARM_NJ], cartctl_state *s);

/* Jdot qd (6), analytic (arm_kin_jdot_qd). 0 / CARTCTL_ERR_ARG. */
int cartctl_jdot_qd(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                    const double qd[ARM_NJ], double jdqd[6]);

/* World rotation vector log(R_d R^T) (rad). */
void cartctl_rot_error(const double R_d[9], const double R[9], double err[3]);

/* Ji = J^-1 (6x6 row-major) of the tool Jacobian J at tool pose T of an
 * arm whose last three joint axes meet at wrist_m (both in J's frame),
 * by the wrist's block-triangular form (docs/method/puma.md §6): the fast
 * path of cartctl_qdd for ARM_STRUCTURE_PUMA. 0, CARTCTL_ERR_SINGULAR
 * (a 3x3 block singular) or CARTCTL_ERR_ARG (NULL, non-finite); Ji is
 * undefined on failure. */
int cartctl_inverse_wrist(const double J[36], const double T[16], const double wrist_m[3],
                          double Ji[36]);

/* Joint accelerations for the tool acceleration a_lin (m/s^2, base frame)
 * with the orientation held at R_d (NULL: no orientation servo, angular
 * acceleration 0). s may be NULL (computed here). 0 / CARTCTL_ERR_ARG. */
int cartctl_qdd(const arm_model *m, const arm_tool *tool, const cartctl_gains *g,
                const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s,
                const double a_lin[3], const double R_d[9], cartctl_out *out);

/* The whole law: cartctl_qdd then RNE with payload (NULL = none) and the
 * torque clamp. 0 / CARTCTL_ERR_ARG (tau is then 0). */
int cartctl_torque(const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                   const cartctl_gains *g, const double q[ARM_NJ], const double qd[ARM_NJ],
                   const cartctl_state *s, const double a_lin[3], const double R_d[9],
                   double tau_Nm[ARM_NJ], cartctl_out *out);

/* cartctl_torque with the kinematics s of q, qd given (not NULL) and out
 * not NULL: the arm cycle's entry (cartseg_step_at). It keeps no
 * kinematics pass or output of its own, so the cycle's deepest stack
 * (down to the damped inverse's SVD) holds none. 0 / CARTCTL_ERR_ARG
 * (tau is then 0). */
int cartctl_torque_at(const arm_model *m, const arm_payload *payload, const cartctl_gains *g,
                      const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s,
                      const double a_lin[3], const double R_d[9], double tau_Nm[ARM_NJ],
                      cartctl_out *out);

#endif

/* arm_kin: forward kinematics, geometric Jacobian and closed-form inverse
 * kinematics (all eight branches) of PUMA-type arms (docs/method/carry.md, §3).
 *
 * All poses are in the base (mounting-surface) frame, 4x4 row-major. A NULL
 * tool means the flange. Angles in rad.
 */
#ifndef TANDEM_ARM_KIN_H
#define TANDEM_ARM_KIN_H

#include "arm_model.h"

#define ARM_KIN_ERR_ARG (-1)      /* NULL, non-finite q or pose           */
#define ARM_KIN_ERR_GEOMETRY (-2) /* arm_ik: the model is not PUMA-type   */
#define ARM_KIN_ERR_NO_BRANCH \
    (-3) /* no IK branch: unknown name, or none
                                       inside the limits                    */

/* Pose of the flange (tool == NULL) or of the tool. 0 ok, ARM_KIN_ERR_ARG bad input. */
int arm_fk(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double T[16]);

/* Geometric Jacobian of the flange/tool point in base coordinates, 6x6
 * row-major, rows vx vy vz wx wy wz: [v; w] = J qd. 0 ok, ARM_KIN_ERR_ARG bad input. */
int arm_jacobian(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double J[36]);

/* Same, also returning the pose (saves a second FK). */
int arm_fk_jacobian(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double T[16],
                    double J[36]);

/* ---- one kinematics pass per control cycle ----------------------------------
 * The cycle's kinematics from one evaluation of the joint sines and cosines
 * (docs/method/carry.md §3): link frames, tool pose and Jacobian, kept so
 * that J-dot q-dot (arm_kin_jdot_qd) and the dynamics (arm_rne_cs, with
 * k.cs) reuse them instead of evaluating the chain again. */
typedef struct arm_kin_pass {
    arm_joint_cs cs;          /* cos/sin theta_i                         */
    double F[ARM_NJ + 1][16]; /* base -> frame i (arm_link_frames)       */
    double T[16];             /* tool pose (flange if no tool)           */
    double J[36];             /* tool Jacobian, as arm_fk_jacobian       */
    const arm_model *m;       /* the model the pass was evaluated with   */
    int puma;                 /* the model's structure is ARM_STRUCTURE_PUMA */
} arm_kin_pass;

/* 0 ok, ARM_KIN_ERR_ARG bad input (k zeroed). */
int arm_kin_eval(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], arm_kin_pass *k);

/* J-dot q-dot (6: m/s^2, rad/s^2) at the pass's q, analytic (docs/method/carry.md
 * §3, eq. for Jdot qd): sum_i qd_i [ (w_i x z_i) x (p - o_i) + z_i x (pdot - odot_i);
 * w_i x z_i ], w_i, odot_i the angular velocity and origin velocity of frame i.
 * 0 ok, ARM_KIN_ERR_ARG bad input (jdqd zeroed). */
int arm_kin_jdot_qd(const arm_kin_pass *k, const double qd[ARM_NJ], double jdqd[6]);

/* ---- inverse kinematics ---------------------------------------------------
 * Branch index b = shoulder | elbow << 1 | wrist << 2:
 *   shoulder 0 left, 1 right (right: the wrist centre is in front of the
 *     shoulder in the arm plane, as at q = 0; left reaches over the back);
 *   elbow 0 up, 1 down (elbow above / below the shoulder-wrist line);
 *   wrist 0 noflip (|q4| <= 90 deg before limit wrapping), 1 flip
 *     (q4 + 180 deg, q5 negated, q6 + 180 deg).
 * Names: "left-up-noflip", "right-down-flip", ...
 */
#define ARM_IK_NBRANCH 8

enum {
    ARM_IK_OK = 0,
    ARM_IK_UNREACHABLE = 1,   /* the pose has no solution on this branch */
    ARM_IK_OUTSIDE_LIMITS = 2 /* a solution, but some joint is out of range */
};

typedef struct arm_ik_branch {
    double q_rad[ARM_NJ]; /* valid unless status has ARM_IK_UNREACHABLE */
    int status;           /* ARM_IK_* flags */
    unsigned limit_bits;  /* bit i: joint i+1 outside its range */
} arm_ik_branch;

typedef struct arm_ik_result {
    arm_ik_branch branch[ARM_IK_NBRANCH];
    int unreachable; /* 1: no branch reaches the pose */
    int n_valid;     /* branches reachable and inside the limits */
} arm_ik_result;

const char *arm_ik_branch_name(int b);
/* Name -> branch index, ARM_KIN_ERR_NO_BRANCH if unknown. */
int arm_ik_branch_from_name(const char *name);

/* Solve every branch. Needs a PUMA-type model (a1 = a4 = a5 = a6 = 0,
 * d5 = 0, alpha = [90 0 -90 90 -90 0] deg). Angles in range are wrapped by
 * +-2 pi when that brings them inside [q_min, q_max].
 * 0 ok (check out->unreachable), ARM_KIN_ERR_ARG bad input,
 * ARM_KIN_ERR_GEOMETRY unsupported geometry. */
int arm_ik(const arm_model *m, const arm_tool *tool, const double T[16], arm_ik_result *out);

/* Index of the in-limits branch closest to q_ref (max-abs joint distance),
 * ARM_KIN_ERR_NO_BRANCH if none. */
int arm_ik_nearest(const arm_ik_result *r, const double q_ref[ARM_NJ]);

/* Branch index of a joint vector (its configuration), as arm_ik names it. */
int arm_ik_branch_of(const arm_model *m, const double q[ARM_NJ]);

#endif

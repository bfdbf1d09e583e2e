/* arm_dyn: rigid-body inverse dynamics, joint-space inertia, gravity and
 * Coriolis/centrifugal torques of the arm models (docs/method/carry.md §3 computed
 * torque, §7 hold with gravity compensation, §5 simulator cross-checks).
 *
 *   tau = M(q) qdd + C(q, qd) qd + g(q)       (link-side torques, N m)
 *
 * Gravity is a vector in base coordinates; NULL means ARM_GRAVITY_DEFAULT
 * (0, 0, -9.81) m/s^2. A payload rigidly held at the flange is optional
 * (NULL = bare arm). The motors' reflected rotor inertia (armature_kgm2)
 * sits on M's diagonal; friction is not modelled.
 */
#ifndef TANDEM_ARM_DYN_H
#define TANDEM_ARM_DYN_H

#include "arm_model.h"

#define ARM_DYN_ERR_ARG (-1) /* NULL, non-finite input, negative payload */
#define ARM_DYN_ERR_NOT_PD \
    (-2) /* mass matrix not positive definite
                                    (cannot happen for a valid model)      */

#define ARM_GRAVITY_MPS2 9.81

typedef struct arm_payload {
    double mass_kg;
    double com_m[3];        /* in the flange frame (frame 6) */
    double inertia_kgm2[9]; /* about its COM, flange axes; zeros = point mass */
} arm_payload;

/* Point-mass payload at com (flange frame). 0 ok, ARM_DYN_ERR_ARG bad input. */
int arm_payload_point(arm_payload *p, double mass_kg, const double com_m[3]);

/* Recursive Newton-Euler (Luh, Walker & Paul 1980): tau for (q, qd, qdd).
 * 0 ok, ARM_DYN_ERR_ARG bad input (NULL, non-finite, negative payload mass). */
int arm_rne(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
            const double qdd[ARM_NJ], const double gravity_mps2[3], const arm_payload *payload,
            double tau_Nm[ARM_NJ]);

/* arm_rne with the joint sines and cosines already evaluated (cs from
 * arm_joint_cs_eval or an arm_kin_pass of the same q): the cycle's one
 * kinematics pass feeds the dynamics too. Same results and codes as arm_rne. */
int arm_rne_cs(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
               const double qdd[ARM_NJ], const double gravity_mps2[3], const arm_payload *payload,
               double tau_Nm[ARM_NJ]);

/* Joint-space inertia M(q), 6x6 row-major, composite rigid body algorithm. */
int arm_mass_matrix(const arm_model *m, const double q[ARM_NJ], const arm_payload *payload,
                    double M[36]);

/* g(q): torques that hold the arm still against gravity. */
int arm_gravity(const arm_model *m, const double q[ARM_NJ], const double gravity_mps2[3],
                const arm_payload *payload, double tau_Nm[ARM_NJ]);

/* C(q, qd) qd: Coriolis and centrifugal torques (no gravity). */
int arm_coriolis(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
                 const arm_payload *payload, double c_Nm[ARM_NJ]);

/* Forward dynamics qdd = M^-1 (tau - C qd - g). ARM_DYN_ERR_NOT_PD if M is
 * not positive definite (cannot happen for a valid model). */
int arm_forward_dynamics(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
                         const double tau_Nm[ARM_NJ], const double gravity_mps2[3],
                         const arm_payload *payload, double qdd[ARM_NJ]);

/* Solve M x = b for a symmetric positive definite 6x6 M (Cholesky).
 * 0 ok, ARM_DYN_ERR_NOT_PD not positive definite. */
int arm_spd_solve6(const double M[36], const double b[ARM_NJ], double x[ARM_NJ]);

#endif

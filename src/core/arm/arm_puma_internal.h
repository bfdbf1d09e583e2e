/* arm_puma_internal: the folded PUMA routines (docs/method/puma.md) behind
 * arm_kin and arm_dyn, which take them for a model whose structure is
 * ARM_STRUCTURE_PUMA. Inputs are validated by those callers. */
#ifndef TANDEM_ARM_PUMA_INTERNAL_H
#define TANDEM_ARM_PUMA_INTERNAL_H

#include "arm_dyn.h"
#include "arm_model.h"

/* arm_rne_cs for a caller that passes m, cs and tau_Nm non-NULL (the
 * Cartesian cycle): the payload is validated, but instead of checking
 * qd, qdd, gravity and cs finite one by one, the torques are checked
 * after (a NaN or Inf in any input shows in them). 0, or ARM_DYN_ERR_ARG
 * (tau_Nm then undefined). arm_dyn.c. */
int arm_rne_cs_unchecked(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
                         const double qdd[ARM_NJ], const double gravity_mps2[3],
                         const arm_payload *payload, double tau_Nm[ARM_NJ]);

/* Mass properties of link i as the dynamics read them: the model's own,
 * or link 6 merged with a payload (then I is a full 3x3). */
typedef struct arm_link_ref {
    double m;
    const double *c; /* COM in frame i */
    const double *I; /* about the COM, frame-i axes, row-major 3x3 */
} arm_link_ref;

/* A rigid body or composite referred to a frame origin: mass, first
 * moment h = m c and inertia about the origin, in that frame's axes; the
 * inertia is symmetric, so I = (xx, yy, zz, xy, yz, xz) (ARM_I_XX ...). */
enum { ARM_I_XX, ARM_I_YY, ARM_I_ZZ, ARM_I_XY, ARM_I_YZ, ARM_I_XZ };
typedef struct arm_composite {
    double m;
    double h[3];
    double I[6];
} arm_composite;

/* b += link l (COM c, inertia about c): h += m c, I += I_c + m (|c|^2 E - c c^T).
 * Both CRBAs use it; inline, so that the folded one keeps its composite
 * in registers. */
static inline void arm_composite_add_link(arm_composite *b, const arm_link_ref *l)
{
    const double m = l->m, *c = l->c, *Ic = l->I;
    const double mx = m * c[0], my = m * c[1], mz = m * c[2];
    b->m += m;
    b->h[0] += mx;
    b->h[1] += my;
    b->h[2] += mz;
    b->I[ARM_I_XX] += Ic[0] + my * c[1] + mz * c[2];
    b->I[ARM_I_YY] += Ic[4] + mx * c[0] + mz * c[2];
    b->I[ARM_I_ZZ] += Ic[8] + mx * c[0] + my * c[1];
    b->I[ARM_I_XY] += Ic[1] - mx * c[1];
    b->I[ARM_I_YZ] += Ic[5] - my * c[2];
    b->I[ARM_I_XZ] += Ic[2] - mx * c[2];
}
/* b, turned into the parent's axes (h: its first moment, turned), moved to
 * the parent's origin p (parallel-axis step); arm_dyn.c, for the general
 * CRBA (the PUMA's has p's zeros folded: shift_xy, shift_z). */
void arm_composite_shift(arm_composite *b, const double p[3], const double h[3]);

/* Every frame F[0..6] as arm_link_frames gives them, F[6] the flange
 * (docs/method/puma.md §2). */
void arm_puma_chain(const arm_model *m, const arm_joint_cs *cs, double (*F)[16]);

/* Geometric Jacobian of the point of pose T from the frames F (§3). */
void arm_puma_jacobian(const double (*F)[16], const double T[16], double J[36]);

/* J-dot q-dot of the point of pose T (§3), F6 the flange frame. */
void arm_puma_jdot_qd(const arm_model *m, const arm_joint_cs *cs, const double F6[16],
                      const double T[16], const double qd[ARM_NJ], double jdqd[6]);

/* The Cartesian cycle's kinematics in one pass (§3a): the frames of
 * arm_puma_chain once, and from them the pose T of the tool (NULL: the
 * flange; a rigid T_flange_tool), its Jacobian J, J-dot q-dot and the
 * wrist centre o4, all in base coordinates; the bits of arm_kin_eval and
 * arm_kin_jdot_qd. Inputs checked by the caller (cartctl_state_at). */
void arm_puma_cycle_kin(const arm_model *m, const arm_joint_cs *cs, const arm_tool *tool,
                        const double qd[ARM_NJ], double T[16], double J[36], double jdqd[6],
                        double wrist_m[3]);

/* RNE torques (§4); g the gravity vector in base coordinates, payload
 * NULL or valid. */
void arm_puma_rne(const arm_model *m, const arm_joint_cs *cs, const arm_payload *payload,
                  const double qd[ARM_NJ], const double qdd[ARM_NJ], const double g[3],
                  double tau_Nm[ARM_NJ]);

/* 1 if link 6 as given (with its payload) is symmetric about its own z
 * axis; then arm_puma_mass_matrix does not read cs of joint 6 (§5). */
int arm_puma_link6_axisymmetric(const arm_link_ref *l6);

/* Joint-space inertia M(q), 6x6 row-major (§5). Reads cs of joints 2-5,
 * and of joint 6 unless link 6 is axisymmetric; never of joint 1. */
void arm_puma_mass_matrix(const arm_model *m, const arm_joint_cs *cs, const arm_link_ref L[ARM_NJ],
                          double M[36]);

#endif

/* arm_puma_internal: the folded PUMA routines (docs/method/puma.md) behind
 * arm_kin and arm_dyn, which take them for a model whose structure is
 * ARM_STRUCTURE_PUMA. Inputs are validated by those callers. */
#ifndef TANDEM_ARM_PUMA_INTERNAL_H
#define TANDEM_ARM_PUMA_INTERNAL_H

#include "arm_dyn.h"
#include "arm_model.h"

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

/* b += link l (arm_dyn.c; both CRBAs use it). */
void arm_composite_add_link(arm_composite *b, const arm_link_ref *l);
/* b, turned into the parent's axes (h: its first moment, turned), moved to
 * the parent's origin p (parallel-axis step); arm_dyn.c. */
void arm_composite_shift(arm_composite *b, const double p[3], const double h[3]);

/* Every frame F[0..6] as arm_link_frames gives them, F[6] the flange
 * (docs/method/puma.md §2). */
void arm_puma_chain(const arm_model *m, const arm_joint_cs *cs, double (*F)[16]);

/* Geometric Jacobian of the point of pose T from the frames F (§3). */
void arm_puma_jacobian(const double (*F)[16], const double T[16], double J[36]);

/* RNE torques (§4); g the gravity vector in base coordinates, payload
 * NULL or valid. */
void arm_puma_rne(const arm_model *m, const arm_joint_cs *cs, const arm_payload *payload,
                  const double qd[ARM_NJ], const double qdd[ARM_NJ], const double g[3],
                  double tau_Nm[ARM_NJ]);

/* Joint-space inertia M(q), 6x6 row-major (§5). */
void arm_puma_mass_matrix(const arm_model *m, const arm_joint_cs *cs, const arm_link_ref L[ARM_NJ],
                          double M[36]);

#endif

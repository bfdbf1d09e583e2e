/* arm_model: constant kinematic and dynamic tables of 6R arms (docs/method/tdsd.md, §5).
 *
 * Standard Denavit-Hartenberg convention (Corke): the transform from frame
 * i-1 to frame i is A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i) with
 * theta_i = q_i + theta_offset_i. Joint i turns about z_{i-1}; link i is
 * rigidly attached to frame i, so its centre of mass and inertia are given
 * in frame i. Frame 0 sits base_height_m above the mounting surface (the
 * "base" frame, z up, same orientation); frame 6 is the flange.
 */
#ifndef TANDEM_ARM_MODEL_H
#define TANDEM_ARM_MODEL_H

#define ARM_MODEL_ERR_ARG \
    (-1) /* NULL (a table without name too),
                                            a non-finite joint or tool offset */
/* arm_model_validate only: */
#define ARM_MODEL_ERR_NONFINITE (-2) /* a table entry is NaN or Inf      */
#define ARM_MODEL_ERR_RANGE \
    (-3) /* a length, joint range, speed or
                                            torque limit or mass outside its
                                            physical range                  */
#define ARM_MODEL_ERR_INCONSISTENT \
    (-4) /* cos/sin_alpha do not match
                                            alpha_rad, or an inertia is not
                                            symmetric positive definite     */
#define ARM_MODEL_ERR_STRUCTURE \
    (-5) /* claims ARM_STRUCTURE_PUMA without
                                            the PUMA's zeros and right angles,
                                            or an unknown structure         */

#define ARM_NJ 6 /* joints of every arm model */

/* Which routines an arm takes (docs/method/puma.md). GENERAL: the DH
 * recursions for any table (the reference). PUMA: the folded closed forms,
 * valid only for a table with alpha = 90 0 -90 90 -90 0 deg, a1 = a4 = a5
 * = a6 = 0, d1 = d2 = d5 = 0, no joint offsets and diagonal link inertias
 * (arm_model_has_puma_structure); arm_model_validate refuses a table that
 * claims it without having it. */
#define ARM_STRUCTURE_GENERAL 0
#define ARM_STRUCTURE_PUMA 1

typedef struct arm_model {
    const char *name;
    int structure;        /* ARM_STRUCTURE_*                    */
    double base_height_m; /* mounting surface -> frame 0 (shoulder) */
    double a_m[ARM_NJ];
    double d_m[ARM_NJ];
    double alpha_rad[ARM_NJ];
    /* cos/sin of alpha_rad, kept in the table so that no routine evaluates
     * trig of a constant per call. A model built or edited at run time must
     * call arm_model_refresh_alpha after setting alpha_rad. */
    double cos_alpha[ARM_NJ];
    double sin_alpha[ARM_NJ];
    double theta_offset_rad[ARM_NJ];
    double q_min_rad[ARM_NJ];
    double q_max_rad[ARM_NJ];
    double qd_max_radps[ARM_NJ]; /* motor speed limit at the joint */
    double tau_max_Nm[ARM_NJ];   /* peak joint torque */
    double mass_kg[ARM_NJ];
    double com_m[ARM_NJ][3];        /* centre of mass of link i in frame i */
    double inertia_kgm2[ARM_NJ][9]; /* about the COM, frame-i axes, row-major */
    /* The motor's rotor inertia reflected through the gear, Jm G^2, at
     * joint i: it adds to M(q)'s diagonal only (the couplings it makes
     * are G times smaller and neglected, as in Corke's rne). */
    double armature_kgm2[ARM_NJ];
} arm_model;

/* Corke's Puma560 (Armstrong, Khatib & Burdick 1986 inertial data). */
extern const arm_model arm_model_puma560;
/* The simplified PUMA of seed 002 (la 671, lc 433, lf 433, lg 50 mm). */
extern const arm_model arm_model_seed002;

/* Tool rigidly fixed to the flange: T_flange_tool (4x4 row-major). */
typedef struct arm_tool {
    double T_flange_tool[16];
} arm_tool;

/* Identity tool (the flange itself). */
void arm_tool_none(arm_tool *tool);
/* Pure translation of the tool point, flange axes kept. 0 or ARM_MODEL_ERR_ARG. */
int arm_tool_offset(arm_tool *tool, const double p_flange_m[3]);

/* The table is sound: a name, every number finite, link lengths a_i and
 * the base height >= 0, q_min < q_max, speed and torque limits and masses > 0,
 * cos/sin_alpha equal to cos/sin(alpha_rad) (to 1e-12), inertias symmetric
 * positive definite, and the structure field one of ARM_STRUCTURE_* that
 * the table has. 0 or ARM_MODEL_ERR_*. For start-up checks. */
int arm_model_validate(const arm_model *m);

/* 1 if the table has the zeros and right angles the folded PUMA routines
 * drop (ARM_STRUCTURE_PUMA above; alpha to 1e-12 rad, the rest exactly),
 * whatever its structure field says; 0 otherwise (also for NULL). */
int arm_model_has_puma_structure(const arm_model *m);

/* "puma560" / "seed002" -> model; NULL if unknown. */
const arm_model *arm_model_by_name(const char *name);

/* 0 if all six numbers are finite, ARM_MODEL_ERR_ARG otherwise (also for NULL). */
int arm_q_finite(const double q[ARM_NJ]);
/* Bit i set if q_i is outside [q_min_i, q_max_i]; 0 = all inside. */
unsigned arm_q_outside_limits(const arm_model *m, const double q[ARM_NJ]);

/* An arm is outside its range when a joint is past a range end by more
 * than this (a joint resting on its mechanical stop is inside). */
#define ARM_RANGE_TOL_RAD 0.0087 /* 0.5 deg */
/* Joint faults of a measured state: bit i (0..5) joint i past its range by
 * more than ARM_RANGE_TOL_RAD, bit 6 + i joint i faster than its speed
 * limit; non-finite values count as both. 0 = healthy. */
#define ARM_FAULT_RANGE(bits) ((bits)&0x3fu)
#define ARM_FAULT_SPEED(bits) (((bits) >> ARM_NJ) & 0x3fu)
unsigned arm_joint_faults(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ]);

/* Recompute cos_alpha/sin_alpha from alpha_rad (for models built or edited
 * at run time; the shipped tables already hold them). */
void arm_model_refresh_alpha(arm_model *m);

/* cos/sin of theta_i = q_i + theta_offset_i: the one trig evaluation per
 * joint that FK, Jacobian, RNE and M(q) share. */
typedef struct arm_joint_cs {
    double c[ARM_NJ];
    double s[ARM_NJ];
} arm_joint_cs;

/* 0 or ARM_MODEL_ERR_ARG (NULL, non-finite q). */
int arm_joint_cs_eval(const arm_model *m, const double q[ARM_NJ], arm_joint_cs *cs);

/* Link i -> frame i transform A_i(q_i) (4x4 row-major). */
void arm_dh_transform(const arm_model *m, int i, double q_i, double A[16]);

/* out = T A_i for joint i with cos/sin theta_i = (ct, st), using the DH
 * structure instead of a general 4x4 product; out may be T (in place). */
void arm_dh_compose(const arm_model *m, int i, double ct, double st, const double T[16],
                    double out[16]);

/* Mounting surface -> frame 0: identity rotation, base_height_m up. */
void arm_base_frame(const arm_model *m, double T[16]);

/* T[0] = mounting surface -> frame 0 (base height), T[i] = mounting
 * surface -> frame i (i = 1..6, T[6] = flange). Link i's body pose is T[i];
 * its COM in base coordinates is T[i] * com_m[i-1].
 * 0 or ARM_MODEL_ERR_ARG (NULL, non-finite q). */
int arm_link_frames(const arm_model *m, const double q[ARM_NJ], double T[ARM_NJ + 1][16]);

#endif

/* arm_model: PUMA 560 and seed-002 arm tables, DH link transforms and the
 * per-link frames the simulator places its bodies with (docs/method/tdsd.md, §5),
 * and arm_model_validate, the tables' start-up check.
 *
 * Sources and choices (every number below is one of these):
 * - Kinematics, masses, COMs, inertias: Corke's mdl_puma560 (standard DH),
 *   itself from Armstrong, Khatib & Burdick 1986 and Corke &
 *   Armstrong-Helouvry 1994. Corke's 'I' = [Ixx Iyy Izz Ixy Iyz Ixz].
 * - Link 1: Corke gives m = 0 and I = diag(0, 0.35, 0). An ODE body needs a
 *   positive mass and a physically valid inertia. Link 1 only rotates about
 *   z0 (= y1) and its COM is on that axis, so its mass and its inertia about
 *   axes other than y1 never enter the joint-space dynamics: we use 13 kg
 *   and diag(0.30, 0.35, 0.30) (triangle inequality holds), keeping the
 *   only dynamically visible number, Iyy = 0.35 kg m^2, unchanged.
 * - Link 3's published principal moments (0.066, 0.086, 0.0125) violate the
 *   triangle inequality (0.066 + 0.0125 < 0.086); kept as published (the
 *   matrix is positive definite, which is all ODE checks).
 * - Motor armature: Jm G^2 with Corke's mdl_puma560 Jm (200e-6 kg m^2 for
 *   joints 1-3, 33e-6 for 4-6) and gear ratios G (-62.6111 107.815
 *   -53.7063 76.0364 71.923 76.686): 0.784 2.325 0.577 0.191 0.171 0.194
 *   kg m^2. On the wrist it is 100-1000 times the link's own inertia:
 *   without it a stick hitting link 6 at cruise spun joint 6 past its
 *   speed limit within one 1 ms step (docs/method/carry.md §8). Gear
 *   friction and Coulomb friction are not modelled (the simulator adds
 *   its own, sim_config).
 * - Joint ranges: docs/method/tdsd.md (seed 002's PUMA 560 ranges).
 * - Base height: shoulder (frame 0) 0.6718 m above the mounting surface.
 * - tau_max: the peak joint torques commonly quoted for the PUMA 560
 *   (97.6 186.4 89.4 24.2 20.1 21.3 N m).
 * - qd_max: no primary Unimation figure was at hand; we use conservative
 *   engineering values of the order of the rated motor speed divided by
 *   Corke's gear ratios (joints 1-3 about 2 rad/s, wrist about 4 rad/s).
 * - seed002: the seed gives only lengths. la -> base height, lc -> a2,
 *   lf -> d4, lg -> d6, lb = ld = le = 0 -> d3 = a3 = 0. Mass properties,
 *   ranges and motor limits are the PUMA's; COMs that are measured from a
 *   frame the seed moves (frame 3: a3 = 0; frame 6: d6 = 0.05) are shifted
 *   so each COM keeps its place relative to the joint axes.
 */
#include "arm_model.h"
#include "arm_puma_internal.h"
#include "trig.h"
#include "vec3.h"
#include <math.h>
#include <stddef.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)
#define PI_2 1.57079632679489661923
/* cos(PI_2) exactly as libm returns it for the double nearest pi/2, so the
 * precomputed table gives the same bits as cos(alpha_rad) did per call. */
#define COS_PI_2 6.123233995736766e-17

/* alpha = 90 0 -90 90 -90 0 deg, shared by both tables */
#define PUMA_ALPHA                                                     \
    .alpha_rad = { PI_2, 0.0, -PI_2, PI_2, -PI_2, 0.0 },               \
    .cos_alpha = { COS_PI_2, 1.0, COS_PI_2, COS_PI_2, COS_PI_2, 1.0 }, \
    .sin_alpha = { 1.0, 0.0, -1.0, 1.0, -1.0, 0.0 }

#define DIAG(x, y, z)                               \
    {                                               \
        (x), 0.0, 0.0, 0.0, (y), 0.0, 0.0, 0.0, (z) \
    }

#define PUMA_LIMITS                                                                         \
    .q_min_rad = { -160 * DEG, -225 * DEG, -45 * DEG, -110 * DEG, -100 * DEG, -266 * DEG }, \
    .q_max_rad = { 160 * DEG, 45 * DEG, 225 * DEG, 170 * DEG, 100 * DEG, 266 * DEG },       \
    .qd_max_radps = { 2.0, 1.75, 2.2, 4.0, 3.6, 4.6 },                                      \
    .tau_max_Nm = { 97.6, 186.4, 89.4, 24.2, 20.1, 21.3 },                                  \
    .mass_kg = { 13.0, 17.4, 4.8, 0.82, 0.34, 0.09 },                                       \
    .armature_kgm2 = { 0.78403, 2.32481, 0.57687, 0.19079, 0.17071, 0.19406 }

#define PUMA_INERTIA                                                              \
    .inertia_kgm2 = { DIAG(0.30, 0.35, 0.30),       DIAG(0.13, 0.524, 0.539),     \
                      DIAG(0.066, 0.086, 0.0125),   DIAG(1.8e-3, 1.3e-3, 1.8e-3), \
                      DIAG(0.3e-3, 0.4e-3, 0.3e-3), DIAG(0.15e-3, 0.15e-3, 0.04e-3) }

const arm_model arm_model_puma560 = {
    .name = "puma560",
    .structure = ARM_STRUCTURE_PUMA,
    .base_height_m = 0.6718,
    .a_m = { 0.0, 0.4318, 0.0203, 0.0, 0.0, 0.0 },
    .d_m = { 0.0, 0.0, 0.15005, 0.4318, 0.0, 0.0 },
    PUMA_ALPHA,
    .theta_offset_rad = { 0, 0, 0, 0, 0, 0 },
    PUMA_LIMITS,
    .com_m = { { 0, 0, 0 },
               { -0.3638, 0.006, 0.2275 },
               { -0.0203, -0.0141, 0.070 },
               { 0, 0.019, 0 },
               { 0, 0, 0 },
               { 0, 0, 0.032 } },
    PUMA_INERTIA,
};

const arm_model arm_model_seed002 = {
    .name = "seed002",
    .structure = ARM_STRUCTURE_PUMA,
    .base_height_m = 0.671,
    .a_m = { 0.0, 0.433, 0.0, 0.0, 0.0, 0.0 },
    .d_m = { 0.0, 0.0, 0.0, 0.433, 0.0, 0.050 },
    PUMA_ALPHA,
    .theta_offset_rad = { 0, 0, 0, 0, 0, 0 },
    PUMA_LIMITS,
    .com_m = { { 0, 0, 0 },
               { -0.3638, 0.006, 0.2275 },
               { 0.0, -0.0141, 0.070 },
               { 0, 0.019, 0 },
               { 0, 0, 0 },
               { 0, 0, 0.032 - 0.050 } },
    PUMA_INERTIA,
};

void arm_tool_none(arm_tool *tool)
{
    if (tool)
        tf_identity(tool->T_flange_tool);
}

int arm_tool_offset(arm_tool *tool, const double p_flange_m[3])
{
    if (!tool || !p_flange_m || !isfinite(p_flange_m[0]) || !isfinite(p_flange_m[1]) ||
        !isfinite(p_flange_m[2]))
        return ARM_MODEL_ERR_ARG;
    tf_identity(tool->T_flange_tool);
    tool->T_flange_tool[3] = p_flange_m[0];
    tool->T_flange_tool[7] = p_flange_m[1];
    tool->T_flange_tool[11] = p_flange_m[2];
    return 0;
}

/* The per-joint rows of the table, for the finiteness check. */
static int rows_finite(const arm_model *m)
{
    const double *rows[] = { m->a_m,        m->d_m,       m->alpha_rad,
                             m->cos_alpha,  m->sin_alpha, m->theta_offset_rad,
                             m->q_min_rad,  m->q_max_rad, m->qd_max_radps,
                             m->tau_max_Nm, m->mass_kg,   m->armature_kgm2 };
    size_t r;
    int i, k;
    if (!isfinite(m->base_height_m))
        return 0;
    for (r = 0; r < sizeof rows / sizeof rows[0]; r++)
        for (i = 0; i < ARM_NJ; i++)
            if (!isfinite(rows[r][i]))
                return 0;
    for (i = 0; i < ARM_NJ; i++) {
        for (k = 0; k < 3; k++)
            if (!isfinite(m->com_m[i][k]))
                return 0;
        for (k = 0; k < 9; k++)
            if (!isfinite(m->inertia_kgm2[i][k]))
                return 0;
    }
    return 1;
}

/* Symmetric positive definite 3x3 (Sylvester: leading minors > 0). */
static int inertia_spd(const double I[9])
{
    const double m2 = I[0] * I[4] - I[1] * I[3];
    const double m3 = I[0] * (I[4] * I[8] - I[5] * I[7]) - I[1] * (I[3] * I[8] - I[5] * I[6]) +
                      I[2] * (I[3] * I[7] - I[4] * I[6]);
    return I[1] == I[3] && I[2] == I[6] && I[5] == I[7] && I[0] > 0.0 && m2 > 0.0 && m3 > 0.0;
}

int arm_model_has_puma_structure(const arm_model *m)
{
    static const double alpha[ARM_NJ] = { PI_2, 0.0, -PI_2, PI_2, -PI_2, 0.0 };
    const double tol = 1e-12;
    int i, k;
    if (!m)
        return 0;
    for (i = 0; i < ARM_NJ; i++) {
        if (!(fabs(m->alpha_rad[i] - alpha[i]) <= tol) || m->theta_offset_rad[i] != 0.0)
            return 0;
        for (k = 0; k < 9; k++)
            if (k != 0 && k != 4 && k != 8 && m->inertia_kgm2[i][k] != 0.0)
                return 0;
    }
    return m->a_m[0] == 0.0 && m->a_m[3] == 0.0 && m->a_m[4] == 0.0 && m->a_m[5] == 0.0 &&
           m->d_m[0] == 0.0 && m->d_m[1] == 0.0 && m->d_m[4] == 0.0;
}

int arm_model_validate(const arm_model *m)
{
    /* the tables store libm's cos/sin of the same double; 1e-12 leaves
     * room for another libm, not for a wrong angle */
    const double trig_tol = 1e-12;
    int i;
    if (!m || !m->name)
        return ARM_MODEL_ERR_ARG;
    if (!rows_finite(m))
        return ARM_MODEL_ERR_NONFINITE;
    if (m->base_height_m < 0.0)
        return ARM_MODEL_ERR_RANGE;
    for (i = 0; i < ARM_NJ; i++)
        if (m->a_m[i] < 0.0 || !(m->q_min_rad[i] < m->q_max_rad[i]) ||
            !(m->qd_max_radps[i] > 0.0) || !(m->tau_max_Nm[i] > 0.0) || !(m->mass_kg[i] > 0.0) ||
            m->armature_kgm2[i] < 0.0)
            return ARM_MODEL_ERR_RANGE;
    for (i = 0; i < ARM_NJ; i++)
        if (fabs(m->cos_alpha[i] - cos(m->alpha_rad[i])) > trig_tol ||
            fabs(m->sin_alpha[i] - sin(m->alpha_rad[i])) > trig_tol ||
            !inertia_spd(m->inertia_kgm2[i]))
            return ARM_MODEL_ERR_INCONSISTENT;
    if (m->structure == ARM_STRUCTURE_PUMA ? !arm_model_has_puma_structure(m)
                                           : m->structure != ARM_STRUCTURE_GENERAL)
        return ARM_MODEL_ERR_STRUCTURE;
    return 0;
}

const arm_model *arm_model_by_name(const char *name)
{
    if (!name)
        return NULL;
    if (strcmp(name, arm_model_puma560.name) == 0)
        return &arm_model_puma560;
    if (strcmp(name, arm_model_seed002.name) == 0)
        return &arm_model_seed002;
    return NULL;
}

int arm_q_finite(const double q[ARM_NJ])
{
    int i;
    if (!q)
        return ARM_MODEL_ERR_ARG;
    for (i = 0; i < ARM_NJ; i++)
        if (!isfinite(q[i]))
            return ARM_MODEL_ERR_ARG;
    return 0;
}

unsigned arm_q_outside_limits(const arm_model *m, const double q[ARM_NJ])
{
    unsigned bits = 0;
    int i;
    for (i = 0; i < ARM_NJ; i++)
        if (!(q[i] >= m->q_min_rad[i] && q[i] <= m->q_max_rad[i]))
            bits |= 1u << i;
    return bits;
}

unsigned arm_joint_faults(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ])
{
    unsigned bits = 0;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        if (!(q[i] >= m->q_min_rad[i] - ARM_RANGE_TOL_RAD &&
              q[i] <= m->q_max_rad[i] + ARM_RANGE_TOL_RAD))
            bits |= 1u << i;
        if (!(fabs(qd[i]) <= m->qd_max_radps[i]))
            bits |= 1u << (ARM_NJ + i);
    }
    return bits;
}

void arm_model_refresh_alpha(arm_model *m)
{
    int i;
    if (!m)
        return;
    for (i = 0; i < ARM_NJ; i++) {
        m->cos_alpha[i] = cos(m->alpha_rad[i]);
        m->sin_alpha[i] = sin(m->alpha_rad[i]);
    }
}

int arm_joint_cs_eval(const arm_model *m, const double q[ARM_NJ], arm_joint_cs *cs)
{
    int i;
    if (!m || !cs || !q)
        return ARM_MODEL_ERR_ARG;
    for (i = 0; i < ARM_NJ; i++) {
        const double th = q[i] + m->theta_offset_rad[i];
        if (!isfinite(q[i]))
            return ARM_MODEL_ERR_ARG;
        /* not libm's: on the 68040 its sin/cos trap to software */
        trig_sincos(th, &cs->s[i], &cs->c[i]);
    }
    return 0;
}

void arm_dh_transform(const arm_model *m, int i, double q_i, double A[16])
{
    const double th = q_i + m->theta_offset_rad[i];
    const double ct = cos(th), st = sin(th);
    const double ca = m->cos_alpha[i], sa = m->sin_alpha[i];
    const double a = m->a_m[i], d = m->d_m[i];
    A[0] = ct;
    A[1] = -st * ca;
    A[2] = st * sa;
    A[3] = a * ct;
    A[4] = st;
    A[5] = ct * ca;
    A[6] = -ct * sa;
    A[7] = a * st;
    A[8] = 0.0;
    A[9] = sa;
    A[10] = ca;
    A[11] = d;
    A[12] = 0.0;
    A[13] = 0.0;
    A[14] = 0.0;
    A[15] = 1.0;
}

void arm_base_frame(const arm_model *m, double T[16])
{
    /* a constant copied in: cheaper than tf_identity's loop on the hot path */
    static const double identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    memcpy(T, identity, sizeof identity);
    T[11] = m->base_height_m;
}

/* A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha), so each row r of T A_i is row r
 * of T turned by theta in its (x, y) entries, then by alpha in its (y, z)
 * entries, and the position gains a (row . x-axis after Rz) + d (row z):
 * 30 multiplications per joint instead of a 4x4 product and a copy. Rows
 * are independent, which makes the in-place call safe. */
void arm_dh_compose(const arm_model *m, int i, double ct, double st, const double T[16],
                    double out[16])
{
    const double ca = m->cos_alpha[i], sa = m->sin_alpha[i];
    const double a = m->a_m[i], d = m->d_m[i];
    int r;
    for (r = 0; r < 12; r += 4) {
        const double x = T[r], y = T[r + 1], z = T[r + 2], p = T[r + 3];
        const double u = x * ct + y * st; /* row . Rz x-axis */
        const double v = y * ct - x * st; /* row . Rz y-axis */
        out[r] = u;
        out[r + 1] = v * ca + z * sa;
        out[r + 2] = z * ca - v * sa;
        out[r + 3] = p + a * u + d * z;
    }
    out[12] = 0.0;
    out[13] = 0.0;
    out[14] = 0.0;
    out[15] = 1.0;
}

int arm_link_frames(const arm_model *m, const double q[ARM_NJ], double T[ARM_NJ + 1][16])
{
    arm_joint_cs cs;
    int i;
    if (!T || arm_joint_cs_eval(m, q, &cs) != 0)
        return ARM_MODEL_ERR_ARG;
    if (m->structure == ARM_STRUCTURE_PUMA) {
        arm_puma_chain(m, &cs, T);
        return 0;
    }
    arm_base_frame(m, T[0]);
    for (i = 0; i < ARM_NJ; i++)
        arm_dh_compose(m, i, cs.c[i], cs.s[i], T[i], T[i + 1]);
    return 0;
}

/* cartctl: operational-space computed torque (docs/method/carry.md §3, the feedback
 * linearisation below eq. 6): tool acceleration -> qdd through a damped
 * SVD inverse of the Jacobian, bounded by the joint-range barrier -> tau
 * by RNE. See cartctl.h. */
#include "cartctl.h"

#include <math.h>
#include <string.h>

#include "arm_puma_internal.h"
#include "jointctl.h"
#include "linalg.h"
#include "vec3.h"

#define RANGE_MARGIN_DEFAULT_RAD 0.017453293 /* 1 deg */
#define SINGULAR (-1)                        /* inverse6: zero pivot; the SVD path takes over */

void cartctl_gains_default(cartctl_gains *g)
{
    g->kp_rot = 100.0;
    g->kv_rot = 20.0;
    g->lambda_max = 0.003;
    g->sigma_band = 0.003;
    g->k_null = 5.0;
    g->range_margin_rad = RANGE_MARGIN_DEFAULT_RAD;
    g->range_w_radps = 20.0;
}

int cartctl_gains_validate(const cartctl_gains *g)
{
    return (g && isfinite(g->kp_rot) && isfinite(g->kv_rot) && isfinite(g->lambda_max) &&
            isfinite(g->sigma_band) && isfinite(g->k_null) && g->kp_rot >= 0.0 &&
            g->kv_rot >= 0.0 && g->lambda_max >= 0.0 && g->sigma_band >= 0.0 && g->k_null >= 0.0 &&
            isfinite(g->range_margin_rad) && isfinite(g->range_w_radps) &&
            g->range_margin_rad >= 0.0 && g->range_w_radps >= 0.0)
               ? 0
               : CARTCTL_ERR_ARG;
}

/* head + row[2] qd[2] + ... + row[5] qd[5], summed in that order */
static inline double row_tail(const double *row, const double qd[ARM_NJ], double head)
{
    return head + row[2] * qd[2] + row[3] * qd[3] + row[4] * qd[4] + row[5] * qd[5];
}

/* twist = J qd for the PUMA's Jacobian (arm_puma_jacobian): its first
 * column is (., ., 0, 0, 0, 1) exactly, and those products are left out
 * (0 + x = x, 1 x = x: the bits of linalg_matvec, summed in its order);
 * row by row, no loop. */
static void puma_twist(const double J[36], const double qd[ARM_NJ], double twist[6])
{
    twist[0] = row_tail(J, qd, J[0] * qd[0] + J[1] * qd[1]);
    twist[1] = row_tail(J + 6, qd, J[6] * qd[0] + J[7] * qd[1]);
    twist[2] = row_tail(J + 12, qd, J[13] * qd[1]);
    twist[3] = row_tail(J + 18, qd, J[19] * qd[1]);
    twist[4] = row_tail(J + 24, qd, J[25] * qd[1]);
    twist[5] = row_tail(J + 30, qd, qd[0] + J[31] * qd[1]);
}

/* The general arm's state: the kinematics pass of arm_kin.c, copied. */
static int state_general(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                         const double qd[ARM_NJ], cartctl_state *s)
{
    arm_kin_pass k;
    /* q is checked finite by arm_kin_eval, qd by arm_kin_jdot_qd */
    if (arm_kin_eval(m, tool, q, &k) != 0 || arm_kin_jdot_qd(&k, qd, s->jdqd) != 0)
        return CARTCTL_ERR_ARG;
    memcpy(s->T, k.T, sizeof s->T);
    memcpy(s->J, k.J, sizeof s->J);
    s->cs = k.cs;
    s->has_wrist = 0;
    vec3_set(s->wrist_m, k.F[4][3], k.F[4][7], k.F[4][11]);
    linalg_matvec(s->twist, s->J, qd, 6, ARM_NJ);
    return 0;
}

int cartctl_state_at(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                     const double qd[ARM_NJ], cartctl_state *s)
{
    if (!m || !q || !qd || !s)
        return CARTCTL_ERR_ARG;
    if (m->structure != ARM_STRUCTURE_PUMA)
        return state_general(m, tool, q, qd, s);
    /* the PUMA: one pass into s, no copies (docs/method/puma.md §3a);
     * q is checked finite by arm_joint_cs_eval */
    if (arm_joint_cs_eval(m, q, &s->cs) != 0 || !linalg_all_finite(qd, ARM_NJ))
        return CARTCTL_ERR_ARG;
    arm_puma_cycle_kin(m, &s->cs, tool, qd, s->T, s->J, s->jdqd, s->wrist_m);
    s->has_wrist = 1;
    puma_twist(s->J, qd, s->twist);
    return 0;
}

int cartctl_jdot_qd(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                    const double qd[ARM_NJ], double jdqd[6])
{
    cartctl_state s;
    if (!jdqd || cartctl_state_at(m, tool, q, qd, &s) != 0)
        return CARTCTL_ERR_ARG;
    memcpy(jdqd, s.jdqd, sizeof s.jdqd);
    return 0;
}

/* log(R_d R^T) with row j of R at R + stride j: a 3x3 (stride 3) or the
 * rotation of a 4x4 pose read in place (stride 4, no copy). */
static void rot_error_rows(const double R_d[9], const double *R, int stride, double err[3])
{
    double E[9], axis[3], angle;
    int i;
    for (i = 0; i < 3; i++) { /* E = R_d R^T, the transpose read in place */
        const double *Rd_i = R_d + 3 * i;
        E[3 * i] = vec3_dot(Rd_i, R);
        E[3 * i + 1] = vec3_dot(Rd_i, R + stride);
        E[3 * i + 2] = vec3_dot(Rd_i, R + 2 * stride);
    }
    angle = rot_to_axis_angle(axis, E);
    vec3_scale(err, axis, angle);
}

void cartctl_rot_error(const double R_d[9], const double R[9], double err[3])
{
    rot_error_rows(R_d, R, 3, err);
}

/* lambda^2 of the damped inverse for the smallest singular value. */
static double damping_sq(const cartctl_gains *g, double s_min)
{
    double r;
    if (g->sigma_band <= 0.0 || s_min >= g->sigma_band)
        return 0.0;
    r = s_min / g->sigma_band;
    return g->lambda_max * g->lambda_max * (1.0 - r * r);
}

/* Gauss-Jordan inverse of a 6x6 matrix with partial pivoting. 0, or
 * SINGULAR on a zero pivot. */
static int inverse6(const double A[36], double Ai[36])
{
    double M[36];
    int i, j, k;
    memcpy(M, A, sizeof M);
    linalg_identity(Ai, 6);
    for (k = 0; k < 6; k++) {
        int p = k;
        double piv, inv;
        for (i = k + 1; i < 6; i++)
            if (fabs(M[i * 6 + k]) > fabs(M[p * 6 + k]))
                p = i;
        if (M[p * 6 + k] == 0.0)
            return SINGULAR;
        if (p != k)
            for (j = 0; j < 6; j++) {
                double t = M[k * 6 + j];
                M[k * 6 + j] = M[p * 6 + j];
                M[p * 6 + j] = t;
                t = Ai[k * 6 + j];
                Ai[k * 6 + j] = Ai[p * 6 + j];
                Ai[p * 6 + j] = t;
            }
        piv = M[k * 6 + k];
        inv = 1.0 / piv;
        for (j = 0; j < 6; j++) {
            M[k * 6 + j] *= inv;
            Ai[k * 6 + j] *= inv;
        }
        for (i = 0; i < 6; i++) {
            const double f = M[i * 6 + k];
            if (i == k || f == 0.0)
                continue;
            for (j = 0; j < 6; j++) {
                M[i * 6 + j] -= f * M[k * 6 + j];
                Ai[i * 6 + j] -= f * Ai[k * 6 + j];
            }
        }
    }
    return 0;
}

/* Lower bound on sigma_min(J) from Ji = J^-1: with B = Ji Ji^T, whose
 * eigenvalues are 1/s_i^2, ||B||_F = sqrt(sum s_i^-4) >= 1/s_min^2, so
 * s_min >= ||B||_F^(-1/2). Tight (to a factor 6^(1/4) at worst) and in
 * practice within a few % when one singular value is well below the
 * others, as at the PUMA's wrist. */
static double sigma_min_lower(const double Ji[36])
{
    double B[36], f2 = 0.0;
    int i;
    linalg_mul_t(B, Ji, Ji, 6, 6, 6);
    for (i = 0; i < 36; i++)
        f2 += B[i] * B[i];
    /* 1/sqrt(sqrt()) rather than pow(f2, -0.25): pow traps to the 68040's
     * FP software package (log and exp), sqrt does not */
    return f2 > 0.0 ? 1.0 / sqrt(sqrt(f2)) : 0.0;
}

/* Ai = A^-1 of a 3x3 by its adjugate: 0, or SINGULAR. */
static int inverse3(const double A[9], double Ai[9])
{
    const double c0 = A[4] * A[8] - A[5] * A[7], c1 = A[5] * A[6] - A[3] * A[8];
    const double c2 = A[3] * A[7] - A[4] * A[6];
    const double det = A[0] * c0 + A[1] * c1 + A[2] * c2;
    double inv;
    if (det == 0.0 || !isfinite(det))
        return SINGULAR;
    inv = 1.0 / det;
    Ai[0] = c0 * inv;
    Ai[1] = (A[2] * A[7] - A[1] * A[8]) * inv;
    Ai[2] = (A[1] * A[5] - A[2] * A[4]) * inv;
    Ai[3] = c1 * inv;
    Ai[4] = (A[0] * A[8] - A[2] * A[6]) * inv;
    Ai[5] = (A[2] * A[3] - A[0] * A[5]) * inv;
    Ai[6] = c2 * inv;
    Ai[7] = (A[1] * A[6] - A[0] * A[7]) * inv;
    Ai[8] = (A[0] * A[4] - A[1] * A[3]) * inv;
    return 0;
}

/* J^-1 for an arm whose last three axes meet at the wrist centre w
 * (docs/method/puma.md §6). With r = p - w (p the tool point of T), the
 * wrist centre's velocity v + r x w_ang makes the Jacobian block
 * triangular, Q J = [A 0; B C], Q = [I [r]x; 0 I], so
 * J^-1 = [A^-1 0; D C^-1] Q, D = -C^-1 B A^-1: two 3x3 inverses and two
 * 3x3 products instead of a 6x6 elimination. The blocks are kept apart,
 * in one array (the cycle keeps them in the SVD's workspace, dead until
 * then): the cycle applies them to one vector (wrist_solve) and never
 * forms the 6x6. */
enum { WB_R = 0, WB_AI = 3, WB_CI = 12, WB_D = 21, WB_N = 30 };

/* A = J_v,123 + [r]x J_w,123 and CB = C^-1 J_w,123 of any Jacobian with a
 * spherical wrist (cartctl_inverse_wrist). */
static void wrist_a_cb_general(const double J[36], const double r[3], const double Ci[9],
                               double A[9], double CB[9])
{
    int i, j;
    for (j = 0; j < 3; j++) {
        const double wx = J[18 + j], wy = J[24 + j], wz = J[30 + j]; /* column j, angular */
        A[j] = J[j] + r[1] * wz - r[2] * wy;
        A[3 + j] = J[6 + j] + r[2] * wx - r[0] * wz;
        A[6 + j] = J[12 + j] + r[0] * wy - r[1] * wx;
    }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            CB[3 * i + j] = Ci[3 * i] * J[18 + j] + Ci[3 * i + 1] * J[24 + j] +
                            Ci[3 * i + 2] * J[30 + j];
}

/* The same for the PUMA's Jacobian (arm_puma_jacobian), whose first three
 * axes are z0 = e_z and z1 = z2 = (s1, -c1, 0) exactly: the products with
 * those zeros and ones are left out (x + 0 = x, 1 x = x: the same bits,
 * docs/method/puma.md §6), and CB's columns 2 and 3 are one. */
/* A row of C^-1 B for the PUMA: (ci . e_z, ci . z1, ci . z1), z1 = (zx, zy, 0) */
static inline void cb_row(const double ci[3], double zx, double zy, double cb[3])
{
    cb[0] = ci[2];
    cb[1] = ci[0] * zx + ci[1] * zy;
    cb[2] = cb[1];
}

static void wrist_a_cb_puma(const double J[36], const double r[3], const double Ci[9], double A[9],
                            double CB[9])
{
    const double zx = J[19], zy = J[25], r2y = r[2] * zy, r2x = r[2] * zx;
    const double r0y = r[0] * zy, r1x = r[1] * zx;
    A[0] = J[0] + r[1];
    A[3] = J[6] - r[0];
    A[6] = J[12];
    A[1] = J[1] - r2y;
    A[2] = J[2] - r2y;
    A[4] = J[7] + r2x;
    A[5] = J[8] + r2x;
    A[7] = J[13] + r0y - r1x;
    A[8] = J[14] + r0y - r1x;
    cb_row(Ci, zx, zy, CB);
    cb_row(Ci + 3, zx, zy, CB + 3);
    cb_row(Ci + 6, zx, zy, CB + 6);
}

/* C^-1 of the PUMA's wrist in closed form (docs/method/puma.md §6): C's
 * columns z3, z4, z5 (J's angular rows, columns 4-6) are those of frames
 * 3-5, with z3 = y4 and z4 orthogonal to both others, so C^-1 has the
 * rows x5 / s5, z4 and -x4 / s5, x4 = z3 x z4, x5 = z5 x z4, s5 = sin q5
 * (det C = -s5): two cross products and a reciprocal instead of the
 * adjugate's nine cofactors and determinant. 0, or SINGULAR (s5 = 0). */
static int wrist_c_inverse_puma(const double J[36], double s5, double Ci[9])
{
    const double z3[3] = { J[21], J[27], J[33] }, z4[3] = { J[22], J[28], J[34] };
    const double z5[3] = { J[23], J[29], J[35] };
    double inv;
    if (s5 == 0.0)
        return SINGULAR;
    inv = 1.0 / s5;
    vec3_cross(Ci, z5, z4);
    vec3_scale(Ci, Ci, inv);
    vec3_copy(Ci + 3, z4);
    vec3_cross(Ci + 6, z4, z3);
    vec3_scale(Ci + 6, Ci + 6, inv);
    return 0;
}

/* b[WB_N]: r, A^-1, C^-1, D; puma_cs: J is the PUMA's at the joint sines
 * and cosines puma_cs (wrist_c_inverse_puma, wrist_a_cb_puma), NULL: any
 * spherical wrist. 0, or CARTCTL_ERR_SINGULAR (A or C singular: the arm
 * at its elbow or wrist singularity). */
static int wrist_blocks(const double J[36], const double T[16], const double w[3],
                        const arm_joint_cs *puma_cs, double b[WB_N])
{
    double A[9], CB[9];
    double *r = b + WB_R, *Ai = b + WB_AI, *Ci = b + WB_CI, *D = b + WB_D;
    int i;
    vec3_set(r, T[3] - w[0], T[7] - w[1], T[11] - w[2]);
    if (puma_cs) {
        if (wrist_c_inverse_puma(J, puma_cs->s[4], Ci) != 0)
            return CARTCTL_ERR_SINGULAR;
        wrist_a_cb_puma(J, r, Ci, A, CB);
    } else {
        double C[9];
        vec3_copy(C, J + 21);
        vec3_copy(C + 3, J + 27);
        vec3_copy(C + 6, J + 33);
        if (inverse3(C, Ci) != 0)
            return CARTCTL_ERR_SINGULAR;
        wrist_a_cb_general(J, r, Ci, A, CB);
    }
    if (inverse3(A, Ai) != 0)
        return CARTCTL_ERR_SINGULAR;
    /* row by row, D_i = -(CB_i A^-1) = -(A^-T CB_i): no temporary copy */
    for (i = 0; i < 3; i++) {
        double *Di = D + 3 * i;
        rot_tapply(Di, Ai, CB + 3 * i);
        vec3_set(Di, -Di[0], -Di[1], -Di[2]);
    }
    return 0;
}

/* Row a of a block times [r]x: a^T [r]x = (a x r)^T. */
static void row_times_rx(const double a[3], const double r[3], double out[3])
{
    out[0] = a[1] * r[2] - a[2] * r[1];
    out[1] = a[2] * r[0] - a[0] * r[2];
    out[2] = a[0] * r[1] - a[1] * r[0];
}

/* x = J^-1 y from the blocks: u = y_v + r x y_w, x_123 = A^-1 u,
 * x_456 = D u + C^-1 y_w. Returns ||J^-1||_F^2, from the blocks too:
 * the rows a of A^-1 [r]x have |a x r|^2 = |a|^2 |r|^2 - (a.r)^2, the
 * rows of D [r]x + C^-1 are formed (3 cross products). */
static double wrist_solve(const double b[WB_N], const double y[6], double x[6])
{
    const double *r = b + WB_R, *yw = y + 3;
    const double rr = vec3_dot(r, r);
    double u[3], f2 = 0.0;
    int i;
    vec3_cross(u, r, yw);
    vec3_add(u, u, y);
    for (i = 0; i < 3; i++) {
        const double *a = b + WB_AI + 3 * i, *d = b + WB_D + 3 * i, *c = b + WB_CI + 3 * i;
        const double aa = vec3_dot(a, a), ar = vec3_dot(a, r);
        double e[3];
        row_times_rx(d, r, e);
        vec3_add(e, e, c);
        x[i] = vec3_dot(a, u);
        x[3 + i] = vec3_dot(d, u) + vec3_dot(c, yw);
        f2 += aa * (1.0 + rr) - ar * ar + vec3_dot(d, d) + vec3_dot(e, e);
    }
    return f2;
}

int cartctl_inverse_wrist(const double J[36], const double T[16], const double w[3], double Ji[36])
{
    double b[WB_N];
    int i, k;
    if (!J || !T || !w || !Ji || !linalg_all_finite(J, 36) || !linalg_all_finite(T, 16) ||
        !linalg_all_finite(w, 3))
        return CARTCTL_ERR_ARG;
    if (wrist_blocks(J, T, w, NULL, b) != 0)
        return CARTCTL_ERR_SINGULAR;
    for (k = 0; k < 6; k++) { /* column k: J^-1 e_k */
        double e[6] = { 0, 0, 0, 0, 0, 0 }, x[6];
        e[k] = 1.0;
        (void)wrist_solve(b, e, x);
        for (i = 0; i < 6; i++)
            Ji[6 * i + k] = x[i];
    }
    return 0;
}

/* The fast path's exact solve (lambda = 0): qdd = J^-1 rhs and a lower
 * bound on sigma_min(J) in *s_lo. For a spherical wrist the blocks above
 * and s_min >= 1/||J^-1||_F (||.||_2 <= ||.||_F: looser than
 * sigma_min_lower by up to sqrt 6 when the singular values are alike,
 * within 0.2 % near the wrist singularity where one is far below the
 * others and the bound matters); otherwise inverse6 and sigma_min_lower.
 * work: 36 doubles of the caller's (the SVD's, dead until then), so that
 * the cycle's deepest stack holds no second 6x6. 0, or SINGULAR (the SVD
 * path decides). */
static int exact_solve(const cartctl_state *s, const double rhs[6], double qdd[6], double *s_lo,
                       double work[36])
{
    if (s->has_wrist) {
        double f2;
        if (wrist_blocks(s->J, s->T, s->wrist_m, &s->cs, work) != 0)
            return SINGULAR;
        f2 = wrist_solve(work, rhs, qdd);
        *s_lo = f2 > 0.0 ? 1.0 / sqrt(f2) : 0.0;
    } else {
        if (inverse6(s->J, work) != 0)
            return SINGULAR;
        *s_lo = sigma_min_lower(work);
        linalg_matvec(qdd, work, rhs, 6, 6);
    }
    return 0;
}

/* Bounds of the range barrier on qdd (see cartctl.h), finite only within
 * the band of a range end. Returns 1 if qdd leaves them (the barrier has
 * work), 0 if it does not: then range_resolve would hold nothing. */
static int range_bounds(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                        const double qd[ARM_NJ], const double qdd[ARM_NJ], double lo[ARM_NJ],
                        double hi[ARM_NJ])
{
    const double w = g->range_w_radps;
    int i, leaves = 0;
    for (i = 0; i < ARM_NJ; i++) {
        const double d_lo = q[i] - (m->q_min_rad[i] + g->range_margin_rad);
        const double d_hi = (m->q_max_rad[i] - g->range_margin_rad) - q[i];
        lo[i] = -HUGE_VAL;
        hi[i] = HUGE_VAL;
        if (d_lo + g->range_margin_rad < CARTCTL_RANGE_BAND_RAD) {
            lo[i] = -w * w * d_lo - 2.0 * w * qd[i];
            leaves |= qdd[i] < lo[i];
        }
        if (d_hi + g->range_margin_rad < CARTCTL_RANGE_BAND_RAD) {
            hi[i] = w * w * d_hi - 2.0 * w * qd[i];
            leaves |= qdd[i] > hi[i];
        }
    }
    return leaves;
}

/* Holds the joints that leave their bounds (worst first) at the bound and
 * re-solves the free ones for J qdd = rhs, weighted least squares with
 * damping mu2. Returns the held joints' bits. */
static unsigned range_resolve(const double J[36], const double rhs[6], const double lo[ARM_NJ],
                              const double hi[ARM_NJ], double mu2, double qdd[ARM_NJ])
{
    unsigned held = 0;
    int pass;
    for (pass = 0; pass < ARM_NJ; pass++) {
        /* A holds the weighted free columns, then (dead after N and r) the
         * Cholesky factor: one 6x6 less on the cycle's deepest stack path */
        double A[6 * ARM_NJ], N[ARM_NJ * ARM_NJ], b[6], r[ARM_NJ], x[ARM_NJ];
        double excess = 0.0;
        int idx[ARM_NJ], nf = 0, worst = -1, i, j, k;
        for (i = 0; i < ARM_NJ; i++) {
            const double e = qdd[i] < lo[i] ? lo[i] - qdd[i]
                                            : (qdd[i] > hi[i] ? qdd[i] - hi[i] : 0.0);
            if (!(held & (1u << i)) && e > excess) {
                excess = e;
                worst = i;
            }
        }
        if (worst < 0)
            break;
        held |= 1u << worst;
        qdd[worst] = qdd[worst] < lo[worst] ? lo[worst] : hi[worst];
        for (i = 0; i < ARM_NJ; i++)
            if (!(held & (1u << i)))
                idx[nf++] = i;
        if (nf == 0)
            break;
        for (k = 0; k < 6; k++) {
            const double wk = k < 3 ? 1.0 : CARTCTL_RANGE_ROT_WEIGHT_M;
            double bk = rhs[k];
            for (i = 0; i < ARM_NJ; i++)
                if (held & (1u << i))
                    bk -= J[k * 6 + i] * qdd[i];
            b[k] = wk * bk;
            for (j = 0; j < nf; j++)
                A[k * nf + j] = wk * J[k * 6 + idx[j]];
        }
        linalg_tmul(N, A, A, 6, nf, nf);
        linalg_tmatvec(r, A, b, 6, nf);
        for (j = 0; j < nf; j++)
            N[j * nf + j] += mu2;
        if (linalg_cholesky(A, N, nf) != 0)
            break; /* the free joints keep their unconstrained values */
        linalg_cholesky_solve(x, A, r, nf);
        for (j = 0; j < nf; j++)
            qdd[idx[j]] = x[j];
    }
    return held;
}

/* The range barrier on out->qdd (J qdd = rhs solved before, its result
 * checked finite by the caller), then the finiteness check of what the
 * barrier re-solved: 0 / -1. */
static int qdd_finish(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                      const double qd[ARM_NJ], const double J[36], const double rhs[6],
                      cartctl_out *out)
{
    double lo[ARM_NJ], hi[ARM_NJ];
    if (!(g->range_w_radps > 0.0) || !range_bounds(m, g, q, qd, out->qdd, lo, hi))
        return 0;
    out->range_limited = range_resolve(J, rhs, lo, hi, g->lambda_max * g->lambda_max + 1e-12,
                                       out->qdd);
    return linalg_all_finite(out->qdd, ARM_NJ) ? 0 : CARTCTL_ERR_ARG;
}

/* cartctl_qdd with the kinematics s given (out zeroed by the caller).
 * Kept apart from the wrappers that evaluate s, so that the worst-case
 * stack holds one kinematics pass, not one per wrapper. */
static int qdd_at(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                  const double qd[ARM_NJ], const cartctl_state *s, const double a_lin[3],
                  const double R_d[9], cartctl_out *out)
{
    double U[36], sv[6], V[36], rhs[6], y[6], Vtqd[6], lam2, s_lo;
    int i, k;
    if (!m || !q || !qd || cartctl_gains_validate(g) != 0 || !a_lin ||
        !linalg_all_finite(a_lin, 3) || (R_d && !linalg_all_finite(R_d, 9)))
        return CARTCTL_ERR_ARG;
    vec3_copy(out->a_cmd, a_lin);
    if (R_d) {
        rot_error_rows(R_d, s->T, 4, out->rot_err);
        for (i = 0; i < 3; i++)
            out->a_cmd[3 + i] = g->kp_rot * out->rot_err[i] - g->kv_rot * s->twist[3 + i];
    }
    vec3_sub(rhs, out->a_cmd, s->jdqd);
    vec3_sub(rhs + 3, out->a_cmd + 3, s->jdqd + 3);
    /* Fast path: when sigma_min >= sigma_band for sure, lambda = 0 and the
     * damped inverse is the exact inverse (P = 0): the wrist's blocks or
     * one 6x6 inverse instead of the SVD (about 7x cheaper). Otherwise, or
     * if J is singular, the SVD below decides. */
    if (exact_solve(s, rhs, out->qdd, &s_lo, U) == 0) {
        if (g->sigma_band <= 0.0 ? s_lo > 0.0 : s_lo >= g->sigma_band) {
            out->sigma_min = s_lo;
            out->lambda = 0.0;
            if (linalg_all_finite(out->qdd, ARM_NJ))
                return qdd_finish(m, g, q, qd, s->J, rhs, out);
        }
    }
    linalg_svd(U, sv, V, s->J, 6, 6);
    out->sigma_min = sv[5];
    lam2 = damping_sq(g, sv[5]);
    out->lambda = sqrt(lam2);
    /* qdd = V diag(s/(s^2+l^2)) U^T rhs - k_null V diag(l^2/(s^2+l^2)) V^T qd */
    linalg_tmatvec(y, U, rhs, 6, 6);
    linalg_tmatvec(Vtqd, V, qd, 6, 6);
    for (k = 0; k < 6; k++) {
        const double den = sv[k] * sv[k] + lam2;
        y[k] = den > 0.0 ? (sv[k] * y[k] - g->k_null * lam2 * Vtqd[k]) / den : 0.0;
    }
    linalg_matvec(out->qdd, V, y, 6, 6);
    if (!linalg_all_finite(out->qdd, ARM_NJ))
        return CARTCTL_ERR_ARG;
    return qdd_finish(m, g, q, qd, s->J, rhs, out);
}

int cartctl_qdd(const arm_model *m, const arm_tool *tool, const cartctl_gains *g,
                const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s,
                const double a_lin[3], const double R_d[9], cartctl_out *out)
{
    cartctl_state s_local;
    if (!out)
        return CARTCTL_ERR_ARG;
    memset(out, 0, sizeof *out);
    if (!s) {
        if (cartctl_state_at(m, tool, q, qd, &s_local) != 0)
            return CARTCTL_ERR_ARG;
        s = &s_local;
    }
    return qdd_at(m, g, q, qd, s, a_lin, R_d, out);
}

int cartctl_torque_at(const arm_model *m, const arm_payload *payload, const cartctl_gains *g,
                      const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s,
                      const double a_lin[3], const double R_d[9], double tau_Nm[ARM_NJ],
                      cartctl_out *out)
{
    if (!tau_Nm || !out)
        return CARTCTL_ERR_ARG;
    memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
    memset(out, 0, sizeof *out);
    if (!s || qdd_at(m, g, q, qd, s, a_lin, R_d, out) != 0)
        return CARTCTL_ERR_ARG;
    if (arm_rne_cs_unchecked(m, &s->cs, qd, out->qdd, NULL, payload, tau_Nm) != 0) {
        memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
        return CARTCTL_ERR_ARG;
    }
    out->saturated = jointctl_saturate(m, tau_Nm);
    return 0;
}

int cartctl_torque(const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                   const cartctl_gains *g, const double q[ARM_NJ], const double qd[ARM_NJ],
                   const cartctl_state *s, const double a_lin[3], const double R_d[9],
                   double tau_Nm[ARM_NJ], cartctl_out *out)
{
    cartctl_out local;
    cartctl_state s_local;
    if (!tau_Nm)
        return CARTCTL_ERR_ARG;
    if (!s) {
        if (cartctl_state_at(m, tool, q, qd, &s_local) != 0) {
            memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
            if (out)
                memset(out, 0, sizeof *out);
            return CARTCTL_ERR_ARG;
        }
        s = &s_local;
    }
    return cartctl_torque_at(m, payload, g, q, qd, s, a_lin, R_d, tau_Nm, out ? out : &local);
}

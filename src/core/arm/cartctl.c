/* cartctl: operational-space computed torque (docs/method/carry.md §3, the feedback
 * linearisation below eq. 6): tool acceleration -> qdd through a damped
 * SVD inverse of the Jacobian, bounded by the joint-range barrier -> tau
 * by RNE. See cartctl.h. */
#include "cartctl.h"

#include <math.h>
#include <string.h>

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

int cartctl_state_at(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                     const double qd[ARM_NJ], cartctl_state *s)
{
    arm_kin_pass k;
    if (!m || !q || !qd || !s || !linalg_all_finite(q, ARM_NJ) || !linalg_all_finite(qd, ARM_NJ))
        return CARTCTL_ERR_ARG;
    if (arm_kin_eval(m, tool, q, &k) != 0 || arm_kin_jdot_qd(&k, qd, s->jdqd) != 0)
        return CARTCTL_ERR_ARG;
    memcpy(s->T, k.T, sizeof s->T);
    memcpy(s->J, k.J, sizeof s->J);
    s->cs = k.cs;
    s->has_wrist = m->structure == ARM_STRUCTURE_PUMA;
    vec3_set(s->wrist_m, k.F[4][3], k.F[4][7], k.F[4][11]);
    linalg_matvec(s->twist, s->J, qd, 6, ARM_NJ);
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

void cartctl_rot_error(const double R_d[9], const double R[9], double err[3])
{
    double Rt[9], E[9], axis[3], angle;
    rot_transpose(Rt, R);
    rot_mul(E, R_d, Rt);
    angle = rot_to_axis_angle(axis, E);
    vec3_scale(err, axis, angle);
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

/* Ji = J^-1 for an arm whose last three axes meet at the wrist centre w
 * (docs/method/puma.md §6). With r = p - w (p the tool point of T), the wrist centre's velocity
 * v + r x w_ang makes the Jacobian block triangular, Q J = [A 0; B C],
 * Q = [I [r]x; 0 I], so J^-1 = [A^-1 0; -C^-1 B A^-1 C^-1] Q: two 3x3
 * inverses and three 3x3 products instead of a 6x6 elimination. 0, or
 * CARTCTL_ERR_SINGULAR (A or C singular: the arm at its elbow or wrist
 * singularity). Two callers (qdd_at, with its inputs already checked, and
 * the public cartctl_inverse_wrist) keep it out of qdd_at's frame, which
 * is on the cycle's deepest stack path. */
static int inverse_wrist(const double J[36], const double T[16], const double w[3], double Ji[36])
{
    double r[3], A[9], B[9], C[9], Ai[9], Ci[9], D[9], Ar[9], Dr[9];
    int i, j;
    vec3_set(r, T[3] - w[0], T[7] - w[1], T[11] - w[2]);
    for (j = 0; j < 3; j++) {
        const double wx = J[18 + j], wy = J[24 + j], wz = J[30 + j]; /* column j, angular */
        A[j] = J[j] + r[1] * wz - r[2] * wy;
        A[3 + j] = J[6 + j] + r[2] * wx - r[0] * wz;
        A[6 + j] = J[12 + j] + r[0] * wy - r[1] * wx;
        for (i = 0; i < 3; i++) {
            B[3 * i + j] = J[18 + 6 * i + j];
            C[3 * i + j] = J[18 + 6 * i + 3 + j];
        }
    }
    if (inverse3(A, Ai) != 0 || inverse3(C, Ci) != 0)
        return CARTCTL_ERR_SINGULAR;
    /* D = -C^-1 B A^-1 */
    {
        double CB[9];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                CB[3 * i + j] = Ci[3 * i] * B[j] + Ci[3 * i + 1] * B[3 + j] +
                                Ci[3 * i + 2] * B[6 + j];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                D[3 * i + j] = -(CB[3 * i] * Ai[j] + CB[3 * i + 1] * Ai[3 + j] +
                                 CB[3 * i + 2] * Ai[6 + j]);
    }
    /* M [r]x row by row; [r]x's columns are (0, r2, -r1), (-r2, 0, r0),
     * (r1, -r0, 0) */
    for (i = 0; i < 3; i++) {
        const double *a = Ai + 3 * i, *d = D + 3 * i;
        Ar[3 * i] = r[2] * a[1] - r[1] * a[2];
        Ar[3 * i + 1] = r[0] * a[2] - r[2] * a[0];
        Ar[3 * i + 2] = r[1] * a[0] - r[0] * a[1];
        Dr[3 * i] = r[2] * d[1] - r[1] * d[2];
        Dr[3 * i + 1] = r[0] * d[2] - r[2] * d[0];
        Dr[3 * i + 2] = r[1] * d[0] - r[0] * d[1];
    }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            Ji[6 * i + j] = Ai[3 * i + j];
            Ji[6 * i + 3 + j] = Ar[3 * i + j];
            Ji[18 + 6 * i + j] = D[3 * i + j];
            Ji[18 + 6 * i + 3 + j] = Dr[3 * i + j] + Ci[3 * i + j];
        }
    return 0;
}

int cartctl_inverse_wrist(const double J[36], const double T[16], const double w[3], double Ji[36])
{
    if (!J || !T || !w || !Ji || !linalg_all_finite(J, 36) || !linalg_all_finite(T, 16) ||
        !linalg_all_finite(w, 3))
        return CARTCTL_ERR_ARG;
    return inverse_wrist(J, T, w, Ji);
}

/* Lower bound on sigma_min(J) from Ji = J^-1: ||Ji||_2 <= ||Ji||_F, so
 * s_min >= 1/||Ji||_F. Looser than sigma_min_lower by up to sqrt 6 when
 * the singular values are alike, within 0.2 % near the wrist singularity
 * where one is far below the others and the bound matters. */
static double sigma_min_lower_frobenius(const double Ji[36])
{
    double f2 = 0.0;
    int i;
    for (i = 0; i < 36; i++)
        f2 += Ji[i] * Ji[i];
    return f2 > 0.0 ? 1.0 / sqrt(f2) : 0.0;
}

/* Bounds of the range barrier on qdd (see cartctl.h). */
static void range_bounds(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                         const double qd[ARM_NJ], double lo[ARM_NJ], double hi[ARM_NJ])
{
    const double w = g->range_w_radps;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        const double d_lo = q[i] - (m->q_min_rad[i] + g->range_margin_rad);
        const double d_hi = (m->q_max_rad[i] - g->range_margin_rad) - q[i];
        lo[i] = d_lo + g->range_margin_rad < CARTCTL_RANGE_BAND_RAD
                    ? -w * w * d_lo - 2.0 * w * qd[i]
                    : -HUGE_VAL;
        hi[i] = d_hi + g->range_margin_rad < CARTCTL_RANGE_BAND_RAD ? w * w * d_hi - 2.0 * w * qd[i]
                                                                    : HUGE_VAL;
    }
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

/* The range barrier on out->qdd (J qdd = rhs solved before), then the
 * finiteness check: 0 / -1. */
static int qdd_finish(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                      const double qd[ARM_NJ], const double J[36], const double rhs[6],
                      cartctl_out *out)
{
    if (!linalg_all_finite(out->qdd, ARM_NJ))
        return CARTCTL_ERR_ARG;
    if (g->range_w_radps > 0.0) {
        double lo[ARM_NJ], hi[ARM_NJ];
        range_bounds(m, g, q, qd, lo, hi);
        out->range_limited = range_resolve(J, rhs, lo, hi, g->lambda_max * g->lambda_max + 1e-12,
                                           out->qdd);
    }
    return linalg_all_finite(out->qdd, ARM_NJ) ? 0 : CARTCTL_ERR_ARG;
}

/* cartctl_qdd with the kinematics s given (out zeroed by the caller).
 * Kept apart from the wrappers that evaluate s, so that the worst-case
 * stack holds one kinematics pass, not one per wrapper. */
static int qdd_at(const arm_model *m, const cartctl_gains *g, const double q[ARM_NJ],
                  const double qd[ARM_NJ], const cartctl_state *s, const double a_lin[3],
                  const double R_d[9], cartctl_out *out)
{
    double U[36], sv[6], V[36], rhs[6], y[6], Vtqd[6], lam2;
    int i, k;
    if (!m || !q || !qd || cartctl_gains_validate(g) != 0 || !a_lin ||
        !linalg_all_finite(a_lin, 3) || (R_d && !linalg_all_finite(R_d, 9)))
        return CARTCTL_ERR_ARG;
    vec3_copy(out->a_cmd, a_lin);
    if (R_d) {
        double R[9];
        tf_rot(R, s->T);
        cartctl_rot_error(R_d, R, out->rot_err);
        for (i = 0; i < 3; i++)
            out->a_cmd[3 + i] = g->kp_rot * out->rot_err[i] - g->kv_rot * s->twist[3 + i];
    }
    for (i = 0; i < 6; i++)
        rhs[i] = out->a_cmd[i] - s->jdqd[i];
    /* Fast path: when sigma_min >= sigma_band for sure, lambda = 0 and the
     * damped inverse is the exact inverse (P = 0): one 6x6 inverse instead
     * of the SVD (about 7x cheaper). Otherwise, or if J is singular, the
     * SVD below decides. */
    if (s->has_wrist ? inverse_wrist(s->J, s->T, s->wrist_m, U) == 0 : inverse6(s->J, U) == 0) {
        const double s_lo = s->has_wrist ? sigma_min_lower_frobenius(U) : sigma_min_lower(U);
        if (g->sigma_band <= 0.0 ? s_lo > 0.0 : s_lo >= g->sigma_band) {
            linalg_matvec(out->qdd, U, rhs, 6, 6);
            out->sigma_min = s_lo;
            out->lambda = 0.0;
            if (linalg_all_finite(out->qdd, ARM_NJ))
                return qdd_finish(m, g, q, qd, s->J, rhs, out);
            memset(out->qdd, 0, sizeof out->qdd);
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

/* cartctl_torque with the kinematics s given (tau and out zeroed by the caller). */
static int torque_at(const arm_model *m, const arm_payload *payload, const cartctl_gains *g,
                     const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s,
                     const double a_lin[3], const double R_d[9], double tau_Nm[ARM_NJ],
                     cartctl_out *o)
{
    if (qdd_at(m, g, q, qd, s, a_lin, R_d, o) != 0)
        return CARTCTL_ERR_ARG;
    if (arm_rne_cs(m, &s->cs, qd, o->qdd, NULL, payload, tau_Nm) != 0) {
        memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
        return CARTCTL_ERR_ARG;
    }
    o->saturated = jointctl_saturate(m, tau_Nm);
    return 0;
}

int cartctl_torque(const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                   const cartctl_gains *g, const double q[ARM_NJ], const double qd[ARM_NJ],
                   const cartctl_state *s, const double a_lin[3], const double R_d[9],
                   double tau_Nm[ARM_NJ], cartctl_out *out)
{
    cartctl_out local;
    cartctl_out *o = out ? out : &local;
    cartctl_state s_local;
    if (!tau_Nm)
        return CARTCTL_ERR_ARG;
    memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
    memset(o, 0, sizeof *o);
    if (!s) {
        if (cartctl_state_at(m, tool, q, qd, &s_local) != 0)
            return CARTCTL_ERR_ARG;
        s = &s_local;
    }
    return torque_at(m, payload, g, q, qd, s, a_lin, R_d, tau_Nm, o);
}

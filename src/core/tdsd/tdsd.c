/* tdsd: task decomposition and speed distribution near singularities,
 * docs/method/tdsd.md (seed 002, Zhang & Fan 2016), eq. 8, 11-13:
 *   y1' = lambda p_d' + K_p e_p                  (12, time-scaled)
 *   y2' = lambda w_d  + K_o e_o                  (13)
 *   P1 = I - J1+ J1,  dq1 = J1+ y1',  dq2 = (J2P1)+ (y2' - J2 dq1),
 *   dq3 = (P1 - (J2P1)+ (J2P1)) k grad V,  dq = dq1 + Q1 dq2 + Q2 dq3 (8, 11)
 * with Q1, Q2 from the joint speed limits and lambda (path-rate factor)
 * chosen so that dq1 alone fits the limits. Resolved each cycle by the
 * L of [J1; J2] = L Q^T (docs/method/tdsd.md §3a: J1^+ = Q1 L11^-1,
 * (J2P1)^+ = Q2 L22^-1, exact while both blocks are nonsingular): from the
 * U D U^T factor of J J^T (L = U D^1/2, §3a "The Gram route") where the
 * product of the blocks' condition bounds is <= TDSD_GRAM_COND_MAX, by
 * modified Gram-Schmidt where each is <= TDSD_FAST_COND_MAX, by the SVD of
 * §3 at and near a singularity (tdsd_step_svd: that path alone, the oracle).
 * Also the baselines of §6: clipped pseudo-inverse and damped-least-squares
 * resolved rate.
 * Pure computation; every matrix is a fixed-size stack array.
 */
#include "tdsd.h"
#include "linalg.h"
#include "vec3.h"
#include <math.h>
#include <stddef.h>

#define NJ TDSD_NJ
#define RATE_INFEASIBLE (-1) /* max_path_rate: no admissible lambda */

/* LINALG_ERR_NOCONV still delivers a usable (best-so-far) factorisation. */
static int la_ok(int rc)
{
    return rc == LINALG_OK || rc == LINALG_ERR_NOCONV;
}

static void rot_col(double c[3], const double R[9], int j)
{
    c[0] = R[j];
    c[1] = R[3 + j];
    c[2] = R[6 + j];
}

void tdsd_orientation_error(double e_o[3], const double R_d[9], const double R[9])
{
    double acc[3] = { 0.0, 0.0, 0.0 };
    int j;
    for (j = 0; j < 3; j++) {
        double c[3], cd[3], x[3];
        rot_col(c, R, j);
        rot_col(cd, R_d, j);
        vec3_cross(x, c, cd);
        vec3_add(acc, acc, x);
    }
    vec3_scale(e_o, acc, 0.5);
}

void tdsd_axis_error(double e2[2], const double R_d[9], const double R[9])
{
    double n[3], o[3], a[3], a_d[3], x[3];
    rot_col(n, R, 0);
    rot_col(o, R, 1);
    rot_col(a, R, 2);
    rot_col(a_d, R_d, 2);
    vec3_cross(x, a, a_d);
    e2[0] = vec3_dot(n, x);
    e2[1] = vec3_dot(o, x);
}

void tdsd_axis_jacobian(double J2[2 * NJ], const double Jw[3 * NJ], const double R[9])
{
    double NO[6]; /* rows n^T, o^T */
    int j;
    for (j = 0; j < 3; j++) {
        NO[j] = R[3 * j];         /* n_j */
        NO[3 + j] = R[3 * j + 1]; /* o_j */
    }
    linalg_mul(J2, NO, Jw, 2, 3, NJ);
}

int tdsd_midrange_init(tdsd_midrange *c, const double q_min_rad[NJ], const double q_max_rad[NJ],
                       unsigned joint_mask)
{
    int i;
    c->mask = joint_mask;
    for (i = 0; i < NJ; i++) {
        c->mid_rad[i] = 0.0;
        c->k_per_rad2[i] = 0.0;
        if (!(joint_mask & (1u << i)))
            continue;
        if (!isfinite(q_min_rad[i]) || !isfinite(q_max_rad[i]) || !(q_max_rad[i] > q_min_rad[i]))
            return TDSD_ERR_ARG;
        {
            const double range = q_max_rad[i] - q_min_rad[i];
            c->mid_rad[i] = 0.5 * (q_min_rad[i] + q_max_rad[i]);
            c->k_per_rad2[i] = -2.0 / (range * range);
        }
    }
    return TDSD_OK;
}

void tdsd_midrange_grad_at(const tdsd_midrange *c, const double q_rad[NJ], double grad_V[NJ])
{
    int i;
    for (i = 0; i < NJ; i++)
        grad_V[i] = c->mask & (1u << i) ? c->k_per_rad2[i] * (q_rad[i] - c->mid_rad[i]) : 0.0;
}

int tdsd_midrange_grad(double grad_V[NJ], double *V, const double q_rad[NJ],
                       const double q_min_rad[NJ], const double q_max_rad[NJ], unsigned joint_mask)
{
    tdsd_midrange c;
    double v = 0.0;
    int i;
    for (i = 0; i < NJ; i++)
        grad_V[i] = 0.0;
    if (tdsd_midrange_init(&c, q_min_rad, q_max_rad, joint_mask) != TDSD_OK)
        return TDSD_ERR_ARG;
    for (i = 0; i < NJ; i++)
        if ((joint_mask & (1u << i)) && !isfinite(q_rad[i]))
            return TDSD_ERR_ARG;
    tdsd_midrange_grad_at(&c, q_rad, grad_V);
    for (i = 0; i < NJ; i++) /* V = sum k_i d_i^2 / 2, d = q - mid */
        v += 0.5 * grad_V[i] * (q_rad[i] - c.mid_rad[i]);
    if (V)
        *V = v;
    return TDSD_OK;
}

static int input_valid(const tdsd_input *in)
{
    int i;
    if (!linalg_all_finite(in->J1, 3 * NJ) || !linalg_all_finite(in->Jw, 3 * NJ) ||
        !linalg_all_finite(in->v_d_mps, 3) || !linalg_all_finite(in->p_d_m, 3) ||
        !linalg_all_finite(in->p_m, 3) || !linalg_all_finite(in->w_d_radps, 3) ||
        !linalg_all_finite(in->R_d, 9) || !linalg_all_finite(in->R, 9) ||
        !linalg_all_finite(in->grad_V, NJ) || !isfinite(in->k_V))
        return 0;
    if (in->orient != TDSD_ORIENT_NONE && in->orient != TDSD_ORIENT_FULL &&
        in->orient != TDSD_ORIENT_AXIS)
        return 0;
    if (!(in->K_p >= 0.0) || !isfinite(in->K_p) || !(in->K_o >= 0.0) || !isfinite(in->K_o))
        return 0;
    if (!(in->rate_cap >= 0.0) || !(in->rate_cap <= 1.0))
        return 0;
    if (!(in->pinv_rtol >= 0.0) || !(in->pinv_rtol < 1.0))
        return 0;
    for (i = 0; i < NJ; i++)
        if (!(in->dq_max_radps[i] > 0.0) || !isfinite(in->dq_max_radps[i]))
            return 0;
    return 1;
}

static void output_reset(tdsd_output *out)
{
    int i;
    for (i = 0; i < NJ; i++)
        out->dq_radps[i] = out->dq1[i] = out->dq2[i] = out->dq3[i] = 0.0;
    for (i = 0; i < 3; i++)
        out->e_p[i] = out->e_o[i] = out->y1[i] = out->y2[i] = 0.0;
    out->Q1 = out->Q2 = 0.0;
    out->lambda = 0.0;
    out->fb_scale = 1.0;
    out->time_scaled = 0;
    out->n_clipped = 0;
    out->sigma_min_J1 = out->sigma_max_J1 = 0.0;
    out->rank_J1 = out->rank_J2P1 = 0;
    out->n2 = 0;
    out->damping = 0.0;
    out->fast = TDSD_PATH_SVD;
}

/* Task 2 rows J2 (n2 x 6), error e2 and feed-forward w2 (n2), per mode:
 * *J2 is in->Jw itself (full orientation) or buf. */
static int task2_setup(const tdsd_input *in, double buf[3 * NJ], const double **J2, double e2[3],
                       double w2[3])
{
    int j;
    *J2 = buf;
    switch (in->orient) {
    case TDSD_ORIENT_FULL:
        *J2 = in->Jw;
        tdsd_orientation_error(e2, in->R_d, in->R);
        for (j = 0; j < 3; j++)
            w2[j] = in->w_d_radps[j];
        return 3;
    case TDSD_ORIENT_AXIS: {
        double n[3], o[3];
        rot_col(n, in->R, 0);
        rot_col(o, in->R, 1);
        tdsd_axis_jacobian(buf, in->Jw, in->R);
        tdsd_axis_error(e2, in->R_d, in->R);
        w2[0] = vec3_dot(n, in->w_d_radps);
        w2[1] = vec3_dot(o, in->w_d_radps);
        return 2;
    }
    default: return 0;
    }
}

/* Largest lambda in [0, cap] with |lambda a_i + b_i| <= m_i for all i.
 * Each joint admits an interval of lambda; returns 0 and sets *lambda if
 * the intersection with [0, cap] is non-empty, RATE_INFEASIBLE otherwise.
 * The interval ends are kept as fractions num / |a_i| and compared by
 * cross-multiplication (denominators > 0): one division, for the result. */
static int max_path_rate(double *lambda, const double a[NJ], const double b[NJ], const double m[NJ],
                         double cap)
{
    double lo_n = 0.0, lo_d = 1.0, hi_n = cap, hi_d = 1.0;
    int i;
    for (i = 0; i < NJ; i++) {
        if (a[i] == 0.0) {
            if (fabs(b[i]) > m[i])
                return RATE_INFEASIBLE;
            continue;
        }
        {
            const double den = fabs(a[i]);
            const double ilo = a[i] > 0.0 ? -m[i] - b[i] : b[i] - m[i];
            const double ihi = a[i] > 0.0 ? m[i] - b[i] : m[i] + b[i];
            if (ilo * lo_d > lo_n * den) {
                lo_n = ilo;
                lo_d = den;
            }
            if (ihi * hi_d < hi_n * den) {
                hi_n = ihi;
                hi_d = den;
            }
        }
    }
    if (!(lo_n * hi_d <= hi_n * lo_d))
        return RATE_INFEASIBLE;
    *lambda = hi_d == 1.0 ? hi_n : hi_n / hi_d;
    return 0;
}

/* Largest Q in [0,1] with |base_i| + Q |d_i| <= m_i for all i: the least
 * (m_i - |base_i|) / |d_i|, compared by cross-multiplication. */
static double speed_share(const double base[NJ], const double d[NJ], const double m[NJ])
{
    double num = 1.0, den = 1.0, Q;
    int i;
    for (i = 0; i < NJ; i++) {
        const double ad = fabs(d[i]);
        if (ad > 0.0) {
            const double n = m[i] - fabs(base[i]);
            if (n * den < num * ad) {
                num = n;
                den = ad;
            }
        }
    }
    Q = den == 1.0 ? num : num / den;
    return Q > 0.0 ? Q : 0.0;
}

/* Saturates each joint to +-m_i; returns how many were cut by more than
 * relative rounding (slack). */
static int clip_joints(double dq[NJ], const double m[NJ], double slack)
{
    int i, n = 0;
    for (i = 0; i < NJ; i++)
        if (fabs(dq[i]) > m[i]) {
            if (fabs(dq[i]) > m[i] * (1.0 + slack))
                n++;
            dq[i] = copysign(m[i], dq[i]);
        }
    return n;
}

/* dq1(lambda) = lambda a + c b (a = J1^+ p_d', b = J1^+ K_p e_p): the
 * largest admissible path rate, else the feedback shrunk in its own
 * direction (docs/method/tdsd.md §4). Sets dq1, y1, lambda, fb_scale,
 * time_scaled; returns c (lambda in out->lambda). */
static double path_rate_dq1(const tdsd_input *in, tdsd_output *out, const double a[NJ],
                            const double b[NJ], const double Kpe[3])
{
    double lambda = 0.0, c = 1.0;
    int i;
    if (max_path_rate(&lambda, a, b, in->dq_max_radps, in->rate_cap) != 0) {
        /* even stopping on the path leaves the feedback too fast: keep its
         * direction (the tool still heads straight for p_d), shrink it */
        lambda = 0.0;
        for (i = 0; i < NJ; i++)
            if (fabs(b[i]) * c > in->dq_max_radps[i])
                c = in->dq_max_radps[i] / fabs(b[i]);
    }
    for (i = 0; i < NJ; i++)
        out->dq1[i] = lambda * a[i] + c * b[i];
    for (i = 0; i < 3; i++)
        out->y1[i] = lambda * in->v_d_mps[i] + c * Kpe[i];
    out->lambda = lambda;
    out->fb_scale = c;
    out->time_scaled = (lambda < in->rate_cap) || (c < 1.0);
    return c;
}

/* The task set-up both resolutions share: e_p, task 2's rows, error and
 * feed-forward, y2' follows once lambda is known. Returns n2. */
static int step_setup(const tdsd_input *in, tdsd_output *out, double buf[3 * NJ], const double **J2,
                      double e2[3], double w2[3], double Kpe[3], double g[NJ])
{
    int n2, i;
    vec3_sub(out->e_p, in->p_d_m, in->p_m);
    n2 = task2_setup(in, buf, J2, e2, w2);
    out->n2 = n2;
    for (i = 0; i < 3; i++) {
        out->e_o[i] = i < n2 ? e2[i] : 0.0;
        Kpe[i] = in->K_p * out->e_p[i];
    }
    for (i = 0; i < NJ; i++)
        g[i] = in->k_V * in->grad_V[i];
    return n2;
}

/* Speed distribution (eq. 9-11) and the exact-limit guard. */
static void step_finish(const tdsd_input *in, tdsd_output *out)
{
    int i, dq3_zero = 1;
    out->Q1 = speed_share(out->dq1, out->dq2, in->dq_max_radps);
    for (i = 0; i < NJ; i++) {
        out->dq_radps[i] = out->dq1[i] + out->Q1 * out->dq2[i];
        dq3_zero &= out->dq3[i] == 0.0;
    }
    /* dq3 = 0 (the 6-row task off a singularity): Q2 = 1 adds nothing */
    out->Q2 = 1.0;
    if (!dq3_zero) {
        out->Q2 = speed_share(out->dq_radps, out->dq3, in->dq_max_radps);
        for (i = 0; i < NJ; i++)
            out->dq_radps[i] += out->Q2 * out->dq3[i];
    }
    /* By construction |dq_i| <= dq_max_i up to rounding; the guard makes the
     * hard limit exact and counts any real violation. The slack is wide
     * because near a singularity dq1 = lambda a + b cancels two terms of
     * size ~ |y1'| / sigma_min, so its rounding is ~ DBL_EPSILON / sigma_min
     * relative (1e-7 at sigma_min = 1e-9). */
    out->n_clipped = clip_joints(out->dq_radps, in->dq_max_radps, 1e-6);
}

/* y2' = lambda w2 + K_o e2 into out->y2, and r = y2' - J2 dq1 with
 * J2 dq1 = M21 z1, z1 = lambda za + c zb (M21: the rows 3.. of the fast
 * paths' lower triangular factor, the first 3 columns). */
static void task2_residual(const tdsd_input *in, tdsd_output *out, const double (*M21)[NJ], int n2,
                           const double w2[3], const double e2[3], const double za[3],
                           const double zb[3], double c, double r[3])
{
    const double z0 = out->lambda * za[0] + c * zb[0], z1 = out->lambda * za[1] + c * zb[1],
                 z2 = out->lambda * za[2] + c * zb[2];
    int i;
    for (i = 0; i < n2; i++) {
        out->y2[i] = out->lambda * w2[i] + in->K_o * e2[i];
        r[i] = out->y2[i] - M21[i][0] * z0 - M21[i][1] * z1 - M21[i][2] * z2;
    }
}

/* ---- fast path: J = [J1; J2] = L Q^T (docs/method/tdsd.md §3a) ----
 * The rows of J (n = 3 + n2 of them) are orthonormalised in order by
 * modified Gram-Schmidt, with a second pass where the first left less than
 * a tenth of a row's norm (Kahan-Parlett, "twice is enough": one pass
 * leaves the new row orthogonal to ~ DBL_EPSILON times the ratio of the
 * norms, the second to ~ DBL_EPSILON), so Q^T's rows q_i are orthonormal
 * to ~ 10 DBL_EPSILON and L is lower triangular with J = L Q^T.
 * Block by the task split, Q = [Q1 Q2], L = [L11 0; L21 L22]:
 *   J1 = L11 Q1^T                 => J1^+ = Q1 L11^-1,   P1 = I - Q1 Q1^T
 *   J2 P1 = L22 Q2^T (Q2 _|_ Q1)  => (J2P1)^+ = Q2 L22^-1,
 *                                    (J2P1)^+(J2P1) = Q2 Q2^T
 *   J2 dq1 = L21 L11^-1 y1'        (Q1^T Q1 = I, Q2^T Q1 = 0)
 * so dq1 = Q1 L11^-1 y1', dq2 = Q2 L22^-1 (y2' - L21 z1), z1 = L11^-1 y1',
 * dq3 = g - Q Q^T g (zero when n = 6: Q is then square and orthogonal).
 * Exact whenever L11 and L22 are nonsingular, and then every singular value
 * of J1 (of J2 P1) is one of L11 (L22). The path is taken only where
 * ||L_kk||_F ||L_kk^-1||_F <= TDSD_FAST_COND_MAX for both blocks: that
 * product bounds sigma_max / sigma_min from above, so no singular value lies
 * under the SVD path's rank cut (which would drop it) and the rounding of
 * the triangular solves stays ~ DBL_EPSILON times it. Elsewhere (at and
 * near a singularity) the SVD resolution runs. */
typedef struct {
    double q[NJ][NJ]; /* q[i]: row i of Q^T */
    double L[NJ][NJ]; /* lower triangular, J = L Q^T */
    double inv[NJ];   /* 1 / L_ii */
    int n;
} lq_factor;

static inline double dot6(const double a[NJ], const double b[NJ])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
}

/* v -= c u */
static inline void sub6(double v[NJ], double c, const double u[NJ])
{
    int k;
    for (k = 0; k < NJ; k++)
        v[k] -= c * u[k];
}

/* Row i of the factor from row r of J; 0, or -1 when the row is (to
 * rounding) in the span of the rows before it. */
static int lq_row(lq_factor *f, int i, const double r[NJ])
{
    double *v = f->q[i], v2, inv;
    int j, k, pass;
    for (k = 0; k < NJ; k++)
        v[k] = r[k];
    for (j = 0; j < i; j++)
        f->L[i][j] = 0.0;
    v2 = i == 0 ? dot6(v, v) : 0.0; /* rows after the first: set by the pass */
    for (pass = 0; pass < 2 && i > 0; pass++) {
        double c2 = 0.0; /* |removed part|^2: |v_before|^2 = |v_after|^2 + c2 */
        for (j = 0; j < i; j++) {
            const double c = dot6(f->q[j], v);
            f->L[i][j] += c;
            c2 += c * c;
            sub6(v, c, f->q[j]);
        }
        v2 = dot6(v, v);
        if (v2 >= 0.01 * (v2 + c2)) /* kept at least 1/10 of the row: orthogonal */
            break;
    }
    if (!(v2 > 0.0))
        return -1;
    f->L[i][i] = sqrt(v2);
    inv = 1.0 / f->L[i][i];
    f->inv[i] = inv;
    for (k = 0; k < NJ; k++)
        v[k] *= inv;
    return 0;
}

/* x = M_kk^-1 y for the diagonal block of rows/columns off..off+k-1 of a
 * lower triangular M whose diagonal has the reciprocals dinv (NULL: unit
 * diagonal); x may be y. Both fast paths' forward substitution. */
static void lower_solve(const double (*M)[NJ], const double *dinv, int off, int k, const double *y,
                        double *x)
{
    int i, j;
    for (i = 0; i < k; i++) {
        double acc = y[i];
        for (j = 0; j < i; j++)
            acc -= M[off + i][off + j] * x[j];
        x[i] = dinv ? acc * dinv[off + i] : acc;
    }
}

/* x = L_kk^-1 y for the diagonal block of rows/columns off..off+k-1. */
static void lq_solve(const lq_factor *f, int off, int k, const double *y, double *x)
{
    lower_solve((const double(*)[NJ])f->L, f->inv, off, k, y, x);
}

/* (||L_kk||_F ||L_kk^-1||_F)^2 of a diagonal block (k <= 3): its root is
 * an upper bound on the block's condition number sigma_max / sigma_min.
 * fro2 = ||L_kk||_F^2 (sigma_max <= its root), inv2 = ||L_kk^-1||_F^2
 * (sigma_min >= 1 / its root). The inverse of a lower triangular block
 * written out: X_ii = 1 / L_ii, X_10 = -L_10 X_00 X_11,
 * X_21 = -L_21 X_11 X_22, X_20 = -(L_20 X_00 + L_21 X_10) X_22. */
static double lq_block_cond2(const lq_factor *f, int off, int k, double *fro2, double *inv2)
{
    const double(*L)[NJ] = f->L;
    const double *d = f->inv + off;
    double fro = 0.0, inv = 0.0;
    int i, c;
    for (i = 0; i < k; i++) {
        for (c = 0; c <= i; c++)
            fro += L[off + i][off + c] * L[off + i][off + c];
        inv += d[i] * d[i];
    }
    if (k >= 2) {
        const double x10 = -L[off + 1][off] * d[0] * d[1];
        inv += x10 * x10;
        if (k == 3) {
            const double x21 = -L[off + 2][off + 1] * d[1] * d[2];
            const double x20 = -(L[off + 2][off] * d[0] + L[off + 2][off + 1] * x10) * d[2];
            inv += x21 * x21 + x20 * x20;
        }
    }
    *fro2 = fro;
    *inv2 = inv;
    return fro * inv;
}

/* x = sum_{i < k} z_i q_{off+i} */
static void lq_combine(const lq_factor *f, int off, int k, const double *z, double x[NJ])
{
    int i, j;
    for (j = 0; j < NJ; j++)
        x[j] = 0.0;
    for (i = 0; i < k; i++)
        for (j = 0; j < NJ; j++)
            x[j] += z[i] * f->q[off + i][j];
}

/* Factors [J1; J2] and checks both blocks; 0 when the fast path applies. */
static int lq_factor_task(lq_factor *f, const tdsd_input *in, const double *J2, int n2,
                          tdsd_output *out)
{
    const double rtol = in->pinv_rtol > 0.0 ? in->pinv_rtol : LINALG_PINV_RTOL;
    const double cmax = rtol * TDSD_FAST_COND_MAX > 1.0 ? 1.0 / rtol : TDSD_FAST_COND_MAX;
    double fro2, inv2;
    int i;
    f->n = 3 + n2;
    for (i = 0; i < f->n; i++)
        if (lq_row(f, i, i < 3 ? in->J1 + i * NJ : J2 + (i - 3) * NJ) != 0)
            return -1;
    if (!(lq_block_cond2(f, 0, 3, &fro2, &inv2) <= cmax * cmax))
        return -1;
    out->sigma_min_J1 = 1.0 / sqrt(inv2);
    out->sigma_max_J1 = sqrt(fro2);
    if (n2 > 0 && !(lq_block_cond2(f, 3, n2, &fro2, &inv2) <= cmax * cmax))
        return -1;
    return 0;
}

static void resolve_lq(const tdsd_input *in, tdsd_output *out, const lq_factor *f, int n2,
                       const double w2[3], const double e2[3], const double Kpe[3],
                       const double g[NJ])
{
    double za[3], zb[3], a[NJ], b[NJ], c;
    int i, j;
    out->fast = TDSD_PATH_LQ;
    out->rank_J1 = 3;
    out->rank_J2P1 = n2;
    lq_solve(f, 0, 3, in->v_d_mps, za);
    lq_solve(f, 0, 3, Kpe, zb);
    lq_combine(f, 0, 3, za, a);
    lq_combine(f, 0, 3, zb, b);
    c = path_rate_dq1(in, out, a, b, Kpe);
    if (n2 > 0) {
        double r[3], z2[3];
        task2_residual(in, out, f->L + 3, n2, w2, e2, za, zb, c, r); /* J2 dq1 = L21 z1 */
        lq_solve(f, 3, n2, r, z2);
        lq_combine(f, 3, n2, z2, out->dq2);
    }
    if (f->n < NJ) { /* dq3 = g - Q Q^T g; else 0, as output_reset left it */
        for (i = 0; i < NJ; i++)
            out->dq3[i] = g[i];
        for (j = 0; j < f->n; j++)
            sub6(out->dq3, dot6(f->q[j], g), f->q[j]);
    }
}

/* ---- fast path: J J^T = U D U^T (docs/method/tdsd.md §3a) ----
 * J = [J1; J2] (n = 3 + n2 rows) has the Gram matrix G = J J^T. Its
 * factor G = U D U^T (U unit lower triangular, D diagonal > 0) gives the
 * L of the LQ factor J = L Q^T as L = U D^1/2, Q = J^T L^-T, without a
 * square root. Block by the task split, U = [U11 0; U21 U22]:
 *   U11 D1 U11^T = J1 J1^T,   U21 = J2 J1^T U11^-T D1^-1,
 *   U22 D2 U22^T = J2 J2^T - U21 D1 U21^T = (J2 P1)(J2 P1)^T  (Schur complement)
 * so L11 = U11 D1^1/2 (L22 = U22 D2^1/2) has the singular values of J1
 * (of J2 P1), and with z1 = U11^-1 y1' (J2 dq1 = U21 z1):
 *   dq1 = J1^T U11^-T D1^-1 z1                                 (= J1^+ y1')
 *   dq2 = J2^T x2 - J1^T U11^-T U21^T x2,  x2 = U22^-T D2^-1 U22^-1 (y2' - U21 z1)
 *   dq3 = g - J^T U^-T D^-1 U^-1 J g          (= g - Q Q^T g; zero when n = 6)
 * Exact whenever D > 0. The path is taken only where the product of the
 * two blocks' ||L_kk||_F ||L_kk^-1||_F is at most TDSD_GRAM_COND_MAX (and
 * 1 / pinv_rtol): each factor bounds its block's sigma_max / sigma_min from
 * above, so no singular value lies under the SVD path's rank cut. Forming
 * G squares the condition numbers: the rounding is ~ DBL_EPSILON
 * (kappa1 kappa2)^2 relative, which that bound keeps small
 * (docs/method/tdsd.md §3a, Accuracy). Beyond it the Gram-Schmidt LQ
 * (TDSD_FAST_COND_MAX per block) and, at and near a singularity, the SVD
 * resolution run. */
typedef struct {
    const double *row[NJ]; /* row i of J = [J1; J2] */
    double U[NJ][NJ];      /* unit lower triangular (below the diagonal) */
    double W[NJ][NJ];      /* W_ij = U_ij d_j */
    double d[NJ];          /* D */
    double dinv[NJ];       /* 1 / d_i */
    int n;
} gram_factor;

/* z = U_kk^-1 y for the diagonal block of rows/columns off..off+k-1 (or
 * the whole factor: off 0, k n); z may be y. */
static void gram_fwd(const gram_factor *f, int off, int k, const double *y, double *z)
{
    lower_solve((const double(*)[NJ])f->U, NULL, off, k, y, z);
}

/* x = U_kk^-T y, the same block, by back substitution; x may be y. */
static void gram_bwd(const gram_factor *f, int off, int k, const double *y, double *x)
{
    int i, j;
    for (i = k - 1; i >= 0; i--) {
        double acc = y[i];
        for (j = i + 1; j < k; j++)
            acc -= f->U[off + j][off + i] * x[j];
        x[i] = acc;
    }
}

/* x = U_kk^-T D_k^-1 U_kk^-1 y: (J_k J_k^T)^-1 y for the first block, the
 * inverse of the Schur complement for the second. */
static void gram_solve(const gram_factor *f, int off, int k, const double *y, double *x)
{
    int i;
    gram_fwd(f, off, k, y, x);
    for (i = 0; i < k; i++)
        x[i] *= f->dinv[off + i];
    gram_bwd(f, off, k, x, x);
}

/* x = U_kk^-T y for a diagonal block of k <= 3 rows at off, written out
 * in gram_bwd's order; x may be y. */
static void gram_block_bwd(const gram_factor *f, int off, int k, const double *y, double *x)
{
    const double *u1 = f->U[off + 1] + off, *u2 = f->U[off + 2] + off;
    if (k == 3) {
        x[2] = y[2];
        x[1] = y[1] - u2[1] * x[2];
        x[0] = y[0] - u1[0] * x[1] - u2[0] * x[2];
    } else if (k == 2) {
        x[1] = y[1];
        x[0] = y[0] - u1[0] * x[1];
    } else {
        x[0] = y[0];
    }
}

/* The same block: z = U_kk^-1 y, x = U_kk^-T D_k^-1 z (for the first
 * block J1^+ y = J1^T x; for the second x = (J2 P1 (J2 P1)^T)^-1 y). */
static inline void gram_block_solve(const gram_factor *f, int off, int k, const double *y,
                                    double *z, double *x)
{
    const double *d = f->dinv + off, *u1 = f->U[off + 1] + off, *u2 = f->U[off + 2] + off;
    int i;
    z[0] = y[0];
    if (k >= 2)
        z[1] = y[1] - u1[0] * z[0];
    if (k == 3)
        z[2] = y[2] - u2[0] * z[0] - u2[1] * z[1];
    for (i = 0; i < k; i++)
        x[i] = z[i] * d[i];
    gram_block_bwd(f, off, k, x, x);
}

/* v = J^T x over the first k rows of J (k = n: 3, 5 or 6), summed in row
 * order. */
static inline void gram_combine(const gram_factor *f, int k, const double *x, double v[NJ])
{
    const double *const *r = f->row;
    int j;
    for (j = 0; j < NJ; j++) {
        double acc = x[0] * r[0][j] + x[1] * r[1][j] + x[2] * r[2][j];
        if (k > 3)
            acc += x[3] * r[3][j];
        if (k > 4)
            acc += x[4] * r[4][j];
        if (k > 5)
            acc += x[5] * r[5][j];
        v[j] = acc;
    }
}

/* (||L_kk||_F ||L_kk^-1||_F)^2 of a diagonal block (k <= 3) of
 * L = U D^1/2: its root is an upper bound on the block's condition number
 * sigma_max / sigma_min. fro2 = ||L_kk||_F^2 = sum d_i + U_ic W_ic
 * (sigma_max <= its root), inv2 = ||L_kk^-1||_F^2 = sum_i (1 + sum_c X_ic^2) / d_i
 * (sigma_min >= 1 / its root), X = U_kk^-1 written out: X_10 = -U_10,
 * X_21 = -U_21, X_20 = U_21 U_10 - U_20. */
static inline double gram_block_cond2(const gram_factor *f, int off, int k, double *fro2,
                                      double *inv2)
{
    const double *d = f->d + off, *di = f->dinv + off;
    const double *u1 = f->U[off + 1] + off, *u2 = f->U[off + 2] + off;
    const double *w1 = f->W[off + 1] + off, *w2 = f->W[off + 2] + off;
    double fro = d[0], inv = di[0];
    if (k >= 2) {
        const double x10 = u1[0];
        fro += d[1];
        fro += u1[0] * w1[0];
        inv += di[1];
        if (k == 3) {
            const double x21 = u2[1], x20 = x21 * x10 - u2[0];
            fro += d[2];
            fro += u2[0] * w2[0];
            fro += u2[1] * w2[1];
            inv += di[2];
            inv += x10 * x10 * di[1];
            inv += (x21 * x21 + x20 * x20) * di[2];
        } else {
            inv += x10 * x10 * di[1];
        }
    }
    *fro2 = fro;
    *inv2 = inv;
    return fro * inv;
}

/* Forms J J^T row by row and factors it (entry (i, j) of G is formed only
 * where U's entry (i, j) is computed), then checks both blocks; 0 when the
 * product of their condition bounds is at most TDSD_GRAM_COND_MAX (and
 * 1 / rtol): each block's is then too, since each is >= 1. */
static int gram_factor_task(gram_factor *f, const tdsd_input *in, const double *J2, int n2,
                            tdsd_output *out)
{
    const double rtol = in->pinv_rtol > 0.0 ? in->pinv_rtol : LINALG_PINV_RTOL;
    const double gmax = rtol * TDSD_GRAM_COND_MAX > 1.0 ? 1.0 / rtol : TDSD_GRAM_COND_MAX;
    double fro2, inv2, fro2b, inv2b, c2;
    int i, j, k;
    f->n = 3 + n2;
    for (i = 0; i < f->n; i++) {
        f->row[i] = i < 3 ? in->J1 + i * NJ : J2 + (i - 3) * NJ;
        for (j = 0; j <= i; j++) {
            double s = dot6(f->row[i], f->row[j]);
            for (k = 0; k < j; k++)
                s -= f->W[i][k] * f->U[j][k];
            if (j < i) {
                f->W[i][j] = s;
                f->U[i][j] = s * f->dinv[j];
            } else {
                if (!(s > 0.0))
                    return -1; /* rank lost to rounding: the SVD path */
                f->d[i] = s;
                f->dinv[i] = 1.0 / s;
            }
        }
    }
    c2 = gram_block_cond2(f, 0, 3, &fro2, &inv2);
    if (n2 > 0)
        c2 *= gram_block_cond2(f, 3, n2, &fro2b, &inv2b);
    if (!(c2 <= gmax * gmax))
        return -1;
    out->sigma_min_J1 = 1.0 / sqrt(inv2);
    out->sigma_max_J1 = sqrt(fro2);
    return 0;
}

static void resolve_gram(const tdsd_input *in, tdsd_output *out, const gram_factor *f, int n2,
                         const double w2[3], const double e2[3], const double Kpe[3],
                         const double g[NJ])
{
    double za[3], zb[3], xa[3], xb[3], x[NJ] = { 0.0 }, a[NJ], b[NJ], c;
    int i, j;
    out->fast = TDSD_PATH_GRAM;
    out->rank_J1 = 3;
    out->rank_J2P1 = n2;
    /* a = J1^+ p_d', b = J1^+ K_p e_p, through z = U11^-1 y */
    gram_block_solve(f, 0, 3, in->v_d_mps, za, xa);
    gram_block_solve(f, 0, 3, Kpe, zb, xb);
    for (j = 0; j < NJ; j++) { /* J1^T xa, J1^T xb in one pass over J1 */
        const double r0 = f->row[0][j], r1 = f->row[1][j], r2 = f->row[2][j];
        a[j] = xa[0] * r0 + xa[1] * r1 + xa[2] * r2;
        b[j] = xb[0] * r0 + xb[1] * r1 + xb[2] * r2;
    }
    c = path_rate_dq1(in, out, a, b, Kpe);
    if (n2 > 0) {
        double r[3], z2[3];
        task2_residual(in, out, f->U + 3, n2, w2, e2, za, zb, c, r); /* J2 dq1 = U21 z1 */
        gram_block_solve(f, 3, n2, r, z2, x + 3);
        /* x = [x1; x2], x1 = -U11^-T U21^T x2: dq2 = J^T x */
        for (j = 0; j < 3; j++) {
            x[j] = 0.0;
            for (i = 0; i < n2; i++)
                x[j] -= f->U[3 + i][j] * x[3 + i];
        }
        gram_block_bwd(f, 0, 3, x, x);
        gram_combine(f, f->n, x, out->dq2);
    }
    if (f->n < NJ) { /* dq3 = g - J^T G^-1 J g; else 0 (output_reset) */
        double u[NJ] = {
            0.0
        }; /* the first n are set; the rest keeps -Wmaybe-uninitialized quiet */
        for (i = 0; i < f->n; i++)
            u[i] = dot6(f->row[i], g);
        gram_solve(f, 0, f->n, u, x);
        gram_combine(f, f->n, x, u);
        for (i = 0; i < NJ; i++)
            out->dq3[i] = g[i] - u[i];
    }
}

/* ---- the SVD resolution: the generic path and the fast path's oracle ----
 * The pseudo-inverses stay in SVD form (linalg_pinv_svd): J1+ is applied
 * to two vectors and P1 only enters through J2 P1 and P1 g, so neither J1+
 * nor P1 (6x6) nor (J2P1)+ is ever formed:
 *   J2 P1 = J2 - (J2 V1) V1^T,   P1 g = g - V1 V1^T g,
 *   (J2P1)+ (J2P1) g = V2 V2^T g   (V1, V2: kept right singular vectors).
 * It is eq. 8-11 of docs/method/tdsd.md §3-4 in the order written there. */
static int resolve_svd(const tdsd_input *in, tdsd_output *out, const double *J2, int n2,
                       const double w2[3], const double e2[3], const double Kpe[3],
                       const double g[NJ])
{
    linalg_pinv_svd F1;
    double a[NJ], b[NJ];
    int i;

    if (!la_ok(linalg_pinv_factor(&F1, in->J1, 3, NJ, in->pinv_rtol)))
        return TDSD_ERR_NUMERIC;
    out->fast = TDSD_PATH_SVD;
    out->sigma_min_J1 = F1.info.sigma_min;
    out->sigma_max_J1 = F1.info.sigma_max;
    out->rank_J1 = F1.info.rank;

    linalg_pinv_apply(a, &F1, in->v_d_mps);
    linalg_pinv_apply(b, &F1, Kpe);
    (void)path_rate_dq1(in, out, a, b, Kpe);

    /* dq3 = P1 g - (J2P1)+ (J2P1) g: project k grad V onto the joint
     * motions that move neither task */
    {
        double t[NJ];
        linalg_pinv_rowspace(t, &F1, g);
        for (i = 0; i < NJ; i++)
            out->dq3[i] = g[i] - t[i];
    }
    if (n2 > 0) {
        double M[3 * NJ], r[3], s[NJ];
        linalg_pinv_null_rows(M, J2, n2, &F1); /* J2 P1 */
        /* F1 is not needed past J2 P1: its storage takes J2 P1's SVD */
        if (!la_ok(linalg_pinv_factor(&F1, M, n2, NJ, in->pinv_rtol)))
            return TDSD_ERR_NUMERIC;
        out->rank_J2P1 = F1.info.rank;
        linalg_matvec(r, J2, out->dq1, n2, NJ);
        for (i = 0; i < n2; i++) {
            out->y2[i] = out->lambda * w2[i] + in->K_o * e2[i];
            r[i] = out->y2[i] - r[i];
        }
        linalg_pinv_apply(out->dq2, &F1, r);
        linalg_pinv_rowspace(s, &F1, g);
        for (i = 0; i < NJ; i++)
            out->dq3[i] -= s[i];
    }
    return TDSD_OK;
}

/* check: 0 skips input_valid (tdsd_step_unchecked: the caller's inputs
 * are valid by construction). */
static int step_with(const tdsd_input *in, tdsd_output *out, int allow_fast, int check)
{
    double buf[3 * NJ], e2[3], w2[3], g[NJ], Kpe[3];
    const double *J2;
    int n2, rc = TDSD_OK, fast = 0;

    output_reset(out);
    if (check && !input_valid(in))
        return TDSD_ERR_ARG;
    n2 = step_setup(in, out, buf, &J2, e2, w2, Kpe, g);
    if (allow_fast) { /* the factors' scopes end before the SVD's: they share stack */
        gram_factor f;
        if (gram_factor_task(&f, in, J2, n2, out) == 0) {
            resolve_gram(in, out, &f, n2, w2, e2, Kpe, g);
            fast = 1;
        }
    }
    if (allow_fast && !fast) { /* near rank loss: orthogonal rows keep eps kappa */
        lq_factor f;
        if (lq_factor_task(&f, in, J2, n2, out) == 0) {
            resolve_lq(in, out, &f, n2, w2, e2, Kpe, g);
            fast = 1;
        }
    }
    if (!fast)
        rc = resolve_svd(in, out, J2, n2, w2, e2, Kpe, g);
    if (rc != TDSD_OK) {
        output_reset(out);
        return rc;
    }
    step_finish(in, out);
    return TDSD_OK;
}

int tdsd_step(const tdsd_input *in, tdsd_output *out)
{
    return step_with(in, out, 1, 1);
}

int tdsd_step_unchecked(const tdsd_input *in, tdsd_output *out)
{
    return step_with(in, out, 1, 0);
}

int tdsd_step_svd(const tdsd_input *in, tdsd_output *out)
{
    return step_with(in, out, 0, 1);
}

/* Stacked task [J1; J2] (m x 6) and velocity [y1'; y2'] at lambda = rate_cap. */
static int rr_setup(const tdsd_input *in, tdsd_output *out, double J[NJ * NJ], double y[NJ])
{
    double buf[3 * NJ], e2[3], w2[3];
    const double *J2;
    linalg_pinv_svd F1;
    int n2, i;

    vec3_sub(out->e_p, in->p_d_m, in->p_m);
    n2 = task2_setup(in, buf, &J2, e2, w2);
    out->n2 = n2;
    out->lambda = in->rate_cap;
    out->Q1 = out->Q2 = 1.0;
    linalg_copy(J, in->J1, 3, NJ);
    linalg_copy(J + 3 * NJ, J2, n2, NJ);
    for (i = 0; i < 3; i++) {
        out->y1[i] = in->rate_cap * in->v_d_mps[i] + in->K_p * out->e_p[i];
        y[i] = out->y1[i];
    }
    for (i = 0; i < n2; i++) {
        out->e_o[i] = e2[i];
        out->y2[i] = in->rate_cap * w2[i] + in->K_o * e2[i];
        y[3 + i] = out->y2[i];
    }
    if (!la_ok(linalg_pinv_factor(&F1, in->J1, 3, NJ, in->pinv_rtol)))
        return TDSD_ERR_NUMERIC;
    out->sigma_min_J1 = F1.info.sigma_min;
    out->sigma_max_J1 = F1.info.sigma_max;
    out->rank_J1 = F1.info.rank;
    return 3 + n2;
}

static void rr_finish(const tdsd_input *in, tdsd_output *out, const double *Jinv, int m,
                      const double y[NJ])
{
    int i;
    linalg_matvec(out->dq1, Jinv, y, NJ, m);
    for (i = 0; i < NJ; i++)
        out->dq_radps[i] = out->dq1[i];
    out->n_clipped = clip_joints(out->dq_radps, in->dq_max_radps, 0.0);
}

/* Both baselines: the stacked J and y (rr_setup) and J's pseudo-inverse
 * Jp (its singular values drive the DLS damping). Row count, or
 * TDSD_ERR_NUMERIC with out reset. */
static int rr_stack_pinv(const tdsd_input *in, tdsd_output *out, double J[NJ * NJ],
                         double Jp[NJ * NJ], double y[NJ], linalg_pinv_info *info)
{
    const int m = rr_setup(in, out, J, y);
    if (m < 0)
        return TDSD_ERR_NUMERIC;
    if (!la_ok(linalg_pinv(Jp, NULL, info, J, m, NJ, in->pinv_rtol))) {
        output_reset(out);
        return TDSD_ERR_NUMERIC;
    }
    out->rank_J2P1 = info->rank;
    return m;
}

int rr_pinv_step(const tdsd_input *in, tdsd_output *out)
{
    double J[NJ * NJ], Jp[NJ * NJ], y[NJ];
    linalg_pinv_info info;
    int m;

    output_reset(out);
    if (!input_valid(in))
        return TDSD_ERR_ARG;
    m = rr_stack_pinv(in, out, J, Jp, y, &info);
    if (m < 0)
        return m;
    rr_finish(in, out, Jp, m, y);
    return TDSD_OK;
}

int rr_dls_step(const tdsd_input *in, const rr_dls_params *dls, tdsd_output *out)
{
    double J[NJ * NJ], Jp[NJ * NJ], Jd[NJ * NJ], y[NJ];
    linalg_pinv_info info;
    double damping;
    int m;

    output_reset(out);
    if (!input_valid(in) || !dls || !(dls->lambda0 >= 0.0) || !isfinite(dls->lambda0) ||
        !isfinite(dls->eps))
        return TDSD_ERR_ARG;
    /* sigma_min of the stacked J drives the variable damping */
    m = rr_stack_pinv(in, out, J, Jp, y, &info);
    if (m < 0)
        return m;
    if (dls->eps <= 0.0) {
        damping = dls->lambda0;
    } else if (info.sigma_min < dls->eps) {
        double r = info.sigma_min / dls->eps;
        damping = dls->lambda0 * sqrt(1.0 - r * r);
    } else {
        damping = 0.0;
    }
    out->damping = damping;
    if (!la_ok(linalg_dls(Jd, J, m, NJ, damping))) {
        output_reset(out);
        return TDSD_ERR_NUMERIC;
    }
    rr_finish(in, out, Jd, m, y);
    return TDSD_OK;
}

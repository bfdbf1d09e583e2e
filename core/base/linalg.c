/* linalg: small dense linear algebra for the velocity-level controllers of
 * docs/method/tdsd.md (pseudo-inverses and null-space projectors of eq. 8/11, the
 * damped least-squares baseline). One-sided (Hestenes) Jacobi SVD: simple,
 * accurate, and bounded (LINALG_SVD_MAX_SWEEPS); well-conditioned 3-row
 * wide matrices start it from the eigenvectors of their 3x3 Gram matrix
 * (svd_wide_gram: why that is safe). The pseudo-inverse is also available
 * as factors (linalg_pinv_svd) for callers that only apply it. No
 * allocation, no state.
 */
#include "linalg.h"
#include <float.h>
#include <math.h>

#define NN (LINALG_MAX * LINALG_MAX)
#define GRAM_DECLINED 1 /* svd_wide_gram: guard failed, nothing computed */
#define SWEEP_CAP_HIT (-1) /* jacobi_rows: LINALG_SVD_MAX_SWEEPS used up */

static int dims_ok(int m, int n)
{
    return m >= 1 && m <= LINALG_MAX && n >= 1 && n <= LINALG_MAX;
}

int linalg_all_finite(const double *A, int count)
{
    /* x - x is 0 for finite x and NaN for NaN or +-Inf, and NaN survives
     * the sum: one test instead of one per entry */
    double acc = 0.0;
    int i;
    for (i = 0; i < count; i++)
        acc += A[i] - A[i];
    return acc == 0.0;
}

void linalg_identity(double *I, int n)
{
    int i, j;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            I[i * n + j] = (i == j) ? 1.0 : 0.0;
}

void linalg_copy(double *B, const double *A, int m, int n)
{
    int i;
    for (i = 0; i < m * n; i++)
        B[i] = A[i];
}

void linalg_transpose(double *At, const double *A, int m, int n)
{
    int i, j;
    for (i = 0; i < m; i++)
        for (j = 0; j < n; j++)
            At[j * m + i] = A[i * n + j];
}

void linalg_mul(double *C, const double *A, const double *B, int m, int k, int n)
{
    int i, j, l;
    for (i = 0; i < m; i++)
        for (j = 0; j < n; j++) {
            double acc = 0.0;
            for (l = 0; l < k; l++)
                acc += A[i * k + l] * B[l * n + j];
            C[i * n + j] = acc;
        }
}

void linalg_tmul(double *C, const double *A, const double *B, int k, int m, int n)
{
    int i, j, l;
    for (i = 0; i < m; i++)
        for (j = 0; j < n; j++) {
            double acc = 0.0;
            for (l = 0; l < k; l++)
                acc += A[l * m + i] * B[l * n + j];
            C[i * n + j] = acc;
        }
}

void linalg_mul_t(double *C, const double *A, const double *B, int m, int k, int n)
{
    int i, j, l;
    for (i = 0; i < m; i++)
        for (j = 0; j < n; j++) {
            double acc = 0.0;
            for (l = 0; l < k; l++)
                acc += A[i * k + l] * B[j * k + l];
            C[i * n + j] = acc;
        }
}

void linalg_matvec(double *y, const double *A, const double *x, int m, int n)
{
    linalg_mul(y, A, x, m, n, 1);
}

void linalg_tmatvec(double *y, const double *A, const double *x, int m, int n)
{
    linalg_tmul(y, A, x, m, n, 1);
}

double linalg_maxabs_diff(const double *A, const double *B, int m, int n)
{
    double worst = 0.0;
    int i;
    for (i = 0; i < m * n; i++) {
        double d = fabs(A[i] - B[i]);
        if (d > worst || d != d)
            worst = d;
    }
    return worst;
}

/* Jacobi rotation that zeroes the off-diagonal of the symmetric 2x2
 * [alpha gamma; gamma beta], gamma != 0: t = tan(theta) is the smaller root
 * of t^2 + 2 zeta t - 1 = 0, zeta = (beta - alpha) / (2 gamma)
 * (Rutishauser), c = cos(theta), s = sin(theta) = c t. Written without
 * zeta: with d = beta - alpha, h = 2 gamma, r = sqrt(d^2 + h^2),
 *   t = sgn(zeta) |h| / (|d| + r),   c = sqrt((1 + |d| / r) / 2),
 * so the dependent chain is sqrt, div, sqrt instead of div, sqrt, div,
 * sqrt, div (the rotations of a sweep are sequential; that latency is most
 * of their cost). 1 + |d|/r has no cancellation and c lies in
 * [1/sqrt 2, 1]. sgn(zeta) |h| = (d >= 0 ? h : -h). The squares are safe
 * while d^2 + h^2 lies in [1e-300, 1e300] (one of them underflowing is
 * harmless); outside that (never for arm Jacobians) the zeta form runs,
 * with sqrt(1 + zeta^2) = |zeta| past |zeta| = 1e150. */
static void jacobi_rot(double alpha, double beta, double gamma, double *c, double *s,
                       double *t)
{
    const double d = beta - alpha, h = 2.0 * gamma;
    const double r2 = d * d + h * h;
    if (r2 >= 1e-300 && r2 <= 1e300) {
        const double r = sqrt(r2), ad = fabs(d);
        *t = (d >= 0.0 ? h : -h) / (ad + r);
        *c = sqrt(0.5 + 0.5 * (ad / r));
    } else {
        const double zeta = d / h, az = fabs(zeta);
        const double tt = 1.0 / (az + (az < 1e150 ? sqrt(1.0 + zeta * zeta) : az));
        *t = zeta >= 0.0 ? tt : -tt;
        *c = 1.0 / sqrt(1.0 + tt * tt);
    }
    *s = *c * *t;
}

static double dot(const double *a, const double *b, int len)
{
    double acc = 0.0;
    int k;
    for (k = 0; k < len; k++)
        acc += a[k] * b[k];
    return acc;
}

/* Columns p, q of X (rows x cols): (x_p, x_q) <- (c x_p - s x_q, s x_p + c x_q). */
static void rotate_cols(double *X, int rows, int cols, int p, int q, double c, double s)
{
    int k;
    for (k = 0; k < rows; k++) {
        double xp = X[k * cols + p], xq = X[k * cols + q];
        X[k * cols + p] = c * xp - s * xq;
        X[k * cols + q] = s * xp + c * xq;
    }
}

/* Hestenes one-sided Jacobi on the k vectors stored as the rows of X
 * (k x len, k <= len): rotate pairs until all are mutually orthogonal to
 * relative precision; V (k x k, orthogonal on entry: the identity, or a warm
 * start) accumulates the rotations as its columns. For a matrix B with
 * these vectors as columns (B = X^T), on return B_in V = B_out.
 * nrm2[k] returns the squared row norms. The rows are stored contiguously
 * so every dot product runs over consecutive memory, and a row's squared
 * norm is recomputed only when the row changes (the same sums, in the same
 * order, as recomputing it at every pair). Returns the number of sweeps
 * used, or SWEEP_CAP_HIT. */
static int jacobi_rows(double *X, double *V, double nrm2[], int k, int len)
{
    const double thresh = 2.0 * DBL_EPSILON;
    int sweep, p, q;

    for (p = 0; p < k; p++)
        nrm2[p] = dot(X + p * len, X + p * len, len);
    for (sweep = 0; sweep < LINALG_SVD_MAX_SWEEPS; sweep++) {
        int rotated = 0;
        for (p = 0; p < k - 1; p++)
            for (q = p + 1; q < k; q++) {
                double *xp = X + p * len, *xq = X + q * len;
                double alpha = nrm2[p], beta = nrm2[q], gamma, t, c, s;
                int i;
                if (alpha == 0.0 || beta == 0.0)
                    continue;
                gamma = dot(xp, xq, len);
                if (gamma == 0.0)
                    continue;
                if (fabs(gamma) <= thresh * sqrt(alpha) * sqrt(beta))
                    continue;
                rotated = 1;
                jacobi_rot(alpha, beta, gamma, &c, &s, &t);
                for (i = 0; i < len; i++) {
                    double a = xp[i], b = xq[i];
                    xp[i] = c * a - s * b;
                    xq[i] = s * a + c * b;
                }
                rotate_cols(V, k, k, p, q, c, s);
                nrm2[p] = dot(xp, xp, len);
                nrm2[q] = dot(xq, xq, len);
            }
        if (!rotated)
            return sweep + 1;
    }
    return SWEEP_CAP_HIT;
}

/* Cyclic two-sided Jacobi on the symmetric k x k G (k <= 3): on return G
 * is diagonal up to DBL_EPSILON * trace (below that its entries are
 * rounding of the product that formed G anyway) and G_in = Q G_out Q^T.
 * Only a warm start (svd_wide_gram), so no convergence flag: the one-sided
 * sweeps that follow decide when the factorisation is accurate. */
static void gram_eigen(double *G, double *Q, int k)
{
    double floor_abs = 0.0;
    int sweep, p, q;

    linalg_identity(Q, k);
    for (p = 0; p < k; p++)
        floor_abs += G[p * k + p];
    floor_abs *= DBL_EPSILON;
    for (sweep = 0; sweep < LINALG_GRAM_MAX_SWEEPS; sweep++) {
        int rotated = 0;
        for (p = 0; p < k - 1; p++)
            for (q = p + 1; q < k; q++) {
                double gpq = G[p * k + q], t, c, s;
                if (!(fabs(gpq) > floor_abs))
                    continue;
                rotated = 1;
                jacobi_rot(G[p * k + p], G[q * k + q], gpq, &c, &s, &t);
                G[p * k + p] -= t * gpq;
                G[q * k + q] += t * gpq;
                G[p * k + q] = G[q * k + p] = 0.0;
                if (k == 3) { /* the one remaining index */
                    const int r = 3 - p - q;
                    const double grp = G[r * 3 + p], grq = G[r * 3 + q];
                    G[r * 3 + p] = G[p * 3 + r] = c * grp - s * grq;
                    G[r * 3 + q] = G[q * 3 + r] = s * grp + c * grq;
                }
                rotate_cols(Q, k, k, p, q, c, s);
            }
        if (!rotated)
            return;
    }
}

/* Makes column j of Q (rows x cols) a unit vector orthogonal to columns
 * 0..j-1 (already orthonormal): the unit basis vector with the largest
 * residual after two Gram-Schmidt passes. */
static void complete_column(double *Q, int rows, int cols, int j)
{
    double best[LINALG_MAX];
    double best_norm = -1.0;
    int e, i, c, pass;

    for (e = 0; e < rows; e++) {
        double v[LINALG_MAX], nrm = 0.0;
        for (i = 0; i < rows; i++)
            v[i] = (i == e) ? 1.0 : 0.0;
        for (pass = 0; pass < 2; pass++)
            for (c = 0; c < j; c++) {
                double d = 0.0;
                for (i = 0; i < rows; i++)
                    d += Q[i * cols + c] * v[i];
                for (i = 0; i < rows; i++)
                    v[i] -= d * Q[i * cols + c];
            }
        for (i = 0; i < rows; i++)
            nrm += v[i] * v[i];
        nrm = sqrt(nrm);
        if (nrm > best_norm) {
            best_norm = nrm;
            for (i = 0; i < rows; i++)
                best[i] = v[i] / nrm;
        }
    }
    for (i = 0; i < rows; i++)
        Q[i * cols + j] = best[i];
}

/* From B Vf = X^T with mutually orthogonal rows of X (k x len, squared
 * norms nrm2) to the thin SVD B = U diag(s) V^T of the len x k matrix B:
 * s = row norms sorted descending, U (len x k), V (k x k). */
static void svd_from_rows(double *U, double *s, double *V, const double *X,
                          const double *Vf, const double nrm2[], int k, int len)
{
    int order[LINALG_MAX];
    double ss[LINALG_MAX];
    int i, j, r;

    for (j = 0; j < k; j++) {
        s[j] = sqrt(nrm2[j]);
        order[j] = j;
    }
    /* insertion sort, descending (k <= 6) */
    for (i = 1; i < k; i++) {
        int o = order[i];
        j = i - 1;
        while (j >= 0 && s[order[j]] < s[o]) {
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = o;
    }
    for (j = 0; j < k; j++)
        ss[j] = s[order[j]];
    for (j = 0; j < k; j++) {
        const double *x = X + order[j] * len;
        s[j] = ss[j];
        for (r = 0; r < k; r++)
            V[r * k + j] = Vf[r * k + order[j]];
        if (ss[j] > 0.0)
            for (r = 0; r < len; r++)
                U[r * k + j] = x[r] / ss[j];
    }
    for (j = 0; j < k; j++)
        if (!(s[j] > 0.0))
            complete_column(U, len, k, j);
}

/* One-sided Jacobi from the identity on the rows of X (k x len, k <= len,
 * overwritten): the thin SVD of B = X^T, U len x k, V k x k. */
static int svd_cold(double *U, double *s, double *V, double *X, int k, int len)
{
    double Vf[NN], nrm2[LINALG_MAX];
    int sweeps;

    linalg_identity(Vf, k);
    sweeps = jacobi_rows(X, Vf, nrm2, k, len);
    svd_from_rows(U, s, V, X, Vf, nrm2, k, len);
    return sweeps == SWEEP_CAP_HIT ? LINALG_ERR_NOCONV : LINALG_OK;
}

/* Wide A (m = LINALG_GRAM_ROWS < n), Gram warm start. The
 * one-sided Jacobi of the cold path is a Jacobi diagonalisation of
 * G = A A^T (m x m) whose entries are recomputed from the rotated rows of A
 * at every step; here G is formed once and diagonalised as a small
 * symmetric matrix, G = Q diag(lambda) Q^T, and X = Q^T A replaces the cold
 * start X = A, Vf = I.
 *
 * Accuracy. Forming G costs absolute errors ~ n eps sigma_max^2, so
 * lambda_i is accurate to ~ eps sigma_max^2 (Weyl) and the rows of Q^T A
 * are orthogonal only to ~ eps (sigma_max / sigma_min)^2 relative: fine
 * where sigma_min is not tiny against sigma_max, useless near rank
 * deficiency (at sigma_min / sigma_max = 1e-8 the small direction is pure
 * rounding). Hence two guards:
 *  - a priori: the warm start is used only if lambda_min >= LINALG_GRAM_RTOL
 *    lambda_max (sigma_min >= 1e-3 sigma_max); otherwise the cold one-sided
 *    Jacobi runs, exactly as for every other shape;
 *  - a posteriori: X is not trusted as it is. The same one-sided sweeps then
 *    run on (X, Q) with the same stopping test (every pair of rows
 *    orthogonal to 2 eps relative) and the same sweep cap, so the result
 *    meets the cold path's orthogonality and reconstruction bounds. From a
 *    start orthogonal to ~ eps kappa^2 <= 2e-10 they converge quadratically:
 *    on the PUMA 560 bench set the first sweep already passes the test in
 *    3 of 4 cases, and one rotating sweep suffices in the rest (the cold
 *    start needs 4..6).
 * Singular values carry absolute errors O(eps sigma_max) on both paths;
 * with the guard that is at most O(1e3 eps) relative to the smallest one.
 * Returns GRAM_DECLINED (nothing written) when the guard fails. */
static int svd_wide_gram(double *U, double *s, double *V, const double *A, int m, int n)
{
    double G[LINALG_GRAM_ROWS * LINALG_GRAM_ROWS];
    double Q[LINALG_GRAM_ROWS * LINALG_GRAM_ROWS];
    double X[NN], nrm2[LINALG_MAX];
    double lmin, lmax;
    int i, j, l, sweeps;

    for (i = 0; i < m; i++)
        for (j = i; j < m; j++)
            G[i * m + j] = G[j * m + i] = dot(A + i * n, A + j * n, n);
    gram_eigen(G, Q, m);
    lmin = lmax = G[0];
    for (i = 1; i < m; i++) {
        double lam = G[i * m + i];
        if (lam < lmin)
            lmin = lam;
        if (lam > lmax)
            lmax = lam;
    }
    if (!(lmax > 0.0) || !(lmin >= LINALG_GRAM_RTOL * lmax))
        return GRAM_DECLINED;
    for (i = 0; i < m; i++) { /* X = Q^T A: row i = sum_l Q_li (row l of A) */
        double *x = X + i * n;
        for (j = 0; j < n; j++)
            x[j] = 0.0;
        for (l = 0; l < m; l++) {
            const double q = Q[l * m + i];
            const double *a = A + l * n;
            for (j = 0; j < n; j++)
                x[j] += q * a[j];
        }
    }
    sweeps = jacobi_rows(X, Q, nrm2, m, n);
    /* A^T Q' = X'^T = W diag(s)  =>  A = Q' diag(s) W^T */
    svd_from_rows(V, s, U, X, Q, nrm2, m, n);
    return sweeps == SWEEP_CAP_HIT ? LINALG_ERR_NOCONV : LINALG_OK;
}

int linalg_svd(double *U, double *s, double *V, const double *A, int m, int n)
{
    double X[NN];
    if (!dims_ok(m, n))
        return LINALG_ERR_SIZE;
    if (!linalg_all_finite(A, m * n))
        return LINALG_ERR_NONFINITE;
    if (m >= n) {
        /* the columns of A are the vectors: X = A^T */
        linalg_transpose(X, A, m, n);
        return svd_cold(U, s, V, X, n, m);
    }
    if (m == LINALG_GRAM_ROWS) {
        int rc = svd_wide_gram(U, s, V, A, m, n);
        if (rc != GRAM_DECLINED)
            return rc;
    }
    /* A^T = U' S V'^T  =>  A = V' S U'^T; the rows of A are A^T's columns */
    linalg_copy(X, A, m, n);
    return svd_cold(V, s, U, X, m, n);
}

int linalg_pinv_factor(linalg_pinv_svd *F, const double *A, int m, int n, double rtol)
{
    int p = m < n ? m : n;
    int k, rank = 0, rc;

    if (!(rtol >= 0.0) || !(rtol < 1.0))
        return LINALG_ERR_ARG;
    if (rtol == 0.0)
        rtol = LINALG_PINV_RTOL;
    rc = linalg_svd(F->U, F->s, F->V, A, m, n);
    if (rc != LINALG_OK && rc != LINALG_ERR_NOCONV)
        return rc;
    F->m = m;
    F->n = n;
    F->p = p;
    F->info.tol = rtol * F->s[0];
    for (k = 0; k < p; k++)
        if (F->s[k] > F->info.tol)
            rank = k + 1;
    F->info.rank = rank;
    F->info.sigma_max = F->s[0];
    F->info.sigma_min = F->s[p - 1];
    return rc;
}

void linalg_pinv_apply(double *x, const linalg_pinv_svd *F, const double *y)
{
    const int m = F->m, n = F->n, p = F->p, r = F->info.rank;
    double c[LINALG_MAX];
    int i, k;
    /* c = diag(1/s_r) U_r^T y, row by row of U (the same sums per c_k) */
    for (k = 0; k < r; k++)
        c[k] = 0.0;
    for (i = 0; i < m; i++) {
        const double *u = F->U + i * p;
        for (k = 0; k < r; k++)
            c[k] += u[k] * y[i];
    }
    for (k = 0; k < r; k++)
        c[k] /= F->s[k];
    for (i = 0; i < n; i++)
        x[i] = dot(F->V + i * p, c, r);
}

void linalg_pinv_rowspace(double *x, const linalg_pinv_svd *F, const double *g)
{
    const int n = F->n, p = F->p, r = F->info.rank;
    double c[LINALG_MAX];
    int i, k;
    for (k = 0; k < r; k++)
        c[k] = 0.0;
    for (i = 0; i < n; i++) {
        const double *v = F->V + i * p;
        for (k = 0; k < r; k++)
            c[k] += v[k] * g[i];
    }
    for (i = 0; i < n; i++)
        x[i] = dot(F->V + i * p, c, r);
}

void linalg_pinv_null_rows(double *M, const double *B, int k, const linalg_pinv_svd *F)
{
    int row;
    for (row = 0; row < k; row++) {
        const double *b = B + row * F->n;
        double *mr = M + row * F->n;
        double proj[LINALG_MAX];
        int j;
        linalg_pinv_rowspace(proj, F, b);
        for (j = 0; j < F->n; j++)
            mr[j] = b[j] - proj[j];
    }
}

int linalg_pinv(double *Ap, double *Pnull, linalg_pinv_info *info,
                const double *A, int m, int n, double rtol)
{
    linalg_pinv_svd F;
    const int p = m < n ? m : n;
    int i, j, k, rank, rc;

    rc = linalg_pinv_factor(&F, A, m, n, rtol);
    if (rc != LINALG_OK && rc != LINALG_ERR_NOCONV)
        return rc;
    rank = F.info.rank;
    for (i = 0; i < n; i++)
        for (j = 0; j < m; j++) {
            double acc = 0.0;
            for (k = 0; k < rank; k++)
                acc += F.V[i * p + k] * F.U[j * p + k] / F.s[k];
            Ap[i * m + j] = acc;
        }
    if (Pnull) {
        for (i = 0; i < n; i++)
            for (j = 0; j < n; j++) {
                double acc = 0.0;
                for (k = 0; k < rank; k++)
                    acc += F.V[i * p + k] * F.V[j * p + k];
                Pnull[i * n + j] = ((i == j) ? 1.0 : 0.0) - acc;
            }
    }
    if (info)
        *info = F.info;
    return rc;
}

int linalg_cholesky(double *L, const double *A, int n)
{
    int i, j, k;
    if (!dims_ok(n, n))
        return LINALG_ERR_SIZE;
    if (!linalg_all_finite(A, n * n))
        return LINALG_ERR_NONFINITE;
    for (i = 0; i < n * n; i++)
        L[i] = 0.0;
    for (j = 0; j < n; j++) {
        double d = A[j * n + j];
        for (k = 0; k < j; k++)
            d -= L[j * n + k] * L[j * n + k];
        if (!(d > 0.0) || !isfinite(d))
            return LINALG_ERR_NOT_PD;
        L[j * n + j] = sqrt(d);
        for (i = j + 1; i < n; i++) {
            double v = A[i * n + j];
            for (k = 0; k < j; k++)
                v -= L[i * n + k] * L[j * n + k];
            L[i * n + j] = v / L[j * n + j];
        }
    }
    return LINALG_OK;
}

void linalg_cholesky_solve(double *x, const double *L, const double *b, int n)
{
    double y[LINALG_MAX];
    int i, k;
    for (i = 0; i < n; i++) {
        double v = b[i];
        for (k = 0; k < i; k++)
            v -= L[i * n + k] * y[k];
        y[i] = v / L[i * n + i];
    }
    for (i = n - 1; i >= 0; i--) {
        double v = y[i];
        for (k = i + 1; k < n; k++)
            v -= L[k * n + i] * x[k];
        x[i] = v / L[i * n + i];
    }
}

/* Ad = sum_k sigma_k / (sigma_k^2 + lambda^2) v_k u_k^T, with the
 * pseudo-inverse's cut when lambda == 0. */
static int dls_svd(double *Ad, const double *A, int m, int n, double lambda)
{
    double U[NN], V[NN], s[LINALG_MAX];
    int p = m < n ? m : n;
    int i, j, k, rc;
    double tol;

    rc = linalg_svd(U, s, V, A, m, n);
    if (rc != LINALG_OK && rc != LINALG_ERR_NOCONV)
        return rc;
    tol = (lambda > 0.0) ? 0.0 : LINALG_PINV_RTOL * s[0];
    for (i = 0; i < n; i++)
        for (j = 0; j < m; j++) {
            double acc = 0.0;
            for (k = 0; k < p; k++)
                if (s[k] > tol)
                    acc += V[i * p + k] * U[j * p + k] * s[k]
                           / (s[k] * s[k] + lambda * lambda);
            Ad[i * m + j] = acc;
        }
    return rc;
}

int linalg_dls(double *Ad, const double *A, int m, int n, double lambda)
{
    double G[NN], L[NN], col[LINALG_MAX];
    double X[NN]; /* X (m x m) = (A A^T + lambda^2 I)^-1, column by column */
    int i, j;

    if (!dims_ok(m, n))
        return LINALG_ERR_SIZE;
    if (!linalg_all_finite(A, m * n))
        return LINALG_ERR_NONFINITE;
    if (!(lambda >= 0.0) || !isfinite(lambda))
        return LINALG_ERR_ARG;
    if (lambda == 0.0)
        return dls_svd(Ad, A, m, n, 0.0);

    linalg_mul_t(G, A, A, m, n, m);
    for (i = 0; i < m; i++)
        G[i * m + i] += lambda * lambda;
    if (linalg_cholesky(L, G, m) != LINALG_OK)
        return dls_svd(Ad, A, m, n, lambda);
    for (j = 0; j < m; j++) {
        for (i = 0; i < m; i++)
            col[i] = (i == j) ? 1.0 : 0.0;
        linalg_cholesky_solve(col, L, col, m);
        for (i = 0; i < m; i++)
            X[i * m + j] = col[i];
    }
    linalg_tmul(Ad, A, X, m, n, m);
    return LINALG_OK;
}

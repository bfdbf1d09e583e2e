/* linalg_svd: the thin SVD behind the pseudo-inverses of docs/method/tdsd.md §3
 * (eq. 8, 11; linalg_pinv.c). One-sided (Hestenes) Jacobi: simple, accurate,
 * and bounded (LINALG_SVD_MAX_SWEEPS); well-conditioned 3-row wide
 * matrices start it from the eigenvectors of their 3x3 Gram matrix
 * (svd_wide_gram: why that is safe). No allocation, no state.
 */
#include "linalg.h"
#include "linalg_internal.h"
#include <float.h>
#include <math.h>

#define GRAM_DECLINED 1    /* svd_wide_gram: guard failed, nothing computed */
#define SWEEP_CAP_HIT (-1) /* jacobi_rows: LINALG_SVD_MAX_SWEEPS used up */

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
static void jacobi_rot(double alpha, double beta, double gamma, double *c, double *s, double *t)
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
        nrm2[p] = linalg_dot(X + p * len, X + p * len, len);
    for (sweep = 0; sweep < LINALG_SVD_MAX_SWEEPS; sweep++) {
        int rotated = 0;
        for (p = 0; p < k - 1; p++)
            for (q = p + 1; q < k; q++) {
                double *xp = X + p * len, *xq = X + q * len;
                double alpha = nrm2[p], beta = nrm2[q], gamma, t, c, s;
                int i;
                if (alpha == 0.0 || beta == 0.0)
                    continue;
                gamma = linalg_dot(xp, xq, len);
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
                nrm2[p] = linalg_dot(xp, xp, len);
                nrm2[q] = linalg_dot(xq, xq, len);
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
static void svd_from_rows(double *U, double *s, double *V, const double *X, const double *Vf,
                          const double nrm2[], int k, int len)
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
    double Vf[LINALG_NN], nrm2[LINALG_MAX];
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
    double X[LINALG_NN], nrm2[LINALG_MAX];
    double lmin, lmax;
    int i, j, l, sweeps;

    for (i = 0; i < m; i++)
        for (j = i; j < m; j++)
            G[i * m + j] = G[j * m + i] = linalg_dot(A + i * n, A + j * n, n);
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
    double X[LINALG_NN];
    if (!linalg_dims_ok(m, n))
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

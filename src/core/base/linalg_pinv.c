/* linalg_pinv: the Moore-Penrose pseudo-inverse and the null-space
 * projector of the task-priority resolution (docs/method/tdsd.md §3, eq. 8
 * and 11), whole (linalg_pinv) or kept as its SVD factors (linalg_pinv_svd)
 * for callers that only apply it (J1^+ y, J2 P1, P1 g, (J2P1)^+(J2P1) g),
 * and the damped least-squares inverse of the baseline (§6, linalg_dls;
 * Cholesky from linalg.c, the SVD form from linalg_svd.c when that fails
 * or lambda is 0). No allocation, no state.
 */
#include "linalg.h"
#include "linalg_internal.h"
#include <math.h>

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
        x[i] = linalg_dot(F->V + i * p, c, r);
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
        x[i] = linalg_dot(F->V + i * p, c, r);
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

int linalg_pinv(double *Ap, double *Pnull, linalg_pinv_info *info, const double *A, int m, int n,
                double rtol)
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

/* Ad = sum_k sigma_k / (sigma_k^2 + lambda^2) v_k u_k^T, with the
 * pseudo-inverse's cut when lambda == 0. */
static int dls_svd(double *Ad, const double *A, int m, int n, double lambda)
{
    double U[LINALG_NN], V[LINALG_NN], s[LINALG_MAX];
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
                    acc += V[i * p + k] * U[j * p + k] * s[k] / (s[k] * s[k] + lambda * lambda);
            Ad[i * m + j] = acc;
        }
    return rc;
}

int linalg_dls(double *Ad, const double *A, int m, int n, double lambda)
{
    double G[LINALG_NN], L[LINALG_NN], col[LINALG_MAX];
    double X[LINALG_NN]; /* X (m x m) = (A A^T + lambda^2 I)^-1, column by column */
    int i, j;

    if (!linalg_dims_ok(m, n))
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

/* linalg: small dense linear algebra for the velocity-level controllers of
 * SPEC.md §3 (pseudo-inverses and null-space projectors of eq. 8/11, the
 * damped least-squares baseline). One-sided (Hestenes) Jacobi SVD: simple,
 * accurate to relative precision on the small singular values, and bounded
 * (LINALG_SVD_MAX_SWEEPS). No allocation, no state.
 */
#include "linalg.h"
#include <float.h>
#include <math.h>

#define NN (LINALG_MAX * LINALG_MAX)

static int dims_ok(int m, int n)
{
    return m >= 1 && m <= LINALG_MAX && n >= 1 && n <= LINALG_MAX;
}

int linalg_all_finite(const double *A, int count)
{
    int i;
    for (i = 0; i < count; i++)
        if (!isfinite(A[i]))
            return 0;
    return 1;
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

/* Hestenes: rotate column pairs of W (m x n, m >= n) until all columns are
 * mutually orthogonal to relative precision; V accumulates the rotations.
 * Returns the number of sweeps used, or -1 if the cap was reached. */
static int jacobi_orthogonalize(double *W, double *V, int m, int n)
{
    const double thresh = 2.0 * DBL_EPSILON;
    int sweep, p, q, k;

    linalg_identity(V, n);
    for (sweep = 0; sweep < LINALG_SVD_MAX_SWEEPS; sweep++) {
        int rotated = 0;
        for (p = 0; p < n - 1; p++)
            for (q = p + 1; q < n; q++) {
                double alpha = 0.0, beta = 0.0, gamma = 0.0;
                double zeta, t, c, s;
                for (k = 0; k < m; k++) {
                    alpha += W[k * n + p] * W[k * n + p];
                    beta += W[k * n + q] * W[k * n + q];
                    gamma += W[k * n + p] * W[k * n + q];
                }
                if (gamma == 0.0 || alpha == 0.0 || beta == 0.0)
                    continue;
                if (fabs(gamma) <= thresh * sqrt(alpha) * sqrt(beta))
                    continue;
                rotated = 1;
                zeta = (beta - alpha) / (2.0 * gamma);
                t = (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + hypot(1.0, zeta));
                c = 1.0 / sqrt(1.0 + t * t);
                s = c * t;
                for (k = 0; k < m; k++) {
                    double wp = W[k * n + p], wq = W[k * n + q];
                    W[k * n + p] = c * wp - s * wq;
                    W[k * n + q] = s * wp + c * wq;
                }
                for (k = 0; k < n; k++) {
                    double vp = V[k * n + p], vq = V[k * n + q];
                    V[k * n + p] = c * vp - s * vq;
                    V[k * n + q] = s * vp + c * vq;
                }
            }
        if (!rotated)
            return sweep + 1;
    }
    return -1;
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

/* Thin SVD of a tall (m >= n) matrix: U m x n, s[n], V n x n. */
static int svd_tall(double *U, double *s, double *V, const double *A, int m, int n)
{
    double W[NN], Vf[NN];
    int order[LINALG_MAX];
    int i, j, k, sweeps;

    linalg_copy(W, A, m, n);
    sweeps = jacobi_orthogonalize(W, Vf, m, n);

    for (j = 0; j < n; j++) {
        double nrm = 0.0;
        for (k = 0; k < m; k++)
            nrm += W[k * n + j] * W[k * n + j];
        s[j] = sqrt(nrm);
        order[j] = j;
    }
    /* insertion sort, descending (n <= 6) */
    for (i = 1; i < n; i++) {
        int o = order[i];
        j = i - 1;
        while (j >= 0 && s[order[j]] < s[o]) {
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = o;
    }
    {
        double ss[LINALG_MAX];
        for (j = 0; j < n; j++)
            ss[j] = s[order[j]];
        for (j = 0; j < n; j++) {
            int src = order[j];
            s[j] = ss[j];
            for (k = 0; k < n; k++)
                V[k * n + j] = Vf[k * n + src];
            for (k = 0; k < m; k++)
                U[k * n + j] = (ss[j] > 0.0) ? W[k * n + src] / ss[j] : 0.0;
        }
    }
    for (j = 0; j < n; j++)
        if (!(s[j] > 0.0))
            complete_column(U, m, n, j);
    return sweeps < 0 ? LINALG_ENOCONV : LINALG_OK;
}

int linalg_svd(double *U, double *s, double *V, const double *A, int m, int n)
{
    double At[NN];
    if (!dims_ok(m, n))
        return LINALG_EDIM;
    if (!linalg_all_finite(A, m * n))
        return LINALG_ENONFINITE;
    if (m >= n)
        return svd_tall(U, s, V, A, m, n);
    /* A^T = U' S V'^T  =>  A = V' S U'^T */
    linalg_transpose(At, A, m, n);
    return svd_tall(V, s, U, At, n, m);
}

int linalg_pinv(double *Ap, double *Pnull, linalg_pinv_info *info,
                const double *A, int m, int n, double rtol)
{
    double U[NN], V[NN], s[LINALG_MAX];
    double tol;
    int p = m < n ? m : n;
    int i, j, k, rank = 0, rc;

    if (!(rtol >= 0.0) || !(rtol < 1.0))
        return LINALG_EARG;
    if (rtol == 0.0)
        rtol = LINALG_PINV_RTOL;
    rc = linalg_svd(U, s, V, A, m, n);
    if (rc != LINALG_OK && rc != LINALG_ENOCONV)
        return rc;

    tol = rtol * s[0];
    for (k = 0; k < p; k++)
        if (s[k] > tol)
            rank = k + 1;

    for (i = 0; i < n; i++)
        for (j = 0; j < m; j++) {
            double acc = 0.0;
            for (k = 0; k < rank; k++)
                acc += V[i * p + k] * U[j * p + k] / s[k];
            Ap[i * m + j] = acc;
        }
    if (Pnull) {
        for (i = 0; i < n; i++)
            for (j = 0; j < n; j++) {
                double acc = 0.0;
                for (k = 0; k < rank; k++)
                    acc += V[i * p + k] * V[j * p + k];
                Pnull[i * n + j] = ((i == j) ? 1.0 : 0.0) - acc;
            }
    }
    if (info) {
        info->rank = rank;
        info->sigma_max = s[0];
        info->sigma_min = s[p - 1];
        info->tol = tol;
    }
    return rc;
}

int linalg_cholesky(double *L, const double *A, int n)
{
    int i, j, k;
    if (!dims_ok(n, n))
        return LINALG_EDIM;
    if (!linalg_all_finite(A, n * n))
        return LINALG_ENONFINITE;
    for (i = 0; i < n * n; i++)
        L[i] = 0.0;
    for (j = 0; j < n; j++) {
        double d = A[j * n + j];
        for (k = 0; k < j; k++)
            d -= L[j * n + k] * L[j * n + k];
        if (!(d > 0.0) || !isfinite(d))
            return LINALG_ENOTPD;
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
    if (rc != LINALG_OK && rc != LINALG_ENOCONV)
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
        return LINALG_EDIM;
    if (!linalg_all_finite(A, m * n))
        return LINALG_ENONFINITE;
    if (!(lambda >= 0.0) || !isfinite(lambda))
        return LINALG_EARG;
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

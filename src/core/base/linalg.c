/* linalg: the basic dense operations (products, transposes, copies, the
 * finiteness test) and the Cholesky factorisation and solve used by the
 * damped least-squares inverse (linalg_dls, linalg_pinv.c) of the
 * baseline in docs/method/tdsd.md §6. The SVD is in
 * linalg_svd.c, the pseudo-inverses and DLS in linalg_pinv.c; include/tandem/base/
 * linalg.h is the one public header of all three. No allocation, no state.
 */
#include "linalg.h"
#include "linalg_internal.h"
#include <math.h>

int linalg_all_finite(const double *A, int count); /* the external definition (C99 6.7.4) */

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
    /* linalg_mul's sums in its order, without its column loop and index
     * products (the control cycles' twist J qd and solves) */
    int i, l;
    for (i = 0; i < m; i++) {
        const double *a = A + i * n;
        double acc = 0.0;
        for (l = 0; l < n; l++)
            acc += a[l] * x[l];
        y[i] = acc;
    }
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

int linalg_cholesky(double *L, const double *A, int n)
{
    int i, j, k;
    if (!linalg_dims_ok(n, n))
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

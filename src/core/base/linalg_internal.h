/* linalg_internal: NOT PART OF THE PUBLIC INTERFACE. What the linalg files
 * (linalg.c basic operations and Cholesky, linalg_svd.c the SVD,
 * linalg_pinv.c pseudo-inverses and DLS) share with one another;
 * everything else uses linalg.h only.
 */
#ifndef TANDEM_LINALG_INTERNAL_H
#define TANDEM_LINALG_INTERNAL_H

#include "linalg.h"

/* Entries of the largest matrix: every scratch buffer's size. */
#define LINALG_NN (LINALG_MAX * LINALG_MAX)

static inline int linalg_dims_ok(int m, int n)
{
    return m >= 1 && m <= LINALG_MAX && n >= 1 && n <= LINALG_MAX;
}

static inline double linalg_dot(const double *a, const double *b, int len)
{
    double acc = 0.0;
    int k;
    for (k = 0; k < len; k++)
        acc += a[k] * b[k];
    return acc;
}

#endif

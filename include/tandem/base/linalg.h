/* linalg: small dense matrices (at most LINALG_MAX rows and columns) for the
 * velocity-level controllers (TDSD, resolved-rate baselines; docs/method/tdsd.md).
 *
 * Matrices are plain row-major double arrays with the dimensions passed
 * explicitly; an m x n matrix occupies a[0 .. m*n-1], element (i,j) at
 * a[i*n + j] (packed, the row stride is the column count). No allocation:
 * every scratch buffer is a fixed LINALG_MAX x LINALG_MAX array on the stack.
 * Outputs must not alias inputs unless a function says otherwise.
 *
 * The void helpers trust their dimensions (1..LINALG_MAX; callers use
 * compile-time sizes). The int functions validate dimensions and finiteness
 * and return 0 on success, a negative LINALG_ERR_* code otherwise.
 */
#ifndef TANDEM_LINALG_H
#define TANDEM_LINALG_H

#define LINALG_MAX 6

/* One-sided Jacobi SVD: hard cap on sweeps (each sweep visits every column
 * pair once). For n <= 6 convergence to full precision takes 5..10 sweeps;
 * the cap bounds the worst-case execution time. */
#define LINALG_SVD_MAX_SWEEPS 40

/* Wide matrices with LINALG_GRAM_ROWS rows and more columns (the 3x6 task
 * Jacobians) start the one-sided Jacobi from the eigenvectors of the 3x3
 * Gram matrix A A^T, if its eigenvalues satisfy
 * lambda_min >= LINALG_GRAM_RTOL lambda_max (sigma_min >= 1e-3 sigma_max);
 * otherwise, and for every other shape, from the identity. Either way the
 * sweeps stop on the same orthogonality test (accuracy argument in
 * linalg_svd.c, svd_wide_gram). (With 2 rows the one Gram rotation would be
 * exactly the cold path's first one, so there is nothing to gain.)
 * LINALG_GRAM_MAX_SWEEPS caps the 3x3 symmetric Jacobi (it converges in
 * 3..5 sweeps). */
#define LINALG_GRAM_ROWS 3
#define LINALG_GRAM_RTOL 1e-6
#define LINALG_GRAM_MAX_SWEEPS 8

/* Default relative rank tolerance of linalg_pinv: singular values
 * sigma_i <= LINALG_PINV_RTOL * sigma_max are treated as zero.
 * Why relative: the Jacobians mix units (m/rad rows, 1/1 rows), and a
 * relative cut is invariant to how the whole matrix is scaled. Why 1e-10:
 * the SVD's own noise on an exactly singular 6x6 matrix is a few
 * DBL_EPSILON * sigma_max (~1e-15 relative); 1e-10 stays five decades above
 * that noise, yet keeps any physically meaningful near-singular direction
 * (an arm 1 um from a singularity still has sigma_min/sigma_max ~ 1e-6), so
 * near-singular motion is left to TDSD's speed distribution, not to a cut. */
#define LINALG_PINV_RTOL 1e-10

enum {
    LINALG_OK = 0,
    LINALG_ERR_SIZE = -1,      /* a dimension outside 1..LINALG_MAX */
    LINALG_ERR_NONFINITE = -2, /* NaN or Inf in an input */
    LINALG_ERR_ARG = -3,       /* bad scalar argument (negative tolerance, ...) */
    LINALG_ERR_NOT_PD = -4,    /* Cholesky: matrix not positive definite */
    LINALG_ERR_NOCONV = -5     /* SVD: sweep cap reached (result still usable) */
};

void linalg_identity(double *I, int n);
void linalg_copy(double *B, const double *A, int m, int n);
/* At (n x m) = A^T, A is m x n. */
void linalg_transpose(double *At, const double *A, int m, int n);
/* C (m x n) = A (m x k) B (k x n). */
void linalg_mul(double *C, const double *A, const double *B, int m, int k, int n);
/* C (m x n) = A^T B, A is k x m, B is k x n. */
void linalg_tmul(double *C, const double *A, const double *B, int k, int m, int n);
/* C (m x n) = A B^T, A is m x k, B is n x k. */
void linalg_mul_t(double *C, const double *A, const double *B, int m, int k, int n);
/* y (m) = A (m x n) x. */
void linalg_matvec(double *y, const double *A, const double *x, int m, int n);
/* y (n) = A^T x, A is m x n, x has m entries. */
void linalg_tmatvec(double *y, const double *A, const double *x, int m, int n);
/* max_ij |A_ij - B_ij| */
double linalg_maxabs_diff(const double *A, const double *B, int m, int n);
/* 1 if every entry is finite. A C99 inline definition (linalg.c holds
 * the external one): the control cycles check a few arrays of 3 to 9
 * each, where the call cost as much as the test. x - x is 0 for finite x
 * and NaN for NaN or +-Inf, and NaN survives the sum: one test instead of
 * one per entry. */
inline int linalg_all_finite(const double *A, int count)
{
    const int threes = count / 3;
    double acc = 0.0;
    int i, k;
    for (k = 0; k < threes; k++, A += 3) /* by threes: the loop's count is a third */
        acc += (A[0] - A[0]) + (A[1] - A[1]) + (A[2] - A[2]);
    for (i = 0; i < count - 3 * threes; i++)
        acc += A[i] - A[i];
    return acc == 0.0;
}

/* Thin SVD A = U diag(s) V^T of an m x n matrix, p = min(m, n):
 * U is m x p, s[p] descending and >= 0, V is n x p; U and V have orthonormal
 * columns (columns for exactly zero singular values are completed to an
 * orthonormal set). Returns LINALG_ERR_NOCONV if the sweep cap was hit; the
 * factors are then still filled in (best so far). */
int linalg_svd(double *U, double *s, double *V, const double *A, int m, int n);

typedef struct {
    int rank;         /* singular values kept */
    double sigma_max; /* largest singular value */
    double sigma_min; /* smallest of the min(m,n) singular values (kept or not) */
    double tol;       /* absolute cut actually used: rtol * sigma_max */
} linalg_pinv_info;

/* Moore-Penrose pseudo-inverse Ap (n x m) of A (m x n) by SVD. Singular
 * values sigma_i <= rtol * sigma_max are treated as zero (rtol = 0 selects
 * LINALG_PINV_RTOL; a zero matrix has the zero pseudo-inverse).
 * Optional outputs (NULL to skip): Pnull (n x n) = I - Ap A, the orthogonal
 * projector onto the null space of A, computed from V as I - V_r V_r^T so it
 * is symmetric and idempotent to rounding; info. */
int linalg_pinv(double *Ap, double *Pnull, linalg_pinv_info *info, const double *A, int m, int n,
                double rtol);

/* The pseudo-inverse kept as its SVD factors, A+ = V_r diag(1/s_r) U_r^T
 * (r = info.rank, the same cut as linalg_pinv), for callers that apply A+
 * and the projectors A+ A, I - A+ A to a few vectors or rows only: cheaper
 * than forming them (TDSD needs J1+ on two vectors and J2 (I - J1+ J1)). */
typedef struct {
    int m, n, p;                       /* A is m x n, p = min(m, n) */
    double U[LINALG_MAX * LINALG_MAX]; /* m x p */
    double s[LINALG_MAX];              /* descending; s[0..rank-1] kept */
    double V[LINALG_MAX * LINALG_MAX]; /* n x p */
    linalg_pinv_info info;
} linalg_pinv_svd;

/* Factors A (m x n) with rank tolerance rtol as linalg_pinv. Same return
 * codes; F is filled in on LINALG_OK and LINALG_ERR_NOCONV. */
int linalg_pinv_factor(linalg_pinv_svd *F, const double *A, int m, int n, double rtol);
/* x (n) = A+ y, y has m entries. */
void linalg_pinv_apply(double *x, const linalg_pinv_svd *F, const double *y);
/* x (n) = A+ A g = V_r V_r^T g: the part of g in the row space of A
 * (g - x is its null-space part). x may alias g. */
void linalg_pinv_rowspace(double *x, const linalg_pinv_svd *F, const double *g);
/* M (k x n) = B (I - A+ A) = B - (B V_r) V_r^T for B (k x n, k <= LINALG_MAX):
 * the rows of B projected onto the null space of A. */
void linalg_pinv_null_rows(double *M, const double *B, int k, const linalg_pinv_svd *F);

/* Damped least-squares inverse Ad (n x m) = A^T (A A^T + lambda^2 I)^-1
 * (Wampler 1986). lambda > 0: Cholesky of the m x m SPD matrix (falls back
 * to the SVD form if rounding makes it fail). lambda == 0: the
 * pseudo-inverse with the default tolerance. */
int linalg_dls(double *Ad, const double *A, int m, int n, double lambda);

/* L (n x n, lower triangular, upper part zeroed) with A = L L^T. */
int linalg_cholesky(double *L, const double *A, int n);
/* Solves L L^T x = b for x (x may alias b). */
void linalg_cholesky_solve(double *x, const double *L, const double *b, int n);

#endif

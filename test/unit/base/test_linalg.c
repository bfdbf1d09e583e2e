/* Unit tests for linalg: SVD reconstruction and orthogonality, the four
 * Penrose conditions on full-rank, rank-deficient, exactly and nearly
 * singular matrices, null-space projector, Cholesky, damped least squares.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>

#include "linalg.h"

#define NN (LINALG_MAX * LINALG_MAX)

static unsigned long long rng_state = 88172645463325252ULL;

static double urand(void) /* uniform in [-1, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 4503599627370496.0 - 1.0;
}

static void rand_mat(double *A, int m, int n)
{
    int i;
    for (i = 0; i < m * n; i++)
        A[i] = urand();
}

/* Random matrix with orthonormal columns (n x k, k <= n), Gram-Schmidt twice. */
static void rand_orth(double *Q, int n, int k)
{
    int j, c, i, pass;
    for (j = 0; j < k; j++) {
        double nrm;
        do {
            for (i = 0; i < n; i++)
                Q[i * k + j] = urand();
            for (pass = 0; pass < 2; pass++)
                for (c = 0; c < j; c++) {
                    double d = 0.0;
                    for (i = 0; i < n; i++)
                        d += Q[i * k + c] * Q[i * k + j];
                    for (i = 0; i < n; i++)
                        Q[i * k + j] -= d * Q[i * k + c];
                }
            nrm = 0.0;
            for (i = 0; i < n; i++)
                nrm += Q[i * k + j] * Q[i * k + j];
            nrm = sqrt(nrm);
        } while (nrm < 1e-3);
        for (i = 0; i < n; i++)
            Q[i * k + j] /= nrm;
    }
}

/* A (m x n) = U diag(sv) V^T with random orthonormal U, V; sv has
 * min(m,n) entries (zeros make it rank-deficient). */
static void mat_with_sv(double *A, int m, int n, const double *sv)
{
    double U[NN], V[NN], US[NN];
    int p = m < n ? m : n;
    int i, k;
    rand_orth(U, m, p);
    rand_orth(V, n, p);
    for (i = 0; i < m; i++)
        for (k = 0; k < p; k++)
            US[i * p + k] = U[i * p + k] * sv[k];
    linalg_mul_t(A, US, V, m, p, n);
}

static double fro(const double *A, int count)
{
    double acc = 0.0;
    int i;
    for (i = 0; i < count; i++)
        acc += A[i] * A[i];
    return sqrt(acc);
}

/* Largest violation of the four Penrose conditions, each relative to the
 * natural scale of its terms. */
static double penrose_error(const double *A, const double *Ap, int m, int n)
{
    double AAp[NN], ApA[NN], T[NN], T2[NN];
    double nA = fro(A, m * n), nAp = fro(Ap, n * m);
    double e, worst = 0.0;

    linalg_mul(AAp, A, Ap, m, n, m);
    linalg_mul(ApA, Ap, A, n, m, n);
    linalg_mul(T, AAp, A, m, m, n); /* A A+ A */
    e = linalg_maxabs_diff(T, A, m, n) / (nA > 0 ? nA : 1.0);
    worst = e > worst ? e : worst;
    linalg_mul(T, ApA, Ap, n, n, m); /* A+ A A+ */
    e = linalg_maxabs_diff(T, Ap, n, m) / (nAp > 0 ? nAp : 1.0);
    worst = e > worst ? e : worst;
    linalg_transpose(T2, AAp, m, m);
    e = linalg_maxabs_diff(T2, AAp, m, m);
    worst = e > worst ? e : worst;
    linalg_transpose(T2, ApA, n, n);
    e = linalg_maxabs_diff(T2, ApA, n, n);
    worst = e > worst ? e : worst;
    return worst;
}

static void check_pinv_case(const double *A, int m, int n, int rank_expected, double tol);

static void check_svd(const double *A, int m, int n, double tol)
{
    double U[NN], V[NN], s[LINALG_MAX], US[NN], R[NN], G[NN], I[NN];
    int p = m < n ? m : n;
    int i, k, rc;
    double nA = fro(A, m * n);

    rc = linalg_svd(U, s, V, A, m, n);
    assert_int_equal(rc, LINALG_OK);
    for (k = 0; k < p; k++) {
        assert_true(s[k] >= 0.0);
        if (k > 0)
            assert_true(s[k] <= s[k - 1]);
    }
    for (i = 0; i < m; i++)
        for (k = 0; k < p; k++)
            US[i * p + k] = U[i * p + k] * s[k];
    linalg_mul_t(R, US, V, m, p, n);
    assert_true(linalg_maxabs_diff(R, A, m, n) <= tol * (nA > 1.0 ? nA : 1.0));
    linalg_identity(I, p);
    linalg_tmul(G, U, U, m, p, p);
    assert_true(linalg_maxabs_diff(G, I, p, p) <= tol);
    linalg_tmul(G, V, V, n, p, p);
    assert_true(linalg_maxabs_diff(G, I, p, p) <= tol);
}

static void test_svd_random_all_shapes(void **state)
{
    double A[NN];
    int m, n, trial;
    (void)state;
    for (m = 1; m <= LINALG_MAX; m++)
        for (n = 1; n <= LINALG_MAX; n++)
            for (trial = 0; trial < 40; trial++) {
                rand_mat(A, m, n);
                if (trial % 4 == 1)
                    A[0] *= 1e6; /* badly scaled */
                check_svd(A, m, n, 1e-13);
            }
}

static void test_svd_recovers_singular_values(void **state)
{
    static const int shapes[][2] = { { 3, 6 }, { 2, 6 }, { 6, 6 }, { 6, 3 }, { 5, 4 } };
    double A[NN], U[NN], V[NN], s[LINALG_MAX];
    double sv[LINALG_MAX] = { 7.0, 3.0, 1.0, 0.5, 1e-4, 1e-9 };
    size_t c;
    int k;
    (void)state;
    for (c = 0; c < sizeof shapes / sizeof shapes[0]; c++) {
        int m = shapes[c][0], n = shapes[c][1], p = m < n ? m : n;
        mat_with_sv(A, m, n, sv);
        assert_int_equal(linalg_svd(U, s, V, A, m, n), LINALG_OK);
        for (k = 0; k < p; k++)
            assert_true(fabs(s[k] - sv[k]) <= 1e-14 * sv[0]);
        check_svd(A, m, n, 1e-13);
    }
}

/* Wide inputs with LINALG_GRAM_ROWS rows can take the Gram
 * warm start; the SVD of A^T (tall) always takes the cold one-sided Jacobi
 * on the same vectors (the rows of A). Returns 1 if the two factorisations
 * of A are bit for bit the same (the warm start was declined). */
static int svd_same_as_cold(const double *A, int m, int n, double tol)
{
    double U[NN], V[NN], s[LINALG_MAX], Uc[NN], Vc[NN], sc[LINALG_MAX], At[NN];
    double P[NN], Pc[NN];
    int i, j, k, same = 1;

    linalg_transpose(At, A, m, n);
    assert_int_equal(linalg_svd(U, s, V, A, m, n), LINALG_OK);
    assert_int_equal(linalg_svd(Vc, sc, Uc, At, n, m), LINALG_OK); /* A = Uc S Vc^T */
    for (k = 0; k < m; k++) {
        assert_true(fabs(s[k] - sc[k]) <= 1e-14 * sc[0]);
        same = same && s[k] == sc[k];
    }
    for (i = 0; i < m * m; i++)
        same = same && U[i] == Uc[i];
    for (i = 0; i < n * m; i++)
        same = same && V[i] == Vc[i];
    /* singular vectors are defined up to sign (and rotation inside a
     * repeated sigma): compare the row-space projectors V V^T */
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            double a = 0.0, b = 0.0;
            for (k = 0; k < m; k++) {
                a += V[i * m + k] * V[j * m + k];
                b += Vc[i * m + k] * Vc[j * m + k];
            }
            P[i * n + j] = a;
            Pc[i * n + j] = b;
        }
    assert_true(linalg_maxabs_diff(P, Pc, n, n) <= tol);
    return same;
}

static void test_svd_gram_path_matches_cold(void **state)
{
    static const int shapes[][2] = { { 3, 6 }, { 2, 6 }, { 3, 4 }, { 2, 3 }, { 1, 6 } };
    static const double kappa[] = { 1.0, 10.0, 100.0, 900.0 };
    double A[NN], sv[LINALG_MAX], Ap[NN], Apc[NN], Apct[NN], At[NN];
    size_t c;
    int trial, k, n_warm = 0, n_all = 0;
    (void)state;
    for (c = 0; c < sizeof shapes / sizeof shapes[0]; c++) {
        int m = shapes[c][0], n = shapes[c][1];
        for (trial = 0; trial < 100; trial++) {
            double kap = kappa[trial % 4];
            /* well conditioned: sigma in [sigma_max / kappa, sigma_max] */
            sv[0] = 0.5 + (urand() + 1.0);
            for (k = 1; k < m; k++)
                sv[k] = sv[0] / kap * (1.0 + (kap - 1.0) * 0.5 * (urand() + 1.0));
            if (m > 1)
                sv[m - 1] = sv[0] / kap;
            mat_with_sv(A, m, n, sv);
            check_svd(A, m, n, 1e-13);
            check_pinv_case(A, m, n, m, 1e-12);
            if (!svd_same_as_cold(A, m, n, 1e-12)) {
                assert_int_equal(m, LINALG_GRAM_ROWS); /* other shapes: cold */
                n_warm++;
            }
            n_all += (m == LINALG_GRAM_ROWS && kap > 1.0);
            /* the same pseudo-inverse as the cold path's, (A^T)+^T */
            linalg_transpose(At, A, m, n);
            assert_int_equal(linalg_pinv(Ap, NULL, NULL, A, m, n, 0.0), LINALG_OK);
            assert_int_equal(linalg_pinv(Apc, NULL, NULL, At, n, m, 0.0), LINALG_OK);
            linalg_transpose(Apct, Apc, m, n);
            assert_true(linalg_maxabs_diff(Ap, Apct, n, m) <= 1e-12 * kap * kap / sv[0]);
        }
    }
    /* the warm start was really taken (at kappa = 1, G is already diagonal
     * and the warm start is the cold one) */
    assert_true(n_warm >= n_all * 9 / 10);
}

static void test_svd_gram_guard_declines_near_singular(void **state)
{
    static const double small[] = { 5e-4, 1e-7, 1e-12, 0.0 };
    double A[NN], sv[3];
    size_t c;
    int trial, j;
    (void)state;
    for (c = 0; c < sizeof small / sizeof small[0]; c++)
        for (trial = 0; trial < 25; trial++) {
            sv[0] = 2.0;
            sv[1] = 1.0;
            sv[2] = small[c] * 2.0; /* sigma_min / sigma_max < 1e-3 */
            mat_with_sv(A, 3, 6, sv);
            assert_true(svd_same_as_cold(A, 3, 6, 1e-12));
            sv[1] = sv[2];
            mat_with_sv(A, 2, 6, sv);
            assert_true(svd_same_as_cold(A, 2, 6, 1e-12));
        }
    for (trial = 0; trial < 25; trial++) { /* exactly rank-deficient */
        rand_mat(A, 3, 6);
        for (j = 0; j < 6; j++)
            A[2 * 6 + j] = A[0 * 6 + j];
        assert_true(svd_same_as_cold(A, 3, 6, 1e-12));
    }
}

static void test_svd_exactly_singular_and_zero(void **state)
{
    double A[6 * 6], Z[3 * 6] = { 0 };
    double U[NN], V[NN], s[LINALG_MAX];
    int j;
    (void)state;
    rand_mat(A, 6, 6);
    for (j = 0; j < 6; j++) {
        A[1 * 6 + j] = A[0 * 6 + j]; /* duplicate row */
        A[4 * 6 + j] = 0.0;          /* zero row */
    }
    check_svd(A, 6, 6, 1e-13);
    assert_int_equal(linalg_svd(U, s, V, A, 6, 6), LINALG_OK);
    assert_true(s[5] <= 1e-14 * s[0]);
    assert_true(s[4] <= 1e-14 * s[0]);
    assert_true(s[3] > 1e-3);
    check_svd(Z, 3, 6, 1e-15); /* all-zero: U, V still orthonormal */
    assert_int_equal(linalg_svd(U, s, V, Z, 3, 6), LINALG_OK);
    assert_true(s[0] == 0.0);
}

static void check_pinv_case(const double *A, int m, int n, int rank_expected, double tol)
{
    double Ap[NN], P[NN], T[NN], PP[NN];
    linalg_pinv_info info;
    int rc = linalg_pinv(Ap, P, &info, A, m, n, 0.0);
    assert_int_equal(rc, LINALG_OK);
    if (rank_expected >= 0)
        assert_int_equal(info.rank, rank_expected);
    assert_true(penrose_error(A, Ap, m, n) <= tol);
    /* P = I - A+ A: A P = 0, P symmetric idempotent */
    linalg_mul(T, A, P, m, n, n);
    assert_true(fro(T, m * n) <= tol * (fro(A, m * n) + 1.0));
    linalg_mul(PP, P, P, n, n, n);
    assert_true(linalg_maxabs_diff(PP, P, n, n) <= tol);
    linalg_transpose(T, P, n, n);
    assert_true(linalg_maxabs_diff(T, P, n, n) <= 1e-15);
}

static void test_pinv_penrose_full_and_deficient(void **state)
{
    static const int shapes[][2] = { { 3, 6 }, { 2, 6 }, { 6, 6 }, { 5, 6 }, { 6, 3 } };
    double A[NN], sv[LINALG_MAX];
    size_t c;
    int r, k, trial;
    (void)state;
    for (c = 0; c < sizeof shapes / sizeof shapes[0]; c++) {
        int m = shapes[c][0], n = shapes[c][1], p = m < n ? m : n;
        for (r = 0; r <= p; r++)
            for (trial = 0; trial < 25; trial++) {
                for (k = 0; k < p; k++)
                    sv[k] = (k < r) ? 0.1 + 3.0 * (urand() + 1.0) : 0.0;
                /* sort descending is not needed: mat_with_sv takes any order */
                mat_with_sv(A, m, n, sv);
                check_pinv_case(A, m, n, r, 1e-12);
            }
    }
}

static void test_pinv_exactly_singular_rows(void **state)
{
    double A[6 * 6], B[3 * 6];
    int j, trial;
    (void)state;
    for (trial = 0; trial < 50; trial++) {
        rand_mat(A, 6, 6);
        rand_mat(B, 3, 6);
        for (j = 0; j < 6; j++) {
            A[5 * 6 + j] = A[2 * 6 + j]; /* two identical rows */
            B[1 * 6 + j] = B[0 * 6 + j];
            if (trial % 2)
                B[2 * 6 + j] = 0.0; /* plus a zero row */
        }
        check_pinv_case(A, 6, 6, 5, 1e-12);
        check_pinv_case(B, 3, 6, (trial % 2) ? 1 : 2, 1e-12);
    }
}

static void test_pinv_nearly_singular(void **state)
{
    double A[NN], Ap[NN], AAp[NN], I[NN];
    double sv[LINALG_MAX] = { 2.0, 1.0, 1e-7 };
    double sv6[LINALG_MAX] = { 3.0, 2.0, 1.0, 0.5, 0.1, 1e-8 };
    linalg_pinv_info info;
    int trial;
    (void)state;
    for (trial = 0; trial < 50; trial++) {
        mat_with_sv(A, 3, 6, sv);
        /* kept: full row rank, so A A+ = I even though |A+| ~ 1e7 */
        check_pinv_case(A, 3, 6, 3, 1e-8);
        assert_int_equal(linalg_pinv(Ap, NULL, &info, A, 3, 6, 0.0), LINALG_OK);
        assert_true(fabs(info.sigma_min - 1e-7) < 1e-14);
        linalg_mul(AAp, A, Ap, 3, 6, 3);
        linalg_identity(I, 3);
        assert_true(linalg_maxabs_diff(AAp, I, 3, 3) <= 1e-8);
        mat_with_sv(A, 6, 6, sv6);
        check_pinv_case(A, 6, 6, 6, 1e-7);
        /* below the tolerance: treated as rank-deficient, Penrose exact */
        sv[2] = 1e-12;
        mat_with_sv(A, 3, 6, sv);
        check_pinv_case(A, 3, 6, 2, 1e-12);
        sv[2] = 1e-7;
    }
}

/* The factored form applies the same A+, A+ A and I - A+ A as the
 * explicit matrices of linalg_pinv, on full-rank, rank-deficient and nearly
 * singular inputs. */
static void test_pinv_factored_matches_explicit(void **state)
{
    static const int shapes[][2] = { { 3, 6 }, { 2, 6 }, { 6, 6 }, { 6, 3 } };
    double A[NN], Ap[NN], P[NN], B[3 * LINALG_MAX], M[3 * LINALG_MAX], Mref[3 * LINALG_MAX];
    double y[LINALG_MAX], g[LINALG_MAX], x[LINALG_MAX], xr[LINALG_MAX], sv[LINALG_MAX];
    linalg_pinv_svd F;
    linalg_pinv_info info;
    size_t c;
    int trial, k, i;
    (void)state;
    for (c = 0; c < sizeof shapes / sizeof shapes[0]; c++) {
        int m = shapes[c][0], n = shapes[c][1], p = m < n ? m : n;
        for (trial = 0; trial < 40; trial++) {
            for (k = 0; k < p; k++)
                sv[k] = 0.1 + (urand() + 1.0);
            if (trial % 4 == 1)
                sv[p - 1] = 0.0; /* rank-deficient */
            if (trial % 4 == 2)
                sv[p - 1] = 1e-7; /* nearly singular, kept */
            mat_with_sv(A, m, n, sv);
            assert_int_equal(linalg_pinv(Ap, P, &info, A, m, n, 0.0), LINALG_OK);
            assert_int_equal(linalg_pinv_factor(&F, A, m, n, 0.0), LINALG_OK);
            assert_int_equal(F.info.rank, info.rank);
            assert_true(F.info.sigma_max == info.sigma_max && F.info.sigma_min == info.sigma_min);
            rand_mat(y, m, 1);
            rand_mat(g, n, 1);
            linalg_pinv_apply(x, &F, y);
            linalg_matvec(xr, Ap, y, n, m);
            assert_true(linalg_maxabs_diff(x, xr, n, 1) <= 1e-12 * (1.0 + fro(Ap, n * m)));
            linalg_pinv_rowspace(x, &F, g); /* A+ A g = g - P g */
            linalg_matvec(xr, P, g, n, n);
            for (i = 0; i < n; i++)
                xr[i] = g[i] - xr[i];
            assert_true(linalg_maxabs_diff(x, xr, n, 1) <= 1e-13);
            linalg_copy(x, g, n, 1); /* in place */
            linalg_pinv_rowspace(x, &F, x);
            assert_true(linalg_maxabs_diff(x, xr, n, 1) <= 1e-13);
            rand_mat(B, 3, n);
            linalg_pinv_null_rows(M, B, 3, &F);
            linalg_mul(Mref, B, P, 3, n, n);
            assert_true(linalg_maxabs_diff(M, Mref, 3, n) <= 1e-13);
            linalg_mul_t(Mref, M, A, 3, n, m); /* rows of M are in null(A) */
            assert_true(fro(Mref, 3 * m) <= 1e-13 * (1.0 + fro(A, m * n)));
        }
    }
    assert_int_equal(linalg_pinv_factor(&F, A, 2, 7, 0.0), LINALG_ERR_SIZE);
    assert_int_equal(linalg_pinv_factor(&F, A, 2, 6, 1.0), LINALG_ERR_ARG);
}

static void test_pinv_zero_matrix_and_bad_input(void **state)
{
    double Z[2 * 6] = { 0 }, Ap[12], A[2 * 6];
    linalg_pinv_info info;
    int i;
    (void)state;
    assert_int_equal(linalg_pinv(Ap, NULL, &info, Z, 2, 6, 0.0), LINALG_OK);
    assert_int_equal(info.rank, 0);
    for (i = 0; i < 12; i++)
        assert_true(Ap[i] == 0.0);
    rand_mat(A, 2, 6);
    assert_int_equal(linalg_pinv(Ap, NULL, NULL, A, 2, 7, 0.0), LINALG_ERR_SIZE);
    assert_int_equal(linalg_pinv(Ap, NULL, NULL, A, 0, 6, 0.0), LINALG_ERR_SIZE);
    assert_int_equal(linalg_pinv(Ap, NULL, NULL, A, 2, 6, -1.0), LINALG_ERR_ARG);
    A[3] = NAN;
    assert_int_equal(linalg_pinv(Ap, NULL, NULL, A, 2, 6, 0.0), LINALG_ERR_NONFINITE);
    A[3] = INFINITY;
    assert_int_equal(linalg_svd(Ap, Z, Z, A, 2, 6), LINALG_ERR_NONFINITE);
}

static void test_mul_identities(void **state)
{
    double A[NN], B[NN], AB[NN], ABt[NN], At[NN], Bt[NN], C[NN];
    int trial;
    (void)state;
    for (trial = 0; trial < 20; trial++) {
        rand_mat(A, 3, 5);
        rand_mat(B, 5, 4);
        linalg_mul(AB, A, B, 3, 5, 4);
        linalg_transpose(ABt, AB, 3, 4);
        linalg_transpose(At, A, 3, 5);
        linalg_transpose(Bt, B, 5, 4);
        linalg_mul(C, Bt, At, 4, 5, 3); /* (AB)^T = B^T A^T */
        assert_true(linalg_maxabs_diff(C, ABt, 4, 3) <= 1e-15);
        linalg_tmul(C, At, B, 5, 3, 4); /* (A^T)^T B */
        assert_true(linalg_maxabs_diff(C, AB, 3, 4) <= 1e-15);
        linalg_mul_t(C, A, Bt, 3, 5, 4); /* A (B^T)^T */
        assert_true(linalg_maxabs_diff(C, AB, 3, 4) <= 1e-15);
    }
}

static void test_cholesky(void **state)
{
    double A[NN], G[NN], L[NN], R[NN], b[6], x[6], r[6];
    int n, i, trial;
    (void)state;
    for (n = 1; n <= 6; n++)
        for (trial = 0; trial < 20; trial++) {
            rand_mat(A, n, n);
            linalg_mul_t(G, A, A, n, n, n);
            for (i = 0; i < n; i++)
                G[i * n + i] += 0.1;
            assert_int_equal(linalg_cholesky(L, G, n), LINALG_OK);
            linalg_mul_t(R, L, L, n, n, n);
            assert_true(linalg_maxabs_diff(R, G, n, n) <= 1e-13);
            rand_mat(b, n, 1);
            linalg_cholesky_solve(x, L, b, n);
            linalg_matvec(r, G, x, n, n);
            assert_true(linalg_maxabs_diff(r, b, n, 1) <= 1e-10);
        }
    linalg_identity(G, 3);
    G[4] = -1.0;
    assert_int_equal(linalg_cholesky(L, G, 3), LINALG_ERR_NOT_PD);
}

static void test_dls(void **state)
{
    double A[NN], Ad[NN], Ap[NN], N[NN], R[NN], At[NN];
    double lambda;
    linalg_pinv_info info;
    int i, trial, j;
    (void)state;
    for (trial = 0; trial < 40; trial++) {
        int m = (trial % 2) ? 3 : 6;
        rand_mat(A, m, 6);
        if (trial % 4 == 3)
            for (j = 0; j < 6; j++)
                A[1 * 6 + j] = A[0 * 6 + j]; /* singular: DLS still defined */
        lambda = 0.05 + 0.5 * (urand() + 1.0);
        assert_int_equal(linalg_dls(Ad, A, m, 6, lambda), LINALG_OK);
        /* normal equations of min |A x - y|^2 + lambda^2 |x|^2:
         * (A^T A + lambda^2 I) Ad = A^T */
        linalg_tmul(N, A, A, m, 6, 6);
        for (i = 0; i < 6; i++)
            N[i * 6 + i] += lambda * lambda;
        linalg_mul(R, N, Ad, 6, 6, m);
        linalg_transpose(At, A, m, 6);
        assert_true(linalg_maxabs_diff(R, At, 6, m) <= 1e-12);
        /* lambda = 0 is the pseudo-inverse */
        assert_int_equal(linalg_dls(Ad, A, m, 6, 0.0), LINALG_OK);
        assert_int_equal(linalg_pinv(Ap, NULL, &info, A, m, 6, 0.0), LINALG_OK);
        assert_true(linalg_maxabs_diff(Ad, Ap, 6, m) <= 1e-12);
        /* small damping on a full-rank matrix approaches it: the gap per
         * singular value is lambda^2 / (sigma (sigma^2 + lambda^2)) */
        if (trial % 4 != 3) {
            double smin = info.sigma_min;
            assert_int_equal(linalg_dls(Ad, A, m, 6, 1e-7), LINALG_OK);
            assert_true(linalg_maxabs_diff(Ad, Ap, 6, m) <=
                        2e-14 / (smin * smin * smin) + 1e-12 / (smin * smin));
        }
    }
    assert_int_equal(linalg_dls(Ad, A, 3, 6, -0.1), LINALG_ERR_ARG);
}

/* linalg_all_finite against the entry-by-entry isfinite test: every
 * length 0..11 (the four-sum loop and its tail), a NaN, +Inf or -Inf at
 * every position, and the largest finite values (whose differences are 0). */
static void test_all_finite_every_position(void **state)
{
    const double bad[3] = { NAN, INFINITY, -INFINITY };
    double A[12];
    int n, k, b, i;
    (void)state;
    for (i = 0; i < 12; i++)
        A[i] = (i % 2 ? -1.0 : 1.0) * DBL_MAX;
    for (n = 0; n <= 12; n++) {
        assert_int_equal(linalg_all_finite(A, n), 1);
        for (k = 0; k < n; k++)
            for (b = 0; b < 3; b++) {
                const double keep = A[k];
                A[k] = bad[b];
                assert_int_equal(linalg_all_finite(A, n), 0);
                A[k] = keep;
            }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_svd_random_all_shapes),
        cmocka_unit_test(test_svd_recovers_singular_values),
        cmocka_unit_test(test_svd_gram_path_matches_cold),
        cmocka_unit_test(test_svd_gram_guard_declines_near_singular),
        cmocka_unit_test(test_svd_exactly_singular_and_zero),
        cmocka_unit_test(test_pinv_penrose_full_and_deficient),
        cmocka_unit_test(test_pinv_exactly_singular_rows),
        cmocka_unit_test(test_pinv_nearly_singular),
        cmocka_unit_test(test_pinv_factored_matches_explicit),
        cmocka_unit_test(test_pinv_zero_matrix_and_bad_input),
        cmocka_unit_test(test_mul_identities),
        cmocka_unit_test(test_cholesky),
        cmocka_unit_test(test_dls),
        cmocka_unit_test(test_all_finite_every_position),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for prng: reproducibility (same seed, same stream), independent
 * streams for different seeds, and the distribution of the uniform and
 * Gaussian draws (moments checked against their sampling error), including
 * the extreme raw outputs that drive Box-Muller to its edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "prng.h"

#define N_DRAWS 100000
/* 5 standard errors: a correct generator fails a check with p ~ 6e-7. */
#define N_SIGMA 5.0

static void test_same_seed_same_stream(void **state)
{
    prng_state a, b;
    int i;
    (void)state;
    prng_seed(&a, UINT64_C(0x0123456789ABCDEF));
    prng_seed(&b, UINT64_C(0x0123456789ABCDEF));
    for (i = 0; i < 1000; i++)
        assert_true(prng_u64(&a) == prng_u64(&b));
    for (i = 0; i < 1000; i++)
        assert_true(prng_uniform(&a) == prng_uniform(&b));
    for (i = 0; i < 1000; i++)
        assert_true(prng_gauss(&a) == prng_gauss(&b));
    /* re-seeding restarts the stream */
    {
        uint64_t first[16];
        prng_seed(&a, 42);
        for (i = 0; i < 16; i++)
            first[i] = prng_u64(&a);
        for (i = 0; i < 100; i++)
            (void)prng_u64(&a);
        prng_seed(&a, 42);
        for (i = 0; i < 16; i++)
            assert_true(prng_u64(&a) == first[i]);
    }
}

static void test_different_seeds_differ(void **state)
{
    enum { SEEDS = 64, LEN = 32 };
    static uint64_t out[SEEDS][LEN];
    prng_state r;
    int s, t, i;
    (void)state;
    /* neighbouring small seeds (1, 2, 3, ...) are the usual case: robot ids */
    for (s = 0; s < SEEDS; s++) {
        prng_seed(&r, (uint64_t)s);
        for (i = 0; i < LEN; i++)
            out[s][i] = prng_u64(&r);
    }
    for (s = 0; s < SEEDS; s++)
        for (t = s + 1; t < SEEDS; t++) {
            int same = 0;
            for (i = 0; i < LEN; i++)
                same += out[s][i] == out[t][i];
            assert_int_equal(same, 0);
        }
    /* a stream does not repeat its own recent values */
    for (s = 0; s < SEEDS; s++)
        for (i = 0; i < LEN; i++)
            for (t = i + 1; t < LEN; t++)
                assert_true(out[s][i] != out[s][t]);
}

static void test_uniform_moments(void **state)
{
    prng_state r;
    double sum = 0.0, sum2 = 0.0, lag = 0.0, prev = 0.5, mean, var, cov;
    long bins[10] = { 0 };
    double chi2 = 0.0;
    long bit_set[64] = { 0 };
    int i, b;
    (void)state;
    prng_seed(&r, 7);
    for (i = 0; i < N_DRAWS; i++) {
        const double u = prng_uniform(&r);
        assert_true(u >= 0.0 && u < 1.0);
        sum += u;
        sum2 += u * u;
        lag += (u - 0.5) * (prev - 0.5);
        prev = u;
        bins[(int)(u * 10.0)]++;
    }
    mean = sum / N_DRAWS;
    var = sum2 / N_DRAWS - mean * mean;
    cov = lag / N_DRAWS;
    /* se(mean) = sqrt(1/12 / N); se(var) = sqrt((1/80 - 1/144) / N);
     * se(lag-1 covariance) = (1/12) / sqrt(N) */
    assert_true(fabs(mean - 0.5) < N_SIGMA * sqrt(1.0 / 12.0 / N_DRAWS));
    assert_true(fabs(var - 1.0 / 12.0) < N_SIGMA * sqrt((1.0 / 80.0 - 1.0 / 144.0) / N_DRAWS));
    assert_true(fabs(cov) < N_SIGMA * (1.0 / 12.0) / sqrt((double)N_DRAWS));
    /* 10 equal bins: chi-square with 9 dof, 0.9999 quantile is 33.7 */
    for (b = 0; b < 10; b++) {
        const double e = N_DRAWS / 10.0;
        chi2 += (bins[b] - e) * (bins[b] - e) / e;
    }
    assert_true(chi2 < 33.7);
    /* every raw bit is a fair coin: se of a count = sqrt(N / 4) */
    prng_seed(&r, 8);
    for (i = 0; i < N_DRAWS; i++) {
        const uint64_t x = prng_u64(&r);
        for (b = 0; b < 64; b++)
            bit_set[b] += (long)((x >> b) & 1u);
    }
    for (b = 0; b < 64; b++)
        assert_true(fabs(bit_set[b] - N_DRAWS / 2.0) < N_SIGMA * sqrt(N_DRAWS / 4.0));
}

static void test_gauss_moments(void **state)
{
    prng_state r;
    double sum = 0.0, sum2 = 0.0, sum3 = 0.0, sum4 = 0.0, mean, var;
    long in1 = 0;
    const double p1 = erf(1.0 / sqrt(2.0)); /* P(|X| < 1) */
    int i;
    (void)state;
    prng_seed(&r, 11);
    for (i = 0; i < N_DRAWS; i++) {
        const double g = prng_gauss(&r);
        assert_false(isnan(g));
        assert_true(isfinite(g));
        sum += g;
        sum2 += g * g;
        sum3 += g * g * g;
        sum4 += g * g * g * g;
        in1 += fabs(g) < 1.0;
    }
    mean = sum / N_DRAWS;
    var = sum2 / N_DRAWS - mean * mean;
    /* se(mean) = 1/sqrt(N); se(E x^2) = sqrt(2/N); se(E x^3) = sqrt(15/N);
     * se(E x^4) = sqrt(96/N) */
    assert_true(fabs(mean) < N_SIGMA / sqrt((double)N_DRAWS));
    assert_true(fabs(var - 1.0) < N_SIGMA * sqrt(2.0 / N_DRAWS));
    assert_true(fabs(sum3 / N_DRAWS) < N_SIGMA * sqrt(15.0 / N_DRAWS));
    assert_true(fabs(sum4 / N_DRAWS - 3.0) < N_SIGMA * sqrt(96.0 / N_DRAWS));
    assert_true(fabs((double)in1 / N_DRAWS - p1) < N_SIGMA * sqrt(p1 * (1.0 - p1) / N_DRAWS));
}

/* splitmix64's output mix is a bijection; invert it to build a state whose
 * next raw output is a chosen value. */
static uint64_t inv_mul(uint64_t a)
{
    uint64_t x = a; /* a odd: Newton doubles the correct bits */
    int i;
    for (i = 0; i < 6; i++)
        x *= 2u - a * x;
    return x;
}

static uint64_t inv_xorshift(uint64_t y, int k)
{
    uint64_t x = y;
    int i;
    for (i = 0; i < 64 / k + 1; i++)
        x = y ^ (x >> k);
    return x;
}

static uint64_t state_for_output(uint64_t out)
{
    uint64_t z = inv_xorshift(out, 31);
    z = inv_xorshift(z * inv_mul(UINT64_C(0x94D049BB133111EB)), 27);
    z = inv_xorshift(z * inv_mul(UINT64_C(0xBF58476D1CE4E5B9)), 30);
    return z - UINT64_C(0x9E3779B97F4A7C15);
}

static void test_extreme_outputs(void **state)
{
    const uint64_t extremes[] = { 0, ~UINT64_C(0), UINT64_C(1) << 11, ~UINT64_C(0) << 11,
                                  UINT64_C(0x7FF) };
    prng_state r;
    size_t i, j;
    (void)state;
    for (i = 0; i < sizeof extremes / sizeof extremes[0]; i++) {
        double u;
        prng_seed(&r, state_for_output(extremes[i]));
        assert_true(prng_u64(&r) == extremes[i]); /* the inversion is right */
        prng_seed(&r, state_for_output(extremes[i]));
        u = prng_uniform(&r);
        assert_true(u >= 0.0 && u < 1.0);
        /* either Box-Muller input at an extreme: still a finite number */
        for (j = 0; j < 2; j++) {
            double g;
            prng_seed(&r, state_for_output(extremes[i]) - j * UINT64_C(0x9E3779B97F4A7C15));
            g = prng_gauss(&r);
            assert_true(isfinite(g));
            assert_true(fabs(g) < 9.0); /* 53-bit inputs bound |g| by sqrt(2 ln 2^53) */
        }
    }
    prng_seed(&r, state_for_output(~UINT64_C(0)));
    assert_true(prng_uniform(&r) == 1.0 - ldexp(1.0, -53));
    prng_seed(&r, state_for_output(0));
    assert_true(prng_uniform(&r) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_seed_same_stream), cmocka_unit_test(test_different_seeds_differ),
        cmocka_unit_test(test_uniform_moments),       cmocka_unit_test(test_gauss_moments),
        cmocka_unit_test(test_extreme_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

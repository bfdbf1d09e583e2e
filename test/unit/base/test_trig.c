/* Unit tests for trig: trig_atan2 and trig_exp agree with libm to a few
 * ulps (every quadrant, the interval ends, signed zeros, the cut-overs);
 * trig_sincos agrees with libm's sin and cos over the
 * joint angles a cycle sees and beyond (seeded random, multiples of pi/2
 * and their neighbours, where the reduction cancels most), keeps
 * sin^2 + cos^2 = 1, is odd/even, and hands huge and non-finite angles to
 * libm. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>

#include "prng.h"
#include "trig.h"

/* a few ulps of 1: libm itself is not correctly rounded everywhere (and
 * the 68040's under qemu is its extended-precision instruction) */
#define TOL 1e-15

static void check_against_libm(double x)
{
    double s, c;
    trig_sincos(x, &s, &c);
    assert_true(fabs(s - sin(x)) <= TOL);
    assert_true(fabs(c - cos(x)) <= TOL);
    assert_true(fabs(s * s + c * c - 1.0) <= 4e-16);
}

static void test_random_angles(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 26);
    for (i = 0; i < 20000; i++)
        check_against_libm(20.0 * (prng_uniform(&r) - 0.5));
    for (i = 0; i < 2000; i++)
        check_against_libm(2000.0 * (prng_uniform(&r) - 0.5));
}

static void test_quarter_turns(void **state)
{
    int k;
    (void)state;
    for (k = -40; k <= 40; k++) {
        const double x = k * 1.57079632679489661923;
        check_against_libm(x);
        check_against_libm(nextafter(x, 1e9));
        check_against_libm(nextafter(x, -1e9));
        check_against_libm(x + 1e-9);
        check_against_libm(x - 1e-9);
    }
    {
        /* cos(pi/2) is the tiny 6.1e-17 the tables hold: relative accuracy
         * there needs the second reduction round */
        double s, c;
        trig_sincos(1.57079632679489661923, &s, &c);
        assert_true(fabs(c - 6.123233995736766e-17) <= 1e-30);
        assert_true(s == 1.0);
    }
}

static void test_symmetry_and_zero(void **state)
{
    double s, c, s2, c2;
    int i;
    (void)state;
    trig_sincos(0.0, &s, &c);
    assert_true(s == 0.0 && c == 1.0);
    for (i = 1; i < 100; i++) {
        const double x = 0.0731 * i;
        trig_sincos(x, &s, &c);
        trig_sincos(-x, &s2, &c2);
        assert_true(s2 == -s && c2 == c);
    }
}

static void test_huge_and_nonfinite(void **state)
{
    double s, c;
    (void)state;
    /* libm's answer (qemu's 68040 sin and sincos differ past 1e-14 there) */
    trig_sincos(1e7, &s, &c);
    assert_true(fabs(s - sin(1e7)) <= 1e-12 && fabs(c - cos(1e7)) <= 1e-12);
    trig_sincos(NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
    trig_sincos(INFINITY, &s, &c);
    assert_true(isnan(s) && isnan(c));
    check_against_libm(TRIG_REDUCE_MAX_RAD * 0.999);
}

/* a and b within two ulps of b: either libm may be an ulp off */
static int same_within_ulps(double a, double b)
{
    return fabs(a - b) <= 2.0 * DBL_EPSILON * fmax(fabs(b), DBL_MIN);
}

/* atan2 on every quadrant, the axes, signed zeros, near the reduction's
 * interval ends and far out */
static void test_atan2_against_libm(void **state)
{
    static const double ends[] = { 0.4375, 0.6875, 1.1875, 2.4375 };
    prng_state r;
    int i, k;
    (void)state;
    prng_seed(&r, 126);
    for (i = 0; i < 20000; i++) {
        const double y = 4.0 * (prng_uniform(&r) - 0.5), x = 4.0 * (prng_uniform(&r) - 0.5);
        const double scale = (i & 1) ? 1e-3 : 1e3;
        assert_true(same_within_ulps(trig_atan2(y, x), atan2(y, x)));
        assert_true(same_within_ulps(trig_atan2(y * scale, x), atan2(y * scale, x)));
    }
    for (k = 0; k < 4; k++)
        for (i = -3; i <= 3; i++) {
            const double t = nextafter(ends[k], i < 0 ? 0.0 : 10.0) + i * 1e-12;
            assert_true(same_within_ulps(trig_atan2(t, 1.0), atan2(t, 1.0)));
            assert_true(same_within_ulps(trig_atan2(-t, -1.0), atan2(-t, -1.0)));
        }
    assert_true(trig_atan2(0.0, 1.0) == 0.0 && !signbit(trig_atan2(0.0, 1.0)));
    assert_true(trig_atan2(-0.0, 1.0) == 0.0 && signbit(trig_atan2(-0.0, 1.0)));
    assert_true(trig_atan2(0.0, -1.0) == atan2(0.0, -1.0));
    assert_true(trig_atan2(-0.0, -1.0) == atan2(-0.0, -1.0));
    assert_true(trig_atan2(0.0, -0.0) == atan2(0.0, -0.0));
    assert_true(trig_atan2(2.0, 0.0) == atan2(2.0, 0.0) &&
                trig_atan2(-2.0, 0.0) == atan2(-2.0, 0.0));
    assert_true(isnan(trig_atan2(NAN, 1.0)) && trig_atan2(1.0, INFINITY) == 0.0);
}

/* exp relative to libm's, over the range the bias of eq. 7 sees and out
 * to the cut-over, and the cut-over itself */
static void test_exp_against_libm(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 127);
    for (i = 0; i < 20000; i++) {
        const double x = (i & 1) ? 100.0 * (prng_uniform(&r) - 0.5)
                                 : 1400.0 * (prng_uniform(&r) - 0.5);
        assert_true(same_within_ulps(trig_exp(x), exp(x)));
    }
    assert_true(trig_exp(0.0) == 1.0);
    {
        /* libm's values, rounded to double (the 68040 returns them in
         * extended, where exp(-800) is not yet 0) */
        volatile double big = exp(800.0), tiny = exp(-800.0);
        volatile double big2 = trig_exp(800.0), tiny2 = trig_exp(-800.0);
        assert_true(big2 == big && tiny2 == tiny);
    }
    assert_true(isnan(trig_exp(NAN)));
    {
        /* handed to libm: whatever it says (qemu's 68040 differs here) */
        const double a = trig_exp(-INFINITY), b = exp(-INFINITY);
        assert_true(a == b || (isnan(a) && isnan(b)));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_angles),      cmocka_unit_test(test_quarter_turns),
        cmocka_unit_test(test_symmetry_and_zero),  cmocka_unit_test(test_huge_and_nonfinite),
        cmocka_unit_test(test_atan2_against_libm), cmocka_unit_test(test_exp_against_libm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

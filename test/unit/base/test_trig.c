/* Unit tests for trig: trig_sincos agrees with libm's sin and cos over the
 * joint angles a cycle sees and beyond (seeded random, multiples of pi/2
 * and their neighbours, where the reduction cancels most), keeps
 * sin^2 + cos^2 = 1, is odd/even, and hands huge and non-finite angles to
 * libm. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
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
    trig_sincos(1e7, &s, &c);
    assert_true(s == sin(1e7) && c == cos(1e7));
    trig_sincos(NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
    trig_sincos(INFINITY, &s, &c);
    assert_true(isnan(s) && isnan(c));
    check_against_libm(TRIG_REDUCE_MAX_RAD * 0.999);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_angles),
        cmocka_unit_test(test_quarter_turns),
        cmocka_unit_test(test_symmetry_and_zero),
        cmocka_unit_test(test_huge_and_nonfinite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

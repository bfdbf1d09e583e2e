/* Unit tests for loopstats: exact min/mean/max, histogram percentiles. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>
#include "loopstats.h"

static loopstats s;

static void test_empty_is_zero(void **state)
{
    (void)state;
    loopstats_reset(&s);
    assert_int_equal(s.count, 0);
    assert_true(loopstats_mean(&s) == 0.0);
    assert_true(loopstats_percentile(&s, 0.99) == 0.0);
}

static void test_min_mean_max_exact(void **state)
{
    int i;
    (void)state;
    loopstats_reset(&s);
    for (i = 1; i <= 100; i++)
        assert_int_equal(loopstats_add(&s, (double)i + 0.25), 0);
    assert_int_equal(s.count, 100);
    assert_true(fabs(s.min_us - 1.25) < 1e-12);
    assert_true(fabs(s.max_us - 100.25) < 1e-12);
    assert_true(fabs(loopstats_mean(&s) - 50.75) < 1e-9);
}

static void test_percentile_within_one_bin(void **state)
{
    int i;
    double p99, p50;
    (void)state;
    loopstats_reset(&s);
    /* 1000 samples 0.5, 1.5, ..., 999.5: true p99 = 989.5, p50 = 499.5 */
    for (i = 0; i < 1000; i++)
        loopstats_add(&s, (double)i + 0.5);
    p99 = loopstats_percentile(&s, 0.99);
    p50 = loopstats_percentile(&s, 0.50);
    assert_true(p99 >= 989.5 && p99 <= 989.5 + LOOPSTATS_BIN_US);
    assert_true(p50 >= 499.5 && p50 <= 499.5 + LOOPSTATS_BIN_US);
    assert_true(loopstats_percentile(&s, 1.0) <= s.max_us);
}

static void test_overflow_bin_reports_max(void **state)
{
    int i;
    (void)state;
    loopstats_reset(&s);
    for (i = 0; i < 98; i++)
        loopstats_add(&s, 10.0);
    loopstats_add(&s, 50000.0);
    loopstats_add(&s, 70000.0);
    /* p99 falls in the overflow bin: reported as the exact max, not the bin edge */
    assert_true(loopstats_percentile(&s, 0.995) == 70000.0);
    assert_true(loopstats_percentile(&s, 0.5) <= 11.0);
}

static void test_rejects_bad_samples(void **state)
{
    (void)state;
    loopstats_reset(&s);
    assert_int_equal(loopstats_add(&s, -1.0), LOOPSTATS_ERR_ARG);
    assert_int_equal(loopstats_add(&s, NAN), LOOPSTATS_ERR_ARG);
    assert_int_equal(loopstats_add(&s, INFINITY), LOOPSTATS_ERR_ARG);
    assert_int_equal(s.count, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_empty_is_zero),
        cmocka_unit_test(test_min_mean_max_exact),
        cmocka_unit_test(test_percentile_within_one_bin),
        cmocka_unit_test(test_overflow_bin_reports_max),
        cmocka_unit_test(test_rejects_bad_samples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

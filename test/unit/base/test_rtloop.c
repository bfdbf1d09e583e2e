/* Unit tests for rtloop: absolute deadlines do not drift, overruns are
 * counted and skipped, period bounds are enforced. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <time.h>
#include <cmocka.h>
#include "rtloop.h"

static rtloop l;

static void busy_ns(int64_t ns)
{
    const int64_t t0 = rtloop_now_ns();
    while (rtloop_now_ns() - t0 < ns) {
    }
}

static void test_rejects_bad_period(void **state)
{
    (void)state;
    assert_int_equal(rtloop_init(&l, 0), RTLOOP_ERR_RANGE);
    assert_int_equal(rtloop_init(&l, 1000), RTLOOP_ERR_RANGE);
    assert_int_equal(rtloop_init(&l, RTLOOP_MAX_PERIOD_NS + 1), RTLOOP_ERR_RANGE);
    assert_int_equal(rtloop_init(&l, 1000000), 0);
}

static void test_deadlines_do_not_drift(void **state)
{
    int i;
    int64_t t0, elapsed;
    (void)state;
    assert_int_equal(rtloop_init(&l, 2000000), 0); /* 2 ms */
    t0 = l.next_ns - l.period_ns;
    for (i = 0; i < 50; i++) {
        rtloop_wait(&l);
        busy_ns(200000); /* work: 0.2 ms */
        rtloop_end_cycle(&l);
    }
    /* Deadlines stay on the t0 + k*period grid whatever the work took
     * (relative sleeps would drift by 0.2 ms per cycle); the wall-clock
     * bound is one-sided so a loaded machine cannot make this flaky. */
    elapsed = l.wake_ns - t0;
    assert_true(elapsed >= 50 * 2000000LL);
    assert_int_equal((l.next_ns - t0) % l.period_ns, 0);
    if (l.overruns == 0)
        assert_true(l.next_ns - t0 == 51 * l.period_ns);
    assert_int_equal(l.cycles, 50);
    assert_true(l.cycle.min_us >= 200.0);
}

static void test_overrun_counted_and_skipped(void **state)
{
    int64_t before;
    (void)state;
    assert_int_equal(rtloop_init(&l, 1000000), 0); /* 1 ms */
    rtloop_wait(&l);
    busy_ns(3500000); /* 3.5 ms of work */
    before = l.next_ns;
    rtloop_end_cycle(&l);
    assert_int_equal(l.overruns, 1);
    /* the next deadline is in the future, aligned to the period grid */
    assert_true(l.next_ns > rtloop_now_ns());
    assert_int_equal((l.next_ns - before) % l.period_ns, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rejects_bad_period),
        cmocka_unit_test(test_deadlines_do_not_drift),
        cmocka_unit_test(test_overrun_counted_and_skipped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

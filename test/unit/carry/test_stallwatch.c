/* Unit tests for stallwatch: the supervisor's progress watchdog. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "stallwatch.h"

/* Runs the watch at 10 ms steps from t0 for dur_s; returns the number of
 * updates that reported a stall beginning, and the time of the first. */
static int run(stallwatch *w, double t0, double dur_s, int pending, int obstructed, double *t_first)
{
    int k, n = 0;
    const int steps = (int)(dur_s / 0.01 + 0.5);
    for (k = 0; k <= steps; k++) {
        const double t = t0 + 0.01 * k;
        if (stallwatch_update(w, t, 0, pending, obstructed) == 1) {
            if (n == 0 && t_first)
                *t_first = t;
            n++;
        }
    }
    return n;
}

static void test_stall_after_limit(void **st)
{
    stallwatch w;
    double t_first = -1.0;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 2.0), STALLWATCH_OK);
    assert_int_equal(run(&w, 0.0, 5.0, 1, 0, &t_first), 1); /* once, not every cycle */
    assert_true(fabs(t_first - 2.01) < 0.011);              /* just past the limit */
    assert_int_equal(w.stalled, 1);
    assert_int_equal(w.stalls, 1);
    /* a completion ends it; a second stall is counted again */
    assert_int_equal(stallwatch_update(&w, 5.02, 1, 1, 0), 0);
    assert_int_equal(w.stalled, 0);
    assert_int_equal(run(&w, 5.03, 3.0, 1, 0, NULL), 1);
    assert_int_equal(w.stalls, 2);
}

static void test_progress_keeps_it_quiet(void **st)
{
    stallwatch w;
    int k;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 2.0), STALLWATCH_OK);
    /* a completion every 1.9 s: never a stall over 100 s */
    for (k = 0; k < 10000; k++)
        assert_int_equal(stallwatch_update(&w, 0.01 * k, k % 190 == 0, 1, 0), 0);
    assert_int_equal(w.stalls, 0);
}

static void test_obstruction_restarts_count(void **st)
{
    stallwatch w;
    double t_first = -1.0;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 2.0), STALLWATCH_OK);
    assert_int_equal(run(&w, 0.0, 1.5, 1, 0, NULL), 0);
    /* the stick is in for 60 s: no stall however long */
    assert_int_equal(run(&w, 1.51, 60.0, 1, 1, NULL), 0);
    /* out: the arm has 2 s again (not the 0.5 s left before the block) */
    assert_int_equal(run(&w, 61.52, 1.9, 1, 0, NULL), 0);
    assert_int_equal(run(&w, 63.43, 1.0, 1, 0, &t_first), 1);
    /* counted from the last obstructed update (61.51 s) */
    assert_true(t_first > 61.51 + 2.0 && t_first < 61.51 + 2.02);
}

/* A stick that never comes out (or one the cell wrongly believes in)
 * excuses the cell only for obstruct_max_s; then limit_s more is a stall. */
static void test_endless_obstruction_stalls(void **st)
{
    stallwatch w;
    double t_first = -1.0;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 2.0), STALLWATCH_OK);
    assert_true(w.obstruct_max_s == STALLWATCH_OBSTRUCT_MAX_S);
    assert_int_equal(stallwatch_set_obstruct_max(&w, 10.0), STALLWATCH_OK);
    assert_int_equal(stallwatch_set_obstruct_max(&w, 0.0), STALLWATCH_ERR_ARG);
    assert_int_equal(run(&w, 0.0, 30.0, 1, 1, &t_first), 1);
    assert_true(t_first > 12.0 && t_first < 12.05);
    /* a completion ends it and the next obstruction is excused again */
    assert_int_equal(stallwatch_update(&w, 30.01, 1, 1, 1), 0);
    assert_int_equal(w.stalled, 0);
    assert_int_equal(run(&w, 30.02, 9.0, 1, 1, NULL), 0);
}

static void test_idle_cell_is_not_stalled(void **st)
{
    stallwatch w;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 2.0), STALLWATCH_OK);
    assert_int_equal(run(&w, 0.0, 30.0, 0, 0, NULL), 0);       /* nothing to do */
    assert_int_equal(run(&w, 30.01, 3.0, 1, 0, NULL), 1);      /* work came, none done */
    assert_int_equal(stallwatch_update(&w, 33.1, 0, 0, 0), 0); /* work gone: no longer stalled */
    assert_int_equal(w.stalled, 0);
}

static void test_bad_input(void **st)
{
    stallwatch w;
    (void)st;
    assert_int_equal(stallwatch_init(&w, 0.0), STALLWATCH_ERR_ARG);
    assert_int_equal(stallwatch_init(&w, NAN), STALLWATCH_ERR_ARG);
    assert_int_equal(stallwatch_init(NULL, 1.0), STALLWATCH_ERR_ARG);
    assert_int_equal(stallwatch_init(&w, 1.0), STALLWATCH_OK);
    assert_int_equal(stallwatch_update(&w, 5.0, 0, 1, 0), 0);
    /* time going backwards or NaN changes nothing */
    assert_int_equal(stallwatch_update(&w, 4.0, 0, 1, 0), STALLWATCH_ERR_ARG);
    assert_int_equal(stallwatch_update(&w, NAN, 0, 1, 0), STALLWATCH_ERR_ARG);
    assert_true(w.last_t_s == 5.0 && w.idle_s == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stall_after_limit),
        cmocka_unit_test(test_progress_keeps_it_quiet),
        cmocka_unit_test(test_obstruction_restarts_count),
        cmocka_unit_test(test_endless_obstruction_stalls),
        cmocka_unit_test(test_idle_cell_is_not_stalled),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

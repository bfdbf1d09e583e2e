/* Unit tests for jtraj: rest to rest, bounds respected (finite differences),
 * velocity and acceleration consistent with position; the controlled stop
 * (docs/method/carry.md §7.4) by its identities: never faster than at its
 * start nor reversing, at rest by |v|/a, v^2 = 2 a d, continuous, its
 * derivatives those of its position, and a replan from where it rests
 * joining it at rest. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>
#include "jtraj.h"

static const double q0[ARM_NJ] = { 0.1, 0.6, 2.9, 0.0, -0.4, 0.2 };
static const double q1[ARM_NJ] = { 1.2, -0.3, 2.0, 1.5, 0.8, -2.5 };

static void test_rest_to_rest_endpoints(void **state)
{
    jtraj t;
    double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
    int i;
    (void)state;
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, 0.5, 2.0), 0);
    assert_true(t.duration_s > 0.0);
    jtraj_at(&t, 0.0, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++) {
        assert_true(fabs(q[i] - q0[i]) < 1e-15);
        assert_true(qd[i] == 0.0);
    }
    jtraj_at(&t, t.duration_s, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++) {
        assert_true(fabs(q[i] - q1[i]) < 1e-12);
        assert_true(qd[i] == 0.0 && qdd[i] == 0.0);
    }
    /* clamped outside [0, T] */
    jtraj_at(&t, t.duration_s + 5.0, q, qd, qdd);
    assert_true(fabs(q[5] - q1[5]) < 1e-12);
}

static void test_bounds_and_derivatives(void **state)
{
    jtraj t;
    const double frac = 0.4, acc = 1.5, h = 1e-5;
    double qa[ARM_NJ], qb[ARM_NJ], q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], qda[ARM_NJ], qdb[ARM_NJ],
        tmp[ARM_NJ];
    int i, k;
    (void)state;
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, frac, acc), 0);
    for (k = 1; k < 200; k++) {
        const double s = t.duration_s * k / 200.0;
        jtraj_at(&t, s, q, qd, qdd);
        jtraj_at(&t, s - h, qa, qda, tmp);
        jtraj_at(&t, s + h, qb, qdb, tmp);
        for (i = 0; i < ARM_NJ; i++) {
            assert_true(fabs(qd[i]) <= frac * arm_model_puma560.qd_max_radps[i] * (1.0 + 1e-9));
            assert_true(fabs(qdd[i]) <= acc * (1.0 + 1e-9));
            assert_true(fabs((qb[i] - qa[i]) / (2.0 * h) - qd[i]) < 1e-6);
            assert_true(fabs((qdb[i] - qda[i]) / (2.0 * h) - qdd[i]) < 1e-5);
        }
    }
}

static void test_duration_is_tight(void **state)
{
    /* The shortest duration: some joint reaches its speed or acceleration
     * bound (otherwise the plan would be needlessly slow). */
    jtraj t;
    double peak_v = 0.0, peak_a = 0.0, q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
    int i, k;
    (void)state;
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, 0.5, 2.0), 0);
    for (k = 0; k <= 2000; k++) {
        jtraj_at(&t, t.duration_s * k / 2000.0, q, qd, qdd);
        for (i = 0; i < ARM_NJ; i++) {
            peak_v = fmax(peak_v, fabs(qd[i]) / (0.5 * arm_model_puma560.qd_max_radps[i]));
            peak_a = fmax(peak_a, fabs(qdd[i]) / 2.0);
        }
    }
    assert_true(fmax(peak_v, peak_a) > 0.99);
}

static void test_bad_input_rejected(void **state)
{
    jtraj t;
    double bad[ARM_NJ] = { 0, 0, NAN, 0, 0, 0 };
    (void)state;
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, bad, 0.5, 2.0), JTRAJ_ERR_ARG);
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, 0.0, 2.0), JTRAJ_ERR_ARG);
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, 1.5, 2.0), JTRAJ_ERR_ARG);
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q1, 0.5, -1.0), JTRAJ_ERR_ARG);
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, q0, q0, 0.5, 2.0), 0);
    assert_true(t.duration_s == 0.0);
}

/* A stop entered at a speed of each sign, one joint at rest, one faster
 * than its budget would allow a move to be: the identities hold for all. */
static const double stop_qd0[ARM_NJ] = { 0.8, -0.4, 0.0, 1.9, -2.5, 0.05 };

static void test_stop_never_faster_and_rests_by_v_over_a(void **state)
{
    jtraj_stop st;
    const double a = JTRAJ_MOVE_QDD_RADPS2;
    double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], prev[ARM_NJ];
    double t_max = 0.0;
    int i, k;
    (void)state;
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, a), 0);
    for (i = 0; i < ARM_NJ; i++) {
        t_max = fmax(t_max, fabs(stop_qd0[i]) / a);
        prev[i] = fabs(stop_qd0[i]);
    }
    assert_true(fabs(st.duration_s - t_max) < 1e-15);
    for (k = 0; k <= 4000; k++) {
        const double t = 1.5 * st.duration_s * k / 4000.0;
        jtraj_stop_at(&st, t, q, qd, qdd);
        for (i = 0; i < ARM_NJ; i++) {
            /* never above the entry speed, never faster than a cycle ago,
             * never reversing, never decelerating harder than a */
            assert_true(fabs(qd[i]) <= fabs(stop_qd0[i]));
            assert_true(fabs(qd[i]) <= prev[i] + 1e-15);
            assert_true(qd[i] * stop_qd0[i] >= 0.0);
            assert_true(fabs(qdd[i]) <= a * (1.0 + 1e-12));
            if (t >= fabs(stop_qd0[i]) / a)
                assert_true(qd[i] == 0.0 && qdd[i] == 0.0);
            prev[i] = fabs(qd[i]);
        }
    }
    /* at rest at the stopping distance: v^2 = 2 a d */
    jtraj_stop_at(&st, st.duration_s, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++) {
        assert_true(qd[i] == 0.0);
        assert_true(fabs(fabs(q[i] - q0[i]) * 2.0 * a - stop_qd0[i] * stop_qd0[i]) < 1e-12);
        assert_true((q[i] - q0[i]) * stop_qd0[i] >= 0.0);
    }
}

static void test_stop_continuous_and_derivatives(void **state)
{
    jtraj_stop st;
    const double a = 1.5, h = 1e-6;
    double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], qa[ARM_NJ], qb[ARM_NJ], qda[ARM_NJ], qdb[ARM_NJ],
        tmp[ARM_NJ];
    int i, k;
    (void)state;
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, a), 0);
    jtraj_stop_at(&st, 0.0, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(q[i] == q0[i] && qd[i] == stop_qd0[i]);
    for (k = 0; k < 997; k++) {
        /* 997 points: none falls within h of a joint's t_i, where the
         * acceleration steps to 0 */
        const double t = h + 1.3 * st.duration_s * k / 997.0;
        jtraj_stop_at(&st, t, q, qd, qdd);
        jtraj_stop_at(&st, t - h, qa, qda, tmp);
        jtraj_stop_at(&st, t + h, qb, qdb, tmp);
        for (i = 0; i < ARM_NJ; i++) {
            /* continuous: no step larger than the entry speed allows */
            assert_true(fabs(qb[i] - qa[i]) <= 2.0 * h * fabs(stop_qd0[i]) + 1e-15);
            assert_true(fabs((qb[i] - qa[i]) / (2.0 * h) - qd[i]) < 1e-6);
            if (fabs(t - fabs(stop_qd0[i]) / a) > 2.0 * h)
                assert_true(fabs((qdb[i] - qda[i]) / (2.0 * h) - qdd[i]) < 1e-6);
        }
    }
}

/* The stop's end, then the move planned again from where it rests: the
 * two join in position and at rest (no step, no lurch). */
static void test_stop_then_replan_joins_at_rest(void **state)
{
    jtraj_stop st;
    jtraj t;
    double qs[ARM_NJ], qds[ARM_NJ], qdds[ARM_NJ], q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
    int i;
    (void)state;
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, JTRAJ_MOVE_QDD_RADPS2), 0);
    jtraj_stop_at(&st, st.duration_s, qs, qds, qdds);
    assert_true(jtraj_at_rest(qds, 0.02));
    assert_int_equal(jtraj_plan(&t, &arm_model_puma560, qs, q1, 0.5, JTRAJ_MOVE_QDD_RADPS2), 0);
    jtraj_at(&t, 0.0, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(q[i] == qs[i] && qd[i] == 0.0 && qds[i] == 0.0);
}

static void test_stop_bad_input_and_rest_test(void **state)
{
    jtraj_stop st;
    double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
    double bad[ARM_NJ] = { 0, 0, 0, NAN, 0, 0 };
    const double slow[ARM_NJ] = { 0.019, -0.019, 0, 0, 0, 0.0 };
    const double one_fast[ARM_NJ] = { 0.0, 0.0, 0.0, 0.0, 0.0, -0.02 };
    int i;
    (void)state;
    assert_int_equal(jtraj_stop_plan(&st, q0, bad, 2.0), JTRAJ_ERR_STOP);
    /* refused: a stop at rest where the arm is, not a motion */
    jtraj_stop_at(&st, 0.3, q, qd, qdd);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(q[i] == q0[i] && qd[i] == 0.0 && qdd[i] == 0.0);
    assert_int_equal(jtraj_stop_plan(&st, bad, stop_qd0, 2.0), JTRAJ_ERR_STOP);
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, 0.0), JTRAJ_ERR_STOP);
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, -2.0), JTRAJ_ERR_STOP);
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, INFINITY), JTRAJ_ERR_STOP);
    assert_int_equal(jtraj_stop_plan(&st, q0, stop_qd0, NAN), JTRAJ_ERR_STOP);
    assert_true(jtraj_at_rest(slow, 0.02));
    assert_false(jtraj_at_rest(one_fast, 0.02));
    assert_false(jtraj_at_rest(bad, 0.02));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rest_to_rest_endpoints),
        cmocka_unit_test(test_bounds_and_derivatives),
        cmocka_unit_test(test_duration_is_tight),
        cmocka_unit_test(test_bad_input_rejected),
        cmocka_unit_test(test_stop_never_faster_and_rests_by_v_over_a),
        cmocka_unit_test(test_stop_continuous_and_derivatives),
        cmocka_unit_test(test_stop_then_replan_joins_at_rest),
        cmocka_unit_test(test_stop_bad_input_and_rest_test),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

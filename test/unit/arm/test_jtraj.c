/* Unit tests for jtraj: rest to rest, bounds respected (finite differences),
 * velocity and acceleration consistent with position. */
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
    double qa[ARM_NJ], qb[ARM_NJ], q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], qda[ARM_NJ], qdb[ARM_NJ], tmp[ARM_NJ];
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rest_to_rest_endpoints),
        cmocka_unit_test(test_bounds_and_derivatives),
        cmocka_unit_test(test_duration_is_tight),
        cmocka_unit_test(test_bad_input_rejected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

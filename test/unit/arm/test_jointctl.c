/* Unit tests for jointctl: with the dynamics model as the plant, computed
 * torque makes every joint error obey e'' + 2 zeta wn e' + wn^2 e = 0
 * (checked against the analytic critically damped response), the hold
 * torque at rest equals gravity, and saturation clamps to the motor limits. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>
#include "jointctl.h"

static const double q_ref[ARM_NJ] = { 0.3, 0.5, 2.8, 0.2, -0.5, 0.4 };

static void test_error_dynamics_are_critically_damped(void **state)
{
    const jointctl_gains g = { 8.0, 1.0 };
    const double dt = 1e-4, e0 = 0.02;
    double q[ARM_NJ], qd[ARM_NJ] = { 0 }, tau[ARM_NJ], qdd[ARM_NJ];
    const double zero[ARM_NJ] = { 0 };
    double worst = 0.0;
    int i, k;
    (void)state;
    for (i = 0; i < ARM_NJ; i++)
        q[i] = q_ref[i] + e0;
    for (k = 1; k <= 5000; k++) { /* 0.5 s, semi-implicit Euler on the model */
        assert_int_equal(
            jointctl_torque(&arm_model_puma560, NULL, &g, q, qd, q_ref, zero, zero, tau, NULL), 0);
        assert_int_equal(arm_forward_dynamics(&arm_model_puma560, q, qd, tau, NULL, NULL, qdd), 0);
        for (i = 0; i < ARM_NJ; i++) {
            qd[i] += qdd[i] * dt;
            q[i] += qd[i] * dt;
        }
        {
            /* e(t) = e0 (1 + wn t) exp(-wn t) for zeta = 1, e'(0) = 0 */
            const double t = k * dt, e_expect = e0 * (1.0 + g.wn_radps * t) * exp(-g.wn_radps * t);
            for (i = 0; i < ARM_NJ; i++)
                worst = fmax(worst, fabs((q[i] - q_ref[i]) - e_expect));
        }
    }
    print_message("max deviation from the analytic error response: %.2e rad\n", worst);
    /* integration error only: a wrong M, C or g would leave O(e0) errors */
    assert_true(worst < 2e-4 * e0 / 0.02);
}

static void test_hold_at_rest_is_gravity(void **state)
{
    const jointctl_gains g = { 8.0, 1.0 };
    const double zero[ARM_NJ] = { 0 };
    double tau[ARM_NJ], grav[ARM_NJ];
    int i;
    (void)state;
    assert_int_equal(
        jointctl_torque(&arm_model_puma560, NULL, &g, q_ref, zero, q_ref, zero, zero, tau, NULL),
        0);
    assert_int_equal(arm_gravity(&arm_model_puma560, q_ref, NULL, NULL, grav), 0);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(fabs(tau[i] - grav[i]) < 1e-9);
}

static void test_saturation(void **state)
{
    const jointctl_gains g = { 50.0, 1.0 };
    const double zero[ARM_NJ] = { 0 };
    double far[ARM_NJ], tau[ARM_NJ];
    int i, sat = 0;
    (void)state;
    for (i = 0; i < ARM_NJ; i++)
        far[i] = q_ref[i] + 1.0;
    assert_int_equal(
        jointctl_torque(&arm_model_puma560, NULL, &g, q_ref, zero, far, zero, zero, tau, &sat), 0);
    assert_int_equal(sat, 1);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(fabs(tau[i]) <= arm_model_puma560.tau_max_Nm[i]);
}

static void test_bad_reference_rejected(void **state)
{
    const jointctl_gains g = { 8.0, 1.0 };
    double zero[ARM_NJ] = { 0 }, bad[ARM_NJ], tau[ARM_NJ];
    (void)state;
    memcpy(bad, q_ref, sizeof bad);
    bad[3] = NAN;
    assert_int_equal(
        jointctl_torque(&arm_model_puma560, NULL, &g, q_ref, zero, bad, zero, zero, tau, NULL),
        JOINTCTL_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_dynamics_are_critically_damped),
        cmocka_unit_test(test_hold_at_rest_is_gravity),
        cmocka_unit_test(test_saturation),
        cmocka_unit_test(test_bad_reference_rejected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for unicycle: O-point kinematics by finite differences, exact
 * arc vs RK4 vs closed form, saturation modes. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "unicycle.h"

static void test_o_behind_c(void **state)
{
    pose2 c = { 1.0, 2.0, 0.7 }, o, c2;
    (void)state;
    unicycle_o_from_c(&o, &c, 0.2);
    /* O lies behind C: (C - O) points along the heading with length d. */
    assert_true(fabs(hypot(c.x_m - o.x_m, c.y_m - o.y_m) - 0.2) < 1e-12);
    assert_true(fabs((c.x_m - o.x_m) * cos(0.7) + (c.y_m - o.y_m) * sin(0.7) - 0.2) < 1e-12);
    unicycle_c_from_o(&c2, &o, 0.2);
    assert_true(fabs(c2.x_m - c.x_m) < 1e-12 && fabs(c2.y_m - c.y_m) < 1e-12);
}

static void test_o_velocity_fd(void **state)
{
    const double d = 0.15, v = 0.4, w = -0.9, h = 1e-6;
    pose2 c = { 0.3, -0.2, 2.1 }, o0, o1;
    double vel[2];
    (void)state;
    unicycle_o_from_c(&o0, &c, d);
    unicycle_o_velocity(vel, c.theta_rad, v, w, d);
    assert_int_equal(unicycle_step_exact(&c, v, w, h), 0);
    unicycle_o_from_c(&o1, &c, d);
    assert_true(fabs((o1.x_m - o0.x_m) / h - vel[0]) < 1e-6);
    assert_true(fabs((o1.y_m - o0.y_m) / h - vel[1]) < 1e-6);
}

static void test_exact_arc_closed_form(void **state)
{
    /* Full circle of radius R returns to the start; quarter circle lands at
     * (R, R) from heading 0. */
    const double R = 2.0, w = 0.5, v = R * w;
    pose2 c = { 0, 0, 0 };
    int i;
    (void)state;
    assert_int_equal(unicycle_step_exact(&c, v, w, (VEC2_PI / 2) / w), 0);
    assert_true(fabs(c.x_m - R) < 1e-12 && fabs(c.y_m - R) < 1e-12);
    assert_true(fabs(c.theta_rad - VEC2_PI / 2) < 1e-12);
    c.x_m = c.y_m = c.theta_rad = 0.0;
    for (i = 0; i < 1000; i++)
        unicycle_step_exact(&c, v, w, (2 * VEC2_PI / w) / 1000);
    assert_true(hypot(c.x_m, c.y_m) < 1e-9);
}

static void test_rk4_matches_exact(void **state)
{
    pose2 a = { 0.5, 0.5, -1.0 }, b = a;
    int i;
    (void)state;
    for (i = 0; i < 200; i++) {
        unicycle_step_exact(&a, 0.3, 0.8, 0.01);
        unicycle_step_rk4(&b, 0.3, 0.8, 0.01);
    }
    assert_true(fabs(a.x_m - b.x_m) < 1e-9 && fabs(a.y_m - b.y_m) < 1e-9);
    assert_true(fabs(vec2_angle_diff_rad(a.theta_rad, b.theta_rad)) < 1e-12);
    /* straight line: w = 0 exactly */
    a.x_m = a.y_m = 0;
    a.theta_rad = 0.3;
    unicycle_step_exact(&a, 1.0, 0.0, 2.0);
    assert_true(fabs(a.x_m - 2 * cos(0.3)) < 1e-12 && fabs(a.y_m - 2 * sin(0.3)) < 1e-12);
}

static void test_saturate(void **state)
{
    unicycle_cmd in = { 2.0, 0.5 }, out;
    (void)state;
    assert_int_equal(unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_CLIP), 1);
    assert_true(out.v_mps == 0.5 && out.w_radps == 0.5);
    assert_int_equal(unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_SCALE), 1);
    /* radius preserved, both within limits */
    assert_true(fabs(out.v_mps / out.w_radps - 4.0) < 1e-12);
    assert_true(fabs(out.v_mps) <= 0.5 + 1e-15 && fabs(out.w_radps) <= 1.0);
    in.v_mps = -0.2;
    in.w_radps = -3.0;
    unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_SCALE);
    assert_true(fabs(out.w_radps + 1.0) < 1e-15 &&
                fabs(out.v_mps / out.w_radps - in.v_mps / in.w_radps) < 1e-12);
    unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_CLIP);
    assert_true(out.v_mps == -0.2 && out.w_radps == -1.0);
    in.v_mps = 0.1;
    in.w_radps = 0.2;
    assert_int_equal(unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_SCALE), 0);
    assert_true(out.v_mps == 0.1 && out.w_radps == 0.2);
    in.v_mps = NAN;
    assert_int_equal(unicycle_saturate(&out, &in, 0.5, 1.0, UNICYCLE_SAT_CLIP), UNICYCLE_ERR_ARG);
    assert_true(out.v_mps == 0.0 && out.w_radps == 0.0);
}

static void test_bad_input(void **state)
{
    pose2 c = { 0, 0, 0 };
    (void)state;
    assert_int_equal(unicycle_step_exact(&c, INFINITY, 0, 1), UNICYCLE_ERR_ARG);
    assert_int_equal(unicycle_step_rk4(&c, 0, NAN, 1), UNICYCLE_ERR_ARG);
    assert_true(c.x_m == 0 && c.y_m == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_o_behind_c),
        cmocka_unit_test(test_o_velocity_fd),
        cmocka_unit_test(test_exact_arc_closed_form),
        cmocka_unit_test(test_rk4_matches_exact),
        cmocka_unit_test(test_saturate),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

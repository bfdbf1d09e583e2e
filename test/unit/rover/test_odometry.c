/* Unit tests for odometry: straight line, rotation in place and an arc,
 * each against the exact kinematic solution. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "odometry.h"

#define R 0.0825
#define B 0.33

static void test_straight(void **state)
{
    odometer o;
    pose2 c0 = { 1.0, -1.0, 0.4 }, c, p;
    int i;
    (void)state;
    assert_int_equal(odometry_init(&o, R, B, 0.1, &c0, 5.0, -3.0), 0);
    for (i = 1; i <= 100; i++)
        odometry_update(&o, 5.0 + 0.1 * i, -3.0 + 0.1 * i, NULL, NULL);
    odometry_pose_c(&o, &c);
    assert_true(fabs(c.x_m - (1.0 + 10.0 * R * cos(0.4))) < 1e-12);
    assert_true(fabs(c.y_m - (-1.0 + 10.0 * R * sin(0.4))) < 1e-12);
    assert_true(fabs(c.theta_rad - 0.4) < 1e-15);
    odometry_pose_o(&o, &p);
    assert_true(fabs(hypot(c.x_m - p.x_m, c.y_m - p.y_m) - 0.1) < 1e-12);
    assert_true(fabs(o.dist_m - 10.0 * R) < 1e-12);
}

static void test_rotation(void **state)
{
    odometer o;
    pose2 c0 = { 0.5, 0.5, 0.0 }, c;
    /* wheels opposite: phi_wheel R / (B/2) = dtheta */
    const double dth = VEC2_PI / 2, phi = dth * B / (2 * R);
    double ds, dt;
    (void)state;
    odometry_init(&o, R, B, 0.1, &c0, 0, 0);
    odometry_update(&o, -phi, phi, &ds, &dt);
    odometry_pose_c(&o, &c);
    assert_true(fabs(c.x_m - 0.5) < 1e-12 && fabs(c.y_m - 0.5) < 1e-12);
    assert_true(fabs(c.theta_rad - dth) < 1e-12);
    assert_true(fabs(ds) < 1e-15 && fabs(dt - dth) < 1e-12);
}

static void test_arc(void **state)
{
    /* Constant wheel speeds: C follows a circle of radius
     * Rc = (B/2) (wr + wl) / (wr - wl). Check after a half circle, in many
     * small increments (also exercises accumulation). */
    odometer o;
    pose2 c0 = { 0, 0, 0 }, c;
    const double wl = 1.0, wr = 2.0;
    const double Rc = 0.5 * B * (wr + wl) / (wr - wl);
    const double wz = R * (wr - wl) / B;
    const double T = VEC2_PI / wz;
    const int n = 777;
    int i;
    (void)state;
    odometry_init(&o, R, B, 0, &c0, 0, 0);
    for (i = 1; i <= n; i++)
        odometry_update(&o, wl * T * i / n, wr * T * i / n, NULL, NULL);
    odometry_pose_c(&o, &c);
    assert_true(fabs(c.x_m) < 1e-10);
    assert_true(fabs(c.y_m - 2 * Rc) < 1e-10);
    assert_true(fabs(fabs(c.theta_rad) - VEC2_PI) < 1e-10);
}

static void test_bad(void **state)
{
    odometer o;
    pose2 c0 = { 0, 0, 0 }, c;
    (void)state;
    assert_int_equal(odometry_init(&o, 0.0, B, 0, &c0, 0, 0), ODOMETRY_ERR_ARG);
    assert_int_equal(odometry_init(&o, R, -1, 0, &c0, 0, 0), ODOMETRY_ERR_ARG);
    assert_int_equal(odometry_init(&o, R, B, 0, &c0, 0, 0), 0);
    assert_int_equal(odometry_update(&o, NAN, 0, NULL, NULL), ODOMETRY_ERR_ARG);
    odometry_pose_c(&o, &c);
    assert_true(c.x_m == 0 && c.y_m == 0 && c.theta_rad == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straight),
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_arc),
        cmocka_unit_test(test_bad),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

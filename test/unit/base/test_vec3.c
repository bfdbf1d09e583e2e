/* Unit tests for vec3: rotation and transform identities that could fail. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>
#include "prng.h"
#include "vec3.h"

static prng_state rng;

static double urand(void)
{
    return prng_uniform(&rng);
}

static void random_rot(double R[9])
{
    double axis[3];
    vec3_set(axis, urand() - 0.5, urand() - 0.5, urand() - 0.5);
    rot_from_axis_angle(R, axis, (urand() * 2.0 - 1.0) * 3.14159);
}

static double max_diff(const double *a, const double *b, int n)
{
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++)
        m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

static void test_rotations_are_orthonormal(void **state)
{
    double R[9], RtR[9], I[9];
    int k;
    (void)state;
    rot_identity(I);
    for (k = 0; k < 200; k++) {
        random_rot(R);
        rot_tmul(RtR, R, R);
        assert_true(max_diff(RtR, I, 9) < 1e-12);
        /* det = +1: (r0 x r1) . r2 */
        {
            double c[3];
            vec3_cross(c, R, R + 3);
            assert_true(fabs(vec3_dot(c, R + 6) - 1.0) < 1e-12);
        }
    }
}

static void test_axis_angle_round_trip(void **state)
{
    double R[9], R2[9], axis[3];
    int k;
    (void)state;
    for (k = 0; k < 200; k++) {
        double angle;
        random_rot(R);
        angle = rot_to_axis_angle(axis, R);
        assert_true(angle >= 0.0 && angle <= 3.14159265358979 + 1e-12);
        rot_from_axis_angle(R2, axis, angle);
        assert_true(max_diff(R, R2, 9) < 1e-10);
    }
    rot_identity(R);
    assert_true(rot_to_axis_angle(axis, R) == 0.0);
    /* a half turn is recovered too (the quaternion route is stable there) */
    vec3_set(axis, 0.0, 0.6, 0.8);
    rot_from_axis_angle(R, axis, 3.14159265358979);
    assert_true(fabs(rot_to_axis_angle(axis, R) - 3.14159265358979) < 1e-9);
}

static void test_quaternion_round_trip(void **state)
{
    double R[9], R2[9], q[4];
    int k;
    (void)state;
    for (k = 0; k < 200; k++) {
        random_rot(R);
        rot_to_quat(q, R);
        assert_true(fabs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0) < 1e-12);
        rot_from_quat(R2, q);
        assert_true(max_diff(R, R2, 9) < 1e-12);
    }
}

static void test_rotation_acts_like_cross_product_for_small_angles(void **state)
{
    /* R(k, h) v = v + h k x v + O(h^2) */
    double R[9], k[3], v[3], Rv[3], kxv[3], fd[3];
    const double h = 1e-6;
    (void)state;
    vec3_set(k, 0.2, -0.5, 0.84);
    vec3_normalize(k, k);
    vec3_set(v, 1.0, 2.0, -0.5);
    rot_from_axis_angle(R, k, h);
    rot_apply(Rv, R, v);
    vec3_sub(fd, Rv, v);
    vec3_scale(fd, fd, 1.0 / h);
    vec3_cross(kxv, k, v);
    assert_true(max_diff(fd, kxv, 3) < 1e-5);
}

static void test_transform_inverse_and_composition(void **state)
{
    double R[9], p[3], T[16], Ti[16], I[16], TTi[16], A[16], B[16], AB[16], x[3], y[3], z[3];
    int k;
    (void)state;
    tf_identity(I);
    for (k = 0; k < 100; k++) {
        random_rot(R);
        vec3_set(p, urand(), urand() - 0.5, 2.0 * urand());
        tf_from_rot_pos(T, R, p);
        tf_inverse(Ti, T);
        tf_mul(TTi, T, Ti);
        assert_true(max_diff(TTi, I, 16) < 1e-12);
        /* (A B) x = A (B x) */
        tf_from_rot_pos(A, R, p);
        random_rot(R);
        vec3_set(x, urand(), -urand(), urand());
        tf_from_rot_pos(B, R, x);
        tf_mul(AB, A, B);
        vec3_set(x, urand(), urand(), urand());
        {
            double Bx[3], ABx[3];
            tf_apply(Bx, B, x);
            tf_apply(ABx, A, Bx);
            tf_apply(y, AB, x);
            vec3_sub(z, y, ABx);
            assert_true(vec3_norm(z) < 1e-12);
            /* T^-1 (T x) = x, in place */
            vec3_copy(y, x);
            tf_apply(y, T, y);
            tf_apply(y, Ti, y);
            vec3_sub(z, y, x);
            assert_true(vec3_norm(z) < 1e-12);
            /* the translation is applied: the origin goes to p */
            vec3_set(y, 0.0, 0.0, 0.0);
            tf_apply(y, T, y);
            vec3_sub(z, y, p);
            assert_true(vec3_norm(z) < 1e-15);
        }
    }
}

static void test_normalize_leaves_zero_alone(void **state)
{
    double z[3] = { 0.0, 0.0, 0.0 }, out[3];
    (void)state;
    assert_true(vec3_normalize(out, z) == 0.0);
    assert_true(out[0] == 0.0 && out[1] == 0.0 && out[2] == 0.0);
}

int main(void)
{
    prng_seed(&rng, 12345);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rotations_are_orthonormal),
        cmocka_unit_test(test_axis_angle_round_trip),
        cmocka_unit_test(test_quaternion_round_trip),
        cmocka_unit_test(test_rotation_acts_like_cross_product_for_small_angles),
        cmocka_unit_test(test_transform_inverse_and_composition),
        cmocka_unit_test(test_normalize_leaves_zero_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

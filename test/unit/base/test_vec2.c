/* Unit tests for vec2: angle wrapping (range, idempotence, same sin/cos,
 * exact boundary behaviour), signed angle differences, rotations (compose,
 * invert, preserve norms, counter-clockwise), norms and finiteness checks. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "prng.h"
#include "vec2.h"

#define N_SAMPLES 20000

/* Angles from tiny to large, both signs, plus values near multiples of pi. */
static double sample_angle(prng_state *r, int i)
{
    const double u = prng_uniform(r);
    switch (i % 4) {
    case 0: return (2.0 * u - 1.0) * 4.0;
    case 1: return (2.0 * u - 1.0) * 1000.0;
    case 2: return (double)((int)(u * 41.0) - 20) * VEC2_PI + (prng_uniform(r) - 0.5) * 1e-12;
    default: return ldexp(2.0 * u - 1.0, (int)(prng_uniform(r) * 60.0) - 40);
    }
}

/* rounding of 2 pi makes a - wrap(a) an inexact multiple of 2 pi: allow an
 * error growing with |a| */
static double tol_for(double a)
{
    return 1e-14 * (1.0 + fabs(a));
}

static void test_wrap_range_idempotent_trig(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 3);
    for (i = 0; i < N_SAMPLES; i++) {
        const double a = sample_angle(&r, i);
        const double w = vec2_wrap_rad(a);
        assert_true(w > -VEC2_PI && w <= VEC2_PI);
        assert_true(vec2_wrap_rad(w) == w); /* idempotent */
        assert_true(fabs(sin(w) - sin(a)) < tol_for(a));
        assert_true(fabs(cos(w) - cos(a)) < tol_for(a));
        /* differs from a by a whole number of turns */
        {
            const double turns = (a - w) / (2.0 * VEC2_PI);
            assert_true(fabs(turns - floor(turns + 0.5)) < 1e-9);
        }
        /* already-wrapped angles are left exactly alone */
        if (a > -VEC2_PI && a <= VEC2_PI)
            assert_true(w == a);
    }
}

static void test_wrap_boundaries(void **state)
{
    const double below = nextafter(-VEC2_PI, 0.0), above = nextafter(VEC2_PI, 4.0);
    (void)state;
    assert_true(vec2_wrap_rad(VEC2_PI) == VEC2_PI);
    assert_true(vec2_wrap_rad(-VEC2_PI) == VEC2_PI); /* -pi maps to +pi */
    assert_true(vec2_wrap_rad(below) == below);
    assert_true(vec2_wrap_rad(above) > -VEC2_PI && vec2_wrap_rad(above) < 0.0);
    assert_true(vec2_wrap_rad(0.0) == 0.0);
    assert_true(fabs(vec2_wrap_rad(2.0 * VEC2_PI)) < 1e-15);
    assert_true(fabs(vec2_wrap_rad(-2.0 * VEC2_PI)) < 1e-15);
    {
        const double w3 = vec2_wrap_rad(3.0 * VEC2_PI), wm3 = vec2_wrap_rad(-3.0 * VEC2_PI);
        assert_true(w3 > -VEC2_PI && w3 <= VEC2_PI && fabs(fabs(w3) - VEC2_PI) < 1e-14);
        assert_true(wm3 > -VEC2_PI && wm3 <= VEC2_PI && fabs(fabs(wm3) - VEC2_PI) < 1e-14);
    }
}

static void test_angle_diff(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 4);
    for (i = 0; i < N_SAMPLES; i++) {
        const double a = sample_angle(&r, i), b = sample_angle(&r, i + 1);
        const double d = vec2_angle_diff_rad(a, b), e = vec2_angle_diff_rad(b, a);
        const double tol = tol_for(a) + tol_for(b);
        assert_true(d > -VEC2_PI && d <= VEC2_PI);
        /* b + d points the same way as a */
        assert_true(fabs(sin(b + d) - sin(a)) < tol);
        assert_true(fabs(cos(b + d) - cos(a)) < tol);
        /* antisymmetric, except that both ends of the half-open range are +pi */
        if (fabs(fabs(d) - VEC2_PI) > 1e-9)
            assert_true(fabs(d + e) < tol);
        /* smallest: no other representative is shorter */
        assert_true(fabs(d) <= VEC2_PI);
        assert_true(fabs(vec2_angle_diff_rad(a, a)) == 0.0);
    }
    /* the short way round across the +-pi seam */
    assert_true(fabs(vec2_angle_diff_rad(-3.0, 3.0) - (2.0 * VEC2_PI - 6.0)) < 1e-15);
    assert_true(fabs(vec2_angle_diff_rad(3.0, -3.0) + (2.0 * VEC2_PI - 6.0)) < 1e-15);
}

static void test_rotate(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 5);
    for (i = 0; i < N_SAMPLES; i++) {
        const double x = (prng_uniform(&r) - 0.5) * 20.0, y = (prng_uniform(&r) - 0.5) * 20.0;
        const double a = (prng_uniform(&r) - 0.5) * 20.0, b = (prng_uniform(&r) - 0.5) * 20.0;
        const double n = vec2_norm(x, y), tol = 1e-13 * (1.0 + n);
        double p[2], q[2], s[2], t[2];
        vec2_rotate(p, x, y, a);
        assert_true(fabs(vec2_norm(p[0], p[1]) - n) < tol); /* isometry */
        /* the angle of the vector advances by a (counter-clockwise) */
        if (n > 1e-6) {
            const double turned = vec2_angle_diff_rad(atan2(p[1], p[0]), atan2(y, x));
            assert_true(fabs(vec2_angle_diff_rad(turned, a)) < 1e-12);
            /* dot and cross with the original: n^2 cos a, n^2 sin a */
            assert_true(fabs(p[0] * x + p[1] * y - n * n * cos(a)) < 1e-12 * (1.0 + n * n));
            assert_true(fabs(x * p[1] - y * p[0] - n * n * sin(a)) < 1e-12 * (1.0 + n * n));
        }
        vec2_rotate(q, p[0], p[1], b); /* compose */
        vec2_rotate(s, x, y, a + b);
        assert_true(fabs(q[0] - s[0]) < tol && fabs(q[1] - s[1]) < tol);
        vec2_rotate(t, p[0], p[1], -a); /* inverse */
        assert_true(fabs(t[0] - x) < tol && fabs(t[1] - y) < tol);
        vec2_rotate(t, x, y, a + 2.0 * VEC2_PI); /* periodic */
        assert_true(fabs(t[0] - p[0]) < 1e-12 * (1.0 + n) && fabs(t[1] - p[1]) < 1e-12 * (1.0 + n));
    }
    {
        double e[2];
        vec2_rotate(e, 1.0, 0.0, 0.5 * VEC2_PI); /* x axis onto y axis */
        assert_true(fabs(e[0]) < 1e-15 && fabs(e[1] - 1.0) < 1e-15);
        vec2_rotate(e, 2.0, -3.0, 0.0);
        assert_true(e[0] == 2.0 && e[1] == -3.0);
    }
}

static void test_norm(void **state)
{
    prng_state r;
    int i;
    (void)state;
    prng_seed(&r, 6);
    for (i = 0; i < N_SAMPLES; i++) {
        const double x = (prng_uniform(&r) - 0.5) * 20.0, y = (prng_uniform(&r) - 0.5) * 20.0;
        const double u = (prng_uniform(&r) - 0.5) * 20.0, v = (prng_uniform(&r) - 0.5) * 20.0;
        const double k = (prng_uniform(&r) - 0.5) * 8.0;
        const double n = vec2_norm(x, y);
        assert_true(n >= 0.0);
        assert_true(fabs(n * n - (x * x + y * y)) < 1e-12 * (1.0 + n * n));
        /* symmetric to rounding: C does not promise hypot(y, x) bit-equal
         * to hypot(x, y) (it is not on the 68040's extended-precision FPU) */
        assert_true(fabs(vec2_norm(-x, y) - n) <= 2e-16 * n &&
                    fabs(vec2_norm(y, x) - n) <= 2e-16 * n);
        assert_true(fabs(vec2_norm(k * x, k * y) - fabs(k) * n) < 1e-13 * (1.0 + fabs(k) * n));
        assert_true(vec2_norm(x + u, y + v) <= n + vec2_norm(u, v) + 1e-12);
    }
    assert_true(vec2_norm(0.0, 0.0) == 0.0);
    assert_true(vec2_norm(3.0, 4.0) == 5.0);
    /* no spurious overflow / underflow of the squares */
    assert_true(fabs(vec2_norm(3e200, 4e200) / 5e200 - 1.0) < 1e-15);
    assert_true(fabs(vec2_norm(3e-200, 4e-200) / 5e-200 - 1.0) < 1e-15);
}

static void test_finite(void **state)
{
    const double bad[] = { NAN, INFINITY, -INFINITY };
    pose2 p = { 1.0, -2.0, 3.0 };
    int i, slot;
    (void)state;
    assert_int_equal(vec2_finite3(0.0, -1e308, 1e-320), 1);
    assert_int_equal(vec2_pose_finite(&p), 1);
    assert_int_equal(vec2_pose_finite(NULL), 0);
    for (i = 0; i < 3; i++)
        for (slot = 0; slot < 3; slot++) {
            double v[3] = { 1.0, 2.0, 3.0 };
            pose2 q = p;
            v[slot] = bad[i];
            assert_int_equal(vec2_finite3(v[0], v[1], v[2]), 0);
            q.x_m = v[0];
            q.y_m = v[1];
            q.theta_rad = v[2];
            assert_int_equal(vec2_pose_finite(&q), 0);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap_range_idempotent_trig),
        cmocka_unit_test(test_wrap_boundaries),
        cmocka_unit_test(test_angle_diff),
        cmocka_unit_test(test_rotate),
        cmocka_unit_test(test_norm),
        cmocka_unit_test(test_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for sonar: rays against boxes, rotated boxes, cylinders and
 * walls at known distances (perpendicular, oblique, missing, inside, 2.5-D
 * height), grid broad phase equal to brute force, cone nearest echo, range
 * clamps, specular loss, noise determinism and the firing sequence. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "sonar.h"

#define DEG (VEC2_PI / 180.0)
static sonar_world W; /* large: keep off the stack */

static void close_to(double a, double b, double tol)
{
    if (!(fabs(a - b) <= tol))
        fail_msg("%.15g != %.15g (tol %g)", a, b, tol);
}

static void test_box(void **state)
{
    sonar_hit h;
    const double a = 35 * DEG;
    (void)state;
    sonar_world_init(&W);
    assert_int_equal(sonar_world_add_aabb(&W, 2.0, -10.0, 3.0, 10.0, -INFINITY, INFINITY), 0);
    /* perpendicular */
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, 0.0, 5.0), 1);
    close_to(h.t_m, 2.0, 1e-12);
    close_to(h.nx, -1.0, 1e-12);
    close_to(h.incidence_rad, 0.0, 1e-7);
    /* oblique: distance 2 / cos a, incidence a */
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, a, 5.0), 1);
    close_to(h.t_m, 2.0 / cos(a), 1e-12);
    close_to(h.incidence_rad, a, 1e-9);
    /* missing: away, and parallel beside */
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, VEC2_PI, 5.0), 0);
    assert_int_equal(sonar_cast(&h, &W, 0, 11.0, 0.2, 0.0, 5.0), 0);
    /* inside */
    assert_int_equal(sonar_cast(&h, &W, 2.5, 0.0, 0.2, 1.0, 5.0), 1);
    close_to(h.t_m, 0.0, 0.0);
    /* beyond max range */
    assert_int_equal(sonar_cast(&h, &W, -4.0, 0.0, 0.2, 0.0, 5.0), 0);
    assert_int_equal(sonar_cast(&h, &W, -4.0, 0.0, 0.2, 0.0, 7.0), 1);
    close_to(h.t_m, 6.0, 1e-12);
    /* rotated box: corner first */
    sonar_world_init(&W);
    sonar_world_add_box(&W, 3.0, 0.0, 0.5, 0.5, 45 * DEG, 0, 1);
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, 0.0, 5.0), 1);
    close_to(h.t_m, 3.0 - 0.5 * sqrt(2.0), 1e-12);
    /* face of the rotated box: along its normal */
    assert_int_equal(
        sonar_cast(&h, &W, 3.0 - 2.0 * cos(45 * DEG), -2.0 * sin(45 * DEG), 0.2, 45 * DEG, 5.0), 1);
    close_to(h.t_m, 1.5, 1e-12);
    close_to(h.incidence_rad, 0.0, 1e-7);
    /* 2.5-D: a low box is under the transducer */
    sonar_world_init(&W);
    sonar_world_add_aabb(&W, 2.0, -1.0, 3.0, 1.0, 0.0, 0.1);
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, 0.0, 5.0), 0);
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.05, 0.0, 5.0), 1);
}

static void test_cylinder_and_wall(void **state)
{
    sonar_hit h;
    (void)state;
    sonar_world_init(&W);
    sonar_world_add_circle(&W, 4.0, 0.0, 0.5, 0, 2);
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, 0.0, 5.0), 1);
    close_to(h.t_m, 3.5, 1e-12);
    assert_int_equal(sonar_cast(&h, &W, 0, 0.3, 0.2, 0.0, 5.0), 1);
    close_to(h.t_m, 4.0 - 0.4, 1e-12);
    close_to(cos(h.incidence_rad), 0.4 / 0.5, 1e-12);
    assert_int_equal(sonar_cast(&h, &W, 0, 0.51, 0.2, 0.0, 5.0), 0);
    assert_int_equal(sonar_cast(&h, &W, 5.0, 0.0, 0.2, 0.0, 5.0), 0); /* behind */
    assert_int_equal(sonar_cast(&h, &W, 4.1, 0.1, 0.2, 2.0, 5.0), 1); /* inside */
    close_to(h.t_m, 0.0, 0.0);
    sonar_world_init(&W);
    sonar_world_add_segment(&W, 2.0, -1.0, 2.0, 1.0, -INFINITY, INFINITY);
    assert_int_equal(sonar_cast(&h, &W, 0, 0.5, 0.2, 0.0, 5.0), 1);
    close_to(h.t_m, 2.0, 1e-12);
    assert_int_equal(sonar_cast(&h, &W, 4, 0.5, 0.2, VEC2_PI, 5.0), 1); /* two-sided */
    close_to(h.t_m, 2.0, 1e-12);
    close_to(h.nx, 1.0, 1e-12);
    assert_int_equal(sonar_cast(&h, &W, 0, 1.2, 0.2, 0.0, 5.0), 0); /* past the end */
    assert_int_equal(sonar_cast(&h, &W, 0, 0, 0.2, NAN, 5.0), SONAR_ERR_ARG);
    assert_int_equal(sonar_world_add_circle(&W, 0, 0, -1, 0, 1), SONAR_ERR_ARG);
    assert_int_equal(sonar_world_add_box(&W, 0, 0, 1, 1, 0, 1, 0), SONAR_ERR_ARG);
}

static void test_grid_equals_brute(void **state)
{
    prng_state r;
    int k, hits = 0;
    (void)state;
    prng_seed(&r, 11);
    sonar_world_init(&W);
    for (k = 0; k < SONAR_MAX_PRIMS; k++) {
        const double x = 60 * prng_uniform(&r) - 10, y = 40 * prng_uniform(&r) - 5;
        const int kind = k % 3;
        int idx;
        if (kind == 0)
            idx = sonar_world_add_box(&W, x, y, 0.1 + prng_uniform(&r), 0.1 + prng_uniform(&r),
                                      6 * prng_uniform(&r), 0, 1);
        else if (kind == 1)
            idx = sonar_world_add_circle(&W, x, y, 0.05 + 0.5 * prng_uniform(&r), 0, 1);
        else
            idx = sonar_world_add_segment(&W, x, y, x + 4 * prng_uniform(&r) - 2,
                                          y + 4 * prng_uniform(&r) - 2, 0, 1);
        assert_int_equal(idx, k);
    }
    assert_int_equal(sonar_world_add_circle(&W, 0, 0, 1, 0, 1), SONAR_ERR_ARG); /* full */
    assert_int_equal(sonar_world_build(&W), 0);
    assert_true(W.built);
    for (k = 0; k < 20000; k++) {
        sonar_hit a, b;
        const double ox = 70 * prng_uniform(&r) - 15, oy = 50 * prng_uniform(&r) - 10;
        const double dir = 2 * VEC2_PI * prng_uniform(&r);
        const int ra = sonar_cast(&a, &W, ox, oy, 0.2, dir, 5.0);
        const int rb = sonar_cast_brute(&b, &W, ox, oy, 0.2, dir, 5.0);
        assert_int_equal(ra, rb);
        if (ra == 1) {
            hits++;
            close_to(a.t_m, b.t_m, 1e-12);
        }
    }
    assert_true(hits > 2000);
}

static void test_cone_nearest_echo_and_clamps(void **state)
{
    sonar_model m;
    const sonar_transducer *s = &sonar_p2dx_front[3];
    const pose2 c = { 0, 0, 0 };
    const double ray = s->angle_rad + 25 * DEG * 0.25; /* the 4th of 5 rays */
    double rg;
    (void)state;
    sonar_model_default(&m);
    sonar_world_init(&W);
    sonar_world_add_aabb(&W, 4.0, -10, 5.0, 10, -INFINITY, INFINITY);
    /* a thin post on an off-centre ray, nearer than the wall */
    sonar_world_add_circle(&W, s->x_m + 1.5 * cos(ray), s->y_m + 1.5 * sin(ray), 0.02, 0, 1);
    sonar_world_build(&W);
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 3, NULL), 1);
    close_to(rg, 1.48, 1e-9);
    /* the +90 deg transducer sees neither the post nor the wall */
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 7, NULL), 0);
    close_to(rg, m.range_max_m, 0);
    /* too near: clamped up to the minimum range */
    sonar_world_init(&W);
    sonar_world_add_circle(&W, s->x_m + 0.07 * cos(s->angle_rad), s->y_m + 0.07 * sin(s->angle_rad),
                           0.02, 0, 1);
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 3, NULL), 1);
    close_to(rg, m.range_min_m, 0);
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 8, NULL), SONAR_ERR_ARG);
}

static void test_specular(void **state)
{
    sonar_model m;
    pose2 c = { 0, 0, 0 };
    double rg;
    (void)state;
    sonar_model_default(&m);
    sonar_world_init(&W);
    /* long wall along y = 1: the +90 transducer sees it head-on; the +10
     * one sees it at ~80 deg incidence */
    sonar_world_add_segment(&W, -20, 1.0, 20, 1.0, -INFINITY, INFINITY);
    m.specular_max_rad = 60 * DEG;
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 7, NULL), 1);
    close_to(rg, 1.0 - sonar_p2dx_front[7].y_m, 1e-12);
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 4, NULL), 0);
    close_to(rg, m.range_max_m, 0);
    m.specular_max_rad = 0.0; /* off: the steep ray echoes (edge ray nearest) */
    m.range_max_m = 10.0;
    assert_int_equal(sonar_fire(&rg, &W, &m, &c, 4, NULL), 1);
    close_to(rg, (1.0 - sonar_p2dx_front[4].y_m) / sin(10 * DEG + 12.5 * DEG), 1e-9);
}

static void test_noise_determinism(void **state)
{
    sonar_model m;
    const pose2 c = { 0.3, -0.2, 0.4 };
    double a[SONAR_N], b[SONAR_N], sum = 0, sq = 0, truth;
    prng_state r1, r2;
    int k, same = 1;
    (void)state;
    sonar_model_default(&m);
    sonar_world_init(&W);
    sonar_world_add_circle(&W, 2.0, 1.0, 1.0, 0, 2);
    sonar_world_add_aabb(&W, -3, -3, 3, -2.5, 0, 2);
    sonar_world_build(&W);
    prng_seed(&r1, 42);
    prng_seed(&r2, 42);
    assert_true(sonar_ring(a, &W, &m, &c, &r1) > 0);
    assert_true(sonar_ring(b, &W, &m, &c, &r2) > 0);
    for (k = 0; k < SONAR_N; k++)
        assert_true(a[k] == b[k]);
    prng_seed(&r2, 43);
    sonar_ring(b, &W, &m, &c, &r2);
    for (k = 0; k < SONAR_N; k++)
        if (a[k] != b[k] && a[k] < m.range_max_m)
            same = 0;
    assert_false(same);
    /* noise is zero-mean with the configured deviation */
    sonar_fire(&truth, &W, &m, &c, 4, NULL);
    for (k = 0; k < 4000; k++) {
        double v;
        sonar_fire(&v, &W, &m, &c, 4, &r1);
        sum += v - truth;
        sq += (v - truth) * (v - truth);
    }
    assert_true(fabs(sum / 4000) < 4 * m.noise_sd_m / sqrt(4000.0));
    assert_true(fabs(sqrt(sq / 4000) - m.noise_sd_m) < 0.1 * m.noise_sd_m);
}

static void test_firing_sequence(void **state)
{
    sonar_model m;
    int k, seen[SONAR_N] = { 0 };
    (void)state;
    sonar_model_default(&m);
    assert_int_equal(sonar_fired_index(0.0, &m), 7);
    assert_int_equal(sonar_fired_index(0.041, &m), 6);
    for (k = 0; k < SONAR_N; k++)
        seen[sonar_fired_index((k + 0.5) * m.fire_period_s, &m)]++;
    for (k = 0; k < SONAR_N; k++)
        assert_int_equal(seen[k], 1);
    assert_int_equal(sonar_fired_index((SONAR_N + 0.5) * m.fire_period_s, &m), 7);
    assert_int_equal(sonar_fired_index(-1.0, &m), SONAR_ERR_ARG);
    /* table: symmetric ring, angles as in docs/method/sonar.md */
    for (k = 0; k < SONAR_N; k++) {
        const sonar_transducer *a = &sonar_p2dx_front[k], *b = &sonar_p2dx_front[SONAR_N - 1 - k];
        close_to(a->angle_rad, -b->angle_rad, 1e-15);
        close_to(a->y_m, -b->y_m, 1e-15);
    }
    close_to(sonar_p2dx_front[0].angle_rad, -90 * DEG, 1e-15);
    close_to(sonar_p2dx_front[3].angle_rad, -10 * DEG, 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box),
        cmocka_unit_test(test_cylinder_and_wall),
        cmocka_unit_test(test_grid_equals_brute),
        cmocka_unit_test(test_cone_nearest_echo_and_clamps),
        cmocka_unit_test(test_specular),
        cmocka_unit_test(test_noise_determinism),
        cmocka_unit_test(test_firing_sequence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

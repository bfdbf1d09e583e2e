/* Unit tests for sync_ref (docs/method/carry.md §4), including a closed loop of two
 * point-mass "arms" under erlaw with the common reference. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "erlaw.h"
#include "sync_ref.h"
#include "vec3.h"

static void test_min_holds_all(void **st)
{
    const double l[3] = { 0.4, 0.8, 0.2 };
    double s[3] = { 0.2, 0.7, 0.02 }, s_star, ref[3];
    sync_ref r;
    int i;
    (void)st;
    assert_int_equal(sync_ref_init(&r, 3, l), 0);
    assert_true(fabs(r.k[1] - 1.0) < 1e-15);
    assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
    /* arm 3 (0.02 of 0.2) is the laggard: s* = 0.1 of 0.8 */
    assert_true(fabs(s_star - 0.08) < 1e-12);
    for (i = 0; i < 3; i++) {
        assert_true(fabs(ref[i] - r.k[i] * s_star) < 1e-15);
        assert_true(ref[i] <= s[i] + 1e-15); /* nobody's reference is ahead of it */
    }
    /* the others advance, the laggard stays: s* does not move */
    s[0] = 0.39;
    s[1] = 0.79;
    assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
    assert_true(fabs(s_star - 0.08) < 1e-12);
}

static void test_equal_lengths(void **st)
{
    const double l[2] = { 0.5, 0.5 };
    double s[2] = { 0.3, 0.1 }, s_star, ref[2];
    sync_ref r;
    (void)st;
    assert_int_equal(sync_ref_init(&r, 2, l), 0);
    assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
    assert_true(s_star == 0.1 && ref[0] == 0.1 && ref[1] == 0.1);
}

static void test_zero_length_excluded(void **st)
{
    const double l[2] = { 0.0, 0.6 }, lz[2] = { 0.0, 0.0 };
    double s[2] = { 0.0, 0.3 }, s_star, ref[2];
    sync_ref r;
    (void)st;
    assert_int_equal(sync_ref_init(&r, 2, l), 0);
    assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
    assert_true(s_star == 0.3 && ref[0] == 0.0 && ref[1] == 0.3);
    assert_int_equal(sync_ref_init(&r, 2, lz), 0);
    assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
    assert_true(s_star == 0.0 && ref[0] == 0.0 && ref[1] == 0.0);
}

static void test_invalid(void **st)
{
    const double l[2] = { 0.2, -0.1 }, ok[2] = { 0.2, 0.1 };
    double s[2] = { NAN, 0.0 }, s_star;
    sync_ref r;
    (void)st;
    assert_int_equal(sync_ref_init(&r, 2, l), SYNC_REF_ERR_ARG);
    assert_int_equal(sync_ref_init(&r, 0, ok), SYNC_REF_ERR_ARG);
    assert_int_equal(sync_ref_init(&r, SYNC_MAX + 1, ok), SYNC_REF_ERR_ARG);
    assert_int_equal(sync_ref_init(&r, 2, ok), 0);
    assert_int_equal(sync_ref_update(&r, s, &s_star, 0), SYNC_REF_ERR_ARG);
    s[0] = -0.01; /* measured s may be a hair below 0: clamped */
    assert_int_equal(sync_ref_update(&r, s, &s_star, 0), 0);
    assert_true(s_star == 0.0);
}

/* Two point masses on segments of different lengths, both driven by
 * erlaw with the common reference. Mass 2 is frozen at speed for 10 s:
 * mass 1's speed falls below 1 cm/s within 50 ms, its lead over its
 * reference stays below g + v0 / (e w) (erlaw.h), it rests at the gap, and
 * both resume and finish. */
static void test_closed_loop_bounded_lead(void **st)
{
    const erlaw_gains g = { 0.25, 0.5, 4.0, 100.0, 20.0, 0.2, 5.0, 50.0 };
    const double p0[2][3] = { { 0, 0, 0 }, { 1, 0, 0 } };
    const double p1[2][3] = { { 0.6, 0, 0 }, { 1, 0.3, 0 } };
    const double dt = 1e-3, w = ERLAW_SYNC_OMEGA_RADPS;
    double x[2][3], v[2][3], l[2], s[2], ref[2], s_star, t = 0.0, max_lead = 0.0, v0 = -1.0;
    double t_stop = -1.0, t_freeze = -1.0;
    erlaw_line seg[2];
    sync_ref r;
    int i, k, done = 0;
    (void)st;
    for (i = 0; i < 2; i++) {
        assert_int_equal(erlaw_line_init(&seg[i], p0[i], p1[i], &g), 0);
        vec3_copy(x[i], p0[i]);
        vec3_set(v[i], 0, 0, 0);
        l[i] = erlaw_channel_length(&seg[i].ch);
    }
    assert_int_equal(sync_ref_init(&r, 2, l), 0);
    while (!done && t < 40.0) {
        const int frozen2 = t > 2.0 && t < 12.0;
        for (i = 0; i < 2; i++)
            s[i] = erlaw_line_s(&seg[i], x[i]);
        assert_int_equal(sync_ref_update(&r, s, &s_star, ref), 0);
        if (frozen2 && t_freeze < 0.0) {
            t_freeze = t;
            v0 = vec3_norm(v[0]);
            assert_true(v0 > 0.15); /* blocked at speed */
        }
        for (i = 0; i < 2; i++) {
            erlaw_out o;
            assert_int_equal(
                erlaw_line_step(&seg[i], x[i], v[i], ERLAW_REF_EXTERNAL, ref[i], dt, &o), 0);
            for (k = 0; k < 3; k++) {
                if (i == 1 && frozen2) {
                    v[i][k] = 0.0;
                    continue;
                }
                v[i][k] += o.u[k] * dt;
                x[i][k] += v[i][k] * dt;
            }
        }
        if (frozen2) {
            /* the free mass is held: it stops within 50 ms, its lead over
             * its reference stays bounded, then it rests at the gap */
            max_lead = fmax(max_lead, s[0] - ref[0]);
            if (t_stop < 0.0 && vec3_norm(v[0]) < 0.01)
                t_stop = t;
            if (t > 3.0) {
                assert_true(vec3_norm(v[0]) < 1e-4);
                assert_true(fabs(s[0] - ref[0] - ERLAW_FOLLOW_GAP_M) < 1e-4);
            }
        }
        done = erlaw_done(s[0], l[0], vec3_norm(v[0]), 1e-3, 5e-3) &&
               erlaw_done(s[1], l[1], vec3_norm(v[1]), 1e-3, 5e-3);
        t += dt;
    }
    assert_true(t_stop > t_freeze && t_stop - t_freeze <= 0.050);
    assert_true(max_lead > 0.0);
    assert_true(max_lead <= ERLAW_FOLLOW_GAP_M + v0 / (exp(1.0) * w) + 2e-4);
    assert_true(done); /* both resumed and finished */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_min_holds_all),
        cmocka_unit_test(test_equal_lengths),
        cmocka_unit_test(test_zero_length_excluded),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_closed_loop_bounded_lead),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

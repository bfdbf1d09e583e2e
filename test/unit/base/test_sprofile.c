/* Unit tests for sprofile (docs/method/carry.md §2): identities checked by finite
 * differences over s, for long, short and very short segments. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "sprofile.h"

typedef struct {
    double s_f, v_m, a_m, u_m;
} profile_case;

/* long with a-plateau, long without plateau (w_m < 2 a_m^2/u_m),
 * short (peak speed lowered), very short (peak a lowered too). */
static const profile_case CASES[] = {
    { 2.0, 0.5, 0.5, 2.0 },   { 1.0, 0.25, 0.5, 2.0 }, { 0.3, 0.5, 0.5, 2.0 },
    { 0.05, 0.5, 0.5, 2.0 },  { 3.0, 1.0, 2.0, 8.0 }, /* rad units: an orientation move */
    { 1e-4, 0.25, 0.5, 2.0 },
};
#define N_CASES (sizeof CASES / sizeof CASES[0])

static void plan(sprofile *p, const profile_case *c)
{
    assert_int_equal(sprofile_plan(p, c->s_f, c->v_m, c->a_m, c->u_m), 0);
}

static void test_ends_at_rest(void **st)
{
    size_t i;
    (void)st;
    for (i = 0; i < N_CASES; i++) {
        sprofile p;
        double a, v;
        plan(&p, &CASES[i]);
        sprofile_at(&p, 0.0, &a, &v);
        assert_true(fabs(a) < 1e-12 && fabs(v) < 1e-12);
        sprofile_at(&p, CASES[i].s_f, &a, &v);
        assert_true(fabs(a) < 1e-9);
        assert_true(fabs(v) < 1e-6);
        /* beyond the ends: clamped */
        sprofile_at(&p, CASES[i].s_f + 1.0, &a, &v);
        assert_true(fabs(a) < 1e-9 && fabs(v) < 1e-6);
        sprofile_at(&p, -1.0, &a, &v);
        assert_true(fabs(a) < 1e-12 && fabs(v) < 1e-12);
        /* the segment is used: the profile moves somewhere */
        sprofile_at(&p, 0.5 * CASES[i].s_f, &a, &v);
        assert_true(v > 0.0);
    }
}

/* Bounds, continuity and the identities dw/ds = 2a, |da/ds| <= u_m. */
static void test_fd_identities(void **st)
{
    size_t i;
    (void)st;
    for (i = 0; i < N_CASES; i++) {
        const profile_case *c = &CASES[i];
        sprofile p;
        const int n = 20000;
        const double h = c->s_f / n;
        double a_prev, v_prev, max_jump_a = 0.0, max_jump_w = 0.0;
        int k;
        plan(&p, c);
        sprofile_at(&p, 0.0, &a_prev, &v_prev);
        for (k = 1; k <= n; k++) {
            double s = k * h, a, v, dwds, dads, a_mid;
            sprofile_at(&p, s, &a, &v);
            assert_true(fabs(a) <= c->a_m * (1 + 1e-12));
            assert_true(v <= c->v_m * (1 + 1e-12));
            dads = (a - a_prev) / h;
            assert_true(fabs(dads) <= c->u_m * (1 + 1e-6));
            /* dw/ds = 2a at the midpoint (second-order exact for the
             * piecewise quadratic w, except across a breakpoint) */
            sprofile_at(&p, s - 0.5 * h, &a_mid, 0);
            dwds = (v * v - v_prev * v_prev) / h;
            assert_true(fabs(dwds - 2.0 * a_mid) <= 2.0 * c->u_m * h + 1e-9);
            max_jump_a = fmax(max_jump_a, fabs(a - a_prev));
            max_jump_w = fmax(max_jump_w, fabs(v * v - v_prev * v_prev));
            a_prev = a;
            v_prev = v;
        }
        /* continuity: no step bigger than the slope bounds allow */
        assert_true(max_jump_a <= c->u_m * h * (1 + 1e-6));
        assert_true(max_jump_w <= 2.0 * c->a_m * h * (1 + 1e-6));
    }
}

/* Continuity right at the eq. 4 breakpoints of a long segment. */
static void test_breakpoints(void **st)
{
    const double s_f = 2.0, v_m = 0.5, a_m = 0.5, u_m = 2.0;
    const double w_m = v_m * v_m;
    const double bp[6] = { a_m / u_m,
                           w_m / (2 * a_m),
                           w_m / (2 * a_m) + a_m / u_m,
                           s_f - w_m / (2 * a_m) - a_m / u_m,
                           s_f - w_m / (2 * a_m),
                           s_f - a_m / u_m };
    const double eps = 1e-9;
    sprofile p;
    int i;
    (void)st;
    assert_int_equal(sprofile_plan(&p, s_f, v_m, a_m, u_m), 0);
    assert_true(fabs(p.a_peak - a_m) < 1e-12);
    assert_true(fabs(p.w_peak - w_m) < 1e-12);
    for (i = 0; i < 6; i++) {
        double a0, v0, a1, v1;
        sprofile_at(&p, bp[i] - eps, &a0, &v0);
        sprofile_at(&p, bp[i] + eps, &a1, &v1);
        assert_true(fabs(a1 - a0) < 1e-7);
        assert_true(fabs(v1 - v0) < 1e-7);
    }
    /* the cruise and plateau values of eq. 4 */
    {
        double a, v;
        sprofile_at(&p, 0.5 * (bp[0] + bp[1]), &a, &v);
        assert_true(fabs(a - a_m) < 1e-12);
        sprofile_at(&p, 0.5 * (bp[2] + bp[3]), &a, &v);
        assert_true(fabs(a) < 1e-12 && fabs(v - v_m) < 1e-12);
        sprofile_at(&p, 0.5 * (bp[4] + bp[5]), &a, &v);
        assert_true(fabs(a + a_m) < 1e-12);
    }
}

/* Short segment: the peak speed is lowered but the profile is still the
 * fastest one that fits: peak speed grows monotonically with s_f. */
static void test_short_monotone(void **st)
{
    double prev = 0.0, s_f;
    (void)st;
    for (s_f = 0.001; s_f < 3.0; s_f *= 1.1) {
        sprofile p;
        assert_int_equal(sprofile_plan(&p, s_f, 0.5, 0.5, 2.0), 0);
        assert_true(sprofile_v_peak(&p) >= prev - 1e-12);
        assert_true(2.0 * p.d_acc_m <= s_f * (1 + 1e-12));
        prev = sprofile_v_peak(&p);
    }
    assert_true(fabs(prev - 0.5) < 1e-12);
}

static void test_degenerate_and_invalid(void **st)
{
    sprofile p;
    double a = 1, v = 1;
    (void)st;
    assert_int_equal(sprofile_plan(&p, 0.0, 0.25, 0.5, 2.0), 0);
    sprofile_at(&p, 0.0, &a, &v);
    assert_true(a == 0.0 && v == 0.0);
    sprofile_at(&p, 1.0, &a, &v);
    assert_true(a == 0.0 && v == 0.0);
    assert_true(sprofile_advance(&p, 0.0, 0.01, 0.1) == 0.0);
    assert_int_equal(sprofile_plan(&p, -1.0, 0.25, 0.5, 2.0), SPROFILE_ERR_ARG);
    assert_int_equal(sprofile_plan(&p, 1.0, 0.0, 0.5, 2.0), SPROFILE_ERR_ARG);
    assert_int_equal(sprofile_plan(&p, 1.0, 0.25, -0.5, 2.0), SPROFILE_ERR_ARG);
    assert_int_equal(sprofile_plan(&p, 1.0, 0.25, 0.5, NAN), SPROFILE_ERR_ARG);
    assert_int_equal(sprofile_plan(&p, INFINITY, 0.25, 0.5, 2.0), SPROFILE_ERR_ARG);
    assert_int_equal(sprofile_plan(0, 1.0, 0.25, 0.5, 2.0), SPROFILE_ERR_ARG);
    sprofile_at(&p, NAN, &a, &v);
    assert_true(a == 0.0 && v == 0.0);
}

/* Time integration: s(t) is monotone, reaches s_f in finite time, and
 * where v > v_floor its time derivative is the planned speed. */
static void test_advance(void **st)
{
    sprofile p;
    const double dt = 1e-3, floor_v = 0.01;
    double s = 0.0, t = 0.0;
    (void)st;
    assert_int_equal(sprofile_plan(&p, 0.5, 0.25, 0.5, 2.0), 0);
    while (s < p.s_f_m && t < 100.0) {
        double s1 = sprofile_advance(&p, s, dt, floor_v), v, v0;
        assert_true(s1 >= s);
        /* given the first stage's rate, the same step bit for bit */
        sprofile_at(&p, s, 0, &v0);
        assert_true(sprofile_advance_at(&p, s, fmax(v0, floor_v), dt, floor_v) == s1);
        sprofile_at(&p, 0.5 * (s + s1), 0, &v);
        if (s1 < p.s_f_m)
            assert_true(fabs((s1 - s) / dt - fmax(v, floor_v)) < 1e-3);
        s = s1;
        t += dt;
    }
    assert_true(s == p.s_f_m);
    assert_true(t < 10.0);
    /* without a floor the pure profile never leaves rest */
    assert_true(sprofile_advance(&p, 0.0, dt, 0.0) == 0.0);
    /* outside its domain sprofile_advance_at is sprofile_advance */
    assert_true(sprofile_advance_at(&p, -1.0, 5.0, dt, floor_v) ==
                sprofile_advance(&p, -1.0, dt, floor_v));
    assert_true(sprofile_advance_at(&p, 0.1, NAN, dt, floor_v) ==
                sprofile_advance(&p, 0.1, dt, floor_v));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ends_at_rest),
        cmocka_unit_test(test_fd_identities),
        cmocka_unit_test(test_breakpoints),
        cmocka_unit_test(test_short_monotone),
        cmocka_unit_test(test_degenerate_and_invalid),
        cmocka_unit_test(test_advance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

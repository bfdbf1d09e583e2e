/* Unit tests for slot_assign: the assignment found has the least sum of
 * squared distances of all n! (checked against every permutation for
 * small teams; for larger ones no exchange of two slots or rotation of
 * three improves it); robots driving straight to it, arriving together,
 * keep apart (the CAPT bound); driving every robot part of the way to
 * its slot keeps the same assignment (the property the arrival relies
 * on); bad arguments are refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "slot_assign.h"

#define N_BRUTE 7

/* A fixed linear congruential generator: the same cases on every host. */
static double uniform(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

static void random_points(uint32_t *s, double p[][2], int n, double side_m)
{
    int j;
    for (j = 0; j < n; j++) {
        p[j][0] = side_m * uniform(s);
        p[j][1] = side_m * uniform(s);
    }
}

static double sq(const double a[2], const double b[2])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

static double cost_of(const double xy[][2], const double sl[][2], const int *slot_of, int n)
{
    double c = 0.0;
    int j;
    for (j = 0; j < n; j++)
        c += sq(xy[j], sl[slot_of[j]]);
    return c;
}

/* The least cost over all permutations of perm[k..n-1] (Heap-free
 * recursion by swaps). */
static double brute_min(const double xy[][2], const double sl[][2], int *perm, int k, int n)
{
    double best = INFINITY;
    int i;
    if (k == n)
        return cost_of(xy, sl, perm, n);
    for (i = k; i < n; i++) {
        int t = perm[k];
        perm[k] = perm[i];
        perm[i] = t;
        best = fmin(best, brute_min(xy, sl, perm, k + 1, n));
        t = perm[k];
        perm[k] = perm[i];
        perm[i] = t;
    }
    return best;
}

static void assert_permutation(const int *slot_of, int n)
{
    int seen[SLOT_ASSIGN_MAX] = { 0 }, j;
    for (j = 0; j < n; j++) {
        assert_true(slot_of[j] >= 0 && slot_of[j] < n);
        assert_int_equal(seen[slot_of[j]], 0);
        seen[slot_of[j]] = 1;
    }
}

static void test_optimal_against_every_permutation(void **state)
{
    double xy[N_BRUTE][2], sl[N_BRUTE][2], cost;
    int slot_of[N_BRUTE], perm[N_BRUTE], n, trial, j;
    uint32_t s = 12345u;
    (void)state;
    for (n = 1; n <= N_BRUTE; n++)
        for (trial = 0; trial < 40; trial++) {
            random_points(&s, xy, n, 10.0);
            random_points(&s, sl, n, 10.0);
            assert_int_equal(slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, n,
                                                slot_of, &cost),
                             SLOT_ASSIGN_OK);
            assert_permutation(slot_of, n);
            assert_true(fabs(cost - cost_of((const double(*)[2])xy, (const double(*)[2])sl, slot_of,
                                            n)) < 1e-9);
            for (j = 0; j < n; j++)
                perm[j] = j;
            assert_true(fabs(cost - brute_min((const double(*)[2])xy, (const double(*)[2])sl, perm,
                                              0, n)) < 1e-9);
        }
}

/* For teams too large to enumerate: no exchange of two robots' slots and
 * no rotation of three improves the assignment found. */
static void test_large_team_no_swap_or_cycle_improves(void **state)
{
    enum { N = 40 };
    double xy[N][2], sl[N][2], cost;
    int slot_of[N], a, b, c;
    uint32_t s = 777u;
    (void)state;
    random_points(&s, xy, N, 20.0);
    random_points(&s, sl, N, 20.0);
    assert_int_equal(
        slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, N, slot_of, &cost),
        SLOT_ASSIGN_OK);
    assert_permutation(slot_of, N);
    for (a = 0; a < N; a++)
        for (b = a + 1; b < N; b++) {
            const double now = sq(xy[a], sl[slot_of[a]]) + sq(xy[b], sl[slot_of[b]]);
            assert_true(sq(xy[a], sl[slot_of[b]]) + sq(xy[b], sl[slot_of[a]]) >= now - 1e-9);
            for (c = b + 1; c < N; c++) {
                const double now3 = now + sq(xy[c], sl[slot_of[c]]);
                assert_true(sq(xy[a], sl[slot_of[b]]) + sq(xy[b], sl[slot_of[c]]) +
                                sq(xy[c], sl[slot_of[a]]) >=
                            now3 - 1e-9);
                assert_true(sq(xy[a], sl[slot_of[c]]) + sq(xy[b], sl[slot_of[a]]) +
                                sq(xy[c], sl[slot_of[b]]) >=
                            now3 - 1e-9);
            }
        }
}

/* Points at least sep_m apart (rejection sampling). */
static void separated_points(uint32_t *s, double p[][2], int n, double side_m, double sep_m)
{
    int j = 0, k;
    while (j < n) {
        p[j][0] = side_m * uniform(s);
        p[j][1] = side_m * uniform(s);
        for (k = 0; k < j && sq(p[j], p[k]) >= sep_m * sep_m; k++)
            ;
        if (k == j)
            j++;
    }
}

/* The least distance between robots a and b moving straight from a0, b0
 * to a1, b1 over the same time: |d0 + t (d1 - d0)| minimised on [0, 1]. */
static double closest_m(const double a0[2], const double a1[2], const double b0[2],
                        const double b1[2])
{
    const double d0[2] = { a0[0] - b0[0], a0[1] - b0[1] };
    const double dd[2] = { (a1[0] - b1[0]) - d0[0], (a1[1] - b1[1]) - d0[1] };
    const double den = dd[0] * dd[0] + dd[1] * dd[1];
    double t = den > 0.0 ? -(d0[0] * dd[0] + d0[1] * dd[1]) / den : 0.0;
    t = fmin(1.0, fmax(0.0, t));
    return hypot(d0[0] + t * dd[0], d0[1] + t * dd[1]);
}

/* Robots that start and end sep apart and drive straight to their slots,
 * arriving together, stay at least sep / sqrt(2) apart all the way (the
 * CAPT bound; an assignment by id breaks it in these cases). */
static void test_synchronised_paths_keep_apart(void **state)
{
    enum { N = 12 };
    const double sep_m = 1.0;
    double xy[N][2], sl[N][2], worst = INFINITY, worst_by_id = INFINITY;
    int slot_of[N], trial, a, b;
    uint32_t s = 4242u;
    (void)state;
    for (trial = 0; trial < 50; trial++) {
        separated_points(&s, xy, N, 8.0, sep_m);
        separated_points(&s, sl, N, 8.0, sep_m);
        assert_int_equal(
            slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, N, slot_of, NULL),
            SLOT_ASSIGN_OK);
        for (a = 0; a < N; a++)
            for (b = a + 1; b < N; b++) {
                worst = fmin(worst, closest_m(xy[a], sl[slot_of[a]], xy[b], sl[slot_of[b]]));
                worst_by_id = fmin(worst_by_id, closest_m(xy[a], sl[a], xy[b], sl[b]));
            }
    }
    assert_true(worst >= sep_m / sqrt(2.0) - 1e-9);
    assert_true(worst_by_id < sep_m / sqrt(2.0)); /* the check can fail */
}

/* Robots driven straight toward their slots, all the same fraction of the
 * way, keep the assignment at every fraction: the rule evaluated afresh
 * each period gives the answer the team is already flying. */
static void test_assignment_holds_while_driven_to_it(void **state)
{
    enum { N = 12 };
    double xy[N][2], sl[N][2], now[N][2];
    int first[N], again[N], trial, step, j;
    uint32_t s = 99u;
    (void)state;
    for (trial = 0; trial < 20; trial++) {
        random_points(&s, xy, N, 10.0);
        random_points(&s, sl, N, 10.0);
        assert_int_equal(
            slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, N, first, NULL),
            SLOT_ASSIGN_OK);
        for (step = 1; step < 10; step++) {
            const double f = step / 10.0;
            for (j = 0; j < N; j++) {
                now[j][0] = xy[j][0] + f * (sl[first[j]][0] - xy[j][0]);
                now[j][1] = xy[j][1] + f * (sl[first[j]][1] - xy[j][1]);
            }
            assert_int_equal(
                slot_assign_min_sq((const double(*)[2])now, (const double(*)[2])sl, N, again, NULL),
                SLOT_ASSIGN_OK);
            assert_memory_equal(first, again, sizeof first);
        }
    }
}

/* Robots in a column behind a column of slots, out of id order: the
 * optimum keeps their order along the line, whatever the ids. */
static void test_column_keeps_its_order(void **state)
{
    const double xy[4][2] = { { -3.0, 0.1 }, { -6.0, -0.1 }, { -4.0, 0.0 }, { -5.0, 0.05 } };
    const double sl[4][2] = { { 1.5, 0.0 }, { 0.5, 0.0 }, { -0.5, 0.0 }, { -1.5, 0.0 } };
    const int want[4] = { 0, 3, 1, 2 };
    int slot_of[4];
    (void)state;
    assert_int_equal(slot_assign_min_sq(xy, sl, 4, slot_of, NULL), SLOT_ASSIGN_OK);
    assert_memory_equal(slot_of, want, sizeof want);
}

/* On one axis the sorted order is the Hungarian's optimum: over random
 * teams of 1 to SLOT_ASSIGN_MAX robots (distinct keys, so the optimum is
 * unique) the same assignment and the same cost; with equal keys the same
 * cost. And bad arguments are refused as slot_assign_min_sq refuses them. */
static void test_sorted_on_one_axis(void **state)
{
    static double xy[SLOT_ASSIGN_MAX][2], sl[SLOT_ASSIGN_MAX][2];
    double x[SLOT_ASSIGN_MAX], s[SLOT_ASSIGN_MAX], c_hung, c_sort;
    int a[SLOT_ASSIGN_MAX], b[SLOT_ASSIGN_MAX], n, j, rep;
    uint32_t seed = 17u;
    (void)state;
    for (rep = 0; rep < 60; rep++) {
        n = 1 + rep * (SLOT_ASSIGN_MAX - 1) / 59;
        for (j = 0; j < n; j++) {
            x[j] = xy[j][0] = 20.0 * uniform(&seed);
            s[j] = sl[j][0] = 20.0 * uniform(&seed);
            /* every third case with repeated keys */
            if (rep % 3 == 2 && j > 0 && j % 4 == 0) {
                x[j] = xy[j][0] = x[j - 1];
                s[j] = sl[j][0] = s[j - 1];
            }
            xy[j][1] = sl[j][1] = 0.0;
        }
        assert_int_equal(
            slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, n, a, &c_hung),
            SLOT_ASSIGN_OK);
        assert_int_equal(slot_assign_sorted(x, s, n, b, &c_sort), SLOT_ASSIGN_OK);
        assert_permutation(b, n);
        assert_true(fabs(c_hung - c_sort) <= 1e-9 * (1.0 + c_hung));
        if (rep % 3 != 2)
            assert_memory_equal(a, b, (size_t)n * sizeof a[0]);
    }
    assert_int_equal(slot_assign_sorted(NULL, s, 2, b, NULL), SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(slot_assign_sorted(x, s, 0, b, NULL), SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(slot_assign_sorted(x, s, SLOT_ASSIGN_MAX + 1, b, NULL), SLOT_ASSIGN_ERR_ARG);
    x[1] = NAN;
    assert_int_equal(slot_assign_sorted(x, s, 2, b, NULL), SLOT_ASSIGN_ERR_ARG);
}

static void test_bad_arguments(void **state)
{
    double xy[2][2] = { { 0.0, 0.0 }, { 1.0, 1.0 } }, sl[2][2] = { { 0.0, 1.0 }, { 1.0, 0.0 } };
    int slot_of[2] = { -7, -7 };
    (void)state;
    assert_int_equal(slot_assign_min_sq(NULL, (const double(*)[2])sl, 2, slot_of, NULL),
                     SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(slot_assign_min_sq((const double(*)[2])xy, NULL, 2, slot_of, NULL),
                     SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(
        slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, 2, NULL, NULL),
        SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(
        slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, 0, slot_of, NULL),
        SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl,
                                        SLOT_ASSIGN_MAX + 1, slot_of, NULL),
                     SLOT_ASSIGN_ERR_ARG);
    xy[1][0] = NAN;
    assert_int_equal(
        slot_assign_min_sq((const double(*)[2])xy, (const double(*)[2])sl, 2, slot_of, NULL),
        SLOT_ASSIGN_ERR_ARG);
    assert_int_equal(slot_of[0], -7);
    assert_int_equal(slot_of[1], -7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_optimal_against_every_permutation),
        cmocka_unit_test(test_large_team_no_swap_or_cycle_improves),
        cmocka_unit_test(test_synchronised_paths_keep_apart),
        cmocka_unit_test(test_assignment_holds_while_driven_to_it),
        cmocka_unit_test(test_column_keeps_its_order),
        cmocka_unit_test(test_sorted_on_one_axis),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for pgrid: on random scenes (uniform, clustered, a long thin
 * row, points on cell edges and duplicates, items left out) every query
 * returns exactly what the brute scan returns, in the same ascending
 * order; a cell size that needs too many cells still indexes everything;
 * bad input is refused and a full buffer is reported. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "pgrid.h"
#include "prng.h"

static pgrid g; /* too large for a 68040 test's stack */
static int32_t got[PGRID_MAX_ITEMS], want[PGRID_MAX_ITEMS];
static double xs[PGRID_MAX_ITEMS], ys[PGRID_MAX_ITEMS];
static int use[PGRID_MAX_ITEMS];

enum { SCENE_UNIFORM, SCENE_CLUSTER, SCENE_ROW, SCENE_LATTICE, SCENE_COUNT };

static void scene(prng_state *r, int kind, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        switch (kind) {
        case SCENE_UNIFORM:
            xs[i] = 200.0 * prng_uniform(r) - 50.0;
            ys[i] = 80.0 * prng_uniform(r) + 3.0;
            break;
        case SCENE_CLUSTER: /* a few tight clumps far apart */
            xs[i] = 1000.0 * (double)(i % 4) + 0.3 * prng_gauss(r);
            ys[i] = -500.0 * (double)(i % 3) + 0.3 * prng_gauss(r);
            break;
        case SCENE_ROW: /* 10 abreast, 1 m apart, as a large team starts */
            xs[i] = 4.0 + (double)(i - i % 10) / 10.0; /* the row: i / 10 */
            ys[i] = (double)(i % 10) - 4.5;
            break;
        default: /* integer lattice with duplicates: items on cell edges */
            xs[i] = (double)(prng_u64(r) % 20);
            ys[i] = (double)(prng_u64(r) % 20);
            break;
        }
        use[i] = (prng_u64(r) % 7) != 0;
    }
}

static void check_queries(prng_state *r, int n, int queries)
{
    int q, k;
    for (q = 0; q < queries; q++) {
        /* around an item, or anywhere, radii from 0 to past the scene */
        const int at = (int)(prng_u64(r) % (uint64_t)n);
        const double x = (q & 1) ? xs[at] : 1500.0 * prng_uniform(r) - 300.0;
        const double y = (q & 1) ? ys[at] : 1500.0 * prng_uniform(r) - 800.0;
        const double rad = (q % 5 == 0) ? 0.0 : (q % 7 == 0 ? 3000.0 : 8.0 * prng_uniform(r));
        const int nw = pgrid_query_brute(&g, x, y, rad, want, PGRID_MAX_ITEMS);
        const int ng = pgrid_query(&g, x, y, rad, got, PGRID_MAX_ITEMS);
        assert_true(nw >= 0);
        assert_int_equal(ng, nw);
        for (k = 0; k < nw; k++)
            assert_int_equal(got[k], want[k]);
    }
}

static void test_matches_brute_force(void **st)
{
    static const int sizes[] = { 1, 2, 7, 100, 1000, PGRID_MAX_ITEMS };
    static const double cells[] = { 0.05, 1.0, 2.5, 40.0 };
    prng_state r;
    size_t s, c;
    int kind;
    (void)st;
    prng_seed(&r, 2026);
    for (kind = 0; kind < SCENE_COUNT; kind++)
        for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
            for (c = 0; c < sizeof cells / sizeof cells[0]; c++) {
                scene(&r, kind, sizes[s]);
                assert_int_equal(pgrid_build(&g, xs, ys, use, sizes[s], cells[c]), PGRID_OK);
                assert_true(g.nx * g.ny <= PGRID_MAX_CELLS);
                check_queries(&r, sizes[s], 200);
            }
}

/* The brute scan must itself see what a query misses: a check that the
 * comparison can fail (a grid that dropped one item from its cell). */
static void test_comparison_can_fail(void **st)
{
    prng_state r;
    int ng, nw, q, differs = 0;
    (void)st;
    prng_seed(&r, 7);
    scene(&r, SCENE_UNIFORM, 500);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 500, 2.0), PGRID_OK);
    g.idx[g.cell_start[g.nx * g.ny] - 1] = g.idx[0]; /* corrupt: one item lost, one twice */
    for (q = 0; q < 500 && !differs; q++) {
        ng = pgrid_query(&g, xs[q], ys[q], 30.0, got, PGRID_MAX_ITEMS);
        nw = pgrid_query_brute(&g, xs[q], ys[q], 30.0, want, PGRID_MAX_ITEMS);
        differs = ng != nw || (ng > 0 && got[ng - 1] != want[nw - 1]) ||
                  (ng > 1 && got[0] == got[1]);
    }
    assert_true(differs);
}

static void test_every_item_at_radius_zero(void **st)
{
    int i;
    (void)st;
    for (i = 0; i < 300; i++) {
        xs[i] = 0.1 * (double)i;
        ys[i] = -0.7 * (double)i;
    }
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 300, 0.5), PGRID_OK);
    for (i = 0; i < 300; i++) {
        assert_int_equal(pgrid_query(&g, xs[i], ys[i], 0.0, got, 4), 1);
        assert_int_equal(got[0], i);
    }
}

static void test_bad_input_and_full(void **st)
{
    int i;
    (void)st;
    for (i = 0; i < 10; i++) {
        xs[i] = (double)i;
        ys[i] = 0.0;
    }
    assert_int_equal(pgrid_build(NULL, xs, ys, NULL, 10, 1.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, NULL, ys, NULL, 10, 1.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, -1, 1.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, PGRID_MAX_ITEMS + 1, 1.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 10, 0.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 10, NAN), PGRID_ERR_ARG);
    xs[3] = INFINITY;
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 10, 1.0), PGRID_ERR_ARG);
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, 100.0, got, 10), 0); /* refused: empty */
    use[3] = 0;
    for (i = 0; i < 10; i++)
        use[i] = i != 3;
    assert_int_equal(pgrid_build(&g, xs, ys, use, 10, 1.0), PGRID_OK); /* unused: not read */
    xs[3] = 3.0;
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, 100.0, got, 10), 9);
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, 100.0, got, 8), PGRID_ERR_FULL);
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, -1.0, got, 10), PGRID_ERR_ARG);
    assert_int_equal(pgrid_query(&g, NAN, 0.0, 1.0, got, 10), PGRID_ERR_ARG);
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, 1.0, NULL, 10), PGRID_ERR_ARG);
    assert_int_equal(pgrid_query_brute(&g, 0.0, 0.0, INFINITY, got, 10), PGRID_ERR_ARG);
    assert_int_equal(pgrid_build(&g, xs, ys, NULL, 0, 1.0), PGRID_OK);
    assert_int_equal(pgrid_query(&g, 0.0, 0.0, 1e6, got, 10), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_brute_force),
        cmocka_unit_test(test_comparison_can_fail),
        cmocka_unit_test(test_every_item_at_radius_zero),
        cmocka_unit_test(test_bad_input_and_full),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

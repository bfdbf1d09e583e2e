/* Unit tests for rover_map: the box merge against the grid it came from
 * (every occupied cell in exactly one box, no free cell in any) on random
 * maps, the capacity limit, the validator on a corrupted map, the team's
 * layout on a map (the open layout moved rigidly onto the start pose),
 * start and goal refused on obstacles and off the map, auto landmarks on
 * free cells, and the sonar grid cast against a brute-force cast over all
 * merged boxes. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "formation.h"
#include "prng.h"
#include "rover_map.h"
#include "sonar.h"

static rover_map M; /* large: keep off the stack */
static rover_world_config W, OPEN;
static rover_obstacle BOX[ROVER_WORLD_MAX_OBST];
static unsigned char COUNT[ROVER_MAP_MAX_SIDE * 64];
static sonar_world SW;

static void map_empty(int w, int h, double res, double ox, double oy)
{
    memset(&M, 0, sizeof M);
    M.width = w;
    M.height = h;
    M.resolution_m = res;
    M.origin_x_m = ox;
    M.origin_y_m = oy;
}

static void set(int i, int j)
{
    M.cell[(long)j * M.width + i] = ROVER_MAP_OCCUPIED;
}

/* Random rectangles and single cells: runs that merge and runs that don't. */
static void map_random(prng_state *r, int w, int h, int rects, int dots)
{
    int k, i, j;
    map_empty(w, h, 0.1 + 0.4 * prng_uniform(r), -5.0 + 10.0 * prng_uniform(r),
              -5.0 + 10.0 * prng_uniform(r));
    for (k = 0; k < rects; k++) {
        const int i0 = (int)(prng_uniform(r) * w), j0 = (int)(prng_uniform(r) * h);
        const int i1 = i0 + (int)(prng_uniform(r) * 8), j1 = j0 + (int)(prng_uniform(r) * 8);
        for (j = j0; j <= j1 && j < h; j++)
            for (i = i0; i <= i1 && i < w; i++)
                set(i, j);
    }
    for (k = 0; k < dots; k++)
        set((int)(prng_uniform(r) * w), (int)(prng_uniform(r) * h));
}

/* Cell range of a box, from its extent in cells (must be whole cells). */
static void box_cells(const rover_obstacle *o, int *i0, int *j0, int *i1, int *j1)
{
    const double u0 = (o->cx_m - o->hx_m - M.origin_x_m) / M.resolution_m;
    const double v0 = (o->cy_m - o->hy_m - M.origin_y_m) / M.resolution_m;
    const double u1 = (o->cx_m + o->hx_m - M.origin_x_m) / M.resolution_m;
    const double v1 = (o->cy_m + o->hy_m - M.origin_y_m) / M.resolution_m;
    assert_true(fabs(u0 - floor(u0 + 0.5)) < 1e-6 && fabs(v1 - floor(v1 + 0.5)) < 1e-6);
    *i0 = (int)floor(u0 + 0.5);
    *j0 = (int)floor(v0 + 0.5);
    *i1 = (int)floor(u1 + 0.5) - 1;
    *j1 = (int)floor(v1 + 0.5) - 1;
}

static void test_merge_covers_exactly_the_occupied_cells(void **state)
{
    prng_state r;
    int trial, n, k, i, j, occupied;
    (void)state;
    prng_seed(&r, 7);
    for (trial = 0; trial < 60; trial++) {
        const int w = 1 + (int)(prng_uniform(&r) * 120), h = 1 + (int)(prng_uniform(&r) * 64);
        map_random(&r, w, h, (int)(prng_uniform(&r) * 40), (int)(prng_uniform(&r) * 80));
        assert_int_equal(rover_map_merge(&M, BOX, ROVER_WORLD_MAX_OBST, &n), ROVER_MAP_OK);
        memset(COUNT, 0, sizeof COUNT);
        for (k = 0; k < n; k++) {
            int i0, j0, i1, j1;
            assert_int_equal(BOX[k].kind, ROVER_OBST_BOX);
            assert_true(BOX[k].angle_rad == 0.0 && BOX[k].height_m > 0.0);
            box_cells(&BOX[k], &i0, &j0, &i1, &j1);
            assert_true(i0 >= 0 && j0 >= 0 && i1 < w && j1 < h && i0 <= i1 && j0 <= j1);
            for (j = j0; j <= j1; j++)
                for (i = i0; i <= i1; i++)
                    COUNT[j * w + i]++;
        }
        occupied = 0;
        for (j = 0; j < h; j++)
            for (i = 0; i < w; i++) {
                const int occ = M.cell[(long)j * w + i] == ROVER_MAP_OCCUPIED;
                occupied += occ;
                assert_int_equal(COUNT[j * w + i], occ); /* the map is restored, too */
            }
        assert_true(n <= occupied);
    }
}

static void test_merge_makes_one_box_of_a_block(void **state)
{
    int i, j, n;
    (void)state;
    map_empty(50, 40, 0.05, 1.0, 2.0);
    for (j = 10; j < 30; j++)
        for (i = 5; i < 25; i++)
            set(i, j);
    assert_int_equal(rover_map_merge(&M, BOX, ROVER_WORLD_MAX_OBST, &n), ROVER_MAP_OK);
    assert_int_equal(n, 1);
    /* its outline: x 1 + 5 * 0.05 .. 1 + 25 * 0.05, y 2 + 0.5 .. 2 + 1.5 */
    assert_true(fabs(BOX[0].cx_m - BOX[0].hx_m - 1.25) < 1e-12 &&
                fabs(BOX[0].cx_m + BOX[0].hx_m - 2.25) < 1e-12);
    assert_true(fabs(BOX[0].cy_m - BOX[0].hy_m - 2.5) < 1e-12 &&
                fabs(BOX[0].cy_m + BOX[0].hy_m - 3.5) < 1e-12);
}

static void test_merge_refuses_beyond_capacity(void **state)
{
    int i, j, n;
    (void)state;
    map_empty(20, 20, 0.1, 0.0, 0.0);
    for (j = 0; j < 20; j++)
        for (i = (j & 1); i < 20; i += 2)
            set(i, j); /* a checkerboard: 200 single-cell boxes */
    assert_int_equal(rover_map_merge(&M, BOX, 199, &n), ROVER_MAP_ERR_BOXES);
    assert_int_equal(rover_map_merge(&M, BOX, 200, &n), ROVER_MAP_OK);
    assert_int_equal(n, 200);
    for (j = 0; j < 20; j++)
        for (i = 0; i < 20; i++)
            assert_int_equal(M.cell[j * 20 + i],
                             ((i + j) & 1) == 0 ? ROVER_MAP_OCCUPIED : ROVER_MAP_FREE);
}

static void test_validate_refuses_each_corruption(void **state)
{
    (void)state;
    map_empty(10, 10, 0.1, 0.0, 0.0);
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_OK);
    M.width = 0;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_SIZE);
    M.width = ROVER_MAP_MAX_SIDE + 1;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_SIZE);
    M.width = 10;
    M.height = -1;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_SIZE);
    M.height = 10;
    M.resolution_m = 0.0;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_RESOLUTION);
    M.resolution_m = NAN;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_RESOLUTION);
    M.resolution_m = 0.1;
    M.origin_y_m = INFINITY;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_RESOLUTION);
    M.origin_y_m = 0.0;
    M.cell[57] = 3;
    assert_int_equal(rover_map_validate(&M), ROVER_MAP_ERR_CELL);
    assert_int_equal(rover_map_validate(NULL), ROVER_MAP_ERR_ARG);
    assert_string_equal(rover_map_strerror(ROVER_MAP_ERR_CELL),
                        "a cell is neither free nor occupied");
}

/* A 30 m x 20 m hall with a wall round it and a block in the middle. */
static void map_hall(void)
{
    int i, j;
    map_empty(300, 200, 0.1, -10.0, -10.0);
    for (i = 0; i < 300; i++) {
        set(i, 0);
        set(i, 199);
    }
    for (j = 0; j < 200; j++) {
        set(0, j);
        set(299, j);
    }
    for (j = 90; j < 110; j++)
        for (i = 190; i < 210; i++)
            set(i, j); /* x 9..11, y -1..1 */
}

static void test_layout_is_the_open_layout_moved_to_the_start(void **state)
{
    static const int formations[] = { FORMATION_LINE, FORMATION_TRIANGLE, FORMATION_COLUMN };
    rover_map_site s;
    int f, n, k;
    (void)state;
    map_hall();
    memset(&s, 0, sizeof s);
    s.start.x_m = -3.0;
    s.start.y_m = 2.0;
    s.start.theta_rad = 0.7;
    s.goal_m[0] = 14.0;
    s.goal_m[1] = 5.0;
    s.n_landmarks = ROVER_MAP_LANDMARKS_AUTO;
    for (f = 0; f < 3; f++)
        for (n = 1; n <= 7; n += 3) {
            double mx = 0.0, my = 0.0;
            assert_int_equal(rover_world_from_map(&W, &M, &s, n, 1.0, formations[f]), ROVER_MAP_OK);
            assert_int_equal(rover_world_layout(&OPEN, ROVER_WORLD_OPEN, n, 1.0, formations[f]), 0);
            assert_int_equal(W.world, ROVER_WORLD_FILE);
            for (k = 0; k < n; k++) {
                pose2 a, b;
                /* team-frame poses agree: the layout moved rigidly */
                rover_world_to_team(&W, &W.start_c[k], &a);
                rover_world_to_team(&OPEN, &OPEN.start_c[k], &b);
                assert_true(fabs(a.x_m - b.x_m) < 1e-9 && fabs(a.y_m - b.y_m) < 1e-9);
                assert_true(fabs(vec2_wrap_rad(W.start_c[k].theta_rad - 0.7)) < 1e-12);
                /* the team reference is the mean of the O points */
                mx += W.start_c[k].x_m - ROVER_BEACON_D_M * cos(0.7);
                my += W.start_c[k].y_m - ROVER_BEACON_D_M * sin(0.7);
            }
            assert_true(fabs(mx / n + 3.0) < 1e-9 && fabs(my / n - 2.0) < 1e-9);
            assert_true(W.n_obst == 5); /* two long walls, two short, the block */
            assert_true(W.x_min_m == -10.0 && fabs(W.x_max_m - 20.0) < 1e-9);
        }
}

static void test_start_and_goal_refused_on_obstacles_and_off_the_map(void **state)
{
    rover_map_site s;
    (void)state;
    map_hall();
    memset(&s, 0, sizeof s);
    s.start.x_m = -3.0;
    s.goal_m[0] = 14.0;
    s.n_landmarks = 0;
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_OK);
    s.goal_m[0] = 10.0; /* in the block */
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_GOAL);
    assert_int_equal(W.n_obst, 0); /* zeroed on failure */
    s.goal_m[0] = 25.0;            /* off the map */
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_GOAL);
    s.goal_m[0] = 14.0;
    s.start.x_m = 9.0; /* the middle robot's nose on the block (x 9..11) */
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_START);
    s.start.x_m = -3.0;
    s.start.y_m = -9.3; /* a robot on the south wall */
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_START);
    s.start.y_m = 0.0;
    s.start.x_m = -30.0; /* off the map */
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_START);
    s.start.x_m = NAN;
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE), ROVER_MAP_ERR_START);
    s.start.x_m = -3.0;
    s.n_landmarks = ROVER_WORLD_MAX_LANDMARKS + 1;
    assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE),
                     ROVER_MAP_ERR_LANDMARKS);
}

static void test_auto_landmarks_stand_on_free_cells(void **state)
{
    double lm[ROVER_WORLD_MAX_LANDMARKS][2];
    const pose2 start = { -3.0, 2.0, 0.0 };
    const double near_goal[2] = { 14.0, 5.0 }, far_goal[2] = { 500.0, 300.0 };
    int n, k;
    (void)state;
    map_hall();
    n = rover_map_auto_landmarks(&M, &start, near_goal, lm);
    assert_true(n >= 8 && n <= ROVER_WORLD_MAX_LANDMARKS);
    for (k = 0; k < n; k++)
        assert_int_equal(rover_map_blocked(&M, lm[k][0], lm[k][1]), 0);
    /* a way far longer than 64 posts at 3 m: fewer, farther apart, still on the map */
    map_empty(2000, 1200, 0.5, -10.0, -10.0);
    n = rover_map_auto_landmarks(&M, &start, far_goal, lm);
    assert_true(n > ROVER_WORLD_MAX_LANDMARKS / 2 && n <= ROVER_WORLD_MAX_LANDMARKS);
}

/* A corridor bent like a hairpin: along x from (0, 1) to (20, 1), 2 m
 * wide; up to (20, 15), 1.3 m wide; back to (0, 15), 2 m wide;
 * everything else occupied. */
static const double hairpin_way[4][2] = {
    { 0.0, 1.0 }, { 20.0, 1.0 }, { 20.0, 15.0 }, { 0.0, 15.0 }
};

static void map_hairpin(void)
{
    int i, j, k;
    map_empty(230, 180, 0.1, -1.5, -1.5);
    for (j = 0; j < M.height; j++)
        for (i = 0; i < M.width; i++) {
            const double x = M.origin_x_m + (i + 0.5) * M.resolution_m;
            const double y = M.origin_y_m + (j + 0.5) * M.resolution_m;
            int free_cell = 0;
            for (k = 0; k < 3; k++) {
                const double h = k == 1 ? 0.65 : 1.0;
                const double x0 = fmin(hairpin_way[k][0], hairpin_way[k + 1][0]) - h;
                const double x1 = fmax(hairpin_way[k][0], hairpin_way[k + 1][0]) + h;
                const double y0 = fmin(hairpin_way[k][1], hairpin_way[k + 1][1]) - h;
                const double y1 = fmax(hairpin_way[k][1], hairpin_way[k + 1][1]) + h;
                free_cell |= x >= x0 && x <= x1 && y >= y0 && y <= y1;
            }
            if (!free_cell)
                set(i, j);
        }
}

/* The posts p sees: within range_m, no occupied cell on the line between. */
static int posts_in_sight(const double p[2], const double (*lm)[2], int n, double range_m)
{
    int k, q, seen = 0;
    for (k = 0; k < n; k++) {
        const double d = hypot(lm[k][0] - p[0], lm[k][1] - p[1]);
        int clear = d <= range_m;
        for (q = 1; clear && q < 200; q++) {
            const double f = q / 200.0;
            clear = !rover_map_blocked(&M, p[0] + f * (lm[k][0] - p[0]),
                                       p[1] + f * (lm[k][1] - p[1]));
        }
        seen += clear;
    }
    return seen;
}

/* The fewest posts in sight (6 m, the camera's range) from any point of
 * the hairpin's way, every 0.25 m. */
static int fewest_in_sight(const double (*lm)[2], int n)
{
    int k, fewest = 1 << 30;
    for (k = 0; k < 3; k++) {
        const double len = hypot(hairpin_way[k + 1][0] - hairpin_way[k][0],
                                 hairpin_way[k + 1][1] - hairpin_way[k][1]);
        double a;
        for (a = 0.0; a <= len; a += 0.25) {
            const double p[2] = {
                hairpin_way[k][0] + a / len * (hairpin_way[k + 1][0] - hairpin_way[k][0]),
                hairpin_way[k][1] + a / len * (hairpin_way[k + 1][1] - hairpin_way[k][1])
            };
            const int seen = posts_in_sight(p, lm, n, 6.0);
            if (seen < fewest)
                fewest = seen;
        }
    }
    return fewest;
}

/* Posts along a bent way stand on free cells and keep one in sight from
 * every point of it, the narrow leg's too (posts 3.5, 2.45, 1.5 or 0.8 m
 * out, as they once stood, left it none); along the straight line from
 * start to goal (the map's way not known) the hairpin's far end has none
 * in sight. And the
 * straight rule is rover_map_landmarks_along on the way of two points. */
static void test_landmarks_along_a_bent_way(void **state)
{
    double lm[ROVER_WORLD_MAX_LANDMARKS][2], straight[ROVER_WORLD_MAX_LANDMARKS][2];
    const pose2 start = { 0.0, 1.0, 0.0 };
    int n, ns, k;
    (void)state;
    map_hairpin();
    n = rover_map_landmarks_along(&M, hairpin_way, 4, 0.0, lm);
    assert_true(n >= 10);
    for (k = 0; k < n; k++)
        assert_int_equal(rover_map_blocked(&M, lm[k][0], lm[k][1]), 0);
    ns = rover_map_auto_landmarks(&M, &start, hairpin_way[3], straight);
    print_message(
        "hairpin corridor: %d posts along the way, at least %d in sight; %d along the straight "
        "line, at least %d in sight\n",
        n, fewest_in_sight((const double(*)[2])lm, n), ns,
        fewest_in_sight((const double(*)[2])straight, ns));
    assert_true(fewest_in_sight((const double(*)[2])lm, n) >= 1);
    assert_int_equal(fewest_in_sight((const double(*)[2])straight, ns), 0);
    assert_int_equal(rover_map_landmarks_along(&M, hairpin_way, 2, 0.0, lm),
                     rover_map_auto_landmarks(&M, &start, hairpin_way[1], straight));
    assert_memory_equal(lm, straight,
                        sizeof lm[0] *
                            (size_t)rover_map_auto_landmarks(&M, &start, hairpin_way[1], straight));
    assert_int_equal(rover_map_landmarks_along(&M, hairpin_way, 0, 0.0, lm), 0);
    assert_int_equal(rover_map_landmarks_along(&M, hairpin_way, ROVER_MAP_WAY_MAX + 1, 0.0, lm), 0);
}

/* The sonar's grid cast on the merged boxes of random large maps gives
 * the brute-force cast's hit over every box. */
static void test_ray_cast_equals_brute_force_on_merged_maps(void **state)
{
    prng_state r;
    int trial, n, k, q, hits = 0;
    (void)state;
    prng_seed(&r, 11);
    for (trial = 0; trial < 6; trial++) {
        map_random(&r, 400, 400, 600, 600);
        M.resolution_m = 0.25; /* 100 m x 100 m */
        assert_int_equal(rover_map_merge(&M, BOX, ROVER_WORLD_MAX_OBST, &n), ROVER_MAP_OK);
        sonar_world_init(&SW);
        for (k = 0; k < n; k++)
            assert_true(sonar_world_add_box(&SW, BOX[k].cx_m, BOX[k].cy_m, BOX[k].hx_m, BOX[k].hy_m,
                                            0.0, 0.0, BOX[k].height_m) >= 0);
        assert_int_equal(sonar_world_build(&SW), 0);
        assert_true(SW.built);
        for (q = 0; q < 2000; q++) {
            sonar_hit a, b;
            const double x = M.origin_x_m + 100.0 * prng_uniform(&r),
                         y = M.origin_y_m + 100.0 * prng_uniform(&r);
            const double dir = 2.0 * VEC2_PI * prng_uniform(&r),
                         range = 0.5 + 10.0 * prng_uniform(&r);
            const int ha = sonar_cast(&a, &SW, x, y, 0.2, dir, range);
            const int hb = sonar_cast_brute(&b, &SW, x, y, 0.2, dir, range);
            assert_int_equal(ha, hb);
            if (ha == 1) {
                assert_true(fabs(a.t_m - b.t_m) < 1e-9);
                hits++;
            }
        }
    }
    assert_true(hits > 1000); /* the maps are dense enough to be hit */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_merge_covers_exactly_the_occupied_cells),
        cmocka_unit_test(test_merge_makes_one_box_of_a_block),
        cmocka_unit_test(test_merge_refuses_beyond_capacity),
        cmocka_unit_test(test_validate_refuses_each_corruption),
        cmocka_unit_test(test_layout_is_the_open_layout_moved_to_the_start),
        cmocka_unit_test(test_start_and_goal_refused_on_obstacles_and_off_the_map),
        cmocka_unit_test(test_auto_landmarks_stand_on_free_cells),
        cmocka_unit_test(test_landmarks_along_a_bent_way),
        cmocka_unit_test(test_ray_cast_equals_brute_force_on_merged_maps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

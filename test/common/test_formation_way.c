/* Unit tests for formation_way (tandem-scenario's measures of a world):
 * on worlds whose answers are known by construction, a wall across the
 * way with one gap, with two gaps side by side, and no wall at all, the
 * way's length, the widest way's bottleneck (passage_width_m) and the
 * cross-section of all the ways together (cut_width_m) come out as the
 * geometry says, to a cell. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#include <string.h>

#include "formation_scen.h"

#define CELL_M 0.1
/* the bottleneck is found on cell centres (a cell off) by bisection to
 * 2 cm each side; it never comes out wider than the gap */
#define PASSAGE_TOL_M (CELL_M + 0.04)

static rover_world_config W;

/* 20 m x 10 m, three robots starting round (3, 5), the goal at (17, 5). */
static void world_open(void)
{
    int k;
    memset(&W, 0, sizeof W);
    W.x_max_m = 20.0;
    W.y_max_m = 10.0;
    W.goal_m[0] = 17.0;
    W.goal_m[1] = 5.0;
    W.n_robots = 3;
    for (k = 0; k < 3; k++)
        W.start_c[k] = (pose2){ 3.0, 4.0 + k, 0.0 };
}

static void wall(double y0, double y1)
{
    rover_obstacle *o = &W.obst[W.n_obst++];
    memset(o, 0, sizeof *o);
    o->kind = ROVER_OBST_BOX;
    o->cx_m = 10.0;
    o->cy_m = 0.5 * (y0 + y1);
    o->hx_m = 0.1;
    o->hy_m = 0.5 * (y1 - y0);
    o->height_m = 0.5;
}

/* The wall x = 10 across the world with gaps [a, b) (sorted). */
static void wall_with_gaps(const double (*gap)[2], int n)
{
    double y = -1.0;
    int i;
    for (i = 0; i < n; i++) {
        wall(y, gap[i][0]);
        y = gap[i][1];
    }
    wall(y, 11.0);
}

static void test_open(void **state)
{
    (void)state;
    world_open();
    assert_true(fabs(fm_way_length_m(&W) - 14.0) < CELL_M);
    assert_true(fm_passage_width_m(&W) == 10.0); /* 5 m kept all the way */
    assert_true(fm_cut_width_m(&W, 2.38) >= 2.38);
}

static void test_one_gap(void **state)
{
    static const double gap[1][2] = { { 4.4, 5.6 } }; /* 1.2 m */
    double passage, cut;
    (void)state;
    world_open();
    wall_with_gaps(gap, 1);
    passage = fm_passage_width_m(&W);
    cut = fm_cut_width_m(&W, 2.38);
    print_message("one 1.2 m gap: passage %.3f m, cut %.3f m\n", passage, cut);
    assert_true(passage <= 1.2 && passage >= 1.2 - PASSAGE_TOL_M);
    assert_true(fabs(cut - 1.2) <= 1.5 * CELL_M);
}

/* Two 1.5 m gaps 3 m apart: no single way is as wide as the team, both
 * together are 3 m, less one body allowance (the cut counts the gaps'
 * passable middles and one body's 2 x 0.32 m: it errs toward asking for
 * a change). */
static void test_two_gaps_side_by_side(void **state)
{
    static const double gap[2][2] = { { 2.75, 4.25 }, { 5.75, 7.25 } };
    double passage, cut;
    (void)state;
    world_open();
    wall_with_gaps(gap, 2);
    passage = fm_passage_width_m(&W);
    cut = fm_cut_width_m(&W, 3.5);
    print_message("two 1.5 m gaps: passage %.3f m, cut %.3f m\n", passage, cut);
    assert_true(passage <= 1.5 && passage >= 1.5 - PASSAGE_TOL_M);
    assert_true(fabs(cut - (3.0 - 2.0 * 0.32)) <= 2.0 * CELL_M);
}

/* A wall at 45 degrees across the world with one 1.5 m gap: the ways
 * through it step diagonally, and the flow must cancel along diagonal
 * steps to find them all; the cut counts oblique cells (up to sqrt(2)
 * times the length), never fewer than the gap's passable middle. */
static void test_oblique_gap(void **state)
{
    const double c = cos(M_PI / 4.0), sn = sin(M_PI / 4.0), gap = 1.5, half = 20.0;
    double cut;
    int side;
    (void)state;
    world_open();
    for (side = -1; side <= 1; side += 2) { /* two boxes along the diagonal, the gap between */
        rover_obstacle *o = &W.obst[W.n_obst++];
        const double d = side * (0.5 * gap + 0.5 * half);
        memset(o, 0, sizeof *o);
        o->kind = ROVER_OBST_BOX;
        o->cx_m = 10.0 + d * c;
        o->cy_m = 5.0 - d * sn;
        o->hx_m = 0.5 * half;
        o->hy_m = 0.1;
        o->angle_rad = -M_PI / 4.0;
        o->height_m = 0.5;
    }
    cut = fm_cut_width_m(&W, 3.0);
    print_message("oblique 1.5 m gap: passage %.3f m, cut %.3f m\n", fm_passage_width_m(&W), cut);
    assert_true(cut >= gap - 2.0 * CELL_M);
    assert_true(cut <= (gap - 0.64) * sqrt(2.0) + 0.64 + 2.0 * CELL_M);
}

/* A team wider than the start's distance to the wall: the cells within
 * half its width of the start are taken by the way, so the flow starts
 * on the start's side and the cut is the gap, not the wall's far side. */
static void test_wall_near_start(void **state)
{
    static const double gap[1][2] = { { 4.4, 5.6 } };
    double cut;
    (void)state;
    world_open();
    W.x_max_m = 40.0;
    W.goal_m[0] = 37.0;
    wall_with_gaps(gap, 1); /* x = 10, 7 m from the start; the team 16 m wide */
    cut = fm_cut_width_m(&W, 16.0);
    print_message("wall 7 m from a 16 m team's start: cut %.3f m\n", cut);
    assert_true(fabs(cut - 1.2) <= 1.5 * CELL_M);
}

static void test_no_way(void **state)
{
    static const double gap[1][2] = { { 5.0, 5.3 } }; /* narrower than the body */
    (void)state;
    world_open();
    wall_with_gaps(gap, 1);
    assert_true(isnan(fm_way_length_m(&W)));
    assert_true(fm_passage_width_m(&W) == 0.0);
    assert_true(fm_cut_width_m(&W, 2.38) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open),
        cmocka_unit_test(test_one_gap),
        cmocka_unit_test(test_two_gaps_side_by_side),
        cmocka_unit_test(test_oblique_gap),
        cmocka_unit_test(test_wall_near_start),
        cmocka_unit_test(test_no_way),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

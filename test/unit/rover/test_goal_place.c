/* Unit tests for goal_place: a goal formation that fits stays where it is
 * given; the dead zone's goal, whose column of eight has its rearmost slot
 * on the U's back wall, moves to the nearest candidate where every slot and
 * the way to it from the centre keep the clearance (checked here by an
 * independent, finer sampling of the obstacle distance, and no nearer
 * candidate fits); a wall between two free slots is refused; a goal with
 * no room keeps the goal given and says so. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "formation.h"
#include "goal_place.h"
#include "rover_world.h"

static rover_world_config W;

/* The distance to the nearest obstacle or edge of the extent. */
static double clearance_at(const rover_world_config *w, double x, double y)
{
    double best = fmin(fmin(x - w->x_min_m, w->x_max_m - x), fmin(y - w->y_min_m, w->y_max_m - y));
    int k;
    for (k = 0; k < w->n_obst; k++)
        best = fmin(best, rover_obstacle_distance(&w->obst[k], x, y));
    return best;
}

/* Slot k of the formation around g, slot by slot (formation_slot_xy, not
 * the all-slots routine goal_place uses), headed from the team origin. */
static void slot_at(const rover_world_config *w, int type, int n, int k, const double g[2],
                    double p[2])
{
    double s[2];
    const double h = atan2(g[1] - w->team_origin.y_m, g[0] - w->team_origin.x_m);
    assert_int_equal(formation_slot_xy(s, type, n, k, w->spacing_m, 1.0), 0);
    p[0] = g[0] + cos(h) * s[0] - sin(h) * s[1];
    p[1] = g[1] + sin(h) * s[0] + cos(h) * s[1];
}

/* The least clearance over the slots and, every centimetre, the straight
 * ways to them from g. */
static double formation_clearance(const rover_world_config *w, int type, int n, const double g[2])
{
    double least = INFINITY;
    int k, i;
    for (k = 0; k < n; k++) {
        double p[2];
        const int steps = 400;
        slot_at(w, type, n, k, g, p);
        for (i = 0; i <= steps; i++) {
            const double f = (double)i / steps;
            least = fmin(least,
                         clearance_at(w, g[0] + f * (p[0] - g[0]), g[1] + f * (p[1] - g[1])));
        }
    }
    return least;
}

static void test_open_world_keeps_goal(void **state)
{
    int f;
    (void)state;
    for (f = FORMATION_LINE; f <= FORMATION_COLUMN; f++) {
        assert_int_equal(rover_world_layout(&W, ROVER_WORLD_OPEN, 8, 1.0, f), 0);
        assert_true(W.goal_fits);
        assert_true(W.goal_m[0] == W.goal_nominal_m[0] && W.goal_m[1] == W.goal_nominal_m[1]);
        assert_true(formation_clearance(&W, f, 8, W.goal_m) >= GOAL_PLACE_CLEAR_M);
    }
}

static void test_dead_zone_column_moves_to_nearest_fit(void **state)
{
    const int n = 8, f = FORMATION_COLUMN;
    double shift, step;
    int i, j, r;
    (void)state;
    assert_int_equal(rover_world_layout(&W, ROVER_WORLD_DEADZONE, n, 1.0, f), 0);
    /* as given, a slot is on (or the way to it crosses) the back wall */
    assert_true(formation_clearance(&W, f, n, W.goal_nominal_m) < GOAL_PLACE_CLEAR_M);
    assert_false(goal_place_fits(&W, f, n, 1.0, W.goal_nominal_m));
    assert_true(W.goal_fits);
    shift = hypot(W.goal_m[0] - W.goal_nominal_m[0], W.goal_m[1] - W.goal_nominal_m[1]);
    assert_true(shift > 0.0);
    assert_true(shift <= goal_place_radius_m(f, n, 1.0) + 1.0);
    /* placed: every slot and way clear, sampled 5x finer than the search
     * (between its samples the clearance falls by at most a quarter step) */
    assert_true(formation_clearance(&W, f, n, W.goal_m) >=
                GOAL_PLACE_CLEAR_M - 0.25 * GOAL_PLACE_STEP_M);
    /* nearest: no candidate of the grid nearer the goal given fits */
    step = fmax(GOAL_PLACE_STEP_M, (goal_place_radius_m(f, n, 1.0) + 1.0) / GOAL_PLACE_RINGS);
    r = (int)ceil(shift / step);
    for (j = -r; j <= r; j++)
        for (i = -r; i <= r; i++) {
            const double g[2] = { W.goal_nominal_m[0] + i * step, W.goal_nominal_m[1] + j * step };
            if (hypot(i * step, j * step) < shift - 1e-9)
                assert_false(goal_place_fits(&W, f, n, 1.0, g));
        }
}

/* A line of three 2 m apart, a short wall between the centre slot and the
 * left one: both slots are far from it, the way between them is not. */
static void test_wall_between_slots_refused(void **state)
{
    const double goal[2] = { 10.0, 0.0 };
    (void)state;
    assert_int_equal(rover_world_layout(&W, ROVER_WORLD_OPEN, 3, 2.0, FORMATION_LINE), 0);
    W.goal_m[0] = goal[0];
    W.goal_m[1] = goal[1];
    W.n_obst = 0;
    assert_int_equal(rover_world_add_box(&W, goal[0], 1.0, 0.5, 0.05, 0.0, 0.5), 0);
    assert_true(clearance_at(&W, goal[0], 2.0) > GOAL_PLACE_CLEAR_M);
    assert_true(clearance_at(&W, goal[0], 0.0) > GOAL_PLACE_CLEAR_M);
    assert_false(goal_place_fits(&W, FORMATION_LINE, 3, 2.0, goal));
    assert_int_equal(goal_place(&W, FORMATION_LINE, 2.0), GOAL_PLACE_OK);
    assert_true(W.goal_fits);
    assert_true(W.goal_m[0] != goal[0] || W.goal_m[1] != goal[1]);
    assert_true(formation_clearance(&W, FORMATION_LINE, 3, W.goal_m) >=
                GOAL_PLACE_CLEAR_M - 0.25 * GOAL_PLACE_STEP_M);
}

/* A world 2.5 m across for a line 2 m wide: no candidate keeps its end
 * slots 0.45 m inside; the goal given is kept. */
static void test_no_room_keeps_goal(void **state)
{
    const double goal[2] = { 10.0, 0.0 };
    (void)state;
    assert_int_equal(rover_world_layout(&W, ROVER_WORLD_OPEN, 3, 1.0, FORMATION_LINE), 0);
    W.goal_m[0] = goal[0];
    W.goal_m[1] = goal[1];
    W.n_obst = 0;
    W.x_min_m = goal[0] - 1.25;
    W.x_max_m = goal[0] + 1.25;
    W.y_min_m = goal[1] - 1.25;
    W.y_max_m = goal[1] + 1.25;
    W.team_origin.x_m = 0.0;
    W.team_origin.y_m = 0.0;
    assert_int_equal(goal_place(&W, FORMATION_LINE, 1.0), GOAL_PLACE_ERR_NO_FIT);
    assert_false(W.goal_fits);
    assert_true(W.goal_m[0] == goal[0] && W.goal_m[1] == goal[1]);
    assert_true(W.goal_nominal_m[0] == goal[0] && W.goal_nominal_m[1] == goal[1]);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    assert_int_equal(goal_place(NULL, FORMATION_LINE, 1.0), GOAL_PLACE_ERR_ARG);
    assert_int_equal(rover_world_layout(&W, ROVER_WORLD_OPEN, 3, 1.0, FORMATION_LINE), 0);
    assert_int_equal(goal_place(&W, 99, 1.0), GOAL_PLACE_ERR_ARG);
    assert_int_equal(goal_place(&W, FORMATION_LINE, -1.0), GOAL_PLACE_ERR_ARG);
    assert_false(goal_place_fits(NULL, FORMATION_LINE, 3, 1.0, W.goal_m));
    assert_true(isnan(goal_place_radius_m(FORMATION_LINE, 0, 1.0)));
    assert_true(fabs(goal_place_radius_m(FORMATION_LINE, 3, 1.0) - 1.0) < 1e-12);
    /* the tests' boxes: refused into no world and into a full one */
    assert_int_equal(rover_world_add_box(NULL, 0, 0, 1, 1, 0, 1), ROVER_WORLD_ERR_ARG);
    W.n_obst = ROVER_WORLD_MAX_OBST;
    assert_int_equal(rover_world_add_box(&W, 0, 0, 1, 1, 0, 1), ROVER_WORLD_ERR_ARG);
    assert_int_equal(W.n_obst, ROVER_WORLD_MAX_OBST);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_world_keeps_goal),
        cmocka_unit_test(test_dead_zone_column_moves_to_nearest_fit),
        cmocka_unit_test(test_wall_between_slots_refused),
        cmocka_unit_test(test_no_room_keeps_goal),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

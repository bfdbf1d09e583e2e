/* Unit tests for fleet: the teams' members by id, their lanes, start
 * poses and goals (ahead and crossing), the same for the same arguments
 * (deterministic), each team's frame at its own start, rows of lanes for
 * many teams inside the world, and the capacities refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "fleet.h"
#include "formation.h"

/* Large: not on the stack. */
static rover_world_config W, W2, ONE;

static void test_members(void **state)
{
    rover_fleet f;
    int32_t lo, hi;
    (void)state;
    assert_int_equal(rover_fleet_layout(&W, &f, 4, 3, 1.0, FORMATION_LINE, ROVER_FLEET_GOALS_AHEAD),
                     0);
    assert_int_equal(W.n_robots, 12);
    assert_int_equal(rover_fleet_team_of(&f, 1), 0);
    assert_int_equal(rover_fleet_team_of(&f, 3), 0);
    assert_int_equal(rover_fleet_team_of(&f, 4), 1);
    assert_int_equal(rover_fleet_team_of(&f, 12), 3);
    assert_int_equal(rover_fleet_team_of(&f, 0), ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_team_of(&f, 13), ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_members(&f, 2, &lo, &hi), 0);
    assert_int_equal(lo, 7);
    assert_int_equal(hi, 9);
    assert_int_equal(rover_fleet_members(&f, 4, &lo, &hi), ROVER_FLEET_ERR_ARG);
}

/* Every team starts as the single team of the open world does, shifted
 * into its lane; the goals are the open world's distance ahead; the same
 * arguments give the same fleet, bit for bit. */
static void test_lanes_and_goals_ahead(void **state)
{
    rover_fleet f, f2;
    int t, i;
    (void)state;
    assert_int_equal(rover_world_layout(&ONE, ROVER_WORLD_OPEN, 3, 1.0, FORMATION_TRIANGLE), 0);
    assert_int_equal(
        rover_fleet_layout(&W, &f, 5, 3, 1.0, FORMATION_TRIANGLE, ROVER_FLEET_GOALS_AHEAD), 0);
    assert_int_equal(
        rover_fleet_layout(&W2, &f2, 5, 3, 1.0, FORMATION_TRIANGLE, ROVER_FLEET_GOALS_AHEAD), 0);
    assert_memory_equal(&f, &f2, sizeof f);
    assert_memory_equal(W.start_c, W2.start_c, sizeof W.start_c);
    assert_true(f.lane_m > 3.0);
    for (t = 0; t < 5; t++) {
        if (t > 0)
            assert_true(fabs(f.lane_y_m[t - 1] - f.lane_y_m[t] - f.lane_m) < 1e-12);
        for (i = 0; i < 3; i++) {
            const pose2 *c = &W.start_c[t * 3 + i];
            assert_true(c->x_m == ONE.start_c[i].x_m);
            assert_true(fabs(c->y_m - ONE.start_c[i].y_m - f.lane_y_m[t]) < 1e-12);
        }
        assert_true(f.goal_m[t][0] == ONE.goal_m[0]);
        assert_true(f.goal_m[t][1] == f.lane_y_m[t]);
        /* the team's frame at its own start, so its goal lies straight ahead */
        assert_true(fabs(f.origin[t].y_m - f.lane_y_m[t] - ONE.team_origin.y_m) < 1e-12);
        assert_true(fabs(f.origin[t].x_m - ONE.team_origin.x_m) < 1e-12);
        assert_true(rover_fleet_frame_of(&W, &f, t * 3 + 2).y_m == f.origin[t].y_m);
    }
    /* lanes side by side, the middle one on y = 0 */
    assert_true(fabs(f.lane_y_m[2]) < 1e-12);
    assert_true(W.y_max_m > f.lane_y_m[0] && W.y_min_m < f.lane_y_m[4]);
    assert_true(W.n_landmarks > 0 && W.n_landmarks <= ROVER_WORLD_MAX_LANDMARKS);
    /* one team: the layout's own frame */
    assert_true(rover_fleet_frame_of(&ONE, NULL, 2).x_m == ONE.team_origin.x_m);
}

/* Crossing: lanes 0-1 and 2-3 swap goals, the odd last team keeps its own. */
static void test_goals_cross(void **state)
{
    rover_fleet f;
    (void)state;
    assert_int_equal(rover_fleet_layout(&W, &f, 5, 4, 1.0, FORMATION_LINE, ROVER_FLEET_GOALS_CROSS),
                     0);
    assert_true(f.goal_m[0][1] == f.lane_y_m[1]);
    assert_true(f.goal_m[1][1] == f.lane_y_m[0]);
    assert_true(f.goal_m[2][1] == f.lane_y_m[3]);
    assert_true(f.goal_m[3][1] == f.lane_y_m[2]);
    assert_true(f.goal_m[4][1] == f.lane_y_m[4]);
    assert_int_equal(rover_fleet_goals_id("cross"), ROVER_FLEET_GOALS_CROSS);
    assert_int_equal(rover_fleet_goals_id("ahead"), ROVER_FLEET_GOALS_AHEAD);
    assert_int_equal(rover_fleet_goals_id("round"), ROVER_FLEET_ERR_ARG);
    assert_string_equal(rover_fleet_goals_name(ROVER_FLEET_GOALS_CROSS), "cross");
}

/* Every robot of the fleet inside the world's extent, and no two starts
 * closer than the spacing. */
static void assert_fits(const rover_world_config *w, double spacing_m)
{
    int i, j;
    for (i = 0; i < w->n_robots; i++) {
        const pose2 *a = &w->start_c[i];
        assert_true(a->x_m > w->x_min_m && a->x_m < w->x_max_m);
        assert_true(a->y_m > w->y_min_m && a->y_m < w->y_max_m);
        for (j = i + 1; j < w->n_robots; j++)
            assert_true(hypot(w->start_c[j].x_m - a->x_m, w->start_c[j].y_m - a->y_m) >
                        spacing_m - 1e-9);
    }
}

/* The posts stand in rows along the lanes' borders, each row from behind
 * the first start to past the last goal with no gap wider than the
 * camera's reach (ROVER_FLEET_POST_STEP_M), within the world's capacity. */
static void assert_posts_within_reach(const rover_world_config *w)
{
    int k, rows = 1;
    assert_true(w->n_landmarks > ROVER_WORLD_MAX_LANDMARKS); /* more than one robot holds */
    assert_true(w->n_landmarks <= ROVER_WORLD_MAX_POSTS);
    for (k = 1; k < w->n_landmarks; k++) {
        const double *a = w->landmark_m[k - 1], *b = w->landmark_m[k];
        if (a[1] != b[1]) { /* the next border's row */
            rows++;
            continue;
        }
        assert_true(b[0] > a[0] && b[0] - a[0] <= ROVER_FLEET_POST_STEP_M + 1e-9);
    }
    assert_int_equal(w->n_landmarks % rows, 0);
}

/* More teams than a row's lanes: rows of ROVER_FLEET_ROW_LANES, team t
 * laid out as team t mod ROVER_FLEET_ROW_LANES moved along the way by
 * whole rows; a row's start area lies ahead of every goal of the row
 * behind it by more than a goal formation's depth; the goals stay in the
 * row. Fewer teams: one row, as before rows were. */
static void test_rows(void **state)
{
    const int teams = 2 * ROVER_FLEET_ROW_LANES + 3, k = 10;
    rover_fleet f;
    int t, i;
    (void)state;
    assert_int_equal(
        rover_fleet_layout(&W, &f, teams, k, 1.0, FORMATION_LINE, ROVER_FLEET_GOALS_CROSS), 0);
    assert_int_equal(f.rows, 3);
    for (t = ROVER_FLEET_ROW_LANES; t < teams; t++) {
        const int u = t - ROVER_FLEET_ROW_LANES; /* the same lane, a row behind */
        assert_true(f.lane_y_m[t] == f.lane_y_m[u]);
        assert_true(fabs(f.goal_m[t][0] - f.goal_m[u][0] - f.row_m) < 1e-9);
        if ((t ^ 1) < teams) /* the odd last team keeps its own lane */
            assert_true(f.goal_m[t][1] == f.goal_m[u][1]);
        for (i = 0; i < k; i++) {
            const pose2 *c = &W.start_c[t * k + i], *b = &W.start_c[u * k + i];
            assert_true(fabs(c->x_m - b->x_m - f.row_m) < 1e-9 && c->y_m == b->y_m);
            assert_true(c->x_m > f.goal_m[u][0] + ROVER_FLEET_ROW_GAP_M);
        }
    }
    assert_fits(&W, 1.0);
    assert_posts_within_reach(&W);
    assert_int_equal(rover_fleet_layout(&W, &f, ROVER_FLEET_ROW_LANES, 3, 1.0, FORMATION_LINE, 0),
                     0);
    assert_int_equal(f.rows, 1);
}

static void test_capacities_refused(void **state)
{
    rover_fleet f;
    (void)state;
    assert_int_equal(rover_fleet_layout(&W, &f, 0, 3, 1.0, FORMATION_LINE, 0), ROVER_FLEET_ERR_ARG);
    assert_int_equal(
        rover_fleet_layout(&W, &f, ROVER_FLEET_MAX_TEAMS + 1, 3, 1.0, FORMATION_LINE, 0),
        ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_layout(&W, &f, 2, ROVER_TEAM_MAX + 1, 1.0, FORMATION_LINE, 0),
                     ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_layout(&W, &f, 2, 3, 1.0, FORMATION_LINE, 2), ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_layout(NULL, &f, 2, 3, 1.0, FORMATION_LINE, 0),
                     ROVER_FLEET_ERR_ARG);
    assert_int_equal(rover_fleet_layout(&W, &f, 2, 3, 0.1, FORMATION_LINE, 0), ROVER_FLEET_ERR_ARG);
    /* the largest fleet the capacities allow */
    assert_int_equal(rover_fleet_layout(&W, &f, ROVER_FLEET_MAX_TEAMS,
                                        ROVER_WORLD_MAX_ROBOTS / ROVER_FLEET_MAX_TEAMS, 1.0,
                                        FORMATION_COLUMN, ROVER_FLEET_GOALS_CROSS),
                     0);
    assert_int_equal(W.n_robots, ROVER_WORLD_MAX_ROBOTS);
    assert_fits(&W, 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_members),
        cmocka_unit_test(test_lanes_and_goals_ahead),
        cmocka_unit_test(test_goals_cross),
        cmocka_unit_test(test_rows),
        cmocka_unit_test(test_capacities_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

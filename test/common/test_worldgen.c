/* Unit tests of the world generator (src/daemons/common/worldgen.c): the
 * way check passes a hall with a doorway wide enough for the body and
 * refuses it with the doorway closed or narrower than the inflated body;
 * every kind gives, for several seeds, a world the check passes, the same
 * world for the same seed, and its start and goal accepted by
 * rover_world_from_map; sizes that cannot hold the team are refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include "formation.h"
#include "worldgen.h"

static rover_map M, M2;
static rover_world_config W;

static const double CLEAR = WORLDGEN_BODY_RADIUS_M + WORLDGEN_MARGIN_M;

/* A 20 m x 10 m hall, walled, a wall across at x = 10 with a doorway of
 * width door_m centred on y = 5 (0: closed). */
static void hall(double door_m, rover_map_site *s)
{
    int i, j;
    memset(&M, 0, sizeof M);
    M.width = 200;
    M.height = 100;
    M.resolution_m = 0.1;
    for (j = 0; j < 100; j++)
        for (i = 0; i < 200; i++) {
            const double x = (i + 0.5) * 0.1, y = (j + 0.5) * 0.1;
            const int edge = i < 2 || j < 2 || i >= 198 || j >= 98;
            const int wall = fabs(x - 10.0) < 0.1 && fabs(y - 5.0) >= 0.5 * door_m;
            M.cell[j * 200 + i] = edge || wall ? ROVER_MAP_OCCUPIED : ROVER_MAP_FREE;
        }
    memset(s, 0, sizeof *s);
    s->start.x_m = 3.0;
    s->start.y_m = 5.0;
    s->goal_m[0] = 17.0;
    s->goal_m[1] = 5.0;
    s->n_landmarks = ROVER_MAP_LANDMARKS_AUTO;
}

static void test_a_closed_or_narrow_passage_is_refused(void **state)
{
    rover_map_site s;
    (void)state;
    hall(2.0, &s);
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 1);
    hall(0.0, &s);
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 0);
    /* narrower than the inflated body (2 x 0.57 m), though wider than the body */
    hall(1.0, &s);
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 0);
    hall(1.4, &s);
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 1);
    /* the goal walled in */
    hall(2.0, &s);
    s.goal_m[0] = 10.0;
    s.goal_m[1] = 1.0;
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 0);
}

/* The generator's parameters for a 30 m x 20 m world of kind and seed,
 * a team of n in line. */
static worldgen_params gen_params(int kind, int seed, int n)
{
    worldgen_params p;
    memset(&p, 0, sizeof p);
    p.kind = kind;
    p.seed = (uint64_t)seed;
    p.width_m = 30.0;
    p.height_m = 20.0;
    p.robots = n;
    p.formation = FORMATION_LINE;
    return p;
}

static void test_every_kind_gives_passable_repeatable_worlds(void **state)
{
    worldgen_params p;
    rover_map_site s, s2;
    int kind, seed, attempt;
    (void)state;
    for (kind = 0; kind < WORLDGEN_KINDS; kind++)
        for (seed = 1; seed <= 4; seed++) {
            p = gen_params(kind, seed, 3);
            assert_int_equal(worldgen_make(&M, &s, &p, &attempt), WORLDGEN_OK);
            assert_true(attempt >= 0 && attempt < WORLDGEN_ATTEMPTS);
            assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 1);
            assert_int_equal(rover_world_from_map(&W, &M, &s, 3, 1.0, FORMATION_LINE),
                             ROVER_MAP_OK);
            assert_true(W.n_obst > 4); /* more than the border */
            memcpy(&M2, &M, sizeof M);
            assert_int_equal(worldgen_make(&M, &s2, &p, NULL), WORLDGEN_OK);
            assert_memory_equal(M.cell, M2.cell, (size_t)M.width * (size_t)M.height);
            assert_memory_equal(&s, &s2, sizeof s);
        }
    assert_int_equal(worldgen_kind("traps"), WORLDGEN_TRAPS);
    assert_int_equal(worldgen_kind("maze"), WORLDGEN_ERR_ARG);
}

/* The goal area holds the team: for teams of 3, 8 and 12 in line (the
 * widest formation) and every kind, each slot of the formation placed at
 * the goal (headed from the start toward it) has every cell within the
 * inflated body's radius free. The generator cleared 1.5 m round the goal
 * before: a line of 8 had slots inside obstacles. The way check refuses a
 * hall whose goal slots lie in a wall. */
static int goal_slots_clear(const rover_map *m, const rover_map_site *s, int n)
{
    const double heading = atan2(s->goal_m[1] - s->start.y_m, s->goal_m[0] - s->start.x_m);
    int k, i, j;
    for (k = 0; k < n; k++) {
        double xy[2], x, y;
        assert_int_equal(formation_slot_xy(xy, FORMATION_LINE, n, k, 1.0, 1.0), 0);
        x = s->goal_m[0] + xy[0] * cos(heading) - xy[1] * sin(heading);
        y = s->goal_m[1] + xy[0] * sin(heading) + xy[1] * cos(heading);
        for (j = 0; j < m->height; j++)
            for (i = 0; i < m->width; i++) {
                const double cx = m->origin_x_m + (i + 0.5) * m->resolution_m;
                const double cy = m->origin_y_m + (j + 0.5) * m->resolution_m;
                if (hypot(cx - x, cy - y) < CLEAR && m->cell[j * m->width + i] != ROVER_MAP_FREE)
                    return 0;
            }
    }
    return 1;
}

static void test_the_goal_area_holds_the_team(void **state)
{
    static const int teams[3] = { 3, 8, 12 };
    worldgen_params p;
    rover_map_site s;
    int kind, seed, t;
    (void)state;
    for (t = 0; t < 3; t++)
        for (kind = 0; kind < WORLDGEN_KINDS; kind++)
            for (seed = 1; seed <= 3; seed++) {
                p = gen_params(kind, seed, teams[t]);
                assert_int_equal(worldgen_make(&M, &s, &p, NULL), WORLDGEN_OK);
                assert_true(goal_slots_clear(&M, &s, teams[t]));
            }
    /* a goal 0.5 m from the hall's wall across: a line of 3 across the way
     * fits, its slots do not once the goal is against the side wall */
    hall(2.0, &s);
    s.goal_m[1] = 1.2;
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 0);
    s.goal_m[1] = 5.0;
    assert_int_equal(worldgen_passable(&M, &s, 3, FORMATION_LINE, CLEAR), 1);
}

static void test_sizes_that_cannot_hold_the_team_are_refused(void **state)
{
    worldgen_params p;
    rover_map_site s;
    (void)state;
    memset(&p, 0, sizeof p);
    p.kind = WORLDGEN_CLUTTER;
    p.width_m = 30.0;
    p.height_m = 3.0; /* a 3-robot line needs more */
    p.robots = 3;
    assert_int_equal(worldgen_make(&M, &s, &p, NULL), WORLDGEN_ERR_ARG);
    p.height_m = 20.0;
    p.width_m = 500.0; /* beyond ROVER_MAP_MAX_SIDE cells */
    assert_int_equal(worldgen_make(&M, &s, &p, NULL), WORLDGEN_ERR_ARG);
    p.width_m = 30.0;
    p.kind = WORLDGEN_KINDS;
    assert_int_equal(worldgen_make(&M, &s, &p, NULL), WORLDGEN_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_closed_or_narrow_passage_is_refused),
        cmocka_unit_test(test_every_kind_gives_passable_repeatable_worlds),
        cmocka_unit_test(test_the_goal_area_holds_the_team),
        cmocka_unit_test(test_sizes_that_cannot_hold_the_team_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

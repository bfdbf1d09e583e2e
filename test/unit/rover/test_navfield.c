/* Unit tests for navfield: in the open the field is the octile distance
 * and the waypoint the goal itself, bit for bit; Bellman's bounds hold on
 * every cell of a world with a pocket facing the start; following
 * waypoints from inside that pocket (where the straight way to the goal
 * runs into its back wall) reaches the goal, every leg clear of the walls
 * by an independent distance check; the team frame's rotation commutes
 * with the query; a point beside a wall does not descend from its far
 * side; the passage on the way ahead is the gap or corridor built, and
 * none in the open or beside one wall; a gap in a thin wall crossed
 * aslant is found, at most its width along the wall and at least its
 * width across the way; a goal on an obstacle and bad parameters are
 * refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "navfield.h"

static navfield F, G; /* large: keep off the stack */
static rover_world_config W;

/* 20 m x 10 m; team frame at (2, 5) heading +x; goal at (18, 5). */
static void world_open(void)
{
    memset(&W, 0, sizeof W);
    W.x_min_m = 0.0;
    W.y_min_m = 0.0;
    W.x_max_m = 20.0;
    W.y_max_m = 10.0;
    W.goal_m[0] = 18.0;
    W.goal_m[1] = 5.0;
    W.team_origin.x_m = 2.0;
    W.team_origin.y_m = 5.0;
}

static void box(double cx, double cy, double hx, double hy)
{
    assert_int_equal(rover_world_add_box(&W, cx, cy, hx, hy, 0.0, 0.5), 0);
}

static void box_turned(double cx, double cy, double hx, double hy, double a)
{
    assert_int_equal(rover_world_add_box(&W, cx, cy, hx, hy, a, 0.5), 0);
}

/* A U pocket 3 m deep, mouth toward the start, across the straight way. */
static void world_pocket(void)
{
    world_open();
    box(12.0, 5.0, 0.15, 2.65);
    box(10.5, 7.5, 1.5, 0.15);
    box(10.5, 2.5, 1.5, 0.15);
}

static void build(navfield *f)
{
    navfield_params p;
    navfield_params_default(&p);
    assert_int_equal(navfield_build(f, &p, &W), NAVFIELD_OK);
}

static double world_clearance(double x, double y)
{
    double best = INFINITY;
    int k;
    for (k = 0; k < W.n_obst; k++)
        best = fmin(best, rover_obstacle_distance(&W.obst[k], x, y));
    return best;
}

static void test_open_is_octile_and_direct(void **state)
{
    const double from[2] = { 0.3, -1.7 }, goal[2] = { 16.0, 0.0 };
    double out[2];
    long c, gi, gj;
    (void)state;
    world_open();
    build(&F);
    gi = F.goal_cell % F.nx;
    gj = F.goal_cell / F.nx;
    for (c = 0; c < (long)F.nx * F.ny; c += 37) {
        const long i = c % F.nx, j = c / F.nx;
        const double dx = fabs((double)(i - gi)), dy = fabs((double)(j - gj));
        const double octile = F.cell_m * (fmax(dx, dy) + (sqrt(2.0) - 1.0) * fmin(dx, dy));
        assert_true(fabs(F.way_m[c] - octile) < 1e-3);
    }
    assert_int_equal(navfield_waypoint(&F, from, goal, out), NAVFIELD_DIRECT);
    assert_true(out[0] == goal[0] && out[1] == goal[1]);
}

/* Every finite cell but the goal's: some neighbour lies lower by at least
 * a cell (the weights are at least the step's length), and no side
 * neighbour joined to the goal lies lower by more than a weighted step. */
static void test_bellman_bounds(void **state)
{
    long i, j, finite = 0;
    (void)state;
    world_pocket();
    build(&F);
    for (j = 0; j < F.ny; j++)
        for (i = 0; i < F.nx; i++) {
            const long c = j * F.nx + i;
            float low = INFINITY;
            int di, dj;
            if (!isfinite(F.way_m[c]) || c == F.goal_cell)
                continue;
            finite++;
            for (dj = -1; dj <= 1; dj++)
                for (di = -1; di <= 1; di++) {
                    const long a = i + di, b = j + dj;
                    if ((di || dj) && a >= 0 && b >= 0 && a < F.nx && b < F.ny)
                        low = fminf(low, F.way_m[b * F.nx + a]);
                }
            assert_true(F.way_m[c] >= low + (float)F.cell_m * 0.999f);
            for (di = 0; di < 4; di++) {
                const long a = i + (di == 0) - (di == 1), b = j + (di == 2) - (di == 3);
                if (a >= 0 && b >= 0 && a < F.nx && b < F.ny && isfinite(F.way_m[b * F.nx + a]))
                    assert_true(F.way_m[c] <= F.way_m[b * F.nx + a] +
                                                  (float)(F.cell_m * (1.0 + F.p.pen_gain)) + 1e-3f);
            }
        }
    assert_true(finite > F.nx * F.ny / 2);
}

/* From inside the pocket the straight way runs into its back wall; the
 * waypoints lead out and round to the goal, each leg clear of the walls. */
static void test_pocket_escape(void **state)
{
    const double goal[2] = { 16.0, 0.0 };
    double p[2] = { 9.0, 0.0 }, out[2];
    int it, rc = NAVFIELD_DESCENT;
    double s, blocked = INFINITY;
    (void)state;
    world_pocket();
    build(&F);
    for (s = 0.0; s <= 1.0; s += 0.01)
        blocked = fmin(blocked, world_clearance(11.0 + s * 7.0, 5.0));
    assert_true(blocked < 0.0); /* the straight way goes through the wall */
    for (it = 0; it < 200 && rc != NAVFIELD_DIRECT; it++) {
        double step, leg_clear = INFINITY;
        rc = navfield_waypoint(&F, p, goal, out);
        assert_true(rc == NAVFIELD_DIRECT || rc == NAVFIELD_DESCENT);
        for (s = 0.0; s <= 1.0; s += 0.005)
            leg_clear = fmin(leg_clear, world_clearance(2.0 + p[0] + s * (out[0] - p[0]),
                                                        5.0 + p[1] + s * (out[1] - p[1])));
        assert_true(leg_clear >= 0.5 * F.p.los_m - F.cell_m);
        step = fmin(0.5, hypot(out[0] - p[0], out[1] - p[1]));
        assert_true(step > 0.0);
        p[0] += step * (out[0] - p[0]) / hypot(out[0] - p[0], out[1] - p[1]);
        p[1] += step * (out[1] - p[1]) / hypot(out[0] - p[0], out[1] - p[1]);
    }
    assert_int_equal(rc, NAVFIELD_DIRECT);
    assert_true(it < 200);
}

/* The way from inside the pocket as a polyline: it starts where asked,
 * ends on the goal, and every leg keeps clear of the walls; a cap too
 * small for it still ends on the goal; bad input gives none. */
static void test_polyline_out_of_pocket(void **state)
{
    const double goal[2] = { 16.0, 0.0 }, from[2] = { 9.0, 0.0 };
    double way[64][2], s;
    int n, k;
    (void)state;
    world_pocket();
    build(&F);
    n = navfield_polyline(&F, from, goal, way, 64);
    assert_true(n >= 3); /* the straight way goes through the wall: at least one turn */
    assert_true(way[0][0] == from[0] && way[0][1] == from[1]);
    assert_true(way[n - 1][0] == goal[0] && way[n - 1][1] == goal[1]);
    for (k = 0; k + 1 < n; k++) {
        double leg_clear = INFINITY;
        for (s = 0.0; s <= 1.0; s += 0.005)
            leg_clear = fmin(leg_clear,
                             world_clearance(2.0 + way[k][0] + s * (way[k + 1][0] - way[k][0]),
                                             5.0 + way[k][1] + s * (way[k + 1][1] - way[k][1])));
        assert_true(leg_clear >= 0.5 * F.p.los_m - F.cell_m);
    }
    n = navfield_polyline(&F, from, goal, way, 2);
    assert_int_equal(n, 2);
    assert_true(way[1][0] == goal[0] && way[1][1] == goal[1]);
    assert_int_equal(navfield_polyline(&F, from, goal, way, 1), 0);
    assert_int_equal(navfield_polyline(NULL, from, goal, way, 64), 0);
}

/* The same world with the team frame turned and moved: the query in the
 * team frame, mapped to the world, is the world-frame query. */
static void test_frame_commutes(void **state)
{
    const double th = 1.1, ox = 3.0, oy = 4.0;
    const double pw[2] = { 11.0, 5.2 }, gw[2] = { 18.0, 5.0 };
    double pt[2], gt[2], ow[2], ot[2], back[2];
    (void)state;
    world_pocket();
    W.team_origin.x_m = 0.0;
    W.team_origin.y_m = 0.0;
    build(&F);
    W.team_origin.x_m = ox;
    W.team_origin.y_m = oy;
    W.team_origin.theta_rad = th;
    build(&G);
    vec2_rotate(pt, pw[0] - ox, pw[1] - oy, -th);
    vec2_rotate(gt, gw[0] - ox, gw[1] - oy, -th);
    assert_int_equal(navfield_waypoint(&F, pw, gw, ow), NAVFIELD_DESCENT);
    assert_int_equal(navfield_waypoint(&G, pt, gt, ot), NAVFIELD_DESCENT);
    vec2_rotate(back, ot[0], ot[1], th);
    assert_true(fabs(back[0] + ox - ow[0]) < 1e-9 && fabs(back[1] + oy - ow[1]) < 1e-9);
}

/* A point beside a thin wall, nearer it than clear_m, with the goal just
 * across: the cell it descends from is on its own side (the far side is
 * within reach and nearer the goal, but only through the wall), so the
 * waypoint leads along the wall to its end, never through it. */
static void test_start_beside_wall(void **state)
{
    const double from_w[2] = { 9.7, 5.0 }, goal_w[2] = { 12.0, 5.0 };
    double from[2], goal[2], out[2], s, leg_clear = INFINITY;
    (void)state;
    world_open();
    W.goal_m[0] = goal_w[0];
    W.goal_m[1] = goal_w[1];
    box(10.0, 4.0, 0.1, 4.0); /* x = 10 from y = 0 to 8; the way round its top end */
    build(&F);
    from[0] = from_w[0] - W.team_origin.x_m;
    from[1] = from_w[1] - W.team_origin.y_m;
    goal[0] = goal_w[0] - W.team_origin.x_m;
    goal[1] = goal_w[1] - W.team_origin.y_m;
    assert_int_equal(navfield_waypoint(&F, from, goal, out), NAVFIELD_DESCENT);
    out[0] += W.team_origin.x_m;
    out[1] += W.team_origin.y_m;
    print_message("beside the wall: waypoint (%.2f, %.2f)\n", out[0], out[1]);
    for (s = 0.0; s <= 1.0; s += 0.005)
        leg_clear = fmin(leg_clear, world_clearance(from_w[0] + s * (out[0] - from_w[0]),
                                                    from_w[1] + s * (out[1] - from_w[1])));
    assert_true(leg_clear > 0.1); /* not through the wall (0.2 m from it at the start) */
    assert_true(out[1] > from_w[1] + 0.5);
}

/* Where along the way: round the end of a thin wall (x = 10, y 0-8, the
 * goal just across it at (12, 5)), points on the way up the near side,
 * over the top and down the far side have ways to the goal that fall in
 * that order, which the straight distance does not (the first point is
 * 3 m from the goal, the one over the top 4.2 m); in a free cell the way
 * is the cell's value plus at most half its diagonal; a point beside the
 * wall, in a cell nearer it than clear_m, still has a way, no longer than
 * a point's a body width out plus the straight step to it (the triangle
 * inequality of navfield_way_from); off the grid and NULL, none. */
static void test_way_from_round_bend(void **state)
{
    static const double along_w[][2] = { { 9.2, 4.0 },  { 9.2, 6.5 },  { 9.5, 8.6 },
                                         { 10.5, 8.7 }, { 10.8, 7.0 }, { 11.2, 5.5 } };
    const int n = (int)(sizeof along_w / sizeof along_w[0]);
    double prev = INFINITY, p[2], q[2];
    int k;
    (void)state;
    world_open();
    W.goal_m[0] = 12.0;
    W.goal_m[1] = 5.0;
    box(10.0, 4.0, 0.1, 4.0);
    build(&F);
    for (k = 0; k < n; k++) {
        double way;
        p[0] = along_w[k][0] - W.team_origin.x_m;
        p[1] = along_w[k][1] - W.team_origin.y_m;
        way = navfield_way_from(&F, p);
        print_message("(%.1f, %.1f): way %.2f m, straight %.2f m\n", along_w[k][0], along_w[k][1],
                      way, hypot(along_w[k][0] - 12.0, along_w[k][1] - 5.0));
        assert_true(isfinite(way) && way < prev);
        assert_true(fabs(way - navfield_way_m(&F, along_w[k][0], along_w[k][1])) <=
                    0.71 * F.cell_m + 1e-9);
        prev = way;
    }
    assert_true(hypot(along_w[0][0] - 12.0, along_w[0][1] - 5.0) <
                hypot(along_w[3][0] - 12.0, along_w[3][1] - 5.0));
    p[0] = 9.8 - W.team_origin.x_m; /* 0.1 m from the wall's face */
    p[1] = 5.0 - W.team_origin.y_m;
    q[0] = 9.4 - W.team_origin.x_m;
    q[1] = p[1];
    assert_false(isfinite(navfield_way_m(&F, 9.8, 5.0)));
    print_message("beside the wall: way %.2f m, a body width out %.2f m\n",
                  navfield_way_from(&F, p), navfield_way_from(&F, q));
    assert_true(navfield_way_from(&F, p) <= navfield_way_from(&F, q) + 0.4 + 0.71 * F.cell_m);
    p[0] = 100.0;
    assert_false(isfinite(navfield_way_from(&F, p)));
    assert_false(isfinite(navfield_way_from(NULL, q)));
}

/* The clearance at a point (callers' frame) is a lower bound on its true
 * distance to the nearest obstacle, and within a cell's diagonal of it,
 * across a wall on both sides; off the grid or with no field there is
 * none (-INFINITY). What a turn on the spot is checked against. */
static void test_clearance_bounds(void **state)
{
    double p[2], x;
    int seen = 0;
    (void)state;
    world_open();
    box(10.0, 4.0, 0.1, 4.0);
    build(&F);
    for (x = 8.5; x <= 11.5; x += 0.037) {
        const double truth = fmax(0.0, fabs(x - 10.0) - 0.1);
        double c;
        p[0] = x - W.team_origin.x_m;
        p[1] = 3.3 - W.team_origin.y_m;
        c = navfield_clearance_m(&F, p);
        if (truth > 0.6)
            continue;
        assert_true(c <= truth + 1e-9);
        assert_true(c >= truth - sqrt(2.0) * F.cell_m - 1e-9);
        seen++;
    }
    assert_true(seen > 20);
    p[0] = 1e3;
    assert_true(navfield_clearance_m(&F, p) == -INFINITY);
    p[0] = 0.0;
    assert_true(navfield_clearance_m(NULL, p) == -INFINITY);
    p[1] = NAN;
    assert_true(navfield_clearance_m(&F, p) == -INFINITY);
}

/* navfield_clearance_slope_m against the world as built, round a wall
 * set aslant to the grid and a post: a lower bound on the true clearance
 * everywhere (inside the walls too), within half a cell of it where the
 * wall is near (a quarter here; the single cell's within a diagonal), and its
 * slope pointing away from the nearest wall, about unit length. What the
 * map's graze guard moves chassis corners against. */
static void test_clearance_slope(void **state)
{
    double worst_gap = 0.0, worst_cos = 1.0;
    int i, j, seen = 0;
    (void)state;
    world_open();
    box_turned(10.0, 5.0, 0.1, 3.0, 0.4);
    box(6.0, 3.0, 0.3, 0.3);
    build(&F);
    for (j = 0; j < 120; j++)
        for (i = 0; i < 160; i++) {
            const double x = 4.0 + 0.0533 * i, y = 1.0 + 0.0617 * j;
            const double p[2] = { x - W.team_origin.x_m, y - W.team_origin.y_m };
            const double truth = world_clearance(x, y), e = 1e-4;
            double slope[2], c, gx, gy, n;
            c = navfield_clearance_slope_m(&F, p, slope);
            assert_true(c <= truth + 1e-6);
            if (truth < F.cell_m || truth > 0.4)
                continue;
            seen++;
            worst_gap = fmax(worst_gap, truth - c);
            /* the true clearance's own gradient, by finite differences */
            gx = (world_clearance(x + e, y) - world_clearance(x - e, y)) / (2 * e);
            gy = (world_clearance(x, y + e) - world_clearance(x, y - e)) / (2 * e);
            n = hypot(slope[0], slope[1]);
            assert_true(n > 0.5 && n < 1.5);
            worst_cos = fmin(worst_cos, (slope[0] * gx + slope[1] * gy) / (n * hypot(gx, gy)));
        }
    print_message("clearance slope: %d points near walls, truth - bound at most %.3f m (cell "
                  "%.2f m), slope within %.1f deg of the true gradient\n",
                  seen, worst_gap, F.cell_m, acos(worst_cos) * 180.0 / 3.14159265358979);
    assert_true(seen > 500);
    assert_true(worst_gap <= 0.25 * F.cell_m);
    assert_true(worst_cos > cos(30.0 * 3.14159265358979 / 180.0));
    {
        double p[2] = { 1e3, 0.0 }, slope[2];
        assert_true(navfield_clearance_slope_m(&F, p, slope) == -INFINITY);
        assert_true(slope[0] == 0.0 && slope[1] == 0.0);
        p[0] = NAN;
        assert_true(navfield_clearance_slope_m(&F, p, slope) == -INFINITY);
        assert_true(navfield_clearance_slope_m(NULL, p, slope) == -INFINITY);
        p[0] = 5.0;
        assert_true(navfield_clearance_slope_m(&F, p, NULL) == -INFINITY);
    }
}

/* The passage on the way ahead, against the world as built: a gap of
 * 1.2 m in a wall 0.2 m thick across the way is a passage of 1.2 m
 * (within a cell a side) and about as long as the wall is thick, once it
 * lies within ahead_m, and none before; a corridor 1.8 m wide is one of
 * 1.8 m, as long as the way looked at runs in it; a wall on one side
 * only, or the open, is none; bad input is refused. From team-frame
 * points (origin (2, 5)). */
static navfield_passage passage_from(double x_w, double y_w, double ahead_m)
{
    const double from[2] = { x_w - W.team_origin.x_m, y_w - W.team_origin.y_m };
    const navfield_passage_query q = { ahead_m, 2.75, 2.0, 1.0 };
    navfield_passage out;
    assert_int_equal(navfield_passage_ahead(&F, from, &q, &out), NAVFIELD_OK);
    return out;
}

static void test_passage_ahead(void **state)
{
    const double tol = 2.5 * 0.1; /* a cell's side and a half-cell sample on each side */
    const double bad[2] = { NAN, 0.0 }, from[2] = { 0.0, 0.0 };
    navfield_passage_query q = { 3.0, 2.75, 2.0, 1.0 };
    navfield_passage out;
    (void)state;
    world_open();
    box(10.0, 2.2, 0.1, 2.2); /* x = 10, y 0 .. 4.4 */
    box(10.0, 7.8, 0.1, 2.2); /* y 5.6 .. 10: a gap of 1.2 m at y = 5 */
    build(&F);
    out = passage_from(7.0, 5.0, 3.5);
    print_message("gap 1.2 m: %.3f m wide, %.3f m long, from 3 m before it\n", out.narrowest_m,
                  out.below_len_m);
    assert_true(fabs(out.narrowest_m - 1.2) <= tol);
    assert_true(fabs(out.below_len_m - 0.2) <= tol);
    assert_true(fabs(passage_from(9.5, 5.0, 3.0).narrowest_m - 1.2) <= tol);
    assert_true(isinf(passage_from(5.0, 5.0, 3.0).narrowest_m));  /* 5 m short of it */
    assert_true(isinf(passage_from(11.0, 5.0, 3.0).narrowest_m)); /* through it */
    assert_int_equal(navfield_passage_ahead(&F, bad, &q, &out), NAVFIELD_ERR_ARG);
    q.ahead_m = -1.0;
    assert_int_equal(navfield_passage_ahead(&F, from, &q, &out), NAVFIELD_ERR_ARG);

    world_open();
    box(10.0, 7.95, 4.0, 2.05); /* the only way: a corridor x 6 .. 14, inner faces y 4.1, 5.9 */
    box(10.0, 2.05, 4.0, 2.05);
    build(&F);
    out = passage_from(4.0, 5.0, 3.0);
    print_message("corridor 1.8 m: %.3f m wide, %.3f m long of the 4 m looked at\n",
                  out.narrowest_m, out.below_len_m);
    assert_true(fabs(out.narrowest_m - 1.8) <= tol);
    assert_true(fabs(out.below_len_m - 2.0) <= tol); /* x 6 .. 8 */
    assert_true(fabs(passage_from(10.0, 5.0, 1.0).narrowest_m - 1.8) <= tol);

    world_open();
    box(10.0, 2.05, 4.0, 2.05); /* its lower side alone */
    build(&F);
    assert_true(isinf(passage_from(4.0, 5.0, 3.0).narrowest_m));
    world_open();
    build(&F);
    out = passage_from(4.0, 5.0, 10.0);
    assert_true(isinf(out.narrowest_m));
    assert_true(out.below_len_m == 0.0);
}

/* A gap of 1.2 m in a wall one cell thick whose two parts stand a cell
 * apart along the way (x 10.0-10.1 below the gap, 10.1-10.2 above it), as
 * a map's wall drawn slightly aslant is: the passage is the gap. Every
 * line across the way through the gap's cells passes beside one part's
 * end, half a cell from it; read as "a sample's centre on an obstacle"
 * those lines read open, and a team of 6 in triangle crossed a 1.9 m gap
 * of generated mixed world 315 with no formation change. */
static void test_passage_staggered_thin_wall(void **state)
{
    const double tol = 2.5 * 0.1;
    navfield_passage out;
    (void)state;
    world_open();
    box(10.05, 2.2, 0.05, 2.2); /* x 10.0 .. 10.1, y 0 .. 4.4 */
    box(10.15, 7.8, 0.05, 2.2); /* x 10.1 .. 10.2, y 5.6 .. 10 */
    build(&F);
    out = passage_from(8.0, 5.0, 3.0);
    print_message("staggered thin wall, gap 1.2 m: %.3f m wide, %.3f m long\n", out.narrowest_m,
                  out.below_len_m);
    assert_true(fabs(out.narrowest_m - 1.2) <= tol);
    assert_true(out.below_len_m < 1.0); /* short: a gap, not a corridor */
}

/* A wall 0.1 m thick turned by beta from the way's normal (the way runs
 * along +x at y = 5), with a gap of 1.4 m along it centred on the way: the
 * team meets a width of 1.4 cos(beta) across its way, and the passage
 * read is between that and 1.4 m (within a cell a side). Across the way's
 * normal alone the lines through the gap pass beside the wall's ends and
 * read it open. */
static void test_passage_aslant(void **state)
{
    const double tol = 2.5 * 0.1, gap = 1.4, half = 2.5; /* each wall piece 5 m long */
    const double betas_deg[] = { 10.0, 17.0, 25.0, 33.0, 40.0 };
    size_t k;
    (void)state;
    for (k = 0; k < sizeof betas_deg / sizeof betas_deg[0]; k++) {
        const double b = betas_deg[k] * 3.14159265358979324 / 180.0;
        const double along[2] = { -sin(b), cos(b) }; /* the wall's direction */
        const double r = 0.5 * gap + half;
        navfield_passage out;
        world_open();
        box_turned(10.0 + r * along[0], 5.0 + r * along[1], 0.05, half, b);
        box_turned(10.0 - r * along[0], 5.0 - r * along[1], 0.05, half, b);
        build(&F);
        out = passage_from(8.0, 5.0, 3.0);
        print_message("gap %.1f m in a wall turned %.0f deg: %.3f m (across the way %.3f m)\n", gap,
                      betas_deg[k], out.narrowest_m, gap * cos(b));
        assert_true(out.narrowest_m <= gap + tol);
        assert_true(out.narrowest_m >= gap * cos(b) - tol);
    }
}

static void test_refusals(void **state)
{
    navfield_params p;
    const double from[2] = { 0.0, 0.0 }, bad[2] = { NAN, 0.0 };
    double out[2];
    (void)state;
    navfield_params_default(&p);
    assert_int_equal(navfield_params_validate(&p), NAVFIELD_OK);
    p.clear_m = -0.1;
    assert_int_equal(navfield_params_validate(&p), NAVFIELD_ERR_ARG);
    navfield_params_default(&p);
    p.min_ahead_m = p.look_m + 1.0;
    assert_int_equal(navfield_params_validate(&p), NAVFIELD_ERR_ARG);
    navfield_params_default(&p);
    p.prefer_m = 0.5 * p.clear_m;
    assert_int_equal(navfield_params_validate(&p), NAVFIELD_ERR_ARG);
    navfield_params_default(&p);
    world_open();
    box(18.0, 5.0, 0.5, 0.5); /* on the goal */
    assert_int_equal(navfield_build(&F, &p, &W), NAVFIELD_ERR_GOAL);
    world_open();
    W.x_max_m = W.x_min_m;
    assert_int_equal(navfield_build(&F, &p, &W), NAVFIELD_ERR_ARG);
    world_open();
    build(&F);
    assert_int_equal(navfield_waypoint(&F, bad, from, out), NAVFIELD_ERR_ARG);
    assert_int_equal(navfield_waypoint(NULL, from, from, out), NAVFIELD_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_is_octile_and_direct),
        cmocka_unit_test(test_bellman_bounds),
        cmocka_unit_test(test_pocket_escape),
        cmocka_unit_test(test_polyline_out_of_pocket),
        cmocka_unit_test(test_frame_commutes),
        cmocka_unit_test(test_start_beside_wall),
        cmocka_unit_test(test_way_from_round_bend),
        cmocka_unit_test(test_clearance_bounds),
        cmocka_unit_test(test_clearance_slope),
        cmocka_unit_test(test_passage_ahead),
        cmocka_unit_test(test_passage_staggered_thin_wall),
        cmocka_unit_test(test_passage_aslant),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* rover_world: launch configuration of the Pioneer team (worlds, initial
 * poses, goal, team frame) and ground-truth footprint clearance
 * (docs/method/formation.md, sonar.md). See rover_world.h.
 */
#include "rover_world.h"

#include "formation.h"
#include "goal_place.h"
#include "unicycle.h"

#include <math.h>
#include <string.h>

static const char *const world_names[ROVER_WORLD_COUNT] = { "open", "obstacles", "corridor",
                                                            "deadzone" };

int rover_world_id(const char *name)
{
    int i;
    if (!name)
        return ROVER_WORLD_ERR_ARG;
    for (i = 0; i < ROVER_WORLD_COUNT; i++)
        if (strcmp(name, world_names[i]) == 0)
            return i;
    return ROVER_WORLD_ERR_UNKNOWN;
}

const char *rover_world_name(int world)
{
    if (world == ROVER_WORLD_FILE)
        return "file";
    return (world >= 0 && world < ROVER_WORLD_COUNT) ? world_names[world] : "?";
}

int rover_world_add_box(rover_world_config *w, double cx, double cy, double hx, double hy,
                        double angle_rad, double height_m)
{
    rover_obstacle *o;
    if (!w || w->n_obst < 0 || w->n_obst >= ROVER_WORLD_MAX_OBST)
        return ROVER_WORLD_ERR_ARG;
    o = &w->obst[w->n_obst++];
    memset(o, 0, sizeof *o);
    o->kind = ROVER_OBST_BOX;
    o->cx_m = cx;
    o->cy_m = cy;
    o->hx_m = hx;
    o->hy_m = hy;
    o->angle_rad = angle_rad;
    o->height_m = height_m;
    return 0;
}

/* A thin wall from (ax, ay) to (bx, by) whose faces are thick_m apart. */
static void add_wall(rover_world_config *w, double ax, double ay, double bx, double by,
                     double thick_m)
{
    const double len = hypot(bx - ax, by - ay);
    (void)rover_world_add_box(w, 0.5 * (ax + bx), 0.5 * (ay + by), 0.5 * len, 0.5 * thick_m,
                              atan2(by - ay, bx - ax), 0.5);
}

static void add_circle(rover_world_config *w, double cx, double cy, double r)
{
    rover_obstacle *o;
    if (w->n_obst >= ROVER_WORLD_MAX_OBST)
        return;
    o = &w->obst[w->n_obst++];
    memset(o, 0, sizeof *o);
    o->kind = ROVER_OBST_CIRCLE;
    o->cx_m = cx;
    o->cy_m = cy;
    o->r_m = r;
    o->height_m = 0.6;
}

/* Obstacles relative to the front start row at x = xf (team centred on y = 0).
 * Distances are chosen for a 3-robot team at 1 m spacing (line width 2.38 m)
 * and scale with nothing else: larger teams meet the same features. */
static void build_features(rover_world_config *w, double xf)
{
    const double t = 0.1; /* wall thickness */
    switch (w->world) {
    case ROVER_WORLD_OPEN: w->goal_m[0] = xf + 12.0; break;
    case ROVER_WORLD_OBSTACLES:
        w->goal_m[0] = xf + 14.0;
        add_circle(w, xf + 4.0, 0.5, 0.25);
        add_circle(w, xf + 6.0, -2.3, 0.35);
        add_circle(w, xf + 8.0, -0.5, 0.3);
        (void)rover_world_add_box(w, xf + 11.0, 1.7, 0.3, 0.3, 0.4, 0.6);
        break;
    case ROVER_WORLD_CORRIDOR:
        /* funnel in, a 1.2 m corridor (faces at y = +-0.6: narrower than the
         * line, wide enough for a column), funnel out; long walls at the
         * funnel mouth so the team cannot go round. */
        w->goal_m[0] = xf + 17.0;
        add_wall(w, xf + 4.0, 3.0 + 0.5 * t, xf + 6.0, 0.6 + 0.5 * t, t);
        add_wall(w, xf + 4.0, -3.0 - 0.5 * t, xf + 6.0, -0.6 - 0.5 * t, t);
        add_wall(w, xf + 6.0, 0.6 + 0.5 * t, xf + 10.0, 0.6 + 0.5 * t, t);
        add_wall(w, xf + 6.0, -0.6 - 0.5 * t, xf + 10.0, -0.6 - 0.5 * t, t);
        add_wall(w, xf + 10.0, 0.6 + 0.5 * t, xf + 11.5, 3.0 + 0.5 * t, t);
        add_wall(w, xf + 10.0, -0.6 - 0.5 * t, xf + 11.5, -3.0 - 0.5 * t, t);
        add_wall(w, xf + 4.0, 3.0, xf + 4.0, 9.0, t);
        add_wall(w, xf + 4.0, -3.0, xf + 4.0, -9.0, t);
        break;
    default: {
        /* DEADZONE (docs/method/formation.md, dead-zone exception): a U lying across the way,
         * centred on the start -> goal line (y = 0), opening toward the
         * team, the goal 3.5 m behind its back wall. The mouth, 3.2 m
         * between the lips, takes the whole line (formation_width 2.38 m
         * at 1 m spacing) with 0.4 m to spare each side, so no robot
         * passes round the outside. Over 1.5 m the side walls close in to
         * a pocket 1.0 m wide and 1.2 m deep: a robot at its bottom has the
         * back wall ahead and a side wall on each hand, all under
         * d_s = 0.5 m (side echoes ~0.36 m; a trap must be narrower than
         * 2 (d_s + 0.136) = 1.27 m, 0.136 m being the side transducers'
         * offset), and room to turn on the spot (corner radius 0.31 m).
         * Mates are never trap walls, so no U wide enough for the whole
         * line can trap a robot at a wide bottom: the taper is what makes
         * the team's way end in a one-robot trap. */
        const double x_lip = xf + 5.5, x_pocket = xf + 7.0, x_back = xf + 8.2;
        const double mouth_half = 1.6, bottom_half = 0.5;
        w->goal_m[0] = x_back + 3.5;
        add_wall(w, x_back + 0.5 * t, -bottom_half - t, x_back + 0.5 * t, bottom_half + t, t);
        add_wall(w, x_lip, mouth_half + 0.5 * t, x_pocket, bottom_half + 0.5 * t, t);
        add_wall(w, x_lip, -mouth_half - 0.5 * t, x_pocket, -bottom_half - 0.5 * t, t);
        add_wall(w, x_pocket, bottom_half + 0.5 * t, x_back + t, bottom_half + 0.5 * t, t);
        add_wall(w, x_pocket, -bottom_half - 0.5 * t, x_back + t, -bottom_half - 0.5 * t, t);
        break;
    }
    }
}

static void add_landmark(rover_world_config *w, double x, double y)
{
    if (w->n_landmarks >= ROVER_WORLD_MAX_LANDMARKS)
        return;
    w->landmark_m[w->n_landmarks][0] = x;
    w->landmark_m[w->n_landmarks][1] = y;
    w->n_landmarks++;
}

/* Landmark pairs every 3 m along the way, 3.5 m out: from any pose on the
 * way the camera's forward frame (6 m, +-60 deg) holds two to four of
 * them, its side frames one or two. */
static void build_landmarks(rover_world_config *w, double x_from_m, double xf)
{
    const double side_m = 3.5, step_m = 3.0;
    /* on a grid anchored at the front start row, so the posts keep their
     * place relative to the worlds' walls whatever the team size */
    double x = xf + step_m * floor((x_from_m - xf) / step_m);
    for (; x <= w->goal_m[0] + 3.0 + 1e-9; x += step_m) {
        add_landmark(w, x, side_m);
        add_landmark(w, x, -side_m);
    }
    if (w->world == ROVER_WORLD_CORRIDOR) {
        add_landmark(w, xf + 7.0, 0.55);
        add_landmark(w, xf + 7.0, -0.55);
        add_landmark(w, xf + 9.0, 0.55);
        add_landmark(w, xf + 9.0, -0.55);
    }
}

/* How far the slots of the formation reach ahead of its centre (the
 * built-in worlds' goals lie ahead of the team, on y = 0). */
static double slots_ahead_m(int formation, int n, double spacing_m)
{
    double xy[2], ahead = 0.0;
    int k;
    for (k = 0; k < n; k++)
        if (formation_slot_xy(xy, formation, n, k, spacing_m, 1.0) == 0)
            ahead = fmax(ahead, xy[0]);
    return ahead;
}

int rover_world_layout(rover_world_config *w, int world, int n, double spacing_m, int formation)
{
    int k, rows;
    double xf, sx = 0.0, sy = 0.0;
    if (!w || world < 0 || world >= ROVER_WORLD_COUNT || n < 1 || n > ROVER_WORLD_MAX_ROBOTS ||
        !isfinite(spacing_m) || spacing_m <= ROVER_BODY_LENGTH_M || spacing_m > 10.0 ||
        formation < FORMATION_LINE || formation > FORMATION_COLUMN)
        return ROVER_WORLD_ERR_ARG;
    memset(w, 0, sizeof *w);
    w->world = world;
    w->n_robots = n;
    w->spacing_m = spacing_m;
    rows = (n + ROVER_WORLD_ROW_MAX - 1) / ROVER_WORLD_ROW_MAX;
    xf = 8.0 + spacing_m * (rows - 1);
    for (k = 0; k < n; k++) {
        const int r = k / ROVER_WORLD_ROW_MAX, j = k % ROVER_WORLD_ROW_MAX;
        const int in_row = (r == rows - 1) ? n - r * ROVER_WORLD_ROW_MAX : ROVER_WORLD_ROW_MAX;
        pose2 *c = &w->start_c[k];
        c->x_m = xf - spacing_m * r;
        c->y_m = spacing_m * (0.5 * (in_row - 1) - j);
        c->theta_rad = 0.0;
        if (n <= ROVER_WORLD_ROW_MAX && formation != FORMATION_LINE) {
            /* small teams start in their nominal formation, front at xf */
            double xy[2], x_top = 0.0;
            int q;
            for (q = 0; q < n; q++) {
                formation_slot_xy(xy, formation, n, q, spacing_m, 1.0);
                if (q == 0 || xy[0] > x_top)
                    x_top = xy[0];
            }
            formation_slot_xy(xy, formation, n, rover_world_slot(formation, n, k), spacing_m, 1.0);
            c->x_m = xf + xy[0] - x_top;
            c->y_m = xy[1];
        }
        sx += c->x_m - ROVER_BEACON_D_M;
        sy += c->y_m;
    }
    w->team_origin.x_m = sx / n;
    w->team_origin.y_m = sy / n;
    w->team_origin.theta_rad = 0.0;
    w->goal_m[1] = 0.0;
    build_features(w, xf);
    /* behind the rearmost start: a column or wedge reaches further back
     * than the rows of the grid */
    w->x_min_m = xf - spacing_m * rows - 1.0;
    for (k = 0; k < n; k++)
        if (w->start_c[k].x_m - spacing_m - 1.0 < w->x_min_m)
            w->x_min_m = w->start_c[k].x_m - spacing_m - 1.0;
    /* past the goal, room for the goal formation's slots ahead of its
     * centre (goal_place keeps them inside the extent, which the
     * navigation function's grid covers) */
    w->x_max_m = w->goal_m[0] + fmax(3.0, slots_ahead_m(formation, n, spacing_m) + 1.0);
    build_landmarks(w, w->x_min_m - 1.0, xf);
    w->y_max_m = 0.5 * spacing_m * ROVER_WORLD_ROW_MAX + 1.0;
    if (w->y_max_m < 4.0)
        w->y_max_m = 4.0;
    w->y_min_m = -w->y_max_m;
    goal_place(w, formation, spacing_m); /* a team too large for slots keeps the goal */
    return 0;
}

int rover_world_slot(int type, int n, int rank)
{
    int mid, j, k = 0;
    if (n < 1 || rank < 0 || rank >= n || type < FORMATION_LINE || type > FORMATION_COLUMN)
        return ROVER_WORLD_ERR_ARG;
    if (type == FORMATION_LINE)
        return rank;
    /* the left side (ranks below mid) takes the odd triangle slots, which
     * are one more than the even ones when n is even: mid = n / 2 keeps
     * every robot on its own side */
    mid = n / 2;
    if (rank == mid)
        return 0;
    /* order: mid, mid-1, mid+1, mid-2, mid+2, ... (skipping the ends) */
    for (j = 1; j < n; j++) {
        if (mid - j >= 0) {
            k++;
            if (rank == mid - j)
                return k;
        }
        if (mid + j < n) {
            k++;
            if (rank == mid + j)
                return k;
        }
    }
    return ROVER_WORLD_ERR_ARG;
}

void rover_frame_to(const pose2 *origin, const pose2 *world_p, pose2 *frame_p)
{
    double v[2];
    vec2_rotate(v, world_p->x_m - origin->x_m, world_p->y_m - origin->y_m, -origin->theta_rad);
    frame_p->x_m = v[0];
    frame_p->y_m = v[1];
    frame_p->theta_rad = vec2_wrap_rad(world_p->theta_rad - origin->theta_rad);
}

void rover_frame_from(const pose2 *origin, const pose2 *frame_p, pose2 *world_p)
{
    double v[2];
    vec2_rotate(v, frame_p->x_m, frame_p->y_m, origin->theta_rad);
    world_p->x_m = v[0] + origin->x_m;
    world_p->y_m = v[1] + origin->y_m;
    world_p->theta_rad = vec2_wrap_rad(frame_p->theta_rad + origin->theta_rad);
}

void rover_world_to_team(const rover_world_config *w, const pose2 *world_p, pose2 *team_p)
{
    rover_frame_to(&w->team_origin, world_p, team_p);
}

void rover_world_from_team(const rover_world_config *w, const pose2 *team_p, pose2 *world_p)
{
    rover_frame_from(&w->team_origin, team_p, world_p);
}

/* Signed distance from (x, y) to a box with centre, half extents, angle. */
static double box_distance(double cx, double cy, double hx, double hy, double a, double x, double y)
{
    double l[2], qx, qy, ox, oy;
    vec2_rotate(l, x - cx, y - cy, -a);
    qx = fabs(l[0]) - hx;
    qy = fabs(l[1]) - hy;
    ox = qx > 0.0 ? qx : 0.0;
    oy = qy > 0.0 ? qy : 0.0;
    return hypot(ox, oy) + (qx > qy ? (qx < 0.0 ? qx : 0.0) : (qy < 0.0 ? qy : 0.0));
}

double rover_obstacle_distance(const rover_obstacle *o, double x_m, double y_m)
{
    if (o->kind == ROVER_OBST_CIRCLE)
        return hypot(x_m - o->cx_m, y_m - o->cy_m) - o->r_m;
    return box_distance(o->cx_m, o->cy_m, o->hx_m, o->hy_m, o->angle_rad, x_m, y_m);
}

void rover_body_centre_of_c(const pose2 *c, double xy_m[2])
{
    xy_m[0] = c->x_m + ROVER_BODY_OFFSET_M * cos(c->theta_rad);
    xy_m[1] = c->y_m + ROVER_BODY_OFFSET_M * sin(c->theta_rad);
}

void rover_body_centre_of_o(const pose2 *o, double xy_m[2])
{
    pose2 c;
    unicycle_c_from_o(&c, o, ROVER_BEACON_D_M);
    rover_body_centre_of_c(&c, xy_m);
}

#define FOOT_PTS 8

/* Footprint outline samples (corners and edge midpoints) of a robot at c. */
static void footprint(const pose2 *c, double px[FOOT_PTS], double py[FOOT_PTS], double *bx,
                      double *by)
{
    static const double u[FOOT_PTS] = { 1, 1, 1, 0, -1, -1, -1, 0 };
    static const double v[FOOT_PTS] = { 1, 0, -1, -1, -1, 0, 1, 1 };
    const double ct = cos(c->theta_rad), st = sin(c->theta_rad);
    const double hx = 0.5 * ROVER_BODY_LENGTH_M, hy = 0.5 * ROVER_BODY_WIDTH_M;
    double b[2];
    int i;
    rover_body_centre_of_c(c, b);
    *bx = b[0];
    *by = b[1];
    for (i = 0; i < FOOT_PTS; i++) {
        px[i] = *bx + u[i] * hx * ct - v[i] * hy * st;
        py[i] = *by + u[i] * hx * st + v[i] * hy * ct;
    }
}

typedef char rover_world_grid_fits[ROVER_WORLD_MAX_ROBOTS <= PGRID_MAX_ITEMS ? 1 : -1];
typedef char
    rover_world_ids_below_landmarks[ROVER_WORLD_MAX_ROBOTS < ROVER_LANDMARK_ID_BASE ? 1 : -1];

#define CLEAR_REACH 0.6 /* two half-diagonals of the body, rounded up */

static int clearance_args(const rover_world_config *w, const pose2 *c, const int *alive, int n,
                          const double *clearance_m)
{
    int i;
    if (!w || !c || !alive || !clearance_m || n < 0 || n > ROVER_WORLD_MAX_ROBOTS)
        return ROVER_WORLD_ERR_ARG;
    for (i = 0; i < n; i++)
        if (alive[i] && !vec2_pose_finite(&c[i]))
            return ROVER_WORLD_ERR_ARG;
    return 0;
}

/* Smallest distance from robot i's footprint to an obstacle. */
static double clearance_obstacles(const rover_world_config *w, const double px[FOOT_PTS],
                                  const double py[FOOT_PTS])
{
    double best = INFINITY;
    int k, p;
    for (k = 0; k < w->n_obst; k++)
        for (p = 0; p < FOOT_PTS; p++) {
            const double d = rover_obstacle_distance(&w->obst[k], px[p], py[p]);
            if (d < best)
                best = d;
        }
    return best;
}

/* best lowered to robot i's distance to robot j's footprint (both ways),
 * unless j's centre is too far to come nearer than best. */
static double clearance_mate(const pose2 *c, int i, int j, const double px[FOOT_PTS],
                             const double py[FOOT_PTS], double bx, double by, double best)
{
    double qx[FOOT_PTS], qy[FOOT_PTS], cx2, cy2;
    int p;
    footprint(&c[j], qx, qy, &cx2, &cy2);
    if (hypot(cx2 - bx, cy2 - by) - CLEAR_REACH > best)
        return best;
    for (p = 0; p < FOOT_PTS; p++) {
        const double d1 = box_distance(cx2, cy2, 0.5 * ROVER_BODY_LENGTH_M,
                                       0.5 * ROVER_BODY_WIDTH_M, c[j].theta_rad, px[p], py[p]);
        const double d2 = box_distance(bx, by, 0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M,
                                       c[i].theta_rad, qx[p], qy[p]);
        if (d1 < best)
            best = d1;
        if (d2 < best)
            best = d2;
    }
    return best;
}

int rover_world_clearance(const rover_world_config *w, const pose2 *c, const int *alive, int n,
                          double *clearance_m)
{
    double px[FOOT_PTS], py[FOOT_PTS], bx, by;
    int i, j;
    if (clearance_args(w, c, alive, n, clearance_m) != 0)
        return ROVER_WORLD_ERR_ARG;
    for (i = 0; i < n; i++) {
        double best;
        if (!alive[i]) {
            clearance_m[i] = INFINITY;
            continue;
        }
        footprint(&c[i], px, py, &bx, &by);
        best = clearance_obstacles(w, px, py);
        for (j = 0; j < n; j++)
            if (j != i && alive[j])
                best = clearance_mate(c, i, j, px, py, bx, by, best);
        clearance_m[i] = best;
    }
    return 0;
}

/* The mates are looked up in a grid of the body centres, in discs that
 * double until the nearest distance found, plus the reach, lies inside
 * (with a margin for rounding): a mate outside has its centre farther
 * than best + reach, so it could not have lowered the minimum, which is
 * the same floating-point number whatever order it is taken in. */
int rover_world_clearance_indexed(const rover_world_config *w, const pose2 *c, const int *alive,
                                  int n, rover_clearance_work *work, double *clearance_m)
{
    double px[FOOT_PTS], py[FOOT_PTS], bx, by;
    int32_t *near;
    int i, q;
    if (clearance_args(w, c, alive, n, clearance_m) != 0 || !work)
        return ROVER_WORLD_ERR_ARG;
    near = work->near;
    for (i = 0; i < n; i++) {
        /* the body centres, as footprint() puts them */
        double b[2] = { 0.0, 0.0 };
        if (alive[i])
            rover_body_centre_of_c(&c[i], b);
        work->bx[i] = b[0];
        work->by[i] = b[1];
    }
    if (pgrid_build(&work->grid, work->bx, work->by, alive, n, 1.0) != PGRID_OK)
        return ROVER_WORLD_ERR_ARG;
    for (i = 0; i < n; i++) {
        double best, r = 2.0;
        int k;
        if (!alive[i]) {
            clearance_m[i] = INFINITY;
            continue;
        }
        footprint(&c[i], px, py, &bx, &by);
        best = clearance_obstacles(w, px, py);
        for (;;) {
            k = pgrid_query(&work->grid, bx, by, r, near, n);
            if (k < 0)
                return ROVER_WORLD_ERR_ARG;
            for (q = 0; q < k; q++)
                if (near[q] != i)
                    best = clearance_mate(c, i, near[q], px, py, bx, by, best);
            if (k >= work->grid.n_used || best + CLEAR_REACH + 1e-6 < r)
                break;
            r *= 2.0;
        }
        clearance_m[i] = best;
    }
    return 0;
}

/* Distance from p to the segment a-b. */
static double segment_distance_m(const double p[2], const double a[2], const double b[2])
{
    const double ux = b[0] - a[0], uy = b[1] - a[1], len2 = ux * ux + uy * uy;
    double t = len2 > 0.0 ? ((p[0] - a[0]) * ux + (p[1] - a[1]) * uy) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return hypot(p[0] - a[0] - t * ux, p[1] - a[1] - t * uy);
}

int rover_world_landmarks_near(const rover_world_config *w, const double a[2], const double b[2],
                               int32_t idx[ROVER_WORLD_MAX_LANDMARKS])
{
    double best_m[ROVER_WORLD_MAX_LANDMARKS] = { 0.0 };
    int k, n = 0, i;
    if (!w || !a || !b || !idx || w->n_landmarks < 0 || w->n_landmarks > ROVER_WORLD_MAX_POSTS)
        return ROVER_WORLD_ERR_ARG;
    if (w->n_landmarks <= ROVER_WORLD_MAX_LANDMARKS) {
        for (k = 0; k < w->n_landmarks; k++)
            idx[k] = k;
        return w->n_landmarks;
    }
    /* the nearest so far, by distance then index, in best_m / idx (an
     * insertion into at most ROVER_WORLD_MAX_LANDMARKS: O(posts x 64)) */
    for (k = 0; k < w->n_landmarks; k++) {
        const double d = segment_distance_m(w->landmark_m[k], a, b);
        if (n == ROVER_WORLD_MAX_LANDMARKS && !(d < best_m[n - 1]))
            continue;
        i = n < ROVER_WORLD_MAX_LANDMARKS ? n++ : n - 1;
        for (; i > 0 && best_m[i - 1] > d; i--) {
            best_m[i] = best_m[i - 1];
            idx[i] = idx[i - 1];
        }
        best_m[i] = d;
        idx[i] = k;
    }
    for (k = 1; k < n; k++) /* ascending index: the camera's order */
        for (i = k; i > 0 && idx[i - 1] > idx[i]; i--) {
            const int32_t t = idx[i];
            idx[i] = idx[i - 1];
            idx[i - 1] = t;
        }
    return n;
}

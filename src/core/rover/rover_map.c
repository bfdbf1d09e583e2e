/* rover_map: occupancy-grid worlds (docs/method/sonar.md §8): the
 * grid's occupied cells merged into axis-aligned boxes, and the team's
 * launch configuration on the map. See rover_map.h.
 */
#include "rover_map.h"

#include "formation.h"
#include "goal_place.h"

#include <math.h>
#include <string.h>

/* A cell taken into a box during rover_map_merge (restored to OCCUPIED). */
#define CELL_TAKEN 2

static int dims_ok(const rover_map *m)
{
    return m->width >= 1 && m->height >= 1 && m->width <= ROVER_MAP_MAX_SIDE &&
           m->height <= ROVER_MAP_MAX_SIDE &&
           (long)m->width * (long)m->height <= ROVER_MAP_MAX_CELLS;
}

int rover_map_validate(const rover_map *m)
{
    long k, cells;
    if (!m)
        return ROVER_MAP_ERR_ARG;
    if (!dims_ok(m))
        return ROVER_MAP_ERR_SIZE;
    if (!isfinite(m->resolution_m) || !(m->resolution_m > 0.0) || !isfinite(m->origin_x_m) ||
        !isfinite(m->origin_y_m))
        return ROVER_MAP_ERR_RESOLUTION;
    cells = (long)m->width * (long)m->height;
    for (k = 0; k < cells; k++)
        if (m->cell[k] != ROVER_MAP_FREE && m->cell[k] != ROVER_MAP_OCCUPIED)
            return ROVER_MAP_ERR_CELL;
    return ROVER_MAP_OK;
}

int rover_map_blocked(const rover_map *m, double x_m, double y_m)
{
    const double u = (x_m - m->origin_x_m) / m->resolution_m;
    const double v = (y_m - m->origin_y_m) / m->resolution_m;
    long i, j;
    if (!(u >= 0.0 && v >= 0.0 && u < m->width && v < m->height))
        return 1;
    i = (long)u;
    j = (long)v;
    return m->cell[j * m->width + i] != ROVER_MAP_FREE;
}

static unsigned char *cell_at(rover_map *m, int i, int j)
{
    return &m->cell[(long)j * m->width + i];
}

/* The box over cells [i0, i1] x [j0, j1]. */
static void box_of_cells(const rover_map *m, int i0, int j0, int i1, int j1, rover_obstacle *o)
{
    const double r = m->resolution_m;
    memset(o, 0, sizeof *o);
    o->kind = ROVER_OBST_BOX;
    o->hx_m = 0.5 * r * (i1 - i0 + 1);
    o->hy_m = 0.5 * r * (j1 - j0 + 1);
    o->cx_m = m->origin_x_m + r * i0 + o->hx_m;
    o->cy_m = m->origin_y_m + r * j0 + o->hy_m;
    o->height_m = ROVER_MAP_WALL_HEIGHT_M;
}

/* Row j0 holds an uncovered occupied run from i0: its end, then the rows
 * above it over which the whole run stays occupied and uncovered. */
static void grow_box(rover_map *m, int i0, int j0, int *i1, int *j1)
{
    int i, j, ok = 1;
    for (i = i0; i + 1 < m->width && *cell_at(m, i + 1, j0) == ROVER_MAP_OCCUPIED; i++) {
    }
    *i1 = i;
    for (j = j0 + 1; j < m->height && ok; j++) {
        for (i = i0; i <= *i1 && ok; i++)
            ok = *cell_at(m, i, j) == ROVER_MAP_OCCUPIED;
        if (!ok)
            break;
    }
    *j1 = j - 1;
}

static void mark_cells(rover_map *m, int i0, int j0, int i1, int j1, unsigned char v)
{
    int i, j;
    for (j = j0; j <= j1; j++)
        for (i = i0; i <= i1; i++)
            *cell_at(m, i, j) = v;
}

static void restore_cells(rover_map *m)
{
    const long cells = (long)m->width * (long)m->height;
    long k;
    for (k = 0; k < cells; k++)
        if (m->cell[k] == CELL_TAKEN)
            m->cell[k] = ROVER_MAP_OCCUPIED;
}

int rover_map_merge(rover_map *m, rover_obstacle *box, int cap, int *n)
{
    int i, j, i1, j1, rc;
    if (!box || !n || cap < 0)
        return ROVER_MAP_ERR_ARG;
    *n = 0;
    if ((rc = rover_map_validate(m)) != ROVER_MAP_OK)
        return rc;
    for (j = 0; j < m->height; j++)
        for (i = 0; i < m->width; i++) {
            if (*cell_at(m, i, j) != ROVER_MAP_OCCUPIED)
                continue;
            if (*n >= cap) {
                restore_cells(m);
                return ROVER_MAP_ERR_BOXES;
            }
            grow_box(m, i, j, &i1, &j1);
            mark_cells(m, i, j, i1, j1, CELL_TAKEN);
            box_of_cells(m, i, j, i1, j1, &box[(*n)++]);
        }
    restore_cells(m);
    return ROVER_MAP_OK;
}

/* The point at arc length a along the polyline way[0..n-1] (a < 0:
 * before way[0] along the first leg; past the end: on along the last
 * leg) and that leg's unit direction. Every leg is longer than 1e-9. */
static void along_point(const double (*way)[2], const double *leg_m, int n, double a, double p[2],
                        double u[2])
{
    int i = 0;
    double at = 0.0;
    while (i < n - 2 && a > at + leg_m[i]) {
        at += leg_m[i];
        i++;
    }
    u[0] = (way[i + 1][0] - way[i][0]) / leg_m[i];
    u[1] = (way[i + 1][1] - way[i][1]) / leg_m[i];
    p[0] = way[i][0] + (a - at) * u[0];
    p[1] = way[i][1] + (a - at) * u[1];
}

/* way[] without legs shorter than 1e-9 (into out; how many, at most cap),
 * each leg's length into leg_m. */
static int way_legs(const double (*way)[2], int n, double (*out)[2], double *leg_m, int cap)
{
    int k, m = 0;
    for (k = 0; k < n && m < cap; k++) {
        const double d = m > 0 ? hypot(way[k][0] - out[m - 1][0], way[k][1] - out[m - 1][1]) : 1.0;
        if (!(d > 1e-9) || !isfinite(way[k][0]) || !isfinite(way[k][1]))
            continue;
        if (m > 0)
            leg_m[m - 1] = d;
        out[m][0] = way[k][0];
        out[m][1] = way[k][1];
        m++;
    }
    return m;
}

/* A post on one side (side = +1 left, -1 right) of the way's point c,
 * across its direction u: side_m out, or, where a wall stands nearer,
 * by that wall on the way's side of it (wall_gap_m before its first
 * occupied sample), so a post never stands beyond a wall and a narrow
 * corridor still has posts on its floor. 1 and the post in out[], or 0
 * (a wall within wall_gap_m of c, or c itself off the free map). */
static int side_post(const rover_map *m, const double c[2], const double u[2], int side,
                     double out[2])
{
    const double side_m = 3.5, wall_gap_m = 0.15;
    const double step = 0.5 * m->resolution_m;
    const double nx = -side * u[1], ny = side * u[0];
    double d = 0.0, at = side_m;
    if (rover_map_blocked(m, c[0], c[1]))
        return 0;
    /* bounded: side_m / step samples */
    for (d = step; d <= side_m; d += step)
        if (rover_map_blocked(m, c[0] + d * nx, c[1] + d * ny)) {
            at = d - wall_gap_m;
            break;
        }
    if (at < step)
        return 0;
    out[0] = c[0] + at * nx;
    out[1] = c[1] + at * ny;
    return 1;
}

int rover_map_landmarks_along(const rover_map *m, const double (*way)[2], int n_way,
                              double heading_rad, double lm[ROVER_WORLD_MAX_LANDMARKS][2])
{
    const double margin_m = 3.0;
    double pts[ROVER_MAP_WAY_MAX][2], leg_m[ROVER_MAP_WAY_MAX], len = 0.0, span, step_m = 3.0;
    int k, n = 0, pairs, np;
    if (!m || !way || n_way < 1 || n_way > ROVER_MAP_WAY_MAX)
        return 0;
    np = way_legs(way, n_way, pts, leg_m, ROVER_MAP_WAY_MAX);
    if (np < 1)
        return 0;
    if (np == 1) { /* a start on the goal still gets posts around it */
        pts[1][0] = pts[0][0] + cos(heading_rad);
        pts[1][1] = pts[0][1] + sin(heading_rad);
        leg_m[0] = 1.0;
        np = 2;
    } else {
        for (k = 0; k < np - 1; k++)
            len += leg_m[k];
    }
    span = len + 2.0 * margin_m;
    /* NOLINTNEXTLINE(bugprone-integer-division): whole pairs of landmarks */
    if (span / step_m + 1.0 > ROVER_WORLD_MAX_LANDMARKS / 2)
        /* NOLINTNEXTLINE(bugprone-integer-division): whole pairs of landmarks */
        step_m = span / (ROVER_WORLD_MAX_LANDMARKS / 2 - 1);
    pairs = (int)floor(span / step_m + 1e-9) + 1;
    if (pairs > ROVER_WORLD_MAX_LANDMARKS / 2)
        pairs = ROVER_WORLD_MAX_LANDMARKS / 2;
    for (k = 0; k < pairs; k++) {
        double c[2], u[2];
        int side;
        along_point((const double(*)[2])pts, leg_m, np, -margin_m + step_m * k, c, u);
        for (side = -1; side <= 1; side += 2)
            n += side_post(m, c, u, side, lm[n]);
    }
    return n;
}

int rover_map_auto_landmarks(const rover_map *m, const pose2 *start, const double goal_m[2],
                             double lm[ROVER_WORLD_MAX_LANDMARKS][2])
{
    const double way[2][2] = { { start->x_m, start->y_m }, { goal_m[0], goal_m[1] } };
    return rover_map_landmarks_along(m, way, 2, start->theta_rad, lm);
}

int rover_map_landmarks_on_way(rover_world_config *w, const rover_map *m, const navfield *f)
{
    double way[ROVER_MAP_WAY_MAX][2], from[2], goal[2];
    pose2 p, q;
    int k, n;
    p = w->team_origin;
    rover_world_to_team(w, &p, &q);
    from[0] = q.x_m;
    from[1] = q.y_m;
    p.x_m = w->goal_m[0];
    p.y_m = w->goal_m[1];
    rover_world_to_team(w, &p, &q);
    goal[0] = q.x_m;
    goal[1] = q.y_m;
    n = navfield_polyline(f, from, goal, way, ROVER_MAP_WAY_MAX);
    if (n >= 1) { /* the start as it is given, the rest to the world frame the posts are in */
        way[0][0] = w->team_origin.x_m;
        way[0][1] = w->team_origin.y_m;
    }
    for (k = 1; k < n; k++) {
        q.x_m = way[k][0];
        q.y_m = way[k][1];
        q.theta_rad = 0.0;
        rover_world_from_team(w, &q, &p);
        way[k][0] = p.x_m;
        way[k][1] = p.y_m;
    }
    if (n >= 2)
        w->n_landmarks = rover_map_landmarks_along(m, (const double(*)[2])way, n,
                                                   w->team_origin.theta_rad, w->landmark_m);
    return w->n_landmarks;
}

/* Robots of the open-world layout moved so that its team frame becomes
 * the start pose. */
static int place_team(rover_world_config *w, const pose2 *start, int n, double spacing_m,
                      int formation)
{
    rover_world_config *open = w; /* built in place, then re-framed */
    pose2 team[ROVER_WORLD_MAX_ROBOTS];
    int k;
    if (rover_world_layout(open, ROVER_WORLD_OPEN, n, spacing_m, formation) != 0)
        return ROVER_MAP_ERR_ARG;
    for (k = 0; k < n; k++)
        rover_world_to_team(open, &open->start_c[k], &team[k]);
    w->team_origin = *start;
    w->team_origin.theta_rad = vec2_wrap_rad(start->theta_rad);
    for (k = 0; k < n; k++)
        rover_world_from_team(w, &team[k], &w->start_c[k]);
    return ROVER_MAP_OK;
}

/* Every robot's body (its footprint, and a disc round it) on the map and
 * clear of the boxes. */
static int starts_clear(const rover_world_config *w, const rover_map *m)
{
    int alive[ROVER_WORLD_MAX_ROBOTS], k, q;
    double cl[ROVER_WORLD_MAX_ROBOTS];
    const double reach = 0.5 * hypot(ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M) +
                         fabs(ROVER_BODY_OFFSET_M);
    for (k = 0; k < w->n_robots; k++)
        alive[k] = 1;
    if (rover_world_clearance(w, w->start_c, alive, w->n_robots, cl) != 0)
        return 0;
    for (k = 0; k < w->n_robots; k++) {
        const pose2 *c = &w->start_c[k];
        if (!(cl[k] > 0.0))
            return 0;
        for (q = 0; q < 8; q++) {
            const double a = q * 0.7853981633974483;
            if (rover_map_blocked(m, c->x_m + reach * cos(a), c->y_m + reach * sin(a))) {
                /* off the map, or a cell the box merge did not see as a
                 * box (it did: then clearance caught it) */
                return 0;
            }
        }
    }
    return 1;
}

static int site_finite(const rover_map_site *s)
{
    int k;
    if (!vec2_pose_finite(&s->start))
        return ROVER_MAP_ERR_START;
    if (!isfinite(s->goal_m[0]) || !isfinite(s->goal_m[1]))
        return ROVER_MAP_ERR_GOAL;
    if (s->n_landmarks != ROVER_MAP_LANDMARKS_AUTO &&
        (s->n_landmarks < 0 || s->n_landmarks > ROVER_WORLD_MAX_LANDMARKS))
        return ROVER_MAP_ERR_LANDMARKS;
    for (k = 0; k < s->n_landmarks; k++)
        if (!isfinite(s->landmark_m[k][0]) || !isfinite(s->landmark_m[k][1]))
            return ROVER_MAP_ERR_LANDMARKS;
    return ROVER_MAP_OK;
}

int rover_world_from_map(rover_world_config *w, rover_map *m, const rover_map_site *s, int n,
                         double spacing_m, int formation)
{
    int rc;
    if (!w || !m || !s)
        return ROVER_MAP_ERR_ARG;
    if ((rc = rover_map_validate(m)) != ROVER_MAP_OK || (rc = site_finite(s)) != ROVER_MAP_OK) {
        memset(w, 0, sizeof *w);
        return rc;
    }
    if ((rc = place_team(w, &s->start, n, spacing_m, formation)) != ROVER_MAP_OK) {
        memset(w, 0, sizeof *w);
        return rc;
    }
    w->world = ROVER_WORLD_FILE;
    w->goal_m[0] = s->goal_m[0];
    w->goal_m[1] = s->goal_m[1];
    w->x_min_m = m->origin_x_m;
    w->y_min_m = m->origin_y_m;
    w->x_max_m = m->origin_x_m + m->resolution_m * m->width;
    w->y_max_m = m->origin_y_m + m->resolution_m * m->height;
    rc = rover_map_merge(m, w->obst, ROVER_WORLD_MAX_OBST, &w->n_obst);
    if (rc == ROVER_MAP_OK && rover_map_blocked(m, s->goal_m[0], s->goal_m[1]))
        rc = ROVER_MAP_ERR_GOAL;
    if (rc == ROVER_MAP_OK && !starts_clear(w, m))
        rc = ROVER_MAP_ERR_START;
    if (rc != ROVER_MAP_OK) {
        memset(w, 0, sizeof *w);
        return rc;
    }
    goal_place(w, formation, spacing_m); /* a team too large for slots keeps the goal */
    if (s->n_landmarks == ROVER_MAP_LANDMARKS_AUTO) {
        w->n_landmarks = rover_map_auto_landmarks(m, &w->team_origin, w->goal_m, w->landmark_m);
    } else {
        w->n_landmarks = s->n_landmarks;
        memcpy(w->landmark_m, s->landmark_m, sizeof s->landmark_m); /* a site holds a robot's 64 */
    }
    return ROVER_MAP_OK;
}

/* worldgen: random occupancy-map worlds with a checked way through
 * (see worldgen.h; docs/formation.md, "Generated worlds"). Shapes are
 * rasterised at cell centres; the way is checked by a breadth-first
 * search over the cells whose distance to an obstacle (a two-pass
 * 8-neighbour chamfer transform) exceeds the body radius plus the margin.
 */
#include "worldgen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "formation.h"
#include "prng.h"

#define WALL_M 0.2         /* the map's border wall */
#define POCKET_WALL_M 0.15 /* a pocket's walls */
#define GOAL_CLEAR_M 1.5   /* free disc round the goal, at least */

static const char *const kind_names[WORLDGEN_KINDS] = { "clutter", "traps", "corridor", "mixed" };

int worldgen_kind(const char *name)
{
    int k;
    for (k = 0; name && k < WORLDGEN_KINDS; k++)
        if (!strcmp(name, kind_names[k]))
            return k;
    return WORLDGEN_ERR_ARG;
}

const char *worldgen_kind_name(int kind)
{
    return kind >= 0 && kind < WORLDGEN_KINDS ? kind_names[kind] : "?";
}

/* ---- rasterising ---------------------------------------------------------------- */

static void cell_centre(const rover_map *m, int i, int j, double *x, double *y)
{
    *x = m->origin_x_m + (i + 0.5) * m->resolution_m;
    *y = m->origin_y_m + (j + 0.5) * m->resolution_m;
}

/* Cell index range covering [x0, x1] x [y0, y1], clipped to the map. */
static void cell_range(const rover_map *m, double x0, double y0, double x1, double y1, int r[4])
{
    r[0] = (int)floor((x0 - m->origin_x_m) / m->resolution_m);
    r[1] = (int)floor((y0 - m->origin_y_m) / m->resolution_m);
    r[2] = (int)floor((x1 - m->origin_x_m) / m->resolution_m);
    r[3] = (int)floor((y1 - m->origin_y_m) / m->resolution_m);
    if (r[0] < 0)
        r[0] = 0;
    if (r[1] < 0)
        r[1] = 0;
    if (r[2] >= m->width)
        r[2] = m->width - 1;
    if (r[3] >= m->height)
        r[3] = m->height - 1;
}

static double seg_distance(double px, double py, double ax, double ay, double bx, double by)
{
    const double ex = bx - ax, ey = by - ay, l2 = ex * ex + ey * ey;
    double t = l2 > 0.0 ? ((px - ax) * ex + (py - ay) * ey) / l2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return hypot(px - ax - t * ex, py - ay - t * ey);
}

/* Cells within half_m of the segment become v. */
static void paint_segment(rover_map *m, double ax, double ay, double bx, double by, double half_m,
                          unsigned char v)
{
    int r[4], i, j;
    double x, y;
    cell_range(m, fmin(ax, bx) - half_m, fmin(ay, by) - half_m, fmax(ax, bx) + half_m,
               fmax(ay, by) + half_m, r);
    for (j = r[1]; j <= r[3]; j++)
        for (i = r[0]; i <= r[2]; i++) {
            cell_centre(m, i, j, &x, &y);
            if (seg_distance(x, y, ax, ay, bx, by) <= half_m)
                m->cell[(long)j * m->width + i] = v;
        }
}

/* A convex polygon (counter-clockwise) filled. */
static void fill_convex(rover_map *m, const double (*p)[2], int n)
{
    double x0 = p[0][0], y0 = p[0][1], x1 = x0, y1 = y0, x, y;
    int r[4], i, j, k;
    for (k = 1; k < n; k++) {
        x0 = fmin(x0, p[k][0]);
        x1 = fmax(x1, p[k][0]);
        y0 = fmin(y0, p[k][1]);
        y1 = fmax(y1, p[k][1]);
    }
    cell_range(m, x0, y0, x1, y1, r);
    for (j = r[1]; j <= r[3]; j++)
        for (i = r[0]; i <= r[2]; i++) {
            int inside = 1;
            cell_centre(m, i, j, &x, &y);
            for (k = 0; k < n && inside; k++) {
                const double *a = p[k], *b = p[(k + 1) % n];
                inside = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) >= 0.0;
            }
            if (inside)
                m->cell[(long)j * m->width + i] = ROVER_MAP_OCCUPIED;
        }
}

static void border(rover_map *m)
{
    const double x0 = m->origin_x_m, y0 = m->origin_y_m;
    const double x1 = x0 + m->width * m->resolution_m, y1 = y0 + m->height * m->resolution_m;
    const double h = 0.5 * WALL_M;
    paint_segment(m, x0 + h, y0 + h, x1 - h, y0 + h, h, ROVER_MAP_OCCUPIED);
    paint_segment(m, x0 + h, y1 - h, x1 - h, y1 - h, h, ROVER_MAP_OCCUPIED);
    paint_segment(m, x0 + h, y0 + h, x0 + h, y1 - h, h, ROVER_MAP_OCCUPIED);
    paint_segment(m, x1 - h, y0 + h, x1 - h, y1 - h, h, ROVER_MAP_OCCUPIED);
}

/* ---- shapes ------------------------------------------------------------------------ */

static double uniform(prng_state *r, double a, double b)
{
    return a + (b - a) * prng_uniform(r);
}

/* A random convex polygon: 3..7 points at sorted angles on a circle,
 * stretched and turned (an affine image of a convex polygon is convex). */
static void clutter_shape(rover_map *m, prng_state *r, double cx, double cy)
{
    double p[7][2] = { { 0.0, 0.0 } }, a[7], tmp;
    const int n = 3 + (int)(prng_uniform(r) * 5);
    const double rad = uniform(r, 0.2, 0.9), sx = uniform(r, 0.5, 1.5),
                 turn = uniform(r, 0.0, 2.0 * VEC2_PI);
    int k, q;
    for (k = 0; k < n; k++)
        a[k] = uniform(r, 0.0, 2.0 * VEC2_PI);
    for (k = 1; k < n; k++) /* insertion sort: ccw order */
        for (q = k; q > 0 && a[q - 1] > a[q]; q--) {
            tmp = a[q];
            a[q] = a[q - 1];
            a[q - 1] = tmp;
        }
    for (k = 0; k < n; k++) {
        const double u = rad * sx * cos(a[k]), v = rad / sx * sin(a[k]);
        p[k][0] = cx + u * cos(turn) - v * sin(turn);
        p[k][1] = cy + u * sin(turn) + v * cos(turn);
    }
    fill_convex(m, (const double(*)[2])p, n);
}

/* A wall between local points (u, v) of a frame at (cx, cy) turned by phi. */
static void local_wall(rover_map *m, double cx, double cy, double phi, double u0, double v0,
                       double u1, double v1)
{
    const double c = cos(phi), s = sin(phi);
    paint_segment(m, cx + u0 * c - v0 * s, cy + u0 * s + v0 * c, cx + u1 * c - v1 * s,
                  cy + u1 * s + v1 * c, 0.5 * POCKET_WALL_M, ROVER_MAP_OCCUPIED);
}

/* A U, V or L pocket whose mouth (at its centre) faces phi. */
static void pocket(rover_map *m, prng_state *r, double cx, double cy, double phi)
{
    const int type = (int)(prng_uniform(r) * 3);
    const double w = uniform(r, 1.0, 3.5), d = uniform(r, 1.0, 3.0);
    if (type == 0) { /* U */
        local_wall(m, cx, cy, phi, -d, -0.5 * w, -d, 0.5 * w);
        local_wall(m, cx, cy, phi, -d, -0.5 * w, 0.0, -0.5 * w);
        local_wall(m, cx, cy, phi, -d, 0.5 * w, 0.0, 0.5 * w);
    } else if (type == 1) { /* V */
        local_wall(m, cx, cy, phi, -d, 0.0, 0.0, -0.5 * w);
        local_wall(m, cx, cy, phi, -d, 0.0, 0.0, 0.5 * w);
    } else { /* L */
        local_wall(m, cx, cy, phi, -d, -0.5 * w, -d, 0.5 * w);
        local_wall(m, cx, cy, phi, -d, 0.5 * w, 0.0, 0.5 * w);
    }
}

/* The team's start area: a disc holding every robot's slot with room. */
static double start_radius(int n)
{
    const int rows = (n + 9) / 10;
    return n <= 10 ? 0.5 * (n - 1) + 1.2 : 0.5 * hypot(9.0, rows - 1.0) + 1.2;
}

/* The goal area: a disc that holds every robot's slot of the formation
 * placed at the goal with the room the start area has (a team that came
 * through a narrow leg in column must open out into its slots there; a
 * disc of 1.5 m jammed lines that came through a corridor). */
static double goal_radius(int n)
{
    /* the line (and the column) reach (n - 1) / 2 spacings of 1 m from
     * their centre, the triangle less */
    return fmax(GOAL_CLEAR_M, 0.5 * (n - 1) + 1.2);
}

/* A point along the way at fraction f, pushed sideways by lat_m. */
static void along(const rover_map_site *s, double f, double lat_m, double *x, double *y)
{
    const double dx = s->goal_m[0] - s->start.x_m, dy = s->goal_m[1] - s->start.y_m,
                 l = hypot(dx, dy);
    *x = s->start.x_m + f * dx - lat_m * dy / l;
    *y = s->start.y_m + f * dy + lat_m * dx / l;
}

static void add_clutter(rover_map *m, prng_state *r, double per_m2)
{
    const double w = m->width * m->resolution_m, h = m->height * m->resolution_m;
    const int n = (int)(per_m2 * w * h);
    int k;
    for (k = 0; k < n; k++)
        clutter_shape(m, r, m->origin_x_m + uniform(r, 0.0, w), m->origin_y_m + uniform(r, 0.0, h));
}

static void add_traps(rover_map *m, prng_state *r, const rover_map_site *s, int count)
{
    const double h = m->height * m->resolution_m;
    int k;
    for (k = 0; k < count; k++) {
        double x, y, phi;
        along(s, uniform(r, 0.3, 0.8), uniform(r, -h / 5.0, h / 5.0), &x, &y);
        /* most face the team: the mouth toward the start, give or take 30 deg */
        if (prng_uniform(r) < 0.6)
            phi = atan2(s->start.y_m - y, s->start.x_m - x) + uniform(r, -0.52, 0.52);
        else
            phi = uniform(r, -VEC2_PI, VEC2_PI);
        pocket(m, r, x, y, phi);
    }
}

/* Everything walled, then a channel carved from start to goal through 1-3
 * bends, each leg its own width, one leg narrowed to 1.3-1.5 m. */
static void add_corridor(rover_map *m, prng_state *r, const rover_map_site *s)
{
    const double h = m->height * m->resolution_m;
    double pts[5][2];
    const int bends = 1 + (int)(prng_uniform(r) * 3), narrow = (int)(prng_uniform(r) * (bends + 1));
    int k;
    memset(m->cell, ROVER_MAP_OCCUPIED, (size_t)m->width * (size_t)m->height);
    pts[0][0] = s->start.x_m;
    pts[0][1] = s->start.y_m;
    for (k = 1; k <= bends; k++)
        along(s, (double)k / (bends + 1), uniform(r, -h / 3.0, h / 3.0), &pts[k][0], &pts[k][1]);
    pts[bends + 1][0] = s->goal_m[0];
    pts[bends + 1][1] = s->goal_m[1];
    for (k = 0; k <= bends; k++) {
        const double half = k == narrow ? uniform(r, 0.65, 0.75) : uniform(r, 0.9, 1.6);
        paint_segment(m, pts[k][0], pts[k][1], pts[k + 1][0], pts[k + 1][1], half, ROVER_MAP_FREE);
    }
}

/* A wall across the way with one gap 1.5-3 m wide somewhere along it. */
static void add_wall_with_gap(rover_map *m, prng_state *r, const rover_map_site *s)
{
    const double h = m->height * m->resolution_m, gap = uniform(r, 1.5, 3.0),
                 at = uniform(r, -h / 4.0, h / 4.0);
    double ax, ay, bx, by;
    const double f = uniform(r, 0.35, 0.65);
    along(s, f, -h, &ax, &ay);
    along(s, f, at - 0.5 * gap, &bx, &by);
    paint_segment(m, ax, ay, bx, by, 0.5 * POCKET_WALL_M, ROVER_MAP_OCCUPIED);
    along(s, f, at + 0.5 * gap, &ax, &ay);
    along(s, f, h, &bx, &by);
    paint_segment(m, ax, ay, bx, by, 0.5 * POCKET_WALL_M, ROVER_MAP_OCCUPIED);
}

static void clear_disc(rover_map *m, double x, double y, double r_m)
{
    paint_segment(m, x, y, x, y, r_m, ROVER_MAP_FREE);
}

static void draw(rover_map *m, prng_state *r, const rover_map_site *s, const worldgen_params *p)
{
    memset(m->cell, ROVER_MAP_FREE, (size_t)m->width * (size_t)m->height);
    switch (p->kind) {
    case WORLDGEN_CLUTTER: add_clutter(m, r, uniform(r, 0.04, 0.09)); break;
    case WORLDGEN_TRAPS: add_traps(m, r, s, 1 + (int)(prng_uniform(r) * 4)); break;
    case WORLDGEN_CORRIDOR: add_corridor(m, r, s); break;
    default:
        add_clutter(m, r, uniform(r, 0.02, 0.04));
        add_traps(m, r, s, 1 + (int)(prng_uniform(r) * 2));
        if (prng_uniform(r) < 0.5)
            add_wall_with_gap(m, r, s);
        break;
    }
    clear_disc(m, s->start.x_m, s->start.y_m, start_radius(p->robots));
    clear_disc(m, s->goal_m[0], s->goal_m[1], goal_radius(p->robots));
    border(m);
}

/* ---- the way -------------------------------------------------------------------------- */

/* Distance (m) from each cell centre to the nearest occupied cell or the
 * map's edge, by the two-pass 8-neighbour chamfer (a path length, so at
 * most 8 % above the straight distance: the margin covers it). */
static void distance_field(const rover_map *m, float *d)
{
    const long w = m->width, h = m->height;
    const float s1 = (float)m->resolution_m, s2 = (float)(m->resolution_m * 1.4142135623730951);
    long i, j;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            const int edge = i == 0 || j == 0 || i == w - 1 || j == h - 1;
            d[j * w + i] = m->cell[j * w + i] != ROVER_MAP_FREE ? 0.0f : (edge ? s1 : 1e30f);
        }
    for (j = 1; j < h; j++)
        for (i = 1; i < w; i++) {
            float *c = &d[j * w + i];
            *c = fminf(*c, fminf(d[j * w + i - 1] + s1, d[(j - 1) * w + i] + s1));
            *c = fminf(*c, d[(j - 1) * w + i - 1] + s2);
            if (i + 1 < w)
                *c = fminf(*c, d[(j - 1) * w + i + 1] + s2);
        }
    for (j = h - 2; j >= 0; j--)
        for (i = w - 2; i >= 0; i--) {
            float *c = &d[j * w + i];
            *c = fminf(*c, fminf(d[j * w + i + 1] + s1, d[(j + 1) * w + i] + s1));
            *c = fminf(*c, d[(j + 1) * w + i + 1] + s2);
            if (i > 0)
                *c = fminf(*c, d[(j + 1) * w + i - 1] + s2);
        }
}

static long cell_of(const rover_map *m, double x, double y)
{
    const double u = (x - m->origin_x_m) / m->resolution_m,
                 v = (y - m->origin_y_m) / m->resolution_m;
    if (!(u >= 0.0 && v >= 0.0 && u < m->width && v < m->height))
        return -1;
    return (long)v * m->width + (long)u;
}

/* Breadth-first from the goal over the cells clear by more than clearance;
 * seen[] marks what it reached. 0 if the goal itself is not clear. */
static int flood_from(const rover_map *m, const float *d, long goal, float clearance,
                      unsigned char *seen, long *queue)
{
    static const int di[8] = { 1, -1, 0, 0, 1, 1, -1, -1 }, dj[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };
    long head = 0, tail = 0;
    if (goal < 0 || d[goal] <= clearance)
        return 0;
    seen[goal] = 1;
    queue[tail++] = goal;
    while (head < tail) {
        const long c = queue[head++];
        const long i = c % m->width, j = c / m->width;
        int k;
        for (k = 0; k < 8; k++) {
            const long ni = i + di[k], nj = j + dj[k];
            long q;
            if (ni < 0 || nj < 0 || ni >= m->width || nj >= m->height)
                continue;
            q = nj * m->width + ni;
            if (seen[q] || d[q] <= clearance)
                continue;
            /* a diagonal step needs both sides clear: no squeezing through a corner */
            if (k >= 4 && (d[j * m->width + ni] <= clearance || d[nj * m->width + i] <= clearance))
                continue;
            seen[q] = 1;
            queue[tail++] = q;
        }
    }
    return 1;
}

/* Slot k of the formation placed at the goal, headed along the
 * bearing of the goal from the start (what each robot's goal behaviour
 * drives it to) lies on a cell the search reached: the team can take its
 * slots, not only get one robot to the goal. */
static int goal_slot_reached(const rover_map *m, const rover_map_site *s, int n, int formation,
                             int k, const unsigned char *seen)
{
    const double heading = atan2(s->goal_m[1] - s->start.y_m, s->goal_m[0] - s->start.x_m);
    double xy[2];
    long c;
    if (formation_slot_xy(xy, formation, n, k, 1.0, 1.0) != 0)
        return 0;
    c = cell_of(m, s->goal_m[0] + xy[0] * cos(heading) - xy[1] * sin(heading),
                s->goal_m[1] + xy[0] * sin(heading) + xy[1] * cos(heading));
    return c >= 0 && seen[c];
}

int worldgen_passable(rover_map *m, const rover_map_site *s, int n, int formation,
                      double clearance_m)
{
    const long cells = (long)m->width * m->height;
    rover_world_config *w = malloc(sizeof *w);
    float *d = malloc(sizeof *d * (size_t)cells);
    unsigned char *seen = calloc((size_t)cells, 1);
    long *queue = malloc(sizeof *queue * (size_t)cells);
    int ok = 0, k;
    if (w && d && seen && queue &&
        rover_world_from_map(w, m, s, n, 1.0, formation) == ROVER_MAP_OK) {
        distance_field(m, d);
        ok = flood_from(m, d, cell_of(m, s->goal_m[0], s->goal_m[1]), (float)clearance_m, seen,
                        queue);
        for (k = 0; ok && k < n; k++) {
            const long c = cell_of(m, w->start_c[k].x_m, w->start_c[k].y_m);
            ok = c >= 0 && seen[c] && goal_slot_reached(m, s, n, formation, k, seen);
        }
    }
    free(w);
    free(d);
    free(seen);
    free(queue);
    return ok;
}

/* ---- the world ---------------------------------------------------------------------------- */

static void place_site(rover_map_site *s, prng_state *r, const worldgen_params *p)
{
    const double rs = start_radius(p->robots);
    memset(s, 0, sizeof *s);
    s->start.x_m = WALL_M + rs + 0.3;
    s->start.y_m = 0.5 * p->height_m + uniform(r, -0.1, 0.1) * p->height_m;
    s->goal_m[0] = p->width_m - WALL_M - goal_radius(p->robots) - 1.0;
    s->goal_m[1] = 0.5 * p->height_m + uniform(r, -0.25, 0.25) * p->height_m;
    s->start.theta_rad = atan2(s->goal_m[1] - s->start.y_m, s->goal_m[0] - s->start.x_m);
    s->n_landmarks = ROVER_MAP_LANDMARKS_AUTO;
}

static int params_ok(const worldgen_params *p)
{
    const double rs = start_radius(p->robots);
    return p->kind >= 0 && p->kind < WORLDGEN_KINDS && p->robots >= 1 &&
           p->robots <= ROVER_TEAM_MAX && p->formation >= FORMATION_LINE &&
           p->formation <= FORMATION_COLUMN && isfinite(p->width_m) && isfinite(p->height_m) &&
           p->height_m >= 2.0 * fmax(rs, goal_radius(p->robots)) + 2.0 * WALL_M + 1.0 &&
           /* start and goal areas (placed as place_site does) do not overlap */
           p->width_m >= 2.0 * WALL_M + 1.3 + 2.0 * (rs + goal_radius(p->robots)) &&
           p->width_m / WORLDGEN_RESOLUTION_M <= ROVER_MAP_MAX_SIDE &&
           p->height_m / WORLDGEN_RESOLUTION_M <= ROVER_MAP_MAX_SIDE;
}

int worldgen_make(rover_map *m, rover_map_site *s, const worldgen_params *p, int *attempt)
{
    int a;
    if (!m || !s || !p || !params_ok(p))
        return WORLDGEN_ERR_ARG;
    m->resolution_m = WORLDGEN_RESOLUTION_M;
    m->origin_x_m = 0.0;
    m->origin_y_m = 0.0;
    m->width = (int)floor(p->width_m / WORLDGEN_RESOLUTION_M + 0.5);
    m->height = (int)floor(p->height_m / WORLDGEN_RESOLUTION_M + 0.5);
    for (a = 0; a < WORLDGEN_ATTEMPTS; a++) {
        prng_state r;
        /* sub-seed a of seed W: a fixed function of both, so W alone names the world */
        prng_seed(&r, p->seed * 1000003ULL + (uint64_t)a * 7919ULL);
        place_site(s, &r, p);
        draw(m, &r, s, p);
        if (worldgen_passable(m, s, p->robots, p->formation,
                              WORLDGEN_BODY_RADIUS_M + WORLDGEN_MARGIN_M)) {
            if (attempt)
                *attempt = a;
            return WORLDGEN_OK;
        }
    }
    return WORLDGEN_ERR_NO_WAY;
}

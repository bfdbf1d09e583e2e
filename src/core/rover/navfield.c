/* navfield: the navigation function of a world and the point to steer for
 * on it (docs/method/formation.md §14; navfield.h says why its descent
 * cannot stall). The field is a shortest-path length computed by
 * Gauss-Seidel relaxation of the 8-connected grid in the four raster
 * orders until a pass changes nothing (the fast-sweeping method): each
 * pass carries the values round the bends its order runs along.
 */
#include "navfield.h"

#include <math.h>

#define START_RING_M 1.5 /* a start in a blocked cell looks this far for one joined to the goal */
#define CELL_GROW 1.05   /* the cell grows by this while the world needs too many */
#define CELL_GROW_MAX 64 /* ... at most this many times */
/* the passage width's lines: the way's normal and 2 x TILTS lines tilted
 * from it in equal steps up to TILT_RAD (45 deg) each way (across_m) */
#define NAVFIELD_ACROSS_TILT_RAD 0.78539816339744831
#define NAVFIELD_ACROSS_TILTS 4

/* the 8 neighbours: the four sides first, then the diagonals */
static const int nb_di[8] = { 1, -1, 0, 0, 1, 1, -1, -1 };
static const int nb_dj[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };

void navfield_params_default(navfield_params *p)
{
    p->clear_m = 0.45; /* the body's 0.32 m about C and 0.13 m */
    p->los_m = 0.45;
    p->prefer_m = 1.5;
    p->pen_gain = 4.0;
    p->look_m = 8.0;
    p->min_ahead_m = 1.0;
    p->cell_min_m = 0.1;
}

static int positive(double x)
{
    return isfinite(x) && x > 0.0;
}

int navfield_params_validate(const navfield_params *p)
{
    if (!p || !positive(p->clear_m) || !positive(p->los_m) || !positive(p->prefer_m) ||
        !isfinite(p->pen_gain) || p->pen_gain < 0.0 || !positive(p->look_m) ||
        !isfinite(p->min_ahead_m) || p->min_ahead_m < 0.0 || p->min_ahead_m > p->look_m ||
        !positive(p->cell_min_m))
        return NAVFIELD_ERR_ARG;
    if (p->los_m < 0.5 * p->clear_m || p->prefer_m < p->clear_m)
        return NAVFIELD_ERR_ARG;
    return NAVFIELD_OK;
}

/* The cell holding world point (x, y), or -1 off the grid. */
static long cell_of(const navfield *f, double x_m, double y_m)
{
    const double u = (x_m - f->x0_m) / f->cell_m, v = (y_m - f->y0_m) / f->cell_m;
    if (!(u >= 0.0 && v >= 0.0 && u < (double)f->nx && v < (double)f->ny))
        return -1;
    return (long)v * f->nx + (long)u;
}

static void centre_of(const navfield *f, long c, double xy[2])
{
    const long i = c % f->nx, j = c / f->nx;
    xy[0] = f->x0_m + ((double)i + 0.5) * f->cell_m;
    xy[1] = f->y0_m + ((double)j + 0.5) * f->cell_m;
}

static int passable(const navfield *f, long c)
{
    return f->clear_m[c] >= (float)f->p.clear_m;
}

/* Neighbour k of cell (i, j), or -1 off the grid or across a blocked
 * corner (a diagonal step between two blocked side cells). */
static long neighbour(const navfield *f, long i, long j, int k)
{
    const long a = i + nb_di[k], b = j + nb_dj[k];
    if (a < 0 || b < 0 || a >= f->nx || b >= f->ny)
        return -1;
    if (k >= 4 && (!passable(f, j * f->nx + a) || !passable(f, b * f->nx + i)))
        return -1;
    return b * f->nx + a;
}

/* ---- build ------------------------------------------------------------------------- */

static long index_floor(double u, long n)
{
    return u < 0.0 ? 0 : u >= (double)n ? n - 1 : (long)u;
}

/* Every cell's clearance, capped at cap_m: each obstacle lowers the cells
 * within its reach plus cap_m only, so the cost is the obstacles' area,
 * not cells times obstacles. */
static void clearance_fill(navfield *f, const rover_world_config *w, double cap_m)
{
    const long n = (long)f->nx * f->ny;
    long c, i, j;
    int k;
    for (c = 0; c < n; c++)
        f->clear_m[c] = (float)cap_m;
    for (k = 0; k < w->n_obst; k++) {
        const rover_obstacle *o = &w->obst[k];
        const double r = (o->kind == ROVER_OBST_CIRCLE ? o->r_m : hypot(o->hx_m, o->hy_m)) + cap_m;
        const double u0 = (o->cx_m - r - f->x0_m) / f->cell_m,
                     u1 = (o->cx_m + r - f->x0_m) / f->cell_m;
        const double v0 = (o->cy_m - r - f->y0_m) / f->cell_m,
                     v1 = (o->cy_m + r - f->y0_m) / f->cell_m;
        if (u1 < 0.0 || v1 < 0.0 || u0 >= (double)f->nx || v0 >= (double)f->ny)
            continue;
        for (j = index_floor(v0, f->ny); j <= index_floor(v1, f->ny); j++)
            for (i = index_floor(u0, f->nx); i <= index_floor(u1, f->nx); i++) {
                double xy[2], d;
                c = j * f->nx + i;
                centre_of(f, c, xy);
                d = rover_obstacle_distance(o, xy[0], xy[1]);
                if (d < (double)f->clear_m[c])
                    f->clear_m[c] = (float)d;
            }
    }
}

/* A step's weight: its length times 1 + pen_gain times the mean shortfall
 * of its ends' clearance below prefer_m (as a fraction of prefer_m). */
static float step_cost(const navfield *f, long a, long b, double len_m)
{
    const double sa = fmax(0.0, 1.0 - f->clear_m[a] / f->p.prefer_m);
    const double sb = fmax(0.0, 1.0 - f->clear_m[b] / f->p.prefer_m);
    return (float)(len_m * (1.0 + f->p.pen_gain * 0.5 * (sa + sb)));
}

/* Bellman's update of cell (i, j) from its neighbours; 1 if it fell. */
static int relax(navfield *f, long i, long j)
{
    const long c = j * f->nx + i;
    float best = f->way_m[c];
    int k;
    if (!passable(f, c))
        return 0;
    for (k = 0; k < 8; k++) {
        const long n = neighbour(f, i, j, k);
        float w;
        if (n < 0 || !(f->way_m[n] < best))
            continue;
        w = f->way_m[n] + step_cost(f, c, n, k >= 4 ? f->cell_m * sqrt(2.0) : f->cell_m);
        if (w < best)
            best = w;
    }
    if (best < f->way_m[c]) {
        f->way_m[c] = best;
        return 1;
    }
    return 0;
}

/* One pass in raster order `order` (bit 0: rows downward, bit 1: columns
 * leftward); 1 if any cell changed. */
static int relax_pass(navfield *f, int order)
{
    int changed = 0;
    long r, s;
    for (r = 0; r < f->ny; r++) {
        const long j = (order & 1) ? f->ny - 1 - r : r;
        for (s = 0; s < f->nx; s++)
            changed |= relax(f, (order & 2) ? f->nx - 1 - s : s, j);
    }
    return changed;
}

/* The grid over w's extent: cells of cell_min_m, grown while there would
 * be more than NAVFIELD_MAX_CELLS. 0, or -1 when even the coarsest fails. */
static int grid_fit(navfield *f, const rover_world_config *w)
{
    const double wx = w->x_max_m - w->x_min_m, wy = w->y_max_m - w->y_min_m;
    double cell = fmax(f->p.cell_min_m, sqrt(wx * wy / (double)NAVFIELD_MAX_CELLS));
    int k;
    if (!(isfinite(wx) && isfinite(wy) && wx > 0.0 && wy > 0.0))
        return -1;
    for (k = 0; k <= CELL_GROW_MAX; k++, cell *= CELL_GROW) {
        const double nx = ceil(wx / cell), ny = ceil(wy / cell);
        if (nx * ny <= (double)NAVFIELD_MAX_CELLS) {
            f->nx = (int)nx;
            f->ny = (int)ny;
            f->cell_m = cell;
            f->x0_m = w->x_min_m;
            f->y0_m = w->y_min_m;
            return 0;
        }
    }
    return -1;
}

int navfield_build(navfield *f, const navfield_params *p, const rover_world_config *w)
{
    if (!f || !w || navfield_params_validate(p) != NAVFIELD_OK)
        return NAVFIELD_ERR_ARG;
    f->p = *p;
    if (grid_fit(f, w) != 0 || !vec2_pose_finite(&w->team_origin) || !isfinite(w->goal_m[0]) ||
        !isfinite(w->goal_m[1]))
        return NAVFIELD_ERR_ARG;
    f->frame = w->team_origin;
    clearance_fill(f, w, fmax(p->prefer_m, p->los_m) + f->cell_m);
    f->goal_cell = cell_of(f, w->goal_m[0], w->goal_m[1]);
    return navfield_relax(f, p->clear_m);
}

int navfield_relax(navfield *f, double clear_m)
{
    const long n = f ? (long)f->nx * f->ny : 0;
    long c;
    int pass, max_passes;
    if (!f || !(clear_m > 0.0) || !(clear_m <= f->p.prefer_m) || 0.5 * clear_m > f->p.los_m)
        return NAVFIELD_ERR_ARG;
    f->p.clear_m = clear_m;
    for (c = 0; c < n; c++)
        f->way_m[c] = INFINITY;
    if (f->goal_cell < 0 || !passable(f, f->goal_cell))
        return NAVFIELD_ERR_GOAL;
    f->way_m[f->goal_cell] = 0.0f;
    /* a pass carries the values along a shortest way up to its next turn
     * against the pass's order; a world whose ways turn more often than
     * this bound (a maze) is refused, not flown on a field not settled */
    max_passes = 4 * (f->nx + f->ny) + 4;
    for (pass = 0; pass < max_passes; pass++)
        if (!relax_pass(f, pass & 3))
            return NAVFIELD_OK; /* no cell fell: Bellman's equation holds everywhere */
    return NAVFIELD_ERR_PASSES;
}

double navfield_way_m(const navfield *f, double x_m, double y_m)
{
    const long c = f ? cell_of(f, x_m, y_m) : -1;
    return c < 0 ? INFINITY : (double)f->way_m[c];
}

/* ---- waypoint ---------------------------------------------------------------------- */

static void to_world(const navfield *f, const double p[2], double w[2])
{
    vec2_rotate(w, p[0], p[1], f->frame.theta_rad);
    w[0] += f->frame.x_m;
    w[1] += f->frame.y_m;
}

static void to_frame(const navfield *f, const double w[2], double p[2])
{
    vec2_rotate(p, w[0] - f->frame.x_m, w[1] - f->frame.y_m, -f->frame.theta_rad);
}

static double clear_at(const navfield *f, const double xy[2])
{
    const long c = cell_of(f, xy[0], xy[1]);
    return c < 0 ? -INFINITY : (double)f->clear_m[c];
}

/* 1 if the straight way a -> b (world frame, both on the grid) keeps
 * need_m from every obstacle, sampled every half cell (at most four
 * samples per cell of the grid's diagonal). */
static int clear_along(const navfield *f, const double a[2], const double b[2], double need_m)
{
    const double len = hypot(b[0] - a[0], b[1] - a[1]);
    const long n = (long)ceil(len / (0.5 * f->cell_m));
    long s;
    if (clear_at(f, a) == -INFINITY || clear_at(f, b) == -INFINITY)
        return 0;
    for (s = 1; s <= n; s++) {
        const double t = (double)s / (double)n;
        const double xy[2] = { a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]) };
        if (clear_at(f, xy) < need_m)
            return 0;
    }
    return 1;
}

/* Seen straight: the way a -> b keeps los_m from every obstacle, or as
 * much as its ends keep (a robot beside a wall, a slot near one), but
 * never less than half of it. */
static int seen_straight(const navfield *f, const double a[2], const double b[2])
{
    const double ca = clear_at(f, a), cb = clear_at(f, b);
    return clear_along(f, a, b, fmax(0.5 * f->p.los_m, fmin(f->p.los_m, fmin(ca, cb))));
}

/* The cell to descend from: a's own if it is joined to the goal, else the
 * one within START_RING_M that is (least way plus the straight distance to
 * it) and that a reaches straight without coming nearer an obstacle than
 * it is or than half clear_m: a point beside a wall does not take a cell
 * on the wall's far side, nearer the goal as that may be; -1 when there
 * is none. */
static long start_cell(const navfield *f, const double a[2])
{
    const long c = cell_of(f, a[0], a[1]);
    const long ring = (long)ceil(START_RING_M / f->cell_m);
    const double need = fmin(clear_at(f, a), 0.5 * f->p.clear_m);
    long best = -1, i, j, i0, j0;
    double best_v = INFINITY;
    if (c < 0 || isfinite(f->way_m[c]))
        return c;
    i0 = c % f->nx;
    j0 = c / f->nx;
    for (j = j0 - ring; j <= j0 + ring; j++)
        for (i = i0 - ring; i <= i0 + ring; i++) {
            double xy[2], v;
            if (i < 0 || j < 0 || i >= f->nx || j >= f->ny || !isfinite(f->way_m[j * f->nx + i]))
                continue;
            centre_of(f, j * f->nx + i, xy);
            v = (double)f->way_m[j * f->nx + i] + hypot(xy[0] - a[0], xy[1] - a[1]);
            if (v < best_v && clear_along(f, a, xy, need)) {
                best_v = v;
                best = j * f->nx + i;
            }
        }
    return best;
}

/* The neighbour of c with the least way below c's (a step the field was
 * built with), or -1 at the goal. */
static long descend(const navfield *f, long c)
{
    const long i = c % f->nx, j = c / f->nx;
    long best = -1;
    float best_v = f->way_m[c];
    int k;
    for (k = 0; k < 8; k++) {
        const long n = neighbour(f, i, j, k);
        if (n >= 0 && f->way_m[n] < best_v) {
            best_v = f->way_m[n];
            best = n;
        }
    }
    return best;
}

double navfield_clearance_m(const navfield *f, const double at_m[2])
{
    double a[2];
    if (!f || !at_m || !isfinite(at_m[0]) || !isfinite(at_m[1]))
        return -INFINITY;
    to_world(f, at_m, a);
    return clear_at(f, a) - 0.5 * sqrt(2.0) * f->cell_m;
}

/* The tightest of the bounds the cells round c give at world point a:
 * the distance to the obstacles is 1-Lipschitz, so no obstacle is nearer
 * a than clear(q) - |a q| for any cell centre q. Exact beside a straight
 * wall along the grid; continuous as a moves, unlike one cell's bound. */
static double clearance_bound(const navfield *f, long c, const double a[2])
{
    const long i = c % f->nx, j = c / f->nx;
    double best = -INFINITY, q[2];
    long di, dj;
    for (dj = -1; dj <= 1; dj++)
        for (di = -1; di <= 1; di++) {
            long n;
            if (i + di < 0 || i + di >= f->nx || j + dj < 0 || j + dj >= f->ny)
                continue;
            n = (j + dj) * f->nx + i + di;
            centre_of(f, n, q);
            best = fmax(best, (double)f->clear_m[n] - hypot(a[0] - q[0], a[1] - q[1]));
        }
    return best;
}

/* Central difference of the cells' clearance across cell c along
 * (di, dj), per metre; one-sided at the grid's edge. */
static double clearance_diff(const navfield *f, long c, int di, int dj)
{
    const long i = c % f->nx, j = c / f->nx;
    const long i0 = i - di >= 0 ? i - di : i, i1 = i + di < f->nx ? i + di : i;
    const long j0 = j - dj >= 0 ? j - dj : j, j1 = j + dj < f->ny ? j + dj : j;
    const long n = (i1 - i0) + (j1 - j0);
    if (n == 0)
        return 0.0;
    return ((double)f->clear_m[j1 * f->nx + i1] - (double)f->clear_m[j0 * f->nx + i0]) /
           ((double)n * f->cell_m);
}

double navfield_clearance_slope_m(const navfield *f, const double at_m[2], double slope[2])
{
    double a[2], gw[2];
    long c;
    if (!slope)
        return -INFINITY;
    slope[0] = slope[1] = 0.0;
    if (!f || !at_m || !isfinite(at_m[0]) || !isfinite(at_m[1]))
        return -INFINITY;
    to_world(f, at_m, a);
    c = cell_of(f, a[0], a[1]);
    if (c < 0)
        return -INFINITY;
    gw[0] = clearance_diff(f, c, 1, 0);
    gw[1] = clearance_diff(f, c, 0, 1);
    vec2_rotate(slope, gw[0], gw[1], -f->frame.theta_rad);
    return clearance_bound(f, c, a);
}

double navfield_way_from(const navfield *f, const double from_m[2])
{
    double a[2], p[2];
    long c;
    if (!f || !from_m || !isfinite(from_m[0]) || !isfinite(from_m[1]))
        return INFINITY;
    to_world(f, from_m, a);
    c = start_cell(f, a);
    if (c < 0)
        return INFINITY;
    centre_of(f, c, p);
    return (double)f->way_m[c] + hypot(p[0] - a[0], p[1] - a[1]);
}

int navfield_waypoint(const navfield *f, const double from_m[2], const double goal_m[2],
                      double out_m[2])
{
    double a[2], g[2], p[2], q[2], best[2], walked;
    long c, n;
    int steps, max_steps;
    if (!f || !from_m || !goal_m || !out_m || !isfinite(from_m[0]) || !isfinite(from_m[1]) ||
        !isfinite(goal_m[0]) || !isfinite(goal_m[1]))
        return NAVFIELD_ERR_ARG;
    out_m[0] = goal_m[0];
    out_m[1] = goal_m[1];
    to_world(f, from_m, a);
    to_world(f, goal_m, g);
    if (seen_straight(f, a, g))
        return NAVFIELD_DIRECT;
    c = start_cell(f, a);
    if (c < 0)
        return NAVFIELD_NO_WAY;
    centre_of(f, c, p);
    best[0] = p[0];
    best[1] = p[1];
    walked = hypot(p[0] - a[0], p[1] - a[1]);
    /* every step is at least a cell long */
    max_steps = (int)ceil(f->p.look_m / f->cell_m) + 1;
    for (steps = 0; steps < max_steps && (n = descend(f, c)) >= 0; steps++) {
        centre_of(f, n, q);
        walked += hypot(q[0] - p[0], q[1] - p[1]);
        if (walked > f->p.look_m)
            break;
        c = n;
        p[0] = q[0];
        p[1] = q[1];
        if (!seen_straight(f, a, p) && walked >= f->p.min_ahead_m)
            break;
        best[0] = p[0];
        best[1] = p[1];
    }
    to_frame(f, best, out_m);
    return NAVFIELD_DESCENT;
}

/* ---- passage width ----------------------------------------------------------------- */

/* How far xy lies inside the grid's outer edges (negative outside). */
static double inside_m(const navfield *f, const double xy[2])
{
    const double x = xy[0] - f->x0_m, y = xy[1] - f->y0_m;
    return fmin(fmin(x, (double)f->nx * f->cell_m - x), fmin(y, (double)f->ny * f->cell_m - y));
}

/* From world point p along the unit direction u: the distance to the
 * obstacle that the first sample whose cell touches one (its centre
 * within 0.71 cell of it: by a side or a corner) finds (the sample's
 * distance plus its cell's clearance), or to the grid's edge, sampled
 * every half cell up to side_m; INFINITY when there is none. Touching,
 * not "its centre on one": a wall one cell thick lies half a cell from the centres
 * beside it, and a line passing through those cells read it open or not
 * as the float rounding of that half cell went (a gap in a thin wall
 * whose two ends stand a cell apart across the way read open, and a team
 * of 6 in triangle crossed a 1.9 m gap without reshaping: mixed world
 * 315). Samples that cannot be that are skipped, with the same answer:
 * the clearance is a distance (it changes by no more than the way moved)
 * stored at cell centres (within 0.71 cell of a sample), so every sample
 * within c - 2.5 cells of one whose cell reads c, and as far inside the
 * grid, reads more than 0.71 cell. */
#define NAVFIELD_TOUCH_CELLS 0.71
static double side_free_m(const navfield *f, const double p[2], const double u[2], double side_m)
{
    const double step = 0.5 * f->cell_m, hit = NAVFIELD_TOUCH_CELLS * f->cell_m;
    const long n = (long)ceil(side_m / step);
    long s = 1;
    while (s <= n) {
        const double d = (double)s * step;
        const double xy[2] = { p[0] + d * u[0], p[1] + d * u[1] };
        const double c = clear_at(f, xy);
        double skip;
        if (c < hit)
            return d + fmax(c, 0.0); /* where the obstacle is, not the sample */
        skip = floor((fmin(c, inside_m(f, xy)) - 2.5 * f->cell_m) / step);
        s += skip > 1.0 ? (long)fmin(skip, (double)n) : 1;
    }
    return INFINITY;
}

/* left + right along the unit direction u from p, times cos_a: the width
 * of the gap that line spans, projected across the way (u at angle a from
 * the way's normal); INFINITY when a side is open. */
static double span_m(const navfield *f, const double p[2], const double u[2], double cos_a,
                     double side_m)
{
    const double v[2] = { -u[0], -u[1] };
    const double left = side_free_m(f, p, u, side_m);
    if (!isfinite(left))
        return INFINITY;
    return (left + side_free_m(f, p, v, side_m)) * cos_a;
}

/* The free width across the way at cell c heading for cell n: to the
 * first obstacle on either side, along the way's normal and along lines
 * tilted from it by up to NAVFIELD_ACROSS_TILT_RAD, each span projected
 * on the normal; the least of them, INFINITY when every line has a side
 * open. Why tilted lines: the way is a chain of 8-neighbour steps, so its
 * normal is known only to 45 deg, and a gap in a thin wall crossed aslant
 * is spanned only by the line along the wall; across the way's normal a
 * line through the gap passes beside the wall's ends and reads open.
 * Why the projection: a team of width W crossing a gap's line at angle a
 * needs W / cos a of it. A corridor reads its width along every line, so
 * tilting never narrows a passage below what the team meets. */
static double across_m(const navfield *f, long c, long n, double side_m)
{
    /* cos and sin of NAVFIELD_ACROSS_TILT_RAD / NAVFIELD_ACROSS_TILTS */
    const double ct = cos(NAVFIELD_ACROSS_TILT_RAD / NAVFIELD_ACROSS_TILTS),
                 st = sin(NAVFIELD_ACROSS_TILT_RAD / NAVFIELD_ACROSS_TILTS);
    double p[2], q[2], d, u[2], a[2], b[2], w, ca = 1.0, sa = 0.0;
    int k;
    centre_of(f, c, p);
    centre_of(f, n, q);
    d = hypot(q[0] - p[0], q[1] - p[1]);
    u[0] = -(q[1] - p[1]) / d; /* left of the way */
    u[1] = (q[0] - p[0]) / d;
    w = span_m(f, p, u, 1.0, side_m);
    for (k = 1; k <= NAVFIELD_ACROSS_TILTS; k++) {
        const double c1 = ca * ct - sa * st; /* angle k tilt / TILTS */
        sa = sa * ct + ca * st;
        ca = c1;
        a[0] = ca * u[0] - sa * u[1]; /* u turned by +angle, and by -angle */
        a[1] = sa * u[0] + ca * u[1];
        b[0] = ca * u[0] + sa * u[1];
        b[1] = -sa * u[0] + ca * u[1];
        w = fmin(w, fmin(span_m(f, p, a, ca, side_m), span_m(f, p, b, ca, side_m)));
    }
    return w;
}

int navfield_passage_ahead(const navfield *f, const double from_m[2],
                           const navfield_passage_query *q, navfield_passage *out)
{
    double a[2], p[2], r[2], walked = 0.0;
    long c, n;
    int steps, max_steps;
    if (!f || !from_m || !q || !out || !isfinite(from_m[0]) || !isfinite(from_m[1]) ||
        !(q->ahead_m >= 0.0) || !isfinite(q->ahead_m) || !(q->side_m > 0.0) ||
        !isfinite(q->side_m) || isnan(q->below_m) || !(q->beyond_m >= 0.0) ||
        !isfinite(q->beyond_m))
        return NAVFIELD_ERR_ARG;
    out->narrowest_m = INFINITY;
    out->below_len_m = 0.0;
    to_world(f, from_m, a);
    c = start_cell(f, a);
    if (c < 0)
        return NAVFIELD_OK;
    centre_of(f, c, p);
    /* a width at every cell (a wall a cell thick is not stepped over);
     * every step is at least a cell long */
    max_steps = (int)ceil((q->ahead_m + q->beyond_m) / f->cell_m) + 1;
    for (steps = 0;
         steps < max_steps && walked <= q->ahead_m + q->beyond_m && (n = descend(f, c)) >= 0;
         steps++) {
        const double w = across_m(f, c, n, q->side_m);
        double step;
        centre_of(f, n, r);
        step = hypot(r[0] - p[0], r[1] - p[1]);
        if (walked <= q->ahead_m)
            out->narrowest_m = fmin(out->narrowest_m, w);
        if (w < q->below_m)
            out->below_len_m += step;
        walked += step;
        c = n;
        p[0] = r[0];
        p[1] = r[1];
    }
    return NAVFIELD_OK;
}

int navfield_polyline(const navfield *f, const double from_m[2], const double goal_m[2],
                      double (*way)[2], int cap)
{
    int n = 0, rc = NAVFIELD_DESCENT;
    if (!f || !from_m || !goal_m || !way || cap < 2 || !isfinite(from_m[0]) ||
        !isfinite(from_m[1]) || !isfinite(goal_m[0]) || !isfinite(goal_m[1]))
        return 0;
    way[n][0] = from_m[0];
    way[n][1] = from_m[1];
    n++;
    /* bounded by cap; a point that does not move on ends it */
    while (rc == NAVFIELD_DESCENT && n < cap - 1) {
        rc = navfield_waypoint(f, way[n - 1], goal_m, way[n]);
        if (rc != NAVFIELD_DESCENT || (way[n][0] == way[n - 1][0] && way[n][1] == way[n - 1][1]))
            break;
        n++;
    }
    way[n][0] = goal_m[0];
    way[n][1] = goal_m[1];
    return n + 1;
}

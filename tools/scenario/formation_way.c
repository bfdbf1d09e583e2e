/* formation_way: what the world asks of the team, measured on its map for
 * the report and the criteria (docs/formation.md, "Scenario"): the length
 * of the shortest way for the body and the time limit it gives, the widest
 * way's bottleneck (passage_width_m), and the cross-section of all the
 * ways side by side (cut_width_m). Each is computed on the way field of
 * navfield.h (docs/method/formation.md §14) without its weights.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "formation_scen.h"
#include "navfield.h"

#define FREE_SIDE_M 5.0 /* a way this clear on both sides is open */

/* ---- the way's length and the time limit ---------------------------------------- */

#define WAY_CLEAR_M 0.32 /* the body's radius about C (WORLDGEN_BODY_RADIUS_M) */

/* The way field of w for a disc of radius clear_m about C, lengths
 * unweighted and clearances kept up to FREE_SIDE_M (navfield.h); NULL
 * when it cannot be built or the goal is nearer an obstacle than clear_m.
 * The caller frees it. */
static navfield *way_field(const rover_world_config *w, double clear_m)
{
    navfield_params p;
    navfield *f = malloc(sizeof *f);
    navfield_params_default(&p);
    p.clear_m = clear_m;
    p.los_m = p.prefer_m = FREE_SIDE_M; /* the bisection's clearances up to it */
    p.pen_gain = 0.0;
    if (f && navfield_build(f, &p, w) == NAVFIELD_OK)
        return f;
    free(f);
    return NULL;
}

/* The way's length from the team's start (the mean of the start poses);
 * NAN when there is none. */
static double way_from_start(const navfield *f, const rover_world_config *w)
{
    double sx = 0.0, sy = 0.0, len;
    int k;
    if (!f || w->n_robots < 1)
        return NAN;
    for (k = 0; k < w->n_robots; k++) {
        sx += w->start_c[k].x_m;
        sy += w->start_c[k].y_m;
    }
    len = navfield_way_m(f, sx / w->n_robots, sy / w->n_robots);
    return isfinite(len) ? len : NAN;
}

double fm_way_length_m(const rover_world_config *w)
{
    navfield *f = way_field(w, WAY_CLEAR_M);
    const double len = way_from_start(f, w);
    free(f);
    return len;
}

double fm_time_limit_s(double way_m)
{
    return isfinite(way_m) ? FM_TIME_BASE_S + way_m / FM_TIME_SPEED_MPS : FM_TIME_DEFAULT_S;
}

/* The narrowest width the team must drive through: the widest way's
 * bottleneck, twice the largest clearance a disc about C keeps from every
 * obstacle on some way from the start to the goal (bisection on the way
 * field's clear_m, navfield_relax, to PASSAGE_TOL_M; 2 FREE_SIDE_M when that clearance
 * reaches FREE_SIDE_M; 0 when not even the body's finds a way). A team
 * wider than this cannot reach the goal without narrowing; one that is
 * not can go round every narrow gap (posts it splits round, a pocket it
 * passes), so the criterion asks for a change only then. Measured along
 * the straight start-goal line instead, a pair of posts beside the line
 * asked for a change that no way needs (generated clutter worlds). */
#define PASSAGE_TOL_M 0.02
double fm_passage_width_m(const rover_world_config *w)
{
    double lo = WAY_CLEAR_M, hi = FREE_SIDE_M, width;
    navfield *f = way_field(w, lo);
    if (!isfinite(way_from_start(f, w)))
        width = 0.0;
    else if (navfield_relax(f, hi) == NAVFIELD_OK && isfinite(way_from_start(f, w)))
        width = 2.0 * FREE_SIDE_M;
    else {
        while (hi - lo > PASSAGE_TOL_M) {
            const double mid = 0.5 * (lo + hi);
            if (navfield_relax(f, mid) == NAVFIELD_OK && isfinite(way_from_start(f, w)))
                lo = mid;
            else
                hi = mid;
        }
        width = 2.0 * lo;
    }
    free(f);
    return width;
}

/* ---- the cross-section of all the ways together --------------------------------- */

/* Max flow of unit-capacity cells (each cell the body's disc passes carries
 * one way; a cell's way may step to any of its 8 neighbours, none across a
 * blocked corner) from the cells near the start to those near the goal, by
 * shortest augmenting paths (Edmonds-Karp) in the residual graph of the
 * cells split in two: node 2c enters cell c, node 2c + 1 leaves it. By
 * Menger's theorem the flow is the fewest cells that cut every way: the
 * cross-section of all the ways side by side, in cells. */
typedef struct {
    const navfield *f;
    long n;               /* cells */
    unsigned char *role;  /* 0 passable, 1 source, 2 sink, 3 blocked */
    unsigned char *used;  /* the cell carries a way */
    signed char *edge;    /* [c * 8 + k]: ways from c to its neighbour k */
    long *parent, *queue; /* [2n] */
} cut_work;

static const int cut_di[8] = { 1, -1, 0, 0, 1, 1, -1, -1 };
static const int cut_dj[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };

/* The direction back: (1, 0) <-> (-1, 0), (0, 1) <-> (0, -1),
 * (1, 1) <-> (-1, -1), (1, -1) <-> (-1, 1). */
static int cut_back(int k)
{
    return k < 4 ? k ^ 1 : 11 - k;
}

/* Neighbour k of c for a way (both passable, no blocked corner), or -1. */
static long cut_nb(const cut_work *w, long c, int k)
{
    const long nx = w->f->nx, i = c % nx + cut_di[k], j = c / nx + cut_dj[k];
    if (i < 0 || j < 0 || i >= nx || j >= w->f->ny || w->role[j * nx + i] == 3)
        return -1;
    if (k >= 4 && (w->role[(c / nx) * nx + i] == 3 || w->role[j * nx + c % nx] == 3))
        return -1;
    return j * nx + i;
}

static void cut_visit(cut_work *w, long from, long to, long *tail)
{
    if (w->parent[to] == -2) {
        w->parent[to] = from;
        w->queue[(*tail)++] = to;
    }
}

/* One augmenting path, applied; 0 when there is none. */
static int cut_augment(cut_work *w)
{
    long head = 0, tail = 0, u, c, end = -1;
    int k;
    for (u = 0; u < 2 * w->n; u++)
        w->parent[u] = -2;
    for (c = 0; c < w->n; c++)
        if (w->role[c] == 1)
            cut_visit(w, -1, 2 * c, &tail);
    while (head < tail && end < 0) {
        u = w->queue[head++];
        c = u / 2;
        if (u % 2 == 0) { /* entering c: through it, or back along a way into it */
            if (!w->used[c])
                cut_visit(w, u, u + 1, &tail);
            for (k = 0; k < 8; k++) {
                const long a = cut_nb(w, c, k);
                if (a >= 0 && w->edge[a * 8 + cut_back(k)] > 0)
                    cut_visit(w, u, 2 * a + 1, &tail);
            }
        } else if (w->role[c] == 2) {
            end = u;
        } else { /* leaving c: to a neighbour, or back out of c's own way */
            if (w->used[c])
                cut_visit(w, u, u - 1, &tail);
            for (k = 0; k < 8; k++) {
                const long a = cut_nb(w, c, k);
                if (a >= 0)
                    cut_visit(w, u, 2 * a, &tail);
            }
        }
    }
    for (u = end; u >= 0 && w->parent[u] >= 0; u = w->parent[u]) {
        const long p = w->parent[u], pc = p / 2, uc = u / 2;
        if (pc == uc)
            w->used[uc] = (unsigned char)(u > p);
        else
            for (k = 0; k < 8; k++) {
                if (p % 2 == 1 && cut_nb(w, pc, k) == uc)
                    w->edge[pc * 8 + k]++;
                if (p % 2 == 0 && cut_nb(w, uc, k) == pc)
                    w->edge[uc * 8 + k]--;
            }
    }
    return end >= 0;
}

/* The cross-section of all the ways together, side by side (a team that
 * splits round an obstacle and joins again needs that, not one way as
 * wide as itself): the max flow above, from the cells where the robots
 * stand at the start (within CUT_START_M of each) to those within half the
 * team's width of the goal by the way (a disc about the start, straight
 * or by the way, reached through or past a gap near it and let the flow
 * start beyond the gap), times a
 * cell's side, plus the body's 2 x WAY_CLEAR_M (a gap is that much wider
 * than its passable middle). Counted only up to what the team's width
 * needs; a cut across the grid obliquely counts up to sqrt(2) times its
 * length (cells, not metres). INFINITY when the start and the goal are
 * nearer than the team is wide, 0 when there is no way. */
#define CUT_START_M 0.5 /* a robot's start: the cells this near its axle */

/* Cell centre (i, j) of f, world frame. */
static void cell_centre(const navfield *f, long i, long j, double *x, double *y)
{
    *x = f->x0_m + ((double)i + 0.5) * f->cell_m;
    *y = f->y0_m + ((double)j + 0.5) * f->cell_m;
}

/* start[c] = 1 for every cell within CUT_START_M of a robot's start: each
 * robot marks the cells of its own square about it, O(robots), where
 * asking every robot of every cell was O(cells x robots) (a fleet's
 * world grows with the fleet); the same test, the same cells. */
static void mark_starts(const navfield *f, const rover_world_config *w, unsigned char *start)
{
    const long reach = (long)ceil(CUT_START_M / f->cell_m) + 1;
    int k;
    for (k = 0; k < w->n_robots; k++) {
        const pose2 *s = &w->start_c[k];
        const long ci = (long)floor((s->x_m - f->x0_m) / f->cell_m);
        const long cj = (long)floor((s->y_m - f->y0_m) / f->cell_m);
        long i, j;
        for (j = cj - reach; j <= cj + reach; j++)
            for (i = ci - reach; i <= ci + reach; i++) {
                double x, y;
                if (i < 0 || j < 0 || i >= f->nx || j >= f->ny)
                    continue;
                cell_centre(f, i, j, &x, &y);
                if (hypot(x - s->x_m, y - s->y_m) <= CUT_START_M)
                    start[j * f->nx + i] = 1;
            }
    }
}

double fm_cut_width_m(const rover_world_config *w, double team_width_m)
{
    navfield *f = way_field(w, WAY_CLEAR_M);
    const double way = way_from_start(f, w), r = 0.5 * team_width_m;
    double width = 0.0;
    cut_work cw;
    long c, flow = 0, cap;
    if (!isfinite(way) || way <= team_width_m) {
        free(f);
        return isfinite(way) ? INFINITY : 0.0;
    }
    memset(&cw, 0, sizeof cw);
    cw.f = f;
    cw.n = (long)f->nx * f->ny;
    cw.role = malloc((size_t)cw.n);
    cw.used = calloc((size_t)cw.n, 1);
    cw.edge = calloc((size_t)cw.n * 8, 1);
    cw.parent = malloc(sizeof *cw.parent * (size_t)(2 * cw.n));
    cw.queue = malloc(sizeof *cw.queue * (size_t)(2 * cw.n));
    if (cw.role && cw.used && cw.edge && cw.parent && cw.queue) {
        cap = (long)ceil(team_width_m / f->cell_m) + 1;
        mark_starts(f, w, cw.used); /* cw.used is the starts' marks until the flow */
        for (c = 0; c < cw.n; c++)
            cw.role[c] = !isfinite(f->way_m[c]) ? 3 : cw.used[c] ? 1 : f->way_m[c] <= r ? 2 : 0;
        memset(cw.used, 0, (size_t)cw.n);
        while (flow < cap && cut_augment(&cw))
            flow++;
        width = (double)flow * f->cell_m + 2.0 * WAY_CLEAR_M;
    }
    free(cw.role);
    free(cw.used);
    free(cw.edge);
    free(cw.parent);
    free(cw.queue);
    free(f);
    return width;
}

/* sonar: 2.5-D ray casting (boxes, cylinders, walls) with a uniform-grid
 * broad phase, and the Pioneer 2 DX front-ring transducer model with cone,
 * nearest echo, range clamp, specular loss and seeded Gaussian noise
 * (docs/method/sonar.md; the 8-sonar grouping used by the avoid behaviour of
 * section 4 is in behaviour.c).
 */
#include "sonar.h"

#include <math.h>
#include <stddef.h>

#define DEG (VEC2_PI / 180.0)
#define SONAR_EPS 1e-12
#define SONAR_GRID_CELLS (SONAR_GRID_MAX * SONAR_GRID_MAX)

/* cell_start and refs are uint16 */
typedef char sonar_prims_fit_uint16[SONAR_MAX_PRIMS < 65536 ? 1 : -1];

/* Pioneer 2 DX front ring (ARIA p2dx parameters, mm -> m), relative to the
 * centre of rotation (the axle centre C), in table order -90 .. 90 deg. */
const sonar_transducer sonar_p2dx_front[SONAR_N] = {
    { 0.069, -0.136, -90.0 * DEG }, { 0.114, -0.119, -50.0 * DEG }, { 0.148, -0.078, -30.0 * DEG },
    { 0.166, -0.027, -10.0 * DEG }, { 0.166, 0.027, 10.0 * DEG },   { 0.148, 0.078, 30.0 * DEG },
    { 0.114, 0.119, 50.0 * DEG },   { 0.069, 0.136, 90.0 * DEG },
};

/* ARIA fires sonar 0 (left, +90) .. 7 (right, -90). */
const int sonar_p2dx_fire_order[SONAR_N] = { 7, 6, 5, 4, 3, 2, 1, 0 };

/* ---- world ------------------------------------------------------------- */

void sonar_world_init(sonar_world *w)
{
    w->n = 0;
    w->built = 0;
    w->nx = w->ny = 0;
    w->gx0 = w->gy0 = 0.0;
    w->cell_m = 1.0;
}

static int z_ok(double z_min, double z_max)
{
    return !isnan(z_min) && !isnan(z_max) && z_min <= z_max;
}

static sonar_prim *prim_new(sonar_world *w, int kind, double z_min, double z_max)
{
    sonar_prim *p;
    if (w->n >= SONAR_MAX_PRIMS || !z_ok(z_min, z_max))
        return NULL;
    p = &w->p[w->n];
    p->kind = kind;
    p->z_min = z_min;
    p->z_max = z_max;
    p->ax = p->ay = p->bx = p->by = p->r = 0.0;
    p->c = 1.0;
    p->s = 0.0;
    w->built = 0;
    return p;
}

static void prim_bounds(sonar_prim *p, double x0, double y0, double x1, double y1)
{
    p->x0 = x0;
    p->y0 = y0;
    p->x1 = x1;
    p->y1 = y1;
    p->bcx = 0.5 * (x0 + x1);
    p->bcy = 0.5 * (y0 + y1);
    p->br = 0.5 * hypot(x1 - x0, y1 - y0);
}

int sonar_world_add_box(sonar_world *w, double cx, double cy, double half_x, double half_y,
                        double angle_rad, double z_min, double z_max)
{
    sonar_prim *p;
    double ex, ey;
    if (!vec2_finite3(cx, cy, angle_rad) || !isfinite(half_x) || !isfinite(half_y) ||
        !(half_x > 0.0) || !(half_y > 0.0))
        return SONAR_ERR_ARG;
    p = prim_new(w, SONAR_PRIM_BOX, z_min, z_max);
    if (!p)
        return SONAR_ERR_ARG;
    p->ax = cx;
    p->ay = cy;
    p->bx = half_x;
    p->by = half_y;
    p->c = cos(angle_rad);
    p->s = sin(angle_rad);
    ex = fabs(p->c) * half_x + fabs(p->s) * half_y;
    ey = fabs(p->s) * half_x + fabs(p->c) * half_y;
    prim_bounds(p, cx - ex, cy - ey, cx + ex, cy + ey);
    return w->n++;
}

int sonar_world_add_aabb(sonar_world *w, double x0, double y0, double x1, double y1, double z_min,
                         double z_max)
{
    return sonar_world_add_box(w, 0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * fabs(x1 - x0),
                               0.5 * fabs(y1 - y0), 0.0, z_min, z_max);
}

int sonar_world_add_circle(sonar_world *w, double cx, double cy, double r, double z_min,
                           double z_max)
{
    sonar_prim *p;
    if (!vec2_finite3(cx, cy, r) || !(r > 0.0))
        return SONAR_ERR_ARG;
    p = prim_new(w, SONAR_PRIM_CIRCLE, z_min, z_max);
    if (!p)
        return SONAR_ERR_ARG;
    p->ax = cx;
    p->ay = cy;
    p->r = r;
    prim_bounds(p, cx - r, cy - r, cx + r, cy + r);
    return w->n++;
}

int sonar_world_add_segment(sonar_world *w, double ax, double ay, double bx, double by,
                            double z_min, double z_max)
{
    sonar_prim *p;
    if (!vec2_finite3(ax, ay, bx) || !isfinite(by) || hypot(bx - ax, by - ay) <= 0.0)
        return SONAR_ERR_ARG;
    p = prim_new(w, SONAR_PRIM_SEGMENT, z_min, z_max);
    if (!p)
        return SONAR_ERR_ARG;
    p->ax = ax;
    p->ay = ay;
    p->bx = bx;
    p->by = by;
    prim_bounds(p, fmin(ax, bx), fmin(ay, by), fmax(ax, bx), fmax(ay, by));
    return w->n++;
}

static int cell_clamp(double v, int n)
{
    int i = (int)floor(v);
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

/* Cell index range covered by prim i's bounding box. */
static void prim_cells(const sonar_world *w, const sonar_prim *p, int *i0, int *j0, int *i1,
                       int *j1)
{
    *i0 = cell_clamp((p->x0 - w->gx0) / w->cell_m, w->nx);
    *i1 = cell_clamp((p->x1 - w->gx0) / w->cell_m, w->nx);
    *j0 = cell_clamp((p->y0 - w->gy0) / w->cell_m, w->ny);
    *j1 = cell_clamp((p->y1 - w->gy0) / w->cell_m, w->ny);
}

static long grid_count(sonar_world *w)
{
    long total = 0;
    int k, i, j, i0, j0, i1, j1;
    for (k = 0; k <= w->nx * w->ny; k++)
        w->cell_start[k] = 0;
    for (k = 0; k < w->n; k++) {
        prim_cells(w, &w->p[k], &i0, &j0, &i1, &j1);
        total += (long)(i1 - i0 + 1) * (j1 - j0 + 1);
        if (total > SONAR_GRID_MAX_REFS)
            return total;
        for (j = j0; j <= j1; j++)
            for (i = i0; i <= i1; i++)
                w->cell_start[j * w->nx + i + 1]++;
    }
    return total;
}

int sonar_world_build(sonar_world *w)
{
    double x0, y0, x1, y1, span;
    int k, i, j, i0, j0, i1, j1, attempt;
    uint16_t fill[SONAR_GRID_MAX * SONAR_GRID_MAX];
    w->built = 0;
    if (w->n == 0)
        return 0;
    x0 = w->p[0].x0;
    y0 = w->p[0].y0;
    x1 = w->p[0].x1;
    y1 = w->p[0].y1;
    for (k = 1; k < w->n; k++) {
        x0 = fmin(x0, w->p[k].x0);
        y0 = fmin(y0, w->p[k].y0);
        x1 = fmax(x1, w->p[k].x1);
        y1 = fmax(y1, w->p[k].y1);
    }
    span = fmax(x1 - x0, y1 - y0);
    w->gx0 = x0;
    w->gy0 = y0;
    /* Cells about 4 prims' worth of area (1 in a map of many boxes, where a
     * ray crosses many cells and each tested box costs), no more than
     * GRID_CELLS of them (the grid may be long and thin: a fleet spread
     * along a row gets cells as fine as a square map of the same area);
     * coarsen until the references fit. For a square world this is the
     * grid of GRID_MAX a side it always was. */
    w->cell_m = fmax(
        fmax(span / SONAR_GRID_CELLS, sqrt((x1 - x0) * (y1 - y0) / SONAR_GRID_CELLS)),
        sqrt((x1 - x0 + 1e-9) * (y1 - y0 + 1e-9) * (w->n > SONAR_MANY_PRIMS ? 1.0 : 4.0) / w->n));
    if (!(w->cell_m > 0.0))
        w->cell_m = 1.0;
    for (attempt = 0; attempt < 8; attempt++, w->cell_m *= 2.0) {
        w->nx = (int)ceil((x1 - x0) / w->cell_m + 1e-9);
        w->ny = (int)ceil((y1 - y0) / w->cell_m + 1e-9);
        if (w->nx < 1)
            w->nx = 1;
        if (w->ny < 1)
            w->ny = 1;
        if (w->nx * w->ny > SONAR_GRID_CELLS)
            continue;
        if (grid_count(w) <= SONAR_GRID_MAX_REFS)
            break;
    }
    if (attempt == 8)
        return 1;
    for (k = 0; k < w->nx * w->ny; k++) {
        w->cell_start[k + 1] = (uint16_t)(w->cell_start[k + 1] + w->cell_start[k]);
        fill[k] = w->cell_start[k];
    }
    for (k = 0; k < w->n; k++) {
        prim_cells(w, &w->p[k], &i0, &j0, &i1, &j1);
        for (j = j0; j <= j1; j++)
            for (i = i0; i <= i1; i++)
                w->refs[fill[j * w->nx + i]++] = (uint16_t)k;
    }
    w->built = 1;
    return 0;
}

/* ---- narrow phase ------------------------------------------------------ */

typedef struct {
    double ox, oy, dx, dy, z, max;
} ray_t;

static int hit_circle(const sonar_prim *p, const ray_t *r, double *t, double n[2])
{
    const double mx = r->ox - p->ax, my = r->oy - p->ay;
    const double b = mx * r->dx + my * r->dy;
    const double c = mx * mx + my * my - p->r * p->r;
    double disc, tt;
    if (c <= 0.0) {
        *t = 0.0;
        n[0] = -r->dx;
        n[1] = -r->dy;
        return 1;
    }
    if (b > 0.0)
        return 0;
    disc = b * b - c;
    if (disc < 0.0)
        return 0;
    tt = -b - sqrt(disc);
    if (tt < 0.0)
        tt = 0.0;
    *t = tt;
    n[0] = (mx + tt * r->dx) / p->r;
    n[1] = (my + tt * r->dy) / p->r;
    return 1;
}

int sonar_line_box(double ox, double oy, double dx, double dy, double cx, double cy, double hx,
                   double hy, double c, double s, double *t_in, double *t_out, double n_in[2])
{
    /* the line in the box frame */
    const double qx = ox - cx, qy = oy - cy;
    const double o[2] = { c * qx + s * qy, -s * qx + c * qy };
    const double d[2] = { c * dx + s * dy, -s * dx + c * dy };
    const double h[2] = { hx, hy };
    double tmin = -INFINITY, tmax = INFINITY;
    int a;
    n_in[0] = n_in[1] = 0.0;
    for (a = 0; a < 2; a++) {
        if (fabs(d[a]) < SONAR_EPS) {
            if (fabs(o[a]) > h[a])
                return 0;
        } else {
            double t1 = (-h[a] - o[a]) / d[a], t2 = (h[a] - o[a]) / d[a];
            if (t1 > t2) {
                const double tmp = t1;
                t1 = t2;
                t2 = tmp;
            }
            if (t1 > tmin) {
                tmin = t1;
                n_in[0] = n_in[1] = 0.0;
                n_in[a] = d[a] > 0.0 ? -1.0 : 1.0;
            }
            if (t2 < tmax)
                tmax = t2;
        }
    }
    *t_in = tmin;
    *t_out = tmax;
    return tmin <= tmax;
}

static int hit_box(const sonar_prim *p, const ray_t *r, double *t, double n[2])
{
    const double qx = r->ox - p->ax, qy = r->oy - p->ay;
    double tmin, tmax, ln[2];
    if (fabs(p->c * qx + p->s * qy) <= p->bx && fabs(-p->s * qx + p->c * qy) <= p->by) {
        *t = 0.0;
        n[0] = -r->dx;
        n[1] = -r->dy;
        return 1;
    }
    if (!sonar_line_box(r->ox, r->oy, r->dx, r->dy, p->ax, p->ay, p->bx, p->by, p->c, p->s, &tmin,
                        &tmax, ln) ||
        tmin < 0.0)
        return 0;
    *t = tmin;
    n[0] = p->c * ln[0] - p->s * ln[1];
    n[1] = p->s * ln[0] + p->c * ln[1];
    return 1;
}

static int hit_segment(const sonar_prim *p, const ray_t *r, double *t, double n[2])
{
    const double ex = p->bx - p->ax, ey = p->by - p->ay;
    const double wx = p->ax - r->ox, wy = p->ay - r->oy;
    const double den = r->dx * ey - r->dy * ex;
    double tt, u, len;
    if (fabs(den) < SONAR_EPS * hypot(ex, ey))
        return 0; /* parallel: grazing, no echo */
    tt = (wx * ey - wy * ex) / den;
    u = (wx * r->dy - wy * r->dx) / den;
    if (tt < 0.0 || u < 0.0 || u > 1.0)
        return 0;
    len = hypot(ex, ey);
    n[0] = -ey / len;
    n[1] = ex / len;
    if (n[0] * r->dx + n[1] * r->dy > 0.0) {
        n[0] = -n[0];
        n[1] = -n[1];
    }
    *t = tt;
    return 1;
}

/* Test one prim; keep it in *best if nearer. */
static void test_prim(const sonar_world *w, int k, const ray_t *r, sonar_hit *best)
{
    const sonar_prim *p = &w->p[k];
    double t, n[2], bx, by, along;
    int hit;
    if (r->z < p->z_min || r->z > p->z_max)
        return;
    /* bounding-circle reject: closest approach and the best so far */
    bx = p->bcx - r->ox;
    by = p->bcy - r->oy;
    along = bx * r->dx + by * r->dy;
    if (along + p->br < 0.0 || along - p->br > best->t_m)
        return;
    if (fabs(bx * r->dy - by * r->dx) > p->br)
        return;
    if (p->kind == SONAR_PRIM_CIRCLE)
        hit = hit_circle(p, r, &t, n);
    else if (p->kind == SONAR_PRIM_BOX)
        hit = hit_box(p, r, &t, n);
    else
        hit = hit_segment(p, r, &t, n);
    if (hit && t < best->t_m) {
        best->t_m = t;
        best->nx = n[0];
        best->ny = n[1];
        best->prim = k;
    }
}

static int ray_make(ray_t *r, double ox, double oy, double z, double dir, double max_m)
{
    if (!vec2_finite3(ox, oy, dir) || isnan(z) || !isfinite(max_m) || max_m < 0.0)
        return SONAR_ERR_ARG;
    r->ox = ox;
    r->oy = oy;
    r->dx = cos(dir);
    r->dy = sin(dir);
    r->z = z;
    r->max = max_m;
    return 0;
}

static int finish(sonar_hit *hit, const sonar_hit *best, const ray_t *r)
{
    double cosi;
    if (best->prim < 0 || best->t_m > r->max)
        return 0;
    *hit = *best;
    cosi = -(best->nx * r->dx + best->ny * r->dy);
    hit->incidence_rad = acos(cosi > 1.0 ? 1.0 : (cosi < 0.0 ? 0.0 : cosi));
    return 1;
}

static void best_init(sonar_hit *b, double max_m)
{
    b->t_m = max_m;
    b->nx = b->ny = 0.0;
    b->incidence_rad = 0.0;
    b->prim = -1;
}

int sonar_cast_brute(sonar_hit *hit, const sonar_world *w, double ox, double oy, double z_m,
                     double dir_rad, double max_m)
{
    ray_t r;
    sonar_hit best;
    int k;
    if (ray_make(&r, ox, oy, z_m, dir_rad, max_m) != 0)
        return SONAR_ERR_ARG;
    best_init(&best, max_m);
    for (k = 0; k < w->n; k++)
        test_prim(w, k, &r, &best);
    return finish(hit, &best, &r);
}

/* Amanatides-Woo walk over the grid cells the ray crosses. */
int sonar_cast(sonar_hit *hit, const sonar_world *w, double ox, double oy, double z_m,
               double dir_rad, double max_m)
{
    ray_t r;
    sonar_hit best;
    uint64_t seen[(SONAR_MAX_PRIMS + 63) / 64] = { 0 };
    double t0 = 0.0, t1 = max_m, tmx, tmy, dtx, dty, gx1, gy1;
    int i, j, sx, sy;
    if (!w->built)
        return sonar_cast_brute(hit, w, ox, oy, z_m, dir_rad, max_m);
    if (ray_make(&r, ox, oy, z_m, dir_rad, max_m) != 0)
        return SONAR_ERR_ARG;
    best_init(&best, max_m);
    gx1 = w->gx0 + w->nx * w->cell_m;
    gy1 = w->gy0 + w->ny * w->cell_m;
    /* clip the ray to the grid rectangle */
    {
        const double o[2] = { r.ox, r.oy }, d[2] = { r.dx, r.dy };
        const double lo[2] = { w->gx0, w->gy0 }, hi[2] = { gx1, gy1 };
        int a;
        for (a = 0; a < 2; a++) {
            if (fabs(d[a]) < SONAR_EPS) {
                if (o[a] < lo[a] || o[a] > hi[a])
                    return 0;
            } else {
                double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
                if (ta > tb) {
                    const double tmp = ta;
                    ta = tb;
                    tb = tmp;
                }
                if (ta > t0)
                    t0 = ta;
                if (tb < t1)
                    t1 = tb;
            }
        }
        if (t0 > t1)
            return 0;
    }
    i = cell_clamp((r.ox + t0 * r.dx - w->gx0) / w->cell_m, w->nx);
    j = cell_clamp((r.oy + t0 * r.dy - w->gy0) / w->cell_m, w->ny);
    sx = r.dx > 0.0 ? 1 : -1;
    sy = r.dy > 0.0 ? 1 : -1;
    dtx = fabs(r.dx) < SONAR_EPS ? INFINITY : w->cell_m / fabs(r.dx);
    dty = fabs(r.dy) < SONAR_EPS ? INFINITY : w->cell_m / fabs(r.dy);
    tmx = fabs(r.dx) < SONAR_EPS ? INFINITY : (w->gx0 + (i + (sx > 0)) * w->cell_m - r.ox) / r.dx;
    tmy = fabs(r.dy) < SONAR_EPS ? INFINITY : (w->gy0 + (j + (sy > 0)) * w->cell_m - r.oy) / r.dy;
    for (;;) {
        const int cell = j * w->nx + i;
        const double t_exit = tmx < tmy ? tmx : tmy;
        int q;
        for (q = w->cell_start[cell]; q < w->cell_start[cell + 1]; q++) {
            const int k = w->refs[q];
            const uint64_t bit = (uint64_t)1 << (k & 63);
            if (seen[k >> 6] & bit)
                continue;
            seen[k >> 6] |= bit;
            test_prim(w, k, &r, &best);
        }
        if (best.prim >= 0 && best.t_m <= t_exit)
            break;
        if (t_exit > t1)
            break;
        if (tmx < tmy) {
            i += sx;
            tmx += dtx;
            if (i < 0 || i >= w->nx)
                break;
        } else {
            j += sy;
            tmy += dty;
            if (j < 0 || j >= w->ny)
                break;
        }
    }
    return finish(hit, &best, &r);
}

/* ---- transducer model -------------------------------------------------- */

void sonar_model_default(sonar_model *m)
{
    m->range_min_m = 0.1;
    m->range_max_m = 5.0;
    m->cone_rad = 25.0 * DEG;
    m->rays_per_cone = 5;
    m->noise_sd_m = 0.01;
    m->specular_max_rad = 0.0;
    m->height_m = 0.2;
    m->fire_period_s = 0.04;
}

int sonar_model_validate(const sonar_model *m)
{
    if (!m || !isfinite(m->range_min_m) || !isfinite(m->range_max_m) || m->range_min_m < 0.0 ||
        !(m->range_max_m > m->range_min_m) || !isfinite(m->cone_rad) || m->cone_rad < 0.0 ||
        m->cone_rad >= VEC2_PI || m->rays_per_cone < 1 || m->rays_per_cone > SONAR_MAX_RAYS ||
        !isfinite(m->noise_sd_m) || m->noise_sd_m < 0.0 || !isfinite(m->specular_max_rad) ||
        m->specular_max_rad < 0.0 || !isfinite(m->height_m) || !isfinite(m->fire_period_s) ||
        !(m->fire_period_s > 0.0))
        return SONAR_ERR_ARG;
    return 0;
}

int sonar_fire(double *range_m, const sonar_world *w, const sonar_model *m, const pose2 *c, int k,
               prng_state *rng)
{
    const sonar_transducer *s;
    double pos[2], best = INFINITY, centre, range;
    int i, n;
    if (!range_m || !w || sonar_model_validate(m) != 0 || !vec2_pose_finite(c) || k < 0 ||
        k >= SONAR_N)
        return SONAR_ERR_ARG;
    *range_m = m->range_max_m;
    s = &sonar_p2dx_front[k];
    vec2_rotate(pos, s->x_m, s->y_m, c->theta_rad);
    pos[0] += c->x_m;
    pos[1] += c->y_m;
    centre = c->theta_rad + s->angle_rad;
    n = m->rays_per_cone;
    for (i = 0; i < n; i++) {
        const double off = n == 1 ? 0.0 : m->cone_rad * ((double)i / (n - 1) - 0.5);
        sonar_hit h;
        if (sonar_cast(&h, w, pos[0], pos[1], m->height_m, centre + off, m->range_max_m) != 1)
            continue;
        if (m->specular_max_rad > 0.0 && h.incidence_rad > m->specular_max_rad)
            continue;
        if (h.t_m < best)
            best = h.t_m;
    }
    if (!isfinite(best))
        return 0;
    range = best;
    if (rng && m->noise_sd_m > 0.0)
        range += m->noise_sd_m * prng_gauss(rng);
    if (range < m->range_min_m)
        range = m->range_min_m;
    if (range > m->range_max_m)
        range = m->range_max_m;
    *range_m = range;
    return 1;
}

int sonar_ring(double range_m[SONAR_N], const sonar_world *w, const sonar_model *m, const pose2 *c,
               prng_state *rng)
{
    int k, echoes = 0;
    for (k = 0; k < SONAR_N; k++) {
        const int r = sonar_fire(&range_m[k], w, m, c, k, rng);
        if (r < 0)
            return SONAR_ERR_ARG;
        echoes += r;
    }
    return echoes;
}

int sonar_fired_index(double t_s, const sonar_model *m)
{
    double slot;
    if (!m || !isfinite(t_s) || t_s < 0.0 || !(m->fire_period_s > 0.0))
        return SONAR_ERR_ARG;
    slot = fmod(floor(t_s / m->fire_period_s), (double)SONAR_N);
    return sonar_p2dx_fire_order[(int)slot];
}

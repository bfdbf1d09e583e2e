/* pgrid: uniform-grid spatial index of moving points (pgrid.h says what it
 * guarantees). The build is a counting sort of the items by cell, in item
 * order, so each cell's list is ascending and the layout depends on the
 * positions alone; a query scans the cells the disc's bounding square
 * overlaps (one cell wider on each side, so that rounding in the cell
 * arithmetic never hides an item), tests each item with the same
 * expression as the brute scan and sorts the few results, so it returns
 * what the brute scan returns, in the same order.
 */
#include "pgrid.h"

#include <math.h>
#include <stddef.h>

static int cell_of(double v, double v0, double cell_m, int n)
{
    const double f = floor((v - v0) / cell_m);
    if (!(f >= 0.0))
        return 0;
    return f >= (double)n ? n - 1 : (int)f;
}

static void pgrid_clear(pgrid *g)
{
    g->n = g->n_used = 0;
    g->nx = g->ny = 1;
    g->x0 = g->y0 = 0.0;
    g->cell_m = 1.0;
    g->cell_start[0] = g->cell_start[1] = 0;
}

/* Grid over [x0, x1] x [y0, y1] with cells of at least cell_m, at most
 * PGRID_MAX_CELLS of them. */
static void grid_shape(pgrid *g, double x0, double y0, double x1, double y1, double cell_m)
{
    for (;;) {
        const double fx = floor((x1 - x0) / cell_m) + 1.0, fy = floor((y1 - y0) / cell_m) + 1.0;
        if (fx * fy <= (double)PGRID_MAX_CELLS) {
            g->nx = (int)fx;
            g->ny = (int)fy;
            break;
        }
        cell_m *= 2.0;
    }
    g->x0 = x0;
    g->y0 = y0;
    g->cell_m = cell_m;
}

int pgrid_build(pgrid *g, const double *x, const double *y, const int *use, int n, double cell_m)
{
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    int32_t fill[PGRID_MAX_CELLS];
    int i, k, cells;
    if (!g)
        return PGRID_ERR_ARG;
    pgrid_clear(g);
    if (!x || !y || n < 0 || n > PGRID_MAX_ITEMS || !isfinite(cell_m) || !(cell_m > 0.0))
        return PGRID_ERR_ARG;
    for (i = 0; i < n; i++) {
        g->used[i] = (uint8_t)(use == NULL || use[i] != 0);
        if (!g->used[i])
            continue;
        if (!isfinite(x[i]) || !isfinite(y[i])) {
            pgrid_clear(g);
            return PGRID_ERR_ARG;
        }
        g->x[i] = x[i];
        g->y[i] = y[i];
        x0 = fmin(x0, x[i]);
        y0 = fmin(y0, y[i]);
        x1 = fmax(x1, x[i]);
        y1 = fmax(y1, y[i]);
        g->n_used++;
    }
    g->n = n;
    if (g->n_used == 0)
        return PGRID_OK;
    grid_shape(g, x0, y0, x1, y1, cell_m);
    cells = g->nx * g->ny;
    for (k = 0; k <= cells; k++)
        g->cell_start[k] = 0;
    for (i = 0; i < n; i++)
        if (g->used[i])
            g->cell_start[1 + cell_of(g->y[i], g->y0, g->cell_m, g->ny) * g->nx +
                          cell_of(g->x[i], g->x0, g->cell_m, g->nx)]++;
    for (k = 0; k < cells; k++) {
        g->cell_start[k + 1] += g->cell_start[k];
        fill[k] = g->cell_start[k];
    }
    for (i = 0; i < n; i++)
        if (g->used[i])
            g->idx[fill[cell_of(g->y[i], g->y0, g->cell_m, g->ny) * g->nx +
                        cell_of(g->x[i], g->x0, g->cell_m, g->nx)]++] = i;
    return PGRID_OK;
}

static int near(const pgrid *g, int32_t i, double x, double y, double r)
{
    const double dx = g->x[i] - x, dy = g->y[i] - y;
    return dx * dx + dy * dy <= r * r;
}

/* Shell sort (Ciura's gaps): a query's results are few; no recursion. */
static void sort_ids(int32_t *a, int n)
{
    static const int gaps[] = { 701, 301, 132, 57, 23, 10, 4, 1 };
    size_t q;
    for (q = 0; q < sizeof gaps / sizeof gaps[0]; q++) {
        const int gap = gaps[q];
        int i;
        for (i = gap; i < n; i++) {
            const int32_t v = a[i];
            int j = i;
            for (; j >= gap && a[j - gap] > v; j -= gap)
                a[j] = a[j - gap];
            a[j] = v;
        }
    }
}

static int query_ok(const pgrid *g, double x, double y, double r, const int32_t *out, int cap)
{
    return g && out && cap >= 0 && isfinite(x) && isfinite(y) && isfinite(r) && r >= 0.0;
}

int pgrid_query(const pgrid *g, double x, double y, double r, int32_t *out, int cap)
{
    int i0, i1, j0, j1, i, j, k = 0;
    if (!query_ok(g, x, y, r, out, cap))
        return PGRID_ERR_ARG;
    if (g->n_used == 0)
        return 0;
    i0 = cell_of(x - r, g->x0, g->cell_m, g->nx) - 1;
    i1 = cell_of(x + r, g->x0, g->cell_m, g->nx) + 1;
    j0 = cell_of(y - r, g->y0, g->cell_m, g->ny) - 1;
    j1 = cell_of(y + r, g->y0, g->cell_m, g->ny) + 1;
    i0 = i0 < 0 ? 0 : i0;
    j0 = j0 < 0 ? 0 : j0;
    i1 = i1 >= g->nx ? g->nx - 1 : i1;
    j1 = j1 >= g->ny ? g->ny - 1 : j1;
    for (j = j0; j <= j1; j++)
        for (i = i0; i <= i1; i++) {
            const int cell = j * g->nx + i;
            int q;
            for (q = g->cell_start[cell]; q < g->cell_start[cell + 1]; q++) {
                if (!near(g, g->idx[q], x, y, r))
                    continue;
                if (k >= cap)
                    return PGRID_ERR_FULL;
                out[k++] = g->idx[q];
            }
        }
    sort_ids(out, k);
    return k;
}

int pgrid_query_brute(const pgrid *g, double x, double y, double r, int32_t *out, int cap)
{
    int32_t i;
    int k = 0;
    if (!query_ok(g, x, y, r, out, cap))
        return PGRID_ERR_ARG;
    for (i = 0; i < g->n; i++) {
        if (!g->used[i] || !near(g, i, x, y, r))
            continue;
        if (k >= cap)
            return PGRID_ERR_FULL;
        out[k++] = i;
    }
    return k;
}

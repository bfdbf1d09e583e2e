/* pgrid: a uniform-grid spatial index of points in the plane (moving
 * bodies: rebuilt whenever they move), with fixed capacities and no heap.
 *
 * Build: the items in use are counted into cells of cell_m (the grid
 * covers their bounding box; if that needs more than PGRID_MAX_CELLS
 * cells, cell_m doubles until it fits), then placed by a counting sort in
 * item order, so each cell lists its items in ascending index order and
 * the index is a deterministic function of the positions.
 * Query: every item within distance r of a point, returned in ascending
 * item index, exactly the items a scan of all of them with the same test
 * (dx * dx + dy * dy <= r * r) would return, in the same order: a caller
 * that replaces such a scan by a query keeps its results bit for bit.
 * Cost: build O(items + cells), query O(cells overlapped + k log k) for k
 * results, independent of the number of items far away.
 *
 * Capacities are compile-time (PGRID_MAX_ITEMS, PGRID_MAX_CELLS; a build
 * may set either with -D).
 */
#ifndef TANDEM_PGRID_H
#define TANDEM_PGRID_H

#include <stdint.h>

#define PGRID_OK 0
#define PGRID_ERR_ARG (-1)  /* NULL, n outside 0..PGRID_MAX_ITEMS, cell_m not > 0, non-finite */
#define PGRID_ERR_FULL (-2) /* pgrid_query: more results than the caller's cap */

#ifndef PGRID_MAX_ITEMS
#define PGRID_MAX_ITEMS 10240
#endif
#ifndef PGRID_MAX_CELLS
#define PGRID_MAX_CELLS 16384
#endif

typedef struct {
    int n;      /* items given to the last build (indices 0..n-1) */
    int n_used; /* of them in the index */
    int nx, ny;
    double x0, y0, cell_m;
    int32_t cell_start[PGRID_MAX_CELLS + 1];
    int32_t idx[PGRID_MAX_ITEMS]; /* item indices grouped by cell */
    double x[PGRID_MAX_ITEMS], y[PGRID_MAX_ITEMS];
    uint8_t used[PGRID_MAX_ITEMS];
} pgrid;

/* Index items 0..n-1 at (x[i], y[i]); use may be NULL (all), else only
 * items with use[i] != 0 (the others' positions are not read). cell_m is
 * the wanted cell size. PGRID_OK, or PGRID_ERR_ARG (then the index is
 * empty). */
int pgrid_build(pgrid *g, const double *x, const double *y, const int *use, int n, double cell_m);

/* Items within r (>= 0) of (x, y), ascending, into out[0..cap-1]: their
 * number, PGRID_ERR_FULL if more than cap, PGRID_ERR_ARG on bad input. */
int pgrid_query(const pgrid *g, double x, double y, double r, int32_t *out, int cap);

/* The same by scanning every item: the reference the tests and the
 * benchmarks compare against. */
int pgrid_query_brute(const pgrid *g, double x, double y, double r, int32_t *out, int cap);

#endif

/* slot_assign: the assignment of robots to slots of least sum of squared
 * distances (docs/method/formation.md §6; see slot_assign.h), by the
 * Hungarian method with row and column potentials u, v: every step keeps
 * u[i] + v[k] <= c(i, k) with equality on the matched pairs, and adds one
 * robot along a shortest augmenting path (Dijkstra on the reduced costs
 * c - u - v), so after n rows the matching is optimal (the potentials are
 * the dual's certificate). n rows of at most n steps of O(n): O(n^3). The
 * costs are computed when needed, not stored: the stack holds O(n), not
 * an n x n matrix. On one axis the optimum is the sorted order
 * (slot_assign_sorted, O(n log n)). */
#include "slot_assign.h"

#include <math.h>
#include <stddef.h>

static double cost_m2(const double xy[2], const double sl[2])
{
    const double dx = xy[0] - sl[0], dy = xy[1] - sl[1];
    return dx * dx + dy * dy;
}

static int args_ok(const double xy_m[][2], const double slot_m[][2], int n, const int *slot_of)
{
    int j;
    if (!xy_m || !slot_m || !slot_of || n < 1 || n > SLOT_ASSIGN_MAX)
        return 0;
    for (j = 0; j < n; j++)
        if (!isfinite(xy_m[j][0]) || !isfinite(xy_m[j][1]) || !isfinite(slot_m[j][0]) ||
            !isfinite(slot_m[j][1]))
            return 0;
    return 1;
}

/* The matching under construction; index 0 is the virtual column the
 * augmenting search starts from (robots and slots are 1..n here). */
typedef struct {
    const double (*xy)[2];
    const double (*sl)[2];
    int n;
    double u[SLOT_ASSIGN_MAX + 1], v[SLOT_ASSIGN_MAX + 1];
    int robot_at[SLOT_ASSIGN_MAX + 1]; /* robot_at[k]: the robot on slot k, 0 none */
} hungarian;

/* Adds robot i: a shortest augmenting path from it over the reduced
 * costs, the potentials moved so the path's edges become tight, then the
 * slots along it passed on. */
static void add_robot(hungarian *h, int i)
{
    double minv[SLOT_ASSIGN_MAX + 1];
    int way[SLOT_ASSIGN_MAX + 1], used[SLOT_ASSIGN_MAX + 1];
    int k, k0 = 0;
    for (k = 0; k <= h->n; k++) {
        minv[k] = INFINITY;
        used[k] = 0;
        way[k] = 0;
    }
    h->robot_at[0] = i;
    do { /* at most n rounds: each marks one more slot used */
        const int i0 = h->robot_at[k0];
        double delta = INFINITY;
        int k1 = 0;
        used[k0] = 1;
        for (k = 1; k <= h->n; k++)
            if (!used[k]) {
                const double cur = cost_m2(h->xy[i0 - 1], h->sl[k - 1]) - h->u[i0] - h->v[k];
                if (cur < minv[k]) {
                    minv[k] = cur;
                    way[k] = k0;
                }
                if (minv[k] < delta) { /* strict: ties go to the lower slot */
                    delta = minv[k];
                    k1 = k;
                }
            }
        for (k = 0; k <= h->n; k++)
            if (used[k]) {
                h->u[h->robot_at[k]] += delta;
                h->v[k] -= delta;
            } else {
                minv[k] -= delta;
            }
        k0 = k1;
    } while (h->robot_at[k0] != 0);
    do { /* the path back to the virtual column */
        const int k1 = way[k0];
        h->robot_at[k0] = h->robot_at[k1];
        k0 = k1;
    } while (k0 != 0);
}

int slot_assign_min_sq(const double xy_m[][2], const double slot_m[][2], int n, int *slot_of,
                       double *cost_sum_m2)
{
    hungarian h;
    double sum = 0.0;
    int i, k;
    if (!args_ok(xy_m, slot_m, n, slot_of))
        return SLOT_ASSIGN_ERR_ARG;
    h.xy = xy_m;
    h.sl = slot_m;
    h.n = n;
    for (k = 0; k <= n; k++) {
        h.u[k] = 0.0;
        h.v[k] = 0.0;
        h.robot_at[k] = 0;
    }
    for (i = 1; i <= n; i++)
        add_robot(&h, i);
    for (k = 1; k <= n; k++) {
        slot_of[h.robot_at[k] - 1] = k - 1;
        sum += cost_m2(xy_m[h.robot_at[k] - 1], slot_m[k - 1]);
    }
    if (cost_sum_m2)
        *cost_sum_m2 = sum;
    return SLOT_ASSIGN_OK;
}

/* order[0..n) = 0..n-1 sorted by key, stably (bottom-up merge sort through
 * tmp: O(n log n), no recursion, no allocation). */
static void sort_index(const double key[], int n, int order[], int tmp[])
{
    int w, i, *a = order, *b = tmp;
    for (i = 0; i < n; i++)
        order[i] = i;
    for (w = 1; w < n; w *= 2) {
        int *t;
        for (i = 0; i < n; i += 2 * w) {
            const int mid = i + w < n ? i + w : n, end = i + 2 * w < n ? i + 2 * w : n;
            int l = i, r = mid, k = i;
            while (l < mid && r < end)
                b[k++] = key[a[r]] < key[a[l]] ? a[r++] : a[l++];
            while (l < mid)
                b[k++] = a[l++];
            while (r < end)
                b[k++] = a[r++];
        }
        t = a;
        a = b;
        b = t;
    }
    if (a != order)
        for (i = 0; i < n; i++)
            order[i] = a[i];
}

int slot_assign_sorted(const double x_m[], const double s_m[], int n, int *slot_of,
                       double *cost_sum_m2)
{
    int by_x[SLOT_ASSIGN_MAX], by_s[SLOT_ASSIGN_MAX], tmp[SLOT_ASSIGN_MAX], j;
    double sum = 0.0;
    if (!x_m || !s_m || !slot_of || n < 1 || n > SLOT_ASSIGN_MAX)
        return SLOT_ASSIGN_ERR_ARG;
    for (j = 0; j < n; j++)
        if (!isfinite(x_m[j]) || !isfinite(s_m[j]))
            return SLOT_ASSIGN_ERR_ARG;
    sort_index(x_m, n, by_x, tmp);
    sort_index(s_m, n, by_s, tmp);
    for (j = 0; j < n; j++) {
        const double d = x_m[by_x[j]] - s_m[by_s[j]];
        slot_of[by_x[j]] = by_s[j];
        sum += d * d;
    }
    if (cost_sum_m2)
        *cost_sum_m2 = sum;
    return SLOT_ASSIGN_OK;
}

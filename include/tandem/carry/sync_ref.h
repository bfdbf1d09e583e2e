/* sync_ref: common action reference for synchronised actions (docs/method/carry.md §4).
 *
 *   l_max = max l_i,  k_i = l_i / l_max,
 *   s* = min_i (s_i / k_i),  reference of arm i = k_i s*
 *
 * (min, not the seed's printed max: one stopped arm must hold the others.)
 *
 * Zero-length actions (k_i = 0, the seed forbids them) are accepted and
 * excluded from the minimum: such an arm has nothing to travel, so it can
 * neither hold nor be held; its reference is 0. If every action has zero
 * length, s* = 0. s* is clamped to [0, l_max].
 */
#ifndef TANDEM_SYNC_REF_H
#define TANDEM_SYNC_REF_H

#define SYNC_REF_ERR_ARG \
    (-1) /* NULL, n outside 1..SYNC_MAX, a length
                                  < 0 or a non-finite number             */

#define SYNC_MAX 4

typedef struct {
    int n;
    double l_max_m;
    double k[SYNC_MAX];
} sync_ref;

/* n in 1..SYNC_MAX, l_m[i] finite and >= 0. Returns 0 or SYNC_REF_ERR_ARG. */
int sync_ref_init(sync_ref *r, int n, const double l_m[]);

/* s_m[i]: measured progress of arm i (finite). Writes s* and, if s_ref_m
 * is not NULL, the n per-arm references k_i s*. Returns 0 or SYNC_REF_ERR_ARG. */
int sync_ref_update(const sync_ref *r, const double s_m[], double *s_star_m, double s_ref_m[]);

#endif

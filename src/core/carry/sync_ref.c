/* sync_ref: common action reference s* = min_i s_i / k_i of docs/method/carry.md §4 (the
 * seed's step 3 prints max; its stated behaviour needs min). */
#include "sync_ref.h"

#include <math.h>

int sync_ref_init(sync_ref *r, int n, const double l_m[])
{
    int i;
    if (!r || !l_m || n < 1 || n > SYNC_MAX)
        return SYNC_REF_ERR_ARG;
    r->n = 0;
    r->l_max_m = 0.0;
    for (i = 0; i < n; i++) {
        if (!isfinite(l_m[i]) || l_m[i] < 0.0)
            return SYNC_REF_ERR_ARG;
        if (l_m[i] > r->l_max_m)
            r->l_max_m = l_m[i];
    }
    for (i = 0; i < n; i++)
        r->k[i] = r->l_max_m > 0.0 ? l_m[i] / r->l_max_m : 0.0;
    r->n = n;
    return 0;
}

int sync_ref_update(const sync_ref *r, const double s_m[], double *s_star_m, double s_ref_m[])
{
    double s_star;
    int i;
    if (!r || !s_m || !s_star_m || r->n < 1 || r->n > SYNC_MAX)
        return SYNC_REF_ERR_ARG;
    for (i = 0; i < r->n; i++)
        if (!isfinite(s_m[i]))
            return SYNC_REF_ERR_ARG;
    s_star = r->l_max_m;
    for (i = 0; i < r->n; i++)
        if (r->k[i] > 0.0)
            s_star = fmin(s_star, s_m[i] / r->k[i]);
    s_star = fmax(s_star, 0.0);
    if (r->l_max_m == 0.0)
        s_star = 0.0;
    *s_star_m = s_star;
    if (s_ref_m)
        for (i = 0; i < r->n; i++)
            s_ref_m[i] = r->k[i] * s_star;
    return 0;
}

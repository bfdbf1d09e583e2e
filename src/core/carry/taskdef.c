/* taskdef: a task in fixed tables and the roles the supervisor finds
 * from its net's structure (docs/tasks.md §7; the net and rows of
 * docs/method/carry.md §5, §6), and the arms' health places it names
 * (taskdef_health_find, docs/tasks.md §8). No equation: structure only.
 */
#include "taskdef.h"
#include <string.h>

#include <stddef.h>

static int8_t entry(const int8_t *tab, const petri_net *n, int i, int j)
{
    return tab ? tab[i * n->n_transitions + j] : 0;
}

#define FNV_OFFSET 14695981039346656037ULL
#define FNV_PRIME 1099511628211ULL

static uint64_t fnv_byte(uint64_t h, uint8_t b)
{
    return (h ^ b) * FNV_PRIME;
}

/* v as 8 bytes, least significant first (the same on every host) */
static uint64_t fnv_u64(uint64_t h, uint64_t v)
{
    int i;
    for (i = 0; i < 8; i++)
        h = fnv_byte(h, (uint8_t)(v >> (8 * i)));
    return h;
}

static uint64_t fnv_int(uint64_t h, long v)
{
    return fnv_u64(h, (uint64_t)(int64_t)v);
}

static uint64_t fnv_double(uint64_t h, double d)
{
    union {
        double d;
        uint64_t u;
    } bits;
    bits.d = d;
    return fnv_u64(h, bits.u);
}

uint64_t taskdef_digest(const petri_net *net, const carry_row *rows)
{
    uint64_t h = FNV_OFFSET;
    int i, j, a, k;
    if (!net)
        return 0;
    h = fnv_int(h, net->n_places);
    h = fnv_int(h, net->n_transitions);
    for (i = 0; i < net->n_places; i++) {
        h = fnv_int(h, net->m0 ? net->m0[i] : 0);
        for (j = 0; j < net->n_transitions; j++) {
            h = fnv_int(h, entry(net->n_minus, net, i, j));
            h = fnv_int(h, entry(net->n_plus, net, i, j));
            h = fnv_int(h, entry(net->n_inhibit, net, i, j));
        }
    }
    for (j = 0; rows && j < net->n_transitions; j++) {
        const carry_row *r = &rows[j];
        const double g[8] = { r->lin.v_m, r->lin.a_m, r->lin.u_m, r->lin.k_p,
                              r->lin.k_v, r->lin.k0,  r->lin.k1,  r->lin.k2 };
        h = fnv_int(h, r->arms);
        h = fnv_int(h, r->sync_group);
        for (k = 0; k < 8; k++)
            h = fnv_double(h, g[k]);
        for (a = 0; a < 2; a++) {
            const carry_arm_plan *p = &r->plan[a];
            h = fnv_int(h, r->target_pose[a]);
            h = fnv_int(h, r->gripper[a]);
            h = fnv_int(h, p->n_segments);
            h = fnv_int(h, p->after_partner);
            for (k = 0; k < p->n_segments && k < CARRY_MAX_SEGMENTS; k++) {
                h = fnv_int(h, p->seg[k].kind);
                h = fnv_int(h, p->seg[k].pose);
            }
        }
    }
    return h;
}

void taskdef_bind(taskdef *t)
{
    t->net.n_places = t->n_places;
    t->net.n_transitions = t->n_transitions;
    t->net.n_minus = t->n_minus;
    t->net.n_plus = t->n_plus;
    t->net.n_inhibit = t->has_inhibit ? t->n_inhibit : NULL;
    t->net.m0 = t->m0;
    t->net.n_invariants = t->n_invariants;
    t->net.invariants = t->n_invariants ? t->invariants : NULL;
}

/* Places with an entry in column j of tab: their count, the last in *last. */
static int column_count(const petri_net *n, const int8_t *tab, int j, int *last)
{
    int i, k = 0;
    for (i = 0; i < n->n_places; i++)
        if (entry(tab, n, i, j)) {
            k++;
            *last = i;
        }
    return k;
}

/* Transitions with an entry in row i of N-: their count, the last in *last. */
static int takers(const petri_net *n, int i, int *last)
{
    int j, k = 0;
    for (j = 0; j < n->n_transitions; j++)
        if (entry(n->n_minus, n, i, j)) {
            k++;
            *last = j;
        }
    return k;
}

int taskdef_roles_find(const petri_net *net, taskdef_roles *r)
{
    int j, sources = 0, src = -1, place = -1, pick = -1, unused;
    if (!r)
        return TASKDEF_ERR_ARG;
    r->source = r->source_place = r->pick = -1;
    if (!net || !net->n_minus || !net->n_plus || net->n_places < 1 ||
        net->n_places > PETRI_MAX_PLACES || net->n_transitions < 1 ||
        net->n_transitions > PETRI_MAX_TRANSITIONS)
        return TASKDEF_ERR_ARG;
    for (j = 0; j < net->n_transitions; j++)
        if (column_count(net, net->n_minus, j, &unused) == 0) {
            sources++;
            src = j;
        }
    if (sources != 1)
        return TASKDEF_ERR_SOURCE;
    /* one place, and the source inhibited by it: otherwise a second
     * detection could come before the first is taken, and the supervisor
     * binds one pose to one token */
    if (column_count(net, net->n_plus, src, &place) != 1 || !entry(net->n_inhibit, net, place, src))
        return TASKDEF_ERR_SOURCE_PLACE;
    if (takers(net, place, &pick) != 1)
        return TASKDEF_ERR_PICK;
    r->source = src;
    r->source_place = place;
    r->pick = pick;
    return TASKDEF_OK;
}

int taskdef_validate(const petri_net *net, const carry_row *rows, taskdef_roles *r)
{
    return taskdef_validate_health(net, rows, 0, r);
}

int taskdef_validate_health(const petri_net *net, const carry_row *rows, uint32_t health_mask,
                            taskdef_roles *r)
{
    taskdef_roles found;
    int rc;
    if (!net || !rows)
        return TASKDEF_ERR_ARG;
    if (petri_net_validate(net) != 0)
        return TASKDEF_ERR_NET;
    if (carry_table_validate_health(rows, net->n_transitions, net, health_mask) != 0)
        return TASKDEF_ERR_TABLE;
    if ((rc = taskdef_roles_find(net, &found)) != TASKDEF_OK)
        return rc;
    if (r)
        *r = found;
    return TASKDEF_OK;
}

/* ---- the arms' health -------------------------------------------------------- */

/* The place named or with the id s, -1 if none. */
static int place_named(const taskdef *t, const char *s)
{
    int i;
    for (i = 0; i < t->n_places; i++)
        if (strcmp(t->place_name[i], s) == 0 || strcmp(t->place_id[i], s) == 0)
            return i;
    return -1;
}

/* The one transition whose only arcs are from place a to place b (no
 * inhibitor arc), -1 if not exactly one. */
static int only_arc(const petri_net *n, int a, int b)
{
    int i, j, found = -1, count = 0;
    for (j = 0; j < n->n_transitions; j++) {
        int ok = entry(n->n_minus, n, a, j) && entry(n->n_plus, n, b, j);
        for (i = 0; i < n->n_places && ok; i++)
            ok = (i == a || !entry(n->n_minus, n, i, j)) &&
                 (i == b || !entry(n->n_plus, n, i, j)) &&
                 !(n->n_inhibit && entry(n->n_inhibit, n, i, j));
        if (ok) {
            found = j;
            count++;
        }
    }
    return count == 1 ? found : -1;
}

static void health_none(taskdef_health *h)
{
    int k;
    for (k = 0; k < 2; k++)
        h->up[k] = h->down[k] = h->fault[k] = h->recover[k] = -1;
    h->mask = 0;
}

int taskdef_health_find(const taskdef *t, taskdef_health *h)
{
    static const char *const up_name[2] = { "arm1_up", "arm2_up" }, *const down_name[2] = {
        "arm1_down", "arm2_down"
    };
    const petri_net *n;
    int k, j;
    if (!h)
        return TASKDEF_ERR_ARG;
    health_none(h);
    if (!t)
        return TASKDEF_ERR_ARG;
    n = &t->net;
    for (k = 0; k < 2; k++) {
        const int up = place_named(t, up_name[k]), down = place_named(t, down_name[k]);
        int f, r;
        if (up < 0 && down < 0)
            continue;
        if (up < 0 || down < 0 || t->m0[up] + t->m0[down] != 1)
            goto refused;
        f = only_arc(n, up, down);
        r = only_arc(n, down, up);
        if (f < 0 || r < 0)
            goto refused;
        for (j = 0; j < n->n_transitions; j++)
            if (j != f && j != r &&
                (entry(n->n_minus, n, up, j) || entry(n->n_plus, n, up, j) ||
                 entry(n->n_minus, n, down, j) || entry(n->n_plus, n, down, j)))
                goto refused;
        h->up[k] = up;
        h->down[k] = down;
        h->fault[k] = f;
        h->recover[k] = r;
        h->mask |= 1u << f | 1u << r;
    }
    return TASKDEF_OK;
refused:
    health_none(h);
    return TASKDEF_ERR_HEALTH;
}

int carry_row_sets_down(const carry_row *r, int a)
{
    const carry_arm_plan *pl, *partner;
    int k, at = CARRY_POSE_NONE, releases = 0, partner_grasps = 0;
    if (!r || a < 0 || a > 1)
        return 0;
    pl = &r->plan[a];
    partner = &r->plan[1 - a];
    for (k = 0; k < partner->n_segments && k < CARRY_MAX_SEGMENTS; k++)
        partner_grasps |= partner->seg[k].kind == CARRY_SEG_GRASP;
    for (k = 0; k < pl->n_segments && k < CARRY_MAX_SEGMENTS; k++) {
        if (pl->seg[k].kind == CARRY_SEG_MOVE)
            at = pl->seg[k].pose;
        else if (pl->seg[k].kind == CARRY_SEG_RELEASE && at != CARRY_POSE_RELEASE_POSE &&
                 at != CARRY_POSE_NONE)
            releases = 1;
    }
    return releases && !partner_grasps;
}

int carry_row_uses_magazine(const carry_row *r)
{
    int a, k;
    if (!r)
        return 0;
    for (a = 0; a < 2; a++)
        for (k = 0; k < r->plan[a].n_segments && k < CARRY_MAX_SEGMENTS; k++)
            if (r->plan[a].seg[k].kind == CARRY_SEG_MOVE &&
                (r->plan[a].seg[k].pose == CARRY_POSE_ABOVE_MAGAZINE ||
                 r->plan[a].seg[k].pose == CARRY_POSE_AT_MAGAZINE))
                return 1;
    return 0;
}

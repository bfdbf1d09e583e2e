/* netc_check: what tandem-netc proves of a task before it becomes tables
 * (docs/tasks.md §4): the validators the supervisor runs at start-up
 * (petri_net_validate, carry_table_validate with the arms' health
 * transitions, taskdef_health_find), gains inside what the arms
 * accept (carry_gains_within_table), then the reachability graph of the
 * split-firing net (petri_explore, docs/method/carry.md §5) within
 * PETRI_MAX_STATES: bounded (safe for bound 1), deadlock-free, every
 * transition fires somewhere, the live ones can fire again from every
 * reachable state; and the P-invariants (y^T C = 0, y >= 0) by the Farkas
 * algorithm, which go into the tables. A refusal prints the firing
 * sequence to the offending state, in words and as a marking table.
 */
#include <stdlib.h>
#include <string.h>
#include "netc.h"

#define MAX_TRACE 512
#define NETC_LOOKUP_SIZE (2 * PETRI_MAX_STATES) /* power of two, half full at most */

typedef struct {
    petri_explore_ws ws;
    int slot[NETC_LOOKUP_SIZE]; /* state index + 1 by hash, 0 = empty      */
    int32_t *succ;              /* n_states x 2*tau successor index or -1   */
    uint32_t *can;              /* bit j: t_j can start from here (or later) */
} explorer;

/* ---- counterexample ------------------------------------------------------ */

static void print_marking_row(const netc_task *t, FILE *f, const char *step, const petri_state *s)
{
    int i;
    fprintf(f, "  %-34s", step);
    for (i = 0; i < t->n_places; i++)
        fprintf(f, " %5d", s->m[i]);
    fprintf(f, "   running:");
    for (i = 0; i < t->n_transitions; i++)
        if (s->running & (1u << i))
            fprintf(f, " %s", t->trans_name[i]);
    fprintf(f, "\n");
}

/* The event path from m0 to state `index`, replayed on the engine. */
static void print_trace(const netc_task *t, const explorer *x, int index, FILE *f)
{
    int8_t ev[MAX_TRACE];
    char step[64];
    petri p;
    int n = petri_explore_trace(&x->ws, index, ev, MAX_TRACE), k, i;
    if (n < 0 || petri_init(&p, &t->net) != 0) {
        fprintf(f, "  (the path is longer than %d events)\n", MAX_TRACE);
        return;
    }
    fprintf(f, "  firing sequence from the initial marking:%s",
            n ? "" : " none, it is the initial marking");
    for (k = 0; k < n; k++)
        fprintf(f, "%s %s %s", k ? "," : "", ev[k] > 0 ? "start" : "complete",
                t->trans_name[abs(ev[k]) - 1]);
    fprintf(f, "\n  %-34s", "marking");
    for (i = 0; i < t->n_places; i++)
        fprintf(f, " %5.5s", t->place_name[i]);
    fprintf(f, "\n");
    print_marking_row(t, f, "initial", &p.st);
    for (k = 0; k < n; k++) {
        const int j = abs(ev[k]) - 1;
        if (ev[k] > 0)
            petri_start(&p, j);
        else
            petri_complete(&p, j);
        snprintf(step, sizeof step, "%d. %s %.20s", k + 1, ev[k] > 0 ? "start" : "complete",
                 t->trans_name[j]);
        print_marking_row(t, f, step, &p.st);
    }
}

/* ---- graph ----------------------------------------------------------------- */

static int state_equal(const petri_state *a, const petri_state *b)
{
    return memcmp(a->m, b->m, sizeof a->m) == 0 && a->running == b->running;
}

static uint32_t state_hash(const petri_state *s)
{
    uint32_t h = 2166136261u ^ s->running;
    size_t i;
    for (i = 0; i < sizeof s->m; i++)
        h = (h ^ s->m[i]) * 16777619u;
    return h;
}

/* Index of s among the explored states (open addressing), or -1. */
static int lookup(const explorer *x, const petri_state *s)
{
    uint32_t k = state_hash(s) & (NETC_LOOKUP_SIZE - 1);
    for (; x->slot[k]; k = (k + 1) & (NETC_LOOKUP_SIZE - 1))
        if (state_equal(&x->ws.states[x->slot[k] - 1], s))
            return x->slot[k] - 1;
    return -1;
}

static void index_states(explorer *x)
{
    int i;
    memset(x->slot, 0, sizeof x->slot);
    for (i = 0; i < x->ws.n_states; i++) {
        uint32_t k = state_hash(&x->ws.states[i]) & (NETC_LOOKUP_SIZE - 1);
        while (x->slot[k])
            k = (k + 1) & (NETC_LOOKUP_SIZE - 1);
        x->slot[k] = i + 1;
    }
}

/* Successors of every state (start t_j: edge 2j, complete t_j: 2j+1) and
 * the transitions enabled in each. */
static void build_graph(const netc_task *t, explorer *x)
{
    const int n = x->ws.n_states, tau = t->n_transitions;
    int i, j;
    petri p;
    index_states(x);
    petri_init(&p, &t->net);
    for (i = 0; i < n; i++) {
        x->can[i] = 0;
        for (j = 0; j < tau; j++) {
            (void)petri_load_state(&p, &x->ws.states[i]);
            x->succ[i * 2 * tau + 2 * j] = petri_start(&p, j) == 0 ? lookup(x, &p.st) : -1;
            if (x->succ[i * 2 * tau + 2 * j] >= 0)
                x->can[i] |= 1u << j;
            (void)petri_load_state(&p, &x->ws.states[i]);
            x->succ[i * 2 * tau + 2 * j + 1] = petri_complete(&p, j) == 0 ? lookup(x, &p.st) : -1;
        }
    }
}

/* can[s] grows to every transition that can start from s or after it
 * (backward closure over the edges, to a fixed point). */
static void close_can(const netc_task *t, explorer *x)
{
    const int n = x->ws.n_states, e = 2 * t->n_transitions;
    int changed = 1, i, k;
    while (changed) {
        changed = 0;
        for (i = 0; i < n; i++)
            for (k = 0; k < e; k++) {
                const int s = x->succ[i * e + k];
                if (s >= 0 && (x->can[s] & ~x->can[i])) {
                    x->can[i] |= x->can[s];
                    changed = 1;
                }
            }
    }
}

/* ---- P-invariants: Farkas ------------------------------------------------------ */

static int gcd(int a, int b)
{
    a = abs(a);
    b = abs(b);
    while (b) {
        const int r = a % b;
        a = b;
        b = r;
    }
    return a;
}

typedef struct {
    int n, w; /* rows, width = tau + rho */
    int v[NETC_MAX_FARKAS_ROWS][2 * PETRI_MAX_PLACES + PETRI_MAX_TRANSITIONS];
} farkas;

static void normalise(int *row, int w)
{
    int g = 0, k;
    for (k = 0; k < w; k++)
        g = gcd(g, row[k]);
    for (k = 0; g > 1 && k < w; k++)
        row[k] /= g;
}

/* Row r is not minimal: another row's y support is a proper subset of
 * its own, or the same support comes earlier. */
static int covers_other(const farkas *f, int r, int tau)
{
    int o, k;
    for (o = 0; o < f->n; o++) {
        int sub = o != r, proper = 0;
        for (k = tau; sub && k < f->w; k++) {
            if (f->v[o][k] && !f->v[r][k])
                sub = 0;
            if (!f->v[o][k] && f->v[r][k])
                proper = 1;
        }
        if (sub && (proper || o < r))
            return 1;
    }
    return 0;
}

static int farkas_push(farkas *tmp, const int *a, int ca, const int *b, int cb)
{
    int k;
    if (tmp->n >= NETC_MAX_FARKAS_ROWS)
        return NETC_ERR_INVARIANT;
    for (k = 0; k < tmp->w; k++)
        tmp->v[tmp->n][k] = ca * a[k] + (b ? cb * b[k] : 0);
    normalise(tmp->v[tmp->n], tmp->w);
    tmp->n++;
    return 0;
}

/* Eliminates column j: rows zero there stay, each pair of opposite signs
 * is combined into one that is zero there. */
static int farkas_column(farkas *f, farkas *tmp, int j)
{
    int a, b, rc = 0;
    tmp->n = 0;
    tmp->w = f->w;
    for (a = 0; a < f->n && rc == 0; a++)
        if (f->v[a][j] == 0)
            rc = farkas_push(tmp, f->v[a], 1, NULL, 0);
    for (a = 0; a < f->n && rc == 0; a++)
        for (b = 0; b < f->n && rc == 0; b++)
            if (f->v[a][j] > 0 && f->v[b][j] < 0)
                rc = farkas_push(tmp, f->v[a], -f->v[b][j], f->v[b], f->v[a][j]);
    memcpy(f->v, tmp->v, (size_t)tmp->n * sizeof f->v[0]);
    f->n = tmp->n;
    return rc;
}

static int inv_cmp(const void *a, const void *b)
{
    return memcmp(a, b, PETRI_MAX_PLACES);
}

/* Minimal semi-positive P-invariants into t->invariants, sorted. */
static int find_invariants(netc_task *t, FILE *err)
{
    const int rho = t->n_places, tau = t->n_transitions;
    farkas *f = calloc(2, sizeof *f);
    int8_t found[NETC_MAX_FARKAS_ROWS][PETRI_MAX_PLACES];
    int i, j, n = 0, rc = 0;
    if (!f)
        return NETC_ERR_IO;
    f->n = rho;
    f->w = tau + rho;
    for (i = 0; i < rho; i++)
        for (j = 0; j < tau; j++)
            f->v[i][j] = t->n_plus[i * tau + j] - t->n_minus[i * tau + j];
    for (i = 0; i < rho; i++)
        f->v[i][tau + i] = 1;
    for (j = 0; j < tau && rc == 0; j++)
        rc = farkas_column(f, f + 1, j);
    for (i = 0; i < f->n && rc == 0; i++) {
        if (covers_other(f, i, tau))
            continue;
        memset(found[n], 0, sizeof found[n]);
        for (j = 0; j < rho; j++) {
            if (f->v[i][tau + j] > 127) {
                rc = NETC_ERR_INVARIANT;
                break;
            }
            found[n][j] = (int8_t)f->v[i][tau + j];
        }
        n++;
    }
    if (rc == 0 && n > PETRI_MAX_INVARIANTS)
        rc = NETC_ERR_INVARIANT;
    if (rc != 0)
        netc_say(err,
                 "the P-invariants exceed PETRI_MAX_INVARIANTS = %d or "
                 "NETC_MAX_FARKAS_ROWS = %d\n",
                 PETRI_MAX_INVARIANTS, NETC_MAX_FARKAS_ROWS);
    else {
        qsort(found, (size_t)n, sizeof found[0], inv_cmp);
        for (i = 0; i < n; i++)
            memcpy(&t->invariants[i * rho], found[i], (size_t)rho);
        t->n_invariants = n;
    }
    free(f);
    netc_task_bind(t);
    return rc;
}

static void print_invariants(const netc_task *t, FILE *out)
{
    int i, j;
    fprintf(out, "P-invariants (y^T C = 0, minimal, semi-positive): %d\n", t->n_invariants);
    for (i = 0; i < t->n_invariants; i++) {
        const int8_t *y = &t->invariants[i * t->n_places];
        int first = 1, sum = 0;
        fprintf(out, "  ");
        for (j = 0; j < t->n_places; j++)
            if (y[j]) {
                fprintf(out, "%s", first ? "" : " + ");
                if (y[j] > 1)
                    fprintf(out, "%d ", y[j]);
                fprintf(out, "%s", t->place_name[j]);
                sum += y[j] * t->m0[j];
                first = 0;
            }
        fprintf(out, " = %d\n", sum);
    }
}

/* ---- the checks ------------------------------------------------------------------ */

/* Every move of row j goes to a pose of its own arm. */
static int check_poses(const netc_task *t, int j, FILE *err)
{
    int a, k;
    for (a = 0; a < 2; a++)
        for (k = 0; k < t->rows[j].plan[a].n_segments; k++) {
            const carry_segment *s = &t->rows[j].plan[a].seg[k];
            if (s->kind == CARRY_SEG_MOVE && carry_pose_arm(s->pose) != a) {
                netc_say(err, "row %s: arm %d cannot go to %s, a pose of arm %d in the cell\n",
                         t->trans_name[j], a + 1, carry_pose_name(s->pose),
                         carry_pose_arm(s->pose) + 1);
                return NETC_ERR_TABLE;
            }
        }
    return NETC_OK;
}

/* The first transition without input places, -1 if none. */
static int first_source(const netc_task *t)
{
    int i, j;
    for (j = 0; j < t->n_transitions; j++) {
        for (i = 0; i < t->n_places && !t->n_minus[i * t->n_transitions + j]; i++)
            ;
        if (i == t->n_places)
            return j;
    }
    return -1;
}

/* The roles the supervisor finds the task by (taskdef.h), named when
 * one is missing: the net is then not a task it can run. */
static int check_roles(const netc_task *t, FILE *err)
{
    taskdef_roles r;
    const int rc = taskdef_roles_find(&t->net, &r), src = first_source(t);
    if (rc == TASKDEF_OK)
        return NETC_OK;
    if (rc == TASKDEF_ERR_SOURCE)
        netc_say(
            err,
            "refused: %s source transition (one without input places: the vision system adding a "
            "workpiece) where the supervisor needs exactly one (TASKDEF_ERR_SOURCE)\n",
            src < 0 ? "no" : "more than one");
    else if (rc == TASKDEF_ERR_SOURCE_PLACE)
        netc_say(
            err,
            "refused: source transition %s: it must fill exactly one place, and that place must "
            "inhibit it (one detection at a time) (TASKDEF_ERR_SOURCE_PLACE)\n",
            t->trans_name[src]);
    else
        netc_say(
            err,
            "refused: source transition %s: not exactly one transition takes the workpiece from the "
            "place it fills (TASKDEF_ERR_PICK)\n",
            t->trans_name[src]);
    return NETC_ERR_ROLES;
}

static int check_tables(netc_task *t, FILE *err)
{
    taskdef_health h;
    int j, rc = petri_net_validate(&t->net);
    if (rc != 0) {
        netc_say(err,
                 "petri_net_validate refuses the net (%d): a transition without "
                 "arcs or inhibited by its own input\n",
                 rc);
        return NETC_ERR_TABLE;
    }
    if (taskdef_health_find(t, &h) != TASKDEF_OK) {
        netc_say(
            err,
            "refused: the arms' health places (armK_up, armK_down): both or neither, one token "
            "between them, one fault (up -> down) and one recovery (down -> up) transition with "
            "no other arc, and no other transition taking or giving their token; other "
            "transitions test them by inhibitor arcs (TASKDEF_ERR_HEALTH)\n");
        return NETC_ERR_TABLE;
    }
    if ((rc = carry_table_validate_health(t->rows, t->n_transitions, &t->net, h.mask)) != 0) {
        netc_say(err,
                 "carry_table_validate refuses the rows (%d, CARRY_NET_ERR_*: "
                 "include/tandem/carry/carry_net.h)\n",
                 rc);
        return NETC_ERR_TABLE;
    }
    for (j = 0; j < t->n_transitions; j++)
        if (t->rows[j].arms && !carry_gains_within_table(&t->rows[j].lin, 0)) {
            netc_say(err,
                     "row %s: gains outside what the arms accept "
                     "(carry_gains_within_table: the shipped table's range)\n",
                     t->trans_name[j]);
            return NETC_ERR_TABLE;
        }
    for (j = 0; j < t->n_transitions; j++)
        if ((rc = check_poses(t, j, err)) != 0)
            return rc;
    return NETC_OK;
}

static int refuse(const netc_task *t, const explorer *x, int index, int rc, const char *what,
                  FILE *err)
{
    netc_say(err, "refused: %s\n", what);
    print_trace(t, x, index, err);
    return rc;
}

static int check_graph(netc_task *t, explorer *x, int bound, FILE *out, FILE *err)
{
    petri_report r;
    uint32_t fired = 0;
    char what[160];
    int i, j;
    if (petri_explore(&x->ws, &t->net, bound, &r) != 0)
        return NETC_ERR_TABLE;
    if (!r.complete) {
        netc_say(err, "refused: more than PETRI_MAX_STATES = %d reachable states\n",
                 PETRI_MAX_STATES);
        return NETC_ERR_STATES;
    }
    if (!r.bounded || (bound == 1 && !r.safe)) {
        snprintf(what, sizeof what, "a place holds more than %d token%s (bound %d%s)", bound,
                 bound == 1 ? "" : "s", bound, bound == 1 ? ": the net must be safe" : "");
        return refuse(t, x, r.unbounded_index >= 0 ? r.unbounded_index : r.unsafe_index,
                      NETC_ERR_UNBOUNDED, what, err);
    }
    if (r.deadlock)
        return refuse(t, x, r.dead_index, NETC_ERR_DEADLOCK,
                      "deadlock: a reachable marking enables no transition and none is running",
                      err);
    build_graph(t, x);
    for (i = 0; i < x->ws.n_states; i++)
        fired |= x->can[i];
    for (j = 0; j < t->n_transitions; j++)
        if (!(fired & (1u << j))) {
            netc_say(
                err,
                "refused: transition %s never fires (enabled in none of the %d reachable states)\n",
                t->trans_name[j], x->ws.n_states);
            return NETC_ERR_DEAD_TRANSITION;
        }
    close_can(t, x);
    for (j = 0; j < t->n_transitions; j++)
        for (i = 0; t->live[j] && i < x->ws.n_states; i++)
            if (!(x->can[i] & (1u << j))) {
                snprintf(what, sizeof what,
                         "transition %s is not live: after this it can never fire again",
                         t->trans_name[j]);
                return refuse(t, x, i, NETC_ERR_NOT_LIVE, what, err);
            }
    fprintf(out,
            "reachability: %d states (split firing: start and completion), bound %d: %s, "
            "deadlock-free, every transition fires, live:",
            r.n_states, bound, r.safe ? "safe" : "bounded");
    for (j = 0; j < t->n_transitions; j++)
        if (t->live[j])
            fprintf(out, " %s", t->trans_name[j]);
    fprintf(out, "\n");
    return NETC_OK;
}

/* NETC_BOUND_FROM_INVARIANTS: the largest y^T m0 / y_i over the
 * invariants y and the places i they cover, at least 1. */
static int invariant_bound(const netc_task *t)
{
    int k, i, b = 1;
    for (k = 0; k < t->n_invariants; k++) {
        const int8_t *y = &t->invariants[k * t->n_places];
        int sum = 0;
        for (i = 0; i < t->n_places; i++)
            sum += y[i] * t->m0[i];
        for (i = 0; i < t->n_places; i++)
            if (y[i] > 0 && sum / y[i] > b)
                b = sum / y[i];
    }
    return b < PETRI_TOKEN_MAX ? b : PETRI_TOKEN_MAX - 1;
}

int netc_check(netc_task *t, int bound, FILE *out, FILE *err)
{
    return netc_check_bound(t, bound, NULL, out, err);
}

int netc_check_bound(netc_task *t, int bound, int *bound_out, FILE *out, FILE *err)
{
    explorer *x = calloc(1, sizeof *x);
    int rc;
    if (!x)
        return NETC_ERR_IO;
    x->succ = calloc((size_t)PETRI_MAX_STATES * 2 * PETRI_MAX_TRANSITIONS, sizeof *x->succ);
    x->can = calloc(PETRI_MAX_STATES, sizeof *x->can);
    rc = (!x->succ || !x->can) ? NETC_ERR_IO : NETC_OK;
    if (rc == 0 && (bound < 0 || bound >= PETRI_TOKEN_MAX))
        rc = NETC_ERR_CAPACITY;
    if (rc == 0)
        rc = check_tables(t, err);
    if (rc == 0)
        rc = find_invariants(t, err);
    if (rc == 0 && bound == NETC_BOUND_FROM_INVARIANTS)
        bound = invariant_bound(t);
    if (bound_out)
        *bound_out = bound;
    if (rc == 0 && petri_net_validate(&t->net) != 0)
        rc = NETC_ERR_INVARIANT;
    if (rc == 0)
        rc = check_graph(t, x, bound, out, err);
    /* last: a net without the roles is refused by name, one with a
     * deadlock or an unbounded place by its counterexample first */
    if (rc == 0)
        rc = check_roles(t, err);
    if (rc == 0)
        print_invariants(t, out);
    free(x->succ);
    free(x->can);
    free(x);
    return rc;
}

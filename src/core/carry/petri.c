/* petri: Petri-net engine of docs/method/carry.md §5 (eq. 11, the seed's I_j / C_j
 * event-path planning, split start/complete firing, inhibitor arcs for
 * external token sources, P-invariant checks) and a fixed-capacity BFS
 * reachability explorer (safe / bounded / deadlock). petri_net_validate
 * checks a definition: 0/1 tables, every transition able to act, and every
 * invariant y a P-invariant of the incidence N = N+ - N- (y^T N = 0).
 * The engine keeps the marked places, the enabled transitions and each
 * invariant's sum, updated per event (§5.3, §5.4) rather than scanned.
 */
#include "petri.h"

#include <string.h>

#define VISIT_FULL (-1) /* visit: PETRI_MAX_STATES states held already */

static int8_t at(const int8_t *tab, const petri_net *n, int i, int j)
{
    return tab ? tab[i * n->n_transitions + j] : 0;
}

static int table_ok(const int8_t *tab, const petri_net *n)
{
    int k;
    if (!tab)
        return 1;
    for (k = 0; k < n->n_places * n->n_transitions; k++)
        if (tab[k] != 0 && tab[k] != 1)
            return 0;
    return 1;
}

/* y_k^T gamma + sum over running t_j of y_k^T N-_j (c->inv_in) */
static int inv_dot(const petri_compiled *c, int k, const petri_state *s)
{
    const petri_net *n = c->net;
    const int8_t *y = n->invariants + k * n->n_places;
    int i, j, v = 0;
    for (i = 0; i < n->n_places; i++)
        v += y[i] * s->m[i];
    for (j = 0; j < n->n_transitions; j++)
        if (s->running & (UINT32_C(1) << j))
            v += c->inv_in[k][j];
    return v;
}

/* What the engine needs of a net: its tables, sizes within the
 * capacities, 0/1 entries. 0, PETRI_ERR_ARG, _SIZE or _ENTRY. */
static int net_tables_check(const petri_net *n)
{
    if (!n || !n->n_minus || !n->n_plus || !n->m0)
        return PETRI_ERR_ARG;
    if (n->n_places < 1 || n->n_places > PETRI_MAX_PLACES || n->n_transitions < 1 ||
        n->n_transitions > PETRI_MAX_TRANSITIONS || n->n_invariants < 0 ||
        n->n_invariants > PETRI_MAX_INVARIANTS)
        return PETRI_ERR_SIZE;
    if (n->n_invariants > 0 && !n->invariants)
        return PETRI_ERR_ARG;
    if (!table_ok(n->n_minus, n) || !table_ok(n->n_plus, n) || !table_ok(n->n_inhibit, n))
        return PETRI_ERR_ENTRY;
    return 0;
}

/* Transition j has an arc and is not inhibited by one of its inputs. */
static int transition_can_act(const petri_net *n, int j)
{
    int i, arcs = 0;
    for (i = 0; i < n->n_places; i++) {
        arcs += at(n->n_minus, n, i, j) + at(n->n_plus, n, i, j);
        if (at(n->n_minus, n, i, j) && at(n->n_inhibit, n, i, j))
            return 0;
    }
    return arcs > 0;
}

/* Invariant k is non-zero and y^T N_j = 0 for every transition j. */
static int invariant_sound(const petri_net *n, int k)
{
    const int8_t *y = n->invariants + k * n->n_places;
    int i, j, nonzero = 0;
    for (i = 0; i < n->n_places; i++)
        nonzero |= y[i] != 0;
    for (j = 0; j < n->n_transitions; j++) {
        int flow = 0;
        for (i = 0; i < n->n_places; i++)
            flow += y[i] * (at(n->n_plus, n, i, j) - at(n->n_minus, n, i, j));
        if (flow != 0)
            return 0;
    }
    return nonzero;
}

int petri_net_validate(const petri_net *n)
{
    int j, k;
    const int r = net_tables_check(n);
    if (r != 0)
        return r;
    for (j = 0; j < n->n_transitions; j++)
        if (!transition_can_act(n, j))
            return PETRI_ERR_TRANSITION;
    for (k = 0; k < n->n_invariants; k++)
        if (!invariant_sound(n, k))
            return PETRI_ERR_INVARIANT;
    return 0;
}

int petri_compile(petri_compiled *c, const petri_net *n)
{
    petri_state s0;
    int i, j, k;
    if (!c || net_tables_check(n) != 0)
        return PETRI_ERR_ARG;
    memset(c, 0, sizeof *c);
    c->net = n;
    for (j = 0; j < n->n_transitions; j++) {
        for (i = 0; i < n->n_places; i++) {
            if (at(n->n_minus, n, i, j)) {
                c->n_in[j]++;
                c->in_mask[j] |= UINT32_C(1) << i;
            }
            if (at(n->n_plus, n, i, j))
                c->out_mask[j] |= UINT32_C(1) << i;
            if (at(n->n_inhibit, n, i, j))
                c->inhibit_mask[j] |= UINT32_C(1) << i;
        }
        for (k = 0; k < n->n_invariants; k++) {
            const int8_t *y = n->invariants + k * n->n_places;
            int in = 0, out = 0;
            for (i = 0; i < n->n_places; i++) {
                in += y[i] * at(n->n_minus, n, i, j);
                out += y[i] * at(n->n_plus, n, i, j);
            }
            c->inv_in[k][j] = (int16_t)in; /* |.| <= 32 * 128: fits */
            c->inv_step[k][j] = (int16_t)(out - in);
        }
    }
    for (j = 0; j < n->n_transitions; j++) {
        const uint32_t places = c->in_mask[j] | c->out_mask[j];
        c->touch[j] = UINT32_C(1) << j;
        for (k = 0; k < n->n_transitions; k++)
            if ((c->in_mask[k] | c->inhibit_mask[k]) & places)
                c->touch[j] |= UINT32_C(1) << k;
    }
    petri_state_initial(c, &s0);
    for (k = 0; k < n->n_invariants; k++)
        c->inv_value[k] = inv_dot(c, k, &s0);
    return 0;
}

void petri_state_initial(const petri_compiled *c, petri_state *s)
{
    int i;
    memset(s, 0, sizeof *s);
    for (i = 0; i < c->net->n_places; i++)
        s->m[i] = c->net->m0[i];
}

static int t_ok(const petri_compiled *c, int t)
{
    return c && c->net && t >= 0 && t < c->net->n_transitions;
}

static int inhibited(const petri_compiled *c, const petri_state *s, int t)
{
    int i;
    for (i = 0; i < c->net->n_places; i++)
        if (at(c->net->n_inhibit, c->net, i, t) && s->m[i] > 0)
            return 1;
    return 0;
}

int petri_state_enabled_scan(const petri_compiled *c, const petri_state *s, int t)
{
    const petri_net *n;
    int i, count = 0;
    if (!t_ok(c, t) || !s)
        return 0;
    n = c->net;
    if (s->running & (UINT32_C(1) << t))
        return 0;
    /* seed step 2: C_j counts marked inputs, stopping at the first
     * unmarked one; step 3: enabled iff C_j = I_j */
    for (i = 0; i < n->n_places; i++) {
        if (at(n->n_minus, n, i, t) > 0) {
            if (s->m[i] == 0)
                break;
            count++;
        }
    }
    return count == c->n_in[t] && !inhibited(c, s, t);
}

static uint32_t marked_mask(const petri_compiled *c, const petri_state *s)
{
    uint32_t m = 0;
    int i;
    for (i = 0; i < c->net->n_places; i++)
        if (s->m[i] > 0)
            m |= UINT32_C(1) << i;
    return m;
}

/* t not running, its inputs marked, its inhibitor places empty. */
static int enabled_by(const petri_compiled *c, uint32_t marked, uint32_t running, int t)
{
    return !(running & (UINT32_C(1) << t)) && (c->in_mask[t] & ~marked) == 0 &&
           (c->inhibit_mask[t] & marked) == 0;
}

int petri_state_enabled_mask(const petri_compiled *c, const petri_state *s, int t)
{
    if (!t_ok(c, t) || !s)
        return 0;
    return enabled_by(c, marked_mask(c, s), s->running, t);
}

int petri_state_invariant_violations(const petri_compiled *c, const petri_state *s)
{
    int k, bad = 0;
    for (k = 0; k < c->net->n_invariants; k++)
        if (inv_dot(c, k, s) != c->inv_value[k])
            bad++;
    return bad;
}

int petri_state_dead(const petri_compiled *c, const petri_state *s)
{
    int j;
    if (s->running)
        return 0;
    for (j = 0; j < c->net->n_transitions; j++)
        if (petri_state_enabled_mask(c, s, j))
            return 0;
    return 1;
}

/* State transitions shared by the engine and the explorer. N- and N+
 * are 0/1, so a start takes one token from each place of in_mask and a
 * completion puts one on each of out_mask. */

/* Start of t, enabled: returns the places it emptied. */
static uint32_t apply_start(const petri_compiled *c, petri_state *s, int t)
{
    const uint32_t in = c->in_mask[t];
    uint32_t emptied = 0;
    int i;
    for (i = 0; i < PETRI_MAX_PLACES && (in >> i) != 0; i++)
        if ((in >> i) & 1u) {
            s->m[i] = (uint8_t)(s->m[i] - 1u);
            if (s->m[i] == 0)
                emptied |= UINT32_C(1) << i;
        }
    s->running |= UINT32_C(1) << t;
    return emptied;
}

/* Completion of t: 0, PETRI_ERR_NOT_RUNNING or PETRI_ERR_OVERFLOW (then
 * s is unchanged). */
static int apply_complete(const petri_compiled *c, petri_state *s, int t)
{
    const uint32_t out = c->out_mask[t];
    int i;
    if (!(s->running & (UINT32_C(1) << t)))
        return PETRI_ERR_NOT_RUNNING;
    for (i = 0; i < PETRI_MAX_PLACES && (out >> i) != 0; i++)
        if (((out >> i) & 1u) && s->m[i] >= PETRI_TOKEN_MAX)
            return PETRI_ERR_OVERFLOW;
    for (i = 0; i < PETRI_MAX_PLACES && (out >> i) != 0; i++)
        if ((out >> i) & 1u)
            s->m[i] = (uint8_t)(s->m[i] + 1u);
    s->running &= ~(UINT32_C(1) << t);
    return 0;
}

static int state_start(const petri_compiled *c, petri_state *s, int t)
{
    if (!petri_state_enabled_mask(c, s, t))
        return PETRI_ERR_NOT_ENABLED;
    (void)apply_start(c, s, t);
    return 0;
}

/* ---- engine -------------------------------------------------------------*/

/* Re-checks the enabling of the transitions in mask. */
static void refresh_enabled(petri *p, uint32_t mask)
{
    int j;
    for (j = 0; j < PETRI_MAX_TRANSITIONS && (mask >> j) != 0; j++)
        if ((mask >> j) & 1u) {
            if (enabled_by(&p->c, p->marked, p->st.running, j))
                p->enabled |= UINT32_C(1) << j;
            else
                p->enabled &= ~(UINT32_C(1) << j);
        }
}

/* marked, enabled and inv_now of p->st, from scratch. */
static void derive_sets(petri *p)
{
    const int nt = p->c.net->n_transitions;
    int k;
    p->marked = marked_mask(&p->c, &p->st);
    p->enabled = 0;
    refresh_enabled(p, nt >= 32 ? UINT32_C(0xFFFFFFFF) : (UINT32_C(1) << nt) - 1u);
    for (k = 0; k < p->c.net->n_invariants; k++)
        p->inv_now[k] = inv_dot(&p->c, k, &p->st);
}

int petri_init(petri *p, const petri_net *net)
{
    if (!p || petri_compile(&p->c, net) != 0)
        return PETRI_ERR_ARG;
    petri_state_initial(&p->c, &p->st);
    derive_sets(p);
    p->invariant_violations = 0;
    p->last_fired = -1;
    p->fired_count = 0;
    return 0;
}

/* The lowest index of the kept enabled set: what the seed's scan
 * (petri_state_enabled_scan over j = 0..) picks, without the scan. */
int petri_select(const petri *p)
{
    int j;
    if (!p)
        return PETRI_ERR_NONE_ENABLED;
    for (j = 0; j < PETRI_MAX_TRANSITIONS && (p->enabled >> j) != 0; j++)
        if ((p->enabled >> j) & 1u)
            return j;
    return PETRI_ERR_NONE_ENABLED;
}

int petri_enabled(const petri *p, int t)
{
    return p && t_ok(&p->c, t) && (p->enabled & (UINT32_C(1) << t)) != 0;
}

int petri_running(const petri *p, int t)
{
    return p && t_ok(&p->c, t) && (p->st.running & (UINT32_C(1) << t)) != 0;
}

static int inv_hold(const petri *p)
{
    int k;
    for (k = 0; k < p->c.net->n_invariants; k++)
        if (p->inv_now[k] != p->c.inv_value[k])
            return 0;
    return 1;
}

static void check_invariants(petri *p)
{
    if (!inv_hold(p))
        p->invariant_violations++;
}

/* A start leaves every y^T gamma + in flight as it was: the tokens it
 * takes are in flight now. */
int petri_start(petri *p, int t)
{
    if (!p || !t_ok(&p->c, t))
        return PETRI_ERR_ARG;
    if (!(p->enabled & (UINT32_C(1) << t)))
        return PETRI_ERR_NOT_ENABLED;
    p->marked &= ~apply_start(&p->c, &p->st, t);
    refresh_enabled(p, p->c.touch[t]);
    check_invariants(p);
    return 0;
}

int petri_complete(petri *p, int t)
{
    int r, k;
    if (!p || !t_ok(&p->c, t))
        return PETRI_ERR_ARG;
    r = apply_complete(&p->c, &p->st, t);
    if (r != 0)
        return r;
    p->marked |= p->c.out_mask[t];
    for (k = 0; k < p->c.net->n_invariants; k++)
        p->inv_now[k] += p->c.inv_step[k][t];
    refresh_enabled(p, p->c.touch[t]);
    p->last_fired = t;
    p->fired_count++;
    check_invariants(p);
    return 0;
}

int petri_fire(petri *p, int t)
{
    petri_state keep;
    int r;
    if (!p || !t_ok(&p->c, t))
        return PETRI_ERR_ARG;
    keep = p->st;
    r = petri_start(p, t);
    if (r == 0) {
        r = petri_complete(p, t);
        if (r != 0) {
            p->st = keep; /* all or nothing */
            derive_sets(p);
        }
    }
    return r;
}

int petri_dead(const petri *p)
{
    return p ? p->st.running == 0 && p->enabled == 0 : 0;
}

static int running_ok(const petri *p, const petri_state *s)
{
    const int nt = p->c.net->n_transitions;
    const uint32_t all = nt >= 32 ? UINT32_C(0xFFFFFFFF) : (UINT32_C(1) << nt) - 1u;
    return (s->running & ~all) == 0;
}

int petri_set_state(petri *p, const petri_state *s)
{
    if (!p || !p->c.net || !s || !running_ok(p, s) ||
        petri_state_invariant_violations(&p->c, s) != 0)
        return PETRI_ERR_ARG;
    p->st = *s;
    derive_sets(p);
    return 0;
}

int petri_load_state(petri *p, const petri_state *s)
{
    if (!p || !p->c.net || !s || !running_ok(p, s))
        return PETRI_ERR_ARG;
    p->st = *s;
    derive_sets(p);
    return 0;
}

int petri_invariants_hold(const petri *p)
{
    return p && inv_hold(p);
}

/* ---- reachability ---------------------------------------------------------*/

static uint32_t state_hash(const petri_compiled *c, const petri_state *s)
{
    uint32_t h = UINT32_C(2166136261);
    int i;
    for (i = 0; i < c->net->n_places; i++)
        h = (h ^ s->m[i]) * UINT32_C(16777619);
    for (i = 0; i < 4; i++)
        h = (h ^ ((s->running >> (8 * i)) & 0xFFu)) * UINT32_C(16777619);
    return h;
}

static int state_eq(const petri_compiled *c, const petri_state *a, const petri_state *b)
{
    return a->running == b->running && memcmp(a->m, b->m, (size_t)c->net->n_places) == 0;
}

/* Adds s if new. Returns 1 added, 0 known, VISIT_FULL capacity exhausted. */
static int visit(petri_explore_ws *ws, const petri_state *s, int parent, int event)
{
    uint32_t h = state_hash(&ws->c, s) & (PETRI_HASH_SIZE - 1);
    while (ws->hash[h] != 0) {
        if (state_eq(&ws->c, &ws->states[ws->hash[h] - 1], s))
            return 0;
        h = (h + 1) & (PETRI_HASH_SIZE - 1);
    }
    if (ws->n_states >= PETRI_MAX_STATES)
        return VISIT_FULL;
    ws->states[ws->n_states] = *s;
    ws->parent[ws->n_states] = (int16_t)parent;
    ws->event[ws->n_states] = (int8_t)event;
    ws->n_states++;
    ws->hash[h] = (int16_t)ws->n_states;
    return 1;
}

static void note(int *first, int index)
{
    if (*first < 0)
        *first = index;
}

/* Records the properties of state k; returns 1 if it should be expanded. */
static int inspect(petri_explore_ws *ws, int k, int token_bound, petri_report *rep)
{
    const petri_state *s = &ws->states[k];
    int i, expand = 1;
    for (i = 0; i < ws->c.net->n_places; i++) {
        if (s->m[i] > rep->max_tokens)
            rep->max_tokens = s->m[i];
        if (s->m[i] > 1) {
            rep->safe = 0;
            note(&rep->unsafe_index, k);
        }
        if (s->m[i] > token_bound) {
            rep->bounded = 0;
            note(&rep->unbounded_index, k);
            expand = 0;
        }
    }
    if (petri_state_invariant_violations(&ws->c, s) > 0) {
        rep->invariant_states++;
        note(&rep->invariant_index, k);
    }
    if (petri_state_dead(&ws->c, s)) {
        rep->deadlock = 1;
        note(&rep->dead_index, k);
    }
    return expand;
}

int petri_explore(petri_explore_ws *ws, const petri_net *net, int token_bound, petri_report *rep)
{
    petri_state s0;
    int head, j;
    if (!ws || !rep || token_bound < 1 || token_bound >= PETRI_TOKEN_MAX)
        return PETRI_ERR_ARG;
    if (petri_compile(&ws->c, net) != 0)
        return PETRI_ERR_ARG;
    memset(ws->hash, 0, sizeof ws->hash);
    ws->n_states = 0;
    memset(rep, 0, sizeof *rep);
    rep->complete = rep->safe = rep->bounded = 1;
    rep->unsafe_index = rep->unbounded_index = rep->dead_index = rep->invariant_index = -1;
    petri_state_initial(&ws->c, &s0);
    visit(ws, &s0, -1, 0);
    for (head = 0; head < ws->n_states; head++) {
        if (!inspect(ws, head, token_bound, rep))
            continue;
        for (j = 0; j < net->n_transitions; j++) {
            petri_state nx = ws->states[head];
            int ev = 0;
            if (state_start(&ws->c, &nx, j) == 0)
                ev = j + 1;
            else if (apply_complete(&ws->c, &nx, j) == 0)
                ev = -(j + 1);
            if (ev != 0 && visit(ws, &nx, head, ev) == VISIT_FULL)
                rep->complete = 0;
        }
    }
    rep->n_states = ws->n_states;
    return 0;
}

int petri_explore_trace(const petri_explore_ws *ws, int index, int8_t *events, int max)
{
    int n = 0, k, i;
    if (!ws || !events || max < 0 || index < 0 || index >= ws->n_states)
        return PETRI_ERR_ARG;
    for (k = index; k > 0 && ws->parent[k] >= 0; k = ws->parent[k])
        n++;
    if (n > max)
        return PETRI_ERR_ARG;
    for (k = index, i = n - 1; i >= 0; k = ws->parent[k], i--)
        events[i] = ws->event[k];
    return n;
}

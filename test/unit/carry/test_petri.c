/* Unit tests for petri (docs/method/carry.md §5): eq. 11, the seed's enabling scan
 * against the bitmask test, split firing, invariants, the engine's kept
 * enabled set and invariant sums against the full scans (random firings
 * on random nets, every reachable state of the carry net), and
 * reachability (safe, unbounded, deadlock, capacity). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "carry_net.h"
#include "petri.h"

/* Two processes sharing two resources, taken in opposite order: the
 * classic reachable deadlock. Places: 0 A idle, 1 A has r1, 2 B idle,
 * 3 B has r2, 4 r1 free, 5 r2 free. Transitions: 0 A takes r1,
 * 1 A takes r2 and works then frees both, 2 B takes r2, 3 B takes r1
 * and frees both. */
#define DL_P 6
#define DL_T 4
static const int8_t DL_MINUS[DL_P * DL_T] = {
    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 1, 0,
};
static const int8_t DL_PLUS[DL_P * DL_T] = {
    0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 1,
};
static const uint8_t DL_M0[DL_P] = { 1, 0, 1, 0, 1, 1 };
/* A: p0 + p1 = 1; B: p2 + p3 = 1 */
static const int8_t DL_INV[2 * DL_P] = { 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0 };
static const petri_net DL = { DL_P, DL_T, DL_MINUS, DL_PLUS, NULL, DL_M0, 2, DL_INV };

/* A source feeding a place consumed by a sink that needs a second place:
 * unbounded without the inhibitor, safe with it. p0 buffer, p1 consumer
 * ready. t0 source (-> p0), t1 consume (p0, p1 -> p1). */
static const int8_t SRC_MINUS[2 * 2] = { 0, 1, 0, 1 };
static const int8_t SRC_PLUS[2 * 2] = { 1, 0, 0, 1 };
static const int8_t SRC_INHIB[2 * 2] = { 1, 0, 0, 0 };
static const uint8_t SRC_M0[2] = { 0, 1 };
static const petri_net SRC_FREE = { 2, 2, SRC_MINUS, SRC_PLUS, NULL, SRC_M0, 0, NULL };
static const petri_net SRC_GUARDED = { 2, 2, SRC_MINUS, SRC_PLUS, SRC_INHIB, SRC_M0, 0, NULL };

static petri_explore_ws WS; /* large: static */

static uint32_t rng_state = 12345u;
static uint32_t rnd(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state >> 8;
}

/* A random net of up to full size into the given tables: arcs with odds
 * 1 in arc_odds, inhibitor arcs 1 in 17 (used only if inhibit), no
 * invariants, an empty initial marking. */
static void random_net(petri_net *n, int arc_odds, int inhibit, int8_t *mi, int8_t *pl, int8_t *ih,
                       uint8_t *m0)
{
    int k;
    n->n_places = 1 + (int)(rnd() % PETRI_MAX_PLACES);
    n->n_transitions = 1 + (int)(rnd() % PETRI_MAX_TRANSITIONS);
    for (k = 0; k < n->n_places * n->n_transitions; k++) {
        mi[k] = (int8_t)(rnd() % (uint32_t)arc_odds == 0);
        pl[k] = (int8_t)(rnd() % (uint32_t)arc_odds == 0);
        ih[k] = (int8_t)(rnd() % 17 == 0);
    }
    memset(m0, 0, PETRI_MAX_PLACES);
    n->n_minus = mi;
    n->n_plus = pl;
    n->n_inhibit = inhibit ? ih : NULL;
    n->m0 = m0;
    n->n_invariants = 0;
    n->invariants = NULL;
}

/* Random nets of full size, random markings and running sets. */
static void test_scan_equals_mask(void **st)
{
    static int8_t mi[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static int8_t pl[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static int8_t ih[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static uint8_t m0[PETRI_MAX_PLACES];
    int trial, agree_enabled = 0;
    (void)st;
    for (trial = 0; trial < 200; trial++) {
        petri_net n;
        petri_compiled c;
        petri_state s;
        int k, j, i;
        random_net(&n, 5, trial % 2, mi, pl, ih, m0);
        assert_int_equal(petri_compile(&c, &n), 0);
        for (k = 0; k < 50; k++) {
            memset(&s, 0, sizeof s);
            for (i = 0; i < n.n_places; i++)
                s.m[i] = (uint8_t)(rnd() % 4 ? 1 + rnd() % 2 : 0);
            /* three draws: about one bit in eight set */
            /* NOLINTNEXTLINE(misc-redundant-expression) */
            s.running = (uint32_t)(rnd() & rnd() & rnd());
            if (n.n_transitions < 32)
                s.running &= (UINT32_C(1) << n.n_transitions) - 1;
            for (j = 0; j < n.n_transitions; j++) {
                int a = petri_state_enabled_scan(&c, &s, j);
                assert_int_equal(a, petri_state_enabled_mask(&c, &s, j));
                agree_enabled += a;
            }
        }
    }
    assert_true(agree_enabled > 100); /* both outcomes were exercised */
}

/* The engine's kept sets (enabled transitions, invariant sums) equal the
 * full scans of its state, and petri_select picks the scan's first. */
static void assert_sets_match_scan(const petri *p)
{
    int j, first = PETRI_ERR_NONE_ENABLED;
    for (j = 0; j < p->c.net->n_transitions; j++) {
        const int on = petri_state_enabled_scan(&p->c, &p->st, j);
        assert_int_equal(petri_enabled(p, j), on);
        if (on && first < 0)
            first = j;
    }
    assert_int_equal(petri_select(p), first); /* the seed's lowest-index pick */
    assert_int_equal(petri_invariants_hold(p),
                     petri_state_invariant_violations(&p->c, &p->st) == 0);
    assert_int_equal(petri_dead(p), petri_state_dead(&p->c, &p->st));
}

/* Random nets with random (mostly not conserved, so the checks see both
 * outcomes) invariants, 300 random starts, completions and firings each:
 * every result code, marking and violation count as a full-scan shadow
 * predicts, and the kept sets equal the scans after every event. */
static void test_incremental_equals_scan(void **st)
{
    static int8_t mi[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static int8_t pl[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static int8_t ih[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    static int8_t inv[PETRI_MAX_INVARIANTS * PETRI_MAX_PLACES];
    static uint8_t m0[PETRI_MAX_PLACES];
    static petri p;
    int trial, fired = 0, refused = 0, broken = 0;
    (void)st;
    for (trial = 0; trial < 100; trial++) {
        petri_net n;
        long viol = 0;
        int k, i;
        random_net(&n, 4, trial % 2, mi, pl, ih, m0);
        n.n_invariants = (int)(rnd() % (PETRI_MAX_INVARIANTS + 1));
        for (k = 0; k < n.n_invariants * n.n_places; k++)
            inv[k] = (int8_t)((int)(rnd() % 4) - 1);
        for (i = 0; i < n.n_places; i++)
            m0[i] = (uint8_t)(rnd() % 3);
        n.invariants = inv;
        assert_int_equal(petri_init(&p, &n), 0);
        assert_sets_match_scan(&p);
        for (k = 0; k < 300; k++) {
            const int t = (int)(rnd() % (uint32_t)n.n_transitions), op = (int)(rnd() % 3);
            const uint32_t bit = UINT32_C(1) << t;
            petri_state want = p.st;
            int r, expect = 0;
            if (op != 1 && !petri_state_enabled_scan(&p.c, &want, t))
                expect = PETRI_ERR_NOT_ENABLED;
            if (op != 1 && expect == 0) { /* start: N- taken, t running */
                for (i = 0; i < n.n_places; i++)
                    want.m[i] = (uint8_t)(want.m[i] - mi[i * n.n_transitions + t]);
                want.running |= bit;
                viol += petri_state_invariant_violations(&p.c, &want) > 0;
            }
            if (op != 0 && expect == 0) { /* completion: N+ put, t done */
                if (!(want.running & bit))
                    expect = PETRI_ERR_NOT_RUNNING;
                for (i = 0; i < n.n_places && expect == 0; i++)
                    if (want.m[i] + pl[i * n.n_transitions + t] > PETRI_TOKEN_MAX)
                        expect = PETRI_ERR_OVERFLOW;
                if (expect == 0) {
                    for (i = 0; i < n.n_places; i++)
                        want.m[i] = (uint8_t)(want.m[i] + pl[i * n.n_transitions + t]);
                    want.running &= ~bit;
                    viol += petri_state_invariant_violations(&p.c, &want) > 0;
                }
            }
            if (op == 2 && expect != 0) /* fire: all or nothing (a start's count stays) */
                want = p.st;
            r = op == 0 ? petri_start(&p, t) : op == 1 ? petri_complete(&p, t) : petri_fire(&p, t);
            assert_int_equal(r, expect);
            assert_memory_equal(p.st.m, want.m, sizeof want.m);
            assert_int_equal(p.st.running, want.running);
            assert_int_equal(p.invariant_violations, viol);
            assert_sets_match_scan(&p);
            fired += r == 0;
            refused += r != 0;
            broken += !petri_invariants_hold(&p);
        }
    }
    assert_true(fired > 1000 && refused > 1000 && broken > 100);
}

/* Every reachable state of the carry net and of the deadlock net, taken
 * into the engine, then every start and completion from it. */
static void sets_on_reachable(const petri_net *n)
{
    static petri p;
    petri_report r;
    int k, j;
    assert_int_equal(petri_explore(&WS, n, 4, &r), 0);
    assert_true(r.complete);
    assert_int_equal(petri_init(&p, n), 0);
    for (k = 0; k < WS.n_states; k++) {
        assert_int_equal(petri_load_state(&p, &WS.states[k]), 0);
        assert_sets_match_scan(&p);
        for (j = 0; j < n->n_transitions; j++) {
            assert_int_equal(petri_load_state(&p, &WS.states[k]), 0);
            if (petri_start(&p, j) == 0)
                assert_sets_match_scan(&p);
            assert_int_equal(petri_load_state(&p, &WS.states[k]), 0);
            if (petri_complete(&p, j) == 0)
                assert_sets_match_scan(&p);
        }
    }
}

static void test_incremental_on_reachable(void **st)
{
    petri p;
    petri_state s;
    (void)st;
    sets_on_reachable(&carry_net);
    sets_on_reachable(&DL);
    sets_on_reachable(&SRC_GUARDED);
    assert_int_equal(petri_init(&p, &DL), 0);
    s = p.st;
    s.running = UINT32_C(1) << DL_T; /* no such transition */
    assert_int_equal(petri_load_state(&p, &s), PETRI_ERR_ARG);
    assert_int_equal(petri_load_state(NULL, &s), PETRI_ERR_ARG);
}

/* eq. 11: gamma(k) = gamma(k-1) + (N+ - N-) t_j, and the split firing. */
static void test_fire_eq11_and_split(void **st)
{
    petri p;
    petri_state before;
    int i, t;
    (void)st;
    assert_int_equal(petri_init(&p, &DL), 0);
    assert_int_equal(petri_select(&p), 0); /* lowest index wins */
    before = p.st;
    assert_int_equal(petri_fire(&p, 0), 0);
    for (i = 0; i < DL_P; i++)
        assert_int_equal(p.st.m[i], before.m[i] + DL_PLUS[i * DL_T + 0] - DL_MINUS[i * DL_T + 0]);
    assert_int_equal(p.last_fired, 0);
    /* A holds r1; B may still start (t2) */
    t = 2;
    assert_int_equal(petri_start(&p, t), 0);
    assert_true(petri_running(&p, t));
    assert_int_equal(petri_start(&p, t), PETRI_ERR_NOT_ENABLED); /* no double start */
    assert_true(petri_invariants_hold(&p));                      /* tokens in flight counted */
    assert_int_equal(petri_complete(&p, 1), PETRI_ERR_NOT_RUNNING);
    assert_int_equal(petri_complete(&p, t), 0);
    assert_false(petri_running(&p, t));
    /* now A needs r2 (held by B) and B needs r1 (held by A): dead */
    assert_int_equal(petri_select(&p), PETRI_ERR_NONE_ENABLED);
    assert_true(petri_dead(&p));
    assert_int_equal(p.invariant_violations, 0);
    assert_int_equal(p.fired_count, 2);
    assert_int_equal(petri_start(&p, 99), PETRI_ERR_ARG);
    assert_int_equal(petri_fire(&p, -1), PETRI_ERR_ARG);
}

/* A saved state (a journal) comes back exactly; one that breaks a
 * P-invariant or names a transition the net lacks is refused and changes
 * nothing. */
static void test_set_state_round_trip(void **st)
{
    petri p, q;
    petri_state saved, bad;
    int i;
    (void)st;
    assert_int_equal(petri_init(&p, &DL), 0);
    assert_int_equal(petri_fire(&p, 0), 0);
    assert_int_equal(petri_start(&p, 2), 0); /* a transition in flight */
    saved = p.st;
    assert_int_equal(petri_init(&q, &DL), 0);
    assert_int_equal(petri_set_state(&q, &saved), 0);
    assert_memory_equal(q.st.m, saved.m, sizeof saved.m);
    assert_int_equal(q.st.running, saved.running);
    assert_int_equal(petri_complete(&q, 2), 0); /* and runs on from there */
    bad = saved;
    for (i = 0; i < DL_P; i++)
        bad.m[i] = 0; /* every token lost */
    assert_int_equal(petri_set_state(&p, &bad), PETRI_ERR_ARG);
    assert_int_equal(p.st.running, saved.running);
    assert_memory_equal(p.st.m, saved.m, sizeof saved.m);
    bad = saved;
    bad.running |= 1u << DL_T; /* no such transition */
    assert_int_equal(petri_set_state(&p, &bad), PETRI_ERR_ARG);
}

/* A wrong invariant is caught after the change that breaks it. */
static void test_invariant_violation_counted(void **st)
{
    static const int8_t bad_inv[DL_P] = { 1, 0, 0, 0, 0, 0 }; /* not y^T N = 0 */
    petri_net n = DL;
    petri p;
    (void)st;
    n.n_invariants = 1;
    n.invariants = bad_inv;
    assert_int_equal(petri_init(&p, &n), 0);
    assert_true(petri_invariants_hold(&p));
    assert_int_equal(petri_start(&p, 0), 0);
    assert_int_equal(p.invariant_violations, 0); /* in flight: still 1 */
    assert_int_equal(petri_complete(&p, 0), 0);
    assert_int_equal(p.invariant_violations, 1);
    assert_false(petri_invariants_hold(&p));
}

static void test_bad_tables(void **st)
{
    static const int8_t two[DL_P * DL_T] = { 2 };
    petri_net n = DL;
    petri p;
    (void)st;
    n.n_minus = two;
    assert_int_equal(petri_init(&p, &n), PETRI_ERR_ARG);
    n = DL;
    n.n_places = PETRI_MAX_PLACES + 1;
    assert_int_equal(petri_init(&p, &n), PETRI_ERR_ARG);
    n = DL;
    n.n_plus = NULL;
    assert_int_equal(petri_init(&p, &n), PETRI_ERR_ARG);
    n = DL;
    n.n_invariants = 1;
    n.invariants = NULL;
    assert_int_equal(petri_init(&p, &n), PETRI_ERR_ARG);
}

static void replay(const petri_net *n, const int8_t *ev, int len, petri *p)
{
    int i;
    assert_int_equal(petri_init(p, n), 0);
    for (i = 0; i < len; i++) {
        if (ev[i] > 0)
            assert_int_equal(petri_start(p, ev[i] - 1), 0);
        else
            assert_int_equal(petri_complete(p, -ev[i] - 1), 0);
    }
}

static void test_explore_deadlock(void **st)
{
    petri_report r;
    int8_t ev[64];
    int len;
    petri p;
    (void)st;
    assert_int_equal(petri_explore(&WS, &DL, 8, &r), 0);
    assert_true(r.complete && r.safe && r.bounded);
    assert_true(r.deadlock);
    assert_int_equal(r.invariant_states, 0);
    assert_true(r.dead_index > 0);
    /* the trace leads the engine to the reported dead state */
    len = petri_explore_trace(&WS, r.dead_index, ev, 64);
    assert_true(len > 0);
    replay(&DL, ev, len, &p);
    assert_true(petri_dead(&p));
    assert_memory_equal(p.st.m, WS.states[r.dead_index].m, DL_P);
}

static void test_explore_source_bounded_by_inhibitor(void **st)
{
    petri_report r;
    (void)st;
    assert_int_equal(petri_explore(&WS, &SRC_FREE, 5, &r), 0);
    assert_false(r.bounded);
    assert_false(r.safe);
    assert_true(r.unbounded_index >= 0);
    assert_true(WS.states[r.unbounded_index].m[0] > 5);
    assert_int_equal(petri_explore(&WS, &SRC_GUARDED, 5, &r), 0);
    assert_true(r.complete && r.safe && r.bounded);
    assert_false(r.deadlock);
    assert_int_equal(r.max_tokens, 1);
}

/* 12 independent toggles: 3^12 states > capacity, reported incomplete. */
static void test_explore_capacity(void **st)
{
    static int8_t mi[24 * 24], pl[24 * 24];
    static uint8_t m0[24];
    petri_net n;
    petri_report r;
    int k;
    (void)st;
    memset(mi, 0, sizeof mi);
    memset(pl, 0, sizeof pl);
    for (k = 0; k < 12; k++) {
        mi[(2 * k) * 24 + 2 * k] = 1; /* t2k: p2k -> p2k+1 */
        pl[(2 * k + 1) * 24 + 2 * k] = 1;
        mi[(2 * k + 1) * 24 + 2 * k + 1] = 1; /* t2k+1: back */
        pl[(2 * k) * 24 + 2 * k + 1] = 1;
        m0[2 * k] = 1;
    }
    n.n_places = 24;
    n.n_transitions = 24;
    n.n_minus = mi;
    n.n_plus = pl;
    n.n_inhibit = NULL;
    n.m0 = m0;
    n.n_invariants = 0;
    n.invariants = NULL;
    assert_int_equal(petri_explore(&WS, &n, 4, &r), 0);
    assert_false(r.complete);
    assert_int_equal(r.n_states, PETRI_MAX_STATES);
    assert_int_equal(petri_explore(&WS, &n, 0, &r), PETRI_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scan_equals_mask),
        cmocka_unit_test(test_incremental_equals_scan),
        cmocka_unit_test(test_incremental_on_reachable),
        cmocka_unit_test(test_fire_eq11_and_split),
        cmocka_unit_test(test_invariant_violation_counted),
        cmocka_unit_test(test_set_state_round_trip),
        cmocka_unit_test(test_bad_tables),
        cmocka_unit_test(test_explore_deadlock),
        cmocka_unit_test(test_explore_source_bounded_by_inhibitor),
        cmocka_unit_test(test_explore_capacity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for carry_net (docs/method/carry.md §5, 2.5): reachability of the carry
 * net, pipelining, the one-workpiece cycle, a randomised concurrent
 * supervisor, and the lookup table's gains on the point-mass loop. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>
#include <math.h>

#include "carry_net.h"
#include "erlaw.h"
#include "vec3.h"

static petri_explore_ws WS;

#define BIT(t) (UINT32_C(1) << (t))

static void test_reachability(void **st)
{
    petri_report r;
    int k;
    (void)st;
    assert_int_equal(petri_explore(&WS, &carry_net, 4, &r), 0);
    assert_true(r.complete);
    assert_true(r.safe);
    assert_true(r.bounded);
    assert_false(r.deadlock);
    assert_int_equal(r.invariant_states, 0);
    assert_int_equal(r.max_tokens, 1);
    assert_true(r.n_states > 10);
    /* independently of the explorer's own check: both invariants with
     * tokens of running transitions counted at their inputs */
    for (k = 0; k < r.n_states; k++) {
        const petri_state *s = &WS.states[k];
        int arm1 = s->m[CARRY_P3] + s->m[CARRY_P4] + s->m[CARRY_P5] + s->m[CARRY_P6] +
                   s->m[CARRY_P7];
        int arm2 = s->m[CARRY_P2] + s->m[CARRY_P6] + s->m[CARRY_P8] + s->m[CARRY_P9];
        int j;
        for (j = 0; j < CARRY_N_TRANSITIONS; j++) {
            if (!(s->running & BIT(j)))
                continue;
            if (carry_table[j].arms & CARRY_ARM1)
                arm1++;
            if (carry_table[j].arms & CARRY_ARM2)
                arm2++;
        }
        assert_int_equal(arm1, 1);
        assert_int_equal(arm2, 1);
        /* an arm never runs two actions at once */
        for (j = 0; j < CARRY_N_TRANSITIONS; j++) {
            int i;
            for (i = j + 1; i < CARRY_N_TRANSITIONS; i++)
                if ((s->running & BIT(j)) && (s->running & BIT(i)))
                    assert_int_equal(carry_table[i].arms & carry_table[j].arms, 0);
        }
    }
}

/* Pipelining: arm 1 fetches the next workpiece (t1) while arm 2 is still
 * delivering (t5, t7). */
static void test_pipelining(void **st)
{
    petri_report r;
    int k, t1_t5 = 0, t1_t7 = 0, t2_t5 = 0;
    (void)st;
    assert_int_equal(petri_explore(&WS, &carry_net, 4, &r), 0);
    for (k = 0; k < r.n_states; k++) {
        uint32_t run = WS.states[k].running;
        t1_t5 |= (run & BIT(CARRY_T1)) && (run & BIT(CARRY_T5));
        t1_t7 |= (run & BIT(CARRY_T1)) && (run & BIT(CARRY_T7));
        t2_t5 |= (run & BIT(CARRY_T2)) && (run & BIT(CARRY_T5));
    }
    assert_true(t1_t5 && t1_t7 && t2_t5);
}

/* One workpiece: t1..t7 plus vision's new token returns to gamma0; each
 * step is the seed's lowest-index choice once t1 is done. */
static void test_one_workpiece_cycle(void **st)
{
    static const int seq[] = { CARRY_T1, CARRY_T2, CARRY_T3, CARRY_T4,
                               CARRY_T5, CARRY_T6, CARRY_T7, CARRY_T_VISION };
    petri p;
    size_t k;
    (void)st;
    assert_int_equal(petri_init(&p, &carry_net), 0);
    assert_int_equal(petri_select(&p), CARRY_T1);
    assert_false(petri_enabled(&p, CARRY_T_VISION)); /* p1 full: inhibited */
    for (k = 0; k < sizeof seq / sizeof seq[0]; k++) {
        assert_true(petri_enabled(&p, seq[k]));
        assert_int_equal(petri_fire(&p, seq[k]), 0);
        assert_true(petri_invariants_hold(&p));
    }
    assert_memory_equal(p.st.m, carry_net.m0, CARRY_N_PLACES);
    assert_int_equal(p.st.running, 0);
    assert_int_equal(p.invariant_violations, 0);
}

/* A supervisor that starts every enabled transition (lowest index first)
 * and completes running ones in random order: it never deadlocks, the
 * invariants hold after every event, and workpieces keep flowing. */
static void test_random_supervisor(void **st)
{
    uint32_t rng = 99u;
    petri p;
    int ev, delivered = 0;
    (void)st;
    assert_int_equal(petri_init(&p, &carry_net), 0);
    for (ev = 0; ev < 20000; ev++) {
        int t;
        while ((t = petri_select(&p)) >= 0)
            assert_int_equal(petri_start(&p, t), 0);
        assert_false(petri_dead(&p));
        assert_true(p.st.running != 0);
        do {
            rng = rng * 1664525u + 1013904223u;
            t = (int)((rng >> 8) % CARRY_N_TRANSITIONS);
        } while (!petri_running(&p, t));
        assert_int_equal(petri_complete(&p, t), 0);
        delivered += t == CARRY_T7;
    }
    assert_int_equal(p.invariant_violations, 0);
    assert_true(delivered > 500);
}

static void test_table_consistent(void **st)
{
    int t, a;
    (void)st;
    assert_null(carry_row_of(-1));
    assert_null(carry_row_of(CARRY_N_TRANSITIONS));
    for (t = 0; t < CARRY_N_TRANSITIONS; t++) {
        const carry_row *row = carry_row_of(t);
        int n_arms = 0;
        assert_non_null(row);
        assert_int_equal(erlaw_gains_validate(&row->lin), 0);
        for (a = 0; a < 2; a++) {
            const carry_arm_plan *pl = &row->plan[a];
            int k, last_pose = CARRY_POSE_NONE;
            int used = (row->arms >> a) & 1u;
            n_arms += used;
            assert_true(pl->n_segments >= 0 && pl->n_segments <= CARRY_MAX_SEGMENTS);
            assert_int_equal(pl->n_segments > 0, used);
            for (k = 0; k < pl->n_segments; k++)
                if (pl->seg[k].kind == CARRY_SEG_MOVE) {
                    assert_true(pl->seg[k].pose > CARRY_POSE_NONE &&
                                pl->seg[k].pose < CARRY_N_POSES);
                    last_pose = pl->seg[k].pose;
                }
            assert_int_equal(last_pose, row->target_pose[a]);
        }
        /* only t3 is synchronised, and it is the only two-arm motion */
        assert_int_equal(row->sync_group != 0, t == CARRY_T3);
        if (t == CARRY_T_VISION)
            assert_int_equal(n_arms, 0);
        else
            assert_true(n_arms >= 1);
    }
    assert_true(carry_pose_from_vision(carry_table[CARRY_T1].target_pose[0]));
    assert_int_equal(carry_table[CARRY_T1].arms, CARRY_ARM1);
    assert_int_equal(carry_table[CARRY_T5].arms, CARRY_ARM2);
    assert_int_equal(carry_table[CARRY_T4].plan[0].after_partner, 1);
    assert_string_equal(carry_pose_name(CARRY_POSE_HANDOVER_2), "HANDOVER_2");
    /* every pose belongs to one arm, and a name ending _1 or _2 says which */
    assert_int_equal(carry_pose_arm(CARRY_POSE_NONE), -1);
    assert_int_equal(carry_pose_arm(CARRY_N_POSES), -1);
    for (t = 1; t < CARRY_N_POSES; t++) {
        const char *name = carry_pose_name(t);
        const size_t len = strlen(name);
        const int arm = carry_pose_arm(t);
        assert_true(arm == 0 || arm == 1);
        if (len > 2 && name[len - 2] == '_' && (name[len - 1] == '1' || name[len - 1] == '2'))
            assert_int_equal(arm, name[len - 1] - '1');
    }
    assert_int_equal(carry_pose_arm(CARRY_POSE_ABOVE_WORKPIECE), 0);
    assert_int_equal(carry_pose_arm(CARRY_POSE_AT_MAGAZINE), 1);
    assert_int_equal(erlaw_gains_validate(&carry_rot_gains), 0);
}

/* Point-mass run of one segment; returns the time to done (within
 * tol_s), or 1e9. */
static double point_mass_segment(const erlaw_gains *g, double len_m, double disturbance,
                                 double tol_s)
{
    const double p0[3] = { 0.3, 0.1, 0.4 };
    double p1[3], x[3], v[3] = { 0, 0, 0 }, t = 0.0, s_raw_max = 0.0;
    erlaw_line l;
    vec3_set(p1, p0[0] + 0.6 * len_m, p0[1] - 0.8 * len_m, p0[2]);
    assert_int_equal(erlaw_line_init(&l, p0, p1, g), 0);
    vec3_copy(x, p0);
    while (t < 30.0) {
        erlaw_out o;
        double d[3];
        int i;
        if (erlaw_done(erlaw_line_s(&l, x), len_m, vec3_norm(v), tol_s, 5e-3))
            break;
        assert_int_equal(erlaw_line_step(&l, x, v, ERLAW_REF_MEASURED, 0.0, 1e-3, &o), 0);
        for (i = 0; i < 3; i++) {
            /* an unmodelled constant acceleration error opposing the move */
            v[i] += (o.u[i] - disturbance * l.ch.e[i]) * 1e-3;
            x[i] += v[i] * 1e-3;
        }
        vec3_sub(d, x, p0);
        s_raw_max = fmax(s_raw_max, vec3_dot(d, l.ch.e));
        t += 1e-3;
    }
    assert_true(s_raw_max <= len_m + 2e-3); /* no overshoot */
    return t < 30.0 ? t : 1e9;
}

/* Every row's gains bring the loop to rest at the goal. Against an
 * opposing model error d (here half the bias) the arm still starts and
 * comes to rest short of the goal by about d / (k_v sqrt(u_m)): along
 * the path eq. 6 has no position term (X_d is taken at the measured s),
 * only k_v V_d(s) ~ k_v sqrt(u_m) (s_f - s) near the end resists d. */
static void test_gains_on_point_mass(void **st)
{
    int t;
    (void)st;
    for (t = 0; t < CARRY_T_VISION; t++) {
        const erlaw_gains *g = &carry_table[t].lin;
        const double d = 0.5 * g->k0, offset = d / (g->k_v * sqrt(g->u_m));
        assert_true(point_mass_segment(g, 0.08, 0.0, 1e-3) < 5.0);
        assert_true(point_mass_segment(g, 0.5, 0.0, 1e-3) < 10.0);
        assert_true(point_mass_segment(g, 0.5, d, offset + 1e-3) < 15.0);
        assert_true(point_mass_segment(g, 0.08, d, offset + 1e-3) < 10.0);
    }
}

/* A writable copy of carry_net, to break one thing at a time. */
typedef struct {
    petri_net net;
    int8_t minus[CARRY_N_PLACES * CARRY_N_TRANSITIONS];
    int8_t plus[CARRY_N_PLACES * CARRY_N_TRANSITIONS];
    int8_t inhibit[CARRY_N_PLACES * CARRY_N_TRANSITIONS];
    int8_t inv[CARRY_N_INVARIANTS * CARRY_N_PLACES];
} net_copy;

static void net_copy_init(net_copy *c)
{
    memcpy(c->minus, carry_net.n_minus, sizeof c->minus);
    memcpy(c->plus, carry_net.n_plus, sizeof c->plus);
    memcpy(c->inhibit, carry_net.n_inhibit, sizeof c->inhibit);
    memcpy(c->inv, carry_net.invariants, sizeof c->inv);
    c->net = carry_net;
    c->net.n_minus = c->minus;
    c->net.n_plus = c->plus;
    c->net.n_inhibit = c->inhibit;
    c->net.invariants = c->inv;
}

#define AT(p, t) ((p)*CARRY_N_TRANSITIONS + (t))

static void test_net_validate(void **st)
{
    net_copy c;
    (void)st;
    assert_int_equal(petri_net_validate(&carry_net), 0);
    net_copy_init(&c);
    assert_int_equal(petri_net_validate(&c.net), 0);
    assert_int_equal(petri_net_validate(NULL), PETRI_ERR_ARG);

    c.net.n_minus = NULL;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_ARG);
    net_copy_init(&c);
    c.net.n_transitions = PETRI_MAX_TRANSITIONS + 1;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_SIZE);
    net_copy_init(&c);
    c.net.n_invariants = -1;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_SIZE);
    net_copy_init(&c);
    c.plus[AT(CARRY_P4, CARRY_T1)] = 2;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_ENTRY);
    net_copy_init(&c);
    c.inhibit[AT(CARRY_P9, CARRY_T2)] = -1;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_ENTRY);
    net_copy_init(&c);
    c.minus[AT(CARRY_P8, CARRY_T5)] = 0; /* t5 left without arcs */
    c.plus[AT(CARRY_P9, CARRY_T5)] = 0;
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_TRANSITION);
    net_copy_init(&c);
    c.inhibit[AT(CARRY_P1, CARRY_T1)] = 1; /* t1 needs p1 marked and empty */
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_TRANSITION);
    net_copy_init(&c);
    c.plus[AT(CARRY_P7, CARRY_T4)] = 0; /* arm 1's token lost at the hand-over */
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_INVARIANT);
    net_copy_init(&c);
    c.inv[CARRY_P1] = 1; /* p1 is not part of arm 1's cycle */
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_INVARIANT);
    net_copy_init(&c);
    memset(c.inv + CARRY_N_PLACES, 0, CARRY_N_PLACES);
    assert_int_equal(petri_net_validate(&c.net), PETRI_ERR_INVARIANT);
}

static void test_table_validate(void **st)
{
    carry_row r[CARRY_N_TRANSITIONS];
    net_copy c;
    (void)st;
#define FRESH() memcpy(r, carry_table, sizeof r)
#define EXPECT(code) \
    assert_int_equal(carry_table_validate(r, CARRY_N_TRANSITIONS, &carry_net), (code))
    assert_int_equal(carry_table_validate(carry_table, CARRY_N_TRANSITIONS, &carry_net), 0);
    assert_int_equal(carry_table_validate(NULL, CARRY_N_TRANSITIONS, &carry_net),
                     CARRY_NET_ERR_ARG);
    assert_int_equal(carry_table_validate(carry_table, CARRY_N_TRANSITIONS, NULL),
                     CARRY_NET_ERR_ARG);
    assert_int_equal(carry_table_validate(carry_table, CARRY_N_TRANSITIONS - 1, &carry_net),
                     CARRY_NET_ERR_SIZE);
    FRESH();
    r[CARRY_T2].plan[0].n_segments = CARRY_MAX_SEGMENTS + 1;
    EXPECT(CARRY_NET_ERR_SIZE);
    FRESH();
    r[CARRY_T1].name = NULL;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T1].arms = 4u;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T3].sync_group = -1;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T1].plan[0].seg[0].pose = CARRY_N_POSES;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T1].plan[0].seg[0].kind = 1;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T4].gripper[1] = 7;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T4].plan[0].after_partner = 2;
    EXPECT(CARRY_NET_ERR_RANGE);
    FRESH();
    r[CARRY_T1].lin.v_m = 0.0;
    EXPECT(CARRY_NET_ERR_GAINS);
    FRESH();
    r[CARRY_T5].lin.k_p = NAN;
    EXPECT(CARRY_NET_ERR_GAINS);
    FRESH();
    r[CARRY_T6].target_pose[0] = CARRY_POSE_CLEAR_1;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T2].gripper[0] = CARRY_GRIP_OPEN;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T1].arms = CARRY_ARM1 | CARRY_ARM2;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T4].plan[1].after_partner = 1;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T1].sync_group = 1;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T1].plan[0].seg[0].kind = CARRY_SEG_GRASP;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
    FRESH();
    r[CARRY_T5].plan[1].seg[0].pose = CARRY_POSE_NONE;
    EXPECT(CARRY_NET_ERR_INCONSISTENT);
#undef EXPECT
    /* rows against their transitions: t1 made a source (no input place)
     * while its row still moves arm 1; and a net that is not sound */
    FRESH();
    net_copy_init(&c);
    c.minus[AT(CARRY_P1, CARRY_T1)] = c.minus[AT(CARRY_P3, CARRY_T1)] = 0;
    c.net.n_invariants = 0;
    assert_int_equal(petri_net_validate(&c.net), 0);
    assert_int_equal(carry_table_validate(r, CARRY_N_TRANSITIONS, &c.net), CARRY_NET_ERR_NET);
    net_copy_init(&c);
    c.plus[AT(CARRY_P7, CARRY_T4)] = 0;
    assert_int_equal(carry_table_validate(r, CARRY_N_TRANSITIONS, &c.net), CARRY_NET_ERR_NET);
#undef FRESH
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reachability),        cmocka_unit_test(test_pipelining),
        cmocka_unit_test(test_one_workpiece_cycle), cmocka_unit_test(test_random_supervisor),
        cmocka_unit_test(test_table_consistent),    cmocka_unit_test(test_net_validate),
        cmocka_unit_test(test_table_validate),      cmocka_unit_test(test_gains_on_point_mass),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for taskdef (docs/tasks.md §7): the roles found from the
 * carry net's structure are the carry's own indices, the same net with
 * its places and transitions in another order gives the permuted roles,
 * and every way a net can lack a role is refused with its own code. The
 * digest a journal records (taskdef_digest) is the carry's for a copy of
 * it, whatever its names, and another for any other arc, marking or row. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "taskdef.h"

#define NP CARRY_N_PLACES
#define NT CARRY_N_TRANSITIONS

/* The carry net copied into a task's fixed tables, places and
 * transitions renumbered by pp (new index of place i) and pt. */
static void task_from_carry(taskdef *t, const int pp[NP], const int pt[NT])
{
    int i, j;
    memset(t, 0, sizeof *t);
    t->n_places = NP;
    t->n_transitions = NT;
    t->has_inhibit = 1;
    for (i = 0; i < NP; i++) {
        t->m0[pp[i]] = carry_net.m0[i];
        for (j = 0; j < NT; j++) {
            const int src = i * NT + j, dst = pp[i] * NT + pt[j];
            t->n_minus[dst] = carry_net.n_minus[src];
            t->n_plus[dst] = carry_net.n_plus[src];
            t->n_inhibit[dst] = carry_net.n_inhibit[src];
        }
    }
    for (j = 0; j < NT; j++)
        t->rows[pt[j]] = carry_table[j];
    taskdef_bind(t);
}

static const int ID_P[NP] = { 0, 1, 2, 3, 4, 5, 6, 7, 8 };
static const int ID_T[NT] = { 0, 1, 2, 3, 4, 5, 6, 7 };

static void test_roles_of_the_carry(void **st)
{
    taskdef_roles r;
    (void)st;
    assert_int_equal(taskdef_validate(&carry_net, carry_table, &r), TASKDEF_OK);
    assert_int_equal(r.source, CARRY_T_VISION);
    assert_int_equal(r.source_place, CARRY_P1);
    assert_int_equal(r.pick, CARRY_T1);
}

/* The same task, copied and renamed: the same digest; one arc, one
 * token, one gain, one segment or a renumbering: another. */
static void test_digest(void **st)
{
    static taskdef t;
    static const int pt[NT] = { 1, 0, 2, 3, 4, 5, 6, 7 };
    const uint64_t carry = taskdef_digest(&carry_net, carry_table);
    (void)st;
    assert_true(carry != 0);
    task_from_carry(&t, ID_P, ID_T);
    snprintf(t.task, sizeof t.task, "renamed");
    t.rows[0].name = "another name";
    assert_true(taskdef_digest(&t.net, t.rows) == carry);
    /* the digest of the net alone is not the task's */
    assert_true(taskdef_digest(&t.net, NULL) != carry);
    t.rows[0].lin.v_m *= 1.0000001;
    assert_true(taskdef_digest(&t.net, t.rows) != carry);
    task_from_carry(&t, ID_P, ID_T);
    t.rows[2].plan[1].seg[0].pose = (int8_t)(t.rows[2].plan[1].seg[0].pose + 1);
    assert_true(taskdef_digest(&t.net, t.rows) != carry);
    task_from_carry(&t, ID_P, ID_T);
    t.m0[3] = (uint8_t)(t.m0[3] + 1);
    assert_true(taskdef_digest(&t.net, t.rows) != carry);
    task_from_carry(&t, ID_P, ID_T);
    t.n_inhibit[0] = (int8_t)!t.n_inhibit[0];
    assert_true(taskdef_digest(&t.net, t.rows) != carry);
    task_from_carry(&t, ID_P, pt);
    assert_true(taskdef_digest(&t.net, t.rows) != carry);
    assert_true(taskdef_digest(NULL, carry_table) == 0);
}

/* The roles follow the structure, not the order of the tables. */
static void test_roles_permuted(void **st)
{
    static taskdef t;
    static const int pp[NP] = { 8, 0, 7, 1, 6, 2, 5, 3, 4 };
    static const int pt[NT] = { 7, 6, 5, 4, 3, 2, 1, 0 };
    taskdef_roles r;
    (void)st;
    task_from_carry(&t, pp, pt);
    assert_int_equal(taskdef_validate(&t.net, t.rows, &r), TASKDEF_OK);
    assert_int_equal(r.source, pt[CARRY_T_VISION]);
    assert_int_equal(r.source_place, pp[CARRY_P1]);
    assert_int_equal(r.pick, pt[CARRY_T1]);
}

/* One entry of the carry's net changed, and the role it takes away. */
typedef struct {
    int table; /* 0 N-, 1 N+, 2 inhibitor */
    int place, transition, value;
    int expect;
} role_edit;

static const role_edit EDITS[] = {
    { 0, CARRY_P9, CARRY_T_VISION, 1, TASKDEF_ERR_SOURCE }, /* no source: vision fed from p9 too */
    { 0, CARRY_P7, CARRY_T6, 0, TASKDEF_ERR_SOURCE },       /* two: t6 takes nothing from p7 */
    { 1, CARRY_P9, CARRY_T_VISION, 1, TASKDEF_ERR_SOURCE_PLACE }, /* the source fills two places */
    { 2, CARRY_P1, CARRY_T_VISION, 0, TASKDEF_ERR_SOURCE_PLACE }, /* not inhibited by its place */
    { 0, CARRY_P1, CARRY_T2, 1, TASKDEF_ERR_PICK }, /* two transitions take the token */
    { 0, CARRY_P1, CARRY_T1, 0, TASKDEF_ERR_PICK }, /* none takes it */
};

static void test_roles_refused(void **st)
{
    static taskdef t;
    taskdef_roles r;
    int k;
    (void)st;
    assert_int_equal(taskdef_roles_find(NULL, &r), TASKDEF_ERR_ARG);
    assert_int_equal(taskdef_roles_find(&carry_net, NULL), TASKDEF_ERR_ARG);
    assert_int_equal(taskdef_validate(NULL, carry_table, &r), TASKDEF_ERR_ARG);

    for (k = 0; k < (int)(sizeof EDITS / sizeof EDITS[0]); k++) {
        const role_edit *e = &EDITS[k];
        int8_t *tab;
        task_from_carry(&t, ID_P, ID_T);
        tab = e->table == 0 ? t.n_minus : e->table == 1 ? t.n_plus : t.n_inhibit;
        tab[e->place * NT + e->transition] = e->value;
        assert_int_equal(taskdef_roles_find(&t.net, &r), e->expect);
        assert_int_equal(r.source, -1);
    }
    /* the validators come first */
    task_from_carry(&t, ID_P, ID_T);
    t.n_plus[CARRY_P7 * NT + CARRY_T4] = 0;
    t.n_invariants = 1;
    memcpy(t.invariants, carry_net.invariants, NP);
    taskdef_bind(&t);
    assert_int_equal(taskdef_validate(&t.net, t.rows, &r), TASKDEF_ERR_NET);
    task_from_carry(&t, ID_P, ID_T);
    t.rows[CARRY_T1].lin.v_m = 0.0;
    assert_int_equal(taskdef_validate(&t.net, t.rows, &r), TASKDEF_ERR_TABLE);
}

static void test_sets_down(void **st)
{
    carry_row r;
    int t;
    (void)st;
    /* the carry hands over (t4: arm 2 grasps) and delivers (t7: at the
     * release pose): nothing is set down elsewhere */
    for (t = 0; t < NT; t++) {
        assert_false(carry_row_sets_down(&carry_table[t], 0));
        assert_false(carry_row_sets_down(&carry_table[t], 1));
    }
    /* arm 1 releasing at the hand-over with arm 2 not grasping */
    r = carry_table[CARRY_T4];
    r.plan[1].n_segments = 0;
    r.plan[0].n_segments = 2;
    r.plan[0].seg[0].kind = CARRY_SEG_MOVE;
    r.plan[0].seg[0].pose = CARRY_POSE_HANDOVER_1;
    r.plan[0].seg[1].kind = CARRY_SEG_RELEASE;
    r.plan[0].seg[1].pose = CARRY_POSE_NONE;
    assert_true(carry_row_sets_down(&r, 0));
    assert_false(carry_row_sets_down(&r, 1));
    assert_false(carry_row_sets_down(NULL, 0));
    assert_false(carry_row_sets_down(&r, 2));
}

/* The carry with arm 1's health: places 9 arm1_up (1 token), 10 arm1_down,
 * transitions 8 (fault) and 9 (recovery) moving no arm, t1 inhibited by
 * arm1_down. */
static void task_with_health(taskdef *t)
{
    const int np = NP + 2, nt = NT + 2;
    int i, j;
    memset(t, 0, sizeof *t);
    t->n_places = np;
    t->n_transitions = nt;
    t->has_inhibit = 1;
    for (i = 0; i < NP; i++) {
        t->m0[i] = carry_net.m0[i];
        for (j = 0; j < NT; j++) {
            t->n_minus[i * nt + j] = carry_net.n_minus[i * NT + j];
            t->n_plus[i * nt + j] = carry_net.n_plus[i * NT + j];
            t->n_inhibit[i * nt + j] = carry_net.n_inhibit[i * NT + j];
        }
    }
    for (j = 0; j < NT; j++)
        t->rows[j] = carry_table[j];
    strcpy(t->place_name[NP], "arm1_up");
    strcpy(t->place_id[NP + 1], "arm1_down"); /* by id too */
    t->m0[NP] = 1;
    t->n_minus[NP * nt + NT] = t->n_plus[(NP + 1) * nt + NT] = 1;         /* fault   */
    t->n_minus[(NP + 1) * nt + NT + 1] = t->n_plus[NP * nt + NT + 1] = 1; /* recover */
    t->n_inhibit[(NP + 1) * nt + CARRY_T1] = 1;
    t->rows[NT] = carry_table[CARRY_T_VISION];
    t->rows[NT + 1] = carry_table[CARRY_T_VISION];
    taskdef_bind(t);
}

/* The arms' health places: none in the carry; found by name in a net that
 * has them; refused when one is missing, the token is doubled or a row
 * takes it. */
static void test_health(void **st)
{
    static taskdef t;
    taskdef_health h;
    carry_row r;
    int k;
    (void)st;
    task_from_carry(&t, ID_P, ID_T);
    assert_int_equal(taskdef_health_find(&t, &h), TASKDEF_OK);
    assert_int_equal(h.mask, 0u);
    assert_int_equal(h.fault[0], -1);
    assert_int_equal(taskdef_health_find(NULL, &h), TASKDEF_ERR_ARG);
    assert_int_equal(h.up[0], -1);
    task_with_health(&t);
    assert_int_equal(taskdef_health_find(&t, &h), TASKDEF_OK);
    assert_int_equal(h.up[0], NP);
    assert_int_equal(h.down[0], NP + 1);
    assert_int_equal(h.fault[0], NT);
    assert_int_equal(h.recover[0], NT + 1);
    assert_int_equal(h.up[1], -1);
    assert_int_equal(h.mask, 3u << NT);
    assert_int_equal(taskdef_validate(&t.net, t.rows, NULL), TASKDEF_ERR_TABLE);
    assert_int_equal(taskdef_validate_health(&t.net, t.rows, h.mask, NULL), TASKDEF_OK);
    /* a health transition that moves an arm */
    t.rows[NT] = carry_table[CARRY_T6];
    assert_int_equal(taskdef_validate_health(&t.net, t.rows, h.mask, NULL), TASKDEF_ERR_TABLE);
    task_with_health(&t);
    t.place_id[NP + 1][0] = '\0';
    assert_int_equal(taskdef_health_find(&t, &h), TASKDEF_ERR_HEALTH);
    assert_int_equal(h.mask, 0u);
    task_with_health(&t);
    t.m0[NP + 1] = 1;
    assert_int_equal(taskdef_health_find(&t, &h), TASKDEF_ERR_HEALTH);
    task_with_health(&t);
    t.n_minus[(NP + 1) * (NT + 2) + CARRY_T2] = 1; /* t2 takes "arm 1 down" */
    assert_int_equal(taskdef_health_find(&t, &h), TASKDEF_ERR_HEALTH);
    /* the magazine: no row of the carry goes there */
    for (k = 0; k < NT; k++)
        assert_false(carry_row_uses_magazine(&carry_table[k]));
    r = carry_table[CARRY_T1];
    r.plan[0].seg[0].pose = CARRY_POSE_ABOVE_MAGAZINE;
    assert_true(carry_row_uses_magazine(&r));
    assert_false(carry_row_uses_magazine(NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roles_of_the_carry), cmocka_unit_test(test_digest),
        cmocka_unit_test(test_roles_permuted),     cmocka_unit_test(test_roles_refused),
        cmocka_unit_test(test_sets_down),          cmocka_unit_test(test_health),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

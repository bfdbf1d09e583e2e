/* equal_carry: asserts a net and lookup table equal, field by field, to
 * the shipped carry_net and carry_table (docs/method/carry.md §5, §6). */
#ifndef TANDEM_EQUAL_CARRY_H
#define TANDEM_EQUAL_CARRY_H

#include <string.h>
#include "carry_net.h"

static void assert_gains_equal(const erlaw_gains *a, const erlaw_gains *b)
{
    assert_true(a->v_m == b->v_m && a->a_m == b->a_m && a->u_m == b->u_m && a->k_p == b->k_p);
    assert_true(a->k_v == b->k_v && a->k0 == b->k0 && a->k1 == b->k1 && a->k2 == b->k2);
}

static void assert_row_equal(const carry_row *a, const carry_row *b)
{
    int arm, k;
    assert_string_equal(a->name, b->name);
    assert_int_equal(a->arms, b->arms);
    assert_int_equal(a->sync_group, b->sync_group);
    assert_gains_equal(&a->lin, &b->lin);
    for (arm = 0; arm < 2; arm++) {
        assert_int_equal(a->target_pose[arm], b->target_pose[arm]);
        assert_int_equal(a->gripper[arm], b->gripper[arm]);
        assert_int_equal(a->plan[arm].n_segments, b->plan[arm].n_segments);
        assert_int_equal(a->plan[arm].after_partner, b->plan[arm].after_partner);
        for (k = 0; k < CARRY_MAX_SEGMENTS; k++) {
            assert_int_equal(a->plan[arm].seg[k].kind, b->plan[arm].seg[k].kind);
            assert_int_equal(a->plan[arm].seg[k].pose, b->plan[arm].seg[k].pose);
        }
    }
}

static void assert_carry_equal(const petri_net *n, const carry_row *rows)
{
    const petri_net *c = &carry_net;
    const size_t cells = (size_t)(c->n_places * c->n_transitions);
    int t;
    assert_int_equal(n->n_places, c->n_places);
    assert_int_equal(n->n_transitions, c->n_transitions);
    assert_memory_equal(n->n_minus, c->n_minus, cells);
    assert_memory_equal(n->n_plus, c->n_plus, cells);
    assert_non_null(n->n_inhibit);
    assert_memory_equal(n->n_inhibit, c->n_inhibit, cells);
    assert_memory_equal(n->m0, c->m0, (size_t)c->n_places);
    assert_int_equal(n->n_invariants, c->n_invariants);
    assert_memory_equal(n->invariants, c->invariants, (size_t)(c->n_invariants * c->n_places));
    for (t = 0; t < c->n_transitions; t++)
        assert_row_equal(&rows[t], &carry_table[t]);
}

#endif

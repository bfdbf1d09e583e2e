/* Unit tests for formation: slot-pattern invariants (centred, spacing,
 * widths, scaling), deterministic slot assignment, and the narrow-passage
 * protocol (shrink -> line -> triangle -> column -> restore) agreed by two
 * robots through announcements, with its confirmation hysteresis. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "formation.h"
#include "prng.h"
#include "vec2.h"

static double dist_slots(int type, int n, int a, int b, double s)
{
    double p[2], q[2];
    formation_slot_xy(p, type, n, a, s, 1.0);
    formation_slot_xy(q, type, n, b, s, 1.0);
    return hypot(p[0] - q[0], p[1] - q[1]);
}

static void test_slots_centred_and_polar(void **state)
{
    int type, n, k;
    (void)state;
    for (type = 0; type < 3; type++)
        for (n = 1; n <= FORMATION_MAX_ROBOTS; n += (n < 8 ? 1 : 17)) {
            double cx = 0, cy = 0;
            for (k = 0; k < n; k++) {
                double xy[2], xy2[2], l, ph;
                assert_int_equal(formation_slot_xy(xy, type, n, k, 0.8, 0.7), 0);
                assert_int_equal(formation_slot(&l, &ph, type, n, k, 0.8, 0.7), 0);
                assert_true(fabs(l * cos(ph) - xy[0]) < 1e-12 && fabs(l * sin(ph) - xy[1]) < 1e-12);
                /* scale is linear */
                formation_slot_xy(xy2, type, n, k, 0.8, 1.4);
                assert_true(fabs(xy2[0] - 2 * xy[0]) < 1e-12 && fabs(xy2[1] - 2 * xy[1]) < 1e-12);
                cx += xy[0];
                cy += xy[1];
            }
            assert_true(fabs(cx) < 1e-9 && fabs(cy) < 1e-9);
        }
}

static void test_slot_spacing_and_width(void **state)
{
    const double s = 1.3, w = 0.38;
    int k;
    (void)state;
    for (k = 0; k + 1 < 9; k++) {
        assert_true(fabs(dist_slots(FORMATION_LINE, 9, k, k + 1, s) - s) < 1e-12);
        assert_true(fabs(dist_slots(FORMATION_COLUMN, 9, k, k + 1, s) - s) < 1e-12);
    }
    /* wedge legs: apex to first row and along each leg, spacing s */
    assert_true(fabs(dist_slots(FORMATION_TRIANGLE, 7, 0, 1, s) - s) < 1e-12);
    assert_true(fabs(dist_slots(FORMATION_TRIANGLE, 7, 0, 2, s) - s) < 1e-12);
    assert_true(fabs(dist_slots(FORMATION_TRIANGLE, 7, 1, 2, s) - s) < 1e-12);
    assert_true(fabs(dist_slots(FORMATION_TRIANGLE, 7, 1, 3, s) - s) < 1e-12);
    assert_true(fabs(dist_slots(FORMATION_TRIANGLE, 7, 4, 6, s) - s) < 1e-12);
    assert_true(fabs(formation_width(FORMATION_LINE, 3, s, 1, w) - (2 * s + w)) < 1e-12);
    assert_true(fabs(formation_width(FORMATION_TRIANGLE, 3, s, 1, w) - (s + w)) < 1e-12);
    assert_true(fabs(formation_width(FORMATION_COLUMN, 3, s, 1, w) - w) < 1e-12);
    assert_true(formation_width(FORMATION_LINE, 5, s, 1, w) >
                formation_width(FORMATION_TRIANGLE, 5, s, 1, w));
    assert_true(fabs(formation_width(FORMATION_LINE, 5, s, 0.5, 0) * 2 -
                     formation_width(FORMATION_LINE, 5, s, 1, 0)) < 1e-12);
    assert_true(formation_width(7, 3, s, 1, w) < 0);
    assert_true(formation_width(FORMATION_LINE, FORMATION_MAX_ROBOTS + 1, s, 1, w) < 0);
    {
        double xy[2];
        assert_int_equal(formation_slot_xy(xy, FORMATION_LINE, 3, 3, s, 1), FORMATION_ERR_ARG);
        assert_int_equal(formation_slot_xy(xy, FORMATION_LINE, 3, 0, NAN, 1), FORMATION_ERR_ARG);
        assert_int_equal(formation_slot_xy(xy, FORMATION_LINE, 3, 0, s, 0), FORMATION_ERR_ARG);
    }
    assert_int_equal(formation_next_type(FORMATION_LINE), FORMATION_TRIANGLE);
    assert_int_equal(formation_next_type(FORMATION_TRIANGLE), FORMATION_COLUMN);
    assert_int_equal(formation_next_type(FORMATION_COLUMN), FORMATION_COLUMN);
}

static void test_slot_assignment(void **state)
{
    int32_t a[5] = { 42, 7, 19, 3, 100 }, b[5] = { 100, 3, 42, 19, 7 }, c[4] = { 100, 3, 42, 7 };
    int k, seen[5] = { 0 };
    (void)state;
    for (k = 0; k < 5; k++) {
        const int s = formation_slot_of(a, 5, a[k]);
        assert_int_equal(s, formation_slot_of(b, 5, a[k])); /* order-free */
        assert_true(s >= 0 && s < 5);
        seen[s]++;
    }
    for (k = 0; k < 5; k++)
        assert_int_equal(seen[k], 1); /* a bijection */
    assert_int_equal(formation_slot_of(a, 5, 3), 0);
    assert_int_equal(formation_slot_of(a, 5, 100), 4);
    /* 19 leaves: 42 moves up one, 3 and 7 keep theirs */
    assert_int_equal(formation_slot_of(c, 4, 42), 2);
    assert_int_equal(formation_slot_of(c, 4, 7), 1);
    assert_int_equal(formation_slot_of(c, 4, 19), FORMATION_ERR_ABSENT);
}

static int run(formation_fsm *f, const formation_fsm_params *p, double width, double secs,
               int32_t self, formation_announce *log, int *nlog)
{
    int k, made = 0;
    for (k = 0; k < (int)(secs / 0.1 + 0.5); k++) {
        formation_announce a;
        const int r = formation_fsm_step(f, p, width, 3, 0.1, self, 1, &a);
        assert_true(r >= 0);
        if (r == 1) {
            log[(*nlog)++] = a;
            made++;
        }
    }
    return made;
}

static void test_protocol_sequence_and_restore(void **state)
{
    formation_fsm_params p;
    formation_fsm A, B;
    formation_announce log[16];
    int nlog = 0, i, seen = 0;
    (void)state;
    formation_fsm_params_default(&p);
    assert_int_equal(formation_fsm_init(&A, FORMATION_LINE, 1.0), 0);
    assert_int_equal(formation_fsm_init(&B, FORMATION_LINE, 1.0), 0);
    assert_int_equal(run(&A, &p, INFINITY, 5, 1, log, &nlog), 0);
    assert_int_equal(A.phase, FORMATION_PHASE_NORMAL);
    /* a 1.0 m corridor: only the column fits */
    run(&A, &p, 1.0, 10, 1, log, &nlog);
    assert_int_equal(nlog, 3);
    assert_int_equal(log[0].code, FORMATION_ANN_SHRINK);
    assert_int_equal(log[0].type, FORMATION_LINE);
    assert_true(fabs(log[0].scale - p.shrink_scale) < 1e-15);
    assert_int_equal(log[1].code, FORMATION_ANN_CHANGE);
    assert_int_equal(log[1].type, FORMATION_TRIANGLE);
    assert_int_equal(log[2].code, FORMATION_ANN_CHANGE);
    assert_int_equal(log[2].type, FORMATION_COLUMN);
    for (i = 1; i < nlog; i++)
        assert_true(log[i].seq > log[i - 1].seq);
    assert_int_equal(A.type, FORMATION_COLUMN);
    /* clear, but shorter than the hold: nothing */
    assert_int_equal(run(&A, &p, INFINITY, p.clear_hold_s - 0.5, 1, log, &nlog), 0);
    /* a moment of narrow resets the hold */
    run(&A, &p, 1.0, 0.1, 1, log, &nlog);
    assert_int_equal(run(&A, &p, INFINITY, p.clear_hold_s - 0.5, 1, log, &nlog), 0);
    assert_int_equal(run(&A, &p, INFINITY, 1.0, 1, log, &nlog), 1);
    assert_int_equal(log[3].code, FORMATION_ANN_RESTORE);
    assert_int_equal(log[3].type, FORMATION_LINE);
    assert_true(log[3].scale == 1.0);
    run(&A, &p, INFINITY, 2, 1, log, &nlog);
    assert_int_equal(A.phase, FORMATION_PHASE_NORMAL);
    assert_int_equal(nlog, 4);
    /* B hears every announcement (twice: repeats are idempotent) */
    for (i = 0; i < nlog; i++) {
        formation_fsm before;
        assert_int_equal(formation_fsm_on_announce(&B, &log[i]), 1);
        memcpy(&before, &B, sizeof B);
        assert_int_equal(formation_fsm_on_announce(&B, &log[i]), 0);
        assert_memory_equal(&before, &B, sizeof B);
        if (i == 2) {
            assert_int_equal(B.type, FORMATION_COLUMN);
            assert_true(fabs(B.scale - p.shrink_scale) < 1e-15);
        }
        seen++;
    }
    assert_int_equal(seen, 4);
    assert_int_equal(B.type, A.type);
    assert_true(B.scale == A.scale);
    /* an old announcement arriving late changes nothing */
    assert_int_equal(formation_fsm_on_announce(&B, &log[1]), 0);
    assert_int_equal(B.type, FORMATION_LINE);
}

static void test_protocol_stops_when_it_fits(void **state)
{
    formation_fsm_params p;
    formation_fsm A;
    formation_announce log[16];
    int nlog = 0;
    (void)state;
    formation_fsm_params_default(&p);
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    /* 1.5 m: shrunk triangle (0.6 + 0.38 + 0.3 = 1.28 m) fits */
    run(&A, &p, 1.5, 10, 1, log, &nlog);
    assert_int_equal(nlog, 2);
    assert_int_equal(A.type, FORMATION_TRIANGLE);
    /* 2.0 m: the shrunk line already fits */
    nlog = 0;
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    run(&A, &p, 2.0, 10, 1, log, &nlog);
    assert_int_equal(nlog, 1);
    assert_int_equal(A.type, FORMATION_LINE);
    assert_int_equal(A.phase, FORMATION_PHASE_SHRINK);
}

static void test_protocol_agreement_and_ties(void **state)
{
    formation_fsm_params p;
    formation_fsm A, B, C;
    formation_announce a, b;
    (void)state;
    formation_fsm_params_default(&p);
    p.confirm_s = 0.0; /* one narrow reading is enough here (see test_protocol_confirm) */
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    formation_fsm_init(&B, FORMATION_LINE, 1.0);
    formation_fsm_init(&C, FORMATION_LINE, 1.0);
    /* A and B announce at once with the same seq: everyone takes id 2's */
    assert_int_equal(formation_fsm_step(&A, &p, 1.0, 3, 0.1, 5, 1, &a), 1);
    assert_int_equal(formation_fsm_step(&B, &p, 1.0, 3, 0.1, 2, 1, &b), 1);
    assert_int_equal(a.seq, b.seq);
    assert_int_equal(formation_fsm_on_announce(&A, &b), 1);
    assert_int_equal(formation_fsm_on_announce(&B, &a), 0);
    assert_int_equal(formation_fsm_on_announce(&C, &a), 1);
    assert_int_equal(formation_fsm_on_announce(&C, &b), 1);
    assert_true(A.origin == 2 && B.origin == 2 && C.origin == 2);
    /* the next announcement from anyone is newer than all of that */
    assert_int_equal(formation_fsm_step(&C, &p, 1.0, 3, 1.5, 9, 1, &a), 1);
    assert_true(a.seq > b.seq && a.code == FORMATION_ANN_CHANGE);
    assert_int_equal(formation_fsm_on_announce(&A, &a), 1);
    assert_int_equal(A.type, FORMATION_TRIANGLE);
    /* LEAVE only advances the counter */
    b.code = FORMATION_ANN_LEAVE;
    b.seq = a.seq + 10;
    assert_int_equal(formation_fsm_on_announce(&A, &b), 0);
    assert_int_equal(A.type, FORMATION_TRIANGLE);
    assert_true(formation_fsm_next_seq(&A) > b.seq);
    b.scale = NAN;
    assert_int_equal(formation_fsm_on_announce(&A, &b), FORMATION_ERR_ARG);
    assert_int_equal(formation_fsm_step(&A, &p, 1.0, 3, NAN, 5, 1, &a), FORMATION_ERR_ARG);
}

/* Restore hysteresis: a robot that cannot see the passage (NAN: a mate
 * hides a side or the front) neither narrows nor clears, and only the
 * rearmost robot restores; the leader of a column that has left the
 * corridor while the others are still inside does not. */
static void test_protocol_restore_rear_and_unknown(void **state)
{
    formation_fsm_params p;
    formation_fsm A;
    formation_announce a;
    int k, made = 0;
    (void)state;
    formation_fsm_params_default(&p);
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    /* unknown in NORMAL: nothing happens */
    for (k = 0; k < 50; k++)
        made += formation_fsm_step(&A, &p, NAN, 3, 0.1, 1, 1, &a);
    assert_int_equal(made, 0);
    assert_int_equal(A.phase, FORMATION_PHASE_NORMAL);
    for (k = 0; k < 50; k++)
        formation_fsm_step(&A, &p, 1.0, 3, 0.1, 1, 0, &a);
    assert_int_equal(A.type, FORMATION_COLUMN);
    /* the leader is out, clear for far longer than the hold: no restore */
    for (k = 0; k < 200; k++)
        made += formation_fsm_step(&A, &p, INFINITY, 3, 0.1, 1, 0, &a);
    assert_int_equal(made, 0);
    assert_int_equal(A.type, FORMATION_COLUMN);
    /* the rear robot: clear for less than the hold, then unknown (a mate
     * in front of a side transducer) for long: the timer holds, no reset */
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    for (k = 0; k < 50; k++)
        formation_fsm_step(&A, &p, 1.0, 3, 0.1, 1, 1, &a);
    for (k = 0; k < (int)(10.0 * (p.clear_hold_s - 1.0)); k++)
        made += formation_fsm_step(&A, &p, INFINITY, 3, 0.1, 1, 1, &a);
    for (k = 0; k < 100; k++)
        made += formation_fsm_step(&A, &p, NAN, 3, 0.1, 1, 1, &a);
    assert_int_equal(made, 0);
    assert_true(fabs(A.clear_s - (p.clear_hold_s - 1.0)) < 1e-6);
    for (k = 0; k < 11; k++)
        made += formation_fsm_step(&A, &p, INFINITY, 3, 0.1, 1, 1, &a);
    assert_int_equal(made, 1);
    assert_int_equal(a.code, FORMATION_ANN_RESTORE);
    assert_int_equal(A.type, FORMATION_LINE);
}

/* Hysteresis on the way in: a passage must read narrow for confirm_s.
 * Narrow readings shorter than that, each followed by a wider one (the
 * gaps between scattered posts a robot threads), never shrink the
 * formation however often they come; unknown readings in between hold the
 * count; a passage that goes on shrinks after confirm_s, and each further
 * step (CHANGE) again needs confirm_s of narrow readings for the new
 * width as well as the dwell. */
static void test_protocol_confirm(void **state)
{
    formation_fsm_params p;
    formation_fsm A;
    formation_announce a;
    const double dt = 0.05;
    double t = 0.0, t_shrink = NAN, t_change = NAN;
    int k, j, made = 0;
    (void)state;
    formation_fsm_params_default(&p);
    assert_true(p.confirm_s > 0.2);
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    for (k = 0; k < 40; k++) {
        for (j = 0; j < (int)((p.confirm_s - 0.2) / dt); j++)
            made += formation_fsm_step(&A, &p, 1.5, 3, dt, 1, 1, &a);
        made += formation_fsm_step(&A, &p, INFINITY, 3, dt, 1, 1, &a);
    }
    assert_int_equal(made, 0);
    assert_int_equal(A.phase, FORMATION_PHASE_NORMAL);
    /* narrow, unknown for long, narrow again: the unknown stretch holds */
    for (j = 0; j < (int)(0.6 * p.confirm_s / dt); j++)
        made += formation_fsm_step(&A, &p, 1.5, 3, dt, 1, 1, &a);
    for (j = 0; j < 100; j++)
        made += formation_fsm_step(&A, &p, NAN, 3, dt, 1, 1, &a);
    assert_int_equal(made, 0);
    for (j = 0; j < (int)(0.6 * p.confirm_s / dt); j++)
        made += formation_fsm_step(&A, &p, 1.5, 3, dt, 1, 1, &a);
    assert_int_equal(made, 1);
    assert_int_equal(a.code, FORMATION_ANN_SHRINK);
    /* a passage only a shrunk triangle fits: SHRINK after confirm_s, CHANGE
     * no sooner than confirm_s and the dwell after that */
    formation_fsm_init(&A, FORMATION_LINE, 1.0);
    for (k = 0; k < 200 && isnan(t_change); k++) {
        t += dt;
        if (formation_fsm_step(&A, &p, 1.5, 3, dt, 1, 1, &a) == 1) {
            if (a.code == FORMATION_ANN_SHRINK)
                t_shrink = t;
            if (a.code == FORMATION_ANN_CHANGE)
                t_change = t;
        }
    }
    assert_true(t_shrink >= p.confirm_s - 1e-9 && t_shrink < p.confirm_s + 2.0 * dt);
    assert_true(t_change - t_shrink >= fmax(p.confirm_s, p.dwell_s) - 1e-9);
    assert_int_equal(A.type, FORMATION_TRIANGLE);
    p.confirm_s = -1.0;
    assert_int_equal(formation_fsm_step(&A, &p, 1.5, 3, dt, 1, 1, &a), FORMATION_ERR_ARG);
}

/* formation_slots_held: robots in any order, each within tol of a slot of
 * its own, hold the slots; one robot moved beyond tol of every slot, or
 * two robots sharing one slot with another left empty, do not (random
 * teams of every size, shuffled). */
static void test_slots_held_any_order(void **state)
{
    static double slot[FORMATION_MAX_ROBOTS][2], xy[FORMATION_MAX_ROBOTS][2];
    const double tol = 0.3;
    prng_state r;
    int trial, n, k;
    (void)state;
    prng_seed(&r, 11);
    for (trial = 0; trial < 200; trial++) {
        int perm[FORMATION_MAX_ROBOTS], type = trial % 3;
        n = 1 + (int)(prng_uniform(&r) * 24.0);
        for (k = 0; k < n; k++) {
            assert_int_equal(formation_slot_xy(slot[k], type, n, k, 1.0, 1.0), 0);
            perm[k] = k;
        }
        for (k = n - 1; k > 0; k--) { /* Fisher-Yates */
            const int j = (int)(prng_uniform(&r) * (k + 1)), t = perm[k];
            perm[k] = perm[j];
            perm[j] = t;
        }
        for (k = 0; k < n; k++) {
            const double a = 2.0 * VEC2_PI * prng_uniform(&r), d = 0.99 * tol * prng_uniform(&r);
            xy[k][0] = slot[perm[k]][0] + d * cos(a);
            xy[k][1] = slot[perm[k]][1] + d * sin(a);
        }
        assert_int_equal(
            formation_slots_held((const double(*)[2])xy, (const double(*)[2])slot, n, tol), 1);
        if (n < 2)
            continue;
        /* two on one slot: the robot of slot perm[1] stands on slot perm[0]'s */
        xy[1][0] = xy[0][0];
        xy[1][1] = xy[0][1];
        assert_int_equal(
            formation_slots_held((const double(*)[2])xy, (const double(*)[2])slot, n, tol), 0);
        /* one far from every slot */
        xy[1][0] = 100.0;
        assert_int_equal(
            formation_slots_held((const double(*)[2])xy, (const double(*)[2])slot, n, tol), 0);
    }
    assert_int_equal(formation_slots_held(NULL, (const double(*)[2])slot, 3, tol),
                     FORMATION_ERR_ARG);
    assert_int_equal(formation_slots_held((const double(*)[2])xy, (const double(*)[2])slot, 0, tol),
                     FORMATION_ERR_ARG);
}

/* formation_slots_xy gives every slot exactly as formation_slot_xy does,
 * for every type and size; bad input is refused. */
static void test_slots_at_once(void **state)
{
    static double all[FORMATION_MAX_ROBOTS][2];
    double one[2];
    int type, n, k;
    (void)state;
    for (type = FORMATION_LINE; type <= FORMATION_COLUMN; type++)
        for (n = 1; n <= FORMATION_MAX_ROBOTS; n++) {
            assert_int_equal(formation_slots_xy(all, type, n, 1.3, 0.7), 0);
            for (k = 0; k < n; k++) {
                assert_int_equal(formation_slot_xy(one, type, n, k, 1.3, 0.7), 0);
                assert_memory_equal(one, all[k], sizeof one);
            }
        }
    assert_int_equal(formation_slots_xy(NULL, FORMATION_LINE, 3, 1.0, 1.0), FORMATION_ERR_ARG);
    assert_int_equal(formation_slots_xy(all, FORMATION_LINE, 0, 1.0, 1.0), FORMATION_ERR_ARG);
    assert_int_equal(formation_slots_xy(all, FORMATION_LINE, FORMATION_MAX_ROBOTS + 1, 1.0, 1.0),
                     FORMATION_ERR_ARG);
    assert_int_equal(formation_slots_xy(all, FORMATION_LINE, 3, 0.0, 1.0), FORMATION_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slots_at_once),
        cmocka_unit_test(test_slots_centred_and_polar),
        cmocka_unit_test(test_slot_spacing_and_width),
        cmocka_unit_test(test_slot_assignment),
        cmocka_unit_test(test_slots_held_any_order),
        cmocka_unit_test(test_protocol_sequence_and_restore),
        cmocka_unit_test(test_protocol_stops_when_it_fits),
        cmocka_unit_test(test_protocol_agreement_and_ties),
        cmocka_unit_test(test_protocol_restore_rear_and_unknown),
        cmocka_unit_test(test_protocol_confirm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for team: team-average reference (circular mean across the
 * +-pi wrap, extrapolation, LEAVE excluded), heartbeat timeout, late join
 * and re-slot ids, beacon fusion, frame-consensus offsets, bad input. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "team.h"
#include "formation.h"

static team_member mate(int32_t id, double x, double y, double th, double v, double w, double t)
{
    team_member m = { 0 };
    m.robot = id;
    m.x_m = x;
    m.y_m = y;
    m.theta_rad = th;
    m.v_mps = v;
    m.w_radps = w;
    m.formation = FORMATION_LINE;
    m.scale = 1.0;
    m.t_s = t;
    return m;
}

static void test_reference_average_wrap(void **state)
{
    team_table t;
    team_member a = mate(3, 1.0, 2.0, VEC2_PI - 0.1, 0.2, 0.1, 10.0);
    team_member b = mate(9, 3.0, -2.0, -VEC2_PI + 0.2, 0.4, -0.4, 10.0);
    unicycle_state self = { 2.0, 3.0, VEC2_PI - 0.05, 0.3, 0.0 }, ref;
    (void)state;
    assert_int_equal(team_init(&t, 5, 1.0), 0);
    assert_int_equal(team_update(&t, &a), 1);
    assert_int_equal(team_update(&t, &b), 1);
    assert_int_equal(team_reference(&ref, &t, &self, 0, 0.15, 10.0), 3);
    assert_true(fabs(ref.x_m - 2.0) < 1e-12 && fabs(ref.y_m - 1.0) < 1e-12);
    assert_true(fabs(ref.v_mps - 0.3) < 1e-12 && fabs(ref.w_radps + 0.1) < 1e-12);
    /* headings all near pi: the mean is near pi, not near 0 */
    assert_true(fabs(vec2_angle_diff_rad(ref.theta_rad, VEC2_PI + 0.05 / 3)) < 1e-3);
    assert_true(cos(ref.theta_rad) < -0.99);
    /* self left: only the mates */
    assert_int_equal(team_reference(&ref, &t, &self, 1, 0.15, 10.0), 2);
    assert_true(fabs(ref.x_m - 2.0) < 1e-12 && fabs(ref.y_m - 0.0) < 1e-12);
    /* a mate announcing LEAVE (dead zone) is left out */
    b.announce = FORMATION_ANN_LEAVE;
    b.t_s = 10.0;
    assert_int_equal(team_update(&t, &b), 0);
    assert_int_equal(team_reference(&ref, &t, &self, 0, 0.15, 10.0), 2);
    assert_true(fabs(ref.x_m - 1.5) < 1e-12);
    /* one giving way to it (GIVE_WAY) is taken into the table (a table that
     * refused the code lost every robot giving way: its echoes were no
     * longer masked and two of them followed each other off as walls) and
     * left out of the reference as well */
    a.announce = FORMATION_ANN_GIVE_WAY;
    a.t_s = 10.0;
    assert_int_equal(team_update(&t, &a), 0);
    assert_true(fabs(t.m[0].x_m - 1.0) < 1e-12 && t.m[0].announce == FORMATION_ANN_GIVE_WAY);
    assert_int_equal(team_reference(&ref, &t, &self, 0, 0.15, 10.0), 1);
    /* an unknown code is refused */
    a.announce = FORMATION_ANN_GIVE_WAY + 1;
    assert_int_equal(team_update(&t, &a), TEAM_ERR_ARG);
}

static void test_reference_extrapolates(void **state)
{
    team_table t;
    team_member a = mate(1, 0.0, 0.0, 0.5, 0.4, 0.0, 2.0);
    unicycle_state ref;
    (void)state;
    team_init(&t, 0, 1.0);
    team_update(&t, &a);
    assert_int_equal(team_reference(&ref, &t, NULL, 0, 0.15, 2.5), 1);
    assert_true(fabs(ref.x_m - 0.2 * cos(0.5)) < 1e-12 && fabs(ref.y_m - 0.2 * sin(0.5)) < 1e-12);
    /* turning in place: O swings about C by the same angle */
    a = mate(1, 0.0, 0.0, 0.0, 0.0, 1.0, 3.0);
    team_update(&t, &a);
    assert_int_equal(team_reference(&ref, &t, NULL, 0, 0.15, 3.0 + VEC2_PI / 2),
                     TEAM_ERR_UNKNOWN); /* stale > 1 s */
    assert_int_equal(team_reference(&ref, &t, NULL, 0, 0.15, 3.5), 1);
    assert_true(fabs(hypot(ref.x_m - 0.15, ref.y_m) - 0.15) < 1e-12);
    assert_true(fabs(ref.theta_rad - 0.5) < 1e-12);
}

static void test_timeout_and_late_join(void **state)
{
    team_table t;
    team_member a = mate(7, 0, 0, 0, 0, 0, 0.0), b = mate(2, 1, 1, 0, 0, 0, 0.0), c;
    int32_t ids[TEAM_MAX + 1];
    int n;
    (void)state;
    team_init(&t, 4, TEAM_TIMEOUT_S_DEFAULT);
    team_update(&t, &a);
    team_update(&t, &b);
    n = team_ids(&t, ids, TEAM_MAX + 1);
    assert_int_equal(n, 3);
    assert_true(ids[0] == 2 && ids[1] == 4 && ids[2] == 7);
    assert_int_equal(formation_slot_of(ids, n, 4), 1);
    /* 7 keeps talking, 2 goes silent */
    a.t_s = 0.9;
    assert_int_equal(team_update(&t, &a), 0);
    assert_int_equal(team_expire(&t, 1.0), 0); /* exactly 1 s: still alive */
    assert_int_equal(team_expire(&t, 1.05), 1);
    assert_null(team_find(&t, 2));
    n = team_ids(&t, ids, TEAM_MAX + 1);
    assert_int_equal(n, 2);
    assert_int_equal(formation_slot_of(ids, n, 4), 0); /* re-slot */
    /* late joiner (and 2 coming back) are taken in */
    c = mate(5, 3, 3, 0, 0, 0, 1.1);
    assert_int_equal(team_update(&t, &c), 1);
    b.t_s = 1.2;
    assert_int_equal(team_update(&t, &b), 1);
    n = team_ids(&t, ids, TEAM_MAX + 1);
    assert_int_equal(n, 4);
    assert_true(ids[0] == 2 && ids[1] == 4 && ids[2] == 5 && ids[3] == 7);
    /* an older message is ignored */
    b.t_s = 1.15;
    b.x_m = 99;
    assert_int_equal(team_update(&t, &b), 0);
    assert_true(team_find(&t, 2)->x_m == 1.0);
}

static void test_capacity_and_bad(void **state)
{
    team_table t;
    team_member m;
    int i;
    (void)state;
    team_init(&t, -1, 1.0);
    for (i = 0; i < TEAM_MAX; i++) {
        m = mate(TEAM_MAX - i, i, 0, 0, 0, 0, 0); /* reverse order: sorted insert */
        assert_int_equal(team_update(&t, &m), 1);
    }
    for (i = 1; i < t.n; i++)
        assert_true(t.m[i - 1].robot < t.m[i].robot);
    m = mate(1000, 0, 0, 0, 0, 0, 0);
    assert_int_equal(team_update(&t, &m), TEAM_ERR_FULL);
    team_init(&t, 3, 1.0);
    m = mate(3, 0, 0, 0, 0, 0, 0);
    assert_int_equal(team_update(&t, &m), TEAM_ERR_ARG); /* own id */
    m = mate(4, NAN, 0, 0, 0, 0, 0);
    assert_int_equal(team_update(&t, &m), TEAM_ERR_ARG);
    m = mate(4, 0, 0, 0, 0, 0, 0);
    m.scale = 0;
    assert_int_equal(team_update(&t, &m), TEAM_ERR_ARG);
    assert_int_equal(t.n, 0);
    assert_int_equal(team_init(&t, 3, 0.0), TEAM_ERR_ARG);
}

static void test_beacon_fusion(void **state)
{
    team_table t;
    team_member a = mate(8, 2.0, 1.0, 0.3, 0, 0, 0);
    const pose2 me = { 0.5, -0.5, 0.7 };
    const double true_x = 2.4, true_y = 0.8; /* where the mate really is */
    const double rng = hypot(true_x - me.x_m, true_y - me.y_m);
    const double brg = atan2(true_y - me.y_m, true_x - me.x_m) - me.theta_rad;
    double xy[2];
    int k;
    (void)state;
    team_init(&t, 1, 1.0);
    team_update(&t, &a);
    assert_int_equal(team_position(&t, 8, xy), 0);
    assert_true(xy[0] == 2.0 && xy[1] == 1.0);
    /* first sighting is taken whole */
    assert_int_equal(team_observe(&t, 8, &me, rng, brg, 0.2, 1.0), 0);
    team_position(&t, 8, xy);
    assert_true(fabs(xy[0] - true_x) < 1e-12 && fabs(xy[1] - true_y) < 1e-12);
    /* the correction survives new messages, and tracks a changed offset
     * geometrically: after k observations the error is (1-alpha)^k */
    a.t_s = 0.1;
    a.x_m = 2.1;
    team_update(&t, &a);
    team_position(&t, 8, xy);
    assert_true(fabs(xy[0] - (true_x + 0.1)) < 1e-12);
    for (k = 0; k < 10; k++)
        team_observe(&t, 8, &me, rng, brg, 0.2, 1.0);
    team_position(&t, 8, xy);
    assert_true(fabs(xy[0] - true_x - 0.1 * pow(0.8, 10)) < 1e-12);
    assert_true(fabs(xy[1] - true_y) < 1e-12);
    assert_int_equal(team_observe(&t, 8, &me, -1.0, brg, 0.2, 1.0), TEAM_ERR_ARG);
    assert_int_equal(team_observe(&t, 8, &me, rng, brg, 1.5, 1.0), TEAM_ERR_ARG);
    assert_int_equal(team_observe(&t, 99, &me, rng, brg, 0.2, 1.0), TEAM_ERR_ARG);
}

/* Frame consensus input. Two robots whose dead reckoning has drifted by
 * e_self and e_mate: the offset of the mate is e_self - e_mate. With a
 * standing mate the mean offset is that, whole; with a mate on the move
 * only its part across the mate's heading counts (along the heading the
 * report lags the sighting); sightings older than max_age_s or farther than
 * max_range_m do not count;
 * shifting our own estimate moves every held offset by the same amount, so
 * a second sighting after the shift agrees with the shifted offset. */
static void test_consensus_offset(void **state)
{
    team_table t;
    const double e_self[2] = { 0.3, -0.2 }, e_mate[2] = { -0.1, 0.4 };
    const double tx = 3.0, ty = 1.0; /* the mate, truly */
    team_member a = mate(4, tx + e_mate[0], ty + e_mate[1], 0.0, 0.0, 0.0, 1.0);
    team_member b = mate(6, 0.0, 5.0, 0.0, 0.0, 0.0, 1.0);
    pose2 me = { 1.0 + e_self[0], -1.0 + e_self[1], 0.4 }; /* truly (1, -1) */
    const double rng = hypot(tx - 1.0, ty + 1.0), brg = atan2(ty + 1.0, tx - 1.0) - 0.4;
    double off[2], xy[2];
    (void)state;
    team_init(&t, 2, 1.0);
    team_update(&t, &a);
    team_update(&t, &b);
    assert_int_equal(team_mean_offset(&t, 1.0, 2.0, 10.0, off), 0); /* nobody seen yet */
    assert_true(off[0] == 0.0 && off[1] == 0.0);
    assert_int_equal(team_observe(&t, 4, &me, rng, brg, 0.2, 1.0), 0);
    assert_int_equal(team_mean_offset(&t, 1.5, 2.0, 10.0, off), 1); /* b never seen */
    assert_true(fabs(off[0] - (e_self[0] - e_mate[0])) < 1e-12);
    assert_true(fabs(off[1] - (e_self[1] - e_mate[1])) < 1e-12);
    assert_int_equal(team_mean_offset(&t, 3.5, 2.0, 10.0, off), 0);      /* too old */
    assert_int_equal(team_mean_offset(&t, 1.5, 2.0, 0.9 * rng, off), 0); /* too far */
    /* moving along +x: only the y part counts */
    a.v_mps = 0.4;
    a.t_s = 1.1;
    team_update(&t, &a);
    assert_int_equal(team_mean_offset(&t, 1.5, 2.0, 10.0, off), 1);
    assert_true(fabs(off[0]) < 1e-12 && fabs(off[1] - (e_self[1] - e_mate[1])) < 1e-12);
    /* shift our estimate by the offset: the held offset goes to zero, and a
     * sighting from the shifted pose finds the same */
    a.v_mps = 0.0;
    a.t_s = 1.2;
    team_update(&t, &a);
    team_mean_offset(&t, 1.5, 2.0, 10.0, off);
    team_shift_offsets(&t, -off[0], -off[1]);
    me.x_m -= off[0];
    me.y_m -= off[1];
    team_position(&t, 4, xy);
    assert_true(fabs(xy[0] - (tx + e_mate[0])) < 1e-12 && fabs(xy[1] - (ty + e_mate[1])) < 1e-12);
    team_observe(&t, 4, &me, rng, brg, 1.0, 1.3);
    team_mean_offset(&t, 1.5, 2.0, 10.0, off);
    assert_true(fabs(off[0]) < 1e-12 && fabs(off[1]) < 1e-12);
    assert_int_equal(team_observe(&t, 4, &me, rng, brg, 0.2, NAN), TEAM_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_average_wrap),
        cmocka_unit_test(test_reference_extrapolates),
        cmocka_unit_test(test_timeout_and_late_join),
        cmocka_unit_test(test_capacity_and_bad),
        cmocka_unit_test(test_beacon_fusion),
        cmocka_unit_test(test_consensus_offset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Unit tests for cell: every working pose of the carry task is reachable by
 * its arm with the tool pointing down, inside the joint ranges, and the
 * frame helpers are consistent. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>
#include "arm_kin.h"
#include "cell.h"
#include "vec3.h"

/* An in-limits IK branch exists for arm a's tool at p_world, pointing down,
 * and FK of it gives the pose back. */
static int reachable(int a, const double p_world[3])
{
    double Tw[16], Tinv[16], R[9], p[3], T[16], Tfk[16];
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    arm_tool tool;
    arm_ik_result r;
    int b;
    arm_tool_offset(&tool, off);
    cell_world_from_arm(&cell_default, a, Tw);
    tf_inverse(Tinv, Tw);
    tf_apply(p, Tinv, p_world);
    cell_tool_down_R(&cell_default, a, R);
    tf_from_rot_pos(T, R, p);
    if (arm_ik(&arm_model_puma560, &tool, T, &r) != 0 || r.unreachable)
        return 0;
    for (b = 0; b < ARM_IK_NBRANCH; b++) {
        int i;
        double err = 0.0;
        if (r.branch[b].status != ARM_IK_OK)
            continue;
        arm_fk(&arm_model_puma560, &tool, r.branch[b].q_rad, Tfk);
        for (i = 0; i < 12; i++)
            err = fmax(err, fabs(Tfk[i] - T[i]));
        if (err < 1e-9)
            return 1;
    }
    return 0;
}

static void test_every_working_pose_is_reachable(void **state)
{
    const cell_layout *c = &cell_default;
    double p[3], centre[3];
    int a, sx, sy;
    (void)state;
    for (a = 0; a < CELL_ARMS; a++) {
        assert_true(reachable(a, c->home_tool_m[a]));
        cell_grasp_point(c, a, c->handover_center_m, p);
        assert_true(reachable(a, p));
        p[2] += CELL_STAND_CLEARANCE_M; /* ABOVE_HANDOVER_1, _2: a stand's approach */
        assert_true(reachable(a, p));
        /* the stand's second place, where both arms set down and take bars:
         * STAND_B_k, ABOVE_STAND_B_k, and arm 1's CLEAR_B_1 */
        cell_grasp_point(c, a, c->stand_b_center_m, p);
        assert_true(reachable(a, p));
        p[2] += CELL_STAND_CLEARANCE_M;
        assert_true(reachable(a, p));
    }
    /* arm 1 backed off the stand's places along the bar (CLEAR_1, CLEAR_B_1:
     * 0.10 m, the supervisor's CLEAR_BACKOFF_M) */
    cell_grasp_point(c, 0, c->handover_center_m, p);
    p[0] -= 0.10;
    assert_true(reachable(0, p));
    cell_grasp_point(c, 0, c->stand_b_center_m, p);
    p[0] -= 0.10;
    assert_true(reachable(0, p));
    /* arm 1: every corner of the pick zone, at grasp height and above it */
    for (sx = -1; sx <= 1; sx += 2)
        for (sy = -1; sy <= 1; sy += 2) {
            vec3_copy(centre, c->pick_center_m);
            centre[0] += sx * c->pick_spread_m[0];
            centre[1] += sy * c->pick_spread_m[1];
            cell_grasp_point(c, 0, centre, p);
            assert_true(reachable(0, p));
            p[2] += c->approach_height_m;
            assert_true(reachable(0, p));
        }
    /* arm 2: the delivery pose and its approach */
    cell_grasp_point(c, 1, c->deliver_center_m, p);
    assert_true(reachable(1, p));
    p[2] += c->approach_height_m;
    assert_true(reachable(1, p));
    /* arm 2: its magazine (AT_MAGAZINE, ABOVE_MAGAZINE); arm 1 cannot reach it */
    cell_grasp_point(c, 1, c->magazine_center_m, p);
    assert_true(reachable(1, p));
    p[2] += c->approach_height_m;
    assert_true(reachable(1, p));
    cell_grasp_point(c, 0, c->magazine_center_m, p);
    assert_false(reachable(0, p));
}

static void test_tool_down_is_down_in_the_world(void **state)
{
    double Tw[16], Rb[9], R[9], Rworld[9];
    int a;
    (void)state;
    for (a = 0; a < CELL_ARMS; a++) {
        cell_world_from_arm(&cell_default, a, Tw);
        tf_rot(Rb, Tw);
        cell_tool_down_R(&cell_default, a, R);
        rot_mul(Rworld, Rb, R);
        /* flange z axis (third column) along -world z */
        assert_true(fabs(Rworld[8] + 1.0) < 1e-12);
    }
}

static void test_grasp_points_are_the_bar_ends(void **state)
{
    double p1[3], p2[3], d[3];
    (void)state;
    cell_grasp_point(&cell_default, 0, cell_default.handover_center_m, p1);
    cell_grasp_point(&cell_default, 1, cell_default.handover_center_m, p2);
    vec3_sub(d, p2, p1);
    assert_true(fabs(vec3_norm(d) - 2.0 * cell_default.grasp_offset_m) < 1e-12);
    assert_true(2.0 * cell_default.grasp_offset_m < cell_default.workpiece_size_m[0]);
    /* the workpiece rests on the table top */
    assert_true(fabs(cell_default.pick_center_m[2] - cell_default.workpiece_size_m[2] / 2.0 -
                     (cell_default.table_center_m[2] + cell_default.table_size_m[2] / 2.0)) < 1e-9);
}

static void test_validate(void **state)
{
    cell_layout c;
    (void)state;
    assert_int_equal(cell_layout_validate(&cell_default), 0);
    assert_int_equal(cell_layout_validate(NULL), CELL_ERR_ARG);
#define BROKEN(field_change, code)                          \
    do {                                                    \
        c = cell_default;                                   \
        field_change;                                       \
        assert_int_equal(cell_layout_validate(&c), (code)); \
    } while (0)
    BROKEN(c.pick_center_m[1] = NAN, CELL_ERR_NONFINITE);
    BROKEN(c.base_yaw_rad[1] = INFINITY, CELL_ERR_NONFINITE);
    BROKEN(c.home_tool_m[1][2] = NAN, CELL_ERR_NONFINITE);
    BROKEN(c.workpiece_mass_kg = 0.0, CELL_ERR_RANGE);
    BROKEN(c.table_size_m[2] = -0.05, CELL_ERR_RANGE);
    BROKEN(c.grasp_tolerance_m = 0.0, CELL_ERR_RANGE);
    BROKEN(c.pick_spread_m[0] = -0.01, CELL_ERR_RANGE);
    BROKEN(c.approach_height_m = 0.0, CELL_ERR_RANGE);
    BROKEN(c.grasp_offset_m = 0.14, CELL_ERR_INCONSISTENT);      /* past the bar's end */
    BROKEN(c.pick_center_m[2] += 0.01, CELL_ERR_INCONSISTENT);   /* floats above the top */
    BROKEN(c.pick_spread_m[1] = 0.5, CELL_ERR_INCONSISTENT);     /* spreads off the table */
    BROKEN(c.deliver_center_m[0] = 0.85, CELL_ERR_INCONSISTENT); /* off the table's end */
    BROKEN(c.handover_center_m[2] = 0.2, CELL_ERR_INCONSISTENT); /* inside the table */
    BROKEN(c.stand_b_center_m[2] = 0.2, CELL_ERR_INCONSISTENT);  /* inside the table */
    BROKEN(c.stand_b_center_m[1] = 0.40, CELL_ERR_INCONSISTENT); /* two bars touching */
    BROKEN(c.stand_b_center_m[0] = NAN, CELL_ERR_NONFINITE);
    BROKEN(c.magazine_center_m[1] = 0.79, CELL_ERR_INCONSISTENT); /* off the table's edge */
    BROKEN(c.magazine_center_m[2] = NAN, CELL_ERR_NONFINITE);
    BROKEN(vec3_copy(c.base_xyz_m[1], c.base_xyz_m[0]), CELL_ERR_INCONSISTENT);
#undef BROKEN
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_working_pose_is_reachable),
        cmocka_unit_test(test_tool_down_is_down_in_the_world),
        cmocka_unit_test(test_grasp_points_are_the_bar_ends),
        cmocka_unit_test(test_validate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

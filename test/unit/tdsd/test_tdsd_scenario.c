/* Guards the claims of docs/tdsd.md on the kinematic plant: the
 * seed-002 S1 path through the shoulder singularity with TDSD (position
 * error, joint speed limits, Q1 behaviour, orientation recovery), that the
 * same path really defeats the baselines (so the S1 numbers mean
 * something), and the S2 liquid run (joints in range, bucket upright with
 * tdsd; q6 out of range with the full 6-D baseline).
 *
 * Links the core only: the scenarios' pure part (tools/scenario/tdsd_run.c,
 * tdsd_setup.c: no LCM, no I/O) is compiled into this test directly.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

/* NOLINTBEGIN(bugprone-suspicious-include): the scenario's sources, statics and all */
#include "tdsd_run.c"
#include "tdsd_setup.c"
/* NOLINTEND(bugprone-suspicious-include) */

#define RAD2DEG_ (180.0 / 3.14159265358979323846)

typedef struct run_out {
    tdsdrun_metrics m;
    double duration_s;
} run_out;

static void run_s1(tdsdrun_method method, run_out *r)
{
    tdsdrun_cfg c;
    tdsdrun_path p;
    double q0[ARM_NJ];
    assert_int_equal(tdsd_setup_singularity(&c, &p, method, q0), 0);
    tdsdrun_metrics_init(&r->m, c.region_m);
    r->duration_s = tdsdrun_kin(&c, &p, q0, 30.0, &r->m, NULL, NULL);
}

static void run_s2(int full, run_out *r)
{
    tdsdrun_cfg c;
    tdsdrun_path p;
    double q0[ARM_NJ];
    assert_int_equal(tdsd_setup_liquid(&c, &p, full, q0), 0);
    tdsdrun_metrics_init(&r->m, c.region_m);
    r->duration_s = tdsdrun_kin(&c, &p, q0, 30.0, &r->m, NULL, NULL);
}

/* The path must really pass the singularity: the wrist centre comes within
 * a few mm of the joint-1 axis (and the 6x6 Jacobian goes singular). */
static void test_s1_path_crosses_the_shoulder_singularity(void **state)
{
    run_out r;
    (void)state;
    run_s1(TDSDRUN_TDSD, &r);
    assert_true(r.m.min_wrist_axis_m < 0.004);
    assert_true(r.m.t_region_in_s > 0.5 && r.m.t_region_out_s > r.m.t_region_in_s);
    assert_int_equal(r.m.resolver_errors, 0);
}

static void test_s1_tdsd_must_show(void **state)
{
    run_out r;
    (void)state;
    run_s1(TDSDRUN_TDSD, &r);
    /* position kept, every joint inside its speed limit */
    assert_true(r.m.max_pos_err_m <= 0.5e-3);
    assert_true(r.m.max_speed_ratio <= 1.0 + 1e-9);
    /* Q1 ~ 0 at the worst point, inside the singular region */
    assert_true(r.m.min_Q1 <= 0.1);
    assert_true(r.m.t_min_Q1_s >= r.m.t_region_in_s && r.m.t_min_Q1_s <= r.m.t_region_out_s);
    /* Q1 = 1 away from it */
    assert_true(r.m.min_Q1_outside >= 1.0 - 1e-12);
    /* the orientation was given up near the singularity, and recovered */
    assert_true(r.m.max_ori_err_rad * RAD2DEG_ > 1.0);
    assert_true(r.m.t_ori_recovered_s > r.m.t_region_in_s);
    assert_true(r.m.t_ori_recovered_s < r.duration_s + 1.0);
    assert_true(r.m.ori_err_end_rad * RAD2DEG_ < 0.5);
    assert_int_equal(r.m.joint_limit_violations, 0);
}

/* The same path with the baselines: the unclipped pseudo-inverse demands
 * far more than the motors can give, and once clipped (pinv) or damped
 * (dls) the tool leaves the path by millimetres. */
static void test_s1_baselines_fail(void **state)
{
    run_out p, d;
    (void)state;
    run_s1(TDSDRUN_PINV, &p);
    run_s1(TDSDRUN_DLS, &d);
    assert_true(p.m.max_demand_ratio > 10.0);
    assert_true(p.m.max_speed_ratio <= 1.0 + 1e-12); /* clipped ... */
    assert_true(p.m.max_pos_err_m > 2e-3);           /* ... so off the path */
    assert_true(d.m.max_pos_err_m > 2e-3);
}

static void test_s2_liquid(void **state)
{
    run_out t, f;
    (void)state;
    run_s2(0, &t);
    run_s2(1, &f);
    assert_int_equal(t.m.joint_limit_violations, 0);
    assert_true(t.m.max_tilt_rad * RAD2DEG_ <= 1.0);
    assert_true(t.m.max_pos_err_m <= 0.5e-3);
    /* the full baseline keeps the bucket level too, but q6 leaves its range */
    assert_true(f.m.joint_limit_violations > 0);
    assert_true(f.m.max_excess_rad[5] * RAD2DEG_ > 10.0);
    assert_true(f.m.max_excess_rad[3] == 0.0 && f.m.max_excess_rad[4] == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_s1_path_crosses_the_shoulder_singularity),
        cmocka_unit_test(test_s1_tdsd_must_show),
        cmocka_unit_test(test_s1_baselines_fail),
        cmocka_unit_test(test_s2_liquid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

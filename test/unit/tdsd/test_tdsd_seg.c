/* Unit tests for tdsd_seg (docs/method/tdsd.md §7: use_tdsd Cartesian segments): closed
 * loop on the kinematic model (the arm follows its joint reference
 * exactly) along a straight tool-down line on the PUMA 560 that passes a
 * few mm from the wrist singularity (q5 = 0): the tool stays within 0.5 mm
 * of the path point, no joint rate exceeds speed_frac * qd_max, the
 * segment reaches its target and the orientation comes back; far from
 * singularities the segment is exact at path rate 1; re-orientation only;
 * bad input; the velocity-limited servo law.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arm_kin.h"
#include "tdsd_seg.h"
#include "vec3.h"

#define DT 0.001
#define TOOL_M 0.10
#define DEG (3.14159265358979323846 / 180.0)

/* Tool-down frame of the cell's arm 1 (x, -y, -z) and the home tool point
 * (0.10, 0.50, 0.45) m in the arm's base frame. */
static const double R_down[9] = { 1, 0, 0, 0, -1, 0, 0, 0, -1 };
static const double q_near_home[ARM_NJ] = { 1.67, 0.71, 2.86, 0.0, -0.42, -1.47 };

static void tool_of(arm_tool *t)
{
    const double off[3] = { 0.0, 0.0, TOOL_M };
    arm_tool_offset(t, off);
}

/* Joint vector for the tool at p with R_down, branch nearest to home. */
static void ik_pose(const double p[3], const double R[9], double q[ARM_NJ])
{
    double T[16];
    arm_tool tool;
    arm_ik_result r;
    int b;
    tool_of(&tool);
    tf_from_rot_pos(T, R, p);
    assert_int_equal(arm_ik(&arm_model_puma560, &tool, T, &r), 0);
    b = arm_ik_nearest(&r, q_near_home);
    assert_true(b >= 0);
    memcpy(q, r.branch[b].q_rad, sizeof(double) * ARM_NJ);
}

/* The wrist line: radially inwards 0.20 m at z = 0.30 m; with the tool
 * straight down the forearm turns through the vertical, i.e. through q5 = 0,
 * about half way. The tool axis tilted sideways by tilt_rad
 * (about the radial direction) makes the forearm pass tilt_rad from it:
 * a near-singular pass, |q5| >= ~tilt, where q4 and q6 must swing by
 * ~150 deg within a few tilt angles of forearm rotation. The line ends
 * where q4 is still inside its range (q4 max 170 deg: with the tool tilted
 * 1 deg and the line 0.1 m longer q4 would end at 178 deg; TDSD does not
 * enforce joint ranges, the path must allow them). */
static void wrist_line(double tilt_rad, double A[3], double B[3], double R1[9])
{
    const double ux = 0.1 / sqrt(0.26), uy = 0.5 / sqrt(0.26); /* radial unit */
    const double r0 = sqrt(0.26) + 0.05, r1 = sqrt(0.26) - 0.15;
    const double radial[3] = { ux, uy, 0.0 };
    double Rt[9];
    vec3_set(A, ux * r0, uy * r0, 0.30);
    vec3_set(B, ux * r1, uy * r1, 0.30);
    rot_from_axis_angle(Rt, radial, tilt_rad);
    rot_mul(R1, Rt, R_down);
}

typedef struct run_result {
    double max_pos_err_m;   /* reference tool vs path point */
    double max_line_dev_m;  /* reference tool vs the straight line */
    double max_speed_ratio; /* max |dq_i| / qd_max_i */
    double min_Q1, min_lambda, min_abs_q5;
    double ori_err_end_rad, final_err_m;
    double t_done_s, t_path_s;
    int errors;
    long limit_violations; /* steps with a joint outside its range */
} run_result;

static double line_distance(const double p[3], const double A[3], const double B[3])
{
    double d[3], u[3], w[3], x[3];
    vec3_sub(d, B, A);
    vec3_normalize(u, d);
    vec3_sub(w, p, A);
    vec3_cross(x, w, u);
    return vec3_norm(x);
}

static void run_kin(const double A[3], const double R0[9], const double B[3], const double R1[9],
                    const tdsd_seg_params *par, double t_max_s, run_result *r)
{
    const arm_model *m = &arm_model_puma560;
    double q[ARM_NJ], qd[ARM_NJ], Tid[16], T[16], p[3], d[3];
    arm_tool tool;
    tdsd_seg g;
    tdsd_seg_out o;
    int i;
    double t = 0.0;
    tool_of(&tool);
    tf_identity(Tid);
    ik_pose(A, R0, q);
    memset(r, 0, sizeof *r);
    r->min_Q1 = r->min_lambda = 1.0;
    r->min_abs_q5 = INFINITY;
    r->t_done_s = r->t_path_s = -1.0;
    assert_int_equal(tdsd_seg_start(&g, m, &tool, Tid, q, B, R1, par), 0);
    for (; t < t_max_s; t += DT) {
        if (tdsd_seg_step(&g, m, DT, &o) != TDSD_OK)
            r->errors++;
        /* kinematic plant: the arm is where its reference is */
        memcpy(q, o.q_d, sizeof q);
        memcpy(qd, o.qd_d, sizeof qd);
        assert_int_equal(arm_fk(m, &tool, q, T), 0);
        tf_pos(p, T);
        vec3_sub(d, p, o.p_d_world);
        /* o.pos_err_m is the error before this step's integration; check
         * the integrated pose against the next reference point instead */
        r->max_pos_err_m = fmax(r->max_pos_err_m, o.pos_err_m);
        r->max_line_dev_m = fmax(r->max_line_dev_m, line_distance(p, A, B));
        for (i = 0; i < ARM_NJ; i++)
            r->max_speed_ratio = fmax(r->max_speed_ratio, fabs(qd[i]) / m->qd_max_radps[i]);
        r->min_Q1 = fmin(r->min_Q1, o.Q1);
        r->min_lambda = fmin(r->min_lambda, o.lambda);
        r->min_abs_q5 = fmin(r->min_abs_q5, fabs(q[4]));
        r->limit_violations += arm_q_outside_limits(m, q) != 0;
        r->ori_err_end_rad = o.ori_err_rad;
        if (o.path_done && r->t_path_s < 0.0)
            r->t_path_s = t;
        if (getenv("TDSD_SEG_TRACE") && ((long)(t / DT + 0.5)) % 20 == 0)
            printf(
                "    t %.3f s %.4f lam %.3f Q1 %.3f Q2 %.3f ep %.4f mm eo %.4f q %.3f %.3f %.3f %.3f %.3f %.3f dq %.2f %.2f %.2f %.2f %.2f %.2f\n",
                t, o.s_m, o.lambda, o.Q1, o.Q2, o.pos_err_m * 1e3, o.ori_err_rad, q[0], q[1], q[2],
                q[3], q[4], q[5], qd[0], qd[1], qd[2], qd[3], qd[4], qd[5]);
        if (tdsd_seg_done(&g, q, (double[ARM_NJ]){ 0 })) {
            r->t_done_s = t;
            break;
        }
    }
    vec3_sub(d, p, B);
    r->final_err_m = vec3_norm(d);
}

static void print_result(const char *what, const run_result *r)
{
    printf(
        "  %-28s pos err %.4f mm, line dev %.4f mm, speed ratio %.3f, min Q1 %.3f, min lambda %.3f, "
        "min |q5| %.2f deg, path %.3f s, done %.3f s, final %.4f mm, ori end %.3f deg\n",
        what, r->max_pos_err_m * 1e3, r->max_line_dev_m * 1e3, r->max_speed_ratio, r->min_Q1,
        r->min_lambda, r->min_abs_q5 / DEG, r->t_path_s, r->t_done_s, r->final_err_m * 1e3,
        asin(fmin(1.0, r->ori_err_end_rad)) / DEG);
}

static void default_params(tdsd_seg_params *p)
{
    tdsd_seg_default_params(p, 0.25, 0.5, 4.0); /* carry_net's FREE row */
}

/* Through and near the wrist singularity: on the path, within the limits,
 * at the target, orientation recovered. */
static void test_wrist_singularity_kin(void **state)
{
    static const double tilts_deg[] = { 0.0, 2.0, 3.0, 4.0 };
    tdsd_seg_params par;
    run_result r;
    double A[3], B[3], R1[9];
    unsigned k;
    (void)state;
    default_params(&par);
    for (k = 0; k < sizeof tilts_deg / sizeof tilts_deg[0]; k++) {
        char what[64];
        wrist_line(tilts_deg[k] * DEG, A, B, R1);
        run_kin(A, R1, B, R1, &par, 8.0, &r);
        snprintf(what, sizeof what, "wrist line, tilt %.0f deg", tilts_deg[k]);
        print_result(what, &r);
        assert_int_equal(r.errors, 0);
        assert_true(r.max_pos_err_m <= 0.0005);
        assert_true(r.max_line_dev_m <= 0.0005);
        assert_true(r.max_speed_ratio <= par.speed_frac + 1e-9);
        assert_true(r.t_done_s > 0.0);
        assert_true(r.final_err_m <= 0.0005);
        assert_true(r.ori_err_end_rad <= TDSD_SEG_DONE_ORI_RAD);
        assert_int_equal(r.limit_violations, 0);
        if (tilts_deg[k] > 0.0 && tilts_deg[k] <= 3.0) {
            /* it really passed near the singular pose, and TDSD had to
             * give up orientation there (q4, q6 at their speed limits) */
            assert_true(r.min_abs_q5 < (tilts_deg[k] + 1.0) * DEG);
            assert_true(r.min_Q1 < 0.5);
            assert_true(r.max_speed_ratio > 0.8 * par.speed_frac);
        } /* it really passed the singular pose */
    }
}

/* Away from singularities: Q1 = 1, path rate 1, the segment takes the
 * profile's nominal time. */
static void test_regular_line_exact(void **state)
{
    tdsd_seg_params par;
    run_result r;
    const double A[3] = { 0.10, 0.55, 0.40 }, B[3] = { 0.25, 0.45, 0.30 };
    (void)state;
    default_params(&par);
    run_kin(A, R_down, B, R_down, &par, 5.0, &r);
    print_result("regular line", &r);
    assert_int_equal(r.errors, 0);
    assert_true(r.min_Q1 == 1.0);
    assert_true(r.min_lambda == 1.0);
    assert_true(r.max_pos_err_m < 1e-4);
    assert_true(r.t_done_s > 0.0 && r.final_err_m < 5e-4);
}

/* A pure re-orientation (no translation) still has a profile and ends on
 * the target frame with the tool point kept. */
static void test_rotation_only(void **state)
{
    tdsd_seg_params par;
    run_result r;
    const double A[3] = { 0.10, 0.55, 0.40 };
    const double z[3] = { 0, 0, 1 };
    double Rz[9], R1[9];
    (void)state;
    default_params(&par);
    rot_from_axis_angle(Rz, z, 30.0 * DEG);
    rot_mul(R1, Rz, R_down);
    run_kin(A, R_down, A, R1, &par, 5.0, &r);
    print_result("rotation only (30 deg)", &r);
    assert_int_equal(r.errors, 0);
    assert_true(r.t_done_s > 0.0);
    assert_true(r.max_pos_err_m < 1e-4 && r.final_err_m < 5e-4);
    assert_true(r.ori_err_end_rad <= TDSD_SEG_DONE_ORI_RAD);
}

static void test_bad_input(void **state)
{
    tdsd_seg_params par;
    tdsd_seg g;
    arm_tool tool;
    double Tid[16], q[ARM_NJ];
    const double B[3] = { 0.1, 0.5, 0.3 }, nan_p[3] = { NAN, 0, 0 };
    (void)state;
    tool_of(&tool);
    tf_identity(Tid);
    memcpy(q, q_near_home, sizeof q);
    default_params(&par);
    assert_int_equal(tdsd_seg_start(&g, &arm_model_puma560, &tool, Tid, q, nan_p, R_down, &par),
                     TDSD_SEG_ERR_ARG);
    par.speed_frac = 1.5;
    assert_int_equal(tdsd_seg_start(&g, &arm_model_puma560, &tool, Tid, q, B, R_down, &par),
                     TDSD_SEG_ERR_ARG);
    default_params(&par);
    par.v_m = 0.0;
    assert_int_equal(tdsd_seg_start(&g, &arm_model_puma560, &tool, Tid, q, B, R_down, &par),
                     TDSD_SEG_ERR_ARG);
    default_params(&par);
    q[2] = INFINITY;
    assert_int_equal(tdsd_seg_start(&g, &arm_model_puma560, &tool, Tid, q, B, R_down, &par),
                     TDSD_SEG_ERR_ARG);
    /* the model's limits and the criterion's ranges are checked once, at
     * the start (tdsd_seg_step then checks neither) */
    memcpy(q, q_near_home, sizeof q);
    {
        arm_model bad = arm_model_puma560;
        bad.qd_max_radps[1] = 0.0;
        assert_int_equal(tdsd_seg_start(&g, &bad, &tool, Tid, q, B, R_down, &par),
                         TDSD_SEG_ERR_ARG);
        bad = arm_model_puma560;
        bad.q_min_rad[4] = bad.q_max_rad[4]; /* joint 5: in the criterion's mask */
        assert_int_equal(tdsd_seg_start(&g, &bad, &tool, Tid, q, B, R_down, &par),
                         TDSD_SEG_ERR_ARG);
        par.criterion_mask = 0x07u; /* not in it: accepted */
        assert_int_equal(tdsd_seg_start(&g, &bad, &tool, Tid, q, B, R_down, &par), 0);
    }
}

/* Velocity limit: unchanged law below the limit; above it, the servo
 * acceleration is Kv (+-lim - qd) (checked through jointctl's formula). */
static void test_servo_vlimit(void **state)
{
    const jointctl_gains g = { 50.0, 1.0 };
    const double kp = g.wn_radps * g.wn_radps, kv = 2.0 * g.zeta * g.wn_radps;
    const double lim[ARM_NJ] = { 2, 1.75, 2.2, 4, 3.6, 4.6 };
    double q[ARM_NJ] = { 0.1, 0.2, 0.3, 0.4, 0.5, 0.6 }, qd[ARM_NJ] = { 1.9, 0, 0, 0, 0, 0 };
    double q_d[ARM_NJ], qd_d[ARM_NJ], qdd_d[ARM_NJ], q_d0[ARM_NJ], qd_d0[ARM_NJ], qdd_d0[ARM_NJ];
    int i;
    (void)state;
    for (i = 0; i < ARM_NJ; i++) {
        q_d0[i] = q[i] + 0.001 * (i + 1);
        qd_d0[i] = 0.5 * lim[i];
        qdd_d0[i] = 3.0;
    }
    q_d0[0] = q[0] + 0.05; /* joint 1 lags: v_c = 2 + 25 * 0.05 > 2 */
    qd_d0[0] = lim[0];
    qd_d0[3] = -lim[3];
    q_d0[3] = q[3] - 0.01; /* joint 4 lags the other way */
    memcpy(q_d, q_d0, sizeof q_d);
    memcpy(qd_d, qd_d0, sizeof qd_d);
    memcpy(qdd_d, qdd_d0, sizeof qdd_d);
    assert_int_equal(tdsd_servo_vlimit(&g, lim, q, q_d, qd_d, qdd_d), 2);
    for (i = 0; i < ARM_NJ; i++) {
        const double a = qdd_d[i] + kv * (qd_d[i] - qd[i]) + kp * (q_d[i] - q[i]);
        const double a0 = qdd_d0[i] + kv * (qd_d0[i] - qd[i]) + kp * (q_d0[i] - q[i]);
        if (i == 0)
            assert_true(fabs(a - kv * (lim[0] - qd[0])) < 1e-9);
        else if (i == 3)
            assert_true(fabs(a - kv * (-lim[3] - qd[3])) < 1e-9);
        else
            assert_true(fabs(a - a0) < 1e-12);
    }
    /* first-order approach: integrating qd' = a from below never crosses the limit */
    {
        double v = 1.5, x = 0.0, xr = 0.1;
        int k;
        for (k = 0; k < 2000; k++) {
            double qq[ARM_NJ] = { x, 0, 0, 0, 0, 0 }, qdr[ARM_NJ] = { 2.0, 0, 0, 0, 0, 0 };
            double qr[ARM_NJ] = { xr, 0, 0, 0, 0, 0 }, ar[ARM_NJ] = { 0 };
            tdsd_servo_vlimit(&g, lim, qq, qr, qdr, ar);
            v += 1e-4 * (ar[0] + kv * (qdr[0] - v) + kp * (qr[0] - x));
            x += 1e-4 * v;
            xr += 1e-4 * 2.0;
            assert_true(v <= lim[0] + 1e-9);
        }
    }
    assert_int_equal(tdsd_servo_vlimit(NULL, lim, q, q_d, qd_d, qdd_d), TDSD_SEG_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrist_singularity_kin), cmocka_unit_test(test_regular_line_exact),
        cmocka_unit_test(test_rotation_only),         cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_servo_vlimit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

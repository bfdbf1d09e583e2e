/* test_arm_kin: Jacobian against finite differences of FK, the one-pass
 * kinematics (arm_kin_eval) against FK and Jacobian, analytic Jdot qd against
 * a central difference of J along qd, FK(IK(x)) = x
 * on every branch for random reachable poses (both arms, with and without
 * a tool), branch naming, limit and reach flags, known pose at q = 0. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include "arm_samples.h"
#include "arm_kin.h"
#include "vec3.h"

#define PI 3.14159265358979323846

static const arm_model *const models[] = { &arm_model_puma560, &arm_model_seed002 };
#define NMODELS (sizeof models / sizeof models[0])

static double pose_error(const double A[16], const double B[16])
{
    double e = 0.0;
    int i;
    for (i = 0; i < 12; i++)
        if (fabs(A[i] - B[i]) > e)
            e = fabs(A[i] - B[i]);
    return e;
}

/* Corke: fkine(p560, qz) = [0.4521 -0.15005 0.4318] in the shoulder frame,
 * identity rotation; our base frame adds the 0.6718 m base height. */
static void test_fk_zero_pose(void **state)
{
    const double q[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    double T[16];
    (void)state;
    assert_int_equal(arm_fk(&arm_model_puma560, NULL, q, T), 0);
    assert_true(fabs(T[3] - 0.4521) < 1e-12);
    assert_true(fabs(T[7] + 0.15005) < 1e-12);
    assert_true(fabs(T[11] - (0.4318 + 0.6718)) < 1e-12);
    assert_true(fabs(T[0] - 1) < 1e-12 && fabs(T[5] - 1) < 1e-12 && fabs(T[10] - 1) < 1e-12);
    /* seed002 at q = 0: upper arm (lc) horizontal, forearm (lf) and
     * flange offset (lg) vertical above the elbow */
    assert_int_equal(arm_fk(&arm_model_seed002, NULL, q, T), 0);
    assert_true(fabs(T[3] - 0.433) < 1e-12);
    assert_true(fabs(T[7]) < 1e-12);
    assert_true(fabs(T[11] - (0.671 + 0.433 + 0.050)) < 1e-12);
}

static void check_jacobian(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ])
{
    const double h = 1e-6;
    double J[36], Tp[16], Tm[16], Rp[9], Rm[9], dR[9], axis[3];
    int i, r;
    assert_int_equal(arm_jacobian(m, tool, q, J), 0);
    for (i = 0; i < ARM_NJ; i++) {
        double qp[ARM_NJ], qm[ARM_NJ], ang;
        memcpy(qp, q, sizeof qp);
        memcpy(qm, q, sizeof qm);
        qp[i] += h;
        qm[i] -= h;
        arm_fk(m, tool, qp, Tp);
        arm_fk(m, tool, qm, Tm);
        /* linear: central difference of the point */
        for (r = 0; r < 3; r++)
            assert_true(fabs((Tp[4 * r + 3] - Tm[4 * r + 3]) / (2 * h) - J[r * 6 + i]) < 1e-7);
        /* angular: Rp Rm^T = rotation by w * 2h (base coordinates) */
        tf_rot(Rp, Tp);
        tf_rot(Rm, Tm);
        {
            double Rmt[9];
            rot_transpose(Rmt, Rm);
            rot_mul(dR, Rp, Rmt);
        }
        ang = rot_to_axis_angle(axis, dR);
        for (r = 0; r < 3; r++)
            assert_true(fabs(axis[r] * ang / (2 * h) - J[(3 + r) * 6 + i]) < 1e-7);
    }
}

static void test_jacobian_finite_differences(void **state)
{
    prng_state seed;
    prng_seed(&seed, 11);
    const double p[3] = { 0.02, -0.03, 0.12 };
    arm_tool tool;
    size_t k;
    int n;
    (void)state;
    arm_tool_offset(&tool, p);
    for (k = 0; k < NMODELS; k++)
        for (n = 0; n < 200; n++) {
            double q[ARM_NJ];
            random_q(models[k], &seed, q);
            check_jacobian(models[k], NULL, q);
            check_jacobian(models[k], &tool, q);
        }
}

/* Jdot qd by a central difference of J along qd: truncation ~h^2, rounding
 * ~eps/h, both below 1e-9 at h = 1e-5 for |qd| ~ 1 rad/s, while Jdot qd
 * itself is ~0.1-10: the tolerance 1e-7 catches any wrong term. */
static void check_jdot(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                       const double qd[ARM_NJ])
{
    const double h = 1e-5;
    arm_kin_pass k;
    double T[16], J[36], jd[6], qp[ARM_NJ], qm[ARM_NJ], Jp[36], Jm[36];
    int i, j;
    assert_int_equal(arm_kin_eval(m, tool, q, &k), 0);
    assert_int_equal(arm_fk_jacobian(m, tool, q, T, J), 0);
    assert_memory_equal(k.T, T, sizeof T); /* same arithmetic, same bits */
    assert_memory_equal(k.J, J, sizeof J);
    assert_int_equal(arm_kin_jdot_qd(&k, qd, jd), 0);
    for (i = 0; i < ARM_NJ; i++) {
        qp[i] = q[i] + h * qd[i];
        qm[i] = q[i] - h * qd[i];
    }
    assert_int_equal(arm_jacobian(m, tool, qp, Jp), 0);
    assert_int_equal(arm_jacobian(m, tool, qm, Jm), 0);
    for (i = 0; i < 6; i++) {
        double fd = 0.0;
        for (j = 0; j < ARM_NJ; j++)
            fd += (Jp[i * 6 + j] - Jm[i * 6 + j]) * qd[j];
        fd /= 2.0 * h;
        assert_true(fabs(fd - jd[i]) < 1e-7);
    }
}

static void test_jdot_qd_finite_differences(void **state)
{
    const double p[3] = { 0.02, -0.03, 0.12 };
    /* the PUMA's singularities: wrist (q5 = 0), elbow straight, wrist
     * centre over the shoulder axis is pose-dependent (random covers it) */
    static const double q_sing[][ARM_NJ] = {
        { 0.3, -0.5, 0.8, 1.0, 0.0, -0.4 },
        { 0.0, 0.0, -1.5707963267948966, 0.0, 0.0, 0.0 },
        { 0, 0, 0, 0, 0, 0 },
    };
    prng_state seed;
    arm_tool tool;
    size_t k, s;
    int n, j;
    (void)state;
    prng_seed(&seed, 21);
    arm_tool_offset(&tool, p);
    for (k = 0; k < NMODELS; k++) {
        for (n = 0; n < 500; n++) {
            double q[ARM_NJ], qd[ARM_NJ];
            random_q(models[k], &seed, q);
            for (j = 0; j < ARM_NJ; j++)
                qd[j] = 2.0 * prng_uniform(&seed) - 1.0;
            check_jdot(models[k], NULL, q, qd);
            check_jdot(models[k], &tool, q, qd);
        }
        for (s = 0; s < sizeof q_sing / sizeof q_sing[0]; s++) {
            const double qd[ARM_NJ] = { 0.4, -0.7, 0.9, 1.1, -0.6, 0.8 };
            check_jdot(models[k], &tool, q_sing[s], qd);
        }
    }
}

/* Distance of q1 from q2 modulo 2 pi, max over joints. */
static double angle_dist(const double a[ARM_NJ], const double b[ARM_NJ])
{
    double d = 0.0;
    int j;
    for (j = 0; j < ARM_NJ; j++) {
        double e = fmod(fabs(a[j] - b[j]), 2 * PI);
        if (e > PI)
            e = 2 * PI - e;
        if (e > d)
            d = e;
    }
    return d;
}

static void ik_round_trip(const arm_model *m, const arm_tool *tool, prng_state *seed, int n_poses)
{
    int n, b, found_original = 0, n_checked = 0;
    for (n = 0; n < n_poses; n++) {
        double q[ARM_NJ], T[16], Tb[16];
        arm_ik_result r;
        int bo;
        random_q(m, seed, q);
        arm_fk(m, tool, q, T);
        assert_int_equal(arm_ik(m, tool, T, &r), 0);
        assert_int_equal(r.unreachable, 0);
        for (b = 0; b < ARM_IK_NBRANCH; b++) {
            const arm_ik_branch *br = &r.branch[b];
            /* a pose produced by FK is reachable on all eight branches */
            assert_false(br->status & ARM_IK_UNREACHABLE);
            arm_fk(m, tool, br->q_rad, Tb);
            assert_true(pose_error(T, Tb) < 1e-9);
            /* flag and bits agree with the model's limits */
            assert_int_equal(br->limit_bits, arm_q_outside_limits(m, br->q_rad));
            assert_int_equal(!!(br->status & ARM_IK_OUTSIDE_LIMITS), br->limit_bits != 0);
            /* the branch a solution lies on is the one it is filed under
             * (skip configurations on a branch boundary) */
            if (fabs(cos(br->q_rad[3])) > 1e-6 && fabs(sin(br->q_rad[4])) > 1e-6)
                assert_int_equal(arm_ik_branch_of(m, br->q_rad), b);
        }
        /* the original configuration is one of the solutions (away from
         * the wrist singularity, where q4 and q6 are not separable) */
        bo = arm_ik_branch_of(m, q);
        if (fabs(sin(q[4])) > 1e-3) {
            n_checked++;
            if (angle_dist(r.branch[bo].q_rad, q) < 1e-7)
                found_original++;
        }
    }
    assert_int_equal(found_original, n_checked);
}

static void test_ik_round_trip(void **state)
{
    prng_state seed;
    prng_seed(&seed, 12345);
    const double p[3] = { 0.0, 0.05, 0.20 };
    arm_tool tool;
    size_t k;
    (void)state;
    arm_tool_offset(&tool, p);
    for (k = 0; k < NMODELS; k++) {
        ik_round_trip(models[k], NULL, &seed, 1000);
        ik_round_trip(models[k], &tool, &seed, 300);
    }
}

/* Narrow q4 to [-10, 10] deg: for a pose reached with q4 = 0 the flipped
 * wrist (q4 = 180 deg) must be flagged, the unflipped one must not. */
static void test_ik_limit_flags(void **state)
{
    arm_model narrow = arm_model_puma560;
    const double q[ARM_NJ] = { 0.2, -0.6, 2.6, 0.0, 0.7, 0.3 };
    double T[16];
    arm_ik_result r;
    int b, found = -1;
    (void)state;
    narrow.q_min_rad[3] = -10 * PI / 180;
    narrow.q_max_rad[3] = 10 * PI / 180;
    arm_fk(&narrow, NULL, q, T);
    assert_int_equal(arm_ik(&narrow, NULL, T, &r), 0);
    for (b = 0; b < ARM_IK_NBRANCH; b++) {
        if (b & 4) {
            assert_true(r.branch[b].status & ARM_IK_OUTSIDE_LIMITS);
            assert_true(r.branch[b].limit_bits & (1u << 3));
        }
        if (angle_dist(r.branch[b].q_rad, q) < 1e-9) {
            found = b;
            assert_int_equal(r.branch[b].status, ARM_IK_OK);
        }
    }
    assert_true(found >= 0 && !(found & 4));
    assert_int_equal(arm_ik_nearest(&r, q), found);
    assert_true(r.n_valid >= 1 && r.n_valid <= 4);
}

static void test_ik_unreachable(void **state)
{
    double T[16];
    arm_ik_result r;
    int b;
    (void)state;
    tf_identity(T);
    /* 3 m away: beyond both arms' reach */
    T[3] = 3.0;
    T[11] = 0.7;
    assert_int_equal(arm_ik(&arm_model_puma560, NULL, T, &r), 0);
    assert_int_equal(r.unreachable, 1);
    assert_int_equal(r.n_valid, 0);
    for (b = 0; b < ARM_IK_NBRANCH; b++)
        assert_true(r.branch[b].status & ARM_IK_UNREACHABLE);
    assert_int_equal(arm_ik_nearest(&r, T), ARM_KIN_ERR_NO_BRANCH);
    /* PUMA wrist centre inside the d3 = 0.15 m cylinder about joint 1 */
    T[3] = 0.05;
    T[7] = 0.0;
    T[11] = 1.0;
    assert_int_equal(arm_ik(&arm_model_puma560, NULL, T, &r), 0);
    assert_int_equal(r.unreachable, 1);
    /* seed002 has no offset: the same point is reachable */
    assert_int_equal(arm_ik(&arm_model_seed002, NULL, T, &r), 0);
    assert_int_equal(r.unreachable, 0);
}

static void test_branch_names(void **state)
{
    int b;
    (void)state;
    assert_string_equal(arm_ik_branch_name(0), "left-up-noflip");
    assert_string_equal(arm_ik_branch_name(7), "right-down-flip");
    assert_string_equal(arm_ik_branch_name(8), "invalid");
    for (b = 0; b < ARM_IK_NBRANCH; b++)
        assert_int_equal(arm_ik_branch_from_name(arm_ik_branch_name(b)), b);
    assert_int_equal(arm_ik_branch_from_name("up"), ARM_KIN_ERR_NO_BRANCH);
}

static void test_bad_input(void **state)
{
    double T[16], J[36], q[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    arm_ik_result r;
    arm_model odd = arm_model_puma560;
    (void)state;
    tf_identity(T);
    T[5] = NAN;
    assert_int_equal(arm_ik(&arm_model_puma560, NULL, T, &r), ARM_KIN_ERR_ARG);
    assert_int_equal(arm_ik(&arm_model_puma560, NULL, NULL, &r), ARM_KIN_ERR_ARG);
    tf_identity(T);
    odd.a_m[4] = 0.01; /* not a spherical wrist */
    assert_int_equal(arm_ik(&odd, NULL, T, &r), ARM_KIN_ERR_GEOMETRY);
    q[2] = NAN;
    assert_int_equal(arm_fk(&arm_model_puma560, NULL, q, T), ARM_KIN_ERR_ARG);
    assert_int_equal(arm_jacobian(&arm_model_puma560, NULL, q, J), ARM_KIN_ERR_ARG);
    {
        arm_kin_pass k;
        double jd[6], qd[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
        assert_int_equal(arm_kin_eval(&arm_model_puma560, NULL, q, &k), ARM_KIN_ERR_ARG);
        q[2] = 0.0;
        assert_int_equal(arm_kin_eval(&arm_model_puma560, NULL, q, &k), 0);
        qd[1] = INFINITY;
        assert_int_equal(arm_kin_jdot_qd(&k, qd, jd), ARM_KIN_ERR_ARG);
        assert_int_equal(arm_kin_jdot_qd(NULL, qd, jd), ARM_KIN_ERR_ARG);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fk_zero_pose),
        cmocka_unit_test(test_jacobian_finite_differences),
        cmocka_unit_test(test_jdot_qd_finite_differences),
        cmocka_unit_test(test_ik_round_trip),
        cmocka_unit_test(test_ik_limit_flags),
        cmocka_unit_test(test_ik_unreachable),
        cmocka_unit_test(test_branch_names),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

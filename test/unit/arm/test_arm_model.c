/* test_arm_model: table sanity (physically valid bodies for ODE), link
 * frames consistent with the DH chain and FK, tool offsets, bad input. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <string.h>
#include "arm_samples.h"
#include "arm_model.h"
#include "arm_kin.h"
#include "vec3.h"

static const arm_model *const models[] = { &arm_model_puma560, &arm_model_seed002 };

static void test_by_name(void **state)
{
    (void)state;
    assert_ptr_equal(arm_model_by_name("puma560"), &arm_model_puma560);
    assert_ptr_equal(arm_model_by_name("seed002"), &arm_model_seed002);
    assert_null(arm_model_by_name("puma761"));
    assert_null(arm_model_by_name(NULL));
}

/* Every link must be a valid ODE body: m > 0, inertia symmetric positive
 * definite (leading minors > 0); link 1 keeps Corke's 0.35 about its axis. */
static void test_mass_properties_valid(void **state)
{
    size_t k;
    int i;
    (void)state;
    for (k = 0; k < sizeof models / sizeof models[0]; k++) {
        const arm_model *m = models[k];
        for (i = 0; i < ARM_NJ; i++) {
            const double *I = m->inertia_kgm2[i];
            const double m1 = I[0];
            const double m2 = I[0] * I[4] - I[1] * I[3];
            const double m3 = I[0] * (I[4] * I[8] - I[5] * I[7]) -
                              I[1] * (I[3] * I[8] - I[5] * I[6]) +
                              I[2] * (I[3] * I[7] - I[4] * I[6]);
            assert_true(m->mass_kg[i] > 0.0);
            assert_true(m1 > 0.0 && m2 > 0.0 && m3 > 0.0);
            assert_true(fabs(I[1] - I[3]) < 1e-15 && fabs(I[2] - I[6]) < 1e-15 &&
                        fabs(I[5] - I[7]) < 1e-15);
            assert_true(m->q_min_rad[i] < m->q_max_rad[i]);
            assert_true(m->qd_max_radps[i] > 0.0 && m->tau_max_Nm[i] > 0.0);
        }
        /* joint 1 axis is y of frame 1 (alpha1 = 90 deg) */
        assert_true(fabs(m->inertia_kgm2[0][4] - 0.35) < 1e-12);
        assert_true(vec3_norm(m->com_m[0]) == 0.0);
    }
}

static void test_frames_chain_and_fk(void **state)
{
    prng_state seed;
    prng_seed(&seed, 7);
    size_t k;
    int n, i, e;
    (void)state;
    for (k = 0; k < sizeof models / sizeof models[0]; k++) {
        const arm_model *m = models[k];
        for (n = 0; n < 200; n++) {
            double q[ARM_NJ], F[ARM_NJ + 1][16], T[16], A[16], C[16], R[9], RtR[9];
            random_q(m, &seed, q);
            assert_int_equal(arm_link_frames(m, q, F), 0);
            assert_true(fabs(F[0][11] - m->base_height_m) < 1e-15);
            assert_int_equal(arm_fk(m, NULL, q, T), 0);
            for (e = 0; e < 16; e++)
                assert_true(fabs(F[ARM_NJ][e] - T[e]) < 1e-12);
            for (i = 0; i < ARM_NJ; i++) {
                /* consecutive frames differ by the DH transform of joint i */
                arm_dh_transform(m, i, q[i], A);
                tf_mul(C, F[i], A);
                for (e = 0; e < 16; e++)
                    assert_true(fabs(C[e] - F[i + 1][e]) < 1e-12);
                tf_rot(R, F[i + 1]);
                rot_tmul(RtR, R, R);
                for (e = 0; e < 9; e++)
                    assert_true(fabs(RtR[e] - (e % 4 == 0 ? 1.0 : 0.0)) < 1e-12);
            }
        }
    }
}

static void test_tool_offset(void **state)
{
    const double p[3] = { 0.01, -0.02, 0.15 };
    const double q[ARM_NJ] = { 0.3, -0.7, 1.1, 0.4, -0.5, 2.0 };
    const double bad[3] = { 0.0, NAN, 0.0 };
    arm_tool tool;
    double T6[16], Tt[16], pt[3], pw[3];
    (void)state;
    assert_int_equal(arm_tool_offset(&tool, p), 0);
    assert_int_equal(arm_tool_offset(&tool, bad), ARM_MODEL_ERR_ARG);
    assert_int_equal(arm_tool_offset(&tool, p), 0);
    arm_fk(&arm_model_puma560, NULL, q, T6);
    arm_fk(&arm_model_puma560, &tool, q, Tt);
    /* the tool point is the flange point p carried by the flange rotation */
    tf_pos(pt, Tt);
    tf_apply(pw, T6, p);
    assert_true(fabs(pt[0] - pw[0]) < 1e-14 && fabs(pt[1] - pw[1]) < 1e-14 &&
                fabs(pt[2] - pw[2]) < 1e-14);
    arm_tool_none(&tool);
    arm_fk(&arm_model_puma560, &tool, q, Tt);
    assert_memory_equal(Tt, T6, sizeof Tt);
}

/* The tables carry cos/sin of alpha so no routine evaluates them per call:
 * they must be the very numbers cos(alpha_rad), sin(alpha_rad). */
static void test_alpha_trig_tables(void **state)
{
    size_t k;
    int i;
    (void)state;
    for (k = 0; k < sizeof models / sizeof models[0]; k++) {
        arm_model copy = *models[k];
        for (i = 0; i < ARM_NJ; i++) {
            assert_true(fabs(models[k]->cos_alpha[i] - cos(models[k]->alpha_rad[i])) <=
                        DBL_EPSILON);
            assert_true(fabs(models[k]->sin_alpha[i] - sin(models[k]->alpha_rad[i])) <=
                        DBL_EPSILON);
        }
        memset(copy.cos_alpha, 0, sizeof copy.cos_alpha);
        memset(copy.sin_alpha, 0, sizeof copy.sin_alpha);
        arm_model_refresh_alpha(&copy);
        for (i = 0; i < ARM_NJ; i++) {
            assert_true(fabs(copy.cos_alpha[i] - models[k]->cos_alpha[i]) <= DBL_EPSILON);
            assert_true(fabs(copy.sin_alpha[i] - models[k]->sin_alpha[i]) <= DBL_EPSILON);
        }
    }
}

/* The DH-specialised product equals the general T * A_i, in place too, for
 * twist angles that are not multiples of 90 deg. */
static void test_dh_compose_general_alpha(void **state)
{
    static const double alpha[ARM_NJ] = { 1.2, -0.4, 2.3, 0.7, -1.9, 0.3 };
    arm_model m = arm_model_puma560;
    prng_state seed;
    prng_seed(&seed, 11);
    int n, i, e;
    (void)state;
    m.structure = ARM_STRUCTURE_GENERAL; /* not a PUMA any more */
    for (i = 0; i < ARM_NJ; i++) {
        m.alpha_rad[i] = alpha[i];
        m.a_m[i] += 0.01 * (i + 1);
        m.theta_offset_rad[i] = 0.1 * i;
    }
    arm_model_refresh_alpha(&m);
    for (n = 0; n < 100; n++) {
        double q[ARM_NJ], F[ARM_NJ + 1][16], T[16], A[16], C[16];
        arm_joint_cs cs;
        random_q(&m, &seed, q);
        assert_int_equal(arm_joint_cs_eval(&m, q, &cs), 0);
        assert_int_equal(arm_link_frames(&m, q, F), 0);
        for (i = 0; i < ARM_NJ; i++) {
            assert_true(fabs(cs.c[i] - cos(q[i] + m.theta_offset_rad[i])) <= DBL_EPSILON);
            assert_true(fabs(cs.s[i] - sin(q[i] + m.theta_offset_rad[i])) <= DBL_EPSILON);
            arm_dh_transform(&m, i, q[i], A);
            tf_mul(C, F[i], A);
            memcpy(T, F[i], sizeof T);
            arm_dh_compose(&m, i, cs.c[i], cs.s[i], T, T);
            for (e = 0; e < 16; e++) {
                assert_true(fabs(C[e] - F[i + 1][e]) < 1e-14);
                assert_true(fabs(T[e] - F[i + 1][e]) == 0.0);
            }
        }
    }
}

static void test_bad_input(void **state)
{
    double q[ARM_NJ] = { 0, 0, 0, 0, 0, 0 }, F[ARM_NJ + 1][16];
    (void)state;
    assert_int_equal(arm_link_frames(NULL, q, F), ARM_MODEL_ERR_ARG);
    assert_int_equal(arm_link_frames(&arm_model_puma560, NULL, F), ARM_MODEL_ERR_ARG);
    q[3] = NAN;
    assert_int_equal(arm_link_frames(&arm_model_puma560, q, F), ARM_MODEL_ERR_ARG);
    q[3] = INFINITY;
    assert_int_equal(arm_q_finite(q), ARM_MODEL_ERR_ARG);
    q[3] = 0.0;
    assert_int_equal(arm_q_finite(q), 0);
    assert_int_equal(arm_q_outside_limits(&arm_model_puma560, q), 0u);
    q[1] = 1.0; /* q2 max is 45 deg */
    assert_int_equal(arm_q_outside_limits(&arm_model_puma560, q), 1u << 1);
}

/* arm_joint_faults: range with its tolerance, speed, NaN; one bit per joint */
static void test_joint_faults(void **st)
{
    const arm_model *m = &arm_model_puma560;
    double q[ARM_NJ], qd[ARM_NJ] = { 0 };
    int i;
    (void)st;
    for (i = 0; i < ARM_NJ; i++)
        q[i] = m->q_max_rad[i] + 0.9 * ARM_RANGE_TOL_RAD; /* on the stop: inside */
    assert_int_equal(arm_joint_faults(m, q, qd), 0u);
    for (i = 0; i < ARM_NJ; i++) {
        double qq[ARM_NJ], vv[ARM_NJ] = { 0 };
        memcpy(qq, q, sizeof qq);
        qq[i] = m->q_min_rad[i] - 1.1 * ARM_RANGE_TOL_RAD;
        assert_int_equal(arm_joint_faults(m, qq, vv), 1u << i);
        assert_int_equal(ARM_FAULT_RANGE(arm_joint_faults(m, qq, vv)), 1u << i);
        qq[i] = q[i];
        vv[i] = -1.01 * m->qd_max_radps[i];
        assert_int_equal(ARM_FAULT_SPEED(arm_joint_faults(m, qq, vv)), 1u << i);
        assert_int_equal(ARM_FAULT_RANGE(arm_joint_faults(m, qq, vv)), 0u);
        vv[i] = 0.99 * m->qd_max_radps[i];
        assert_int_equal(arm_joint_faults(m, qq, vv), 0u);
        qq[i] = NAN;
        assert_int_equal(arm_joint_faults(m, qq, vv), 1u << i);
    }
}

/* Both shipped tables pass; a copy with one field broken fails with the
 * code that names the fault. */
static void test_validate(void **state)
{
    arm_model m;
    (void)state;
    assert_int_equal(arm_model_validate(&arm_model_puma560), 0);
    assert_int_equal(arm_model_validate(&arm_model_seed002), 0);
    assert_int_equal(arm_model_validate(NULL), ARM_MODEL_ERR_ARG);
#define BROKEN(field_change, code)                        \
    do {                                                  \
        m = arm_model_puma560;                            \
        field_change;                                     \
        assert_int_equal(arm_model_validate(&m), (code)); \
    } while (0)
    BROKEN(m.name = NULL, ARM_MODEL_ERR_ARG);
    BROKEN(m.d_m[3] = NAN, ARM_MODEL_ERR_NONFINITE);
    BROKEN(m.inertia_kgm2[2][4] = INFINITY, ARM_MODEL_ERR_NONFINITE);
    BROKEN(m.q_min_rad[1] = m.q_max_rad[1], ARM_MODEL_ERR_RANGE); /* lo < hi */
    BROKEN(m.mass_kg[4] = 0.0, ARM_MODEL_ERR_RANGE);
    BROKEN(m.armature_kgm2[5] = NAN, ARM_MODEL_ERR_NONFINITE);
    BROKEN(m.armature_kgm2[1] = -2.3, ARM_MODEL_ERR_RANGE);
    BROKEN(m.tau_max_Nm[0] = -97.6, ARM_MODEL_ERR_RANGE);
    BROKEN(m.qd_max_radps[5] = 0.0, ARM_MODEL_ERR_RANGE);
    BROKEN(m.a_m[1] = -0.4318, ARM_MODEL_ERR_RANGE);
    BROKEN(m.base_height_m = -0.1, ARM_MODEL_ERR_RANGE);
    BROKEN(m.alpha_rad[2] = -m.alpha_rad[2], ARM_MODEL_ERR_INCONSISTENT); /* trig tables stale */
    arm_model_refresh_alpha(&m);                                          /* ... until refreshed, */
    assert_int_equal(arm_model_validate(&m), ARM_MODEL_ERR_STRUCTURE);    /* no PUMA any more ... */
    m.structure = ARM_STRUCTURE_GENERAL; /* ... but a general arm */
    assert_int_equal(arm_model_validate(&m), 0);
    /* claiming the PUMA structure without each of its zeros, one at a time */
    BROKEN(m.a_m[0] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.a_m[3] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.a_m[4] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.a_m[5] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.d_m[0] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.d_m[1] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.d_m[4] = 0.01, ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.theta_offset_rad[2] = 0.1, ARM_MODEL_ERR_STRUCTURE);
    BROKEN((m.alpha_rad[1] = 0.1, arm_model_refresh_alpha(&m)), ARM_MODEL_ERR_STRUCTURE);
    BROKEN((m.inertia_kgm2[2][1] = 1e-3, m.inertia_kgm2[2][3] = 1e-3), ARM_MODEL_ERR_STRUCTURE);
    BROKEN(m.structure = 7, ARM_MODEL_ERR_STRUCTURE);
    /* the lengths the folded routines keep may take any value */
    BROKEN((m.a_m[1] = 0.5, m.a_m[2] = 0.0, m.d_m[2] = 0.0, m.d_m[3] = 0.3, m.d_m[5] = 0.07), 0);
    {
        int k;
        for (k = 0; k < 2; k++)
            assert_int_equal(
                arm_model_has_puma_structure(k ? &arm_model_seed002 : &arm_model_puma560), 1);
        assert_int_equal(arm_model_has_puma_structure(NULL), 0);
    }
    BROKEN(m.inertia_kgm2[1][1] = 0.01, ARM_MODEL_ERR_INCONSISTENT);    /* not symmetric */
    BROKEN(m.inertia_kgm2[3][8] = -1.8e-3, ARM_MODEL_ERR_INCONSISTENT); /* not positive definite */
#undef BROKEN
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_by_name),
        cmocka_unit_test(test_mass_properties_valid),
        cmocka_unit_test(test_frames_chain_and_fk),
        cmocka_unit_test(test_tool_offset),
        cmocka_unit_test(test_alpha_trig_tables),
        cmocka_unit_test(test_dh_compose_general_alpha),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_joint_faults),
        cmocka_unit_test(test_validate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

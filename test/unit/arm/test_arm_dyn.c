/* test_arm_dyn: M(q) symmetric positive definite and equal to RNE columns,
 * g(q) = dV/dq (finite differences of the potential, with and without a
 * payload), RNE = M qdd + C qd + g, C qd = Christoffel symbols of M,
 * forward dynamics inverts RNE, link-1 mass invisible in joint space. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include "arm_samples.h"
#include "arm_dyn.h"
#include "arm_kin.h"
#include "vec3.h"

/* An arm with no special twist angles, offsets everywhere and joint angle
 * offsets: the recursions must not depend on alpha in {0, +-90 deg}. Filled
 * in by main() from the PUMA table. */
static arm_model skewed;

static const arm_model *const models[] = { &arm_model_puma560, &arm_model_seed002, &skewed };
#define NMODELS (sizeof models / sizeof models[0])

static const arm_payload *test_payload(void)
{
    static arm_payload p;
    const double c[3] = { 0.03, -0.02, 0.11 };
    arm_payload_point(&p, 2.5, c);
    p.inertia_kgm2[0] = 0.004;
    p.inertia_kgm2[4] = 0.005;
    p.inertia_kgm2[8] = 0.003;
    return &p;
}

/* Plain Cholesky: 0 if M is positive definite. */
static int cholesky_ok(const double M[36])
{
    double L[36] = { 0 };
    int i, j, k;
    for (j = 0; j < 6; j++) {
        double s = M[j * 6 + j];
        for (k = 0; k < j; k++)
            s -= L[j * 6 + k] * L[j * 6 + k];
        if (!(s > 0.0))
            return -1;
        L[j * 6 + j] = sqrt(s);
        for (i = j + 1; i < 6; i++) {
            double t = M[i * 6 + j];
            for (k = 0; k < j; k++)
                t -= L[i * 6 + k] * L[j * 6 + k];
            L[i * 6 + j] = t / L[j * 6 + j];
        }
    }
    return 0;
}

static void test_mass_matrix_spd_and_rne_columns(void **state)
{
    static const double zero[ARM_NJ] = { 0 }, nog[3] = { 0, 0, 0 };
    prng_state seed;
    prng_seed(&seed, 3);
    size_t k;
    int n, i, j, pl;
    (void)state;
    for (k = 0; k < NMODELS; k++)
        for (pl = 0; pl < 2; pl++)
            for (n = 0; n < 300; n++) {
                const arm_payload *p = pl ? test_payload() : NULL;
                double q[ARM_NJ], M[36];
                random_q(models[k], &seed, q);
                assert_int_equal(arm_mass_matrix(models[k], q, p, M), 0);
                for (i = 0; i < 6; i++)
                    for (j = 0; j < 6; j++)
                        assert_true(fabs(M[i * 6 + j] - M[j * 6 + i]) < 1e-12);
                assert_int_equal(cholesky_ok(M), 0);
                /* column j of M is RNE(q, 0, e_j) without gravity */
                for (j = 0; j < 6; j++) {
                    double e[ARM_NJ] = { 0 }, tau[ARM_NJ];
                    e[j] = 1.0;
                    assert_int_equal(arm_rne(models[k], q, zero, e, nog, p, tau), 0);
                    for (i = 0; i < 6; i++)
                        assert_true(fabs(tau[i] - M[i * 6 + j]) < 1e-10);
                }
            }
}

/* V(q) = -sum m_k g . c_k(q), COMs placed with the link frames. */
static double potential(const arm_model *m, const double q[ARM_NJ], const double g[3],
                        const arm_payload *p)
{
    double F[ARM_NJ + 1][16], V = 0.0;
    int i;
    arm_link_frames(m, q, F);
    for (i = 0; i < ARM_NJ; i++) {
        double R[9], o[3], c[3];
        tf_rot(R, F[i + 1]);
        tf_pos(o, F[i + 1]);
        rot_apply(c, R, m->com_m[i]);
        vec3_add(c, c, o);
        V -= m->mass_kg[i] * vec3_dot(g, c);
    }
    if (p) {
        double R[9], o[3], c[3];
        tf_rot(R, F[ARM_NJ]);
        tf_pos(o, F[ARM_NJ]);
        rot_apply(c, R, p->com_m);
        vec3_add(c, c, o);
        V -= p->mass_kg * vec3_dot(g, c);
    }
    return V;
}

static void test_gravity_is_potential_gradient(void **state)
{
    const double g_default[3] = { 0, 0, -ARM_GRAVITY_MPS2 };
    const double g_tilted[3] = { 1.2, -0.7, -9.7 };
    const double h = 1e-6;
    prng_state seed;
    prng_seed(&seed, 5);
    size_t k;
    int n, j, pl, gv;
    (void)state;
    for (k = 0; k < NMODELS; k++)
        for (pl = 0; pl < 2; pl++)
            for (gv = 0; gv < 2; gv++)
                for (n = 0; n < 200; n++) {
                    const arm_payload *p = pl ? test_payload() : NULL;
                    const double *g = gv ? g_tilted : g_default;
                    double q[ARM_NJ], tau[ARM_NJ];
                    random_q(models[k], &seed, q);
                    assert_int_equal(arm_gravity(models[k], q, gv ? g : NULL, p, tau), 0);
                    for (j = 0; j < ARM_NJ; j++) {
                        double qp[ARM_NJ], qm[ARM_NJ], dV;
                        memcpy(qp, q, sizeof qp);
                        memcpy(qm, q, sizeof qm);
                        qp[j] += h;
                        qm[j] -= h;
                        dV = (potential(models[k], qp, g, p) - potential(models[k], qm, g, p)) /
                             (2 * h);
                        assert_true(fabs(dV - tau[j]) < 1e-6);
                    }
                }
}

static void test_rne_decomposition_and_christoffel(void **state)
{
    const double h = 1e-6;
    prng_state seed;
    prng_seed(&seed, 9);
    size_t k;
    int n, i, j, pl;
    (void)state;
    for (k = 0; k < NMODELS; k++)
        for (pl = 0; pl < 2; pl++)
            for (n = 0; n < 300; n++) {
                const arm_model *m = models[k];
                const arm_payload *p = pl ? test_payload() : NULL;
                double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], tau[ARM_NJ], M[36], c[ARM_NJ], g[ARM_NJ],
                    Mp[36], Mm[36], qp[ARM_NJ], qm[ARM_NJ], qdd2[ARM_NJ];
                double scale = 0.0;
                random_q(m, &seed, q);
                random_vec(&seed, 3.0, qd);
                random_vec(&seed, 10.0, qdd);
                assert_int_equal(arm_rne(m, q, qd, qdd, NULL, p, tau), 0);
                assert_int_equal(arm_mass_matrix(m, q, p, M), 0);
                assert_int_equal(arm_coriolis(m, q, qd, p, c), 0);
                assert_int_equal(arm_gravity(m, q, NULL, p, g), 0);
                for (i = 0; i < 6; i++) {
                    double t = c[i] + g[i];
                    for (j = 0; j < 6; j++)
                        t += M[i * 6 + j] * qdd[j];
                    assert_true(fabs(t - tau[i]) < 1e-9 * (1.0 + fabs(tau[i])));
                }
                /* C(q,qd) qd from the Christoffel symbols of the CRBA
                 * mass matrix: c_i = sum_k qd_k (dM/dq_k qd)_i
                 *                    - 1/2 qd . (dM/dq_i) qd */
                {
                    double dM[ARM_NJ][36], cc[ARM_NJ] = { 0 };
                    int kk;
                    for (kk = 0; kk < 6; kk++) {
                        memcpy(qp, q, sizeof qp);
                        memcpy(qm, q, sizeof qm);
                        qp[kk] += h;
                        qm[kk] -= h;
                        arm_mass_matrix(m, qp, p, Mp);
                        arm_mass_matrix(m, qm, p, Mm);
                        for (i = 0; i < 36; i++)
                            dM[kk][i] = (Mp[i] - Mm[i]) / (2 * h);
                    }
                    for (i = 0; i < 6; i++) {
                        for (kk = 0; kk < 6; kk++)
                            for (j = 0; j < 6; j++)
                                cc[i] += qd[kk] * dM[kk][i * 6 + j] * qd[j] -
                                         0.5 * qd[kk] * dM[i][kk * 6 + j] * qd[j];
                        scale += fabs(c[i]);
                    }
                    for (i = 0; i < 6; i++)
                        assert_true(fabs(cc[i] - c[i]) < 1e-6 * (1.0 + scale));
                }
                /* forward dynamics inverts inverse dynamics */
                assert_int_equal(arm_forward_dynamics(m, q, qd, tau, NULL, p, qdd2), 0);
                for (i = 0; i < 6; i++)
                    assert_true(fabs(qdd2[i] - qdd[i]) < 1e-7 * (1.0 + fabs(qdd[i])));
            }
}

/* Corke's link 1 (m = 0, I = diag(0, 0.35, 0)) and ours (13 kg, valid
 * inertia) give the same joint-space dynamics. */
static void test_link1_mass_invisible(void **state)
{
    arm_model corke = arm_model_puma560;
    prng_state seed;
    prng_seed(&seed, 21);
    int n, i;
    (void)state;
    corke.mass_kg[0] = 0.0;
    corke.inertia_kgm2[0][0] = 0.0;
    corke.inertia_kgm2[0][8] = 0.0;
    for (n = 0; n < 100; n++) {
        double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], t1[ARM_NJ], t2[ARM_NJ], M1[36], M2[36];
        random_q(&corke, &seed, q);
        random_vec(&seed, 2.0, qd);
        random_vec(&seed, 5.0, qdd);
        arm_rne(&corke, q, qd, qdd, NULL, NULL, t1);
        arm_rne(&arm_model_puma560, q, qd, qdd, NULL, NULL, t2);
        arm_mass_matrix(&corke, q, NULL, M1);
        arm_mass_matrix(&arm_model_puma560, q, NULL, M2);
        for (i = 0; i < 6; i++)
            assert_true(fabs(t1[i] - t2[i]) < 1e-10);
        for (i = 0; i < 36; i++)
            assert_true(fabs(M1[i] - M2[i]) < 1e-12);
    }
}

/* The rotors' reflected inertia sits on the diagonal alone: against the
 * same model without it, M(q) differs by diag(J) exactly and the RNE by
 * J_i qdd_i, whatever q, qd and the payload; forward dynamics still
 * inverts the RNE with it. */
static void test_armature_on_the_diagonal(void **state)
{
    arm_model bare = arm_model_puma560;
    const arm_model *m = &arm_model_puma560;
    const arm_payload *p = test_payload();
    prng_state seed;
    int n, i, j;
    (void)state;
    prng_seed(&seed, 23);
    for (i = 0; i < ARM_NJ; i++) {
        assert_true(m->armature_kgm2[i] > 0.0);
        bare.armature_kgm2[i] = 0.0;
    }
    for (n = 0; n < 50; n++) {
        double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], t1[ARM_NJ], t0[ARM_NJ], M1[36], M0[36],
            qdd2[ARM_NJ];
        random_q(m, &seed, q);
        random_vec(&seed, 2.0, qd);
        random_vec(&seed, 5.0, qdd);
        assert_int_equal(arm_rne(m, q, qd, qdd, NULL, p, t1), 0);
        assert_int_equal(arm_rne(&bare, q, qd, qdd, NULL, p, t0), 0);
        assert_int_equal(arm_mass_matrix(m, q, p, M1), 0);
        assert_int_equal(arm_mass_matrix(&bare, q, p, M0), 0);
        for (i = 0; i < ARM_NJ; i++) {
            assert_true(fabs(t1[i] - t0[i] - m->armature_kgm2[i] * qdd[i]) <
                        1e-9 * (1.0 + fabs(t1[i])));
            for (j = 0; j < ARM_NJ; j++)
                assert_true(fabs(M1[i * 6 + j] - M0[i * 6 + j] -
                                 (i == j ? m->armature_kgm2[i] : 0.0)) < 1e-12);
        }
        assert_int_equal(arm_forward_dynamics(m, q, qd, t1, NULL, p, qdd2), 0);
        for (i = 0; i < ARM_NJ; i++)
            assert_true(fabs(qdd2[i] - qdd[i]) < 1e-7 * (1.0 + fabs(qdd[i])));
    }
}

/* A payload is a load on the flange: its gravity torque is the one of a
 * force m g applied at its COM, tau = J_c^T (-m g), J_c its point Jacobian. */
static void test_payload_gravity_as_wrench(void **state)
{
    const arm_payload *p = test_payload();
    arm_tool tool;
    prng_state seed;
    prng_seed(&seed, 33);
    int n, i;
    (void)state;
    arm_tool_offset(&tool, p->com_m);
    for (n = 0; n < 100; n++) {
        double q[ARM_NJ], g0[ARM_NJ], g1[ARM_NJ], J[36];
        random_q(&arm_model_puma560, &seed, q);
        arm_gravity(&arm_model_puma560, q, NULL, NULL, g0);
        arm_gravity(&arm_model_puma560, q, NULL, p, g1);
        arm_jacobian(&arm_model_puma560, &tool, q, J);
        for (i = 0; i < 6; i++)
            assert_true(fabs((g1[i] - g0[i]) - J[2 * 6 + i] * p->mass_kg * ARM_GRAVITY_MPS2) <
                        1e-10);
    }
}

/* arm_rne_cs with the sines and cosines of arm_joint_cs_eval is arm_rne,
 * bit for bit, with and without payload. */
static void test_rne_cs_is_rne(void **state)
{
    prng_state seed;
    int n, i;
    (void)state;
    prng_seed(&seed, 34);
    for (n = 0; n < 100; n++) {
        double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], t0[ARM_NJ], t1[ARM_NJ];
        arm_joint_cs cs;
        random_q(&arm_model_puma560, &seed, q);
        for (i = 0; i < ARM_NJ; i++) {
            qd[i] = 2.0 * prng_uniform(&seed) - 1.0;
            qdd[i] = 4.0 * prng_uniform(&seed) - 2.0;
        }
        assert_int_equal(arm_joint_cs_eval(&arm_model_puma560, q, &cs), 0);
        assert_int_equal(arm_rne(&arm_model_puma560, q, qd, qdd, NULL, test_payload(), t0), 0);
        assert_int_equal(arm_rne_cs(&arm_model_puma560, &cs, qd, qdd, NULL, test_payload(), t1), 0);
        assert_memory_equal(t0, t1, sizeof t0);
    }
    {
        arm_joint_cs cs;
        double z[ARM_NJ] = { 0, 0, 0, 0, 0, 0 }, t[ARM_NJ];
        assert_int_equal(arm_joint_cs_eval(&arm_model_puma560, z, &cs), 0);
        cs.s[3] = NAN;
        assert_int_equal(arm_rne_cs(&arm_model_puma560, &cs, z, z, NULL, NULL, t), ARM_DYN_ERR_ARG);
        assert_int_equal(arm_rne_cs(&arm_model_puma560, NULL, z, z, NULL, NULL, t),
                         ARM_DYN_ERR_ARG);
    }
}

static void test_bad_input(void **state)
{
    double q[ARM_NJ] = { 0 }, qd[ARM_NJ] = { 0 }, tau[ARM_NJ], M[36];
    arm_payload p;
    const double c[3] = { 0, 0, 0.1 };
    (void)state;
    assert_int_equal(arm_payload_point(&p, -1.0, c), ARM_DYN_ERR_ARG);
    assert_int_equal(arm_payload_point(&p, 1.0, c), 0);
    p.mass_kg = NAN;
    assert_int_equal(arm_gravity(&arm_model_puma560, q, NULL, &p, tau), ARM_DYN_ERR_ARG);
    assert_int_equal(arm_mass_matrix(&arm_model_puma560, q, &p, M), ARM_DYN_ERR_ARG);
    qd[4] = INFINITY;
    assert_int_equal(arm_rne(&arm_model_puma560, q, qd, q, NULL, NULL, tau), ARM_DYN_ERR_ARG);
    assert_int_equal(arm_rne(NULL, q, q, q, NULL, NULL, tau), ARM_DYN_ERR_ARG);
    q[0] = NAN;
    assert_int_equal(arm_mass_matrix(&arm_model_puma560, q, NULL, M), ARM_DYN_ERR_ARG);
    memset(M, 0, sizeof M);
    assert_int_equal(arm_spd_solve6(M, qd, tau), ARM_DYN_ERR_NOT_PD);
}

static void make_skewed(void)
{
    static const double alpha[ARM_NJ] = { 1.2, -0.4, 2.3, 0.7, -1.9, 0.3 };
    static const double a[ARM_NJ] = { 0.05, 0.4318, 0.0203, -0.03, 0.02, 0.01 };
    static const double d[ARM_NJ] = { 0.1, -0.02, 0.15005, 0.4318, 0.03, 0.06 };
    static const double off[ARM_NJ] = { 0.1, -0.3, 0.5, 0.0, -0.2, 0.4 };
    int i;
    skewed = arm_model_puma560;
    skewed.structure = ARM_STRUCTURE_GENERAL; /* not a PUMA any more */
    for (i = 0; i < ARM_NJ; i++) {
        skewed.alpha_rad[i] = alpha[i];
        skewed.a_m[i] = a[i];
        skewed.d_m[i] = d[i];
        skewed.theta_offset_rad[i] = off[i];
    }
    arm_model_refresh_alpha(&skewed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mass_matrix_spd_and_rne_columns),
        cmocka_unit_test(test_gravity_is_potential_gradient),
        cmocka_unit_test(test_rne_decomposition_and_christoffel),
        cmocka_unit_test(test_link1_mass_invisible),
        cmocka_unit_test(test_armature_on_the_diagonal),
        cmocka_unit_test(test_payload_gravity_as_wrench),
        cmocka_unit_test(test_rne_cs_is_rne),
        cmocka_unit_test(test_bad_input),
    };
    make_skewed();
    return cmocka_run_group_tests(tests, NULL, NULL);
}

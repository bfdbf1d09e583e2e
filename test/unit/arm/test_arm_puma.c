/* test_arm_puma: the folded PUMA routines (docs/method/puma.md) against the
 * general DH recursions they replace, and identities that hold them on
 * their own.
 *  - agreement to 1e-12 (relative to the largest entry of each result) of
 *    FK, Jacobian, the kinematics pass and its Jdot qd, the Cartesian
 *    cycle's one pass (cartctl_state_at: pose, J, Jdot qd, J qd, wrist
 *    centre), RNE torques for random qd, qdd,
 *    tilted gravity and a payload, and M(q): 10,000 seeded configurations
 *    inside the joint ranges per model, every corner of the ranges, and
 *    the shoulder, elbow and wrist singularities;
 *  - the Jacobian is the derivative of FK (central differences);
 *  - M(q) symmetric positive definite, tau = M qdd + C qd + g;
 *  - a table that claims the structure without having it is refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "arm_dyn.h"
#include "arm_kin.h"
#include "arm_samples.h"
#include "cartctl.h"
#include "vec3.h"

#define N_RANDOM 10000
#define REL_TOL 1e-12

static const arm_model *const models[] = { &arm_model_puma560, &arm_model_seed002 };
#define NMODELS (sizeof models / sizeof models[0])

/* The same table taking the general path: the reference. */
static arm_model general_of(const arm_model *m)
{
    arm_model g = *m;
    g.structure = ARM_STRUCTURE_GENERAL;
    return g;
}

/* max |a - b| <= REL_TOL max |b| */
static int agree(const double *a, const double *b, int n)
{
    double err = 0.0, scale = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        const double e = fabs(a[i] - b[i]);
        if (!(e <= err))
            err = e; /* NaN propagates into a failure */
        if (fabs(b[i]) > scale)
            scale = fabs(b[i]);
    }
    return err <= REL_TOL * scale;
}

static const arm_payload *bar(void)
{
    static arm_payload p;
    const double c[3] = { 0.1, -0.02, 0.2 };
    arm_payload_point(&p, 3.2, c);
    p.inertia_kgm2[0] = 0.02;
    p.inertia_kgm2[4] = 0.03;
    p.inertia_kgm2[8] = 0.01;
    p.inertia_kgm2[1] = p.inertia_kgm2[3] = 0.002;
    return &p;
}

static arm_tool tool_of(int k)
{
    arm_tool t;
    const double off[3] = { 0.01, -0.02, 0.16 };
    if (k == 0) {
        arm_tool_none(&t);
    } else {
        arm_tool_offset(&t, off);
        if (k == 2) { /* a turned tool takes the general product */
            t.T_flange_tool[0] = t.T_flange_tool[5] = cos(0.3);
            t.T_flange_tool[1] = -sin(0.3);
            t.T_flange_tool[4] = sin(0.3);
        }
    }
    return t;
}

/* The Cartesian cycle's one pass (cartctl_state_at: arm_puma_cycle_kin,
 * docs/method/puma.md §3a) against the separate general routines: the
 * pass kb, its J-dot q-dot, J qd, and the wrist centre from the frames
 * (F4: frame 4, its origin o4). */
static void check_cycle_pass(const arm_model *m, const arm_kin_pass *kb, const double q[ARM_NJ],
                             const double qd[ARM_NJ], const arm_tool *tool, const double F4[16])
{
    const double w[3] = { F4[3], F4[7], F4[11] };
    double jb[6], vb[6];
    cartctl_state s;
    int i, j;
    assert_int_equal(cartctl_state_at(m, tool, q, qd, &s), 0);
    assert_int_equal(arm_kin_jdot_qd(kb, qd, jb), 0);
    for (i = 0; i < 6; i++) {
        vb[i] = 0.0;
        for (j = 0; j < ARM_NJ; j++)
            vb[i] += kb->J[6 * i + j] * qd[j];
    }
    assert_true(agree(s.T, kb->T, 16) && agree(s.J, kb->J, 36));
    assert_true(agree(s.jdqd, jb, 6) && agree(s.twist, vb, 6) && agree(s.wrist_m, w, 3));
    assert_true(agree(s.cs.c, kb->cs.c, ARM_NJ) && agree(s.cs.s, kb->cs.s, ARM_NJ));
    assert_int_equal(s.has_wrist, m->structure == ARM_STRUCTURE_PUMA);
}

/* Every routine, folded (m) and general (g), at one state. */
static void check_state(const arm_model *m, const arm_model *g, const double q[ARM_NJ],
                        const double qd[ARM_NJ], const double qdd[ARM_NJ], const double grav[3],
                        int variant)
{
    const arm_payload *p = (variant & 1) ? bar() : NULL;
    const arm_tool tool = tool_of(variant % 3);
    double Ta[16], Tb[16], Ja[36], Jb[36], ta[ARM_NJ], tb[ARM_NJ], Ma[36], Mb[36];
    double Fa[ARM_NJ + 1][16], Fb[ARM_NJ + 1][16];
    arm_kin_pass ka, kb;
    assert_int_equal(arm_fk(m, &tool, q, Ta), 0);
    assert_int_equal(arm_fk(g, &tool, q, Tb), 0);
    assert_true(agree(Ta, Tb, 16));
    assert_int_equal(arm_fk_jacobian(m, &tool, q, Ta, Ja), 0);
    assert_int_equal(arm_fk_jacobian(g, &tool, q, Tb, Jb), 0);
    assert_true(agree(Ta, Tb, 16));
    assert_true(agree(Ja, Jb, 36));
    assert_int_equal(arm_kin_eval(m, &tool, q, &ka), 0);
    assert_int_equal(arm_kin_eval(g, &tool, q, &kb), 0);
    assert_true(agree(ka.T, kb.T, 16) && agree(ka.J, kb.J, 36));
    assert_true(agree(ka.F[0], kb.F[0], 16 * (ARM_NJ + 1)));
    {
        double ja[6], jb[6];
        assert_int_equal(arm_kin_jdot_qd(&ka, qd, ja), 0);
        assert_int_equal(arm_kin_jdot_qd(&kb, qd, jb), 0);
        assert_true(agree(ja, jb, 6));
    }
    assert_int_equal(arm_link_frames(m, q, Fa), 0);
    assert_int_equal(arm_link_frames(g, q, Fb), 0);
    assert_true(agree(Fa[0], Fb[0], 16 * (ARM_NJ + 1)));
    check_cycle_pass(m, &kb, q, qd, &tool, Fb[4]);
    assert_int_equal(arm_rne(m, q, qd, qdd, grav, p, ta), 0);
    assert_int_equal(arm_rne(g, q, qd, qdd, grav, p, tb), 0);
    assert_true(agree(ta, tb, ARM_NJ));
    assert_int_equal(arm_rne_cs(m, &ka.cs, qd, qdd, grav, p, ta), 0);
    assert_true(agree(ta, tb, ARM_NJ));
    assert_int_equal(arm_mass_matrix(m, q, p, Ma), 0);
    assert_int_equal(arm_mass_matrix(g, q, p, Mb), 0);
    assert_true(agree(Ma, Mb, 36));
}

static void test_agree_random(void **state)
{
    static const double tilted[3] = { 1.2, -0.7, -9.7 };
    prng_state seed;
    size_t k;
    int n;
    (void)state;
    prng_seed(&seed, 26);
    for (k = 0; k < NMODELS; k++) {
        const arm_model g = general_of(models[k]);
        for (n = 0; n < N_RANDOM; n++) {
            double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ];
            random_q(models[k], &seed, q);
            random_vec(&seed, 2.0, qd);
            random_vec(&seed, 10.0, qdd);
            check_state(models[k], &g, q, qd, qdd, (n & 2) ? tilted : NULL, n);
        }
    }
}

/* Every corner of the joint ranges (2^6), and the singular poses: wrist
 * (q5 = 0), elbow stretched (q3 where a3, d4 line up with a2), shoulder
 * (wrist centre on the axis of joint 1). */
static void test_agree_limits_and_singularities(void **state)
{
    static const double zero[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    size_t k;
    int corner, n;
    (void)state;
    for (k = 0; k < NMODELS; k++) {
        const arm_model *m = models[k];
        const arm_model g = general_of(m);
        const double qd[ARM_NJ] = { 0.4, -1.1, 0.9, 2.0, -1.7, 3.0 };
        const double qdd[ARM_NJ] = { -3.0, 2.0, 5.0, -8.0, 6.0, -4.0 };
        for (corner = 0; corner < 64; corner++) {
            double q[ARM_NJ];
            int j;
            for (j = 0; j < ARM_NJ; j++)
                q[j] = (corner >> j) & 1 ? m->q_max_rad[j] : m->q_min_rad[j];
            check_state(m, &g, q, qd, qdd, NULL, corner);
            check_state(m, &g, q, zero, zero, NULL, corner + 1);
        }
        for (n = 0; n < 3; n++) {
            const double elbow = atan2(m->a_m[2], m->d_m[3]); /* a2 and the forearm in line */
            double q[ARM_NJ] = { 0.3, -0.5, 0.0, 0.7, 0.0, -0.2 };
            if (n == 1)
                q[2] = 1.57079632679489662 + elbow;
            if (n == 2) {
                /* wrist centre over the shoulder: X = a2 c2 + a3 c23 - d4 s23 = 0
                 * with q3 = 0: tan q2 = a2 + a3 ... solved by bisection */
                double lo = -3.0, hi = 0.0;
                int it;
                for (it = 0; it < 200; it++) {
                    const double mid = 0.5 * (lo + hi);
                    const double X = m->a_m[1] * cos(mid) + m->a_m[2] * cos(mid) -
                                     m->d_m[3] * sin(mid);
                    if (X > 0.0)
                        hi = mid;
                    else
                        lo = mid;
                }
                q[1] = 0.5 * (lo + hi);
            }
            check_state(m, &g, q, qd, qdd, NULL, n);
            check_state(m, &g, q, qd, qdd, NULL, n + 1);
        }
    }
}

/* J = dFK/dq: linear part by central differences of the point, angular
 * part from R(q+h) R(q-h)^T. */
static void test_jacobian_is_fk_derivative(void **state)
{
    const double h = 1e-6;
    prng_state seed;
    size_t k;
    int n, j, r;
    (void)state;
    prng_seed(&seed, 27);
    for (k = 0; k < NMODELS; k++)
        for (n = 0; n < 300; n++) {
            const arm_tool tool = tool_of(1);
            double q[ARM_NJ], T[16], J[36];
            random_q(models[k], &seed, q);
            assert_int_equal(arm_fk_jacobian(models[k], &tool, q, T, J), 0);
            for (j = 0; j < ARM_NJ; j++) {
                double qp[ARM_NJ], qm[ARM_NJ], Tp[16], Tm[16], Rp[9], Rm[9], Rmt[9], D[9];
                memcpy(qp, q, sizeof qp);
                memcpy(qm, q, sizeof qm);
                qp[j] += h;
                qm[j] -= h;
                arm_fk(models[k], &tool, qp, Tp);
                arm_fk(models[k], &tool, qm, Tm);
                for (r = 0; r < 3; r++)
                    assert_true(fabs((Tp[4 * r + 3] - Tm[4 * r + 3]) / (2 * h) - J[r * 6 + j]) <
                                1e-8);
                tf_rot(Rp, Tp);
                tf_rot(Rm, Tm);
                rot_transpose(Rmt, Rm);
                rot_mul(D, Rp, Rmt); /* ~ I + 2h [w]x */
                assert_true(fabs((D[7] - D[5]) / (4 * h) - J[18 + j]) < 1e-8);
                assert_true(fabs((D[2] - D[6]) / (4 * h) - J[24 + j]) < 1e-8);
                assert_true(fabs((D[3] - D[1]) / (4 * h) - J[30 + j]) < 1e-8);
            }
        }
}

/* Plain Cholesky: 0 if M is positive definite. */
static int positive_definite(const double M[36])
{
    double x[ARM_NJ];
    const double b[ARM_NJ] = { 1, 1, 1, 1, 1, 1 };
    return arm_spd_solve6(M, b, x);
}

static void test_mass_matrix_and_decomposition(void **state)
{
    prng_state seed;
    size_t k;
    int n, i, j;
    (void)state;
    prng_seed(&seed, 28);
    for (k = 0; k < NMODELS; k++)
        for (n = 0; n < 1000; n++) {
            const arm_model *m = models[k];
            const arm_payload *p = (n & 1) ? bar() : NULL;
            double q[ARM_NJ], qd[ARM_NJ], qdd[ARM_NJ], tau[ARM_NJ], M[36], c[ARM_NJ], g[ARM_NJ];
            random_q(m, &seed, q);
            random_vec(&seed, 2.0, qd);
            random_vec(&seed, 10.0, qdd);
            assert_int_equal(arm_mass_matrix(m, q, p, M), 0);
            for (i = 0; i < 6; i++)
                for (j = 0; j < i; j++)
                    assert_true(M[i * 6 + j] == M[j * 6 + i]);
            assert_int_equal(positive_definite(M), 0);
            assert_int_equal(arm_rne(m, q, qd, qdd, NULL, p, tau), 0);
            assert_int_equal(arm_coriolis(m, q, qd, p, c), 0);
            assert_int_equal(arm_gravity(m, q, NULL, p, g), 0);
            for (i = 0; i < 6; i++) {
                double t = c[i] + g[i];
                for (j = 0; j < 6; j++)
                    t += M[i * 6 + j] * qdd[j];
                assert_true(fabs(t - tau[i]) <= 1e-10 * (1.0 + fabs(tau[i])));
            }
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_agree_random),
        cmocka_unit_test(test_agree_limits_and_singularities),
        cmocka_unit_test(test_jacobian_is_fk_derivative),
        cmocka_unit_test(test_mass_matrix_and_decomposition),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

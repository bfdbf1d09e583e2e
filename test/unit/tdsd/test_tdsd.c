/* Unit tests for tdsd (docs/method/tdsd.md): priority-1 exactness, joint speed limits on
 * random and singular Jacobians, speed distribution Q1/Q2, time scaling,
 * eq. 13 orientation error, null-space invariance, criterion gradient, and
 * the clipped-pinv / DLS baselines. Jacobians are random matrices: TDSD is
 * arm-agnostic.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <string.h>

#include "arm_kin.h"
#include "linalg.h"
#include "tdsd.h"
#include "vec3.h"

#define NJ TDSD_NJ
#define PI_ 3.14159265358979323846
/* fast paths vs SVD: error <= FAST_TOL_FACTOR eps kappa(J1) kappa(J2 P1) scale
 * (LQ), FAST_TOL_FACTOR eps (kappa(J1) kappa(J2 P1))^2 scale (U D U^T of J J^T) */
#define FAST_TOL_FACTOR 64.0
/* and on the U D U^T path away from singularities (kappa1 kappa2 <= 100):
 * error <= WELL_TOL scale */
#define WELL_TOL 1e-9

static unsigned long long rng_state = 0x9E3779B97F4A7C15ULL;

static double urand(void) /* uniform in [-1, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 4503599627370496.0 - 1.0;
}

static void rand_vec(double *v, int n, double scale)
{
    int i;
    for (i = 0; i < n; i++)
        v[i] = scale * urand();
}

static void rand_unit(double k[3])
{
    do
        rand_vec(k, 3, 1.0);
    while (vec3_normalize(k, k) < 0.1);
}

static void rand_rot(double R[9], double max_angle)
{
    double k[3];
    rand_unit(k);
    rot_from_axis_angle(R, k, max_angle * 0.5 * (urand() + 1.0));
}

static double sigma_min_of(const double *A, int m, int n)
{
    double Ap[NJ * NJ];
    linalg_pinv_info info;
    assert_int_equal(linalg_pinv(Ap, NULL, &info, A, m, n, 0.0), LINALG_OK);
    return info.sigma_min;
}

/* Random well-conditioned task: [J1; Jw] has sigma_min >= 0.3, generous
 * limits (Q1 = Q2 = 1 expected), small pose errors. */
static void make_input(tdsd_input *in)
{
    double J[NJ * NJ], Rerr[9];
    int i;
    memset(in, 0, sizeof *in);
    do {
        rand_vec(in->J1, 3 * NJ, 1.0);
        rand_vec(in->Jw, 3 * NJ, 1.0);
        memcpy(J, in->J1, sizeof in->J1);
        memcpy(J + 3 * NJ, in->Jw, sizeof in->Jw);
    } while (sigma_min_of(J, 6, 6) < 0.3);
    in->orient = TDSD_ORIENT_FULL;
    rand_vec(in->v_d_mps, 3, 0.2);
    rand_vec(in->p_m, 3, 1.0);
    rand_vec(in->p_d_m, 3, 0.01);
    vec3_add(in->p_d_m, in->p_d_m, in->p_m);
    rand_vec(in->w_d_radps, 3, 0.2);
    rand_rot(in->R, PI_);
    rand_rot(Rerr, 0.1);
    rot_mul(in->R_d, Rerr, in->R);
    in->K_p = 5.0;
    in->K_o = 3.0;
    in->k_V = 0.0;
    for (i = 0; i < NJ; i++)
        in->dq_max_radps[i] = 1e3;
    in->rate_cap = 1.0;
}

static void task_rates(double y1[3], double y2[3], const tdsd_input *in, const double dq[NJ])
{
    linalg_matvec(y1, in->J1, dq, 3, NJ);
    linalg_matvec(y2, in->Jw, dq, 3, NJ);
}

static void check_limits(const tdsd_input *in, const tdsd_output *out)
{
    int i;
    for (i = 0; i < NJ; i++)
        assert_true(fabs(out->dq_radps[i]) <= in->dq_max_radps[i] + 1e-12);
    assert_true(out->Q1 >= 0.0 && out->Q1 <= 1.0);
    assert_true(out->Q2 >= 0.0 && out->Q2 <= 1.0);
    assert_true(out->lambda >= 0.0 && out->lambda <= in->rate_cap);
    assert_true(out->fb_scale > 0.0 && out->fb_scale <= 1.0);
}

static void test_priority1_exact_and_Q_one_when_generous(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double y1[3], y2[3], want[3];
    int trial, i;
    (void)state;
    for (trial = 0; trial < 300; trial++) {
        make_input(&in);
        in.rate_cap = (trial % 3 == 0) ? 0.5 : 1.0;
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        assert_false(out.time_scaled);
        assert_true(out.Q1 == 1.0);
        assert_true(out.Q2 == 1.0);
        assert_true(out.lambda == in.rate_cap);
        assert_int_equal(out.rank_J1, 3);
        task_rates(y1, y2, &in, out.dq_radps);
        for (i = 0; i < 3; i++)
            want[i] = in.rate_cap * in.v_d_mps[i] + in.K_p * (in.p_d_m[i] - in.p_m[i]);
        assert_true(linalg_maxabs_diff(y1, want, 3, 1) <= 1e-9);
        /* stacked J full rank and Q1 = 1: the orientation task is met too */
        {
            double e_o[3];
            tdsd_orientation_error(e_o, in.R_d, in.R);
            for (i = 0; i < 3; i++)
                want[i] = in.rate_cap * in.w_d_radps[i] + in.K_o * e_o[i];
            assert_true(linalg_maxabs_diff(y2, want, 3, 1) <= 1e-9);
        }
        check_limits(&in, &out);
    }
}

/* Tight random limits: Q1 < 1 often. Whatever Q1, J1 dq is y1' of the
 * (possibly time-scaled) path, exactly. */
static void test_priority1_exact_under_speed_distribution(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double y1[3], y2[3], want[3];
    int trial, i, n_q1 = 0, n_ts = 0;
    (void)state;
    for (trial = 0; trial < 500; trial++) {
        make_input(&in);
        rand_vec(in.v_d_mps, 3, 2.0);
        for (i = 0; i < NJ; i++)
            in.dq_max_radps[i] = 0.3 + 3.0 * (urand() + 1.0);
        in.K_o = 30.0;
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        assert_int_equal(out.n_clipped, 0);
        assert_true(out.fb_scale == 1.0);
        task_rates(y1, y2, &in, out.dq_radps);
        for (i = 0; i < 3; i++)
            want[i] = out.lambda * in.v_d_mps[i] + in.K_p * (in.p_d_m[i] - in.p_m[i]);
        assert_true(linalg_maxabs_diff(y1, want, 3, 1) <= 1e-9);
        assert_true(linalg_maxabs_diff(out.y1, want, 3, 1) <= 1e-15);
        if (out.Q1 < 1.0)
            n_q1++;
        if (out.time_scaled) {
            /* lambda is the largest feasible: some joint of dq1 is at its limit */
            double worst = 0.0;
            n_ts++;
            for (i = 0; i < NJ; i++) {
                double r = fabs(out.dq1[i]) / in.dq_max_radps[i];
                worst = r > worst ? r : worst;
            }
            assert_true(fabs(worst - 1.0) <= 1e-12);
            assert_true(out.Q1 == 0.0 || worst < 1.0);
        }
    }
    assert_true(n_q1 > 50); /* the branches were exercised */
    assert_true(n_ts > 20);
}

static void make_singular_J1(double J1[3 * NJ], int kind)
{
    int j;
    rand_vec(J1, 3 * NJ, 1.0);
    for (j = 0; j < NJ; j++) {
        switch (kind % 4) {
        case 0: J1[1 * NJ + j] = J1[0 * NJ + j]; break;                    /* equal rows */
        case 1: J1[2 * NJ + j] = 0.0; break;                               /* zero row */
        case 2: J1[2 * NJ + j] = 2.0 * J1[0 * NJ + j] - J1[NJ + j]; break; /* dependent */
        default: J1[j] = J1[NJ + j] = J1[2 * NJ + j] = 0.0; break;         /* J1 = 0 */
        }
    }
}

static void test_limits_random_and_singular(void **state)
{
    tdsd_input in;
    tdsd_output out;
    rr_dls_params dls = { 0.05, 0.1 };
    int trial, i;
    (void)state;
    for (trial = 0; trial < 2000; trial++) {
        make_input(&in);
        if (trial % 2)
            make_singular_J1(in.J1, trial / 2);
        if (trial % 5 == 0)
            in.J1[trial % (3 * NJ)] += 1e-9; /* nearly singular */
        if (trial % 7 == 0)
            make_singular_J1(in.Jw, trial / 7);
        in.orient = (tdsd_orient_mode)(trial % 3);
        rand_vec(in.v_d_mps, 3, 5.0);
        rand_vec(in.p_d_m, 3, (trial % 11 == 0) ? 10.0 : 0.1);
        in.k_V = 10.0;
        rand_vec(in.grad_V, NJ, 1.0);
        for (i = 0; i < NJ; i++)
            in.dq_max_radps[i] = 0.05 + 2.0 * (urand() + 1.0);
        in.rate_cap = 0.5 * (urand() + 1.0);
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        assert_int_equal(out.n_clipped, 0);
        assert_int_equal(rr_pinv_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        assert_int_equal(rr_dls_step(&in, &dls, &out), TDSD_OK);
        check_limits(&in, &out);
    }
}

/* tdsd_step keeps J1+ and (J2 P1)+ as SVD factors and never forms P1;
 * this is eq. 8/11 with the explicit matrices (linalg_pinv, P1 = I - J1+ J1,
 * M = J2 P1), evaluated at the lambda and fb_scale tdsd_step chose. The
 * three components must agree on random well-conditioned tasks; scale is
 * the size of the terms, so the bound is relative. */
static void reference_components(const tdsd_input *in, const tdsd_output *out, double dq1[NJ],
                                 double dq2[NJ], double dq3[NJ])
{
    double J1p[NJ * 3], P1[NJ * NJ], J2[3 * NJ], M[3 * NJ], Mp[NJ * 3];
    double y1[3], r[3], Mg[3], t[NJ], g[NJ];
    int n2 = out->n2, i;
    assert_int_equal(linalg_pinv(J1p, P1, NULL, in->J1, 3, NJ, 0.0), LINALG_OK);
    for (i = 0; i < 3; i++)
        y1[i] = out->lambda * in->v_d_mps[i] + out->fb_scale * in->K_p * out->e_p[i];
    linalg_matvec(dq1, J1p, y1, NJ, 3);
    for (i = 0; i < NJ; i++)
        g[i] = in->k_V * in->grad_V[i];
    linalg_matvec(dq3, P1, g, NJ, NJ);
    for (i = 0; i < NJ; i++)
        dq2[i] = 0.0;
    if (n2 == 0)
        return;
    if (n2 == 3)
        memcpy(J2, in->Jw, sizeof J2);
    else
        tdsd_axis_jacobian(J2, in->Jw, in->R);
    linalg_mul(M, J2, P1, n2, NJ, NJ);
    assert_int_equal(linalg_pinv(Mp, NULL, NULL, M, n2, NJ, 0.0), LINALG_OK);
    linalg_matvec(r, J2, dq1, n2, NJ);
    for (i = 0; i < n2; i++)
        r[i] = out->y2[i] - r[i];
    linalg_matvec(dq2, Mp, r, NJ, n2);
    linalg_matvec(Mg, M, g, n2, NJ);
    linalg_matvec(t, Mp, Mg, NJ, n2);
    for (i = 0; i < NJ; i++)
        dq3[i] -= t[i];
}

static double norm6(const double v[NJ])
{
    double acc = 0.0;
    int i;
    for (i = 0; i < NJ; i++)
        acc += v[i] * v[i];
    return sqrt(acc);
}

static void test_factored_matches_explicit_formulas(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double dq1[NJ], dq2[NJ], dq3[NJ];
    int trial;
    (void)state;
    for (trial = 0; trial < 500; trial++) {
        double scale;
        make_input(&in);
        in.orient = (tdsd_orient_mode)(trial % 3);
        in.k_V = 2.0;
        rand_vec(in.grad_V, NJ, 1.0);
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        reference_components(&in, &out, dq1, dq2, dq3);
        scale = 1.0 + vec3_norm(out.y1) / out.sigma_min_J1;
        assert_true(linalg_maxabs_diff(out.dq1, dq1, NJ, 1) <= 1e-12 * scale);
        assert_true(linalg_maxabs_diff(out.dq2, dq2, NJ, 1) <= 1e-10 * (scale + norm6(out.dq2)));
        assert_true(linalg_maxabs_diff(out.dq3, dq3, NJ, 1) <= 1e-10 * (1.0 + norm6(out.dq3)));
    }
}

/* J1 = U diag(1, 1, eps) V^T, eps -> 0, fixed y1' = p_d' with a component
 * along the vanishing direction: Q1 decreases toward 0, lambda too, and
 * the (time-scaled) position task stays exact. */
static void test_Q1_drops_toward_singularity(void **state)
{
    double U[9], V[NJ * NJ], US[3 * NJ];
    tdsd_input in;
    tdsd_output out;
    double eps, prev_Q1 = 2.0, y1[3], y2[3], want[3];
    int i, j, step = 0;
    (void)state;
    make_input(&in);
    rand_rot(U, PI_);
    /* V: orthonormal 6x6 from the SVD of a random matrix */
    {
        double A[NJ * NJ], Uu[NJ * NJ], s[NJ];
        rand_vec(A, NJ * NJ, 1.0);
        assert_int_equal(linalg_svd(Uu, s, V, A, NJ, NJ), LINALG_OK);
    }
    in.v_d_mps[0] = 0.1;
    in.v_d_mps[1] = 0.05;
    in.v_d_mps[2] = 0.1;
    vec3_copy(in.p_d_m, in.p_m); /* e_p = 0: y1' fixed */
    for (i = 0; i < NJ; i++)
        in.dq_max_radps[i] = 2.0;
    for (eps = 0.3; eps > 1e-7; eps *= 0.5, step++) {
        double sv[3] = { 1.0, 1.0, eps };
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                US[i * 3 + j] = U[i * 3 + j] * sv[j];
        /* J1 = U S V(:,0:3)^T */
        for (i = 0; i < 3; i++)
            for (j = 0; j < NJ; j++)
                in.J1[i * NJ + j] = US[i * 3 + 0] * V[j * NJ + 0] + US[i * 3 + 1] * V[j * NJ + 1] +
                                    US[i * 3 + 2] * V[j * NJ + 2];
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        if (out.fast) /* Frobenius bounds: sigma_min / sqrt 3 <= bound <= sigma_min */
            assert_true(out.sigma_min_J1 <= eps * (1.0 + 1e-12) &&
                        out.sigma_min_J1 >= eps / sqrt(3.0) * (1.0 - 1e-12));
        else
            assert_true(fabs(out.sigma_min_J1 - eps) <= 1e-12);
        assert_true(out.Q1 <= prev_Q1 + 1e-12);
        prev_Q1 = out.Q1;
        task_rates(y1, y2, &in, out.dq_radps);
        for (i = 0; i < 3; i++)
            want[i] = out.lambda * in.v_d_mps[i];
        assert_true(linalg_maxabs_diff(y1, want, 3, 1) <= 1e-9);
        if (step == 0)
            assert_true(out.Q1 == 1.0);
    }
    assert_true(prev_Q1 < 1e-3);
    assert_true(out.lambda < 1e-4);
    assert_true(out.time_scaled);
}

static void test_orientation_error_formula(void **state)
{
    double R[9], Rd[9], Rk[9], k[3], e[3], e2[2], want[3];
    int trial;
    (void)state;
    for (trial = 0; trial < 200; trial++) {
        double theta = PI_ * 0.5 * (urand() + 1.0);
        rand_rot(R, PI_);
        tdsd_orientation_error(e, R, R);
        assert_true(vec3_norm(e) <= 1e-15);
        tdsd_axis_error(e2, R, R);
        assert_true(fabs(e2[0]) + fabs(e2[1]) <= 1e-15);
        rand_unit(k);
        rot_from_axis_angle(Rk, k, theta);
        rot_mul(Rd, Rk, R); /* desired = actual rotated by theta about k */
        tdsd_orientation_error(e, Rd, R);
        vec3_scale(want, k, sin(theta));
        assert_true(linalg_maxabs_diff(e, want, 3, 1) <= 1e-14);
        /* axis error: |e2| = sin(angle(a, a_d)) */
        {
            double a[3] = { R[2], R[5], R[8] }, ad[3] = { Rd[2], Rd[5], Rd[8] }, x[3];
            vec3_cross(x, a, ad);
            tdsd_axis_error(e2, Rd, R);
            assert_true(fabs(hypot(e2[0], e2[1]) - vec3_norm(x)) <= 1e-14);
        }
        /* a rotation about the tool axis itself is no axis error */
        {
            double a[3] = { R[2], R[5], R[8] };
            rot_from_axis_angle(Rk, a, theta);
            rot_mul(Rd, Rk, R);
            tdsd_axis_error(e2, Rd, R);
            assert_true(fabs(e2[0]) + fabs(e2[1]) <= 1e-14);
        }
    }
}

/* R' = [w]x R over dt (exact, by Rodrigues). */
static void rotate_by(double R[9], const double w[3], double dt)
{
    double k[3], Rw[9], tmp[9];
    double ang = vec3_normalize(k, w) * dt;
    if (ang == 0.0)
        return;
    rot_from_axis_angle(Rw, k, ang);
    rot_mul(tmp, Rw, R);
    memcpy(R, tmp, sizeof tmp);
}

/* With the position at rest (p_d' = 0, e_p = 0), dq is pure dq2: it moves
 * no point of the position task (J1 Q1 dq2 = 0) and closing the loop on the
 * orientation drives e_o to zero monotonically. */
static void test_dq2_reduces_orientation_keeps_position(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double y1[3], y2[3], Rerr[9], k[3];
    int trial, it, mode;
    (void)state;
    for (mode = 1; mode <= 2; mode++)
        for (trial = 0; trial < 30; trial++) {
            double prev, e_now;
            make_input(&in);
            in.orient = (tdsd_orient_mode)mode;
            vec3_set(in.v_d_mps, 0, 0, 0);
            vec3_set(in.w_d_radps, 0, 0, 0);
            vec3_copy(in.p_d_m, in.p_m);
            rand_unit(k);
            rot_from_axis_angle(Rerr, k, 1.0);
            rot_mul(in.R_d, Rerr, in.R);
            if (trial % 2) /* tight limits: Q1 < 1 must not disturb position */
                for (it = 0; it < NJ; it++)
                    in.dq_max_radps[it] = 0.5;
            prev = 1e9;
            for (it = 0; it < 400; it++) {
                assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
                check_limits(&in, &out);
                task_rates(y1, y2, &in, out.dq_radps);
                assert_true(vec3_norm(y1) <= 1e-12 * (1.0 + vec3_norm(out.dq2)));
                e_now = hypot(hypot(out.e_o[0], out.e_o[1]), mode == 1 ? out.e_o[2] : 0.0);
                assert_true(e_now <= prev + 1e-12);
                prev = e_now;
                rotate_by(in.R, y2, 0.01);
            }
            assert_true(prev < 0.5 * sin(1.0));
            if (trial % 2 == 0)
                assert_true(prev < 1e-2);
        }
    /* dq2 is orthogonal to J1's row space also with a moving position task */
    for (trial = 0; trial < 200; trial++) {
        make_input(&in);
        rand_vec(in.v_d_mps, 3, 2.0);
        for (it = 0; it < NJ; it++)
            in.dq_max_radps[it] = 1.0;
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        linalg_matvec(y1, in.J1, out.dq2, 3, NJ);
        assert_true(vec3_norm(y1) <= 1e-12 * (1.0 + vec3_norm(out.dq2)));
    }
}

/* Tool-axis task (5 rows) leaves one joint-space direction free: dq3 uses
 * it, changes neither J1 dq nor J2 dq, and ascends V. */
static void test_nullspace_term_invariance(void **state)
{
    tdsd_input in;
    tdsd_output o0, o1;
    double y1a[3], y1b[3], J2[2 * NJ], y2a[2], y2b[2];
    int trial;
    (void)state;
    for (trial = 0; trial < 300; trial++) {
        make_input(&in);
        in.orient = (trial % 3 == 0) ? TDSD_ORIENT_NONE : TDSD_ORIENT_AXIS;
        rand_vec(in.grad_V, NJ, 1.0);
        in.k_V = 0.0;
        assert_int_equal(tdsd_step(&in, &o0), TDSD_OK);
        in.k_V = 2.0;
        assert_int_equal(tdsd_step(&in, &o1), TDSD_OK);
        assert_true(o1.Q1 == 1.0 && o1.Q2 == 1.0);
        assert_true(vec3_norm(o1.dq3) > 1e-6);
        linalg_matvec(y1a, in.J1, o0.dq_radps, 3, NJ);
        linalg_matvec(y1b, in.J1, o1.dq_radps, 3, NJ);
        assert_true(linalg_maxabs_diff(y1a, y1b, 3, 1) <= 1e-12);
        tdsd_axis_jacobian(J2, in.Jw, in.R);
        linalg_matvec(y2a, J2, o0.dq_radps, 2, NJ);
        linalg_matvec(y2b, J2, o1.dq_radps, 2, NJ);
        if (in.orient == TDSD_ORIENT_AXIS)
            assert_true(linalg_maxabs_diff(y2a, y2b, 2, 1) <= 1e-12);
        {
            double d = 0.0;
            int i;
            for (i = 0; i < NJ; i++)
                d += in.grad_V[i] * o1.dq3[i];
            assert_true(d > 0.0); /* projected gradient ascends V */
        }
    }
    /* full 6-row task on a full-rank J: no freedom left, dq3 = 0 */
    make_input(&in);
    in.k_V = 1.0;
    rand_vec(in.grad_V, NJ, 1.0);
    assert_int_equal(tdsd_step(&in, &o1), TDSD_OK);
    {
        int i;
        for (i = 0; i < NJ; i++)
            assert_true(fabs(o1.dq3[i]) <= 1e-12);
    }
}

static void test_time_scaling_and_feedback_fallback(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double y1[3], y2[3], want[3], c[3];
    int i, trial;
    (void)state;
    for (trial = 0; trial < 100; trial++) {
        make_input(&in);
        vec3_set(in.v_d_mps, 50.0 * urand(), 50.0, 0.0);
        for (i = 0; i < NJ; i++)
            in.dq_max_radps[i] = 1.0;
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        assert_true(out.time_scaled);
        assert_true(out.lambda < 1.0 && out.lambda > 0.0);
        assert_true(out.fb_scale == 1.0);
        task_rates(y1, y2, &in, out.dq_radps);
        for (i = 0; i < 3; i++)
            want[i] = out.lambda * in.v_d_mps[i] + in.K_p * (in.p_d_m[i] - in.p_m[i]);
        assert_true(linalg_maxabs_diff(y1, want, 3, 1) <= 1e-9);

        /* feedback alone too fast: direction toward p_d kept, speed cut */
        vec3_set(in.v_d_mps, 0, 0, 0);
        rand_vec(in.p_d_m, 3, 100.0);
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        assert_true(out.fb_scale < 1.0 && out.time_scaled);
        task_rates(y1, y2, &in, out.dq_radps);
        vec3_sub(want, in.p_d_m, in.p_m);
        vec3_cross(c, y1, want);
        assert_true(vec3_norm(c) <= 1e-9 * vec3_norm(y1) * vec3_norm(want));
        assert_true(vec3_dot(y1, want) > 0.0);
    }
    /* rate_cap = 0 holds the path: only feedback */
    make_input(&in);
    in.rate_cap = 0.0;
    assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
    assert_true(out.lambda == 0.0 && !out.time_scaled);
}

/* Caller contract: advancing the path parameter by lambda * dt keeps the
 * tool on the moving reference while time scaling is active (J1 fixed and
 * nearly singular, the path heading along its weak direction). */
static void test_time_scaled_path_tracking(void **state)
{
    tdsd_input in;
    tdsd_output out;
    double p0[3], y1[3], y2[3], e[3];
    double s_path = 0.0, min_lambda = 1.0, worst = 0.0;
    const double dt = 0.004;
    int it, i;
    (void)state;
    make_input(&in);
    for (i = 0; i < NJ; i++)
        in.J1[2 * NJ + i] = 0.5 * in.J1[i] + 0.5 * in.J1[NJ + i] + 1e-3 * in.Jw[i];
    in.v_d_mps[0] = 0.5;
    in.v_d_mps[1] = 0.5;
    in.v_d_mps[2] = 1.0;
    for (i = 0; i < NJ; i++)
        in.dq_max_radps[i] = 1.5;
    vec3_copy(p0, in.p_m);
    for (it = 0; it < 500; it++) {
        vec3_axpy(in.p_d_m, p0, s_path, in.v_d_mps);
        assert_int_equal(tdsd_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        vec3_sub(e, in.p_d_m, in.p_m);
        worst = vec3_norm(e) > worst ? vec3_norm(e) : worst;
        min_lambda = out.lambda < min_lambda ? out.lambda : min_lambda;
        task_rates(y1, y2, &in, out.dq_radps);
        vec3_axpy(in.p_m, in.p_m, dt, y1);
        rotate_by(in.R, y2, dt);
        s_path += out.lambda * dt;
    }
    assert_true(min_lambda < 0.1); /* it really crawled */
    assert_true(s_path > 0.0);     /* and still advanced */
    assert_true(worst <= 1e-12);   /* on the path throughout */
}

static void test_midrange_grad(void **state)
{
    const double deg = PI_ / 180.0;
    const double qmin[NJ] = {
        -160 * deg, -225 * deg, -45 * deg, -110 * deg, -100 * deg, -266 * deg
    };
    const double qmax[NJ] = { 160 * deg, 45 * deg, 225 * deg, 170 * deg, 100 * deg, 266 * deg };
    double q[NJ], g[NJ], V, Vp, Vm, gd[NJ];
    int trial, i;
    (void)state;
    for (trial = 0; trial < 100; trial++) {
        for (i = 0; i < NJ; i++)
            q[i] = 0.5 * (qmin[i] + qmax[i]) + 0.5 * (qmax[i] - qmin[i]) * urand();
        assert_int_equal(tdsd_midrange_grad(g, &V, q, qmin, qmax, 0x38u), TDSD_OK);
        assert_true(V <= 0.0);
        for (i = 0; i < NJ; i++) {
            const double h = 1e-6;
            double qq[NJ];
            memcpy(qq, q, sizeof q);
            qq[i] = q[i] + h;
            assert_int_equal(tdsd_midrange_grad(gd, &Vp, qq, qmin, qmax, 0x38u), TDSD_OK);
            qq[i] = q[i] - h;
            assert_int_equal(tdsd_midrange_grad(gd, &Vm, qq, qmin, qmax, 0x38u), TDSD_OK);
            assert_true(fabs((Vp - Vm) / (2 * h) - g[i]) <= 1e-8);
            if (i < 3)
                assert_true(g[i] == 0.0);
        }
    }
    for (i = 0; i < NJ; i++)
        q[i] = 0.5 * (qmin[i] + qmax[i]);
    assert_int_equal(tdsd_midrange_grad(g, &V, q, qmin, qmax, 0x38u), TDSD_OK);
    assert_true(fabs(V) <= 1e-30);
    assert_int_equal(tdsd_midrange_grad(g, &V, q, qmax, qmin, 0x38u), TDSD_ERR_ARG);
    q[4] = NAN;
    assert_int_equal(tdsd_midrange_grad(g, &V, q, qmin, qmax, 0x38u), TDSD_ERR_ARG);
    /* the ranges taken once: the same gradient bit for bit, a NaN of an
     * unmasked joint left out, the same range check */
    {
        tdsd_midrange c;
        assert_int_equal(tdsd_midrange_init(&c, qmin, qmax, 0x38u), TDSD_OK);
        q[4] = 0.3;
        q[0] = NAN;
        tdsd_midrange_grad_at(&c, q, gd);
        assert_int_equal(tdsd_midrange_grad(g, &V, q, qmin, qmax, 0x38u), TDSD_OK);
        assert_memory_equal(g, gd, sizeof g);
        assert_true(gd[0] == 0.0 && gd[4] != 0.0);
        assert_int_equal(tdsd_midrange_init(&c, qmax, qmin, 0x38u), TDSD_ERR_ARG);
        assert_int_equal(tdsd_midrange_init(&c, qmax, qmin, 0x7u), TDSD_ERR_ARG);
        assert_int_equal(tdsd_midrange_init(&c, qmin, qmax, 0u), TDSD_OK);
    }
}

static void test_baselines(void **state)
{
    tdsd_input in;
    tdsd_output out, ref;
    rr_dls_params dls;
    double J[NJ * NJ], y[NJ], Jdq[NJ];
    int trial, i, n_distorted = 0;
    (void)state;
    for (trial = 0; trial < 200; trial++) {
        make_input(&in);
        memcpy(J, in.J1, sizeof in.J1);
        memcpy(J + 3 * NJ, in.Jw, sizeof in.Jw);
        /* generous limits: the 6-D task is met exactly */
        assert_int_equal(rr_pinv_step(&in, &out), TDSD_OK);
        assert_int_equal(out.n_clipped, 0);
        linalg_matvec(Jdq, J, out.dq_radps, NJ, NJ);
        memcpy(y, out.y1, sizeof out.y1);
        memcpy(y + 3, out.y2, sizeof out.y2);
        assert_true(linalg_maxabs_diff(Jdq, y, NJ, 1) <= 1e-9);
        /* DLS outside the singular region (sigma_min >= eps): no damping */
        dls.lambda0 = 0.1;
        dls.eps = 0.01;
        memcpy(&ref, &out, sizeof out);
        assert_int_equal(rr_dls_step(&in, &dls, &out), TDSD_OK);
        assert_true(out.damping == 0.0);
        assert_true(linalg_maxabs_diff(out.dq_radps, ref.dq_radps, NJ, 1) <= 1e-9);
        /* inside it: lambda^2 = lambda0^2 (1 - (sigma_min/eps)^2) */
        dls.eps = 10.0;
        assert_int_equal(rr_dls_step(&in, &dls, &out), TDSD_OK);
        {
            double smin = sigma_min_of(J, NJ, NJ), r = smin / dls.eps;
            assert_true(fabs(out.damping * out.damping - dls.lambda0 * dls.lambda0 * (1 - r * r)) <=
                        1e-12);
        }
        /* constant damping and its normal equations */
        dls.eps = 0.0;
        assert_int_equal(rr_dls_step(&in, &dls, &out), TDSD_OK);
        assert_true(out.damping == dls.lambda0);
        {
            double JtJ[NJ * NJ], lhs[NJ], rhs[NJ];
            linalg_tmul(JtJ, J, J, NJ, NJ, NJ);
            for (i = 0; i < NJ; i++)
                JtJ[i * NJ + i] += dls.lambda0 * dls.lambda0;
            linalg_matvec(lhs, JtJ, out.dq_radps, NJ, NJ);
            linalg_tmatvec(rhs, J, y, NJ, NJ);
            assert_true(linalg_maxabs_diff(lhs, rhs, NJ, 1) <= 1e-9);
        }
        /* tight limits: per-joint clipping distorts the direction */
        rand_vec(in.v_d_mps, 3, 3.0);
        for (i = 0; i < NJ; i++)
            in.dq_max_radps[i] = 0.2;
        assert_int_equal(rr_pinv_step(&in, &out), TDSD_OK);
        check_limits(&in, &out);
        if (out.n_clipped > 0) {
            double cr[3];
            linalg_matvec(Jdq, J, out.dq_radps, NJ, NJ);
            vec3_cross(cr, Jdq, out.y1);
            if (vec3_norm(cr) > 1e-3 * vec3_norm(Jdq) * vec3_norm(out.y1))
                n_distorted++;
        }
    }
    assert_true(n_distorted > 50);
}

static void test_invalid_input(void **state)
{
    tdsd_input in, bad;
    tdsd_output out;
    rr_dls_params dls = { 0.1, 0.1 };
    int i;
    (void)state;
    make_input(&in);
    bad = in;
    bad.J1[4] = NAN;
    assert_int_equal(tdsd_step(&bad, &out), TDSD_ERR_ARG);
    for (i = 0; i < NJ; i++)
        assert_true(out.dq_radps[i] == 0.0);
    bad = in;
    bad.dq_max_radps[2] = 0.0;
    assert_int_equal(tdsd_step(&bad, &out), TDSD_ERR_ARG);
    bad = in;
    bad.rate_cap = 1.5;
    assert_int_equal(tdsd_step(&bad, &out), TDSD_ERR_ARG);
    bad = in;
    bad.orient = (tdsd_orient_mode)7;
    assert_int_equal(tdsd_step(&bad, &out), TDSD_ERR_ARG);
    bad = in;
    bad.K_p = -1.0;
    assert_int_equal(rr_pinv_step(&bad, &out), TDSD_ERR_ARG);
    bad = in;
    bad.R[3] = INFINITY;
    assert_int_equal(rr_dls_step(&bad, &dls, &out), TDSD_ERR_ARG);
    dls.lambda0 = -1.0;
    assert_int_equal(rr_dls_step(&in, &dls, &out), TDSD_ERR_ARG);
    assert_int_equal(rr_dls_step(&in, NULL, &out), TDSD_ERR_ARG);
}

/* ---- the fast path against the SVD path (docs/method/tdsd.md §3a) ---- */

/* sigma_max / sigma_min of J1 and of J2 P1 (explicit, by the SVD). */
static void task_conds(const tdsd_input *in, double *k1, double *k2)
{
    linalg_pinv_svd F1, F2;
    double J2[3 * NJ], M[3 * NJ];
    int n2 = 0, i;
    assert_true(linalg_pinv_factor(&F1, in->J1, 3, NJ, 1e-300) >= LINALG_ERR_NOCONV);
    *k1 = F1.s[0] / F1.s[2];
    *k2 = 1.0;
    if (in->orient == TDSD_ORIENT_FULL) {
        n2 = 3;
        for (i = 0; i < 3 * NJ; i++)
            J2[i] = in->Jw[i];
    } else if (in->orient == TDSD_ORIENT_AXIS) {
        n2 = 2;
        tdsd_axis_jacobian(J2, in->Jw, in->R);
    }
    if (n2 > 0) {
        F1.info.rank = 3; /* the whole row space of J1 */
        linalg_pinv_null_rows(M, J2, n2, &F1);
        assert_true(linalg_pinv_factor(&F2, M, n2, NJ, 1e-300) >= LINALG_ERR_NOCONV);
        *k2 = F2.s[0] / F2.s[n2 - 1];
    }
}

static double vmax(const double *v, int n)
{
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++)
        if (fabs(v[i]) > m)
            m = fabs(v[i]);
    return m;
}

/* A joint within tol of its limit at the base of either speed share. */
static int at_limit(const tdsd_input *in, const tdsd_output *o, double tol)
{
    int i;
    for (i = 0; i < NJ; i++) {
        const double m = in->dq_max_radps[i];
        if (fabs(fabs(o->dq1[i]) - m) <= tol ||
            fabs(fabs(o->dq1[i] + o->Q1 * o->dq2[i]) - m) <= tol)
            return 1;
    }
    return 0;
}

typedef struct {
    int gram, lq, slow;
    double worst_gram; /* max error / (DBL_EPSILON (kappa1 kappa2)^2 scale) */
    double worst_lq;   /* max error / (DBL_EPSILON kappa1 kappa2 scale) */
    double worst_well; /* max error / scale where kappa1 kappa2 <= 100 */
} fast_stats;

/* One input through both paths: the fast path taken only where both
 * blocks are well conditioned, and then the same rates to rounding. */
static void compare_paths(const tdsd_input *in, fast_stats *st)
{
    tdsd_output f, o, u;
    double k1, k2, scale, tol, err;
    assert_int_equal(tdsd_step(in, &f), TDSD_OK);
    /* the unchecked entry (tdsd_seg_step's) is the same step */
    assert_int_equal(tdsd_step_unchecked(in, &u), TDSD_OK);
    assert_memory_equal(&f, &u, sizeof f);
    assert_int_equal(tdsd_step_svd(in, &o), TDSD_OK);
    assert_int_equal(o.fast, 0);
    check_limits(in, &f);
    task_conds(in, &k1, &k2);
    if (f.fast == TDSD_PATH_SVD) {
        /* declined: one block's condition number is past the bound (the
         * Frobenius product overestimates it at most 3 times) */
        st->slow++;
        assert_true(k1 >= TDSD_FAST_COND_MAX / 3.0 || k2 >= TDSD_FAST_COND_MAX / 3.0 || k1 != k1 ||
                    k2 != k2);
        assert_memory_equal(f.dq_radps, o.dq_radps, sizeof f.dq_radps);
        return;
    }
    assert_true(k1 <= TDSD_FAST_COND_MAX * (1.0 + 1e-9) && k2 <= TDSD_FAST_COND_MAX * (1.0 + 1e-9));
    if (f.fast == TDSD_PATH_GRAM) { /* the product of the bounds is <= the Gram bound */
        st->gram++;
        assert_true(k1 * k2 <= TDSD_GRAM_COND_MAX * (1.0 + 1e-9));
    } else { /* declined by the Gram path: the product of the bounds (each at
              * most 3 times its kappa) is past the Gram bound */
        assert_int_equal(f.fast, TDSD_PATH_LQ);
        st->lq++;
        assert_true(k1 * k2 >= TDSD_GRAM_COND_MAX / 9.0 * (1.0 - 1e-9));
    }
    /* the singular-value bounds bracket the SVD's */
    assert_true(f.sigma_min_J1 <= o.sigma_min_J1 * (1.0 + 1e-9));
    assert_true(f.sigma_min_J1 * sqrt(3.0) >= o.sigma_min_J1 * (1.0 - 1e-9));
    assert_true(f.sigma_max_J1 >= o.sigma_max_J1 * (1.0 - 1e-9));
    assert_true(f.sigma_max_J1 <= o.sigma_max_J1 * sqrt(3.0) * (1.0 + 1e-9));
    assert_int_equal(f.rank_J1, o.rank_J1);
    assert_int_equal(f.rank_J2P1, o.rank_J2P1);
    scale = 1.0 + vmax(o.dq1, NJ) + vmax(o.dq2, NJ) + vmax(o.dq3, NJ) + vmax(in->dq_max_radps, NJ);
    tol = DBL_EPSILON * k1 * k2 * scale;
    if (f.fast == TDSD_PATH_GRAM)
        tol *= k1 * k2;
    /* Q1 (Q2) is decided by rounding where a joint of dq1 (dq1 + Q1 dq2)
     * already runs at its limit, as after time scaling or a shrunk
     * feedback: (dq_max_i - |base_i|) / |d_i| is then rounding over
     * rounding. There the final rates are compared through their parts. */
    err = at_limit(in, &o, FAST_TOL_FACTOR * tol)
              ? 0.0
              : linalg_maxabs_diff(f.dq_radps, o.dq_radps, NJ, 1);
    err = fmax(err, linalg_maxabs_diff(f.dq1, o.dq1, NJ, 1));
    err = fmax(err, linalg_maxabs_diff(f.dq2, o.dq2, NJ, 1));
    err = fmax(err, linalg_maxabs_diff(f.dq3, o.dq3, NJ, 1));
    err = fmax(err, fabs(f.lambda - o.lambda) * (1.0 + vmax(o.dq1, NJ)));
    if (f.fast == TDSD_PATH_GRAM) {
        st->worst_gram = fmax(st->worst_gram, err / tol);
        if (k1 * k2 <= 100.0) {
            st->worst_well = fmax(st->worst_well, err / scale);
            assert_true(err <= WELL_TOL * scale);
        }
    } else {
        st->worst_lq = fmax(st->worst_lq, err / tol);
    }
    assert_true(err <= FAST_TOL_FACTOR * tol);
}

static void print_stats(const fast_stats *st)
{
    print_message("U D U^T %d, LQ %d, SVD %d; worst error / (eps (k1 k2)^2 scale) %.3g, "
                  "/ (eps k1 k2 scale) %.3g; where k1 k2 <= 100: error / scale %.3g\n",
                  st->gram, st->lq, st->slow, st->worst_gram, st->worst_lq, st->worst_well);
}

/* J1 = U diag(1, s2, s3) V1^T with random orthogonal U, V: conditioning set. */
static void set_conditioned_J1(tdsd_input *in, double s2, double s3)
{
    double A[NJ * NJ], Uu[NJ * NJ], V[NJ * NJ], s[NJ], U[9], sv[3];
    int i, j, k;
    rand_vec(A, NJ * NJ, 1.0);
    assert_true(linalg_svd(Uu, s, V, A, NJ, NJ) >= LINALG_ERR_NOCONV);
    rand_rot(U, PI_);
    sv[0] = 1.0;
    sv[1] = s2;
    sv[2] = s3;
    for (i = 0; i < 3; i++)
        for (j = 0; j < NJ; j++) {
            double acc = 0.0;
            for (k = 0; k < 3; k++)
                acc += U[i * 3 + k] * sv[k] * V[j * NJ + k];
            in->J1[i * NJ + j] = acc;
        }
}

static void randomise_task(tdsd_input *in)
{
    int i;
    in->orient = (tdsd_orient_mode)(rng_state % 3u);
    in->k_V = 2.0 * (urand() + 1.0);
    rand_vec(in->grad_V, NJ, 1.0);
    for (i = 0; i < NJ; i++)
        in->dq_max_radps[i] = 0.05 + 1.5 * (urand() + 1.0);
    in->rate_cap = 0.5 * (urand() + 1.0);
    in->K_p = 20.0;
    in->K_o = 10.0;
}

static void test_fast_path_matches_svd_random(void **state)
{
    fast_stats st = { 0, 0, 0, 0.0, 0.0, 0.0 };
    int t;
    (void)state;
    for (t = 0; t < 2000; t++) {
        tdsd_input in;
        const double e = pow(10.0, -14.0 * 0.5 * (urand() + 1.0)); /* 1 .. 1e-14 */
        make_input(&in);
        randomise_task(&in);
        set_conditioned_J1(&in, 0.5 * (urand() + 1.0), t % 2 ? e : 0.5 * (urand() + 1.0));
        if (t % 3 == 0) { /* J2 P1 near rank loss: a row of Jw near J1's row space */
            const double d = pow(10.0, -14.0 * 0.5 * (urand() + 1.0));
            int j;
            for (j = 0; j < NJ; j++)
                in.Jw[j] = in.J1[j] - 0.5 * in.J1[NJ + j] + d * in.Jw[j];
        }
        compare_paths(&in, &st);
    }
    print_stats(&st);
    assert_true(st.gram > 600 && st.lq > 200 && st.slow > 200);
}

/* The PUMA 560's own Jacobians (tool 0.1 m down the flange), over the
 * joint ranges and at the wrist (q5 = 0) and elbow (q3 with the arm
 * stretched) singularities and near them. */
static void test_fast_path_matches_svd_puma(void **state)
{
    const arm_model *m = &arm_model_puma560;
    const double off[3] = { 0.0, 0.0, 0.1 };
    fast_stats st = { 0, 0, 0, 0.0, 0.0, 0.0 };
    arm_tool tool;
    int t, i;
    (void)state;
    arm_tool_offset(&tool, off);
    for (t = 0; t < 2000; t++) {
        tdsd_input in;
        double q[ARM_NJ], T[16], J[36];
        const double e = t % 4 == 0 ? 0.0 : pow(10.0, -12.0 * 0.5 * (urand() + 1.0));
        make_input(&in);
        randomise_task(&in);
        for (i = 0; i < ARM_NJ; i++)
            q[i] = m->q_min_rad[i] + 0.5 * (urand() + 1.0) * (m->q_max_rad[i] - m->q_min_rad[i]);
        switch (t % 5) {
        case 1: q[4] = e * urand(); break; /* wrist */
        case 2: /* elbow: wrist centre on link 2's line, d4 cos q3 = a3 sin q3 */
            q[2] = atan2(m->d_m[3], m->a_m[2]) + e * urand();
            break;
        default: break;
        }
        assert_int_equal(arm_fk_jacobian(m, &tool, q, T, J), 0);
        for (i = 0; i < 3 * NJ; i++) {
            in.J1[i] = J[i];
            in.Jw[i] = J[18 + i];
        }
        tf_rot(in.R, T);
        compare_paths(&in, &st);
    }
    print_stats(&st);
    assert_true(st.gram > 600 && st.lq > 0 && st.slow > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_priority1_exact_and_Q_one_when_generous),
        cmocka_unit_test(test_priority1_exact_under_speed_distribution),
        cmocka_unit_test(test_limits_random_and_singular),
        cmocka_unit_test(test_factored_matches_explicit_formulas),
        cmocka_unit_test(test_Q1_drops_toward_singularity),
        cmocka_unit_test(test_orientation_error_formula),
        cmocka_unit_test(test_dq2_reduces_orientation_keeps_position),
        cmocka_unit_test(test_nullspace_term_invariance),
        cmocka_unit_test(test_time_scaling_and_feedback_fallback),
        cmocka_unit_test(test_time_scaled_path_tracking),
        cmocka_unit_test(test_midrange_grad),
        cmocka_unit_test(test_baselines),
        cmocka_unit_test(test_invalid_input),
        cmocka_unit_test(test_fast_path_matches_svd_random),
        cmocka_unit_test(test_fast_path_matches_svd_puma),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

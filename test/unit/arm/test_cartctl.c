/* test_cartctl: Jdot qd against second differences of FK, the model as
 * plant (arm_forward_dynamics) reproduces the commanded tool acceleration,
 * a closed loop with that plant tracks a straight-line acceleration
 * profile and holds the orientation, damping engages only near the wrist
 * singularity, the range barrier keeps a joint inside its range where the
 * unbounded law runs it past (and the tool still converges), bad input is
 * refused; the PUMA's fast path (C^-1 in closed form) solves as the
 * general wrist blocks do. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "arm_samples.h"
#include "cartctl.h"
#include "linalg.h"
#include "vec3.h"

static const double Q_A[ARM_NJ] = { 0.3, -0.6, 2.7, 0.2, -0.45, 0.1 };
static const double QD_A[ARM_NJ] = { 0.4, -0.3, 0.5, -0.6, 0.7, 0.9 };

static arm_tool tool10(void)
{
    arm_tool t;
    const double off[3] = { 0.0, 0.0, 0.10 };
    arm_tool_offset(&t, off);
    return t;
}

static void pose_at(const double q[ARM_NJ], const double qd[ARM_NJ], double t, double p[3],
                    double R[9])
{
    const arm_tool tool = tool10();
    double qt[ARM_NJ], T[16];
    int i;
    for (i = 0; i < ARM_NJ; i++)
        qt[i] = q[i] + t * qd[i];
    arm_fk(&arm_model_puma560, &tool, qt, T);
    tf_pos(p, T);
    tf_rot(R, T);
}

/* angular velocity along q + t qd from FK alone: log(R(t+h) R(t-h)^T)/2h */
static void omega_fk(double t, double w[3])
{
    const double h = 1e-4;
    double p[3], Rp[9], Rm[9];
    pose_at(Q_A, QD_A, t + h, p, Rp);
    pose_at(Q_A, QD_A, t - h, p, Rm);
    cartctl_rot_error(Rp, Rm, w);
    vec3_scale(w, w, 1.0 / (2.0 * h));
}

static void test_jdot_qd_matches_fk(void **st)
{
    const arm_tool tool = tool10();
    const double h = 1e-3;
    double jd[6], pp[3], p0[3], pm[3], R[9], wp[3], wm[3];
    int i;
    (void)st;
    assert_int_equal(cartctl_jdot_qd(&arm_model_puma560, &tool, Q_A, QD_A, jd), 0);
    /* with qdd = 0, xdd = Jdot qd: second difference of the FK position */
    pose_at(Q_A, QD_A, h, pp, R);
    pose_at(Q_A, QD_A, 0.0, p0, R);
    pose_at(Q_A, QD_A, -h, pm, R);
    for (i = 0; i < 3; i++)
        assert_true(fabs((pp[i] - 2.0 * p0[i] + pm[i]) / (h * h) - jd[i]) < 1e-3);
    omega_fk(h, wp);
    omega_fk(-h, wm);
    for (i = 0; i < 3; i++)
        assert_true(fabs((wp[i] - wm[i]) / (2.0 * h) - jd[3 + i]) < 1e-3);
}

static void test_model_plant_gives_commanded_accel(void **st)
{
    const arm_tool tool = tool10();
    const double a_lin[3] = { 0.4, -0.3, 0.2 };
    arm_payload pl;
    const double com[3] = { 0.0, 0.0, 0.10 };
    cartctl_gains g;
    cartctl_state s;
    cartctl_out o;
    double tau[ARM_NJ], qdd[ARM_NJ], jd[6], xdd[6], R_d[9], R[9], axis[3] = { 0.3, 0.5, -0.2 };
    double qd[ARM_NJ];
    int i;
    (void)st;
    for (i = 0; i < ARM_NJ; i++)
        qd[i] = 0.1 * QD_A[i]; /* moderate speed: no torque limit reached */
    cartctl_gains_default(&g);
    arm_payload_point(&pl, 0.5, com);
    assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, Q_A, qd, &s), 0);
    tf_rot(R, s.T);
    vec3_normalize(axis, axis);
    {
        double dR[9];
        rot_from_axis_angle(dR, axis, 0.002);
        rot_mul(R_d, dR, R);
    }
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, &pl, &g, Q_A, qd, &s, a_lin, R_d, tau, &o), 0);
    assert_int_equal(o.saturated, 0);
    assert_true(o.lambda == 0.0);
    assert_int_equal(arm_forward_dynamics(&arm_model_puma560, Q_A, qd, tau, NULL, &pl, qdd), 0);
    cartctl_jdot_qd(&arm_model_puma560, &tool, Q_A, qd, jd);
    for (i = 0; i < 6; i++) {
        int k;
        xdd[i] = jd[i];
        for (k = 0; k < ARM_NJ; k++)
            xdd[i] += s.J[i * 6 + k] * qdd[k];
        assert_true(fabs(xdd[i] - o.a_cmd[i]) < 1e-6);
    }
    for (i = 0; i < 3; i++)
        assert_true(fabs(o.a_cmd[i] - a_lin[i]) < 1e-15);
    /* the orientation channel is a PD on the rotation error */
    for (i = 0; i < 3; i++)
        assert_true(fabs(o.rot_err[i] - 0.002 * axis[i]) < 1e-9);
}

/* Closed loop: x_d(t) = x0 + e (a t^2 / 2) with a PD around it, the model
 * as plant at 1 kHz: position error stays well under a millimetre and the
 * orientation under a milliradian. */
static void test_closed_loop_tracks(void **st)
{
    const arm_tool tool = tool10();
    const double dt = 1e-3, acc = 0.3, e[3] = { 0.6, 0.0, -0.8 };
    double q[ARM_NJ], qd[ARM_NJ] = { 0 }, x0[3], R0[9], max_err = 0.0, max_rot = 0.0;
    cartctl_gains g;
    int k, i;
    (void)st;
    cartctl_gains_default(&g);
    memcpy(q, Q_A, sizeof q);
    {
        cartctl_state s;
        cartctl_state_at(&arm_model_puma560, &tool, q, qd, &s);
        tf_pos(x0, s.T);
        tf_rot(R0, s.T);
    }
    for (k = 0; k < 1000; k++) {
        const double t = k * dt;
        cartctl_state s;
        cartctl_out o;
        double x[3], u[3], tau[ARM_NJ], qdd[ARM_NJ], err;
        cartctl_state_at(&arm_model_puma560, &tool, q, qd, &s);
        tf_pos(x, s.T);
        for (i = 0; i < 3; i++) {
            const double xd = x0[i] + e[i] * 0.5 * acc * t * t, vd = e[i] * acc * t;
            u[i] = e[i] * acc + 20.0 * (vd - s.twist[i]) + 100.0 * (xd - x[i]);
        }
        err = 0.0;
        for (i = 0; i < 3; i++) {
            const double d = x0[i] + e[i] * 0.5 * acc * t * t - x[i];
            err += d * d;
        }
        max_err = fmax(max_err, sqrt(err));
        assert_int_equal(
            cartctl_torque(&arm_model_puma560, &tool, NULL, &g, q, qd, &s, u, R0, tau, &o), 0);
        max_rot = fmax(max_rot, vec3_norm(o.rot_err));
        arm_forward_dynamics(&arm_model_puma560, q, qd, tau, NULL, NULL, qdd);
        for (i = 0; i < ARM_NJ; i++) {
            qd[i] += dt * qdd[i];
            q[i] += dt * qd[i];
        }
    }
    assert_true(max_err < 5e-4);
    assert_true(max_rot < 1e-3);
}

static void test_damping_near_wrist_singularity(void **st)
{
    const arm_tool tool = tool10();
    const double a[3] = { 0.5, 0.5, 0.5 };
    double q[ARM_NJ], tau[ARM_NJ], n_far = 0.0, n_near = 0.0;
    cartctl_gains g;
    cartctl_out o;
    int i;
    (void)st;
    cartctl_gains_default(&g);
    memcpy(q, Q_A, sizeof q);
    q[4] = 1e-4;
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, q, QD_A, NULL, a, NULL, tau, &o), 0);
    assert_true(o.lambda > 0.9 * g.lambda_max);
    for (i = 0; i < ARM_NJ; i++)
        n_near = fmax(n_near, fabs(o.qdd[i]));
    assert_true(n_near < 1e3); /* bounded although J is singular */
    q[4] = -0.45;
    cartctl_torque(&arm_model_puma560, &tool, NULL, &g, q, QD_A, NULL, a, NULL, tau, &o);
    assert_true(o.lambda == 0.0);
    for (i = 0; i < ARM_NJ; i++)
        n_far = fmax(n_far, fabs(o.qdd[i]));
    assert_true(n_far > 0.0);
}

/* The fast path (J^-1 when a lower bound on sigma_min clears the band)
 * is the same law as the damped SVD inverse: over poses from far to
 * right at the wrist singularity, qdd matches V diag(s/(s^2+l^2)) U^T rhs
 * - k_null V diag(l^2/(s^2+l^2)) V^T qd computed here from one SVD, and
 * the reported sigma_min never exceeds the true one. Both paths run. */
/* The fast path (the spherical wrist's block inverse for the PUMA, the
 * 6x6 inverse for a general table) equals the damped SVD law. */
static void fast_path_matches_svd(const arm_model *m)
{
    const arm_tool tool = tool10();
    cartctl_gains g;
    int n, fast = 0, slow = 0;
    cartctl_gains_default(&g);
    for (n = 0; n < 200; n++) {
        double q[ARM_NJ], qd[ARM_NJ], a[3], R_d[9], U[36], sv[6], V[36], jd[6], rhs[6], y[6], vq[6];
        double ref[ARM_NJ], lam2 = 0.0, err = 0.0, scale = 0.0;
        cartctl_out o;
        cartctl_state s;
        int i;
        for (i = 0; i < ARM_NJ; i++) {
            q[i] = Q_A[i] + 0.3 * sin(1.7 * n + i);
            qd[i] = QD_A[i] * cos(0.9 * n + 2 * i);
        }
        q[4] = -0.6 * (double)(n % 50) / 49.0; /* 0 .. -0.6 rad: through the band */
        vec3_set(a, 0.3 * sin(n), 0.2, -0.1 * cos(n));
        assert_int_equal(cartctl_state_at(m, &tool, q, qd, &s), 0);
        rot_from_axis_angle(R_d, a, 0.05);
        assert_int_equal(cartctl_qdd(m, &tool, &g, q, qd, &s, a, R_d, &o), 0);
        assert_int_equal(cartctl_jdot_qd(m, &tool, q, qd, jd), 0);
        for (i = 0; i < 6; i++)
            rhs[i] = o.a_cmd[i] - jd[i];
        linalg_svd(U, sv, V, s.J, 6, 6);
        if (sv[5] < g.sigma_band)
            lam2 = g.lambda_max * g.lambda_max *
                   (1.0 - (sv[5] / g.sigma_band) * (sv[5] / g.sigma_band));
        linalg_tmatvec(y, U, rhs, 6, 6);
        linalg_tmatvec(vq, V, qd, 6, 6);
        for (i = 0; i < 6; i++)
            y[i] = (sv[i] * y[i] - g.k_null * lam2 * vq[i]) / (sv[i] * sv[i] + lam2);
        linalg_matvec(ref, V, y, 6, 6);
        for (i = 0; i < ARM_NJ; i++) {
            err = fmax(err, fabs(o.qdd[i] - ref[i]));
            scale = fmax(scale, fabs(ref[i]));
        }
        assert_true(err <= 1e-9 * fmax(scale, 1.0));
        assert_int_equal(o.range_limited, 0u); /* far from every range end */
        assert_true(o.sigma_min <= sv[5] * (1.0 + 1e-9));
        if (lam2 == 0.0 && o.sigma_min < sv[5] * (1.0 - 1e-9)) {
            fast++; /* bound, not the SVD value: the fast path ran */
            if (s.has_wrist) {
                /* the wrist path's bound, summed from the blocks, is
                 * 1/||J^-1||_F of the 6x6 inverse */
                double Ji[36], f2 = 0.0;
                double x[ARM_NJ], xe = 0.0, xs = 0.0;
                assert_int_equal(cartctl_inverse_wrist(s.J, s.T, s.wrist_m, Ji), 0);
                for (i = 0; i < 36; i++)
                    f2 += Ji[i] * Ji[i];
                assert_true(fabs(o.sigma_min * sqrt(f2) - 1.0) < 1e-12);
                /* and the cycle's blocks, folded for the PUMA's zeros
                 * (wrist_a_cb_puma), solve as the general ones do */
                linalg_matvec(x, Ji, rhs, 6, 6);
                for (i = 0; i < ARM_NJ; i++) {
                    xe = fmax(xe, fabs(o.qdd[i] - x[i]));
                    xs = fmax(xs, fabs(x[i]));
                }
                assert_true(xe <= 1e-12 * xs);
            }
        } else
            slow++;
    }
    assert_true(fast > 0 && slow > 0);
}

static void test_fast_path_matches_svd(void **st)
{
    arm_model general = arm_model_puma560;
    (void)st;
    general.structure = ARM_STRUCTURE_GENERAL;
    fast_path_matches_svd(&arm_model_puma560);
    fast_path_matches_svd(&general);
}

/* cartctl_inverse_wrist is J's inverse (J Ji = I) for random PUMA poses,
 * says so at the wrist singularity, and refuses bad input. */
static void test_inverse_wrist(void **st)
{
    const arm_tool tool = tool10();
    double Ji[36];
    int n, i, j, k;
    (void)st;
    for (n = 0; n < 200; n++) {
        cartctl_state s;
        double q[ARM_NJ];
        for (i = 0; i < ARM_NJ; i++)
            q[i] = Q_A[i] + 0.8 * sin(2.3 * n + 1.1 * i);
        assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, q, QD_A, &s), 0);
        assert_int_equal(s.has_wrist, 1);
        assert_int_equal(cartctl_inverse_wrist(s.J, s.T, s.wrist_m, Ji), 0);
        for (i = 0; i < 6; i++)
            for (j = 0; j < 6; j++) {
                double t = 0.0;
                for (k = 0; k < 6; k++)
                    t += s.J[6 * i + k] * Ji[6 * k + j];
                assert_true(fabs(t - (i == j ? 1.0 : 0.0)) < 1e-9);
            }
    }
    {
        cartctl_state s;
        double q[ARM_NJ];
        memcpy(q, Q_A, sizeof q);
        q[4] = 0.0; /* z4 and z6 in line */
        assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, q, QD_A, &s), 0);
        assert_int_equal(cartctl_inverse_wrist(s.J, s.T, s.wrist_m, Ji), CARTCTL_ERR_SINGULAR);
        assert_int_equal(cartctl_inverse_wrist(NULL, s.T, s.wrist_m, Ji), CARTCTL_ERR_ARG);
        s.T[7] = NAN;
        assert_int_equal(cartctl_inverse_wrist(s.J, s.T, s.wrist_m, Ji), CARTCTL_ERR_ARG);
    }
}

/* The largest |qdd - J^-1 rhs| / max |J^-1 rhs| of the cycle's fast path
 * at q (the PUMA's blocks, C^-1 in closed form: wrist_c_inverse_puma)
 * against the general blocks (cartctl_inverse_wrist, C^-1 by its
 * adjugate); -1 where the fast path did not run (damping, the range
 * barrier, a singular block). */
static double fast_path_vs_general_blocks(const double q[ARM_NJ], const double qd[ARM_NJ])
{
    const arm_tool tool = tool10();
    const double a[3] = { 0.3, -0.2, 0.1 };
    double R_d[9], Ji[36], rhs[6], x[6], err = 0.0, scale = 0.0;
    cartctl_gains g;
    cartctl_state s;
    cartctl_out o;
    int i;
    cartctl_gains_default(&g);
    rot_from_axis_angle(R_d, a, 0.4);
    assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, q, qd, &s), 0);
    assert_int_equal(cartctl_qdd(&arm_model_puma560, &tool, &g, q, qd, &s, a, R_d, &o), 0);
    if (o.lambda != 0.0 || o.range_limited || cartctl_inverse_wrist(s.J, s.T, s.wrist_m, Ji) != 0)
        return -1.0;
    vec3_sub(rhs, o.a_cmd, s.jdqd);
    vec3_sub(rhs + 3, o.a_cmd + 3, s.jdqd + 3);
    linalg_matvec(x, Ji, rhs, 6, 6);
    for (i = 0; i < ARM_NJ; i++) {
        err = fmax(err, fabs(o.qdd[i] - x[i]));
        scale = fmax(scale, fabs(x[i]));
    }
    return err / scale;
}

/* The fast path with C^-1 in closed form agrees with the general blocks to
 * 1e-12 on 10,000 seeded poses inside the joint ranges and on the 64
 * corners of the ranges (docs/method/puma.md §6); at the wrist
 * singularity (q5 = 0, C^-1 undefined) it leaves the solve to the SVD. */
static void test_wrist_closed_form(void **st)
{
    prng_state seed;
    double worst = 0.0;
    int n, fast = 0;
    (void)st;
    prng_seed(&seed, 6);
    for (n = 0; n < 10000 + 64; n++) {
        double q[ARM_NJ], qd[ARM_NJ], e;
        int j;
        random_q(&arm_model_puma560, &seed, q);
        random_vec(&seed, 1.0, qd);
        for (j = 0; n >= 10000 && j < ARM_NJ; j++)
            q[j] = ((n - 10000) >> j) & 1 ? arm_model_puma560.q_max_rad[j]
                                          : arm_model_puma560.q_min_rad[j];
        e = fast_path_vs_general_blocks(q, qd);
        if (e >= 0.0) {
            fast++;
            worst = fmax(worst, e);
        }
    }
    print_message("fast path on %d of 10064 poses; largest difference %.2g of the largest qdd\n",
                  fast, worst);
    assert_true(fast > 5000 && worst <= 1e-12);
    {
        double q[ARM_NJ];
        memcpy(q, Q_A, sizeof q);
        q[4] = 0.0;
        assert_true(fast_path_vs_general_blocks(q, QD_A) < 0.0);
    }
}

/* Runs an underdamped tool servo (k_p 400, k_v 8: zeta 0.2) from Q_B to
 * the pose at q_goal with the model as plant for 4 s. Returns the largest
 * q2 reached; the final tool position and orientation errors and the
 * largest q2 while the barrier held a joint go to *pos_err, *rot_err. */
static double servo_to(const cartctl_gains *g, const double q_goal[ARM_NJ], double *pos_err,
                       double *rot_err, int *limited)
{
    static const double Q_B[ARM_NJ] = { 0.3, 0.45, 2.9, 0.1, -0.5, 0.2 };
    const arm_tool tool = tool10();
    const double dt = 1e-3;
    double q[ARM_NJ], qd[ARM_NJ] = { 0 }, x1[3], R1[9], T1[16], q2_max = -HUGE_VAL;
    int k, i;
    memcpy(q, Q_B, sizeof q);
    arm_fk(&arm_model_puma560, &tool, q_goal, T1);
    tf_pos(x1, T1);
    tf_rot(R1, T1);
    *limited = 0;
    for (k = 0; k < 4000; k++) {
        cartctl_state s;
        cartctl_out o;
        double x[3], u[3], tau[ARM_NJ], qdd[ARM_NJ];
        assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, q, qd, &s), 0);
        tf_pos(x, s.T);
        for (i = 0; i < 3; i++)
            u[i] = 400.0 * (x1[i] - x[i]) - 8.0 * s.twist[i];
        assert_int_equal(
            cartctl_torque(&arm_model_puma560, &tool, NULL, g, q, qd, &s, u, R1, tau, &o), 0);
        *limited |= o.range_limited != 0;
        *rot_err = vec3_norm(o.rot_err);
        vec3_sub(x, x1, x);
        *pos_err = vec3_norm(x);
        assert_int_equal(arm_forward_dynamics(&arm_model_puma560, q, qd, tau, NULL, NULL, qdd), 0);
        for (i = 0; i < ARM_NJ; i++) {
            qd[i] += dt * qdd[i];
            q[i] += dt * qd[i];
        }
        q2_max = fmax(q2_max, q[1]);
    }
    return q2_max;
}

/* Range barrier: the goal has q2 = 0.74 rad, 2.6 deg inside its 45 deg
 * end (and 0.6 deg inside the barrier); the underdamped servo overshoots
 * it. Without the barrier q2 runs past its range (the plant has no
 * stops); with it q2 stays inside the range, the barrier holds the
 * joint, and the tool error still converges to the goal. */
static void test_range_barrier(void **st)
{
    const double q_goal[ARM_NJ] = { 0.3, 0.74, 2.9, 0.1, -0.5, 0.2 };
    const double q2_end = arm_model_puma560.q_max_rad[1];
    double pos_err, rot_err, q2_free, q2_held;
    cartctl_gains g;
    int limited;
    (void)st;
    cartctl_gains_default(&g);
    g.range_w_radps = 0.0;
    q2_free = servo_to(&g, q_goal, &pos_err, &rot_err, &limited);
    assert_int_equal(limited, 0);
    assert_true(q2_free > q2_end);
    cartctl_gains_default(&g);
    q2_held = servo_to(&g, q_goal, &pos_err, &rot_err, &limited);
    print_message(
        "q2 end %.4f: peak without barrier %.4f, with %.4f; final error %.2g m, %.2g rad\n", q2_end,
        q2_free, q2_held, pos_err, rot_err);
    assert_int_equal(limited, 1);
    assert_true(q2_held < q2_end);
    assert_true(q2_held >= q_goal[1]);
    assert_true(pos_err < 1e-4 && rot_err < 1e-3);
}

static void test_bad_input(void **st)
{
    const arm_tool tool = tool10();
    double a[3] = { 0.0, NAN, 0.0 }, tau[ARM_NJ], q[ARM_NJ];
    cartctl_gains g;
    cartctl_out o;
    int i;
    (void)st;
    cartctl_gains_default(&g);
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, Q_A, QD_A, NULL, a, NULL, tau, &o),
        CARTCTL_ERR_ARG);
    for (i = 0; i < ARM_NJ; i++)
        assert_true(tau[i] == 0.0);
    a[1] = 0.0;
    memcpy(q, Q_A, sizeof q);
    q[2] = INFINITY;
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, q, QD_A, NULL, a, NULL, tau, &o),
        CARTCTL_ERR_ARG);
    g.k_null = -1.0;
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, Q_A, QD_A, NULL, a, NULL, tau, &o),
        CARTCTL_ERR_ARG);
    cartctl_gains_default(&g);
    g.range_w_radps = -1.0;
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, Q_A, QD_A, NULL, a, NULL, tau, &o),
        CARTCTL_ERR_ARG);
    /* the cycle's entry wants the kinematics and an output */
    cartctl_gains_default(&g);
    {
        cartctl_state s;
        assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, Q_A, QD_A, &s), 0);
        tau[0] = 1.0;
        assert_int_equal(
            cartctl_torque_at(&arm_model_puma560, NULL, &g, Q_A, QD_A, NULL, a, NULL, tau, &o),
            CARTCTL_ERR_ARG);
        assert_true(tau[0] == 0.0);
        assert_int_equal(
            cartctl_torque_at(&arm_model_puma560, NULL, &g, Q_A, QD_A, &s, a, NULL, tau, NULL),
            CARTCTL_ERR_ARG);
    }
}

/* cartctl_torque_at (the cycle's entry) is cartctl_torque with the
 * kinematics given: the same torques and outputs, to the bit */
static void test_torque_at_is_torque(void **st)
{
    const arm_tool tool = tool10();
    const double a[3] = { 0.2, -0.1, 0.3 };
    double R_d[9], ta[ARM_NJ], tb[ARM_NJ];
    cartctl_gains g;
    cartctl_state s;
    cartctl_out oa, ob;
    (void)st;
    cartctl_gains_default(&g);
    rot_from_axis_angle(R_d, a, 0.3);
    assert_int_equal(cartctl_state_at(&arm_model_puma560, &tool, Q_A, QD_A, &s), 0);
    assert_int_equal(
        cartctl_torque_at(&arm_model_puma560, NULL, &g, Q_A, QD_A, &s, a, R_d, ta, &oa), 0);
    assert_int_equal(
        cartctl_torque(&arm_model_puma560, &tool, NULL, &g, Q_A, QD_A, NULL, a, R_d, tb, &ob), 0);
    assert_memory_equal(ta, tb, sizeof ta);
    assert_memory_equal(oa.qdd, ob.qdd, sizeof oa.qdd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jdot_qd_matches_fk),
        cmocka_unit_test(test_model_plant_gives_commanded_accel),
        cmocka_unit_test(test_closed_loop_tracks),
        cmocka_unit_test(test_damping_near_wrist_singularity),
        cmocka_unit_test(test_fast_path_matches_svd),
        cmocka_unit_test(test_inverse_wrist),
        cmocka_unit_test(test_wrist_closed_form),
        cmocka_unit_test(test_range_barrier),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_torque_at_is_torque),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* cartctl: operational-space computed torque (SPEC 2.2, the feedback
 * linearisation below eq. 6): tool acceleration -> qdd through a damped
 * SVD inverse of the Jacobian -> tau by RNE. See cartctl.h. */
#include "cartctl.h"

#include <math.h>
#include <string.h>

#include "jointctl.h"
#include "linalg.h"
#include "vec3.h"

#define JDOT_H_S 1e-4   /* central-difference step along qd, seconds */

void cartctl_gains_default(cartctl_gains *g)
{
    g->kp_rot = 100.0;
    g->kv_rot = 20.0;
    g->lambda_max = 0.003;
    g->sigma_band = 0.003;
    g->k_null = 5.0;
}

int cartctl_gains_valid(const cartctl_gains *g)
{
    return g && isfinite(g->kp_rot) && isfinite(g->kv_rot) && isfinite(g->lambda_max) &&
           isfinite(g->sigma_band) && isfinite(g->k_null) && g->kp_rot >= 0.0 && g->kv_rot >= 0.0 &&
           g->lambda_max >= 0.0 && g->sigma_band >= 0.0 && g->k_null >= 0.0;
}

static int vec_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

int cartctl_state_at(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                     const double qd[ARM_NJ], cartctl_state *s)
{
    if (!m || !q || !qd || !s || !vec_finite(q, ARM_NJ) || !vec_finite(qd, ARM_NJ))
        return -1;
    if (arm_fk_jacobian(m, tool, q, s->T, s->J) != 0)
        return -1;
    linalg_matvec(s->twist, s->J, qd, 6, ARM_NJ);
    return 0;
}

int cartctl_jdot_qd(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ],
                    const double qd[ARM_NJ], double jdqd[6])
{
    double qp[ARM_NJ], qm[ARM_NJ], Jp[36], Jm[36], vp[6], vm[6];
    int i;
    if (!m || !q || !qd || !jdqd || !vec_finite(q, ARM_NJ) || !vec_finite(qd, ARM_NJ))
        return -1;
    for (i = 0; i < ARM_NJ; i++) {
        qp[i] = q[i] + JDOT_H_S * qd[i];
        qm[i] = q[i] - JDOT_H_S * qd[i];
    }
    if (arm_jacobian(m, tool, qp, Jp) != 0 || arm_jacobian(m, tool, qm, Jm) != 0)
        return -1;
    linalg_matvec(vp, Jp, qd, 6, ARM_NJ);
    linalg_matvec(vm, Jm, qd, 6, ARM_NJ);
    for (i = 0; i < 6; i++)
        jdqd[i] = (vp[i] - vm[i]) / (2.0 * JDOT_H_S);
    return 0;
}

void cartctl_rot_error(const double R_d[9], const double R[9], double err[3])
{
    double Rt[9], E[9], axis[3], angle;
    rot_transpose(Rt, R);
    rot_mul(E, R_d, Rt);
    angle = rot_to_axis_angle(axis, E);
    vec3_scale(err, axis, angle);
}

/* lambda^2 of the damped inverse for the smallest singular value. */
static double damping_sq(const cartctl_gains *g, double s_min)
{
    double r;
    if (g->sigma_band <= 0.0 || s_min >= g->sigma_band)
        return 0.0;
    r = s_min / g->sigma_band;
    return g->lambda_max * g->lambda_max * (1.0 - r * r);
}

int cartctl_qdd(const arm_model *m, const arm_tool *tool, const cartctl_gains *g,
                const double q[ARM_NJ], const double qd[ARM_NJ], const cartctl_state *s_in,
                const double a_lin[3], const double R_d[9], cartctl_out *out)
{
    cartctl_state s_local;
    const cartctl_state *s = s_in;
    double U[36], sv[6], V[36], jdqd[6], rhs[6], y[6], Vtqd[6], lam2;
    int i, k;
    if (!out)
        return -1;
    memset(out, 0, sizeof *out);
    if (!cartctl_gains_valid(g) || !a_lin || !vec_finite(a_lin, 3) || (R_d && !vec_finite(R_d, 9)))
        return -1;
    if (!s) {
        if (cartctl_state_at(m, tool, q, qd, &s_local) != 0)
            return -1;
        s = &s_local;
    }
    if (cartctl_jdot_qd(m, tool, q, qd, jdqd) != 0)
        return -1;
    vec3_copy(out->a_cmd, a_lin);
    if (R_d) {
        double R[9];
        tf_rot(R, s->T);
        cartctl_rot_error(R_d, R, out->rot_err);
        for (i = 0; i < 3; i++)
            out->a_cmd[3 + i] = g->kp_rot * out->rot_err[i] - g->kv_rot * s->twist[3 + i];
    }
    for (i = 0; i < 6; i++)
        rhs[i] = out->a_cmd[i] - jdqd[i];
    linalg_svd(U, sv, V, s->J, 6, 6);
    out->sigma_min = sv[5];
    lam2 = damping_sq(g, sv[5]);
    out->lambda = sqrt(lam2);
    /* qdd = V diag(s/(s^2+l^2)) U^T rhs - k_null V diag(l^2/(s^2+l^2)) V^T qd */
    linalg_tmatvec(y, U, rhs, 6, 6);
    linalg_tmatvec(Vtqd, V, qd, 6, 6);
    for (k = 0; k < 6; k++) {
        const double den = sv[k] * sv[k] + lam2;
        y[k] = den > 0.0 ? (sv[k] * y[k] - g->k_null * lam2 * Vtqd[k]) / den : 0.0;
    }
    linalg_matvec(out->qdd, V, y, 6, 6);
    return vec_finite(out->qdd, ARM_NJ) ? 0 : -1;
}

int cartctl_torque(const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                   const cartctl_gains *g, const double q[ARM_NJ], const double qd[ARM_NJ],
                   const cartctl_state *s, const double a_lin[3], const double R_d[9],
                   double tau_Nm[ARM_NJ], cartctl_out *out)
{
    cartctl_out local;
    cartctl_out *o = out ? out : &local;
    if (!tau_Nm)
        return -1;
    memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
    if (cartctl_qdd(m, tool, g, q, qd, s, a_lin, R_d, o) != 0)
        return -1;
    if (arm_rne(m, q, qd, o->qdd, NULL, payload, tau_Nm) != 0) {
        memset(tau_Nm, 0, sizeof(double) * ARM_NJ);
        return -1;
    }
    o->saturated = jointctl_saturate(m, tau_Nm);
    return 0;
}

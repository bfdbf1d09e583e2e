/* arm_kin: forward kinematics, geometric Jacobian and closed-form inverse
 * kinematics of PUMA-type 6R arms (used by docs/method/carry.md §3 operational-space
 * control and §3 TDSD; model tables in arm_model.c).
 *
 * IK (Paul & Zhang 1986 geometry, standard DH): the wrist centre
 * p_w = p_6 - d6 z_6 fixes q1..q3. In the arm plane of frame 1 the wrist is
 * at X = a2 c2 + a3 c23 - d4 s23, Y = a2 s2 + a3 s23 + d4 c23, with the
 * lateral offset Z = d2 + d3, so r^2 = px^2 + py^2 = X^2 + Z^2 and
 * q1 = atan2(py, px) + atan2(Z, X). With L3 = |(a3, d4)|, beta = atan2(d4, a3)
 * and gamma = q3 + beta, the plane is a two-link arm (a2, L3):
 * cos gamma = (X^2 + Y^2 - a2^2 - L3^2) / (2 a2 L3). The wrist angles come
 * from R36 = R03^T R06 with z6 in frame 3 = (-c4 s5, -s4 s5, c5).
 */
#include "arm_kin.h"
#include "arm_puma_internal.h"
#include "linalg.h"
#include "vec3.h"
#include <math.h>
#include <stddef.h>
#include <string.h>

#define PI 3.14159265358979323846
#define TWO_PI (2.0 * PI)
#define IK_REACH_EPS 1e-12 /* relative slack on the reach tests */

static const char *const branch_names[ARM_IK_NBRANCH] = {
    "left-up-noflip", "right-up-noflip", "left-down-noflip", "right-down-noflip",
    "left-up-flip",   "right-up-flip",   "left-down-flip",   "right-down-flip",
};

const char *arm_ik_branch_name(int b)
{
    return (b >= 0 && b < ARM_IK_NBRANCH) ? branch_names[b] : "invalid";
}

int arm_ik_branch_from_name(const char *name)
{
    int b;
    if (!name)
        return ARM_KIN_ERR_ARG;
    for (b = 0; b < ARM_IK_NBRANCH; b++)
        if (strcmp(name, branch_names[b]) == 0)
            return b;
    return ARM_KIN_ERR_NO_BRANCH;
}

/* T = T6 T_flange_tool. A tool that only moves the point (arm_tool_offset,
 * every tool of the cell) costs 9 products instead of a 4x4 product. */
static void flange_to_tool(const arm_tool *tool, const double T6[16], double T[16])
{
    const double *X = tool ? tool->T_flange_tool : NULL;
    int r;
    if (!X) {
        memcpy(T, T6, 16 * sizeof T[0]);
        return;
    }
    if (!(X[0] == 1.0 && X[5] == 1.0 && X[10] == 1.0 && X[1] == 0.0 && X[2] == 0.0 && X[4] == 0.0 &&
          X[6] == 0.0 && X[8] == 0.0 && X[9] == 0.0 && X[12] == 0.0 && X[13] == 0.0 &&
          X[14] == 0.0 && X[15] == 1.0)) {
        tf_mul(T, T6, X);
        return;
    }
    memcpy(T, T6, 16 * sizeof T[0]);
    for (r = 0; r < 12; r += 4)
        T[r + 3] += T6[r] * X[3] + T6[r + 1] * X[7] + T6[r + 2] * X[11];
}

int arm_fk(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double T[16])
{
    arm_joint_cs cs;
    double T6[16];
    double *Ti = tool ? T6 : T; /* no tool: build the pose in the caller's T */
    int i;
    if (!T || arm_joint_cs_eval(m, q, &cs) != 0)
        return ARM_KIN_ERR_ARG;
    if (m->structure == ARM_STRUCTURE_PUMA) {
        double F[ARM_NJ + 1][16];
        arm_puma_chain(m, &cs, F);
        flange_to_tool(tool, F[ARM_NJ], T);
        return 0;
    }
    arm_base_frame(m, Ti);
    /* in place: arm_dh_compose works row by row */
    for (i = 0; i < ARM_NJ; i++)
        arm_dh_compose(m, i, cs.c[i], cs.s[i], Ti, Ti);
    if (tool)
        flange_to_tool(tool, T6, T);
    return 0;
}

/* The Jacobian's columns from the link frames F (ARM_NJ + 1 transforms of
 * 16, one after the other) and the tool pose T. */
static void jacobian_of_frames(const double *F, const double T[16], double J[36])
{
    double p_e[3], z[3], o[3], r[3], v[3];
    int i;
    tf_pos(p_e, T);
    for (i = 0; i < ARM_NJ; i++) {
        /* joint i+1 turns about z of frame i, through its origin */
        vec3_set(z, F[16 * i + 2], F[16 * i + 6], F[16 * i + 10]);
        tf_pos(o, F + 16 * i);
        vec3_sub(r, p_e, o);
        vec3_cross(v, z, r);
        J[0 * 6 + i] = v[0];
        J[1 * 6 + i] = v[1];
        J[2 * 6 + i] = v[2];
        J[3 * 6 + i] = z[0];
        J[4 * 6 + i] = z[1];
        J[5 * 6 + i] = z[2];
    }
}

int arm_fk_jacobian(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double T[16],
                    double J[36])
{
    double F[ARM_NJ + 1][16];
    if (!m || !T || !J || arm_link_frames(m, q, F) != 0)
        return ARM_KIN_ERR_ARG;
    flange_to_tool(tool, F[ARM_NJ], T);
    if (m->structure == ARM_STRUCTURE_PUMA)
        arm_puma_jacobian((const double(*)[16])F, T, J);
    else
        jacobian_of_frames(F[0], T, J);
    return 0;
}

int arm_kin_eval(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], arm_kin_pass *k)
{
    int i;
    if (!k)
        return ARM_KIN_ERR_ARG;
    if (!m || arm_joint_cs_eval(m, q, &k->cs) != 0) {
        memset(k, 0, sizeof *k);
        return ARM_KIN_ERR_ARG;
    }
    k->m = m;
    k->puma = m->structure == ARM_STRUCTURE_PUMA;
    if (k->puma) {
        arm_puma_chain(m, &k->cs, k->F);
        flange_to_tool(tool, k->F[ARM_NJ], k->T);
        arm_puma_jacobian((const double(*)[16])k->F, k->T, k->J);
        return 0;
    }
    arm_base_frame(m, k->F[0]);
    for (i = 0; i < ARM_NJ; i++)
        arm_dh_compose(m, i, k->cs.c[i], k->cs.s[i], k->F[i], k->F[i + 1]);
    flange_to_tool(tool, k->F[ARM_NJ], k->T);
    jacobian_of_frames(k->F[0], k->T, k->J);
    return 0;
}

/* Why analytic: the central difference of J along qd cost two more
 * kinematics passes per cycle (and carried an O(h^2) error). The PUMA's
 * is the RNE's outward recursion with qdd = 0 and no gravity, in link
 * coordinates (arm_puma_jdot_qd, docs/method/puma.md §3). The general
 * one, in base coordinates: frame i's z axis and origin turn with link i,
 * zdot_i = w_i x z_i and odot_{i+1} = odot_i + w_{i+1} x (o_{i+1} - o_i)
 * (o_i lies on joint i+1's axis, so it moves with link i+1 as well as
 * with link i). */
/* The general sum; apart so that its locals are not on the PUMA path's
 * stack (the Cartesian cycle's deepest). */
static void jdot_general(const arm_kin_pass *k, const double qd[ARM_NJ], double jdqd[6])
{
    double w[3] = { 0, 0, 0 }, odot[3] = { 0, 0, 0 }, pdot[3] = { 0, 0, 0 };
    double p_e[3];
    int i, j;
    for (j = 0; j < 3; j++)
        for (i = 0; i < ARM_NJ; i++)
            pdot[j] += k->J[j * 6 + i] * qd[i];
    tf_pos(p_e, k->T);
    for (i = 0; i < ARM_NJ; i++) {
        const double *Fi = k->F[i];
        const double z[3] = { Fi[2], Fi[6], Fi[10] };
        const double o[3] = { Fi[3], Fi[7], Fi[11] };
        double zdot[3], r[3], dv[3], a[3], b[3];
        vec3_cross(zdot, w, z);
        vec3_sub(r, p_e, o);
        vec3_sub(dv, pdot, odot);
        vec3_cross(a, zdot, r);
        vec3_cross(b, z, dv);
        for (j = 0; j < 3; j++) {
            jdqd[j] += qd[i] * (a[j] + b[j]);
            jdqd[3 + j] += qd[i] * zdot[j];
            w[j] += z[j] * qd[i]; /* now w_{i+1} */
        }
        if (i < ARM_NJ - 1) {
            const double *Fn = k->F[i + 1];
            const double step[3] = { Fn[3] - o[0], Fn[7] - o[1], Fn[11] - o[2] };
            double ws[3];
            vec3_cross(ws, w, step);
            vec3_add(odot, odot, ws);
        }
    }
}

int arm_kin_jdot_qd(const arm_kin_pass *k, const double qd[ARM_NJ], double jdqd[6])
{
    if (!jdqd)
        return ARM_KIN_ERR_ARG;
    memset(jdqd, 0, 6 * sizeof jdqd[0]);
    if (!k || !k->m || !qd || !linalg_all_finite(qd, ARM_NJ))
        return ARM_KIN_ERR_ARG;
    if (k->puma)
        arm_puma_jdot_qd(k->m, &k->cs, k->F[ARM_NJ], k->T, qd, jdqd);
    else
        jdot_general(k, qd, jdqd);
    return 0;
}

int arm_jacobian(const arm_model *m, const arm_tool *tool, const double q[ARM_NJ], double J[36])
{
    double T[16];
    return arm_fk_jacobian(m, tool, q, T, J);
}

/* ---- inverse kinematics ------------------------------------------------- */

static int ik_geometry_supported(const arm_model *m)
{
    static const double alpha[ARM_NJ] = { PI / 2, 0, -PI / 2, PI / 2, -PI / 2, 0 };
    const double tol = 1e-9;
    int i;
    for (i = 0; i < ARM_NJ; i++)
        if (fabs(m->alpha_rad[i] - alpha[i]) > tol)
            return 0;
    if (fabs(m->a_m[0]) > tol || fabs(m->a_m[3]) > tol || fabs(m->a_m[4]) > tol ||
        fabs(m->a_m[5]) > tol || fabs(m->d_m[4]) > tol)
        return 0;
    /* a two-link arm plane needs both lengths */
    return m->a_m[1] > tol && hypot(m->a_m[2], m->d_m[3]) > tol;
}

static double wrap_pi(double a)
{
    while (a > PI)
        a -= TWO_PI;
    while (a <= -PI)
        a += TWO_PI;
    return a;
}

/* Choose q or q +- 2 pi so that it lies in the joint range if possible. */
static double wrap_into_range(double q, double lo, double hi)
{
    int k;
    q = wrap_pi(q);
    if (q >= lo && q <= hi)
        return q;
    for (k = 1; k <= 2; k++) {
        if (q + k * TWO_PI >= lo && q + k * TWO_PI <= hi)
            return q + k * TWO_PI;
        if (q - k * TWO_PI >= lo && q - k * TWO_PI <= hi)
            return q - k * TWO_PI;
    }
    return q;
}

/* Rotation part of A_1 A_2 A_3 (frame 0 -> frame 3). */
static void rot_03(const arm_model *m, const double q[3], double R03[9])
{
    double A[16], T[16], Tn[16];
    int i;
    tf_identity(T);
    for (i = 0; i < 3; i++) {
        arm_dh_transform(m, i, q[i], A);
        tf_mul(Tn, T, A);
        memcpy(T, Tn, sizeof T);
    }
    tf_rot(R03, T);
}

/* q4..q6 from R36 for both wrist branches (index 0 noflip, 1 flip). */
static void ik_wrist(const arm_model *m, const double R36[9], double q456[2][3])
{
    const double r13 = R36[2], r23 = R36[5], r33 = R36[8];
    const double s5 = hypot(r13, r23);
    double t4, t5, A4[16], A5[16], T45[16], R35[9], R56[9];
    int w;
    if (s5 > 1e-12) {
        t4 = atan2(-r23, -r13);
        t5 = atan2(s5, r33);
    } else {
        /* wrist singular: only q4 + q6 is defined; put it all in q6 */
        t4 = 0.0;
        t5 = atan2(0.0, r33);
    }
    if (cos(t4) < 0.0) {
        t4 = wrap_pi(t4 + PI);
        t5 = -t5;
    }
    for (w = 0; w < 2; w++) {
        const double q4 = (w ? wrap_pi(t4 + PI) : t4) - m->theta_offset_rad[3];
        const double q5 = (w ? -t5 : t5) - m->theta_offset_rad[4];
        double t6;
        arm_dh_transform(m, 3, q4, A4);
        arm_dh_transform(m, 4, q5, A5);
        tf_mul(T45, A4, A5);
        tf_rot(R35, T45);
        rot_tmul(R56, R35, R36);
        /* R56 = Rz(theta6) since alpha6 = 0 */
        t6 = atan2(R56[3], R56[0]);
        q456[w][0] = q4;
        q456[w][1] = q5;
        q456[w][2] = t6 - m->theta_offset_rad[5];
    }
}

/* Kept whole (about 90 lines): the closed-form solution is one sequence
 * (wrist centre, q1 for both shoulders, q2-q3 for both elbows, q4-q6 for
 * both wrists, then the eight branches ranked) whose steps share the
 * wrist centre and the branch tables; the wrist part is already apart
 * (ik_wrist above). */
int arm_ik(const arm_model *m, const arm_tool *tool, const double T[16], arm_ik_result *out)
{
    double T6[16], Tinv[16], R06[9], pw[3];
    double a2, a3, d4, L3, beta, Z, Y, r2, reach2;
    int s, e, w, b;

    if (!m || !T || !out || !linalg_all_finite(T, 16))
        return ARM_KIN_ERR_ARG;
    if (!ik_geometry_supported(m))
        return ARM_KIN_ERR_GEOMETRY;
    memset(out, 0, sizeof *out);

    if (tool) {
        tf_inverse(Tinv, tool->T_flange_tool);
        tf_mul(T6, T, Tinv);
    } else {
        memcpy(T6, T, sizeof T6);
    }
    tf_rot(R06, T6);
    /* wrist centre in frame 0 */
    pw[0] = T6[3] - m->d_m[5] * T6[2];
    pw[1] = T6[7] - m->d_m[5] * T6[6];
    pw[2] = T6[11] - m->d_m[5] * T6[10] - m->base_height_m;

    a2 = m->a_m[1];
    a3 = m->a_m[2];
    d4 = m->d_m[3];
    L3 = hypot(a3, d4);
    beta = atan2(d4, a3);
    Z = m->d_m[1] + m->d_m[2];
    Y = pw[2] - m->d_m[0];
    r2 = pw[0] * pw[0] + pw[1] * pw[1];

    out->n_valid = 0;
    for (s = 0; s < 2; s++) {
        /* s = 0 left (X < 0), s = 1 right (X >= 0) */
        double X2 = r2 - Z * Z, X, q123[2][3], D;
        int reach = 1;
        if (X2 < -IK_REACH_EPS * (r2 + Z * Z + 1.0))
            reach = 0;
        X = sqrt(X2 > 0.0 ? X2 : 0.0);
        if (s == 0)
            X = -X;
        reach2 = X * X + Y * Y;
        D = (reach2 - a2 * a2 - L3 * L3) / (2.0 * a2 * L3);
        if (fabs(D) > 1.0 + IK_REACH_EPS * 1e3)
            reach = 0;
        if (D > 1.0)
            D = 1.0;
        if (D < -1.0)
            D = -1.0;
        for (e = 0; e < 2; e++) {
            /* elbow up iff sign(X) * (-sin gamma) > 0 */
            const double g_abs = acos(D);
            const double gamma = (s == 1) == (e == 0) ? -g_abs : g_abs;
            double R03[9], R36[9], q456[2][3];
            const double t1 = atan2(pw[1], pw[0]) + atan2(Z, X);
            const double t2 = atan2(Y, X) - atan2(L3 * sin(gamma), a2 + L3 * cos(gamma));
            const double t3 = gamma - beta;
            q123[e][0] = t1 - m->theta_offset_rad[0];
            q123[e][1] = t2 - m->theta_offset_rad[1];
            q123[e][2] = t3 - m->theta_offset_rad[2];
            rot_03(m, q123[e], R03);
            rot_tmul(R36, R03, R06);
            ik_wrist(m, R36, q456);
            for (w = 0; w < 2; w++) {
                arm_ik_branch *br;
                int j;
                b = s | (e << 1) | (w << 2);
                br = &out->branch[b];
                for (j = 0; j < 3; j++) {
                    br->q_rad[j] = q123[e][j];
                    br->q_rad[j + 3] = q456[w][j];
                }
                for (j = 0; j < ARM_NJ; j++)
                    br->q_rad[j] = wrap_into_range(br->q_rad[j], m->q_min_rad[j], m->q_max_rad[j]);
                br->status = ARM_IK_OK;
                br->limit_bits = 0;
                if (!reach) {
                    br->status = ARM_IK_UNREACHABLE;
                    continue;
                }
                br->limit_bits = arm_q_outside_limits(m, br->q_rad);
                if (br->limit_bits)
                    br->status |= ARM_IK_OUTSIDE_LIMITS;
                else
                    out->n_valid++;
            }
        }
    }
    out->unreachable = 1;
    for (b = 0; b < ARM_IK_NBRANCH; b++)
        if (!(out->branch[b].status & ARM_IK_UNREACHABLE))
            out->unreachable = 0;
    return 0;
}

int arm_ik_nearest(const arm_ik_result *r, const double q_ref[ARM_NJ])
{
    int b, j, best = ARM_KIN_ERR_NO_BRANCH;
    double best_d = 0.0;
    if (!r || arm_q_finite(q_ref) != 0)
        return ARM_KIN_ERR_ARG;
    for (b = 0; b < ARM_IK_NBRANCH; b++) {
        double d = 0.0;
        if (r->branch[b].status != ARM_IK_OK)
            continue;
        for (j = 0; j < ARM_NJ; j++) {
            const double dj = fabs(r->branch[b].q_rad[j] - q_ref[j]);
            if (dj > d)
                d = dj;
        }
        if (best < 0 || d < best_d) {
            best = b;
            best_d = d;
        }
    }
    return best;
}

int arm_ik_branch_of(const arm_model *m, const double q[ARM_NJ])
{
    double t[ARM_NJ], X, gamma;
    int j, s, e, w;
    if (!m || arm_q_finite(q) != 0)
        return ARM_KIN_ERR_ARG;
    for (j = 0; j < ARM_NJ; j++)
        t[j] = q[j] + m->theta_offset_rad[j];
    X = m->a_m[1] * cos(t[1]) + m->a_m[2] * cos(t[1] + t[2]) - m->d_m[3] * sin(t[1] + t[2]);
    gamma = t[2] + atan2(m->d_m[3], m->a_m[2]);
    s = X >= 0.0;
    e = !((s ? 1.0 : -1.0) * -sin(gamma) > 0.0);
    w = cos(t[3]) < 0.0;
    return s | (e << 1) | (w << 2);
}

/* arm_dyn: rigid-body dynamics of the 6R arm models (SPEC.md §2.2 computed
 * torque / operational-space control, §7 gravity-compensated hold).
 *
 * - arm_rne: recursive Newton-Euler in link frames for standard DH (Luh,
 *   Walker & Paul 1980; same recursion as Corke's rne_dh). Base acceleration
 *   -g stands in for gravity.
 * - arm_mass_matrix: composite rigid body algorithm in base coordinates:
 *   with C_i = links i..6 (mass m_c, COM c_c, inertia I_c about c_c), a unit
 *   rate of joint i gives C_i the momentum h = m_c z_i x (c_c - o_i),
 *   L = I_c z_i, and M_ji = z_j . (L + (c_c - o_j) x h) for j <= i.
 * A payload is merged into link 6 (mass, COM, parallel-axis inertia).
 */
#include "arm_dyn.h"
#include "vec3.h"
#include <math.h>
#include <stddef.h>
#include <string.h>

/* Mass properties of one link, possibly merged with the payload. */
typedef struct link_mass {
    double m;
    double c[3];
    double I[9];
} link_mass;

static int vec_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

int arm_payload_point(arm_payload *p, double mass_kg, const double com_m[3])
{
    if (!p || !com_m || !isfinite(mass_kg) || mass_kg < 0.0 || !vec_finite(com_m, 3))
        return -1;
    memset(p, 0, sizeof *p);
    p->mass_kg = mass_kg;
    vec3_copy(p->com_m, com_m);
    return 0;
}

static int payload_valid(const arm_payload *p)
{
    return !p || (isfinite(p->mass_kg) && p->mass_kg >= 0.0 && vec_finite(p->com_m, 3)
                  && vec_finite(p->inertia_kgm2, 9));
}

/* I += m (|r|^2 E - r r^T): inertia of mass m at offset r (parallel axis). */
static void add_parallel_axis(double I[9], double m, const double r[3])
{
    const double rr = vec3_dot(r, r);
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            I[3 * i + j] += m * ((i == j ? rr : 0.0) - r[i] * r[j]);
}

/* Merge body b into a (both given in the same frame). */
static void merge_mass(link_mass *a, const link_mass *b)
{
    const double m = a->m + b->m;
    double c[3], ra[3], rb[3];
    int k;
    if (m <= 0.0)
        return;
    for (k = 0; k < 3; k++)
        c[k] = (a->m * a->c[k] + b->m * b->c[k]) / m;
    vec3_sub(ra, a->c, c);
    vec3_sub(rb, b->c, c);
    add_parallel_axis(a->I, a->m, ra);
    for (k = 0; k < 9; k++)
        a->I[k] += b->I[k];
    add_parallel_axis(a->I, b->m, rb);
    a->m = m;
    vec3_copy(a->c, c);
}

static void link_masses(const arm_model *m, const arm_payload *p, link_mass L[ARM_NJ])
{
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        L[i].m = m->mass_kg[i];
        vec3_copy(L[i].c, m->com_m[i]);
        memcpy(L[i].I, m->inertia_kgm2[i], sizeof L[i].I);
    }
    if (p && p->mass_kg > 0.0) {
        link_mass pl;
        pl.m = p->mass_kg;
        vec3_copy(pl.c, p->com_m);
        memcpy(pl.I, p->inertia_kgm2, sizeof pl.I);
        merge_mass(&L[ARM_NJ - 1], &pl);
    }
}

int arm_rne(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
            const double qdd[ARM_NJ], const double gravity_mps2[3],
            const arm_payload *payload, double tau_Nm[ARM_NJ])
{
    static const double z0[3] = { 0.0, 0.0, 1.0 };
    link_mass L[ARM_NJ];
    double R[ARM_NJ][9], ps[ARM_NJ][3];
    double w[3] = { 0, 0, 0 }, wd[3] = { 0, 0, 0 }, vd[3];
    double F[ARM_NJ][3], N[ARM_NJ][3];
    double f[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 };
    int i;

    if (!m || !q || !qd || !qdd || !tau_Nm || !vec_finite(q, ARM_NJ) || !vec_finite(qd, ARM_NJ)
        || !vec_finite(qdd, ARM_NJ) || (gravity_mps2 && !vec_finite(gravity_mps2, 3))
        || !payload_valid(payload))
        return -1;
    link_masses(m, payload, L);
    if (gravity_mps2)
        vec3_scale(vd, gravity_mps2, -1.0);
    else
        vec3_set(vd, 0.0, 0.0, ARM_GRAVITY_MPS2);

    /* outward: velocities and accelerations of frame i, in frame i */
    for (i = 0; i < ARM_NJ; i++) {
        double A[16], t[3], u[3], wz[3], vc[3];
        arm_dh_transform(m, i, q[i], A);
        tf_rot(R[i], A);
        vec3_set(ps[i], m->a_m[i], m->d_m[i] * sin(m->alpha_rad[i]),
                 m->d_m[i] * cos(m->alpha_rad[i]));
        /* wd_i = R^T (wd + z0 qdd + w x z0 qd) */
        vec3_cross(wz, w, z0);
        vec3_axpy(t, wd, qdd[i], z0);
        vec3_axpy(t, t, qd[i], wz);
        rot_tapply(wd, R[i], t);
        /* w_i = R^T (w + z0 qd) */
        vec3_axpy(t, w, qd[i], z0);
        rot_tapply(w, R[i], t);
        /* vd_i = wd x p* + w x (w x p*) + R^T vd */
        rot_tapply(t, R[i], vd);
        vec3_cross(u, wd, ps[i]);
        vec3_add(t, t, u);
        vec3_cross(u, w, ps[i]);
        vec3_cross(u, w, u);
        vec3_add(vd, t, u);
        /* COM acceleration, force and moment */
        vec3_cross(vc, wd, L[i].c);
        vec3_cross(u, w, L[i].c);
        vec3_cross(u, w, u);
        vec3_add(vc, vc, u);
        vec3_add(vc, vc, vd);
        vec3_scale(F[i], vc, L[i].m);
        {
            double Iw[3], Iwd[3];
            int k;
            for (k = 0; k < 3; k++) {
                Iw[k] = L[i].I[3 * k] * w[0] + L[i].I[3 * k + 1] * w[1] + L[i].I[3 * k + 2] * w[2];
                Iwd[k] = L[i].I[3 * k] * wd[0] + L[i].I[3 * k + 1] * wd[1]
                         + L[i].I[3 * k + 2] * wd[2];
            }
            vec3_cross(u, w, Iw);
            vec3_add(N[i], Iwd, u);
        }
    }
    /* inward: forces and moments exerted on link i by link i-1, in frame i */
    for (i = ARM_NJ - 1; i >= 0; i--) {
        double t[3], u[3], pc[3], zi[3];
        if (i < ARM_NJ - 1) {
            double Rf[3], Rn[3];
            rot_apply(Rf, R[i + 1], f);
            rot_apply(Rn, R[i + 1], n);
            vec3_cross(u, ps[i], Rf);
            vec3_add(n, Rn, u);
            vec3_copy(f, Rf);
        }
        vec3_add(pc, ps[i], L[i].c);
        vec3_cross(t, pc, F[i]);
        vec3_add(n, n, t);
        vec3_add(n, n, N[i]);
        vec3_add(f, f, F[i]);
        rot_tapply(zi, R[i], z0);
        tau_Nm[i] = vec3_dot(n, zi);
    }
    return 0;
}

int arm_gravity(const arm_model *m, const double q[ARM_NJ], const double gravity_mps2[3],
                const arm_payload *payload, double tau_Nm[ARM_NJ])
{
    static const double zero[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    return arm_rne(m, q, zero, zero, gravity_mps2, payload, tau_Nm);
}

int arm_coriolis(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
                 const arm_payload *payload, double c_Nm[ARM_NJ])
{
    static const double zero[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    static const double no_gravity[3] = { 0, 0, 0 };
    return arm_rne(m, q, qd, zero, no_gravity, payload, c_Nm);
}

/* out = R I R^T */
static void rot_inertia(double out[9], const double R[9], const double I[9])
{
    double RI[9], Rt[9];
    rot_mul(RI, R, I);
    rot_transpose(Rt, R);
    rot_mul(out, RI, Rt);
}

int arm_mass_matrix(const arm_model *m, const double q[ARM_NJ],
                    const arm_payload *payload, double M[36])
{
    double F[ARM_NJ + 1][16];
    link_mass L[ARM_NJ], comp;
    int i, j;

    if (!m || !M || !payload_valid(payload) || arm_link_frames(m, q, F) != 0)
        return -1;
    link_masses(m, payload, L);
    memset(&comp, 0, sizeof comp);
    for (i = ARM_NJ - 1; i >= 0; i--) {
        link_mass lb;
        double R[9], o[3], z[3], r[3], v[3], h[3], Lm[3];
        /* link i+1 (index i) in base coordinates */
        tf_rot(R, F[i + 1]);
        tf_pos(o, F[i + 1]);
        lb.m = L[i].m;
        rot_apply(lb.c, R, L[i].c);
        vec3_add(lb.c, lb.c, o);
        rot_inertia(lb.I, R, L[i].I);
        if (comp.m <= 0.0)
            comp = lb;
        else
            merge_mass(&comp, &lb);
        /* joint i+1: axis z of frame i through its origin */
        vec3_set(z, F[i][2], F[i][6], F[i][10]);
        tf_pos(o, F[i]);
        vec3_sub(r, comp.c, o);
        vec3_cross(v, z, r);
        vec3_scale(h, v, comp.m);
        rot_apply(Lm, comp.I, z);
        for (j = 0; j <= i; j++) {
            double zj[3], oj[3], rj[3], t[3];
            vec3_set(zj, F[j][2], F[j][6], F[j][10]);
            tf_pos(oj, F[j]);
            vec3_sub(rj, comp.c, oj);
            vec3_cross(t, rj, h);
            vec3_add(t, t, Lm);
            M[j * 6 + i] = M[i * 6 + j] = vec3_dot(zj, t);
        }
    }
    return 0;
}

int arm_spd_solve6(const double M[36], const double b[ARM_NJ], double x[ARM_NJ])
{
    double Lc[36], y[ARM_NJ];
    int i, j, k;
    for (j = 0; j < ARM_NJ; j++) {
        double s = M[j * 6 + j];
        for (k = 0; k < j; k++)
            s -= Lc[j * 6 + k] * Lc[j * 6 + k];
        if (!(s > 0.0))
            return -2;
        Lc[j * 6 + j] = sqrt(s);
        for (i = j + 1; i < ARM_NJ; i++) {
            double t = M[i * 6 + j];
            for (k = 0; k < j; k++)
                t -= Lc[i * 6 + k] * Lc[j * 6 + k];
            Lc[i * 6 + j] = t / Lc[j * 6 + j];
        }
    }
    for (i = 0; i < ARM_NJ; i++) {
        double t = b[i];
        for (k = 0; k < i; k++)
            t -= Lc[i * 6 + k] * y[k];
        y[i] = t / Lc[i * 6 + i];
    }
    for (i = ARM_NJ - 1; i >= 0; i--) {
        double t = y[i];
        for (k = i + 1; k < ARM_NJ; k++)
            t -= Lc[k * 6 + i] * x[k];
        x[i] = t / Lc[i * 6 + i];
    }
    return 0;
}

int arm_forward_dynamics(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
                         const double tau_Nm[ARM_NJ], const double gravity_mps2[3],
                         const arm_payload *payload, double qdd[ARM_NJ])
{
    static const double zero[ARM_NJ] = { 0, 0, 0, 0, 0, 0 };
    double M[36], h[ARM_NJ], rhs[ARM_NJ];
    int i;
    if (!tau_Nm || !qdd || !vec_finite(tau_Nm, ARM_NJ))
        return -1;
    if (arm_rne(m, q, qd, zero, gravity_mps2, payload, h) != 0
        || arm_mass_matrix(m, q, payload, M) != 0)
        return -1;
    for (i = 0; i < ARM_NJ; i++)
        rhs[i] = tau_Nm[i] - h[i];
    return arm_spd_solve6(M, rhs, qdd);
}

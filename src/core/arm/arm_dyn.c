/* arm_dyn: rigid-body dynamics of the 6R arm models (docs/method/carry.md §3 computed
 * torque / operational-space control, §7 gravity-compensated hold).
 *
 * - arm_rne: recursive Newton-Euler in link frames for standard DH (Luh,
 *   Walker & Paul 1980; same recursion as Corke's rne_dh). Base acceleration
 *   -g stands in for gravity.
 * - arm_mass_matrix: composite rigid body algorithm in joint frames: the
 *   composite C_i = links i..6 is held in frame i-1 (mass m, first moment
 *   h = m c, inertia I about the frame origin), where joint i turns about z
 *   through the origin. A unit rate of joint i gives C_i the momentum
 *   n = I z, f = z x h; M_ii = n_z, and carrying (n, f) inward frame by
 *   frame (f' = R f, n' = R n + p x f') gives M_ji = n'_z for j < i.
 * Both use R_i = Rz(theta_i) Rx(alpha_i) as two plane rotations (cos/sin of
 * theta once per call, of alpha from the table) rather than 3x3 products.
 * A payload is merged into link 6 (mass, COM, parallel-axis inertia).
 */
#include "arm_dyn.h"
#include "arm_puma_internal.h"
#include "linalg.h"
#include "trig.h"
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

int arm_payload_point(arm_payload *p, double mass_kg, const double com_m[3])
{
    if (!p || !com_m || !isfinite(mass_kg) || mass_kg < 0.0 || !linalg_all_finite(com_m, 3))
        return ARM_DYN_ERR_ARG;
    memset(p, 0, sizeof *p);
    p->mass_kg = mass_kg;
    vec3_copy(p->com_m, com_m);
    return 0;
}

static int payload_valid(const arm_payload *p)
{
    return !p || (isfinite(p->mass_kg) && p->mass_kg >= 0.0 && linalg_all_finite(p->com_m, 3) &&
                  linalg_all_finite(p->inertia_kgm2, 9));
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

/* Mass properties of link i as the recursions read them (arm_link_ref,
 * arm_puma_internal.h): the model's own numbers, except link 6 when a
 * payload is merged into it (then they point into *merged). Pointers, not
 * copies: most calls carry no payload. */
typedef arm_link_ref link_ref;

static void link_refs(const arm_model *m, const arm_payload *p, link_mass *merged,
                      link_ref L[ARM_NJ])
{
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        L[i].m = m->mass_kg[i];
        L[i].c = m->com_m[i];
        L[i].I = m->inertia_kgm2[i];
    }
    if (p && p->mass_kg > 0.0) {
        link_mass pl;
        const int l = ARM_NJ - 1;
        merged->m = m->mass_kg[l];
        vec3_copy(merged->c, m->com_m[l]);
        memcpy(merged->I, m->inertia_kgm2[l], sizeof merged->I);
        pl.m = p->mass_kg;
        vec3_copy(pl.c, p->com_m);
        memcpy(pl.I, p->inertia_kgm2, sizeof pl.I);
        merge_mass(merged, &pl);
        L[l].m = merged->m;
        L[l].c = merged->c;
        L[l].I = merged->I;
    }
}

/* out = R_i v, R_i = Rz(theta) Rx(alpha): turn (y, z) by alpha, then
 * (x, y) by theta; 8 multiplications instead of 9 and no matrix. out may
 * be v. */
static inline void dh_rot(const arm_model *m, int i, const arm_joint_cs *cs, const double v[3],
                          double out[3])
{
    const double ca = m->cos_alpha[i], sa = m->sin_alpha[i], ct = cs->c[i], st = cs->s[i];
    const double x = v[0], y = ca * v[1] - sa * v[2];
    out[2] = sa * v[1] + ca * v[2];
    out[0] = ct * x - st * y;
    out[1] = st * x + ct * y;
}

/* out = R_i^T v: the same two plane rotations, backwards; out may be v. */
static inline void dh_rot_t(const arm_model *m, int i, const arm_joint_cs *cs, const double v[3],
                            double out[3])
{
    const double ca = m->cos_alpha[i], sa = m->sin_alpha[i], ct = cs->c[i], st = cs->s[i];
    const double x = ct * v[0] + st * v[1], y = ct * v[1] - st * v[0];
    out[0] = x;
    out[1] = ca * y + sa * v[2];
    out[2] = ca * v[2] - sa * y;
}

/* p*_i: origin of frame i seen from frame i-1, in frame i coordinates
 * (R_i^T (a ct, a st, d) = (a, d sa, d ca), free of theta). */
static inline void dh_pstar(const arm_model *m, int i, double ps[3])
{
    vec3_set(ps, m->a_m[i], m->d_m[i] * m->sin_alpha[i], m->d_m[i] * m->cos_alpha[i]);
}

/* RNE with the joint trig already evaluated and the inputs validated.
 * Centripetal terms use w x (w x p) = w (w . p) - p |w|^2 (one dot product
 * instead of two cross products), and the inward moment is taken as
 * p* x f + c x F after f is summed (two cross products instead of three). */
static void rne_cs(const arm_model *m, const arm_joint_cs *cs, const link_ref L[ARM_NJ],
                   const double qd[ARM_NJ], const double qdd[ARM_NJ], const double g[3],
                   double tau_Nm[ARM_NJ])
{
    /* p*_i is recomputed inward (3 products) rather than kept: 144 bytes
     * less on the joint cycle's stack */
    double ps[3], F[ARM_NJ][3], N[ARM_NJ][3];
    double w[3] = { 0, 0, 0 }, wd[3] = { 0, 0, 0 }, vd[3], f[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 };
    int i, k;

    vec3_scale(vd, g, -1.0);
    /* outward: velocities and accelerations of frame i, in frame i */
    for (i = 0; i < ARM_NJ; i++) {
        /* locals, so the stores into F, N and vd need not reload them */
        const double mi = L[i].m, *c = L[i].c, *I = L[i].I;
        const double I0 = I[0], I1 = I[1], I2 = I[2], I3 = I[3], I4 = I[4], I5 = I[5];
        const double I6 = I[6], I7 = I[7], I8 = I[8];
        double t[3], u[3], Iw[3], ww, wp, wc;
        dh_pstar(m, i, ps);
        /* wd_i = R^T (wd + z0 qdd + w x z0 qd), w x z0 = (w1, -w0, 0) */
        t[0] = wd[0] + w[1] * qd[i];
        t[1] = wd[1] - w[0] * qd[i];
        t[2] = wd[2] + qdd[i];
        dh_rot_t(m, i, cs, t, wd);
        /* w_i = R^T (w + z0 qd) */
        w[2] += qd[i];
        dh_rot_t(m, i, cs, w, w);
        ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        /* vd_i = R^T vd + wd x p* + w x (w x p*) */
        dh_rot_t(m, i, cs, vd, vd);
        wp = w[0] * ps[0] + w[1] * ps[1] + w[2] * ps[2];
        vec3_cross(u, wd, ps);
        for (k = 0; k < 3; k++)
            vd[k] += u[k] + w[k] * wp - ps[k] * ww;
        /* F = m (vd + wd x c + w x (w x c)) */
        wc = w[0] * c[0] + w[1] * c[1] + w[2] * c[2];
        vec3_cross(u, wd, c);
        for (k = 0; k < 3; k++)
            F[i][k] = mi * (vd[k] + u[k] + w[k] * wc - c[k] * ww);
        /* N = I wd + w x (I w) */
        Iw[0] = I0 * w[0] + I1 * w[1] + I2 * w[2];
        Iw[1] = I3 * w[0] + I4 * w[1] + I5 * w[2];
        Iw[2] = I6 * w[0] + I7 * w[1] + I8 * w[2];
        vec3_cross(N[i], w, Iw);
        N[i][0] += I0 * wd[0] + I1 * wd[1] + I2 * wd[2];
        N[i][1] += I3 * wd[0] + I4 * wd[1] + I5 * wd[2];
        N[i][2] += I6 * wd[0] + I7 * wd[1] + I8 * wd[2];
    }
    /* inward: force f and moment n (about origin i-1) exerted on link i by
     * link i-1, in frame i: f = R f_{i+1} + F, n = R n_{i+1} + p* x f + c x F + N */
    for (i = ARM_NJ - 1; i >= 0; i--) {
        double pf[3], cF[3];
        if (i < ARM_NJ - 1) {
            dh_rot(m, i + 1, cs, f, f);
            dh_rot(m, i + 1, cs, n, n);
        }
        for (k = 0; k < 3; k++)
            f[k] += F[i][k];
        dh_pstar(m, i, ps);
        vec3_cross(pf, ps, f);
        vec3_cross(cF, L[i].c, F[i]);
        for (k = 0; k < 3; k++)
            n[k] += pf[k] + cF[k] + N[i][k];
        /* joint axis z_{i-1} in frame i is R^T z0 = (0, sa, ca); the
         * rotor's reflected inertia on the diagonal (arm_model.h) */
        tau_Nm[i] = n[1] * m->sin_alpha[i] + n[2] * m->cos_alpha[i] + m->armature_kgm2[i] * qdd[i];
    }
}

static int rne_inputs_valid(const double qd[ARM_NJ], const double qdd[ARM_NJ],
                            const double gravity_mps2[3], const arm_payload *payload)
{
    return qd && qdd && linalg_all_finite(qd, ARM_NJ) && linalg_all_finite(qdd, ARM_NJ) &&
           (!gravity_mps2 || linalg_all_finite(gravity_mps2, 3)) && payload_valid(payload);
}

static const double default_gravity[3] = { 0.0, 0.0, -ARM_GRAVITY_MPS2 };

/* The general RNE with the payload merged into link 6; the callers take
 * the folded PUMA routine first (the model says which), so that this
 * recursion's arrays are not on the PUMA cycle's stack. */
static void rne_general(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
                        const double qdd[ARM_NJ], const double g[3], const arm_payload *payload,
                        double tau_Nm[ARM_NJ])
{
    link_mass merged;
    link_ref L[ARM_NJ];
    link_refs(m, payload, &merged, L);
    rne_cs(m, cs, L, qd, qdd, g, tau_Nm);
}

/* The folded or the general RNE, as the model says (inputs checked). */
static inline void rne_dispatch(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
                                const double qdd[ARM_NJ], const double gravity_mps2[3],
                                const arm_payload *payload, double tau_Nm[ARM_NJ])
{
    const double *g = gravity_mps2 ? gravity_mps2 : default_gravity;
    if (m->structure == ARM_STRUCTURE_PUMA)
        arm_puma_rne(m, cs, payload, qd, qdd, g, tau_Nm);
    else
        rne_general(m, cs, qd, qdd, g, payload, tau_Nm);
}

int arm_rne(const arm_model *m, const double q[ARM_NJ], const double qd[ARM_NJ],
            const double qdd[ARM_NJ], const double gravity_mps2[3], const arm_payload *payload,
            double tau_Nm[ARM_NJ])
{
    arm_joint_cs cs;
    if (!tau_Nm || !rne_inputs_valid(qd, qdd, gravity_mps2, payload) ||
        arm_joint_cs_eval(m, q, &cs) != 0)
        return ARM_DYN_ERR_ARG;
    rne_dispatch(m, &cs, qd, qdd, gravity_mps2, payload, tau_Nm);
    return 0;
}

int arm_rne_cs(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
               const double qdd[ARM_NJ], const double gravity_mps2[3], const arm_payload *payload,
               double tau_Nm[ARM_NJ])
{
    if (!m || !cs || !tau_Nm || !rne_inputs_valid(qd, qdd, gravity_mps2, payload) ||
        !linalg_all_finite(cs->c, ARM_NJ) || !linalg_all_finite(cs->s, ARM_NJ))
        return ARM_DYN_ERR_ARG;
    rne_dispatch(m, cs, qd, qdd, gravity_mps2, payload, tau_Nm);
    return 0;
}

int arm_rne_cs_unchecked(const arm_model *m, const arm_joint_cs *cs, const double qd[ARM_NJ],
                         const double qdd[ARM_NJ], const double gravity_mps2[3],
                         const arm_payload *payload, double tau_Nm[ARM_NJ])
{
    if (!payload_valid(payload))
        return ARM_DYN_ERR_ARG;
    rne_dispatch(m, cs, qd, qdd, gravity_mps2, payload, tau_Nm);
    /* every input reaches every torque through products and sums (no
     * branch, no fmin), so a NaN or Inf among them shows in tau */
    return linalg_all_finite(tau_Nm, ARM_NJ) ? 0 : ARM_DYN_ERR_ARG;
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

/* ---- joint-space inertia ------------------------------------------------ */

/* A composite about a frame origin (arm_composite, arm_puma_internal.h):
 * sums of bodies are plain sums in this form, which is why CRBA keeps it. */
typedef arm_composite origin_body;
enum { XX = ARM_I_XX, YY = ARM_I_YY, ZZ = ARM_I_ZZ, XY = ARM_I_XY, YZ = ARM_I_YZ, XZ = ARM_I_XZ };

/* b, already turned into the parent's axes (I turned, its first moment h
 * given turned), moved to the parent's origin p: the parallel-axis step
 * I += m (|p|^2 E - p p^T) + 2 (p . h) E - (p h^T + h p^T), then
 * b->h = h + m p. Shared with the folded CRBA (arm_puma.c). */
void arm_composite_shift(arm_composite *b, const double p[3], const double h[3])
{
    double *I = b->I;
    const double pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const double ph = p[0] * h[0] + p[1] * h[1] + p[2] * h[2];
    int k;
    for (k = 0; k < 3; k++)
        I[k] += b->m * (pp - p[k] * p[k]) + 2.0 * (ph - p[k] * h[k]);
    I[XY] -= b->m * p[0] * p[1] + p[0] * h[1] + h[0] * p[1];
    I[YZ] -= b->m * p[1] * p[2] + p[1] * h[2] + h[1] * p[2];
    I[XZ] -= b->m * p[0] * p[2] + p[0] * h[2] + h[0] * p[2];
    for (k = 0; k < 3; k++)
        b->h[k] = h[k] + b->m * p[k];
}

/* I <- G I G^T for G the rotation by (c, s) in the plane of axes (a, b),
 * k the third axis: only the entries touching a or b change. */
static inline void sym_rotate_plane(double *aa, double *bb, double *ab, double *ak, double *bk,
                                    double c, double s)
{
    const double Iaa = *aa, Ibb = *bb, Iab = *ab, Iak = *ak, Ibk = *bk;
    const double cc = c * c, ss = s * s, cs = c * s;
    *aa = cc * Iaa - 2.0 * cs * Iab + ss * Ibb;
    *bb = ss * Iaa + 2.0 * cs * Iab + cc * Ibb;
    *ab = cs * (Iaa - Ibb) + (cc - ss) * Iab;
    *ak = c * Iak - s * Ibk;
    *bk = s * Iak + c * Ibk;
}

/* Re-express body b, given in frame i+1 about its origin, in frame i about
 * frame i's origin (A_i = (R_i, p_i), p_i = (a ct, a st, d)):
 * I' = R I R^T + m (|p|^2 E - p p^T) + 2 (p . h') E - (p h'^T + h' p^T)
 * with h' = R h, then h' += m p (parallel-axis theorem with a first moment).
 * R I R^T = Rz (Rx I Rx^T) Rz^T: two plane rotations, no 3x3 products. */
static void origin_body_to_parent(const arm_model *m, int i, const arm_joint_cs *cs, origin_body *b)
{
    const double p[3] = { m->a_m[i] * cs->c[i], m->a_m[i] * cs->s[i], m->d_m[i] };
    double *I = b->I, h[3];
    dh_rot(m, i, cs, b->h, h);
    sym_rotate_plane(&I[YY], &I[ZZ], &I[YZ], &I[XY], &I[XZ], m->cos_alpha[i], m->sin_alpha[i]);
    sym_rotate_plane(&I[XX], &I[YY], &I[XY], &I[XZ], &I[YZ], cs->c[i], cs->s[i]);
    arm_composite_shift(b, p, h);
}

/* (n, f) of frame i+1 -> frame i, n about the frame origin:
 * f' = R f, n' = R n + p x R f = R (n + p* x f) since p = R p*. */
static void wrench_to_parent(const arm_model *m, int i, const arm_joint_cs *cs, double n[3],
                             double f[3])
{
    double ps[3], pf[3];
    int k;
    dh_pstar(m, i, ps);
    vec3_cross(pf, ps, f);
    for (k = 0; k < 3; k++)
        n[k] += pf[k];
    dh_rot(m, i, cs, n, n);
    dh_rot(m, i, cs, f, f);
}

static void mass_matrix_cs(const arm_model *m, const arm_joint_cs *cs, const link_ref L[ARM_NJ],
                           double M[36])
{
    origin_body comp;
    int i, j;
    if (m->structure == ARM_STRUCTURE_PUMA) {
        arm_puma_mass_matrix(m, cs, L, M);
        return;
    }
    memset(&comp, 0, sizeof comp);
    for (i = ARM_NJ - 1; i >= 0; i--) {
        double n[3], f[3];
        /* C_i = link i + C_{i+1}, both in frame i (1-based: link i+1, frame i+1) */
        arm_composite_add_link(&comp, &L[i]);
        origin_body_to_parent(m, i, cs, &comp);
        /* unit rate about z through the origin: n = I z, f = z x h */
        vec3_set(n, comp.I[XZ], comp.I[YZ], comp.I[ZZ]);
        vec3_set(f, -comp.h[1], comp.h[0], 0.0);
        M[i * 6 + i] = n[2];
        for (j = i - 1; j >= 0; j--) {
            wrench_to_parent(m, j, cs, n, f);
            M[j * 6 + i] = M[i * 6 + j] = n[2];
        }
    }
    for (i = 0; i < ARM_NJ; i++)
        M[i * 6 + i] += m->armature_kgm2[i]; /* the rotors' reflected inertia, as in rne_cs */
}

/* cos/sin of the joints the PUMA's M(q) reads (arm_puma_mass_matrix):
 * joints 2-5, and 6 unless link 6 with its payload is symmetric about its
 * axis; joint 1 never (its axis is vertical: M does not depend on q1).
 * The others are set to cos 1, sin 0. q checked finite by the caller. */
static void puma_mass_cs(const arm_model *m, const double q[ARM_NJ], const link_ref *l6,
                         arm_joint_cs *cs)
{
    const int last = arm_puma_link6_axisymmetric(l6) ? ARM_NJ - 1 : ARM_NJ;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        cs->c[i] = 1.0;
        cs->s[i] = 0.0;
    }
    for (i = 1; i < last; i++)
        trig_sincos(q[i] + m->theta_offset_rad[i], &cs->s[i], &cs->c[i]);
}

int arm_mass_matrix(const arm_model *m, const double q[ARM_NJ], const arm_payload *payload,
                    double M[36])
{
    arm_joint_cs cs;
    link_mass merged;
    link_ref L[ARM_NJ];
    if (!M || !m || !q || !payload_valid(payload) || !linalg_all_finite(q, ARM_NJ))
        return ARM_DYN_ERR_ARG;
    link_refs(m, payload, &merged, L);
    if (m->structure == ARM_STRUCTURE_PUMA) {
        puma_mass_cs(m, q, &L[ARM_NJ - 1], &cs);
        arm_puma_mass_matrix(m, &cs, L, M);
        return 0;
    }
    (void)arm_joint_cs_eval(m, q, &cs);
    mass_matrix_cs(m, &cs, L, M);
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
            return ARM_DYN_ERR_NOT_PD;
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
    arm_joint_cs cs;
    link_mass merged;
    link_ref L[ARM_NJ];
    double M[36], h[ARM_NJ], rhs[ARM_NJ];
    int i;
    if (!tau_Nm || !qdd || !linalg_all_finite(tau_Nm, ARM_NJ) ||
        !rne_inputs_valid(qd, zero, gravity_mps2, payload) || arm_joint_cs_eval(m, q, &cs) != 0)
        return ARM_DYN_ERR_ARG;
    /* one trig evaluation and one payload merge serve both RNE and M(q) */
    link_refs(m, payload, &merged, L);
    if (m->structure == ARM_STRUCTURE_PUMA)
        arm_puma_rne(m, &cs, payload, qd, zero, gravity_mps2 ? gravity_mps2 : default_gravity, h);
    else
        rne_cs(m, &cs, L, qd, zero, gravity_mps2 ? gravity_mps2 : default_gravity, h);
    mass_matrix_cs(m, &cs, L, M);
    for (i = 0; i < ARM_NJ; i++)
        rhs[i] = tau_Nm[i] - h[i];
    return arm_spd_solve6(M, rhs, qdd);
}

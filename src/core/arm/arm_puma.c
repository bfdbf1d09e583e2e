/* arm_puma: forward kinematics, Jacobian, J-dot q-dot (and the Cartesian
 * cycle's one pass of them, §3a), RNE torques and M(q) folded for the PUMA
 * structure (docs/method/puma.md §2-§5): twists of 90, 0, -90,
 * 90, -90, 0 deg, a1 = a4 = a5 = a6 = 0, d1 = d2 = d5 = 0, no joint
 * offsets, diagonal link inertias (arm_model_has_puma_structure).
 *
 * Why: every R_i = Rz(theta_i) Rx(alpha_i) is then a plane rotation
 * followed by a signed swap of two axes, every p*_i has one or two
 * non-zero entries, and a link's inertia three; the general DH recursions
 * (arm_kin.c, arm_dyn.c) multiply all those zeros and ones on every cycle.
 * Written out here with the zeros dropped by hand (a compiler may not drop
 * x * 0.0 under IEEE rules). The general routines stay the reference: the
 * unit tests hold these to them to 1e-12.
 */
#include "arm_puma_internal.h"

#include <string.h>

#include "vec3.h"

/* The three twist angles of the structure. */
enum { TWIST_P90, TWIST_0, TWIST_M90 };

/* out = R^T v, R = Rz(theta) Rx(alpha): turn (x, y) back by theta, then
 * (y, z) by alpha, here a swap with a sign. out may be v. */
static inline void rot_t(int twist, double c, double s, const double v[3], double out[3])
{
    const double x = c * v[0] + s * v[1], y = c * v[1] - s * v[0], z = v[2];
    out[0] = x;
    if (twist == TWIST_P90) {
        out[1] = z;
        out[2] = -y;
    } else if (twist == TWIST_0) {
        out[1] = y;
        out[2] = z;
    } else {
        out[1] = -z;
        out[2] = y;
    }
}

/* out = R v (the same two turns forwards); out may be v. */
static inline void rot(int twist, double c, double s, const double v[3], double out[3])
{
    const double x = v[0];
    double y, z;
    if (twist == TWIST_P90) {
        y = -v[2];
        z = v[1];
    } else if (twist == TWIST_0) {
        y = v[1];
        z = v[2];
    } else {
        y = v[2];
        z = -v[1];
    }
    out[0] = c * x - s * y;
    out[1] = s * x + c * y;
    out[2] = z;
}

/* ---- kinematics ----------------------------------------------------------- */

/* One row of a 4x4 */
static inline void frame_row(double *row, double x, double y, double z, double o)
{
    row[0] = x;
    row[1] = y;
    row[2] = z;
    row[3] = o;
}

/* Frame F (4x4 row-major) from its axes and origin, written out row by
 * row (no loop: the chain stores seven) */
static inline void frame_store(double F[16], const double x[3], const double y[3],
                               const double z[3], const double o[3])
{
    frame_row(F, x[0], y[0], z[0], o[0]);
    frame_row(F + 4, x[1], y[1], z[1], o[1]);
    frame_row(F + 8, x[2], y[2], z[2], o[2]);
    frame_row(F + 12, 0.0, 0.0, 0.0, 1.0);
}

/* a = ca u + sa v (a frame axis turned by a joint) */
static inline void axis_comb(double a[3], double ca, const double u[3], double sa,
                             const double v[3])
{
    a[0] = ca * u[0] + sa * v[0];
    a[1] = ca * u[1] + sa * v[1];
    a[2] = ca * u[2] + sa * v[2];
}

/* out = o + len v: the next origin along one axis; out may be o */
static inline void origin_next(double out[3], const double o[3], double len, const double v[3])
{
    vec3_axpy(out, o, len, v);
}

/* x2, y2 (z2 = z1) */
static inline void frame2_axes(double c1, double s1, double c2, double s2, double x[3], double y[3])
{
    x[0] = c1 * c2;
    x[1] = s1 * c2;
    x[2] = s2;
    y[0] = -c1 * s2;
    y[1] = -s1 * s2;
    y[2] = c2;
}

/* x3, y3, z3: R_03 = Rz(q1) Ry(-(q2 + q3)), and o3 = o2 + a3 x3 + d3 z2
 * with z2 = z1 = (s1, -c1, 0); o may be o2 */
static inline void frame3(double c1, double s1, double c23, double s23, double a3, double d3,
                          const double o2[3], double x[3], double y[3], double z[3], double o[3])
{
    x[0] = c1 * c23;
    x[1] = s1 * c23;
    x[2] = s23;
    y[0] = -s1;
    y[1] = c1;
    y[2] = 0.0;
    z[0] = -c1 * s23;
    z[1] = -s1 * s23;
    z[2] = c23;
    o[0] = o2[0] + (a3 * x[0] + d3 * s1);
    o[1] = o2[1] + (a3 * x[1] - d3 * c1);
    o[2] = o2[2] + a3 * x[2];
}

/* The wrist's axes from frame 3's (§2): x4, z4 (y4 = z3), x5, y5 = -z4,
 * z5, then the flange's x6, y6 (z6 = z5) */
static inline void wrist_axes(const arm_joint_cs *cs, const double x3[3], const double y3[3],
                              const double z3[3], double x4[3], double z4[3], double x5[3],
                              double y5[3], double z5[3])
{
    axis_comb(x4, cs->c[3], x3, cs->s[3], y3);
    axis_comb(z4, cs->s[3], x3, -cs->c[3], y3);
    axis_comb(x5, cs->c[4], x4, cs->s[4], z3);
    axis_comb(z5, -cs->s[4], x4, cs->c[4], z3);
    vec3_set(y5, -z4[0], -z4[1], -z4[2]);
}

static inline void flange_axes(const arm_joint_cs *cs, const double x5[3], const double y5[3],
                               double x6[3], double y6[3])
{
    axis_comb(x6, cs->c[5], x5, cs->s[5], y5);
    axis_comb(y6, -cs->s[5], x5, cs->c[5], y5);
}

/* docs/method/puma.md §2: R_03 = Rz(q1) Ry(-(q2 + q3)) in closed form, the
 * wrist axes by one plane turn each, o_i = o_{i-1} + a_i x_i + d_i z_{i-1}
 * with the zero lengths left out. Written frame by frame into F. */
void arm_puma_chain(const arm_model *m, const arm_joint_cs *cs, double (*F)[16])
{
    const double c1 = cs->c[0], s1 = cs->s[0], c2 = cs->c[1], s2 = cs->s[1];
    const double c3 = cs->c[2], s3 = cs->s[2];
    const double c23 = c2 * c3 - s2 * s3, s23 = s2 * c3 + c2 * s3;
    const double z1[3] = { s1, -c1, 0.0 };
    double x[3], y[3], z[3], o[3] = { 0.0, 0.0, m->base_height_m };
    {
        const double ex[3] = { 1.0, 0.0, 0.0 }, ey[3] = { 0.0, 1.0, 0.0 },
                     ez[3] = { 0.0, 0.0, 1.0 };
        const double x1[3] = { c1, s1, 0.0 };
        frame_store(F[0], ex, ey, ez, o);
        frame_store(F[1], x1, ez, z1, o);
    }
    frame2_axes(c1, s1, c2, s2, x, y);
    origin_next(o, o, m->a_m[1], x);
    frame_store(F[2], x, y, z1, o);
    frame3(c1, s1, c23, s23, m->a_m[2], m->d_m[2], o, x, y, z, o);
    frame_store(F[3], x, y, z, o);
    {
        double x4[3], z4[3], x5[3], y5[3], z5[3];
        wrist_axes(cs, x, y, z, x4, z4, x5, y5, z5);
        origin_next(o, o, m->d_m[3], z);
        frame_store(F[4], x4, z, z4, o);  /* y4 = z3 */
        frame_store(F[5], x5, y5, z5, o); /* o5 = o4 */
        flange_axes(cs, x5, y5, x, y);
        origin_next(o, o, m->d_m[5], z5);
        frame_store(F[6], x, y, z5, o); /* z6 = z5 */
    }
}

/* Column i of J: [z x (p - o); z], z and o axis and origin of frame i-1 */
static inline void jacobian_column(double J[36], int i, const double z[3], const double o[3],
                                   const double p[3])
{
    const double r0 = p[0] - o[0], r1 = p[1] - o[1], r2 = p[2] - o[2];
    J[i] = z[1] * r2 - z[2] * r1;
    J[6 + i] = z[2] * r0 - z[0] * r2;
    J[12 + i] = z[0] * r1 - z[1] * r0;
    J[18 + i] = z[0];
    J[24 + i] = z[1];
    J[30 + i] = z[2];
}

/* Column 1: z_0 = e_z, o_0 on the z axis: free of products */
static inline void jacobian_column0(double J[36], const double o0[3], const double p[3])
{
    J[0] = -(p[1] - o0[1]);
    J[6] = p[0] - o0[0];
    J[12] = 0.0;
    J[18] = 0.0;
    J[24] = 0.0;
    J[30] = 1.0;
}

void arm_puma_jacobian(const double (*F)[16], const double T[16], double J[36])
{
    const double p[3] = { T[3], T[7], T[11] };
    int i;
    {
        const double o0[3] = { F[0][3], F[0][7], F[0][11] };
        jacobian_column0(J, o0, p);
    }
    for (i = 1; i < ARM_NJ; i++) {
        const double *Fi = F[i];
        const double z[3] = { Fi[2], Fi[6], Fi[10] }, o[3] = { Fi[3], Fi[7], Fi[11] };
        jacobian_column(J, i, z, o, p);
    }
}

/* ---- recursive Newton-Euler ----------------------------------------------- */

/* The acceleration of a point r of a body: vd + K r with
 * K = [wd]x + [w]x^2 (docs/method/puma.md §4); one K serves p*_i and the COM.
 * w01, w02, w12 are reused by the gyroscopic moment. */
typedef struct accel_map {
    double K[9];
    double w01, w02, w12;
} accel_map;

static inline void accel_map_of(const double w[3], const double wd[3], accel_map *a)
{
    const double w00 = w[0] * w[0], w11 = w[1] * w[1], w22 = w[2] * w[2];
    a->w01 = w[0] * w[1];
    a->w02 = w[0] * w[2];
    a->w12 = w[1] * w[2];
    a->K[0] = -(w11 + w22);
    a->K[1] = a->w01 - wd[2];
    a->K[2] = a->w02 + wd[1];
    a->K[3] = a->w01 + wd[2];
    a->K[4] = -(w00 + w22);
    a->K[5] = a->w12 - wd[0];
    a->K[6] = a->w02 - wd[1];
    a->K[7] = a->w12 + wd[0];
    a->K[8] = -(w00 + w11);
}

/* vd += len * column col of K: the origin of the next frame at len along
 * one axis (p*_i has one or two non-zero entries). */
static inline void add_column(double vd[3], const accel_map *a, int col, double len)
{
    vd[0] += len * a->K[col];
    vd[1] += len * a->K[3 + col];
    vd[2] += len * a->K[6 + col];
}

/* One link outward: frame i's w, wd, vd from frame i-1's (before the
 * p*_i terms, added by the caller), eq. of docs/method/puma.md §4. */
static inline void outward(int twist, double c, double s, double qd, double qdd, double w[3],
                           double wd[3], double vd[3])
{
    double t[3];
    t[0] = wd[0] + w[1] * qd;
    t[1] = wd[1] - w[0] * qd;
    t[2] = wd[2] + qdd;
    rot_t(twist, c, s, t, wd);
    w[2] += qd;
    rot_t(twist, c, s, w, w);
    rot_t(twist, c, s, vd, vd);
}

/* Inertial force F = m (vd + K c) of a body of mass m, COM c. Written
 * out (no loop: the cycle's RNE calls it six times). */
static inline void body_force(double mass, const accel_map *a, const double vd[3],
                              const double c[3], double F[3])
{
    const double *K = a->K;
    F[0] = mass * (vd[0] + K[0] * c[0] + K[1] * c[1] + K[2] * c[2]);
    F[1] = mass * (vd[1] + K[3] * c[0] + K[4] * c[1] + K[5] * c[2]);
    F[2] = mass * (vd[2] + K[6] * c[0] + K[7] * c[1] + K[8] * c[2]);
}

/* The moment about the COM N = I wd + w x (I w) of link i, whose inertia
 * is diagonal. Apart from body_force: the 68040's compiler inlines the two
 * at each link, not one function doing both, whose call cost the RNE 124
 * bytes of stack (make budget). */
static inline void link_moment_diag(const arm_model *m, int i, const accel_map *a,
                                    const double wd[3], double N[3])
{
    const double *I = m->inertia_kgm2[i];
    N[0] = I[0] * wd[0] + (I[8] - I[4]) * a->w12;
    N[1] = I[4] * wd[1] + (I[0] - I[8]) * a->w02;
    N[2] = I[8] * wd[2] + (I[4] - I[0]) * a->w01;
}

/* A payload held at the flange, as a body of its own in frame 6 (merging
 * it into link 6 cost more than the body: a parallel-axis sum per call):
 * F = m (vd + K c), N = I wd + w x (I w) with a full inertia, skipped for
 * a point mass. */
static void payload_wrench(const arm_payload *p, const accel_map *a, const double w[3],
                           const double vd[3], const double wd[3], double F[3], double N[3])
{
    const double *I = p->inertia_kgm2;
    body_force(p->mass_kg, a, vd, p->com_m, F);
    if (I[0] == 0.0 && I[4] == 0.0 && I[8] == 0.0 && I[1] == 0.0 && I[2] == 0.0 && I[3] == 0.0 &&
        I[5] == 0.0 && I[6] == 0.0 && I[7] == 0.0) {
        N[0] = N[1] = N[2] = 0.0;
        return;
    }
    {
        double Iw[3];
        rot_apply(Iw, I, w); /* I w */
        N[0] = I[0] * wd[0] + I[1] * wd[1] + I[2] * wd[2] + w[1] * Iw[2] - w[2] * Iw[1];
        N[1] = I[3] * wd[0] + I[4] * wd[1] + I[5] * wd[2] + w[2] * Iw[0] - w[0] * Iw[2];
        N[2] = I[6] * wd[0] + I[7] * wd[1] + I[8] * wd[2] + w[0] * Iw[1] - w[1] * Iw[0];
    }
}

/* n += c x F + N (the link's own moment about its frame origin) */
static inline void add_link_moment(double n[3], const double c[3], const double F[3],
                                   const double N[3])
{
    n[0] += c[1] * F[2] - c[2] * F[1] + N[0];
    n[1] += c[2] * F[0] - c[0] * F[2] + N[1];
    n[2] += c[0] * F[1] - c[1] * F[0] + N[2];
}

/* tau_i + J_i qdd_i: the rotors' reflected inertia (arm_model.h
 * armature_kgm2, Jm G^2) acts on each joint's own acceleration only, a
 * diagonal term, as in arm_dyn.c. */
static inline double with_armature(const arm_model *m, const double qdd[ARM_NJ], int i,
                                   double tau_Nm)
{
    return tau_Nm + m->armature_kgm2[i] * qdd[i];
}

/* Outward by joints, with p*_1 = 0, p*_2 = (a2, 0, 0), p*_3 = (a3, -d3, 0),
 * p*_4 = (0, d4, 0), p*_5 = 0, p*_6 = (0, 0, d6); inward with the same
 * zeros; tau_i = n_i . (0, sin alpha_i, cos alpha_i), a signed component. */
void arm_puma_rne(const arm_model *m, const arm_joint_cs *cs, const arm_payload *payload,
                  const double qd[ARM_NJ], const double qdd[ARM_NJ], const double g[3],
                  double tau_Nm[ARM_NJ])
{
    const double a2 = m->a_m[1], a3 = m->a_m[2], d3 = m->d_m[2], d4 = m->d_m[3], d6 = m->d_m[5];
    const double *c = cs->c, *s = cs->s;
    double F[ARM_NJ][3], N[ARM_NJ][3], w[3], wd[3], vd[3], f[3], n[3], mg[3];
    double Fp[3] = { 0.0, 0.0, 0.0 }, Np[3] = { 0.0, 0.0, 0.0 };
    accel_map a;

    /* joint 1 turns about the base z: w = (0, qd1, 0), wd = (0, qdd1, 0) in frame 1 */
    mg[0] = -g[0];
    mg[1] = -g[1];
    mg[2] = -g[2];
    w[0] = 0.0;
    w[1] = qd[0];
    w[2] = 0.0;
    wd[0] = 0.0;
    wd[1] = qdd[0];
    wd[2] = 0.0;
    rot_t(TWIST_P90, c[0], s[0], mg, vd);
    {
        /* link 1 adds only its moment about its joint axis (frame 1's y):
         * (c x F)_y + N_y, with w x (I w) = 0 (w along y) */
        const double *c1 = m->com_m[0];
        const double w11 = w[1] * w[1];
        F[0][0] = m->mass_kg[0] * (vd[0] - w11 * c1[0] + wd[1] * c1[2]);
        F[0][2] = m->mass_kg[0] * (vd[2] - wd[1] * c1[0] - w11 * c1[2]);
        N[0][1] = m->inertia_kgm2[0][4] * wd[1];
    }

    outward(TWIST_0, c[1], s[1], qd[1], qdd[1], w, wd, vd);
    accel_map_of(w, wd, &a);
    add_column(vd, &a, 0, a2);
    body_force(m->mass_kg[1], &a, vd, m->com_m[1], F[1]);
    link_moment_diag(m, 1, &a, wd, N[1]);

    outward(TWIST_M90, c[2], s[2], qd[2], qdd[2], w, wd, vd);
    accel_map_of(w, wd, &a);
    add_column(vd, &a, 0, a3);
    add_column(vd, &a, 1, -d3);
    body_force(m->mass_kg[2], &a, vd, m->com_m[2], F[2]);
    link_moment_diag(m, 2, &a, wd, N[2]);

    outward(TWIST_P90, c[3], s[3], qd[3], qdd[3], w, wd, vd);
    accel_map_of(w, wd, &a);
    add_column(vd, &a, 1, d4);
    body_force(m->mass_kg[3], &a, vd, m->com_m[3], F[3]);
    link_moment_diag(m, 3, &a, wd, N[3]);

    outward(TWIST_M90, c[4], s[4], qd[4], qdd[4], w, wd, vd);
    accel_map_of(w, wd, &a);
    body_force(m->mass_kg[4], &a, vd, m->com_m[4], F[4]);
    link_moment_diag(m, 4, &a, wd, N[4]);

    outward(TWIST_0, c[5], s[5], qd[5], qdd[5], w, wd, vd);
    accel_map_of(w, wd, &a);
    add_column(vd, &a, 2, d6);
    body_force(m->mass_kg[5], &a, vd, m->com_m[5], F[5]);
    link_moment_diag(m, 5, &a, wd, N[5]);
    if (payload && payload->mass_kg > 0.0)
        payload_wrench(payload, &a, w, vd, wd, Fp, Np);

    /* inward: link 6, p*_6 x f = d6 (-f1, f0, 0) */
    vec3_add(f, F[5], Fp);
    n[0] = -d6 * f[1];
    n[1] = d6 * f[0];
    n[2] = 0.0;
    add_link_moment(n, m->com_m[5], F[5], N[5]);
    if (payload)
        add_link_moment(n, payload->com_m, Fp, Np);
    tau_Nm[5] = with_armature(m, qdd, 5, n[2]);
    /* link 5: p*_5 = 0 */
    rot(TWIST_0, c[5], s[5], f, f);
    rot(TWIST_0, c[5], s[5], n, n);
    vec3_add(f, f, F[4]);
    add_link_moment(n, m->com_m[4], F[4], N[4]);
    tau_Nm[4] = with_armature(m, qdd, 4, -n[1]);
    /* link 4: p*_4 x f = d4 (f2, 0, -f0) */
    rot(TWIST_M90, c[4], s[4], f, f);
    rot(TWIST_M90, c[4], s[4], n, n);
    vec3_add(f, f, F[3]);
    n[0] += d4 * f[2];
    n[2] -= d4 * f[0];
    add_link_moment(n, m->com_m[3], F[3], N[3]);
    tau_Nm[3] = with_armature(m, qdd, 3, n[1]);
    /* link 3: p*_3 x f = a3 (0, -f2, f1) - d3 (f2, 0, -f0) */
    rot(TWIST_P90, c[3], s[3], f, f);
    rot(TWIST_P90, c[3], s[3], n, n);
    vec3_add(f, f, F[2]);
    n[0] -= d3 * f[2];
    n[1] -= a3 * f[2];
    n[2] += a3 * f[1] + d3 * f[0];
    add_link_moment(n, m->com_m[2], F[2], N[2]);
    tau_Nm[2] = with_armature(m, qdd, 2, -n[1]);
    /* link 2: p*_2 x f = a2 (0, -f2, f1) */
    rot(TWIST_M90, c[2], s[2], f, f);
    rot(TWIST_M90, c[2], s[2], n, n);
    vec3_add(f, f, F[1]);
    n[1] -= a2 * f[2];
    n[2] += a2 * f[1];
    add_link_moment(n, m->com_m[1], F[1], N[1]);
    tau_Nm[1] = with_armature(m, qdd, 1, n[2]);
    /* link 1: only the moment's y (its joint axis in frame 1) is wanted */
    rot(TWIST_0, c[1], s[1], n, n);
    tau_Nm[0] = with_armature(m, qdd, 0,
                              n[1] + m->com_m[0][2] * F[0][0] - m->com_m[0][0] * F[0][2] + N[0][1]);
}

/* out = R v and out = R^T v, R the rotation of a frame F (4x4, row-major),
 * read in place */
static inline void frame_turn(const double F[16], const double v[3], double out[3])
{
    out[0] = F[0] * v[0] + F[1] * v[1] + F[2] * v[2];
    out[1] = F[4] * v[0] + F[5] * v[1] + F[6] * v[2];
    out[2] = F[8] * v[0] + F[9] * v[1] + F[10] * v[2];
}

static inline void frame_turn_back(const double F[16], const double v[3], double out[3])
{
    out[0] = F[0] * v[0] + F[4] * v[1] + F[8] * v[2];
    out[1] = F[1] * v[0] + F[5] * v[1] + F[9] * v[2];
    out[2] = F[2] * v[0] + F[6] * v[1] + F[10] * v[2];
}

/* ---- J-dot q-dot ------------------------------------------------------------ */

/* docs/method/puma.md §3: J-dot q-dot is the acceleration of the point p of
 * T and link 6's angular acceleration when qdd = 0 and g = 0, so the
 * outward half of the RNE above, in link coordinates with its zeros
 * (w_1 = (0, qd1, 0), wd_1 = vd_1 = 0, the p*_i), then
 * [R_06 (vd_6 + K_6 r); R_06 wd_6] with r = R_06^T (p - o_6), the point
 * in frame 6. */
void arm_puma_jdot_qd(const arm_model *m, const arm_joint_cs *cs, const double F6[16],
                      const double T[16], const double qd[ARM_NJ], double jdqd[6])
{
    const double *c = cs->c, *s = cs->s;
    double w[3], wd[3], vd[3], r[3];
    accel_map k;
    w[0] = 0.0;
    w[1] = qd[0];
    w[2] = 0.0;
    wd[0] = wd[1] = wd[2] = 0.0;
    vd[0] = vd[1] = vd[2] = 0.0;
    outward(TWIST_0, c[1], s[1], qd[1], 0.0, w, wd, vd);
    accel_map_of(w, wd, &k);
    add_column(vd, &k, 0, m->a_m[1]);
    outward(TWIST_M90, c[2], s[2], qd[2], 0.0, w, wd, vd);
    accel_map_of(w, wd, &k);
    add_column(vd, &k, 0, m->a_m[2]);
    add_column(vd, &k, 1, -m->d_m[2]);
    outward(TWIST_P90, c[3], s[3], qd[3], 0.0, w, wd, vd);
    accel_map_of(w, wd, &k);
    add_column(vd, &k, 1, m->d_m[3]);
    outward(TWIST_M90, c[4], s[4], qd[4], 0.0, w, wd, vd);
    outward(TWIST_0, c[5], s[5], qd[5], 0.0, w, wd, vd);
    accel_map_of(w, wd, &k);
    add_column(vd, &k, 2, m->d_m[5]);
    {
        const double d[3] = { T[3] - F6[3], T[7] - F6[7], T[11] - F6[11] };
        frame_turn_back(F6, d, r);
    }
    /* vd_6 + K_6 r: the point's acceleration */
    vd[0] += k.K[0] * r[0] + k.K[1] * r[1] + k.K[2] * r[2];
    vd[1] += k.K[3] * r[0] + k.K[4] * r[1] + k.K[5] * r[2];
    vd[2] += k.K[6] * r[0] + k.K[7] * r[1] + k.K[8] * r[2];
    frame_turn(F6, vd, jdqd);
    frame_turn(F6, wd, jdqd + 3);
}

/* ---- the Cartesian cycle's kinematics pass -------------------------------- */

/* T = F6 X for a rigid tool X (bottom row 0 0 0 1, as arm_tool_none and
 * arm_tool_offset make it), the flange's bottom row left out. A tool
 * that only moves the point keeps the flange's axes (no products: on the
 * 68040 the 27 of the turn cost more than the test); its point, and a
 * turned tool's axes, are the bits of arm_kin_eval's pose (x 1 + y 0 = x). */
static void tool_pose(const double F6[16], const double X[16], double T[16])
{
    const int turns = !(X[0] == 1.0 && X[5] == 1.0 && X[10] == 1.0 && X[1] == 0.0 && X[2] == 0.0 &&
                        X[4] == 0.0 && X[6] == 0.0 && X[8] == 0.0 && X[9] == 0.0);
    int r;
    for (r = 0; r < 12; r += 4) {
        const double *a = F6 + r;
        if (turns) {
            T[r] = a[0] * X[0] + a[1] * X[4] + a[2] * X[8];
            T[r + 1] = a[0] * X[1] + a[1] * X[5] + a[2] * X[9];
            T[r + 2] = a[0] * X[2] + a[1] * X[6] + a[2] * X[10];
        } else {
            T[r] = a[0];
            T[r + 1] = a[1];
            T[r + 2] = a[2];
        }
        T[r + 3] = a[0] * X[3] + a[1] * X[7] + a[2] * X[11] + a[3];
    }
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
}

/* docs/method/puma.md §3a: the axes and origins of §2 once, in locals:
 * of frames 0-5 only what J reads (z_i, o_i), never stored as frames;
 * the flange frame for the tool pose and J-dot q-dot (§3); written
 * straight into the caller's arrays. The same operations as
 * arm_puma_chain (the same helpers), so the same bits. */
void arm_puma_cycle_kin(const arm_model *m, const arm_joint_cs *cs, const arm_tool *tool,
                        const double qd[ARM_NJ], double T[16], double J[36], double jdqd[6],
                        double wrist_m[3])
{
    const double c1 = cs->c[0], s1 = cs->s[0], c2 = cs->c[1], s2 = cs->s[1];
    const double c3 = cs->c[2], s3 = cs->s[2];
    const double c23 = c2 * c3 - s2 * s3, s23 = s2 * c3 + c2 * s3;
    const double z1[3] = { s1, -c1, 0.0 }, o0[3] = { 0.0, 0.0, m->base_height_m };
    double F6[16], x[3], y[3], z3[3], x4[3], z4[3], x5[3], y5[3], z5[3];
    double o2[3], o3[3], o4[3], o6[3];
    frame2_axes(c1, s1, c2, s2, x, y);
    origin_next(o2, o0, m->a_m[1], x);
    frame3(c1, s1, c23, s23, m->a_m[2], m->d_m[2], o2, x, y, z3, o3);
    wrist_axes(cs, x, y, z3, x4, z4, x5, y5, z5);
    origin_next(o4, o3, m->d_m[3], z3);
    flange_axes(cs, x5, y5, x, y);
    origin_next(o6, o4, m->d_m[5], z5);
    frame_store(F6, x, y, z5, o6);
    if (tool)
        tool_pose(F6, tool->T_flange_tool, T);
    else
        memcpy(T, F6, sizeof F6);
    {
        const double p[3] = { T[3], T[7], T[11] };
        jacobian_column0(J, o0, p);
        jacobian_column(J, 1, z1, o0, p);
        jacobian_column(J, 2, z1, o2, p);
        jacobian_column(J, 3, z3, o3, p);
        jacobian_column(J, 4, z4, o4, p);
        jacobian_column(J, 5, z5, o4, p);
    }
    arm_puma_jdot_qd(m, cs, F6, T, qd, jdqd);
    wrist_m[0] = o4[0];
    wrist_m[1] = o4[1];
    wrist_m[2] = o4[2];
}

/* ---- joint-space inertia (composite rigid bodies) ---------------------- */

/* The composite of arm_dyn.c's CRBA (arm_composite), its entries by name */
enum { XX = ARM_I_XX, YY = ARM_I_YY, ZZ = ARM_I_ZZ, XY = ARM_I_XY, YZ = ARM_I_YZ, XZ = ARM_I_XZ };
typedef arm_composite composite;

/* I <- Rx(alpha) I Rx(alpha)^T for alpha = +-90 deg: y and z swap, signs
 * follow (docs/method/puma.md §5). */
static inline void inertia_twist(int twist, double I[6])
{
    double t;
    if (twist == TWIST_0)
        return;
    t = I[YY];
    I[YY] = I[ZZ];
    I[ZZ] = t;
    I[YZ] = -I[YZ];
    t = I[XY];
    if (twist == TWIST_P90) {
        I[XY] = -I[XZ];
        I[XZ] = t;
    } else {
        I[XY] = I[XZ];
        I[XZ] = -t;
    }
}

/* I <- Rz(theta) I Rz(theta)^T */
static inline void inertia_turn(double c, double s, double I[6])
{
    const double xx = I[XX], yy = I[YY], xy = I[XY], xz = I[XZ], yz = I[YZ];
    const double cc = c * c, ss = s * s, cs = c * s;
    I[XX] = cc * xx - 2.0 * cs * xy + ss * yy;
    I[YY] = ss * xx + 2.0 * cs * xy + cc * yy;
    I[XY] = cs * (xx - yy) + (cc - ss) * xy;
    I[XZ] = c * xz - s * yz;
    I[YZ] = s * xz + c * yz;
}

/* The composite about o_{i+1} moved to o_i, still in frame i+1's axes:
 * the parallel-axis step (arm_composite_shift) with p = p*_{i+1}, the
 * origin of frame i+1 seen from o_i, which has its zeros here: (px, py, 0)
 * for joints 2, 3 and 4, (0, 0, pz) for joint 6 (docs/method/puma.md §5). */
static inline void shift_xy(composite *b, double px, double py)
{
    const double m = b->m, hx = b->h[0], hy = b->h[1], hz = b->h[2];
    b->I[XX] += py * (m * py + 2.0 * hy);
    b->I[YY] += px * (m * px + 2.0 * hx);
    b->I[ZZ] += px * (m * px + 2.0 * hx) + py * (m * py + 2.0 * hy);
    b->I[XY] -= m * px * py + px * hy + hx * py;
    b->I[YZ] -= py * hz;
    b->I[XZ] -= px * hz;
    b->h[0] += m * px;
    b->h[1] += m * py;
}

static inline void shift_z(composite *b, double pz)
{
    const double d = pz * (b->m * pz + 2.0 * b->h[2]);
    b->I[XX] += d;
    b->I[YY] += d;
    b->I[YZ] -= b->h[1] * pz;
    b->I[XZ] -= b->h[0] * pz;
    b->h[2] += b->m * pz;
}

/* The composite, about o_i, turned from frame i+1's axes into frame i's:
 * R_i = Rz(theta_i) Rx(alpha_i) on h and on I. turn = 0 skips the Rz
 * part (a composite symmetric about z_i, on which it acts as identity). */
static inline void composite_turn(int twist, double c, double s, int turn, composite *b)
{
    inertia_twist(twist, b->I);
    rot(twist, turn ? c : 1.0, turn ? s : 0.0, b->h, b->h);
    if (turn)
        inertia_turn(c, s, b->I);
}

/* Link 6 (with its payload) symmetric about its own z axis: I diagonal
 * with I_xx = I_yy and the COM on the axis. Then turning it by q6 changes
 * nothing, and M does not depend on q6. */
int arm_puma_link6_axisymmetric(const arm_link_ref *l6)
{
    const double *I = l6->I, *c = l6->c;
    return I[0] == I[4] && I[1] == 0.0 && I[2] == 0.0 && I[3] == 0.0 && I[5] == 0.0 &&
           I[6] == 0.0 && I[7] == 0.0 && c[0] == 0.0 && c[1] == 0.0;
}

/* Column i's wrench for a unit qdd_i: n = I z, f = z x h; M_ii = n_z. */
static inline void column_of(const composite *b, double n[3], double f[3], double *Mii)
{
    n[0] = b->I[XZ];
    n[1] = b->I[YZ];
    n[2] = b->I[ZZ];
    f[0] = -b->h[1];
    f[1] = b->h[0];
    f[2] = 0.0;
    *Mii = b->I[ZZ];
}

/* Composites inward (links i+1..6 about o_i in frame i: shift by p*_{i+1},
 * then turn by R_i), each giving column i's wrench for a unit qdd_i,
 * n = I z_i, f = z_i x h, and M_ii = n_z; then all the wrenches carried
 * inward together, joint by joint: n += p*_{j+1} x f, both turned by R_j,
 * M_ji = n_z. What folds beyond the zeros of p*: the z row of R_j v is
 * v_y, v_z or -v_y, so M_ji needs no turn; joint 1 needs none at all
 * (M_0i = n_y in frame 1, and M does not depend on q1), joint 2 only the
 * y of n, and f is turned only while a later p* reads it. */
void arm_puma_mass_matrix(const arm_model *m, const arm_joint_cs *cs, const arm_link_ref L[ARM_NJ],
                          double M[36])
{
    const double a2 = m->a_m[1], a3 = m->a_m[2], d3 = m->d_m[2], d4 = m->d_m[3], d6 = m->d_m[5];
    const double *c = cs->c, *s = cs->s;
    double n[ARM_NJ][3], f[ARM_NJ][3];
    composite b;
    int i;
    memset(&b, 0, sizeof b);

    /* phase 1: the composites, link 6 first, written out so that the
     * composite stays in registers */
    arm_composite_add_link(&b, &L[5]);
    shift_z(&b, d6);
    composite_turn(TWIST_0, c[5], s[5], !arm_puma_link6_axisymmetric(&L[5]), &b);
    column_of(&b, n[5], f[5], &M[5 * 6 + 5]);
    arm_composite_add_link(&b, &L[4]); /* p*_5 = 0 */
    composite_turn(TWIST_M90, c[4], s[4], 1, &b);
    column_of(&b, n[4], f[4], &M[4 * 6 + 4]);
    arm_composite_add_link(&b, &L[3]);
    shift_xy(&b, 0.0, d4);
    composite_turn(TWIST_P90, c[3], s[3], 1, &b);
    column_of(&b, n[3], f[3], &M[3 * 6 + 3]);
    arm_composite_add_link(&b, &L[2]);
    shift_xy(&b, a3, -d3);
    composite_turn(TWIST_M90, c[2], s[2], 1, &b);
    column_of(&b, n[2], f[2], &M[2 * 6 + 2]);
    arm_composite_add_link(&b, &L[1]);
    shift_xy(&b, a2, 0.0);
    composite_turn(TWIST_0, c[1], s[1], 1, &b);
    column_of(&b, n[1], f[1], &M[1 * 6 + 1]);
    /* link 1: p*_1 = 0, and Rx(90) turns yy into zz, which Rz(q1) keeps */
    arm_composite_add_link(&b, &L[0]);
    M[0] = b.I[YY];

    /* phase 2: the wrenches inward. Joint 5 (p*_5 = 0, twist -90) */
    rot(TWIST_M90, c[4], s[4], n[5], n[5]);
    rot(TWIST_M90, c[4], s[4], f[5], f[5]);
    M[4 * 6 + 5] = n[5][2];
    for (i = 4; i < ARM_NJ; i++) { /* joint 4: p*_4 = (0, d4, 0), twist 90 */
        n[i][0] += d4 * f[i][2];
        n[i][2] -= d4 * f[i][0];
        rot(TWIST_P90, c[3], s[3], n[i], n[i]);
        rot(TWIST_P90, c[3], s[3], f[i], f[i]);
        M[3 * 6 + i] = n[i][2];
    }
    for (i = 3; i < ARM_NJ; i++) { /* joint 3: p*_3 = (a3, -d3, 0), twist -90 */
        n[i][0] -= d3 * f[i][2];
        n[i][1] -= a3 * f[i][2];
        n[i][2] += a3 * f[i][1] + d3 * f[i][0];
        rot(TWIST_M90, c[2], s[2], n[i], n[i]);
        rot(TWIST_M90, c[2], s[2], f[i], f[i]);
        M[2 * 6 + i] = n[i][2];
    }
    for (i = 2; i < ARM_NJ; i++) { /* joint 2: p*_2 = (a2, 0, 0), twist 0; only y is read on */
        n[i][1] -= a2 * f[i][2];
        M[1 * 6 + i] = n[i][2] + a2 * f[i][1];
        n[i][1] = s[1] * n[i][0] + c[1] * n[i][1];
    }
    for (i = 1; i < ARM_NJ; i++) /* joint 1: the z row of Rx(90) is y */
        M[i] = n[i][1];
    for (i = 0; i < ARM_NJ; i++) {
        int j;
        for (j = 0; j < i; j++)
            M[i * 6 + j] = M[j * 6 + i];
        M[i * 6 + i] += m->armature_kgm2[i]; /* the rotors' reflected inertia, as in arm_puma_rne */
    }
}

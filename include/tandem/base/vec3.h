/* vec3: 3-vectors, 3x3 rotation matrices and homogeneous transforms.
 *
 * Shared small-geometry kernel for every core module (kinematics, path
 * profiles, TDSD, sonar). Plain arrays, row-major, no allocation, so the
 * same code runs on a 68040 or a Cortex-M. Rotations R are 3x3 row-major
 * (double[9]); transforms T are 4x4 row-major (double[16]).
 */
#ifndef TANDEM_VEC3_H
#define TANDEM_VEC3_H

#include <math.h>

/* The small ones below are C99 inline definitions (vec3.c holds the
 * external ones): the kinematics, dynamics and segment laws call them a
 * few dozen times per control cycle, and a call costs more than the
 * arithmetic on the 68040 (arguments through memory). */
inline void vec3_set(double out[3], double x, double y, double z)
{
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
inline void vec3_copy(double out[3], const double a[3])
{
    out[0] = a[0];
    out[1] = a[1];
    out[2] = a[2];
}
inline void vec3_add(double out[3], const double a[3], const double b[3])
{
    out[0] = a[0] + b[0];
    out[1] = a[1] + b[1];
    out[2] = a[2] + b[2];
}
inline void vec3_sub(double out[3], const double a[3], const double b[3])
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}
inline void vec3_scale(double out[3], const double a[3], double k)
{
    out[0] = k * a[0];
    out[1] = k * a[1];
    out[2] = k * a[2];
}
/* out = a + k b */
inline void vec3_axpy(double out[3], const double a[3], double k, const double b[3])
{
    out[0] = a[0] + k * b[0];
    out[1] = a[1] + k * b[1];
    out[2] = a[2] + k * b[2];
}
inline double vec3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline void vec3_cross(double out[3], const double a[3], const double b[3])
{
    const double x = a[1] * b[2] - a[2] * b[1];
    const double y = a[2] * b[0] - a[0] * b[2];
    const double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
inline double vec3_norm(const double a[3])
{
    return sqrt(vec3_dot(a, a));
}
/* Returns the norm before normalising; leaves a zero vector unchanged. */
double vec3_normalize(double out[3], const double a[3]);

void rot_identity(double R[9]);
void rot_mul(double out[9], const double A[9], const double B[9]);
/* out = A^T B */
void rot_tmul(double out[9], const double A[9], const double B[9]);
inline void rot_apply(double out[3], const double R[9], const double v[3])
{
    const double x = R[0] * v[0] + R[1] * v[1] + R[2] * v[2];
    const double y = R[3] * v[0] + R[4] * v[1] + R[5] * v[2];
    const double z = R[6] * v[0] + R[7] * v[1] + R[8] * v[2];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
/* out = R^T v */
inline void rot_tapply(double out[3], const double R[9], const double v[3])
{
    const double x = R[0] * v[0] + R[3] * v[1] + R[6] * v[2];
    const double y = R[1] * v[0] + R[4] * v[1] + R[7] * v[2];
    const double z = R[2] * v[0] + R[5] * v[1] + R[8] * v[2];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
void rot_transpose(double out[9], const double R[9]);
/* Rotation about the unit axis k whose angle has sine s and cosine c
 * (Rodrigues), for callers with their own sine and cosine. */
void rot_from_unit_axis_sc(double R[9], const double k[3], double s, double c);
/* Rotation of angle_rad about unit axis (Rodrigues). */
void rot_from_axis_angle(double R[9], const double axis[3], double angle_rad);
/* Inverse of the above; angle in [0, pi]; axis (1,0,0) for the identity. */
double rot_to_axis_angle(double axis[3], const double R[9]);
/* Unit quaternion w x y z <-> rotation matrix. */
void rot_from_quat(double R[9], const double q_wxyz[4]);
void rot_to_quat(double q_wxyz[4], const double R[9]);

void tf_identity(double T[16]);
void tf_mul(double out[16], const double A[16], const double B[16]);
void tf_from_rot_pos(double T[16], const double R[9], const double p[3]);
inline void tf_rot(double R[9], const double T[16])
{
    int r;
    for (r = 0; r < 3; r++) {
        R[3 * r] = T[4 * r];
        R[3 * r + 1] = T[4 * r + 1];
        R[3 * r + 2] = T[4 * r + 2];
    }
}
void tf_pos(double p[3], const double T[16]);
/* out = R p + t: the point p carried by T (out may alias p); R read in
 * place (each row of R p before its t, as rot_apply sums it). */
inline void tf_apply(double out[3], const double T[16], const double p[3])
{
    const double x = T[0] * p[0] + T[1] * p[1] + T[2] * p[2];
    const double y = T[4] * p[0] + T[5] * p[1] + T[6] * p[2];
    const double z = T[8] * p[0] + T[9] * p[1] + T[10] * p[2];
    out[0] = x + T[3];
    out[1] = y + T[7];
    out[2] = z + T[11];
}
/* out = T^-1 for a rigid transform. */
void tf_inverse(double out[16], const double T[16]);

#endif

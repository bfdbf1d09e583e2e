/* vec3: 3-vectors, 3x3 rotation matrices and homogeneous transforms.
 *
 * Shared small-geometry kernel for every core module (kinematics, path
 * profiles, TDSD, sonar). Plain arrays, row-major, no allocation, so the
 * same code runs on a 68040 or a Cortex-M. Rotations R are 3x3 row-major
 * (double[9]); transforms T are 4x4 row-major (double[16]).
 */
#ifndef TANDEM_VEC3_H
#define TANDEM_VEC3_H

void vec3_set(double out[3], double x, double y, double z);
void vec3_copy(double out[3], const double a[3]);
/* vec3_add, vec3_sub, vec3_dot and vec3_cross are C99 inline definitions
 * (vec3.c holds the external ones): the kinematics and dynamics call them
 * a few dozen times per control cycle, and a call costs more than the
 * arithmetic on the 68040 (arguments through memory). */
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
void vec3_scale(double out[3], const double a[3], double k);
/* out = a + k b */
void vec3_axpy(double out[3], const double a[3], double k, const double b[3]);
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
double vec3_norm(const double a[3]);
/* Returns the norm before normalising; leaves a zero vector unchanged. */
double vec3_normalize(double out[3], const double a[3]);

void rot_identity(double R[9]);
void rot_mul(double out[9], const double A[9], const double B[9]);
/* out = A^T B */
void rot_tmul(double out[9], const double A[9], const double B[9]);
void rot_apply(double out[3], const double R[9], const double v[3]);
/* out = R^T v */
void rot_tapply(double out[3], const double R[9], const double v[3]);
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
void tf_rot(double R[9], const double T[16]);
void tf_pos(double p[3], const double T[16]);
/* out = R p + t: the point p carried by T (out may alias p). */
void tf_apply(double out[3], const double T[16], const double p[3]);
/* out = T^-1 for a rigid transform. */
void tf_inverse(double out[16], const double T[16]);

#endif

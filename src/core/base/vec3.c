/* vec3: 3-vectors, rotations and rigid transforms (see vec3.h).
 * Pure geometry used by every equation of docs/method/; no state, no allocation.
 */
#include "vec3.h"
#include "trig.h"
#include <math.h>

/* The external definitions of vec3.h's inline ones (C99 6.7.4). */
void vec3_set(double out[3], double x, double y, double z);
void vec3_copy(double out[3], const double a[3]);
void vec3_add(double out[3], const double a[3], const double b[3]);
void vec3_sub(double out[3], const double a[3], const double b[3]);
void vec3_scale(double out[3], const double a[3], double k);
void vec3_axpy(double out[3], const double a[3], double k, const double b[3]);
double vec3_dot(const double a[3], const double b[3]);
void vec3_cross(double out[3], const double a[3], const double b[3]);
double vec3_norm(const double a[3]);
void rot_apply(double out[3], const double R[9], const double v[3]);
void rot_tapply(double out[3], const double R[9], const double v[3]);
void tf_rot(double R[9], const double T[16]);
void tf_apply(double out[3], const double T[16], const double p[3]);

double vec3_normalize(double out[3], const double a[3])
{
    const double n = vec3_norm(a);
    if (n > 0.0)
        vec3_scale(out, a, 1.0 / n);
    else
        vec3_copy(out, a);
    return n;
}

void rot_identity(double R[9])
{
    int i;
    for (i = 0; i < 9; i++)
        R[i] = (i % 4 == 0) ? 1.0 : 0.0;
}

void rot_mul(double out[9], const double A[9], const double B[9])
{
    double t[9];
    int r, c;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            t[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
    for (r = 0; r < 9; r++)
        out[r] = t[r];
}

void rot_tmul(double out[9], const double A[9], const double B[9])
{
    double At[9];
    rot_transpose(At, A);
    rot_mul(out, At, B);
}

void rot_transpose(double out[9], const double R[9])
{
    double t[9];
    int r, c;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            t[3 * c + r] = R[3 * r + c];
    for (r = 0; r < 9; r++)
        out[r] = t[r];
}

void rot_from_unit_axis_sc(double R[9], const double k[3], double s, double c)
{
    const double v = 1.0 - c;
    R[0] = k[0] * k[0] * v + c;
    R[1] = k[0] * k[1] * v - k[2] * s;
    R[2] = k[0] * k[2] * v + k[1] * s;
    R[3] = k[1] * k[0] * v + k[2] * s;
    R[4] = k[1] * k[1] * v + c;
    R[5] = k[1] * k[2] * v - k[0] * s;
    R[6] = k[2] * k[0] * v - k[1] * s;
    R[7] = k[2] * k[1] * v + k[0] * s;
    R[8] = k[2] * k[2] * v + c;
}

void rot_from_axis_angle(double R[9], const double axis[3], double angle_rad)
{
    double k[3];
    if (vec3_normalize(k, axis) == 0.0) {
        rot_identity(R);
        return;
    }
    rot_from_unit_axis_sc(R, k, sin(angle_rad), cos(angle_rad));
}

double rot_to_axis_angle(double axis[3], const double R[9])
{
    /* Via the quaternion: well conditioned at 0 and at pi. */
    double q[4], n;
    rot_to_quat(q, R);
    if (q[0] < 0.0) {
        q[0] = -q[0];
        q[1] = -q[1];
        q[2] = -q[2];
        q[3] = -q[3];
    }
    n = vec3_norm(q + 1);
    if (n < 1e-15) {
        vec3_set(axis, 1.0, 0.0, 0.0);
        return 0.0;
    }
    vec3_scale(axis, q + 1, 1.0 / n);
    return 2.0 * trig_atan2(n, q[0]); /* libm's traps to the 68040's FPSP three times */
}

void rot_from_quat(double R[9], const double q_wxyz[4])
{
    double q[4], n;
    int i;
    n = sqrt(q_wxyz[0] * q_wxyz[0] + q_wxyz[1] * q_wxyz[1] + q_wxyz[2] * q_wxyz[2] +
             q_wxyz[3] * q_wxyz[3]);
    if (n == 0.0) {
        rot_identity(R);
        return;
    }
    for (i = 0; i < 4; i++)
        q[i] = q_wxyz[i] / n;
    R[0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]);
    R[1] = 2 * (q[1] * q[2] - q[0] * q[3]);
    R[2] = 2 * (q[1] * q[3] + q[0] * q[2]);
    R[3] = 2 * (q[1] * q[2] + q[0] * q[3]);
    R[4] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]);
    R[5] = 2 * (q[2] * q[3] - q[0] * q[1]);
    R[6] = 2 * (q[1] * q[3] - q[0] * q[2]);
    R[7] = 2 * (q[2] * q[3] + q[0] * q[1]);
    R[8] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
}

void rot_to_quat(double q[4], const double R[9])
{
    /* Shepperd's method: pick the largest diagonal term for stability. */
    const double tr = R[0] + R[4] + R[8];
    double s;
    if (tr > R[0] && tr > R[4] && tr > R[8]) {
        s = 2.0 * sqrt(1.0 + tr);
        q[0] = 0.25 * s;
        q[1] = (R[7] - R[5]) / s;
        q[2] = (R[2] - R[6]) / s;
        q[3] = (R[3] - R[1]) / s;
    } else if (R[0] > R[4] && R[0] > R[8]) {
        s = 2.0 * sqrt(1.0 + R[0] - R[4] - R[8]);
        q[0] = (R[7] - R[5]) / s;
        q[1] = 0.25 * s;
        q[2] = (R[1] + R[3]) / s;
        q[3] = (R[2] + R[6]) / s;
    } else if (R[4] > R[8]) {
        s = 2.0 * sqrt(1.0 + R[4] - R[0] - R[8]);
        q[0] = (R[2] - R[6]) / s;
        q[1] = (R[1] + R[3]) / s;
        q[2] = 0.25 * s;
        q[3] = (R[5] + R[7]) / s;
    } else {
        s = 2.0 * sqrt(1.0 + R[8] - R[0] - R[4]);
        q[0] = (R[3] - R[1]) / s;
        q[1] = (R[2] + R[6]) / s;
        q[2] = (R[5] + R[7]) / s;
        q[3] = 0.25 * s;
    }
}

void tf_identity(double T[16])
{
    int i;
    for (i = 0; i < 16; i++)
        T[i] = (i % 5 == 0) ? 1.0 : 0.0;
}

void tf_mul(double out[16], const double A[16], const double B[16])
{
    double t[16];
    int r, c, k;
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++) {
            double acc = 0.0;
            for (k = 0; k < 4; k++)
                acc += A[4 * r + k] * B[4 * k + c];
            t[4 * r + c] = acc;
        }
    for (r = 0; r < 16; r++)
        out[r] = t[r];
}

void tf_from_rot_pos(double T[16], const double R[9], const double p[3])
{
    int r;
    for (r = 0; r < 3; r++) {
        T[4 * r] = R[3 * r];
        T[4 * r + 1] = R[3 * r + 1];
        T[4 * r + 2] = R[3 * r + 2];
        T[4 * r + 3] = p[r];
    }
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
}

void tf_pos(double p[3], const double T[16])
{
    p[0] = T[3];
    p[1] = T[7];
    p[2] = T[11];
}

void tf_inverse(double out[16], const double T[16])
{
    double R[9], Rt[9], p[3], pi[3];
    tf_rot(R, T);
    tf_pos(p, T);
    rot_transpose(Rt, R);
    rot_apply(pi, Rt, p);
    vec3_scale(pi, pi, -1.0);
    tf_from_rot_pos(out, Rt, pi);
}

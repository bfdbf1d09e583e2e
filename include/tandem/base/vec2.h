/* vec2: planar poses and angle helpers shared by the seed-003 modules
 * (unicycle, behaviour, formation, team, odometry, sonar).
 */
#ifndef TANDEM_VEC2_H
#define TANDEM_VEC2_H

#define VEC2_PI 3.14159265358979323846

/* A planar pose: position of a point and the robot heading. */
typedef struct {
    double x_m;
    double y_m;
    double theta_rad;
} pose2;

/* Wrap an angle to (-pi, pi]. */
double vec2_wrap_rad(double a_rad);
/* Smallest signed difference a - b, wrapped to (-pi, pi]. */
double vec2_angle_diff_rad(double a_rad, double b_rad);
double vec2_norm(double x, double y);
/* Rotate (x, y) by angle a: out = R(a) (x, y). */
void vec2_rotate(double out[2], double x, double y, double a_rad);
/* 1 if every value is finite. */
int vec2_finite3(double a, double b, double c);
int vec2_pose_finite(const pose2 *p);

#endif

/* vec2: planar pose and angle helpers for the seed-003 formation core
 * (docs/method/formation.md). Pure C99 + libm.
 */
#include "vec2.h"

#include <math.h>

double vec2_wrap_rad(double a_rad)
{
    const double two_pi = 2.0 * VEC2_PI;
    double a = fmod(a_rad, two_pi);
    if (a <= -VEC2_PI)
        a += two_pi;
    else if (a > VEC2_PI)
        a -= two_pi;
    return a;
}

double vec2_angle_diff_rad(double a_rad, double b_rad)
{
    return vec2_wrap_rad(a_rad - b_rad);
}

double vec2_norm(double x, double y)
{
    return hypot(x, y);
}

void vec2_rotate(double out[2], double x, double y, double a_rad)
{
    const double c = cos(a_rad), s = sin(a_rad);
    out[0] = c * x - s * y;
    out[1] = s * x + c * y;
}

int vec2_finite3(double a, double b, double c)
{
    return isfinite(a) && isfinite(b) && isfinite(c);
}

int vec2_pose_finite(const pose2 *p)
{
    return p != 0 && vec2_finite3(p->x_m, p->y_m, p->theta_rad);
}

/* odometry: differential-drive dead reckoning (docs/method/formation.md: no global
 * positioning, each robot knows itself by odometry). Each encoder increment
 * is taken as a constant-curvature arc of C (exact for constant wheel
 * speeds between samples) and integrated with unicycle_step_exact.
 */
#include "odometry.h"
#include "unicycle.h"

#include <math.h>

int odometry_init(odometer *o, double wheel_radius_m, double axle_track_m, double d_m,
                  const pose2 *c0, double left0_rad, double right0_rad)
{
    if (!(wheel_radius_m > 0.0) || !(axle_track_m > 0.0) || !isfinite(wheel_radius_m) ||
        !isfinite(axle_track_m) || !isfinite(d_m) || !vec2_pose_finite(c0) ||
        !isfinite(left0_rad) || !isfinite(right0_rad))
        return ODOMETRY_ERR_ARG;
    o->wheel_radius_m = wheel_radius_m;
    o->axle_track_m = axle_track_m;
    o->d_m = d_m;
    o->last_left_rad = left0_rad;
    o->last_right_rad = right0_rad;
    o->dist_m = 0.0;
    o->c = *c0;
    o->c.theta_rad = vec2_wrap_rad(c0->theta_rad);
    return 0;
}

int odometry_update(odometer *o, double left_rad, double right_rad, double *ds_m,
                    double *dtheta_rad)
{
    double dl, dr, ds, dth;
    if (!isfinite(left_rad) || !isfinite(right_rad))
        return ODOMETRY_ERR_ARG;
    dl = (left_rad - o->last_left_rad) * o->wheel_radius_m;
    dr = (right_rad - o->last_right_rad) * o->wheel_radius_m;
    ds = 0.5 * (dl + dr);
    dth = (dr - dl) / o->axle_track_m;
    /* (V, w) = (ds, dth) over a unit interval is the same arc. */
    if (unicycle_step_exact(&o->c, ds, dth, 1.0) != 0)
        return ODOMETRY_ERR_ARG;
    o->last_left_rad = left_rad;
    o->last_right_rad = right_rad;
    o->dist_m += fabs(ds);
    if (ds_m)
        *ds_m = ds;
    if (dtheta_rad)
        *dtheta_rad = dth;
    return 0;
}

void odometry_pose_c(const odometer *o, pose2 *c)
{
    *c = o->c;
}

void odometry_pose_o(const odometer *o, pose2 *p)
{
    unicycle_o_from_c(p, &o->c, o->d_m);
}

/* odometry: differential-drive dead reckoning from accumulated wheel
 * encoder angles (docs/method/formation.md, sonar.md: each robot knows itself only by
 * odometry). Integrates the pose of the axle centre C exactly along the arc
 * implied by each encoder increment; O (the beacon) is at the signed
 * distance d behind C (d < 0: ahead, unicycle.h).
 */
#ifndef TANDEM_ODOMETRY_H
#define TANDEM_ODOMETRY_H

#include "vec2.h"

#define ODOMETRY_ERR_ARG (-1) /* non-positive geometry or non-finite input */

typedef struct {
    double wheel_radius_m;
    double axle_track_m; /* distance between the wheel contact points */
    double d_m;          /* O lies d_m behind C (signed) */
    double last_left_rad;
    double last_right_rad;
    double dist_m; /* path length of C travelled, for logging */
    pose2 c;       /* pose of C */
} odometer;

/* Pioneer 2 DX nominal geometry. */
#define ODOMETRY_P2DX_WHEEL_RADIUS_M 0.0825
#define ODOMETRY_P2DX_AXLE_TRACK_M 0.33

/* Start at pose c0 (of C) with the encoders currently reading
 * (left0, right0). ODOMETRY_ERR_ARG on non-positive geometry or non-finite input. */
int odometry_init(odometer *o, double wheel_radius_m, double axle_track_m, double d_m,
                  const pose2 *c0, double left0_rad, double right0_rad);

/* New accumulated encoder readings. Returns ODOMETRY_ERR_ARG (state unchanged) on
 * non-finite input. Optionally returns the increment as (ds, dtheta). */
int odometry_update(odometer *o, double left_rad, double right_rad, double *ds_m,
                    double *dtheta_rad);

void odometry_pose_c(const odometer *o, pose2 *c);
void odometry_pose_o(const odometer *o, pose2 *p);

#endif

/* localize: one Pioneer's own pose from its own sensors (docs/method/
 * formation.md, distribution: odometry corrected by fixed LED landmarks seen by its
 * camera; never ground truth). A fixed-size extended Kalman filter on the
 * pose of the axle centre C, s = (x, y, theta):
 *
 *   predict (each encoder increment ds, dtheta; midpoint arc):
 *     x += ds cos(theta + dtheta/2), y += ds sin(theta + dtheta/2),
 *     theta += dtheta;
 *     P = F P F^T + G Q G^T, Q = diag(k_ds^2 |ds|,
 *                                     k_th_ds^2 |ds| + k_th_dth^2 |dtheta|)
 *     (wheel slip is a random walk per metre driven and per radian turned:
 *     variances grow linearly with both);
 *   update (camera at O = C - d (cos theta, sin theta), d signed as in
 *   unicycle.h, sees landmark L at range r and bearing b from the heading):
 *     z = (|L - O|, atan2(L - O) - theta), R = diag((r0 + r1 r)^2, sb^2),
 *     innovation gated by its Mahalanobis distance (chi-square, 2 dof),
 *     Joseph-form covariance update (stays symmetric positive definite);
 *   recovery: reject_reset landmark sightings gated out in a row mean the
 *     estimate has left its covariance (a robot pushing against a wall
 *     spins its wheels: the encoders run, the robot does not); the position
 *     and heading variances are then raised by reset_sd_xy_m^2 and
 *     reset_sd_theta_rad^2 so the next sightings pull it back.
 *
 * Landmarks are identified (each LED blinks its own code, as the robots'
 * beacons do): no data association beyond the gate. Capacity
 * LOCALIZE_LANDMARKS_MAX, no allocation.
 */
#ifndef TANDEM_LOCALIZE_H
#define TANDEM_LOCALIZE_H

#include "vec2.h"

#define LOCALIZE_ERR_ARG \
    (-1) /* NULL, non-finite input, parameter out of
                                  range, unknown landmark, or a degenerate
                                  measurement (landmark at the camera,
                                  innovation covariance not positive)     */

#define LOCALIZE_LANDMARKS_MAX 64

typedef struct {
    double d_m;         /* camera (O) lies d behind C, signed */
    double k_ds;        /* distance noise, m per sqrt(m) driven */
    double k_th_ds;     /* heading noise, rad per sqrt(m) driven */
    double k_th_dth;    /* heading noise, rad per sqrt(rad) turned */
    double range_sd0_m; /* camera range noise: r0 + r1 r */
    double range_sd1;
    double bearing_sd_rad;
    double gate_chi2; /* reject innovations beyond this (2 dof) */
    int reject_reset; /* this many rejections in a row: inflate P */
    double reset_sd_xy_m, reset_sd_theta_rad;
} localize_params;

typedef struct {
    localize_params p;
    double s[3]; /* x_m, y_m, theta_rad of C */
    double P[9]; /* covariance, row-major */
    int n_lm;
    double lm[LOCALIZE_LANDMARKS_MAX][2];
    long accepted, rejected, resets;
    int rejected_run; /* rejections since the last fused sighting */
} localizer;

/* Defaults for the simulated Pioneer 2 DX and camera (sim/models/sim_rovers_sense.c:
 * slip 0.5 % of rim speed per wheel, camera 1 cm + 2 % range, 0.6 deg
 * bearing), each inflated about 2-3x for what the filter does not model
 * (slip correlation time, the 0.1 s camera period): k_ds 0.01 m/sqrt(m),
 * k_th_ds 0.03 rad/sqrt(m), k_th_dth 0.02 rad/sqrt(rad), range 0.02 m +
 * 3 %, bearing 0.02 rad, gate 13.8 (99.9 %); reset after 10 rejections
 * in a row by 0.5 m and 0.3 rad. d -0.15 m. */
void localize_params_default(localize_params *p);
int localize_params_validate(const localize_params *p);

/* Start at C pose c0 with standard deviations sd_xy_m, sd_theta_rad, and
 * the n landmark positions lm (same frame as c0). LOCALIZE_ERR_ARG on bad input
 * (n outside 0..LOCALIZE_LANDMARKS_MAX, non-finite, negative sd). */
int localize_init(localizer *l, const localize_params *p, const pose2 *c0, double sd_xy_m,
                  double sd_theta_rad, const double (*lm)[2], int n);

/* Odometry increment of C (path length ds, heading change dtheta). */
int localize_predict(localizer *l, double ds_m, double dtheta_rad);

/* Camera sees landmark k at (range, bearing from the heading). Returns 1
 * if fused, 0 if gated out, LOCALIZE_ERR_ARG on bad input (k unknown, non-finite). */
int localize_landmark(localizer *l, int k, double range_m, double bearing_rad);

/* Expected measurement of landmark k from pose s and its Jacobian
 * H (2x3, row-major) (exposed for the finite-difference test). LOCALIZE_ERR_ARG if the
 * landmark sits on the camera. */
int localize_measure(const localizer *l, const double s[3], int k, double z[2], double H[6]);

/* Pose of C, and of O (the camera, beacon). */
void localize_pose_c(const localizer *l, pose2 *c);
void localize_pose_o(const localizer *l, pose2 *o);

/* Shift the position estimate (the frame consensus moves it). */
void localize_shift(localizer *l, double dx_m, double dy_m);

#endif

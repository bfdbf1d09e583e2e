/* unicycle: kinematic model of a Pioneer-style robot (docs/method/formation.md).
 *
 * The unicycle point is C, the wheel-axle centre, with heading theta and
 * controls (V, w): C' = V (cos theta, sin theta), theta' = w. The tracked
 * point O (the LED beacon, the robot's own origin, what team messages and
 * the behaviours use) lies on the heading line at the SIGNED distance d:
 *     O = C - d (cos theta, sin theta)
 *     O' = V (cos theta, sin theta) + d w (sin theta, -cos theta)
 * d > 0 puts O behind C (the seed's eq. 3 as written), d < 0 ahead of it
 * (the Pioneer team flies d = -0.15 m: docs/formation.md derives why).
 *
 * Saturation (seed eq. 6 and eq. 10): the seed clips V and w independently
 * to [-V_max, V_max] x [-w_max, w_max] (UNICYCLE_SAT_CLIP). That changes the
 * turning radius V/w when only one of them saturates; UNICYCLE_SAT_SCALE
 * scales both by one factor instead, which keeps the radius (and the sign
 * of both). The behaviours default to CLIP because it is what the seed does
 * and because far from the goal it keeps the full heading correction while
 * V is capped (SCALE would shrink w by V_max / V and turn very slowly).
 */
#ifndef TANDEM_UNICYCLE_H
#define TANDEM_UNICYCLE_H

#include "vec2.h"

#define UNICYCLE_ERR_ARG (-1) /* non-finite input (the output is then 0) */

/* A control (V, w). */
typedef struct {
    double v_mps;
    double w_radps;
} unicycle_cmd;

/* A moving unicycle: pose of O plus its controls; also the team reference
 * R0 = (x0, y0, theta0, V0, w0). */
typedef struct {
    double x_m;
    double y_m;
    double theta_rad;
    double v_mps;
    double w_radps;
} unicycle_state;

enum {
    UNICYCLE_SAT_CLIP = 0, /* seed eq. 6 / 10: per component */
    UNICYCLE_SAT_SCALE = 1 /* one factor for both: keeps V / w */
};

/* Pose of O from pose of C (and back); same heading. d_m signed (above). */
void unicycle_o_from_c(pose2 *o, const pose2 *c, double d_m);
void unicycle_c_from_o(pose2 *c, const pose2 *o, double d_m);

/* Velocity of O for controls (V, w) at heading theta. */
void unicycle_o_velocity(double out[2], double theta_rad, double v_mps, double w_radps, double d_m);

/* Exact integration of C over dt with constant (V, w): a circular arc
 * (straight line when |w dt| is tiny). Returns UNICYCLE_ERR_ARG on non-finite input. */
int unicycle_step_exact(pose2 *c, double v_mps, double w_radps, double dt_s);

/* Classical RK4 of the same ODE (for cross-checking the exact arc). */
int unicycle_step_rk4(pose2 *c, double v_mps, double w_radps, double dt_s);

/* Saturate (V, w) to (v_max, w_max) with mode UNICYCLE_SAT_*. Non-finite
 * input gives (0, 0) and UNICYCLE_ERR_ARG. Returns 1 if anything was limited, else 0. */
int unicycle_saturate(unicycle_cmd *out, const unicycle_cmd *in, double v_max_mps,
                      double w_max_radps, int mode);

#endif

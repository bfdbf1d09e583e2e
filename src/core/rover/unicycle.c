/* unicycle: kinematics of the wheel-axle centre C and of the tracked point
 * O at the signed distance d behind it (d < 0: ahead) (docs/method/formation.md,
 * seed eqs. 1, 3), exact-arc and RK4 integration, and the (V, w)
 * saturation of seed eqs. 6 and 10.
 */
#include "unicycle.h"

#include <math.h>

void unicycle_o_from_c(pose2 *o, const pose2 *c, double d_m)
{
    const double th = c->theta_rad;
    o->x_m = c->x_m - d_m * cos(th);
    o->y_m = c->y_m - d_m * sin(th);
    o->theta_rad = th;
}

void unicycle_c_from_o(pose2 *c, const pose2 *o, double d_m)
{
    const double th = o->theta_rad;
    c->x_m = o->x_m + d_m * cos(th);
    c->y_m = o->y_m + d_m * sin(th);
    c->theta_rad = th;
}

void unicycle_o_velocity(double out[2], double theta_rad, double v_mps, double w_radps, double d_m)
{
    const double c = cos(theta_rad), s = sin(theta_rad);
    out[0] = v_mps * c + d_m * w_radps * s;
    out[1] = v_mps * s - d_m * w_radps * c;
}

int unicycle_step_exact(pose2 *c, double v_mps, double w_radps, double dt_s)
{
    const double th = c->theta_rad;
    const double dth = w_radps * dt_s;
    double fwd, side;
    if (!vec2_pose_finite(c) || !vec2_finite3(v_mps, w_radps, dt_s))
        return UNICYCLE_ERR_ARG;
    if (fabs(dth) < 1e-9) {
        /* Second-order series of the arc: avoids 0/0 and loses nothing. */
        fwd = v_mps * dt_s * (1.0 - dth * dth / 6.0);
        side = v_mps * dt_s * (dth / 2.0);
    } else {
        const double R = v_mps / w_radps;
        fwd = R * sin(dth);
        side = R * (1.0 - cos(dth));
    }
    c->x_m += fwd * cos(th) - side * sin(th);
    c->y_m += fwd * sin(th) + side * cos(th);
    c->theta_rad = vec2_wrap_rad(th + dth);
    return 0;
}

static void unicycle_deriv(double k[3], double th, double v, double w)
{
    k[0] = v * cos(th);
    k[1] = v * sin(th);
    k[2] = w;
}

int unicycle_step_rk4(pose2 *c, double v_mps, double w_radps, double dt_s)
{
    double k1[3], k2[3], k3[3], k4[3];
    const double th = c->theta_rad;
    if (!vec2_pose_finite(c) || !vec2_finite3(v_mps, w_radps, dt_s))
        return UNICYCLE_ERR_ARG;
    unicycle_deriv(k1, th, v_mps, w_radps);
    unicycle_deriv(k2, th + 0.5 * dt_s * k1[2], v_mps, w_radps);
    unicycle_deriv(k3, th + 0.5 * dt_s * k2[2], v_mps, w_radps);
    unicycle_deriv(k4, th + dt_s * k3[2], v_mps, w_radps);
    c->x_m += dt_s / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]);
    c->y_m += dt_s / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]);
    c->theta_rad = vec2_wrap_rad(th + dt_s * w_radps);
    return 0;
}

static double clampd(double x, double lim)
{
    return x > lim ? lim : (x < -lim ? -lim : x);
}

int unicycle_saturate(unicycle_cmd *out, const unicycle_cmd *in, double v_max_mps,
                      double w_max_radps, int mode)
{
    const double v = in->v_mps, w = in->w_radps;
    const double vm = fabs(v_max_mps), wm = fabs(w_max_radps);
    if (!isfinite(v) || !isfinite(w) || !isfinite(vm) || !isfinite(wm)) {
        out->v_mps = 0.0;
        out->w_radps = 0.0;
        return UNICYCLE_ERR_ARG;
    }
    if (mode == UNICYCLE_SAT_SCALE) {
        double k = 1.0;
        if (fabs(v) > vm)
            k = vm / fabs(v);
        if (fabs(w) * k > wm)
            k = wm / fabs(w);
        out->v_mps = v * k;
        out->w_radps = w * k;
        return k < 1.0;
    }
    out->v_mps = clampd(v, vm);
    out->w_radps = clampd(w, wm);
    return fabs(v) > vm || fabs(w) > wm;
}

/* localize: EKF of one Pioneer's axle-centre pose from its encoder
 * increments and its camera's range and bearing to known LED landmarks
 * (docs/method/formation.md: odometry corrected only by the robot's own sensors;
 * equations in localize.h and docs/formation.md "Localization").
 */
#include "localize.h"
#include "linalg.h"
#include "unicycle.h"

#include <math.h>
#include <string.h>

void localize_params_default(localize_params *p)
{
    p->d_m = -0.15;
    p->k_ds = 0.01;
    p->k_th_ds = 0.03;
    p->k_th_dth = 0.02;
    p->range_sd0_m = 0.02;
    p->range_sd1 = 0.03;
    p->bearing_sd_rad = 0.02;
    p->gate_chi2 = 13.8;
    p->reject_reset = 10;
    p->reset_sd_xy_m = 0.5;
    p->reset_sd_theta_rad = 0.3;
}

int localize_params_validate(const localize_params *p)
{
    double nonneg[4];
    size_t i;
    if (!p)
        return LOCALIZE_ERR_ARG;
    /* read only once p is known to be there */
    nonneg[0] = p->k_ds;
    nonneg[1] = p->k_th_ds;
    nonneg[2] = p->k_th_dth;
    nonneg[3] = p->range_sd1;
    if (!isfinite(p->d_m) || p->reject_reset < 1 || !isfinite(p->reset_sd_xy_m) ||
        !(p->reset_sd_xy_m > 0.0) || !isfinite(p->reset_sd_theta_rad) ||
        !(p->reset_sd_theta_rad > 0.0))
        return LOCALIZE_ERR_ARG;
    for (i = 0; i < sizeof nonneg / sizeof nonneg[0]; i++)
        if (!isfinite(nonneg[i]) || nonneg[i] < 0.0)
            return LOCALIZE_ERR_ARG;
    if (!isfinite(p->range_sd0_m) || !(p->range_sd0_m > 0.0) || !isfinite(p->bearing_sd_rad) ||
        !(p->bearing_sd_rad > 0.0) || !isfinite(p->gate_chi2) || !(p->gate_chi2 > 0.0))
        return LOCALIZE_ERR_ARG;
    return 0;
}

int localize_init(localizer *l, const localize_params *p, const pose2 *c0, double sd_xy_m,
                  double sd_theta_rad, const double (*lm)[2], int n)
{
    int k;
    if (!l || localize_params_validate(p) != 0 || !c0 || !vec2_pose_finite(c0) ||
        !isfinite(sd_xy_m) || sd_xy_m < 0.0 || !isfinite(sd_theta_rad) || sd_theta_rad < 0.0 ||
        n < 0 || n > LOCALIZE_LANDMARKS_MAX || (n > 0 && !lm))
        return LOCALIZE_ERR_ARG;
    for (k = 0; k < n; k++)
        if (!isfinite(lm[k][0]) || !isfinite(lm[k][1]))
            return LOCALIZE_ERR_ARG;
    memset(l, 0, sizeof *l);
    l->p = *p;
    l->s[0] = c0->x_m;
    l->s[1] = c0->y_m;
    l->s[2] = vec2_wrap_rad(c0->theta_rad);
    l->P[0] = l->P[4] = sd_xy_m * sd_xy_m;
    l->P[8] = sd_theta_rad * sd_theta_rad;
    l->n_lm = n;
    for (k = 0; k < n; k++) {
        l->lm[k][0] = lm[k][0];
        l->lm[k][1] = lm[k][1];
    }
    return 0;
}

/* P = (P + P^T) / 2: rounding must not make it drift from symmetric. */
static void symmetrize(double P[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = i + 1; j < 3; j++)
            P[3 * i + j] = P[3 * j + i] = 0.5 * (P[3 * i + j] + P[3 * j + i]);
}

int localize_predict(localizer *l, double ds_m, double dtheta_rad)
{
    const double a = l->s[2] + 0.5 * dtheta_rad;
    const double ca = cos(a), sa = sin(a);
    /* F = d s' / d s, G = d s' / d (ds, dtheta) of the midpoint arc */
    const double F[9] = { 1, 0, -ds_m * sa, 0, 1, ds_m * ca, 0, 0, 1 };
    const double G[6] = { ca, -0.5 * ds_m * sa, sa, 0.5 * ds_m * ca, 0, 1 };
    double q[2], FP[9], GQ[6], Q[9];
    int i;
    if (!isfinite(ds_m) || !isfinite(dtheta_rad))
        return LOCALIZE_ERR_ARG;
    q[0] = l->p.k_ds * l->p.k_ds * fabs(ds_m);
    q[1] = l->p.k_th_ds * l->p.k_th_ds * fabs(ds_m) +
           l->p.k_th_dth * l->p.k_th_dth * fabs(dtheta_rad);
    l->s[0] += ds_m * ca;
    l->s[1] += ds_m * sa;
    l->s[2] = vec2_wrap_rad(l->s[2] + dtheta_rad);
    linalg_mul(FP, F, l->P, 3, 3, 3);
    linalg_mul_t(l->P, FP, F, 3, 3, 3);
    for (i = 0; i < 3; i++) {
        GQ[2 * i] = G[2 * i] * q[0];
        GQ[2 * i + 1] = G[2 * i + 1] * q[1];
    }
    linalg_mul_t(Q, GQ, G, 3, 2, 3);
    for (i = 0; i < 9; i++)
        l->P[i] += Q[i];
    symmetrize(l->P);
    return 0;
}

int localize_measure(const localizer *l, const double s[3], int k, double z[2], double H[6])
{
    const double c = cos(s[2]), sn = sin(s[2]), d = l->p.d_m;
    double dx, dy, r2, r, dO_dth[2];
    if (k < 0 || k >= l->n_lm)
        return LOCALIZE_ERR_ARG;
    dx = l->lm[k][0] - (s[0] - d * c);
    dy = l->lm[k][1] - (s[1] - d * sn);
    r2 = dx * dx + dy * dy;
    if (!(r2 > 1e-12))
        return LOCALIZE_ERR_ARG;
    r = sqrt(r2);
    z[0] = r;
    z[1] = vec2_wrap_rad(atan2(dy, dx) - s[2]);
    /* O = C - d (cos, sin): dO/dtheta = d (sin, -cos) */
    dO_dth[0] = d * sn;
    dO_dth[1] = -d * c;
    H[0] = -dx / r;
    H[1] = -dy / r;
    H[2] = H[0] * dO_dth[0] + H[1] * dO_dth[1];
    H[3] = dy / r2;
    H[4] = -dx / r2;
    H[5] = H[3] * dO_dth[0] + H[4] * dO_dth[1] - 1.0;
    return 0;
}

int localize_landmark(localizer *l, int k, double range_m, double bearing_rad)
{
    double z[2], H[6], nu[2], HP[6], S[4], Si[4], det, K[6], IKH[9], A[9], B[9], KR[6], R[4];
    double sr;
    int i, j;
    if (!l || !isfinite(range_m) || range_m < 0.0 || !isfinite(bearing_rad) ||
        localize_measure(l, l->s, k, z, H) != 0)
        return LOCALIZE_ERR_ARG;
    nu[0] = range_m - z[0];
    nu[1] = vec2_wrap_rad(bearing_rad - z[1]);
    sr = l->p.range_sd0_m + l->p.range_sd1 * range_m;
    R[0] = sr * sr;
    R[1] = R[2] = 0.0;
    R[3] = l->p.bearing_sd_rad * l->p.bearing_sd_rad;
    linalg_mul(HP, H, l->P, 2, 3, 3);
    linalg_mul_t(S, HP, H, 2, 3, 2);
    for (i = 0; i < 4; i++)
        S[i] += R[i];
    det = S[0] * S[3] - S[1] * S[2];
    if (!(det > 0.0))
        return LOCALIZE_ERR_ARG;
    Si[0] = S[3] / det;
    Si[1] = -S[1] / det;
    Si[2] = -S[2] / det;
    Si[3] = S[0] / det;
    if (nu[0] * (Si[0] * nu[0] + Si[1] * nu[1]) + nu[1] * (Si[2] * nu[0] + Si[3] * nu[1]) >
        l->p.gate_chi2) {
        l->rejected++;
        if (++l->rejected_run >= l->p.reject_reset) {
            l->P[0] += l->p.reset_sd_xy_m * l->p.reset_sd_xy_m;
            l->P[4] += l->p.reset_sd_xy_m * l->p.reset_sd_xy_m;
            l->P[8] += l->p.reset_sd_theta_rad * l->p.reset_sd_theta_rad;
            l->rejected_run = 0;
            l->resets++;
        }
        return 0;
    }
    l->rejected_run = 0;
    /* K = P H^T S^-1 = (HP)^T S^-1 */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 2; j++)
            K[2 * i + j] = HP[i] * Si[j] + HP[3 + i] * Si[2 + j];
    for (i = 0; i < 3; i++)
        l->s[i] += K[2 * i] * nu[0] + K[2 * i + 1] * nu[1];
    l->s[2] = vec2_wrap_rad(l->s[2]);
    /* Joseph form: P = (I - KH) P (I - KH)^T + K R K^T */
    linalg_mul(IKH, K, H, 3, 2, 3);
    for (i = 0; i < 9; i++)
        IKH[i] = (i % 4 == 0 ? 1.0 : 0.0) - IKH[i];
    linalg_mul(A, IKH, l->P, 3, 3, 3);
    linalg_mul_t(B, A, IKH, 3, 3, 3);
    linalg_mul(KR, K, R, 3, 2, 2);
    linalg_mul_t(A, KR, K, 3, 2, 3);
    for (i = 0; i < 9; i++)
        l->P[i] = B[i] + A[i];
    symmetrize(l->P);
    l->accepted++;
    return 1;
}

void localize_pose_c(const localizer *l, pose2 *c)
{
    c->x_m = l->s[0];
    c->y_m = l->s[1];
    c->theta_rad = l->s[2];
}

void localize_pose_o(const localizer *l, pose2 *o)
{
    pose2 c;
    localize_pose_c(l, &c);
    unicycle_o_from_c(o, &c, l->p.d_m);
}

void localize_shift(localizer *l, double dx_m, double dy_m)
{
    l->s[0] += dx_m;
    l->s[1] += dy_m;
}

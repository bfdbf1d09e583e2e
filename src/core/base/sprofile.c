/* sprofile: minimum-time jerk-limited profile in the path-length domain,
 * docs/method/carry.md §2 eq. 2-4, with the short-segment case the seed omits solved in
 * closed form (see sprofile.h).
 *
 * Acceleration phase of length D with peak acceleration A (x = s - s0):
 *   [0, A/u]      a = u x                w = u x^2
 *   [A/u, D-A/u]  a = A                  w = A^2/u + 2A (x - A/u)
 *   [D-A/u, D]    a = A - u (x - D + A/u)
 * and w(D) = 2 A D - 2 A^2/u is the peak w. The deceleration phase is the
 * mirror image: a(s) = -a_acc(s_f - s), w(s) = w_acc(s_f - s).
 */
#include "sprofile.h"

#include <math.h>

static int finite_pos(double x)
{
    return isfinite(x) && x > 0.0;
}

static void zero(sprofile *p)
{
    p->s_f_m = 0.0;
    p->u_m = 1.0;
    p->a_peak = 0.0;
    p->w_peak = 0.0;
    p->d_acc_m = 0.0;
    p->x1_m = 0.0;
    p->w_x1 = 0.0;
}

int sprofile_plan(sprofile *p, double s_f_m, double v_m, double a_m, double u_m)
{
    double w_m, a0, d0, d, a;
    if (!p)
        return SPROFILE_ERR_ARG;
    zero(p);
    if (!isfinite(s_f_m) || s_f_m < 0.0 || !finite_pos(v_m) || !finite_pos(a_m) || !finite_pos(u_m))
        return SPROFILE_ERR_ARG;
    p->s_f_m = s_f_m;
    p->u_m = u_m;
    w_m = v_m * v_m;
    /* Long segment: A0 = a_m unless w_m is reached before a_m can be
     * (w_m < 2 a_m^2 / u_m); then no constant-acceleration plateau. */
    a0 = fmin(a_m, sqrt(0.5 * w_m * u_m));
    d0 = 0.5 * w_m / a0 + a0 / u_m;
    d = fmin(d0, 0.5 * s_f_m);
    /* D >= 2A/u is needed for the rise and fall of a to fit in D. */
    a = fmin(a0, 0.5 * u_m * d);
    p->d_acc_m = d;
    p->a_peak = a;
    p->w_peak = fmin(w_m, fmax(0.0, 2.0 * a * d - 2.0 * a * a / u_m));
    p->x1_m = a / u_m;
    p->w_x1 = a * a / u_m;
    return 0;
}

/* s clamped to [0, s_f] (s not NaN): fmin(fmax(s, 0), s_f) without the
 * two library calls of every control cycle. */
static double clamp_s(double s, double s_f)
{
    s = s > 0.0 ? s : 0.0;
    return s < s_f ? s : s_f;
}

/* Acceleration phase, x in [0, D]. */
static void acc_phase(const sprofile *p, double x, double *a, double *w)
{
    const double u = p->u_m, A = p->a_peak, x1 = p->x1_m, x2 = p->d_acc_m - p->x1_m;
    if (x <= x1) {
        *a = u * x;
        *w = u * x * x;
    } else if (x <= x2) {
        *a = A;
        *w = p->w_x1 + 2.0 * A * (x - x1);
    } else {
        double y = x - x2;
        *a = A - u * y;
        *w = p->w_x1 + 2.0 * A * (x2 - x1) + 2.0 * A * y - u * y * y;
    }
    if (*w > p->w_peak)
        *w = p->w_peak;
    if (*w < 0.0)
        *w = 0.0;
}

void sprofile_at(const sprofile *p, double s_m, double *a_d, double *v_d)
{
    double a = 0.0, w = 0.0, s;
    if (p && p->s_f_m > 0.0 && !isnan(s_m)) {
        s = clamp_s(s_m, p->s_f_m);
        if (s <= p->d_acc_m) {
            acc_phase(p, s, &a, &w);
        } else if (s >= p->s_f_m - p->d_acc_m) {
            acc_phase(p, p->s_f_m - s, &a, &w);
            a = -a;
        } else {
            w = p->w_peak;
        }
    }
    if (a_d)
        *a_d = a;
    if (v_d)
        *v_d = sqrt(w);
}

double sprofile_v_peak(const sprofile *p)
{
    return p ? sqrt(p->w_peak) : 0.0;
}

static double rate(const sprofile *p, double s, double v_floor)
{
    double v;
    sprofile_at(p, s, 0, &v);
    return v > v_floor ? v : v_floor;
}

/* The RK4 step from s with its first stage's rate k1 = rate(p, s, v_floor). */
static double advance_from(const sprofile *p, double s, double k1, double dt_s, double v_floor)
{
    const double k2 = rate(p, s + 0.5 * dt_s * k1, v_floor);
    const double k3 = rate(p, s + 0.5 * dt_s * k2, v_floor);
    const double k4 = rate(p, s + dt_s * k3, v_floor);
    s += dt_s * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
    return clamp_s(s, p->s_f_m);
}

double sprofile_advance(const sprofile *p, double s_m, double dt_s, double v_floor)
{
    double s;
    if (!p || !isfinite(s_m))
        return 0.0;
    s = clamp_s(s_m, p->s_f_m);
    if (!isfinite(dt_s) || dt_s <= 0.0 || !isfinite(v_floor))
        return s;
    if (v_floor < 0.0)
        v_floor = 0.0;
    return advance_from(p, s, rate(p, s, v_floor), dt_s, v_floor);
}

double sprofile_advance_at(const sprofile *p, double s_m, double rate_s, double dt_s,
                           double v_floor)
{
    if (!p || !isfinite(s_m) || !(s_m >= 0.0) || !(s_m <= p->s_f_m) || !isfinite(rate_s) ||
        !isfinite(dt_s) || dt_s <= 0.0 || !isfinite(v_floor) || v_floor < 0.0)
        return sprofile_advance(p, s_m, dt_s, v_floor);
    return advance_from(p, s_m, rate_s, dt_s, v_floor);
}

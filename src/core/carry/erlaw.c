/* erlaw: event-referenced segment control law, docs/method/carry.md §3 eq. 6-7 (with the
 * start-up bias), the orientation channel referenced by rotated angle, the
 * external reference of docs/method/carry.md §4 and the time-referenced baseline of
 * docs/method/carry.md §8. One generic channel does the arithmetic for both the line and
 * the rotation; they differ only in how progress and error are measured.
 */
#include "erlaw.h"

#include <math.h>

#include "trig.h"
#include "vec3.h"

static int finite3(const double v[3])
{
    return v && isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static double clamp(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

int erlaw_gains_validate(const erlaw_gains *g)
{
    if (!g)
        return ERLAW_ERR_ARG;
    if (!(isfinite(g->v_m) && isfinite(g->a_m) && isfinite(g->u_m) && isfinite(g->k_p) &&
          isfinite(g->k_v) && isfinite(g->k0) && isfinite(g->k1) && isfinite(g->k2)))
        return ERLAW_ERR_ARG;
    return (g->v_m > 0.0 && g->a_m > 0.0 && g->u_m > 0.0 && g->k_p >= 0.0 && g->k_v >= 0.0 &&
            g->k0 >= 0.0 && g->k2 >= 0.0)
               ? 0
               : ERLAW_ERR_ARG;
}

static int channel_init(erlaw_channel *c, const double e[3], double s_f, const erlaw_gains *g)
{
    if (erlaw_gains_validate(g) != 0)
        return ERLAW_ERR_ARG;
    if (sprofile_plan(&c->prof, s_f, g->v_m, g->a_m, g->u_m) != 0)
        return ERLAW_ERR_ARG;
    c->g = *g;
    /* Short segments: eq. 7 would already be fading at s = 0 (k2 s_f < k1)
     * and the arm might not start. Fade over the last half instead. */
    c->k2_eff = g->k2;
    if (s_f > 0.0 && g->k2 * s_f < 2.0 * g->k1)
        c->k2_eff = 2.0 * g->k1 / s_f;
    vec3_copy(c->e, e);
    c->s_time_m = 0.0;
    c->t_s = 0.0;
    c->s_ext_prev = 0.0;
    c->v_ext = 0.0;
    c->ext_seen = 0;
    c->s_resume_m = 0.0;
    c->resumed = 0;
    return 0;
}

void erlaw_channel_resume(erlaw_channel *c, double s_r)
{
    if (!c || !isfinite(s_r))
        return;
    c->s_resume_m = clamp(s_r, 0.0, c->prof.s_f_m);
    c->resumed = 1;
    c->ext_seen = 0;
}

/* The resume ramp (erlaw_channel_resume): the profile started afresh at
 * s_resume, where it is slower than the plan at s, with the full start-up
 * bias k0 while it is (eq. 7 fades near the goal, and the ramp's V_d
 * starts at 0: resumed 4 cm before the goal with the faded bias, the arm
 * crept 1 mm per 300 ms and its block detector held it for good). */
static void resume_cap(const erlaw_channel *c, double s_ref, double *a_d, double *v_d, double *b)
{
    double a_r, v_r;
    if (!c->resumed)
        return;
    sprofile_at(&c->prof, s_ref - c->s_resume_m, &a_r, &v_r);
    if (v_r < *v_d) {
        *v_d = v_r;
        *a_d = a_r;
        *b = c->g.k0;
    }
}

double erlaw_channel_length(const erlaw_channel *c)
{
    return c ? c->prof.s_f_m : 0.0;
}

static double bias(const erlaw_channel *c, double s)
{
    const erlaw_gains *g = &c->g;
    /* s is clamped to [0, s_f] so the exponent is <= k1: no overflow.
     * trig_exp, not libm's: that traps to the 68040's FPSP every cycle. */
    return g->k0 / (1.0 + trig_exp(g->k1 - c->k2_eff * (c->prof.s_f_m - s)));
}

/* V_ref: first-order filtered difference of the external reference,
 * clamped to |V_ref| <= 2 v_m (a stale or skipped partner message must not
 * become a speed spike). */
static void ext_rate_update(erlaw_channel *c, double s_ext, double dt)
{
    const double lim = 2.0 * c->g.v_m;
    if (c->ext_seen && dt > 0.0) {
        const double raw = (s_ext - c->s_ext_prev) / dt;
        c->v_ext += dt / (ERLAW_REF_RATE_TAU_S + dt) * (raw - c->v_ext);
        c->v_ext = clamp(c->v_ext, -lim, lim);
    } else if (!c->ext_seen) {
        c->v_ext = 0.0;
    }
    c->s_ext_prev = s_ext;
    c->ext_seen = 1;
}

/* Picks s_ref, advancing the baseline clock when it is the reference. */
static int channel_ref(erlaw_channel *c, double s, erlaw_ref ref, double s_ext, double dt,
                       double *s_ref)
{
    const double s_f = c->prof.s_f_m;
    if (!isfinite(dt) || dt < 0.0)
        return ERLAW_ERR_ARG;
    if (ref == ERLAW_REF_EXTERNAL && !isfinite(s_ext))
        return ERLAW_ERR_ARG;
    c->t_s += dt;
    if (ref != ERLAW_REF_EXTERNAL)
        c->ext_seen = 0;
    switch (ref) {
    /* NOLINTNEXTLINE(bugprone-branch-clone): BLOCKED keeps s for a reason of its own */
    case ERLAW_REF_MEASURED: *s_ref = s; return 0;
    case ERLAW_REF_BLOCKED:
        /* no reference motion along e (the error across it is taken from
         * the hold pose by the caller) */
        *s_ref = s;
        return 0;
    case ERLAW_REF_EXTERNAL:
        /* min semantics (docs/method/carry.md §4): never a reference ahead of oneself */
        s_ext = clamp(s_ext, 0.0, s_f);
        ext_rate_update(c, s_ext, dt);
        *s_ref = fmin(s_ext, s);
        return 0;
    case ERLAW_REF_TIME:
        c->s_time_m = sprofile_advance(&c->prof, c->s_time_m, dt,
                                       ERLAW_TIME_V_FLOOR_FRAC * sprofile_v_peak(&c->prof));
        *s_ref = c->s_time_m;
        return 0;
    }
    return ERLAW_ERR_ARG;
}

/* Numerical slack for "s_ref = s": the laggard's k_i (s_i / k_i). */
#define FOLLOW_EPS_M 1e-9

/* u = A e + k_v (V e - V) + k_p err + p_bias e  (eq. 6, 7), with (A, V,
 * gains, bias) chosen by the reference mode (see erlaw.h). */
static void channel_command(const erlaw_channel *c, double s, double s_ref, erlaw_ref ref,
                            const double err[3], const double vel[3], erlaw_out *out)
{
    const erlaw_gains *g = &c->g;
    const double w = ERLAW_SYNC_OMEGA_RADPS;
    double a_d, v_d, b, k_p = g->k_p, k_v = g->k_v, gap = 0.0, dv[3];
    int i;
    sprofile_at(&c->prof, s_ref, &a_d, &v_d);
    b = bias(c, s);
    out->follower = ref == ERLAW_REF_EXTERNAL && s_ref < s - FOLLOW_EPS_M;
    if (out->follower) {
        const double rho = v_d > 1e-9 ? clamp(c->v_ext / v_d, 0.0, 1.0) : 0.0;
        a_d = rho * rho * a_d;
        /* never faster than its own profile at its reference: two arms
         * that each took the other's rate (each a follower by a cycle-old
         * PROGRESS) sped each other up to the end of t3 and hit it at
         * 0.39 m/s after a long block (the bar was knocked out at the
         * hand-over) */
        v_d = fmin(c->v_ext, v_d);
        k_p = fmax(k_p, w * w);
        k_v = fmax(k_v, 2.0 * w);
        b = 0.0;
        gap = fmin(ERLAW_FOLLOW_GAP_M, c->prof.s_f_m - s_ref);
    } else if (ref == ERLAW_REF_MEASURED || ref == ERLAW_REF_EXTERNAL) {
        resume_cap(c, s_ref, &a_d, &v_d, &b);
    } else if (ref == ERLAW_REF_BLOCKED) {
        /* lean with the full start-up bias k0 wherever the block met the
         * arm: eq. 7 fades near the goal, and a faded bias could not move
         * the arm on once the obstacle is gone (a block 3 cm before the
         * goal crept for 19 s) */
        a_d = v_d = 0.0;
        b = g->k0;
    }
    for (i = 0; i < 3; i++) {
        dv[i] = v_d * c->e[i] - vel[i];
        out->u[i] = (a_d + b + k_p * gap) * c->e[i] + k_v * dv[i] + k_p * err[i];
        out->x_err[i] = err[i];
    }
    out->s_m = s;
    out->s_ref_m = s_ref;
    out->a_d = a_d;
    out->v_d = v_d;
    out->bias = b;
}

static void out_zero(erlaw_out *out)
{
    if (!out)
        return;
    vec3_set(out->u, 0.0, 0.0, 0.0);
    vec3_set(out->x_err, 0.0, 0.0, 0.0);
    out->s_m = out->s_ref_m = out->a_d = out->v_d = out->bias = 0.0;
    out->follower = 0;
}

/* ---- line ---------------------------------------------------------------*/

int erlaw_line_init(erlaw_line *l, const double p0_m[3], const double p1_m[3], const erlaw_gains *g)
{
    double d[3], e[3], s_f;
    if (!l || !finite3(p0_m) || !finite3(p1_m))
        return ERLAW_ERR_ARG;
    vec3_sub(d, p1_m, p0_m);
    s_f = vec3_normalize(e, d);
    if (s_f == 0.0)
        vec3_set(e, 1.0, 0.0, 0.0);
    vec3_copy(l->p0_m, p0_m);
    vec3_copy(l->x_hold_m, p0_m);
    return channel_init(&l->ch, e, s_f, g);
}

int erlaw_line_hold(erlaw_line *l, const double x_m[3])
{
    if (!l || !finite3(x_m))
        return ERLAW_ERR_ARG;
    vec3_copy(l->x_hold_m, x_m);
    return 0;
}

double erlaw_line_s(const erlaw_line *l, const double x_m[3])
{
    double d[3];
    if (!l || !finite3(x_m))
        return 0.0;
    vec3_sub(d, x_m, l->p0_m);
    return clamp(vec3_dot(d, l->ch.e), 0.0, l->ch.prof.s_f_m);
}

int erlaw_line_step(erlaw_line *l, const double x_m[3], const double v_mps[3], erlaw_ref ref,
                    double s_ext_m, double dt_s, erlaw_out *out)
{
    double s, s_ref, x_d[3], err[3];
    out_zero(out);
    if (!l || !out || !finite3(x_m) || !finite3(v_mps))
        return ERLAW_ERR_ARG;
    s = erlaw_line_s(l, x_m);
    if (channel_ref(&l->ch, s, ref, s_ext_m, dt_s, &s_ref) != 0)
        return ERLAW_ERR_ARG;
    if (ref == ERLAW_REF_BLOCKED) {
        vec3_sub(err, l->x_hold_m, x_m);
    } else {
        vec3_axpy(x_d, l->p0_m, s_ref, l->ch.e);
        vec3_sub(err, x_d, x_m);
    }
    channel_command(&l->ch, s, s_ref, ref, err, v_mps, out);
    return 0;
}

/* ---- orientation ----------------------------------------------------------*/

static int finite9(const double R[9])
{
    int i;
    if (!R)
        return 0;
    for (i = 0; i < 9; i++)
        if (!isfinite(R[i]))
            return 0;
    return 1;
}

/* World-frame rotation vector of A B^T. */
static void rotvec_abt(double out[3], const double A[9], const double B[9])
{
    double Bt[9], M[9], axis[3], ang;
    rot_transpose(Bt, B);
    rot_mul(M, A, Bt);
    ang = rot_to_axis_angle(axis, M);
    vec3_scale(out, axis, ang);
}

int erlaw_rot_init(erlaw_rot *r, const double R0[9], const double R1[9], const erlaw_gains *g)
{
    double phi[3], n[3], theta_f;
    int i;
    if (!r || !finite9(R0) || !finite9(R1))
        return ERLAW_ERR_ARG;
    rotvec_abt(phi, R1, R0);
    theta_f = vec3_normalize(n, phi);
    if (theta_f < 1e-12) {
        theta_f = 0.0;
        vec3_set(n, 1.0, 0.0, 0.0);
    }
    for (i = 0; i < 9; i++)
        r->R0[i] = r->R_hold[i] = R0[i];
    return channel_init(&r->ch, n, theta_f, g);
}

double erlaw_rot_angle(const erlaw_rot *r, const double R[9])
{
    double phi[3];
    if (!r || !finite9(R))
        return 0.0;
    rotvec_abt(phi, R, r->R0);
    return clamp(vec3_dot(phi, r->ch.e), 0.0, r->ch.prof.s_f_m);
}

int erlaw_rot_hold(erlaw_rot *r, const double R[9])
{
    int i;
    if (!r || !finite9(R))
        return ERLAW_ERR_ARG;
    for (i = 0; i < 9; i++)
        r->R_hold[i] = R[i];
    return 0;
}

int erlaw_rot_step(erlaw_rot *r, const double R[9], const double w_radps[3], erlaw_ref ref,
                   double s_ext_rad, double dt_s, erlaw_out *out)
{
    double th, th_ref, Rs[9], Rd[9], err[3];
    out_zero(out);
    if (!r || !out || !finite9(R) || !finite3(w_radps))
        return ERLAW_ERR_ARG;
    th = erlaw_rot_angle(r, R);
    if (channel_ref(&r->ch, th, ref, s_ext_rad, dt_s, &th_ref) != 0)
        return ERLAW_ERR_ARG;
    if (ref == ERLAW_REF_BLOCKED) {
        rotvec_abt(err, r->R_hold, R);
    } else {
        rot_from_axis_angle(Rs, r->ch.e, th_ref);
        rot_mul(Rd, Rs, r->R0);
        rotvec_abt(err, Rd, R);
    }
    channel_command(&r->ch, th, th_ref, ref, err, w_radps, out);
    return 0;
}

/* ---- predicates -----------------------------------------------------------*/

int erlaw_done(double s_m, double s_f_m, double speed, double tol_s, double tol_v)
{
    if (!isfinite(s_m) || !isfinite(s_f_m) || !isfinite(speed))
        return 0;
    return fabs(s_f_m - s_m) <= tol_s && fabs(speed) <= tol_v;
}

void erlaw_block_reset(erlaw_block *b, double s_m)
{
    if (!b)
        return;
    b->s_best_m = isfinite(s_m) ? s_m : 0.0;
    b->t_still_s = 0.0;
}

int erlaw_block_update(erlaw_block *b, double s_m, int commanding, double dt_s, double eps_s,
                       double t_block_s)
{
    if (!b || !isfinite(s_m) || !isfinite(dt_s) || dt_s < 0.0)
        return 0;
    if (s_m > b->s_best_m + eps_s || !commanding) {
        /* progress (or nothing asked): restart the still timer */
        if (s_m > b->s_best_m)
            b->s_best_m = s_m;
        b->t_still_s = 0.0;
        return 0;
    }
    b->t_still_s += dt_s;
    return b->t_still_s > t_block_s;
}

/* tdsd_seg: a Cartesian action-row segment resolved by TDSD (docs/method/tdsd.md,
 * eq. 8, 11-13; path rate contract of tdsd.h) along a jerk-limited profile
 * (docs/method/carry.md §2, sprofile), integrated into a joint reference for the
 * computed-torque servo (docs/method/carry.md §3), plus the servo's velocity limit.
 * See tdsd_seg.h.
 */
#include "tdsd_seg.h"
#include "arm_kin.h"
#include "linalg.h"
#include "trig.h"
#include "vec3.h"
#include <float.h>
#include <math.h>
#include <string.h>

void tdsd_seg_default_params(tdsd_seg_params *p, double v_m, double a_m, double u_m)
{
    p->v_m = v_m;
    p->a_m = a_m;
    p->u_m = u_m;
    p->K_p = 20.0;
    p->K_o = 10.0;
    p->k_V = 10.0;
    p->criterion_mask = 0x38u;
    p->speed_frac = 0.9;
    p->T_recover_s = 0.5;
    p->rot_len_m = 0.2;
    p->v_floor_mps = 0.01;
}

static int params_valid(const tdsd_seg_params *p)
{
    return isfinite(p->v_m) && p->v_m > 0.0 && isfinite(p->a_m) && p->a_m > 0.0 &&
           isfinite(p->u_m) && p->u_m > 0.0 && isfinite(p->K_p) && p->K_p >= 0.0 &&
           isfinite(p->K_o) && p->K_o >= 0.0 && isfinite(p->k_V) && p->k_V >= 0.0 &&
           p->speed_frac > 0.0 && p->speed_frac <= 1.0 && isfinite(p->T_recover_s) &&
           p->T_recover_s > 0.0 && isfinite(p->rot_len_m) && p->rot_len_m >= 0.0 &&
           isfinite(p->v_floor_mps) && p->v_floor_mps >= 0.0;
}

/* world point -> base frame */
static void to_base(double out[3], const double T_world_base[16], const double p_world[3])
{
    double R[9], t[3], d[3];
    tf_rot(R, T_world_base);
    tf_pos(t, T_world_base);
    vec3_sub(d, p_world, t);
    rot_tapply(out, R, d);
}

int tdsd_seg_start(tdsd_seg *g, const arm_model *m, const arm_tool *tool,
                   const double T_world_base[16], const double q[ARM_NJ], const double p1_world[3],
                   const double R1_world[9], const tdsd_seg_params *par)
{
    double T[16], Rwb[9], dR[9], d[3];
    int i;
    if (!g || !m || !tool || !T_world_base || !q || !p1_world || !R1_world || !par ||
        !params_valid(par) || arm_q_finite(q) != 0 || !linalg_all_finite(T_world_base, 16) ||
        !linalg_all_finite(p1_world, 3) || !linalg_all_finite(R1_world, 9))
        return TDSD_SEG_ERR_ARG;
    memset(g, 0, sizeof *g);
    g->par = *par;
    g->tool = *tool;
    memcpy(g->T_world_base, T_world_base, sizeof g->T_world_base);
    if (arm_fk(m, tool, q, T) != 0 || !linalg_all_finite(T, 16))
        return TDSD_SEG_ERR_ARG;
    tf_pos(g->p0, T);
    tf_rot(g->R0, T);
    to_base(g->p1, T_world_base, p1_world);
    tf_rot(Rwb, T_world_base);
    rot_tmul(g->R1, Rwb, R1_world);
    {
        double R0t[9];
        rot_transpose(R0t, g->R0);
        rot_mul(dR, g->R1, R0t);
    }
    g->rot_rad = rot_to_axis_angle(g->rot_axis, dR);
    if (!isfinite(g->rot_rad) || !linalg_all_finite(g->rot_axis, 3))
        return TDSD_SEG_ERR_ARG;
    vec3_sub(d, g->p1, g->p0);
    g->L_m = fmax(vec3_norm(d), par->rot_len_m * g->rot_rad);
    if (sprofile_plan(&g->prof, g->L_m, par->v_m, par->a_m, par->u_m) != 0)
        return TDSD_SEG_ERR_ARG;
    memcpy(g->q_ref, q, sizeof g->q_ref);
    tf_rot(g->R_world_base, T_world_base);
    g->in.orient = TDSD_ORIENT_FULL;
    g->in.K_p = par->K_p;
    g->in.K_o = par->K_o;
    g->in.k_V = par->k_V;
    g->in.pinv_rtol = 0.0;
    for (i = 0; i < ARM_NJ; i++) {
        g->in.grad_V[i] = 0.0;
        g->in.dq_max_radps[i] = par->speed_frac * m->qd_max_radps[i];
        if (!(g->in.dq_max_radps[i] > 0.0) || !(g->in.dq_max_radps[i] <= DBL_MAX))
            return TDSD_SEG_ERR_ARG;
    }
    if (tdsd_midrange_init(&g->crit, m->q_min_rad, m->q_max_rad, par->criterion_mask) != TDSD_OK)
        return TDSD_SEG_ERR_ARG;
    {
        /* the path frame's fixed parts (path_at) */
        const double *k = g->rot_axis;
        const double K[9] = { 0.0, -k[2], k[1], k[2], 0.0, -k[0], -k[1], k[0], 0.0 };
        double kR[3];
        rot_mul(g->KR0, K, g->R0);
        rot_tapply(kR, g->R0, k); /* k^T R0, as a column */
        for (i = 0; i < 9; i++)
            g->kkR0[i] = k[i / 3] * kR[i % 3];
    }
    g->lambda = 1.0;
    g->t_path_end_s = g->L_m > 0.0 ? -1.0 : 0.0;
    return 0;
}

/* Path point, frame and their rates at path rate 1 (d/dt with ds/dt =
 * max(v(s), floor)), base frame; returns max(v(s), floor), the profile's
 * rate at s (sprofile_advance_at's first stage; the floor where v(s) = 0,
 * at L). */
static double path_at(const tdsd_seg *g, double s, double p[3], double R[9], double v[3],
                      double w[3])
{
    double vs = 0.0, f = 0.0, rate = g->par.v_floor_mps, d[3], sn, cs;
    int i;
    if (g->L_m > 0.0) {
        f = s / g->L_m;
        if (s < g->L_m) {
            sprofile_at(&g->prof, s, NULL, &vs);
            rate = vs > g->par.v_floor_mps ? vs : g->par.v_floor_mps;
            vs = rate / g->L_m; /* df/dt */
        }
    }
    vec3_sub(d, g->p1, g->p0);
    vec3_axpy(p, g->p0, f, d);
    vec3_scale(v, d, vs);
    /* R = Rot(k, f theta) R0, Rodrigues (c I + s K + (1 - c) k k^T) applied
     * to R0 through its fixed parts; sine and cosine of trig.c (no FPSP
     * trap on the 68040) */
    trig_sincos(f * g->rot_rad, &sn, &cs);
    for (i = 0; i < 9; i++)
        R[i] = cs * g->R0[i] + sn * g->KR0[i] + (1.0 - cs) * g->kkR0[i];
    vec3_scale(w, g->rot_axis, g->rot_rad * vs);
    return rate;
}

int tdsd_seg_step(tdsd_seg *g, const arm_model *m, double dt_s, tdsd_seg_out *out)
{
    tdsd_input *in;
    double rate_s, inv_dt;
    int i, rc;
    if (!g || !m || !out || !isfinite(dt_s) || dt_s <= 0.0)
        return TDSD_ERR_ARG;
    in = &g->in;
    { /* T and J in a block of their own, and the step's output in a later
       * one: they share stack (the step below is the cycle's deepest path) */
        double T[16], J[36];
        /* arm_fk_jacobian checks q_ref: the segment (tdsd_seg_start) and
         * the reference being finite, every input of the step below is
         * (the one pass over them, tdsd_step_unchecked) */
        if (arm_fk_jacobian(m, &g->tool, g->q_ref, T, J) != 0) {
            memset(out, 0, sizeof *out);
            return TDSD_ERR_ARG;
        }
        tf_pos(in->p_m, T);
        tf_rot(in->R, T);
        memcpy(in->J1, J, sizeof in->J1);
        memcpy(in->Jw, J + 18, sizeof in->Jw);
    }
    rate_s = path_at(g, g->s_m, in->p_d_m, in->R_d, in->v_d_mps, in->w_d_radps);
    if (g->par.criterion_mask)
        tdsd_midrange_grad_at(&g->crit, g->q_ref, in->grad_V);
    /* re-accelerate smoothly after a slow-down (tdsd.h, rate_cap) */
    in->rate_cap = g->lambda + dt_s / g->par.T_recover_s;
    if (!(in->rate_cap < 1.0))
        in->rate_cap = 1.0;
    /* on error o.dq is zero: the reference holds. A non-finite model table,
     * the one input not checked here or at the start, makes the command
     * non-finite: refused the same way. */
    {
        tdsd_output o;
        rc = tdsd_step_unchecked(in, &o);
        if (rc == TDSD_OK && !linalg_all_finite(o.dq_radps, ARM_NJ)) {
            rc = TDSD_ERR_NUMERIC;
            for (i = 0; i < ARM_NJ; i++)
                o.dq_radps[i] = 0.0;
        }

        inv_dt = 1.0 / dt_s;
        for (i = 0; i < ARM_NJ; i++) {
            g->ddq_ref[i] = (o.dq_radps[i] - g->dq_ref[i]) * inv_dt;
            g->dq_ref[i] = o.dq_radps[i];
            g->q_ref[i] += o.dq_radps[i] * dt_s;
            out->q_d[i] = g->q_ref[i];
            out->qd_d[i] = g->dq_ref[i];
            out->qdd_d[i] = g->ddq_ref[i];
        }
        g->lambda = rc == TDSD_OK ? o.lambda : 0.0;
        out->pos_err_m = vec3_norm(o.e_p);
        out->ori_err_rad = vec3_norm(o.e_o);
        out->Q1 = o.Q1;
        out->Q2 = o.Q2;
    }
    out->lambda = g->lambda;
    out->status = rc;
    rot_apply(out->p_d_world, g->R_world_base, in->p_d_m);
    for (i = 0; i < 3; i++)
        out->p_d_world[i] += g->T_world_base[4 * i + 3];

    g->s_m = sprofile_advance_at(&g->prof, g->s_m, rate_s, g->lambda * dt_s, g->par.v_floor_mps);
    g->t_s += dt_s;
    if (g->t_path_end_s < 0.0 && g->s_m >= g->L_m)
        g->t_path_end_s = g->t_s;
    /* settled: judged on the errors at the path's end point */
    g->settled = g->t_path_end_s >= 0.0 && rc == TDSD_OK && g->s_m >= g->L_m &&
                 out->pos_err_m < TDSD_SEG_DONE_POS_M && out->ori_err_rad < TDSD_SEG_DONE_ORI_RAD;

    out->s_m = g->s_m;
    out->L_m = g->L_m;
    out->path_done = g->t_path_end_s >= 0.0;
    return rc;
}

int tdsd_seg_done(const tdsd_seg *g, const double q[ARM_NJ], const double qd[ARM_NJ])
{
    int i;
    if (!g || !q || !qd || g->t_path_end_s < 0.0)
        return 0;
    if (!g->settled && g->t_s - g->t_path_end_s < TDSD_SEG_SETTLE_MAX_S)
        return 0;
    for (i = 0; i < ARM_NJ; i++)
        if (!(fabs(q[i] - g->q_ref[i]) <= TDSD_SEG_DONE_Q_RAD) ||
            !(fabs(qd[i]) <= TDSD_SEG_DONE_QD_RADPS))
            return 0;
    return 1;
}

int tdsd_servo_vlimit(const jointctl_gains *gains, const double qd_lim[ARM_NJ],
                      const double q[ARM_NJ], double q_d[ARM_NJ], double qd_d[ARM_NJ],
                      double qdd_d[ARM_NJ])
{
    double k, v_c[ARM_NJ];
    int i, n = 0;
    if (!gains || !qd_lim || !q || !q_d || !qd_d || !qdd_d || !(gains->wn_radps > 0.0) ||
        !(gains->zeta > 0.0) || !isfinite(gains->wn_radps) || !isfinite(gains->zeta))
        return TDSD_SEG_ERR_ARG;
    k = gains->wn_radps / (2.0 * gains->zeta); /* Kp / Kv */
    for (i = 0; i < ARM_NJ; i++) {
        if (!(qd_lim[i] > 0.0))
            return TDSD_SEG_ERR_ARG;
        v_c[i] = qd_d[i] + k * (q_d[i] - q[i]);
    }
    /* v_c is finite only if q, q_d and qd_d are (k is finite, > 0): one
     * check of the three */
    if (!linalg_all_finite(v_c, ARM_NJ))
        return TDSD_SEG_ERR_ARG;
    for (i = 0; i < ARM_NJ; i++) {
        if (fabs(v_c[i]) > qd_lim[i]) {
            q_d[i] = q[i];
            qd_d[i] = v_c[i] > 0.0 ? qd_lim[i] : -qd_lim[i];
            qdd_d[i] = 0.0;
            n++;
        }
    }
    return n;
}

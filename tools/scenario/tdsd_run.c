/* tdsd_run: path, resolver step, measures and kinematic plant shared by the
 * singularity and liquid scenarios (docs/method/tdsd.md §8 S1/S2, §6; see tdsd_run.h).
 * Pure C99 + libm over the core (arm_kin, tdsd, linalg, vec3).
 */
#include "tdsd_run.h"
#include "arm_kin.h"
#include "linalg.h"
#include "vec3.h"
#include <math.h>
#include <string.h>

#define ORI_RECOVERED_RAD (0.5 * 3.14159265358979323846 / 180.0)

double tdsdrun_path_length_s(const tdsdrun_path *p)
{
    double T = 0.0;
    int i;
    for (i = 0; i + 1 < p->n_wp; i++)
        T += p->seg_s[i];
    return T;
}

void tdsdrun_path_eval(const tdsdrun_path *p, double s, double p_m[3], double v_mps[3])
{
    int i = 0;
    double tau, u, du, d[3];
    if (s < 0.0)
        s = 0.0;
    /* find the segment; past the end stay at the last waypoint */
    while (i + 2 < p->n_wp && s > p->seg_s[i]) {
        s -= p->seg_s[i];
        i++;
    }
    tau = s / p->seg_s[i];
    if (tau > 1.0)
        tau = 1.0;
    /* quintic rest-to-rest: u = 10 t^3 - 15 t^4 + 6 t^5 */
    u = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    du = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / p->seg_s[i];
    vec3_sub(d, p->wp_m[i + 1], p->wp_m[i]);
    vec3_axpy(p_m, p->wp_m[i], u, d);
    vec3_scale(v_mps, d, du);
}

void tdsdrun_init(tdsdrun_state *st)
{
    st->t_s = 0.0;
    st->s = 0.0;
    st->lambda = 1.0;
    st->t_path_end_s = -1.0;
}

static double sigma_min6(const double J[36])
{
    double U[36], sv[6], V[36];
    linalg_svd(U, sv, V, J, 6, 6);
    return sv[5];
}

static double wrist_axis_distance(const arm_model *m, const double q[ARM_NJ])
{
    double T[ARM_NJ + 1][16];
    arm_link_frames(m, q, T);
    /* PUMA-type wrist (d5 = 0): the wrist centre is frame 5's origin */
    return sqrt(T[5][3] * T[5][3] + T[5][7] * T[5][7]);
}

static double angle_between(const double a[3], const double b[3])
{
    double x[3];
    vec3_cross(x, a, b);
    return atan2(vec3_norm(x), vec3_dot(a, b));
}

int tdsdrun_step(const tdsdrun_cfg *c, const tdsdrun_path *p, tdsdrun_state *st,
                 const double q_rad[ARM_NJ], tdsdrun_sample *out)
{
    double T[16], J[36], R[9], Rt[9], dR[9], axis[3], a[3], a_d[3];
    const double T_end = tdsdrun_path_length_s(p);
    tdsd_input in;
    tdsd_output o;
    int i, rc;

    memset(out, 0, sizeof *out);
    memset(&in, 0, sizeof in);
    out->t_s = st->t_s;
    out->s = st->s;
    if (arm_fk_jacobian(c->model, &c->tool, q_rad, T, J) != 0) {
        out->status = TDSD_ERR_ARG;
        return TDSD_ERR_ARG;
    }
    tf_rot(R, T);
    tf_pos(in.p_m, T);
    tdsdrun_path_eval(p, st->s, in.p_d_m, in.v_d_mps);
    memcpy(in.J1, J, sizeof in.J1);
    memcpy(in.Jw, J + 18, sizeof in.Jw);
    in.orient = c->orient;
    memcpy(in.R_d, p->R_d, sizeof in.R_d);
    memcpy(in.R, R, sizeof in.R);
    in.K_p = c->K_p;
    in.K_o = c->K_o;
    in.k_V = c->k_V;
    if (c->criterion_mask)
        tdsd_midrange_grad(in.grad_V, NULL, q_rad, c->model->q_min_rad, c->model->q_max_rad,
                           c->criterion_mask);
    {
        const double frac = c->speed_frac > 0.0 ? c->speed_frac : 1.0;
        int i;
        for (i = 0; i < ARM_NJ; i++)
            in.dq_max_radps[i] = frac * c->model->qd_max_radps[i];
    }
    /* re-accelerate smoothly after a slow-down (tdsd.h, rate_cap) */
    in.rate_cap = st->lambda + c->dt_s / c->T_recover_s;
    if (in.rate_cap > 1.0)
        in.rate_cap = 1.0;

    switch (c->method) {
    case TDSDRUN_PINV: rc = rr_pinv_step(&in, &o); break;
    case TDSDRUN_DLS: rc = rr_dls_step(&in, &c->dls, &o); break;
    default: rc = tdsd_step(&in, &o); break;
    }
    out->status = rc;
    out->lambda = rc == TDSD_OK ? o.lambda : 0.0;
    out->Q1 = o.Q1;
    out->Q2 = o.Q2;
    out->time_scaled = o.time_scaled;
    for (i = 0; i < ARM_NJ; i++) {
        out->dq_radps[i] = o.dq_radps[i];
        /* the baselines keep their unclipped J+ y in dq1 */
        out->dq_demand_radps[i] = c->method == TDSDRUN_TDSD ? o.dq_radps[i] : o.dq1[i];
    }
    vec3_copy(out->p_d_m, in.p_d_m);
    vec3_copy(out->p_m, in.p_m);
    {
        double e[3];
        vec3_sub(e, in.p_d_m, in.p_m);
        out->pos_err_m = vec3_norm(e);
    }
    rot_transpose(Rt, R);
    rot_mul(dR, p->R_d, Rt);
    out->ori_err_rad = rot_to_axis_angle(axis, dR);
    vec3_set(a, R[2], R[5], R[8]);
    vec3_set(a_d, p->R_d[2], p->R_d[5], p->R_d[8]);
    out->tilt_rad = angle_between(a, a_d);
    out->sigma_min_J = sigma_min6(J);
    out->wrist_axis_m = wrist_axis_distance(c->model, q_rad);

    st->lambda = out->lambda;
    st->s += out->lambda * c->dt_s;
    if (st->s >= T_end) {
        st->s = T_end;
        if (st->t_path_end_s < 0.0)
            st->t_path_end_s = st->t_s + c->dt_s;
    }
    st->t_s += c->dt_s;
    return rc;
}

int tdsdrun_finished(const tdsdrun_cfg *c, const tdsdrun_state *st)
{
    return st->t_path_end_s >= 0.0 && st->t_s >= st->t_path_end_s + c->settle_s - 1e-9;
}

void tdsdrun_metrics_init(tdsdrun_metrics *m, double region_m)
{
    int i;
    memset(m, 0, sizeof *m);
    m->region_m = region_m;
    m->min_Q1 = m->min_Q1_outside = 1.0;
    m->min_lambda = 1.0;
    m->t_region_in_s = m->t_region_out_s = -1.0;
    m->t_ori_recovered_s = 0.0;
    m->min_wrist_axis_m = INFINITY;
    for (i = 0; i < ARM_NJ; i++) {
        m->q_lo_rad[i] = INFINITY;
        m->q_hi_rad[i] = -INFINITY;
    }
}

void tdsdrun_metrics_add(tdsdrun_metrics *m, const arm_model *model, const tdsdrun_sample *s,
                         const double q_rad[ARM_NJ], const double qd_radps[ARM_NJ])
{
    int i, outside = 0;
    const int in_region = s->wrist_axis_m < m->region_m;
    m->n++;
    if (s->status != TDSD_OK)
        m->resolver_errors++;
    if (s->pos_err_m > m->max_pos_err_m)
        m->max_pos_err_m = s->pos_err_m;
    m->sum_sq_pos_err += s->pos_err_m * s->pos_err_m;
    if (s->ori_err_rad > m->max_ori_err_rad)
        m->max_ori_err_rad = s->ori_err_rad;
    if (s->tilt_rad > m->max_tilt_rad)
        m->max_tilt_rad = s->tilt_rad;
    if (s->ori_err_rad > ORI_RECOVERED_RAD)
        m->t_ori_recovered_s = s->t_s;
    m->ori_err_end_rad = s->ori_err_rad;
    m->tilt_end_rad = s->tilt_rad;
    if (s->Q1 < m->min_Q1) {
        m->min_Q1 = s->Q1;
        m->t_min_Q1_s = s->t_s;
    }
    if (!in_region && s->Q1 < m->min_Q1_outside)
        m->min_Q1_outside = s->Q1;
    if (in_region) {
        if (m->t_region_in_s < 0.0)
            m->t_region_in_s = s->t_s;
        m->t_region_out_s = s->t_s;
    }
    if (s->wrist_axis_m < m->min_wrist_axis_m)
        m->min_wrist_axis_m = s->wrist_axis_m;
    if (s->lambda < m->min_lambda)
        m->min_lambda = s->lambda;
    for (i = 0; i < ARM_NJ; i++) {
        const double r = fabs(qd_radps[i]) / model->qd_max_radps[i];
        const double rd = fabs(s->dq_demand_radps[i]) / model->qd_max_radps[i];
        const double below = model->q_min_rad[i] - q_rad[i], above = q_rad[i] - model->q_max_rad[i];
        const double excess = below > above ? below : above;
        if (r > m->max_speed_ratio)
            m->max_speed_ratio = r;
        if (rd > m->max_demand_ratio)
            m->max_demand_ratio = rd;
        if (excess > 0.0) {
            outside = 1;
            if (excess > m->max_excess_rad[i])
                m->max_excess_rad[i] = excess;
        }
        if (q_rad[i] < m->q_lo_rad[i])
            m->q_lo_rad[i] = q_rad[i];
        if (q_rad[i] > m->q_hi_rad[i])
            m->q_hi_rad[i] = q_rad[i];
    }
    m->joint_limit_violations += outside;
}

double tdsdrun_kin(const tdsdrun_cfg *c, const tdsdrun_path *p, const double q0_rad[ARM_NJ],
                   double t_max_s, tdsdrun_metrics *m, tdsdrun_sample_fn on_sample, void *user)
{
    double q[ARM_NJ];
    tdsdrun_state st;
    tdsdrun_sample s;
    int i;
    memcpy(q, q0_rad, sizeof q);
    tdsdrun_init(&st);
    while (!tdsdrun_finished(c, &st) && st.t_s < t_max_s) {
        tdsdrun_step(c, p, &st, q, &s);
        if (m)
            tdsdrun_metrics_add(m, c->model, &s, q, s.dq_radps);
        if (on_sample)
            on_sample(user, &s, q);
        for (i = 0; i < ARM_NJ; i++)
            q[i] += s.dq_radps[i] * c->dt_s;
    }
    return st.t_path_end_s >= 0.0 ? st.t_path_end_s : t_max_s;
}

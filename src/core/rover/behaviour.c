/* behaviour: move-to-goal (seed eq. 5 as corrected in docs/method/formation.md,
 * saturation eq. 6), keep-formation (docs/method/formation.md §3 A, B, gamma form of eqs. 7-9,
 * saturation eq. 10), avoid-obstacles (d_st, k S_F, k_s (S_LF - S_RF)),
 * exceptions (dead zone eq. 2, narrow passage) and the blending of eq. 11
 * with the subsumption and vector-sum baselines.
 */
#include "behaviour.h"

#include <math.h>
#include <stddef.h>

#define BEH_MIN_RANGE_FLOOR_M 1e-3 /* keeps W4 finite for a zero echo */
#define BEH_L_EPS_M 1e-9           /* below this phi of a slot is undefined */
#define BEH_WAIT_V_MPS 0.1         /* a team this fast brings the slot to a robot that waits */

void behaviour_params_default(behaviour_params *p)
{
    p->d_m = -0.15; /* O ahead of the axle: behaviour.h */
    p->v_max_mps = 0.5;
    p->w_max_radps = 1.0;
    p->v_fm_max_mps = 0.5;
    p->w_fm_max_radps = 1.0;
    p->sat_mode = UNICYCLE_SAT_CLIP;
    p->a1 = 0.4;
    p->a2 = 1.0;
    p->goal_tol_m = 0.3;
    p->goal_margin_m = 0.05;
    p->b1 = 0.5;
    p->b2 = 1.0;
    p->d_s_m = 0.6;
    p->k_v = 0.3;
    p->k_s = 0.8;
    p->d_st_lateral = 0;
    p->d_st_rear_max_m = 1.0;
    p->v_k_mps = 0.0;
    p->w_k_radps = 0.6;
    p->dead_zone_time_s = 2.0;
    p->passage_safety_m = 0.3;
    p->robot_width_m = 0.38;
    p->k2 = 1.0;
    p->k3 = 1.0;
    p->k4 = 1.0;
    p->d_r_m = 0.3;
    p->form_near_m = 0.3;
    p->form_far_m = 0.8;
}

static int params_check_values(const behaviour_params *p)
{
    const double pos[] = { fabs(p->d_m),    p->v_max_mps,      p->w_max_radps,
                           p->v_fm_max_mps, p->w_fm_max_radps, p->d_r_m };
    const double nonneg[] = { p->a1,
                              p->a2,
                              p->goal_tol_m,
                              p->goal_margin_m,
                              p->b1,
                              p->b2,
                              p->d_s_m,
                              p->d_st_rear_max_m,
                              p->k_v,
                              p->k_s,
                              p->v_k_mps,
                              p->w_k_radps,
                              p->dead_zone_time_s,
                              p->passage_safety_m,
                              p->robot_width_m,
                              p->k2,
                              p->k3,
                              p->k4 };
    size_t i;
    for (i = 0; i < sizeof pos / sizeof pos[0]; i++)
        if (!isfinite(pos[i]) || !(pos[i] > 0.0))
            return BEHAVIOUR_ERR_ARG;
    for (i = 0; i < sizeof nonneg / sizeof nonneg[0]; i++)
        if (!isfinite(nonneg[i]) || nonneg[i] < 0.0)
            return BEHAVIOUR_ERR_ARG;
    if (p->sat_mode != UNICYCLE_SAT_CLIP && p->sat_mode != UNICYCLE_SAT_SCALE)
        return BEHAVIOUR_ERR_ARG;
    if (!isfinite(p->form_near_m) || p->form_near_m < 0.0 || !isfinite(p->form_far_m) ||
        !(p->form_far_m > p->form_near_m))
        return BEHAVIOUR_ERR_ARG;
    return 0;
}

int behaviour_params_validate(const behaviour_params *p)
{
    return p ? params_check_values(p) : BEHAVIOUR_ERR_ARG;
}

static double range_ok(double r)
{
    return (isfinite(r) && r > 0.0) ? r : 0.0;
}

static double min2(double a, double b)
{
    return a < b ? a : b;
}

void behaviour_sonar_groups(sonar_groups *g, const double range_m[BEH_SONAR_N])
{
    double r[BEH_SONAR_N];
    int i;
    for (i = 0; i < BEH_SONAR_N; i++)
        r[i] = range_ok(range_m[i]);
    g->right_m = r[0];
    g->right_front_m = min2(r[1], r[2]);
    g->front_m = min2(r[3], r[4]);
    g->left_front_m = min2(r[5], r[6]);
    g->left_m = r[7];
    g->min_m = r[0];
    for (i = 1; i < BEH_SONAR_N; i++)
        g->min_m = min2(g->min_m, r[i]);
}

static void cmd_zero(unicycle_cmd *u)
{
    u->v_mps = 0.0;
    u->w_radps = 0.0;
}

/* ---- move to goal ------------------------------------------------------ */

void behaviour_goal_polar(double *r_m, double *phi_rad, const pose2 *o, const double goal_m[2])
{
    const double ex = goal_m[0] - o->x_m, ey = goal_m[1] - o->y_m;
    *r_m = hypot(ex, ey);
    *phi_rad = vec2_wrap_rad(atan2(ey, ex) - o->theta_rad);
}

int behaviour_goal_raw(unicycle_cmd *u, double r_m, double phi_rad, double d_m, double a1,
                       double a2)
{
    const double c = cos(phi_rad), s = sin(phi_rad);
    const double den = r_m * c - d_m;
    if (!(fabs(den) > 1e-12)) {
        cmd_zero(u);
        return BEHAVIOUR_ERR_ARG;
    }
    u->w_radps = r_m * (a1 * s + a2 * phi_rad * c) / den;
    u->v_mps = r_m * (a1 * (r_m - d_m * c) + a2 * d_m * phi_rad * s) / den;
    return 0;
}

int behaviour_goal(unicycle_cmd *u, const pose2 *o, const double goal_m[2],
                   const behaviour_params *p)
{
    double r, phi;
    unicycle_cmd raw;
    cmd_zero(u);
    if (!vec2_pose_finite(o) || !isfinite(goal_m[0]) || !isfinite(goal_m[1]))
        return BEHAVIOUR_ERR_ARG;
    behaviour_goal_polar(&r, &phi, o, goal_m);
    if (r <= p->goal_tol_m)
        return BEH_GOAL_REACHED;
    if (r * cos(phi) - p->d_m <= p->goal_margin_m) {
        /* Eq. 5 is singular at r cos phi = d; face the goal first. */
        behaviour_goal_face(u, phi, p);
        return BEH_GOAL_TURN;
    }
    behaviour_goal_raw(&raw, r, phi, p->d_m, p->a1, p->a2);
    unicycle_saturate(u, &raw, p->v_max_mps, p->w_max_radps, p->sat_mode);
    return BEH_GOAL_DRIVE;
}

void behaviour_goal_face(unicycle_cmd *u, double phi_rad, const behaviour_params *p)
{
    unicycle_cmd raw;
    raw.v_mps = 0.0;
    raw.w_radps = p->a2 * phi_rad;
    unicycle_saturate(u, &raw, p->v_max_mps, p->w_max_radps, UNICYCLE_SAT_CLIP);
}

/* ---- keep formation ---------------------------------------------------- */

void behaviour_formation_polar(double *l_m, double *phi_rad, const pose2 *o,
                               const unicycle_state *ref)
{
    double rel[2];
    vec2_rotate(rel, o->x_m - ref->x_m, o->y_m - ref->y_m, -ref->theta_rad);
    *l_m = hypot(rel[0], rel[1]);
    *phi_rad = atan2(rel[1], rel[0]);
}

double behaviour_slot_error(double l_m, double phi_rad, double l_d_m, double phi_d_rad)
{
    const double q = l_m * l_m + l_d_m * l_d_m - 2.0 * l_m * l_d_m * cos(phi_rad - phi_d_rad);
    return q > 0.0 ? sqrt(q) : 0.0;
}

void behaviour_formation_raw(unicycle_cmd *u, double l_m, double phi_rad, double gamma_rad,
                             double l_d_m, double phi_d_rad, double v0_mps, double w0_radps,
                             double d_m, double b1, double b2)
{
    const double cp = cos(phi_rad), sp = sin(phi_rad);
    const double cg = cos(gamma_rad), sg = sin(gamma_rad);
    const double A = b1 * (l_d_m - l_m) + v0_mps * cp - d_m * w0_radps * sp;
    const double B = v0_mps * sp + d_m * w0_radps * cp - l_m * w0_radps -
                     l_m * b2 * vec2_wrap_rad(phi_d_rad - phi_rad);
    u->v_mps = A * cg + B * sg;
    u->w_radps = (B * cg - A * sg) / d_m;
}

int behaviour_formation(unicycle_cmd *u, double *R_d_m, const pose2 *o, const unicycle_state *ref,
                        double l_d_m, double phi_d_rad, const behaviour_params *p)
{
    double l, phi, gamma;
    unicycle_cmd raw;
    cmd_zero(u);
    if (R_d_m)
        *R_d_m = 0.0;
    if (!vec2_pose_finite(o) || !ref || !vec2_finite3(ref->x_m, ref->y_m, ref->theta_rad) ||
        !isfinite(ref->v_mps) || !isfinite(ref->w_radps) || !isfinite(l_d_m) ||
        !isfinite(phi_d_rad) || l_d_m < 0.0 || !(fabs(p->d_m) > 0.0))
        return BEHAVIOUR_ERR_ARG;
    behaviour_formation_polar(&l, &phi, o, ref);
    /* At l = 0 the bearing is undefined; any value works since l multiplies
     * the phi error, so take the demanded one. */
    if (l < BEH_L_EPS_M)
        phi = phi_d_rad;
    gamma = vec2_wrap_rad(phi + ref->theta_rad - o->theta_rad);
    behaviour_formation_raw(&raw, l, phi, gamma, l_d_m, phi_d_rad, ref->v_mps, ref->w_radps, p->d_m,
                            p->b1, p->b2);
    unicycle_saturate(u, &raw, p->v_fm_max_mps, p->w_fm_max_radps, p->sat_mode);
    if (R_d_m)
        *R_d_m = behaviour_slot_error(l, phi, l_d_m, phi_d_rad);
    return 0;
}

int behaviour_formation_seed(unicycle_cmd *u, double *R_d_m, const pose2 *o,
                             const unicycle_state *ref, double l_d_m, double phi_d_rad,
                             const behaviour_params *p)
{
    const int rc = behaviour_formation(u, R_d_m, o, ref, l_d_m, phi_d_rad, p);
    /* No rear sonar: a robot whose O would have to move backward (it is
     * ahead of its slot, or faces away from the team's way) stops. While
     * the team moves it turns onto the team heading and waits: the slot
     * comes to it, and the law's forward motion takes over once it is
     * level. Turning by the law's own w instead (the sideways part of a
     * backward velocity, divided by |d|) swung the robot round after a
     * slot a few centimetres behind, and for a robot facing backward that
     * turn's sign is noise: it cancelled the goal behaviour's turn in the
     * blend and a team facing away from its goal crept on away from it.
     * A team that stands (at the goal) brings no slot: there the law's
     * own turn, toward the slot, is kept; in between the two are mixed
     * by V0 / BEH_WAIT_V_MPS. */
    if (rc == 0 && u->v_mps < 0.0) {
        double mu = ref->v_mps / BEH_WAIT_V_MPS;
        unicycle_cmd raw;
        if (mu < 0.0)
            mu = 0.0;
        if (mu > 1.0)
            mu = 1.0;
        raw.v_mps = 0.0;
        raw.w_radps = mu * p->b2 * vec2_angle_diff_rad(ref->theta_rad, o->theta_rad) +
                      (1.0 - mu) * u->w_radps;
        unicycle_saturate(u, &raw, p->v_fm_max_mps, p->w_fm_max_radps, UNICYCLE_SAT_CLIP);
    }
    return rc;
}

/* Slot position and the slot's offset seen from O in the robot frame. */
static void slot_in_robot_frame(double *ex, double *ey, const pose2 *o, const unicycle_state *ref,
                                double l_d_m, double phi_d_rad)
{
    double s[2];
    const double c = cos(o->theta_rad), sn = sin(o->theta_rad);
    vec2_rotate(s, l_d_m * cos(phi_d_rad), l_d_m * sin(phi_d_rad), ref->theta_rad);
    s[0] += ref->x_m - o->x_m;
    s[1] += ref->y_m - o->y_m;
    *ex = s[0] * c + s[1] * sn;
    *ey = -s[0] * sn + s[1] * c;
}

static int formation_inputs_ok(const pose2 *o, const unicycle_state *ref, double l_d_m,
                               double phi_d_rad, const behaviour_params *p)
{
    return vec2_pose_finite(o) && ref && vec2_finite3(ref->x_m, ref->y_m, ref->theta_rad) &&
           isfinite(ref->v_mps) && isfinite(ref->w_radps) && isfinite(l_d_m) &&
           isfinite(phi_d_rad) && l_d_m >= 0.0 && fabs(p->d_m) > 0.0;
}

int behaviour_slot_track(unicycle_cmd *u, const pose2 *o, const unicycle_state *ref, double l_d_m,
                         double phi_d_rad, const behaviour_params *p)
{
    double ex, ey, dist, mu, kv, kw;
    unicycle_cmd raw;
    cmd_zero(u);
    if (!formation_inputs_ok(o, ref, l_d_m, phi_d_rad, p))
        return BEHAVIOUR_ERR_ARG;
    slot_in_robot_frame(&ex, &ey, o, ref, l_d_m, phi_d_rad);
    dist = hypot(ex, ey);
    {
        /* Kanayama et al. 1990 with k_y = 4, k_th = 2 (per m, per rad at
         * the reference speed); the speed floor keeps it steering when the
         * team stands */
        const double eth = vec2_angle_diff_rad(ref->theta_rad, o->theta_rad);
        const double vr = ref->v_mps > 0.1 ? ref->v_mps : 0.1;
        kv = ref->v_mps * cos(eth) + p->b1 * ex;
        kw = ref->w_radps + vr * (4.0 * ey + 2.0 * sin(eth));
    }
    /* far with the slot ahead: pursue the slot point (nose toward it) */
    mu = ex > 0.0 ? (dist - p->form_near_m) / (p->form_far_m - p->form_near_m) : 0.0;
    if (mu < 0.0)
        mu = 0.0;
    if (mu > 1.0)
        mu = 1.0;
    if (mu > 0.0) {
        const double b = atan2(ey, ex);
        const double v0 = ref->v_mps > 0.0 ? ref->v_mps : 0.0;
        kv = (1.0 - mu) * kv + mu * (v0 + p->b1 * dist) * cos(b);
        kw = (1.0 - mu) * kw + mu * (ref->w_radps + p->b2 * b);
    }
    raw.v_mps = kv > 0.0 ? kv : 0.0;
    raw.w_radps = kw;
    unicycle_saturate(u, &raw, p->v_fm_max_mps, p->w_fm_max_radps, UNICYCLE_SAT_CLIP);
    return 0;
}

int behaviour_formation_track(unicycle_cmd *u, double *R_d_m, const pose2 *o,
                              const unicycle_state *ref, double l_d_m, double phi_d_rad,
                              const behaviour_params *p)
{
    unicycle_cmd seed;
    double R_d = 0.0;
    cmd_zero(u);
    if (R_d_m)
        *R_d_m = 0.0;
    if (behaviour_formation(&seed, &R_d, o, ref, l_d_m, phi_d_rad, p) != 0)
        return BEHAVIOUR_ERR_ARG;
    if (behaviour_slot_track(u, o, ref, l_d_m, phi_d_rad, p) != 0)
        return BEHAVIOUR_ERR_ARG;
    if (R_d_m)
        *R_d_m = R_d;
    return 0;
}

/* ---- avoid obstacles --------------------------------------------------- */

/* The seed's d_st grows with the slot's distance behind R0: a rear robot
 * of a three-robot triangle starts avoiding what lies ahead of the
 * formation. Counted in full for a large team it outgrows the sonar
 * (the rearmost of a column of twelve, 5.5 m behind R0, had 6.3 m
 * against the sonar's 5 m): every echo, and no echo at all, was within
 * it, so avoidance was always on, always weighed d_st / 5 m and drove on
 * at full speed, and the robot crept past its goal slot while the goal
 * behaviour turned it. So what lies behind R0 counts up to
 * d_st_rear_max_m, one spacing: a robot reacts at most as much earlier
 * as the mate in front of it, which sees the obstacle first. Teams whose
 * slots lie within one spacing behind R0 (every team of three) are not
 * changed. */
double behaviour_d_st(const behaviour_params *p, double width_D_m, double l_d_m, double phi_d_rad)
{
    double off = p->d_st_lateral ? fabs(l_d_m * sin(phi_d_rad)) : l_d_m * cos(phi_d_rad), d_st;
    if (off < -p->d_st_rear_max_m)
        off = -p->d_st_rear_max_m;
    d_st = p->d_s_m + (0.5 * width_D_m - off);
    return (isfinite(d_st) && d_st > p->d_s_m) ? d_st : p->d_s_m;
}

int behaviour_avoid(unicycle_cmd *u, const sonar_groups *g, double v_now_mps, double d_st_m,
                    const behaviour_params *p)
{
    const double near = min2(g->front_m, min2(g->left_front_m, g->right_front_m));
    unicycle_cmd raw;
    if (near > d_st_m) {
        raw.v_mps = isfinite(v_now_mps) ? v_now_mps : 0.0;
        raw.w_radps = 0.0;
        unicycle_saturate(u, &raw, p->v_max_mps, p->w_max_radps, UNICYCLE_SAT_CLIP);
        return 0;
    }
    raw.v_mps = p->k_v * g->front_m;
    raw.w_radps = p->k_s * (g->left_front_m - g->right_front_m);
    unicycle_saturate(u, &raw, p->v_max_mps, p->w_max_radps, UNICYCLE_SAT_CLIP);
    return 1;
}

/* ---- exceptions -------------------------------------------------------- */

void behaviour_exception_init(behaviour_exception *e)
{
    e->blocked_s = 0.0;
    e->active = 0;
    e->entries = 0;
}

int behaviour_exception_step(behaviour_exception *e, unicycle_cmd *u, const sonar_groups *g,
                             double dt_s, const behaviour_params *p)
{
    const double ds = p->d_s_m;
    const int blocked = g->front_m < ds && g->left_m < ds && g->right_m < ds;
    cmd_zero(u);
    if (!isfinite(dt_s) || dt_s < 0.0)
        return BEHAVIOUR_ERR_ARG;
    if (e->active) {
        if (g->front_m > ds) {
            e->active = 0;
            e->blocked_s = 0.0;
            return 0;
        }
    } else if (!blocked) {
        e->blocked_s = 0.0;
        return 0;
    } else {
        e->blocked_s += dt_s;
        if (e->blocked_s < p->dead_zone_time_s)
            return 0;
        e->active = 1;
        e->entries++;
    }
    /* Alternate the turn so a trap that one direction cannot escape is
     * tried the other way on the next entry (eq. 2). */
    u->v_mps = p->v_k_mps;
    u->w_radps = (e->entries % 2 == 1) ? p->w_k_radps : -p->w_k_radps;
    return 1;
}

int behaviour_passage_narrow(const sonar_groups *g, double width_D_m, const behaviour_params *p)
{
    return g->left_m + g->right_m + p->robot_width_m < width_D_m + p->passage_safety_m;
}

/* ---- blending ---------------------------------------------------------- */

static int inputs_finite(const behaviour_inputs *in)
{
    int i;
    for (i = 0; i < BEH_COUNT; i++)
        if (!isfinite(in->u[i].v_mps) || !isfinite(in->u[i].w_radps))
            return 0;
    return isfinite(in->R_d_m) && isfinite(in->d_st_m) && isfinite(in->min_range_m);
}

static void raw_weights(double W[BEH_COUNT], const behaviour_inputs *in, int mode,
                        const behaviour_params *p)
{
    int i;
    for (i = 0; i < BEH_COUNT; i++)
        W[i] = 0.0;
    if (in->exception_active) {
        W[BEH_EXCEPTION] = 1.0;
        return;
    }
    if (mode == BEH_BLEND_SUBSUMPTION) {
        if (in->avoid_active)
            W[BEH_AVOID] = 1.0;
        else if (in->R_d_m > p->d_r_m)
            W[BEH_FORMATION] = 1.0;
        else
            W[BEH_GOAL] = 1.0;
    } else if (mode == BEH_BLEND_VECSUM) {
        W[BEH_GOAL] = W[BEH_FORMATION] = W[BEH_AVOID] = 1.0;
    } else {
        const double mr = in->min_range_m > BEH_MIN_RANGE_FLOOR_M ? in->min_range_m
                                                                  : BEH_MIN_RANGE_FLOOR_M;
        W[BEH_GOAL] = p->k2;
        W[BEH_FORMATION] = p->k3 * fabs(in->R_d_m) / p->d_r_m;
        W[BEH_AVOID] = p->k4 * fabs(in->d_st_m) / mr;
    }
}

int behaviour_blend(behaviour_blender *out, const behaviour_inputs *in, int mode,
                    const behaviour_params *p)
{
    double sum = 0.0, v = 0.0, w = 0.0;
    int i;
    for (i = 0; i < BEH_COUNT; i++)
        out->weight_raw[i] = out->weight[i] = 0.0;
    cmd_zero(&out->u);
    out->winner = BEH_GOAL;
    if ((mode != BEH_BLEND_WEIGHTED && mode != BEH_BLEND_SUBSUMPTION && mode != BEH_BLEND_VECSUM) ||
        !inputs_finite(in))
        return BEHAVIOUR_ERR_ARG;
    raw_weights(out->weight_raw, in, mode, p);
    for (i = 0; i < BEH_COUNT; i++)
        sum += out->weight_raw[i];
    if (!(sum > 0.0) || !isfinite(sum))
        return BEHAVIOUR_ERR_ARG;
    for (i = 0; i < BEH_COUNT; i++) {
        out->weight[i] = out->weight_raw[i] / sum;
        v += out->weight[i] * in->u[i].v_mps;
        w += out->weight[i] * in->u[i].w_radps;
        if (out->weight[i] > out->weight[out->winner])
            out->winner = i;
    }
    out->u.v_mps = v;
    out->u.w_radps = w;
    return 0;
}

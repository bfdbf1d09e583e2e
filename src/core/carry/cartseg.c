/* cartseg: a straight Cartesian segment under the event-referenced law
 * (docs/method/carry.md §3 eq. 6-7), its synchronised (2.3) and time-referenced (2.6)
 * variants, turned into torques by cartctl; the blocked detector (with
 * contact sensing) and the in-range joint-space goal a stuck segment is
 * re-planned to; see cartseg.h. */
#include "cartseg.h"

#include <math.h>
#include <string.h>

#include "vec3.h"

static void R_of(const double T[16], double R[9])
{
    tf_rot(R, T);
}

int cartseg_tool_world(const arm_model *m, const arm_tool *tool, const double T_world_base[16],
                       const double q[ARM_NJ], const double qd[ARM_NJ], double x[3], double v[3])
{
    cartctl_state s;
    if (cartctl_state_at(m, tool, q, qd, &s) != 0)
        return CARTSEG_ERR_ARG;
    return cartseg_tool_world_at(&s, T_world_base, x, v);
}

/* x = T_world_base p_tool, v = R_world_base v_tool: the tool point alone,
 * not the whole 4x4 product; Rwb = R_world_base, kept for the caller */
static void tool_world(const cartctl_state *st, const double T_world_base[16], double Rwb[9],
                       double x[3], double v[3])
{
    double p[3];
    tf_pos(p, st->T);
    tf_apply(x, T_world_base, p);
    R_of(T_world_base, Rwb);
    rot_apply(v, Rwb, st->twist);
}

int cartseg_tool_world_at(const cartctl_state *st, const double T_world_base[16], double x[3],
                          double v[3])
{
    double Rwb[9];
    if (!st || !T_world_base || !x || !v)
        return CARTSEG_ERR_ARG;
    tool_world(st, T_world_base, Rwb, x, v);
    return 0;
}

int cartseg_start(cartseg *c, const arm_model *m, const arm_tool *tool,
                  const double T_world_base[16], const double q[ARM_NJ], const double p1_world[3],
                  const double R1_world[9], const erlaw_gains *g, erlaw_ref ref)
{
    double x[3], v[3], Rwb[9];
    const double qd0[ARM_NJ] = { 0 };
    int i;
    if (!c || !p1_world || !R1_world || (ref != ERLAW_REF_MEASURED && ref != ERLAW_REF_TIME))
        return CARTSEG_ERR_ARG;
    for (i = 0; i < 3; i++)
        if (!isfinite(p1_world[i]))
            return CARTSEG_ERR_ARG;
    memset(c, 0, sizeof *c);
    if (cartseg_tool_world(m, tool, T_world_base, q, qd0, x, v) != 0)
        return CARTSEG_ERR_ARG;
    if (erlaw_line_init(&c->line, x, p1_world, g) != 0)
        return CARTSEG_ERR_ARG;
    memcpy(c->T_world_base, T_world_base, sizeof c->T_world_base);
    R_of(T_world_base, Rwb);
    rot_tmul(c->R_d_base, Rwb, R1_world);
    vec3_copy(c->p1_world, p1_world);
    cartctl_gains_default(&c->cg);
    c->ref = ref;
    erlaw_block_reset(&c->blk, 0.0);
    c->dev_ref_m = 0.0;
    vec3_set(c->hold_off_m, 0.0, 0.0, 0.0);
    vec3_set(c->err_filt_m, 0.0, 0.0, 0.0);
    vec3_set(c->err_snap_m, 0.0, 0.0, 0.0);
    c->t_snap_s = 0.0;
    c->block_detect = 1;
    c->contact_N = -1.0;
    c->t_no_contact_s = HUGE_VAL;
    return 0;
}

int cartseg_resume(cartseg *c, const double x_world[3])
{
    if (!c || !x_world || !isfinite(x_world[0]) || !isfinite(x_world[1]) || !isfinite(x_world[2]))
        return CARTSEG_ERR_ARG;
    erlaw_channel_resume(&c->line.ch, erlaw_line_s(&c->line, x_world));
    return 0;
}

int cartseg_take_up(cartseg *c, double done_frac)
{
    double p0[3], d[3];
    erlaw_gains g;
    if (!c || !(done_frac > 0.0 && done_frac <= CARTSEG_TAKE_UP_MAX))
        return CARTSEG_ERR_ARG;
    g = c->line.ch.g;
    vec3_sub(d, c->line.p0_m, c->p1_world);
    if (vec3_norm(d) < CARTSEG_TAKE_UP_MIN_M)
        return CARTSEG_ERR_ARG;
    vec3_axpy(p0, c->p1_world, 1.0 / (1.0 - done_frac), d);
    if (erlaw_line_init(&c->line, p0, c->p1_world, &g) != 0)
        return CARTSEG_ERR_ARG;
    erlaw_channel_resume(&c->line.ch, done_frac * erlaw_channel_length(&c->line.ch));
    erlaw_block_reset(&c->blk, c->line.ch.s_resume_m);
    return 0;
}

void cartseg_set_contact(cartseg *c, double force_N)
{
    if (c)
        c->contact_N = isfinite(force_N) && force_N >= 0.0 ? force_N : -1.0;
}

/* Of the angles q_b + 2 pi k, the one nearest q_ref; with lo <= hi, only
 * those in [lo, hi] (NAN if none). */
static double angle_near(double q_b, double q_ref, double lo, double hi)
{
    const double two_pi = 6.283185307179586;
    double best = NAN;
    int k;
    q_b += two_pi * floor((q_ref - q_b) / two_pi + 0.5);
    for (k = -1; k <= 1; k++) {
        const double a = q_b + two_pi * k;
        if (lo <= hi && !(a >= lo && a <= hi))
            continue;
        if (isnan(best) || fabs(a - q_ref) < fabs(best - q_ref))
            best = a;
    }
    return best;
}

/* Max |a - b| over the joints. */
static double joint_dist(const double a[ARM_NJ], const double b[ARM_NJ])
{
    double d = 0.0;
    int j;
    for (j = 0; j < ARM_NJ; j++)
        d = fmax(d, fabs(a[j] - b[j]));
    return d;
}

int cartseg_joint_goal(const arm_model *m, const arm_tool *tool, const double T_world_base[16],
                       const double q[ARM_NJ], const double p1_world[3], const double R1_world[9],
                       double q_goal[ARM_NJ])
{
    double Tw[16], Tinv[16], T[16], cont[ARM_NJ], best[ARM_NJ], d_cont = HUGE_VAL,
                                                                d_best = HUGE_VAL;
    arm_ik_result r;
    int b, j, arm_cfg, best_same = 0, inside = 0;
    if (!m || !T_world_base || !p1_world || !R1_world || !q_goal || arm_q_finite(q) != 0)
        return CARTSEG_ERR_ARG;
    memcpy(q_goal, q, sizeof(double) * ARM_NJ);
    tf_from_rot_pos(Tw, R1_world, p1_world);
    tf_inverse(Tinv, T_world_base);
    tf_mul(T, Tinv, Tw);
    arm_cfg = arm_ik_branch_of(m, q);
    if (arm_ik(m, tool, T, &r) != 0 || r.unreachable || arm_cfg < 0)
        return CARTSEG_ERR_NO_GOAL;
    for (b = 0; b < ARM_IK_NBRANCH; b++) {
        double qc[ARM_NJ], qr[ARM_NJ], d;
        int ok = 1, same;
        if (r.branch[b].status & ARM_IK_UNREACHABLE)
            continue;
        for (j = 0; j < ARM_NJ; j++) {
            const double lo = m->q_min_rad[j] + CARTSEG_GOAL_MARGIN_RAD,
                         hi = m->q_max_rad[j] - CARTSEG_GOAL_MARGIN_RAD;
            qc[j] = angle_near(r.branch[b].q_rad[j], q[j], 1.0, 0.0);
            qr[j] = angle_near(r.branch[b].q_rad[j], q[j], lo, hi);
            ok = ok && !isnan(qr[j]);
        }
        d = joint_dist(qc, q);
        if (d < d_cont) { /* where a continuous move ends */
            d_cont = d;
            memcpy(cont, qc, sizeof cont);
        }
        if (!ok)
            continue;
        d = joint_dist(qr, q);
        same = (b & 3) == (arm_cfg & 3); /* shoulder and elbow as now */
        if (!inside || (same && !best_same) || (same == best_same && d < d_best)) {
            inside = 1;
            best_same = same;
            d_best = d;
            memcpy(best, qr, sizeof best);
        }
    }
    for (j = 0; j < ARM_NJ; j++)
        if (!(cont[j] >= m->q_min_rad[j] + CARTSEG_GOAL_MARGIN_RAD &&
              cont[j] <= m->q_max_rad[j] - CARTSEG_GOAL_MARGIN_RAD))
            break;
    if (d_cont < HUGE_VAL && j == ARM_NJ) {
        memcpy(q_goal, cont, sizeof cont);
        return 0;
    }
    if (!inside)
        return CARTSEG_ERR_NO_GOAL;
    memcpy(q_goal, best, sizeof best);
    return 1;
}

/* Distance of the tool point from the segment's line. */
static double line_deviation(const erlaw_line *l, const double x[3])
{
    double d[3];
    vec3_sub(d, l->p0_m, x);
    vec3_axpy(d, d, -vec3_dot(d, l->ch.e), l->ch.e);
    return vec3_norm(d);
}

/* While blocked the hold point moves on along the path with the tool as
 * long as the tool moves along the path (faster than
 * CARTSEG_HOLD_V_MPS, its sideways speed at most CARTSEG_HOLD_SIDE_FRAC
 * of that): the obstacle is gone (or lets it slide), and the bias carries
 * the arm on until s gains CARTSEG_UNBLOCK_EPS_M. Progress that drags the
 * tool sideways (a pinned proximal link: the other joints can only carry
 * the tool on along the path by leaving it) is not taken: the hold point
 * stays and the servo holds the arm near it, so the bias alone is
 * resisted. "Near" is measured after the free servo's static cross-track
 * error (hold_off, model error / k_p: 4-7 mm in the simulator), and with
 * a 4 mm allowance for the rest of it: a released arm must not be held
 * by its own static error (with 2 mm, arm 2 stayed held for good after a
 * t5 upper-arm block). The price: a pinned arm may slide up to that far
 * sideways before the hold stops it (model as plant, upper arm pinned:
 * 10 N settled with 2 mm, 16 N with 4 mm). */
/* The rest rule of hold_ratchet: 1 when the hold point may move on to a
 * tool that has rested CARTSEG_HOLD_REST_S half the bias's reach ahead of
 * it; after the first such move, only if the tool went on mostly along
 * the path since (sideways at most CARTSEG_HOLD_SIDE_FRAC of it). */
static int hold_rest_step(cartseg *c, const double x[3], const double v[3], double along, double dt)
{
    const double *e = c->line.ch.e;
    const erlaw_gains *g = &c->line.ch.g;
    double d[3], d_along;
    if (!(vec3_norm(v) < CARTSEG_HOLD_REST_MPS && g->k_p > 0.0 && along >= 0.5 * g->k0 / g->k_p)) {
        c->t_rest_s = 0.0;
        return 0;
    }
    c->t_rest_s += dt;
    if (c->t_rest_s < CARTSEG_HOLD_REST_S)
        return 0;
    c->t_rest_s = 0.0;
    vec3_sub(d, x, c->rest_pos_m);
    d_along = vec3_dot(d, e);
    vec3_axpy(d, d, -d_along, e);
    if (c->rest_steps > 0 && !(d_along > 0.0 && vec3_norm(d) <= CARTSEG_HOLD_SIDE_FRAC * d_along))
        return 0;
    vec3_copy(c->rest_pos_m, x);
    c->rest_steps++;
    return 1;
}

static void hold_ratchet(cartseg *c, const double x[3], const double v[3], double dt)
{
    const double *e = c->line.ch.e;
    const double v_along = vec3_dot(v, e);
    double side_v[3], side_x[3], along;
    int moving_along, near;
    vec3_axpy(side_v, v, -v_along, e);
    vec3_sub(side_x, x, c->line.x_hold_m);
    along = vec3_dot(side_x, e);
    vec3_axpy(side_x, side_x, -along, e);
    /* where the servo leaves the tool when nothing but the model error
     * pushes it: hold_off short of the hold point */
    vec3_add(side_x, side_x, c->hold_off_m);
    vec3_axpy(side_x, side_x, -vec3_dot(side_x, e), e);
    moving_along = v_along >= CARTSEG_HOLD_V_MPS &&
                   vec3_norm(side_v) <= CARTSEG_HOLD_SIDE_FRAC * v_along;
    near = vec3_norm(side_x) < CARTSEG_HOLD_SLIP_M;
    if (along > 0.0 && (moving_along || near || hold_rest_step(c, x, v, along, dt)))
        vec3_axpy(c->line.x_hold_m, c->line.x_hold_m, along, e);
}

/* Blocked detection: s stalls (erlaw_block_update), or, while motion is
 * commanded, the tool is pushed CARTSEG_BLOCK_DEV_M further off the line
 * than it has been since the last block ended. The second test catches an
 * obstacle that pins a proximal link: the other joints carry the tool on
 * along the path (s does not stall for a second or more) but off the line,
 * and the cross-track and orientation servos load the contact with the
 * lever-arm multiple of their error. A deviation block then lasts, like a
 * stall, until s gains CARTSEG_UNBLOCK_EPS_M. */
static int block_update(cartseg *c, double s, double v_along, double dev, int commanding, double dt)
{
    int blocked;
    c->dev_ref_m = fmin(c->dev_ref_m, dev);
    if (!c->blocked && commanding && dev > c->dev_ref_m + CARTSEG_BLOCK_DEV_M) {
        /* the tool may still be moving along the path: count the progress
         * that releases the block from where the damping -k_v V alone
         * brings it to rest (v / k_v on), not from here */
        const double k_v = c->line.ch.g.k_v;
        c->blk.s_best_m = fmax(c->blk.s_best_m, s + (k_v > 0.0 ? fmax(v_along, 0.0) / k_v : 0.0));
        c->blk.t_still_s = CARTSEG_BLOCK_TIME_S + dt;
    }
    blocked = erlaw_block_update(&c->blk, s, commanding, dt,
                                 c->blocked ? CARTSEG_UNBLOCK_EPS_M : CARTSEG_BLOCK_EPS_M,
                                 CARTSEG_BLOCK_TIME_S);
    if (c->blocked && !blocked)
        c->dev_ref_m = dev; /* rejoining the line from here is not a new block */
    return blocked;
}

/* Static cross-track error of the free servo (model error / k_p). */
static void static_err_update(cartseg *c, const double x_err[3], double dt_s)
{
    double xe[3];
    const double a = dt_s / (CARTSEG_STATIC_ERR_TAU_S + dt_s);
    int i;
    vec3_copy(xe, x_err);
    vec3_axpy(xe, xe, -vec3_dot(xe, c->line.ch.e), c->line.ch.e);
    for (i = 0; i < 3; i++)
        c->err_filt_m[i] += a * (xe[i] - c->err_filt_m[i]);
    /* hold_off is the filter as it was 0.25-0.5 s ago: the deflection
     * an obstacle causes before it is detected must not count */
    c->t_snap_s += dt_s;
    if (c->t_snap_s >= CARTSEG_STATIC_ERR_DELAY_S) {
        c->t_snap_s = 0.0;
        vec3_copy(c->hold_off_m, c->err_snap_m);
        vec3_copy(c->err_snap_m, c->err_filt_m);
    }
}

/* A block is detected: freeze the references at the measured pose (plus
 * the servo's static error, so it keeps up its effort against the model
 * error): from the next cycle the only demand is the bias along the path. */
static void block_enter(cartseg *c, const double x_world[3], const double T_base[16])
{
    double x_hold[3];
    c->t_rest_s = 0.0;
    c->rest_steps = 0;
    vec3_copy(c->rest_pos_m, x_world);
    vec3_add(x_hold, x_world, c->hold_off_m);
    erlaw_line_hold(&c->line, x_hold);
    tf_rot(c->R_hold_base, T_base);
}

int cartseg_step(cartseg *c, const arm_model *m, const arm_tool *tool, const arm_payload *payload,
                 const double q[ARM_NJ], const double qd[ARM_NJ], double s_ext_m, double dt_s,
                 cartseg_out *out)
{
    cartctl_state st;
    if (cartctl_state_at(m, tool, q, qd, &st) != 0) {
        if (out)
            memset(out, 0, sizeof *out);
        return CARTSEG_ERR_ARG;
    }
    return cartseg_step_at(c, m, payload, &st, q, qd, s_ext_m, dt_s, out);
}

int cartseg_step_at(cartseg *c, const arm_model *m, const arm_payload *payload,
                    const cartctl_state *stp, const double q[ARM_NJ], const double qd[ARM_NJ],
                    double s_ext_m, double dt_s, cartseg_out *out)
{
    cartctl_out co;
    erlaw_out eo;
    double Rwb[9], u_base[3], dev;
    int sync, commanding, blocked, held;
    erlaw_ref ref;
    if (!c || !out)
        return CARTSEG_ERR_ARG;
    sync = s_ext_m >= 0.0 && c->ref == ERLAW_REF_MEASURED; /* c is checked first */
    ref = sync ? ERLAW_REF_EXTERNAL : c->ref;
    memset(out, 0, sizeof *out);
    if (!isfinite(dt_s) || dt_s < 0.0 || !stp)
        return CARTSEG_ERR_ARG;
    tool_world(stp, c->T_world_base, Rwb, out->x_world, out->v_world);
    if (c->contact_N >= 0.0)
        c->t_no_contact_s = c->contact_N >= CARTSEG_CONTACT_N ? 0.0 : c->t_no_contact_s + dt_s;
    /* a detected block suspends the planned motion (event law only; the
     * baseline keeps its clock): lean on the obstacle with the bias, the
     * pose across the path and the orientation held where the block was
     * detected */
    if (c->blocked && c->ref == ERLAW_REF_MEASURED)
        ref = ERLAW_REF_BLOCKED;
    if (erlaw_line_step(&c->line, out->x_world, out->v_world, ref, s_ext_m, dt_s, &eo) != 0)
        return CARTSEG_ERR_ARG;
    out->s_m = eo.s_m;
    out->s_ref_m = eo.s_ref_m;
    out->s_f_m = erlaw_channel_length(&c->line.ch);
    out->bias = eo.bias;
    vec3_copy(out->u_world, eo.u);
    out->done = erlaw_done(eo.s_m, out->s_f_m, vec3_norm(out->v_world), CARTSEG_DONE_TOL_M,
                           CARTSEG_DONE_SPEED_MPS);
    /* motion is asked while not done; a synchronised arm whose reference
     * k_i s* is behind its own s is held by its partner (a follower rests
     * ERLAW_FOLLOW_GAP_M ahead of it): waiting, not blocked. The laggard has k_i s* = s. Near
     * the goal the law creeps in exponentially (V_d ~ sqrt(u_m)(s_f - s)):
     * slow, not blocked. */
    held = sync && fmin(s_ext_m, out->s_f_m) <= eo.s_m - 0.5 * CARTSEG_BLOCK_EPS_M;
    commanding = !out->done && out->s_f_m - eo.s_m > CARTSEG_BLOCK_NEAR_GOAL_M && !held;
    dev = line_deviation(&c->line, out->x_world);
    out->deviation_m = dev;
    blocked = c->block_detect ? block_update(c, eo.s_m, vec3_dot(out->v_world, c->line.ch.e), dev,
                                             commanding, dt_s)
                              : 0;
    if (blocked && c->contact_N >= 0.0 && c->ref == ERLAW_REF_MEASURED &&
        c->t_no_contact_s > (c->blocked ? CARTSEG_FREE_S : CARTSEG_BLOCK_TIME_S)) {
        /* nothing touches the arm: a new stall is not an obstacle (stuck),
         * and a blocked arm's obstacle is gone */
        out->stuck = !c->blocked;
        blocked = 0;
        erlaw_block_reset(&c->blk, eo.s_m);
        c->dev_ref_m = dev;
    }
    out->block_changed = blocked != c->blocked;
    if (blocked && c->blocked)
        hold_ratchet(c, out->x_world, out->v_world, dt_s);
    if (!blocked)
        static_err_update(c, eo.x_err, dt_s);
    if (blocked && !c->blocked)
        block_enter(c, out->x_world, stp->T);
    if (!blocked && c->blocked)
        erlaw_channel_resume(&c->line.ch, eo.s_m); /* released: from rest, as a start */
    c->blocked = blocked;
    out->blocked = blocked;
    rot_tapply(u_base, Rwb, eo.u);
    if (cartctl_torque_at(m, payload, &c->cg, q, qd, stp, u_base,
                          ref == ERLAW_REF_BLOCKED ? c->R_hold_base : c->R_d_base, out->tau_Nm,
                          &co) != 0)
        return CARTSEG_ERR_ARG;
    out->saturated = co.saturated;
    out->range_limited = co.range_limited;
    return 0;
}

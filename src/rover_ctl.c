/* rover_ctl: one Pioneer's distributed formation controller (SPEC.md
 * section 4: team-average reference, behaviours, eq. 11 blend, narrow
 * passage protocol, dead-zone escape, heartbeat membership; section 7: safe
 * stop on stale input). Glue over odometry, team, formation and behaviour;
 * the one new piece is the escape's boundary following (see rover_ctl.h).
 */
#include "rover_ctl.h"
#include "rover_world.h"

#include <math.h>
#include <string.h>

void rover_ctl_params_default(rover_ctl_params_t *p)
{
    behaviour_params_default(&p->beh);
    /* 0.5 m: a column in a 1.3 m corridor (side echoes ~0.51 m) must not
     * read as a dead zone, a robot in a 1.0 m trap (~0.36 m) must. */
    p->beh.d_s_m = 0.5;
    formation_fsm_params_default(&p->fsm);
    p->fsm.shrink_scale = 0.8;
    p->fsm.clear_hold_s = 4.0;   /* 10 s (the whole column out) did worse in the corridor runs */
    p->blend_mode = BEH_BLEND_WEIGHTED;
    p->formation = FORMATION_LINE;
    p->team_timeout_s = TEAM_TIMEOUT_S_DEFAULT;
    p->beacon_alpha = 0.2;
    p->stale_s = 0.5;
    p->team_period_s = 0.1;
    p->wheel_radius_m = ODOMETRY_P2DX_WHEEL_RADIUS_M;
    p->axle_track_m = ODOMETRY_P2DX_AXLE_TRACK_M;
    p->follow_dist_m = 0.45;
    p->follow_v_mps = 0.25;
    p->follow_w_radps = 0.7;
    p->escape_max_s = 60.0;
    p->passage_sense_max_m = 2.5;
    p->mate_keep_m = 0.45;
    p->v_change_mps = 0.25;
    p->goal_heading_gain = 1.0;
    p->guard_m = 0.5;
    p->guard_stop_m = 0.15;
    p->passage_front_min_m = 2.0;
    p->passage_hold_s = 0.0;
    p->sonar_max_m = 5.0;
}

static int pos(double v) { return isfinite(v) && v > 0.0; }

int rover_ctl_params_check(const rover_ctl_params_t *p)
{
    if (!p || behaviour_params_check(&p->beh) != 0) return -1;
    if (p->blend_mode < BEH_BLEND_WEIGHTED || p->blend_mode > BEH_BLEND_VECSUM) return -1;
    if (p->formation < FORMATION_LINE || p->formation > FORMATION_COLUMN) return -1;
    if (!pos(p->team_timeout_s) || !pos(p->stale_s) || !pos(p->team_period_s) ||
        !pos(p->wheel_radius_m) || !pos(p->axle_track_m) || !pos(p->follow_dist_m) ||
        !pos(p->follow_v_mps) || !pos(p->follow_w_radps) || !pos(p->escape_max_s) ||
        !pos(p->passage_sense_max_m) || !pos(p->mate_keep_m) || !pos(p->v_change_mps) || !pos(p->guard_m) || !pos(p->guard_stop_m) || !isfinite(p->goal_heading_gain) ||
        p->goal_heading_gain < 0.0 || p->goal_heading_gain > 1.0 || !pos(p->passage_front_min_m) || !(p->passage_hold_s >= 0.0) || !pos(p->sonar_max_m) || !pos(p->fsm.spacing_m) ||
        !(p->fsm.shrink_scale > 0.0 && p->fsm.shrink_scale <= 1.0))
        return -1;
    if (!isfinite(p->beacon_alpha) || p->beacon_alpha < 0.0 || p->beacon_alpha > 1.0) return -1;
    return 0;
}

int rover_ctl_init(rover_ctl_t *c, const rover_ctl_params_t *p, int32_t id,
                   const pose2_t *start_c, const double goal_m[2])
{
    if (!c || rover_ctl_params_check(p) != 0 || !start_c || !vec2_pose_finite(start_c) ||
        !goal_m || !isfinite(goal_m[0]) || !isfinite(goal_m[1]) || id < 0)
        return -1;
    memset(c, 0, sizeof *c);
    c->id = id;
    c->p = *p;
    c->start_c = *start_c;
    c->goal_m[0] = goal_m[0];
    c->goal_m[1] = goal_m[1];
    if (team_init(&c->team, id, p->team_timeout_s) != 0) return -1;
    if (formation_fsm_init(&c->fsm, p->formation, 1.0) != 0) return -1;
    behaviour_exception_init(&c->exc);
    c->team_tx_t_s = -INFINITY;
    c->passage_m = INFINITY;
    c->passage_t_s = -INFINITY;
    return 0;
}

int rover_ctl_encoders(rover_ctl_t *c, double left_rad, double right_rad, double t_s)
{
    double ds, dth;
    if (!isfinite(left_rad) || !isfinite(right_rad) || !isfinite(t_s)) return -1;
    if (!c->have_enc) {
        if (odometry_init(&c->odo, c->p.wheel_radius_m, c->p.axle_track_m, c->p.beh.d_m,
                          &c->start_c, left_rad, right_rad) != 0)
            return -1;
        c->have_enc = 1;
        c->enc_t_s = c->prev_enc_t_s = t_s;
        return 0;
    }
    if (t_s < c->enc_t_s) return -1;
    if (odometry_update(&c->odo, left_rad, right_rad, &ds, &dth) != 0) return -1;
    if (t_s > c->enc_t_s) {
        const double dt = t_s - c->enc_t_s;
        c->v_est_mps = ds / dt;
        c->w_est_radps = dth / dt;
    }
    c->prev_enc_t_s = c->enc_t_s;
    c->enc_t_s = t_s;
    return 0;
}

int rover_ctl_sonar(rover_ctl_t *c, const double range_m[BEH_SONAR_N], double t_s)
{
    int i;
    if (!range_m || !isfinite(t_s)) return -1;
    for (i = 0; i < BEH_SONAR_N; i++)
        if (!isfinite(range_m[i]) || range_m[i] < 0.0) return -1;
    memcpy(c->range_m, range_m, sizeof c->range_m);
    c->have_sonar = 1;
    c->sonar_t_s = t_s;
    return 0;
}

int rover_ctl_team_msg(rover_ctl_t *c, const rover_team_msg_t *msg, double t_s)
{
    team_member_t m;
    int rc;
    if (!msg || !isfinite(t_s) || msg->m.robot == c->id) return -1;
    m = msg->m;
    m.t_s = t_s;
    rc = team_update(&c->team, &m);
    if (rc < 0) return -1;
    if (m.announce >= FORMATION_ANN_SHRINK && m.announce <= FORMATION_ANN_RESTORE) {
        formation_announce_t a;
        const int before = c->fsm.type;
        a.code = m.announce;
        a.seq = m.announce_seq;
        a.origin = m.robot;
        a.type = m.formation;
        a.scale = m.scale;
        if (formation_fsm_on_announce(&c->fsm, &a) == 1 && c->fsm.type != before)
            c->formation_changes++;
    } else if (m.announce == FORMATION_ANN_LEAVE || m.announce == FORMATION_ANN_REJOIN) {
        formation_announce_t a;
        a.code = m.announce;
        a.seq = m.announce_seq;
        a.origin = m.robot;
        a.type = c->fsm.type;
        a.scale = c->fsm.scale;
        formation_fsm_on_announce(&c->fsm, &a);
    }
    return rc;
}

int rover_ctl_beacon(rover_ctl_t *c, int32_t target, double range_m, double bearing_rad)
{
    pose2_t o;
    if (!c->have_enc) return -1;
    odometry_pose_o(&c->odo, &o);
    return team_observe(&c->team, target, &o, range_m, bearing_rad, c->p.beacon_alpha);
}

void rover_ctl_follow(unicycle_cmd_t *u, const sonar_groups_t *g, int side,
                      const rover_ctl_params_t *p)
{
    const double s = side < 0 ? -1.0 : 1.0;
    const double near_side = s < 0 ? fmin(g->right_m, g->right_front_m)
                                   : fmin(g->left_m, g->left_front_m);
    const double wmax = p->follow_w_radps;
    if (g->front_m < p->follow_dist_m + 0.1 ||
        (s < 0 ? g->right_front_m : g->left_front_m) < 0.75 * p->follow_dist_m) {
        /* blocked ahead: turn away from the wall side, nearly on the spot */
        u->v_mps = 0.03;
        u->w_radps = -s * wmax;
    } else if (near_side > p->follow_dist_m + 0.8) {
        /* lost the wall (a convex corner): arc round toward it */
        u->v_mps = 0.7 * p->follow_v_mps;
        u->w_radps = s * 0.8 * wmax;
    } else {
        double w = -s * 2.0 * (p->follow_dist_m - near_side);
        if (w > wmax) w = wmax;
        if (w < -wmax) w = -wmax;
        u->v_mps = p->follow_v_mps;
        u->w_radps = w;
    }
}

/* The transducer whose bearing is nearest to b (table order, -90..90 deg). */
static double range_toward(const double range_m[BEH_SONAR_N], double b_rad)
{
    static const double deg[BEH_SONAR_N] = { -90, -50, -30, -10, 10, 30, 50, 90 };
    int i, best = 0;
    for (i = 1; i < BEH_SONAR_N; i++)
        if (fabs(deg[i] * VEC2_PI / 180.0 - b_rad) < fabs(deg[best] * VEC2_PI / 180.0 - b_rad))
            best = i;
    return range_m[best];
}

/* Sonar echoes explained by a team-mate where the team table puts it (and
 * not dangerously close) are not obstacles for the avoid behaviour, the
 * passage test or the dead-zone test: a formation would otherwise flee its
 * own members and read its neighbours as corridor walls. */
static void mask_mates(const rover_ctl_t *c, const pose2_t *o, double keep_m,
                       double masked[BEH_SONAR_N])
{
    static const double deg[BEH_SONAR_N] = { -90, -50, -30, -10, 10, 30, 50, 90 };
    pose2_t cpos;
    int i, k;
    unicycle_c_from_o(&cpos, o, c->p.beh.d_m);
    for (k = 0; k < BEH_SONAR_N; k++) masked[k] = c->range_m[k];
    for (i = 0; i < c->team.n; i++) {
        const team_member_t *m = &c->team.m[i];
        double xy[2], bx, by;
        if (team_position(&c->team, m->robot, xy) != 0) continue;
        /* body centre of the mate: O + (d + offset) along its heading */
        bx = xy[0] + (c->p.beh.d_m + 0.12) * cos(m->theta_rad);
        by = xy[1] + (c->p.beh.d_m + 0.12) * sin(m->theta_rad);
        for (k = 0; k < BEH_SONAR_N; k++) {
            const double a = cpos.theta_rad + deg[k] * VEC2_PI / 180.0;
            const double dist = hypot(bx - cpos.x_m, by - cpos.y_m);
            const double bear = vec2_angle_diff_rad(atan2(by - cpos.y_m, bx - cpos.x_m), a);
            const double half = 0.22 + atan2(0.3, dist > 0.3 ? dist : 0.3) + 0.09;
            if (fabs(bear) < half && fabs(c->range_m[k] - (dist - 0.24)) < 0.4 &&
                c->range_m[k] > keep_m)
                masked[k] = INFINITY;
        }
    }
    for (k = 0; k < BEH_SONAR_N; k++)
        if (isinf(masked[k])) masked[k] = c->p.sonar_max_m;
}

/* R0's heading: the SPEC's circular mean of the robots' headings couples
 * every slot to every robot's turning (a robot that turns rotates the
 * frame, its slot moves sideways, it turns more): long formations (a
 * column) drift round in a slow spiral. With goal_heading_gain g > 0 the
 * heading used is the mean heading pulled toward the bearing of the goal
 * from R0 by the fraction g (1: the goal bearing alone), and its rate w0 is
 * dropped in the same proportion; near the goal the mean is kept. */
static void ref_heading_to_goal(const rover_ctl_t *c, unicycle_state_t *ref)
{
    const double g = c->p.goal_heading_gain;
    const double dx = c->goal_m[0] - ref->x_m, dy = c->goal_m[1] - ref->y_m;
    if (!(g > 0.0) || hypot(dx, dy) < 1.0) return;
    ref->theta_rad = vec2_wrap_rad(ref->theta_rad +
                                   g * vec2_angle_diff_rad(atan2(dy, dx), ref->theta_rad));
    ref->w_radps *= 1.0 - g;
}

/* Eq. 11 only weights avoidance by d_st / range; goal and formation keep
 * pushing, so a robot can creep into an obstacle dead ahead (and with
 * S_LF = S_RF the seed's turn is zero). Last line of defence: forward speed
 * falls to zero guard_stop_m short of the nearest front echo, and a robot
 * blocked ahead that is not turning turns toward the freer side (toward its
 * goal on a tie). */
static void collision_guard(unicycle_cmd_t *u, const sonar_groups_t *g, const pose2_t *o,
                            const double goal[2], const rover_ctl_params_t *p)
{
    const double near = fmin(g->front_m, fmin(g->left_front_m, g->right_front_m));
    double vmax, side;
    if (near >= p->guard_m) return;
    vmax = p->beh.k_v * (near - p->guard_stop_m);
    if (vmax < 0.0) vmax = 0.0;
    if (u->v_mps > vmax) u->v_mps = vmax;
    if (fabs(u->w_radps) < 0.2 && g->front_m < p->guard_m) {
        side = g->left_front_m - g->right_front_m;
        if (fabs(side) < 0.05)
            side = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m), o->theta_rad);
        u->w_radps = side >= 0.0 ? 0.5 : -0.5;
    }
}

/* This robot is the last of the team along the direction of travel (from
 * the team's mean position toward the goal), within 0.1 m: only the last
 * robot through a passage may restore the formation. */
static int is_rearmost(const rover_ctl_t *c, const pose2_t *o)
{
    double mx = o->x_m, my = o->y_m, ex, ey, len, own;
    int i, n = 1;
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (team_position(&c->team, c->team.m[i].robot, xy) != 0) continue;
        mx += xy[0];
        my += xy[1];
        n++;
    }
    mx /= n;
    my /= n;
    ex = c->goal_m[0] - mx;
    ey = c->goal_m[1] - my;
    len = hypot(ex, ey);
    if (!(len > 1e-6)) return 1;
    own = (o->x_m * ex + o->y_m * ey) / len;
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (team_position(&c->team, c->team.m[i].robot, xy) != 0) continue;
        if ((xy[0] * ex + xy[1] * ey) / len < own - 0.1) return 0;
    }
    return 1;
}

static void own_goal(const rover_ctl_t *c, int n, int k, double g[2])
{
    double xy[2] = { 0.0, 0.0 }, r[2];
    const double heading = atan2(c->goal_m[1], c->goal_m[0]);
    if (k >= 0) formation_slot_xy(xy, c->fsm.type, n, k, c->p.fsm.spacing_m, c->fsm.scale);
    vec2_rotate(r, xy[0], xy[1], heading);
    g[0] = c->goal_m[0] + r[0];
    g[1] = c->goal_m[1] + r[1];
}

static void announce_own(rover_ctl_t *c, int code)
{
    c->ann_code = code;
    c->ann_seq = formation_fsm_next_seq(&c->fsm);
}

/* Dead-zone escape state machine; returns 1 while escaping (U in *u). */
static int escape_step(rover_ctl_t *c, const sonar_groups_t *gw, const sonar_groups_t *g,
                       const pose2_t *o,
                       const double goal[2], double dt_s, unicycle_cmd_t *u)
{
    unicycle_cmd_t turn;
    const int entries = c->exc.entries;
    const int in_dz = behaviour_exception_step(&c->exc, &turn, gw, dt_s, &c->p.beh);
    const double dist = hypot(goal[0] - o->x_m, goal[1] - o->y_m);
    if (in_dz == 1) {
        if (c->exc.entries != entries) {        /* a new entry */
            if (c->esc_phase == ROVER_ESC_NONE) {
                c->esc_hit_dist_m = dist;
                announce_own(c, FORMATION_ANN_LEAVE);
            }
            c->escapes++;
            c->esc_s = 0.0;
            /* turned left (+w_k): keep the wall on the right */
            c->esc_side = turn.w_radps > 0.0 ? -1 : 1;
        }
        c->esc_phase = ROVER_ESC_TURN;
        *u = turn;
        return 1;
    }
    if (c->esc_phase == ROVER_ESC_NONE) return 0;
    c->esc_phase = ROVER_ESC_FOLLOW;
    c->esc_s += dt_s;
    {
        const double b = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m),
                                             o->theta_rad);
        const int free_way = fabs(b) < 0.5 * VEC2_PI && range_toward(c->range_m, b) > 1.2 &&
                             g->front_m > 0.8;
        if ((dist < c->esc_hit_dist_m - 0.5 && free_way) || c->esc_s > c->p.escape_max_s) {
            c->esc_phase = ROVER_ESC_NONE;
            announce_own(c, FORMATION_ANN_REJOIN);
            return 0;
        }
    }
    rover_ctl_follow(u, g, c->esc_side, &c->p);
    return 1;
}

static void stop_out(rover_ctl_out_t *out, int mode)
{
    memset(out, 0, sizeof *out);
    out->mode = mode;
}

int rover_ctl_step(rover_ctl_t *c, double t_s, double dt_s, rover_ctl_out_t *out)
{
    const behaviour_params_t *bp = &c->p.beh;
    sonar_groups_t g, gw;
    pose2_t o;
    unicycle_state_t self, ref;
    int32_t ids[TEAM_MAX + 1];
    int n, k, rc_goal, escaping, i;
    double l_d, phi_d, D, goal[2], R_d = 0.0, passage;
    int side_hidden;
    double masked[BEH_SONAR_N];
    behaviour_inputs_t in;
    formation_announce_t ann;
    unicycle_cmd_t u;
    if (!c || !out || !isfinite(t_s) || !isfinite(dt_s) || dt_s < 0.0) {
        if (out) stop_out(out, ROVER_MODE_SAFE_STOP);
        return -1;
    }
    if (!c->have_enc || !c->have_sonar || t_s - c->enc_t_s > c->p.stale_s ||
        t_s - c->sonar_t_s > c->p.stale_s) {
        /* SPEC 7: stop, and stay silent so the mates re-slot without us */
        stop_out(out, ROVER_MODE_SAFE_STOP);
        if (c->have_enc) odometry_pose_o(&c->odo, &out->o);
        return 0;
    }
    memset(out, 0, sizeof *out);
    team_expire(&c->team, t_s);
    odometry_pose_o(&c->odo, &o);
    self.x_m = o.x_m; self.y_m = o.y_m; self.theta_rad = o.theta_rad;
    self.v_mps = c->v_est_mps; self.w_radps = c->w_est_radps;
    n = team_ids(&c->team, ids, TEAM_MAX + 1);
    k = rover_world_slot(c->fsm.type, n, formation_slot_of(ids, n, c->id));
    {
        /* avoid sees mates that come too near; the passage and dead-zone
         * tests never take a mate for a wall */
        mask_mates(c, &o, c->p.mate_keep_m, masked);
        behaviour_sonar_groups(&g, masked);
        mask_mates(c, &o, 0.0, masked);
        behaviour_sonar_groups(&gw, masked);
        /* a side transducer that sees a mate cannot see the wall behind it */
        side_hidden = masked[0] != c->range_m[0] || masked[BEH_SONAR_N - 1] != c->range_m[BEH_SONAR_N - 1];
    }
    own_goal(c, n, k, goal);
    escaping = escape_step(c, &gw, &g, &o, goal, dt_s, &in.u[BEH_EXCEPTION]);

    /* narrow-passage protocol (not while escaping: the trap is not a passage).
     * A passage has an open end ahead; walls on three sides are a trap
     * (the dead-zone exception's business), not a passage. A side hidden
     * by a mate or a front blocked (a mate or a bend ahead) leaves the
     * width unknown, not clear: unknown neither narrows nor restores. */
    if (!side_hidden && gw.left_m < c->p.passage_sense_max_m &&
        gw.right_m < c->p.passage_sense_max_m && gw.front_m > c->p.passage_front_min_m) {
        c->passage_m = gw.left_m + gw.right_m + bp->robot_width_m;
        c->passage_t_s = t_s;
        passage = c->passage_m;
    } else if ((gw.left_m >= c->p.passage_sense_max_m &&
                masked[BEH_SONAR_N - 1] == c->range_m[BEH_SONAR_N - 1]) ||
               (gw.right_m >= c->p.passage_sense_max_m && masked[0] == c->range_m[0])) {
        passage = INFINITY;                   /* a real open side: no passage */
    } else {
        passage = t_s - c->passage_t_s <= c->p.passage_hold_s ? c->passage_m : NAN;
    }
    if (!escaping) {
        const int before = c->fsm.type;
        if (formation_fsm_step(&c->fsm, &c->p.fsm, passage, n, dt_s, c->id,
                               is_rearmost(c, &o), &ann) == 1) {
            c->ann_code = ann.code;
            c->ann_seq = ann.seq;
            if (c->fsm.type != before) c->formation_changes++;
        }
    }
    k = rover_world_slot(c->fsm.type, n, formation_slot_of(ids, n, c->id));  /* type may have changed */
    if (team_reference(&ref, &c->team, &self, escaping, bp->d_m, t_s) < 0) ref = self;
    ref_heading_to_goal(c, &ref);
    if (k < 0 || formation_slot(&l_d, &phi_d, c->fsm.type, n, k, c->p.fsm.spacing_m,
                                c->fsm.scale) != 0) {
        l_d = 0.0;
        phi_d = 0.0;
    }
    D = formation_width(c->fsm.type, n, c->p.fsm.spacing_m, c->fsm.scale, bp->robot_width_m);

    rc_goal = behaviour_goal(&in.u[BEH_GOAL], &o, goal, bp);
    /* the seed law near the slot, slot tracking away from it (behaviour.h) */
    behaviour_formation_track(&in.u[BEH_FORMATION], &R_d, &o, &ref, l_d, phi_d, bp);
    in.d_st_m = behaviour_d_st(bp, D, l_d, phi_d);
    in.avoid_active = behaviour_avoid(&in.u[BEH_AVOID], &g, self.v_mps, in.d_st_m, bp);
    in.exception_active = escaping;
    if (!escaping) in.u[BEH_EXCEPTION].v_mps = in.u[BEH_EXCEPTION].w_radps = 0.0;
    in.R_d_m = R_d;
    in.min_range_m = g.min_m > 0.05 ? g.min_m : 0.05;
    if (behaviour_blend(&c->blend, &in, c->p.blend_mode, bp) != 0) {
        stop_out(out, ROVER_MODE_SAFE_STOP);
        return -1;
    }
    u = c->blend.u;
    /* while the formation reshapes for a passage, give it time */
    if (c->fsm.phase == FORMATION_PHASE_SHRINK || c->fsm.phase == FORMATION_PHASE_CHANGE)
        if (u.v_mps > c->p.v_change_mps) u.v_mps = c->p.v_change_mps;
    out->mode = escaping ? ROVER_MODE_DEAD_ZONE
              : c->fsm.phase != FORMATION_PHASE_NORMAL ? ROVER_MODE_CHANGING
              : ROVER_MODE_FORMATION;
    if (!escaping && rc_goal == BEH_GOAL_REACHED) {
        u.v_mps = u.w_radps = 0.0;
        out->mode = ROVER_MODE_AT_GOAL;
    }
    if (!escaping) collision_guard(&u, &g, &o, goal, &c->p);
    /* no rear sonar: never back up blindly */
    if (u.v_mps < 0.0) u.v_mps = 0.0;
    unicycle_saturate(&out->u, &u, bp->v_max_mps, bp->w_max_radps, UNICYCLE_SAT_CLIP);
    out->o = o;
    for (i = 0; i < BEH_COUNT; i++) out->weight[i] = c->blend.weight[i];
    out->slot_err_m = R_d;
    out->team_size = n;

    if (t_s - c->team_tx_t_s >= c->p.team_period_s - 1e-9) {
        team_member_t *m = &out->team;
        c->team_tx_t_s = t_s;
        out->send_team = 1;
        memset(m, 0, sizeof *m);
        m->robot = c->id;
        m->x_m = o.x_m; m->y_m = o.y_m; m->theta_rad = o.theta_rad;
        m->v_mps = self.v_mps; m->w_radps = self.w_radps;
        m->formation = c->fsm.type;
        m->scale = c->fsm.scale;
        m->announce = escaping ? FORMATION_ANN_LEAVE : c->ann_code;
        m->announce_seq = c->ann_seq;
        m->t_s = t_s;
    }
    return 0;
}

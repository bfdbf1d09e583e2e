/* rover_ctl: one Pioneer's distributed formation controller (SPEC.md
 * section 4: team-average reference, behaviours, eq. 11 blend, narrow
 * passage protocol, dead-zone escape, heartbeat membership; section 7: safe
 * stop on stale input). Glue over odometry, team, formation and behaviour;
 * the pieces of its own are the escape's boundary following, giving way to
 * a mate that escapes, the mate mask of the sonar ring, the collision guard
 * and the frame consensus (see rover_ctl.h and each function).
 */
#include "rover_ctl.h"
#include "rover_world.h"
#include "sonar.h"

#include <math.h>
#include <string.h>

void rover_ctl_params_default(rover_ctl_params *p)
{
    behaviour_params_default(&p->beh);
    /* 0.5 m: a column in a 1.3 m corridor (side echoes ~0.51 m) must not
     * read as a dead zone, a robot in a 1.0 m trap (~0.36 m) must. */
    p->beh.d_s_m = 0.5;
    /* at the goal slot: stop when O is this near. The behaviour's 0.3 m left
     * every robot about that far short, the whole team's centroid with it
     * (the goal test allows 0.5 m, odometry drift takes most of it); eq. 5
     * drives O forward down to d + goal_margin = 0.2 m, so a little above */
    p->beh.goal_tol_m = 0.22;
    formation_fsm_params_default(&p->fsm);
    p->fsm.shrink_scale = 0.8;
    p->fsm.clear_hold_s = 4.0;   /* 10 s (the whole column out) did worse in the corridor runs */
    p->blend_mode = BEH_BLEND_WEIGHTED;
    p->formation_law = ROVER_LAW_SEED;
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
    p->give_way_m = 2.0;
    p->yield_max_s = 6.0;
    p->give_way_seen_s = 1.0;
    p->yield_clear_m = 0.75;
    p->yield_wait_s = 5.0;
    p->follow_lost_s = 5.0;
    p->passage_sense_max_m = 2.5;
    p->mate_keep_m = 0.45;
    p->v_change_mps = 0.25;
    p->goal_heading_gain = 1.0;
    p->guard_m = 0.5;
    p->guard_stop_m = 0.15;
    p->guard_lane_m = 0.1;
    p->side_guard_m = 0.3;
    p->side_turn_radps = 0.4;
    p->passage_front_min_m = 2.0;
    p->sonar_max_m = 5.0;
    p->consensus_gain = 0.2;
    p->consensus_age_s = 2.0;
    p->consensus_max_mps = 0.05;
    p->consensus_range_m = 2.5;
    p->localize = 1;
    localize_params_default(&p->loc);
    p->loc_sd0_xy_m = 0.02;
    p->loc_sd0_theta_rad = 0.01;
}

static int pos(double v) { return isfinite(v) && v > 0.0; }

int rover_ctl_params_validate(const rover_ctl_params *p)
{
    if (!p || behaviour_params_validate(&p->beh) != 0) return -1;
    if (p->blend_mode < BEH_BLEND_WEIGHTED || p->blend_mode > BEH_BLEND_VECSUM) return -1;
    if (p->formation_law != ROVER_LAW_SEED && p->formation_law != ROVER_LAW_KANAYAMA) return -1;
    if (p->formation < FORMATION_LINE || p->formation > FORMATION_COLUMN) return -1;
    if (!pos(p->team_timeout_s) || !pos(p->stale_s) || !pos(p->team_period_s) ||
        !pos(p->wheel_radius_m) || !pos(p->axle_track_m) || !pos(p->follow_dist_m) ||
        !pos(p->follow_v_mps) || !pos(p->follow_w_radps) || !pos(p->escape_max_s) ||
        !pos(p->give_way_m) || !pos(p->yield_max_s) || !pos(p->give_way_seen_s) ||
        !pos(p->yield_clear_m) || !pos(p->yield_wait_s) ||
        !pos(p->follow_lost_s) ||
        !pos(p->passage_sense_max_m) || !pos(p->mate_keep_m) || !pos(p->v_change_mps) || !pos(p->guard_m) || !pos(p->guard_stop_m) || !pos(p->guard_lane_m) ||
        !pos(p->side_guard_m) || !pos(p->side_turn_radps) || !isfinite(p->goal_heading_gain) ||
        p->goal_heading_gain < 0.0 || p->goal_heading_gain > 1.0 || !pos(p->passage_front_min_m) || !pos(p->sonar_max_m) ||
        !(p->consensus_gain >= 0.0) || !isfinite(p->consensus_gain) || !pos(p->consensus_age_s) ||
        !pos(p->consensus_max_mps) || !pos(p->consensus_range_m) || !pos(p->fsm.spacing_m) ||
        !(p->fsm.shrink_scale > 0.0 && p->fsm.shrink_scale <= 1.0))
        return -1;
    if (!isfinite(p->beacon_alpha) || p->beacon_alpha < 0.0 || p->beacon_alpha > 1.0) return -1;
    if ((p->localize != 0 && p->localize != 1) || localize_params_validate(&p->loc) != 0 ||
        !isfinite(p->loc_sd0_xy_m) || p->loc_sd0_xy_m < 0.0 || !isfinite(p->loc_sd0_theta_rad) ||
        p->loc_sd0_theta_rad < 0.0)
        return -1;
    return 0;
}

int rover_ctl_init(rover_ctl_state *c, const rover_ctl_params *p, int32_t id,
                   const pose2 *start_c, const double goal_m[2])
{
    if (!c || rover_ctl_params_validate(p) != 0 || !start_c || !vec2_pose_finite(start_c) ||
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
    return 0;
}

int rover_ctl_set_landmarks(rover_ctl_state *c, const double (*lm_m)[2], int n)
{
    int k;
    if (!c || n < 0 || n > LOCALIZE_LANDMARKS_MAX || (n > 0 && !lm_m) || c->have_enc) return -1;
    for (k = 0; k < n; k++) {
        if (!isfinite(lm_m[k][0]) || !isfinite(lm_m[k][1])) return -1;
        c->lm_m[k][0] = lm_m[k][0];
        c->lm_m[k][1] = lm_m[k][1];
    }
    c->n_lm = n;
    return 0;
}

/* The localizer starts where the odometry does, with the camera at O. */
static int localize_start(rover_ctl_state *c)
{
    localize_params lp = c->p.loc;
    lp.d_m = c->p.beh.d_m;
    return localize_init(&c->loc, &lp, &c->start_c, c->p.loc_sd0_xy_m, c->p.loc_sd0_theta_rad,
                         (const double (*)[2])c->lm_m, c->n_lm);
}

int rover_ctl_encoders(rover_ctl_state *c, double left_rad, double right_rad, double t_s)
{
    double ds, dth;
    if (!isfinite(left_rad) || !isfinite(right_rad) || !isfinite(t_s)) return -1;
    if (!c->have_enc) {
        if (odometry_init(&c->odo, c->p.wheel_radius_m, c->p.axle_track_m, c->p.beh.d_m,
                          &c->start_c, left_rad, right_rad) != 0 ||
            localize_start(c) != 0)
            return -1;
        c->have_enc = 1;
        c->enc_t_s = c->prev_enc_t_s = t_s;
        return 0;
    }
    if (t_s < c->enc_t_s) return -1;
    if (odometry_update(&c->odo, left_rad, right_rad, &ds, &dth) != 0 ||
        localize_predict(&c->loc, ds, dth) != 0)
        return -1;
    if (t_s > c->enc_t_s) {
        const double dt = t_s - c->enc_t_s;
        c->v_est_mps = ds / dt;
        c->w_est_radps = dth / dt;
    }
    c->prev_enc_t_s = c->enc_t_s;
    c->enc_t_s = t_s;
    return 0;
}

int rover_ctl_sonar(rover_ctl_state *c, const double range_m[BEH_SONAR_N], double t_s)
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

int rover_ctl_team_msg(rover_ctl_state *c, const rover_team_msg *msg, double t_s)
{
    team_member m;
    int rc;
    if (!msg || !isfinite(t_s) || msg->m.robot == c->id) return -1;
    m = msg->m;
    m.t_s = t_s;
    rc = team_update(&c->team, &m);
    if (rc < 0) return -1;
    if (m.announce >= FORMATION_ANN_SHRINK && m.announce <= FORMATION_ANN_RESTORE) {
        formation_announce a;
        const int before = c->fsm.type;
        a.code = m.announce;
        a.seq = m.announce_seq;
        a.origin = m.robot;
        a.type = m.formation;
        a.scale = m.scale;
        if (formation_fsm_on_announce(&c->fsm, &a) == 1 && c->fsm.type != before)
            c->formation_changes++;
    } else if (m.announce == FORMATION_ANN_LEAVE || m.announce == FORMATION_ANN_REJOIN) {
        formation_announce a;
        a.code = m.announce;
        a.seq = m.announce_seq;
        a.origin = m.robot;
        a.type = c->fsm.type;
        a.scale = c->fsm.scale;
        formation_fsm_on_announce(&c->fsm, &a);
    }
    return rc;
}

/* Landmarks fused: localization on and the world has some. */
static int localizing(const rover_ctl_state *c)
{
    return c->p.localize && c->n_lm > 0;
}

/* Own pose of O: the localizer's when localizing, else odometry; plus the
 * frame-consensus correction (zero when localizing). */
static void own_pose(const rover_ctl_state *c, pose2 *o)
{
    if (localizing(c)) localize_pose_o(&c->loc, o);
    else odometry_pose_o(&c->odo, o);
    o->x_m += c->corr_m[0];
    o->y_m += c->corr_m[1];
}

int rover_ctl_beacon(rover_ctl_state *c, int32_t target, double range_m, double bearing_rad)
{
    pose2 o;
    if (!c->have_enc) return -1;
    if (target >= ROVER_LANDMARK_ID_BASE) {
        /* a landmark: the localizer's business (ignored with it off) */
        if (!localizing(c)) return 0;
        return localize_landmark(&c->loc, target - ROVER_LANDMARK_ID_BASE, range_m, bearing_rad);
    }
    own_pose(c, &o);
    return team_observe(&c->team, target, &o, range_m, bearing_rad, c->p.beacon_alpha,
                        c->enc_t_s);
}

/* Frame consensus (team.h): every robot dead-reckons with its own drift,
 * so after a few metres the mates' frames disagree by decimetres: robots
 * stopped at their goal slots in their own frames, and a mate holding
 * its formation slot relative to them (the camera sees where they really
 * are) could never reach its own goal slot and circled it. Each robot
 * moves its estimate toward the team mean of the offsets it sees, at
 * consensus_gain (a first-order average over the team: the drifts average
 * out, the frames agree). */
static void frame_consensus(rover_ctl_state *c, double t_s, double dt_s)
{
    double off[2], k, dx, dy, len;
    int n;
    /* with landmarks every robot's frame is the world's: nothing to agree on */
    if (localizing(c)) return;
    n = team_mean_offset(&c->team, t_s, c->p.consensus_age_s, c->p.consensus_range_m, off);
    if (n == 0) return;
    k = c->p.consensus_gain * dt_s * n / (n + 1.0);
    dx = -k * off[0];
    dy = -k * off[1];
    len = hypot(dx, dy);
    if (len > c->p.consensus_max_mps * dt_s) {
        dx *= c->p.consensus_max_mps * dt_s / len;
        dy *= c->p.consensus_max_mps * dt_s / len;
    }
    c->corr_m[0] += dx;
    c->corr_m[1] += dy;
    team_shift_offsets(&c->team, dx, dy);
}

void rover_ctl_follow(unicycle_cmd *u, const sonar_groups *g, int side,
                      const rover_ctl_params *p)
{
    const double s = side < 0 ? -1.0 : 1.0;
    const double near_side = s < 0 ? fmin(g->right_m, g->right_front_m)
                                   : fmin(g->left_m, g->left_front_m);
    const double wmax = p->follow_w_radps;
    if (g->front_m < p->follow_dist_m + 0.1 ||
        (s < 0 ? g->right_front_m : g->left_front_m) < 0.75 * p->follow_dist_m) {
        /* blocked ahead: turn away from the wall side on the spot (creeping
         * forward while turning walked the axle toward the walls of a narrow
         * pocket until the turning tail touched one) */
        u->v_mps = 0.0;
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

/* Entry and exit distances along a ray from (px, py) with direction
 * (dx, dy) through a box (centre, half extents, heading as cos c, sin s);
 * 0 if it misses, 1 if it meets it (entry 0 when the ray starts inside). */
static int ray_box_m(double px, double py, double dx, double dy, double bx, double by,
                     double hx, double hy, double c, double s, double *t_in, double *t_out)
{
    double n_in[2];
    if (!sonar_line_box(px, py, dx, dy, bx, by, hx, hy, c, s, t_in, t_out, n_in)) return 0;
    *t_in = fmax(*t_in, 0.0);
    return *t_in <= *t_out;
}

/* The range of echoes transducer k (at C pose c) can get from a mate whose
 * O the team table puts at xy with heading th, known to MASK_GROW_M: from
 * where the cone (MASK_RAYS rays, widened by MASK_EXTRA_RAD for the
 * heading) first meets the chassis grown by that much to where it leaves
 * it (a ray grazing a face meets it anywhere along the face). 0 if the
 * cone misses even the grown chassis. */
#define MASK_RAYS 7
#define MASK_CONE_RAD (25.0 * VEC2_PI / 180.0)
#define MASK_EXTRA_RAD (3.0 * VEC2_PI / 180.0)
#define MASK_GROW_M 0.15
static int mate_echo_m(const pose2 *c, int k, const double xy[2], double th, double d_m,
                       double *near_m, double *far_m)
{
    const sonar_transducer *tr = &sonar_p2dx_front[k];
    const double cc = cos(c->theta_rad), sc = sin(c->theta_rad);
    const double px = c->x_m + tr->x_m * cc - tr->y_m * sc;
    const double py = c->y_m + tr->x_m * sc + tr->y_m * cc;
    const double cth = cos(th), sth = sin(th);
    const double bx = xy[0] + (d_m + ROVER_BODY_OFFSET_M) * cth;
    const double by = xy[1] + (d_m + ROVER_BODY_OFFSET_M) * sth;
    const double hx = 0.5 * ROVER_BODY_LENGTH_M, hy = 0.5 * ROVER_BODY_WIDTH_M;
    const double span = MASK_CONE_RAD + 2.0 * MASK_EXTRA_RAD;
    const double a0 = c->theta_rad + tr->angle_rad - 0.5 * span, step = span / (MASK_RAYS - 1);
    const double cs = cos(step), ss = sin(step);
    double dx = cos(a0), dy = sin(a0);
    int j, hit = 0;
    *near_m = INFINITY;
    *far_m = 0.0;
    /* the rays of the cone, each the last one turned by `step` */
    for (j = 0; j < MASK_RAYS; j++) {
        const double nx = dx * cs - dy * ss;
        double t_in, t_out;
        if (ray_box_m(px, py, dx, dy, bx, by, hx + MASK_GROW_M, hy + MASK_GROW_M, cth, sth,
                      &t_in, &t_out)) {
            hit = 1;
            if (t_in < *near_m) *near_m = t_in;
            if (t_out > *far_m) *far_m = t_out;
        }
        dy = dx * ss + dy * cs;
        dx = nx;
    }
    return hit;
}

/* A lower bound on any echo mate_echo_m can return: C to the chassis
 * centre, less reach_m (the farthest transducer from C) and the grown
 * chassis' half-diagonal. */
static double mate_min_echo_m(const pose2 *c, const double xy[2], double th, double d_m,
                              double reach_m)
{
    const double bx = xy[0] + (d_m + ROVER_BODY_OFFSET_M) * cos(th);
    const double by = xy[1] + (d_m + ROVER_BODY_OFFSET_M) * sin(th);
    return hypot(bx - c->x_m, by - c->y_m) - reach_m -
           hypot(0.5 * ROVER_BODY_LENGTH_M + MASK_GROW_M, 0.5 * ROVER_BODY_WIDTH_M + MASK_GROW_M);
}

/* Sonar echoes explained by a team-mate where the team table puts it (and
 * not dangerously close) are not obstacles for the avoid behaviour, the
 * passage test or the dead-zone test: a formation would otherwise flee its
 * own members and read its neighbours as corridor walls. An echo is the
 * mate's when it lies in the range of echoes the mate can give
 * (mate_echo_m); a nearer echo is something between us and the mate. For
 * walls (keep_m 0: passage and trap tests) the whole range counts, since
 * a mate must never be taken for a wall; for avoidance only echoes within
 * MASK_DEPTH_M of the nearest possible one (the mate's near face): a far
 * echo off a grazed face is as likely something else, and robots that let
 * mates come closer than that met when they turned on the spot. */
#define MASK_DEPTH_M 0.5
void rover_ctl_mask_mates(const rover_ctl_state *c, const pose2 *o, double keep_m,
                          double masked[BEH_SONAR_N])
{
    pose2 cpos;
    double far_echo_m = 0.0, reach_m = 0.0;
    int i, k;
    unicycle_c_from_o(&cpos, o, c->p.beh.d_m);
    for (k = 0; k < BEH_SONAR_N; k++) {
        masked[k] = c->range_m[k];
        far_echo_m = fmax(far_echo_m, c->range_m[k]);
        reach_m = fmax(reach_m, hypot(sonar_p2dx_front[k].x_m, sonar_p2dx_front[k].y_m));
    }
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        double xy[2];
        if (team_position(&c->team, m->robot, xy) != 0) continue;
        /* a mate whose grown chassis lies beyond every echo explains none:
         * skip the ray casts (a large team is mostly such mates) */
        if (mate_min_echo_m(&cpos, xy, m->theta_rad, c->p.beh.d_m, reach_m) > far_echo_m + 0.05)
            continue;
        for (k = 0; k < BEH_SONAR_N; k++) {
            double near, far;
            if (mate_echo_m(&cpos, k, xy, m->theta_rad, c->p.beh.d_m, &near, &far) &&
                c->range_m[k] > keep_m && c->range_m[k] >= near - 0.05 &&
                c->range_m[k] <= (keep_m > 0.0 ? fmin(far, near + MASK_DEPTH_M) : far) + 0.05)
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
 * dropped in the same proportion. Within a metre of the goal the bearing
 * swings about, so the heading of the goal's own slot frame (own_goal) is
 * used: there the mean heading of robots that have stopped anyhow turned
 * the formation round, and a robot whose slot came to lie behind it
 * circled the goal chasing it. */
static void ref_heading_to_goal(const rover_ctl_state *c, unicycle_state *ref)
{
    const double g = c->p.goal_heading_gain;
    const double dx = c->goal_m[0] - ref->x_m, dy = c->goal_m[1] - ref->y_m;
    const double to = hypot(dx, dy) < 1.0 ? atan2(c->goal_m[1], c->goal_m[0]) : atan2(dy, dx);
    if (!(g > 0.0)) return;
    ref->theta_rad = vec2_wrap_rad(ref->theta_rad + g * vec2_angle_diff_rad(to, ref->theta_rad));
    ref->w_radps *= 1.0 - g;
}

/* Nearest echo in the robot's way: of the front transducers, those whose
 * cone reaches within guard_lane_m of the line the chassis sweeps driving
 * straight (the edge of the cone nearest the heading, from the mounting
 * point), the smallest range. A side-front echo off that lane (a mate
 * driving alongside, a wall being passed) is not in the way; counting it
 * kept two robots that ended up side by side crawling along together. */
static double range_in_way(const double range_m[BEH_SONAR_N], const rover_ctl_params *p)
{
    const double half_cone = 12.5 * VEC2_PI / 180.0;
    double best = INFINITY;
    int k;
    for (k = 1; k < BEH_SONAR_N - 1; k++) {
        const sonar_transducer *tr = &sonar_p2dx_front[k];
        const double b = fmax(fabs(tr->angle_rad) - half_cone, 0.0);
        const double lat = fabs(tr->y_m) + range_m[k] * sin(b);
        if (lat < 0.5 * ROVER_BODY_WIDTH_M + p->guard_lane_m && range_m[k] < best)
            best = range_m[k];
    }
    return best;
}

/* The guard's first rule alone: forward speed falls to zero guard_stop_m
 * short of the nearest echo in the way (range_in_way, which it returns).
 * Also used while giving way, where the boundary follower sees walls only. */
static double guard_speed(unicycle_cmd *u, const double range_m[BEH_SONAR_N], const rover_ctl_params *p)
{
    const double near = range_in_way(range_m, p);
    if (near < p->guard_m) {
        double vmax = p->beh.k_v * (near - p->guard_stop_m);
        if (vmax < 0.0) vmax = 0.0;
        if (u->v_mps > vmax) u->v_mps = vmax;
    }
    return near;
}

/* Eq. 11 only weights avoidance by d_st / range; goal and formation keep
 * pushing, so a robot can creep into an obstacle dead ahead (and with
 * S_LF = S_RF the seed's turn is zero). Last line of defence: forward speed
 * falls to zero guard_stop_m short of the nearest echo in the way
 * (range_in_way); inside guard_m the robot never turns toward the nearer
 * front-side echo (a robot whose formation slot lay beyond a post kept
 * turning into it, the guard held it, and the weighted sum of "toward the
 * slot" and "away from the post" came to nothing: it stood there for the
 * rest of the run); and a robot the guard has stopped that is not turning
 * turns toward the freer side (toward its goal on a tie); an echo alongside
 * within side_guard_m turns it away. It works on the
 * raw ranges: a mate is masked out of the avoid behaviour (or a line would
 * flee its own members), but one in our way is still something to stop
 * short of (two robots closing head-on at full speed met, each taking the
 * other's echo for a mate's). */
void rover_ctl_guard(unicycle_cmd *u, const double range_m[BEH_SONAR_N], const pose2 *o,
                     const double goal[2], const rover_ctl_params *p)
{
    sonar_groups g;
    const double near = guard_speed(u, range_m, p);
    double side;
    behaviour_sonar_groups(&g, range_m);
    side = g.left_front_m - g.right_front_m;
    if (fabs(side) < 0.05)
        side = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m), o->theta_rad);
    if (fmin(g.left_front_m, g.right_front_m) < p->guard_m && u->w_radps * side < 0.0)
        u->w_radps = 0.0;
    if (near < p->guard_m && fabs(u->w_radps) < 0.2 &&
        (g.front_m < p->guard_m || u->v_mps < 0.05))
        u->w_radps = side >= 0.0 ? 0.5 : -0.5;
    {
        /* something alongside within side_guard_m (a mate squeezed toward
         * us past an obstacle: eq. 11's avoidance looks ahead only): turn
         * away from it, if nothing is close ahead on the other side */
        const double l = g.left_m, r = g.right_m;
        if (l < p->side_guard_m && l < r && g.right_front_m >= p->guard_m &&
            u->w_radps > -p->side_turn_radps)
            u->w_radps = -p->side_turn_radps;
        else if (r < p->side_guard_m && r <= l && g.left_front_m >= p->guard_m &&
                 u->w_radps < p->side_turn_radps)
            u->w_radps = p->side_turn_radps;
    }
}

/* Lateral offset of a point from the team's centre line (R0 position,
 * R0 heading), positive to the left. */
static double lateral_m(const unicycle_state *ref, double x, double y)
{
    return -(x - ref->x_m) * sin(ref->theta_rad) + (y - ref->y_m) * cos(ref->theta_rad);
}

enum { SIDE_UNKNOWN = 0, SIDE_OPEN = 1, SIDE_WALL = 2 };

/* What side transducer k (0 right, BEH_SONAR_N - 1 left) says about a
 * passage wall on its side: a mate's echo hides the wall (unknown); no echo
 * within passage_sense_max_m is an open side; an echo is a passage wall
 * only if it lies beyond every mate on that side of the team's centre
 * line. An obstacle with a mate further out lies inside the formation: the
 * team splits round it, it does not squeeze the formation (scattered
 * posts read as walls made the line shrink and change type among them);
 * unknown. */
static int side_wall(const rover_ctl_state *c, const pose2 *cpos, const unicycle_state *ref,
                     const double masked[BEH_SONAR_N], int k)
{
    const sonar_transducer *tr = &sonar_p2dx_front[k];
    const double r = c->range_m[k], side = k == 0 ? -1.0 : 1.0;
    const double ct = cos(cpos->theta_rad), st = sin(cpos->theta_rad);
    const double a = cpos->theta_rad + tr->angle_rad;
    double lat;
    int i;
    if (masked[k] != r) return SIDE_UNKNOWN;
    if (r >= c->p.passage_sense_max_m) return SIDE_OPEN;
    lat = lateral_m(ref, cpos->x_m + tr->x_m * ct - tr->y_m * st + r * cos(a),
                    cpos->y_m + tr->x_m * st + tr->y_m * ct + r * sin(a));
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (team_position(&c->team, c->team.m[i].robot, xy) != 0) continue;
        if (side * (lateral_m(ref, xy[0], xy[1]) - lat) > -0.5 * ROVER_BODY_WIDTH_M)
            return SIDE_UNKNOWN;
    }
    return SIDE_WALL;
}

/* Width of the passage the team is in, for the passage protocol (SPEC 4:
 * left + right + robot width against formation width + safety):
 * INFINITY when a side is really open, NAN when this robot cannot tell
 * (a side hidden by a mate or an obstacle inside the formation, see
 * side_wall; the front closed within passage_front_min_m: walls on three
 * sides are a trap, the dead-zone exception's business, not a passage; or
 * the robot turned more than 45 deg off the team's heading, its side
 * transducers no longer looking across the way). */
static double passage_width(const rover_ctl_state *c, const pose2 *o, const unicycle_state *ref,
                            const sonar_groups *gw, const double masked[BEH_SONAR_N])
{
    pose2 cpos;
    int right, left;
    if (gw->front_m <= c->p.passage_front_min_m ||
        fabs(vec2_angle_diff_rad(o->theta_rad, ref->theta_rad)) > 0.25 * VEC2_PI)
        return NAN;
    unicycle_c_from_o(&cpos, o, c->p.beh.d_m);
    right = side_wall(c, &cpos, ref, masked, 0);
    left = side_wall(c, &cpos, ref, masked, BEH_SONAR_N - 1);
    if (right == SIDE_OPEN || left == SIDE_OPEN) return INFINITY;
    if (right == SIDE_WALL && left == SIDE_WALL)
        return c->range_m[0] + c->range_m[BEH_SONAR_N - 1] + c->p.beh.robot_width_m;
    return NAN;
}

/* This robot is the last of the team along the direction of travel (from
 * the team's mean position toward the goal), within 0.1 m: only the last
 * robot through a passage may restore the formation. Mates that announced
 * LEAVE are out of the formation and do not count (their fsm is idle while
 * they escape; one left behind in a dead zone held the team in a column
 * all the way to the goal). */
static int counts_in_formation(const team_member *m)
{
    return m->announce != FORMATION_ANN_LEAVE;
}

static int is_rearmost(const rover_ctl_state *c, const pose2 *o)
{
    double mx = o->x_m, my = o->y_m, ex, ey, len, own;
    int i, n = 1;
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (!counts_in_formation(&c->team.m[i]) ||
            team_position(&c->team, c->team.m[i].robot, xy) != 0)
            continue;
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
        if (!counts_in_formation(&c->team.m[i]) ||
            team_position(&c->team, c->team.m[i].robot, xy) != 0)
            continue;
        if ((xy[0] * ex + xy[1] * ey) / len < own - 0.1) return 0;
    }
    return 1;
}

static void own_goal(const rover_ctl_state *c, int n, int k, double g[2])
{
    double xy[2] = { 0.0, 0.0 }, r[2];
    const double heading = atan2(c->goal_m[1], c->goal_m[0]);
    if (k >= 0) formation_slot_xy(xy, c->fsm.type, n, k, c->p.fsm.spacing_m, c->fsm.scale);
    vec2_rotate(r, xy[0], xy[1], heading);
    g[0] = c->goal_m[0] + r[0];
    g[1] = c->goal_m[1] + r[1];
}

static void announce_own(rover_ctl_state *c, int code)
{
    c->ann_code = code;
    c->ann_seq = formation_fsm_next_seq(&c->fsm);
}

/* The nearest mate that announced LEAVE (it is escaping a dead zone, or
 * giving way itself) within give_way_m whose bearing from our heading is
 * within cone_rad: 1 and its bearing, or 0. With seen_s > 0 only a mate
 * whose beacon the camera saw within seen_s counts (walls hide beacons: a
 * mate behind a wall is not coming our way) and only one heading our way
 * (within 90 deg of the line to us: one trapped facing the end of its
 * pocket has not turned round yet, one following a wall past us is not
 * coming through). */
static int leaving_mate(const rover_ctl_state *c, const pose2 *o, double cone_rad, double seen_s,
                        double now_s, double *bearing_rad)
{
    double best = c->p.give_way_m;
    int i, found = 0;
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        double xy[2], dist, b;
        if (m->announce != FORMATION_ANN_LEAVE ||
            (seen_s > 0.0 && !(now_s - m->obs_t_s <= seen_s)) ||
            team_position(&c->team, m->robot, xy) != 0)
            continue;
        dist = hypot(xy[0] - o->x_m, xy[1] - o->y_m);
        b = vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad);
        if (seen_s > 0.0 &&
            cos(m->theta_rad) * (o->x_m - xy[0]) + sin(m->theta_rad) * (o->y_m - xy[1]) <= 0.0)
            continue;
        if (dist < best && fabs(b) < cone_rad) {
            best = dist;
            *bearing_rad = b;
            found = 1;
        }
    }
    return found;
}

/* A lower-id mate turning on the spot (not driving) with its axle within
 * yield_clear_m of ours: a robot turning on the spot sweeps a circle of
 * ~0.31 m round its axle, two side by side that both turn sweep their
 * tails into each other; the higher id waits its turn (at most
 * yield_wait_s: the other may be spinning in place until we move). */
static int turn_blocked_by_mate(const rover_ctl_state *c, const pose2 *o)
{
    pose2 own_c;
    int i;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        const int spinning = fabs(m->v_mps) <= 0.05 && fabs(m->w_radps) >= 0.1;
        double xy[2];
        if (m->robot >= c->id || !spinning || team_position(&c->team, m->robot, xy) != 0)
            continue;
        if (hypot(xy[0] + c->p.beh.d_m * cos(m->theta_rad) - own_c.x_m,
                  xy[1] + c->p.beh.d_m * sin(m->theta_rad) - own_c.y_m) < c->p.yield_clear_m)
            return 1;
    }
    return 0;
}

/* Walls (not mates) within reach of boundary following on some side. */
static int confined(const sonar_groups *gw, const rover_ctl_params *p)
{
    return fmin(fmin(gw->left_m, gw->left_front_m), fmin(gw->right_m, gw->right_front_m)) <
           p->follow_dist_m + 0.8;
}

/* Side (-1 right, +1 left) of the nearer wall. */
static int nearer_wall_side(const sonar_groups *gw)
{
    return fmin(gw->left_m, gw->left_front_m) < fmin(gw->right_m, gw->right_front_m) ? 1 : -1;
}

/* Start giving way when a mate that announced LEAVE is ahead within
 * give_way_m and walls are near (the trapped robot's only way out is back
 * past us; nobody made room, it spun in its pocket and the team jammed):
 * leave the formation as well, turn away from the mate, then follow the
 * nearer wall out and round (the escape's boundary following, hit point
 * here). Returns 1 if it started. */
static int give_way_start(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double dist,
                          double t_s)
{
    double b;
    if (!leaving_mate(c, o, 0.5 * VEC2_PI, c->p.give_way_seen_s, t_s, &b) || !confined(gw, &c->p))
        return 0;
    c->esc_phase = ROVER_ESC_YIELD;
    c->esc_yield = 1;
    c->esc_hit_dist_m = dist;
    c->esc_s = 0.0;
    c->esc_lost_s = 0.0;
    c->esc_wait_s = 0.0;
    /* away from the mate; one dead ahead: toward the roomier side */
    if (fabs(b) > 0.2) c->esc_turn = b > 0.0 ? -1 : 1;
    else c->esc_turn = gw->left_m + gw->left_front_m >= gw->right_m + gw->right_front_m ? 1 : -1;
    announce_own(c, FORMATION_ANN_LEAVE);
    return 1;
}

/* Dead-zone escape and give-way state machine; returns 1 while escaping
 * (U in *u).
 *   trapped (SPEC: front, left, right < d_s for the dead-zone time): LEAVE,
 *     turn +-w_k alternately per entry until the front is free (eq. 2),
 *     then FOLLOW the boundary, the wall on the side turned away from;
 *   a mate escaping right ahead (give_way_start): LEAVE, YIELD (turn on
 *     the spot until no leaving mate is ahead, at most yield_max_s of
 *     turning; a lower-id mate turning next to us goes first), then FOLLOW
 *     the nearer wall;
 *   FOLLOW ends (REJOIN) when closer to the goal than where it started
 *     by 0.5 m with the way to the goal free (Bug2's leave rule), or when
 *     no wall has been in reach for follow_lost_s (open floor: nothing to
 *     follow; the follow law would circle for ever looking for it). After
 *     escape_max_s without that it follows the other way round (the
 *     alternation of eq. 2 applied to the boundary): it never rejoins
 *     short of the leave point. Rejoining on a timeout put an escaped robot
 *     back on the straight way to the goal, through the U it had left. */
static int escape_step(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                       const pose2 *o, const double goal[2], double t_s, double dt_s,
                       unicycle_cmd *u)
{
    unicycle_cmd turn;
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
            c->esc_lost_s = 0.0;
            c->esc_wait_s = 0.0;
            c->esc_yield = 0;
            /* turned left (+w_k): keep the wall on the right */
            c->esc_side = turn.w_radps > 0.0 ? -1 : 1;
        }
        c->esc_phase = ROVER_ESC_TURN;
        *u = turn;
        return 1;
    }
    if (c->esc_phase == ROVER_ESC_NONE && !give_way_start(c, gw, o, dist, t_s)) return 0;
    c->esc_s += dt_s;
    if (c->esc_phase == ROVER_ESC_YIELD) {
        double b;
        if (leaving_mate(c, o, 2.0 * VEC2_PI / 3.0, 0.0, t_s, &b) && c->esc_s < c->p.yield_max_s) {
            u->v_mps = 0.0;
            if (c->esc_wait_s < c->p.yield_wait_s && turn_blocked_by_mate(c, o)) {
                u->w_radps = 0.0;
                c->esc_wait_s += dt_s;
                c->esc_s -= dt_s;        /* waiting does not count as turning */
            } else {
                u->w_radps = c->esc_turn * c->p.follow_w_radps;
            }
            return 1;
        }
        c->esc_side = nearer_wall_side(gw);
        c->esc_s = 0.0;
    }
    c->esc_phase = ROVER_ESC_FOLLOW;
    {
        const double b = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m),
                                             o->theta_rad);
        const int free_way = fabs(b) < 0.5 * VEC2_PI && range_toward(c->range_m, b) > 1.2 &&
                             g->front_m > 0.8;
        c->esc_lost_s = confined(gw, &c->p) ? 0.0 : c->esc_lost_s + dt_s;
        if ((dist < c->esc_hit_dist_m - 0.5 && free_way) || c->esc_lost_s > c->p.follow_lost_s) {
            c->esc_phase = ROVER_ESC_NONE;
            c->esc_yield = 0;
            announce_own(c, FORMATION_ANN_REJOIN);
            return 0;
        }
        if (c->esc_s > c->p.escape_max_s) {
            c->esc_side = -c->esc_side;
            c->esc_s = 0.0;
        }
    }
    rover_ctl_follow(u, g, c->esc_side, &c->p);
    if (c->esc_yield) {
        /* the follower sees walls only: a robot giving way stops short of
         * a mate in the way (the echoes the team table explains), not of
         * the wall it follows round a corner */
        double masked[BEH_SONAR_N], mates[BEH_SONAR_N];
        int k;
        rover_ctl_mask_mates(c, o, 0.0, masked);
        for (k = 0; k < BEH_SONAR_N; k++)
            mates[k] = masked[k] != c->range_m[k] ? c->range_m[k] : INFINITY;
        guard_speed(u, mates, &c->p);
    }
    return 1;
}

static void stop_out(rover_ctl_out *out, int mode)
{
    memset(out, 0, sizeof *out);
    out->mode = mode;
}

int rover_ctl_step(rover_ctl_state *c, double t_s, double dt_s, rover_ctl_out *out)
{
    const behaviour_params *bp = &c->p.beh;
    sonar_groups g, gw;
    pose2 o;
    unicycle_state self, ref;
    int32_t ids[TEAM_MAX + 1];
    int n, k, rc_goal, escaping, i;
    double l_d, phi_d, D, goal[2], R_d = 0.0, passage;
    double masked[BEH_SONAR_N];
    behaviour_inputs in;
    formation_announce ann;
    unicycle_cmd u;
    if (!c || !out || !isfinite(t_s) || !isfinite(dt_s) || dt_s < 0.0) {
        if (out) stop_out(out, ROVER_MODE_SAFE_STOP);
        return -1;
    }
    if (!c->have_enc || !c->have_sonar || t_s - c->enc_t_s > c->p.stale_s ||
        t_s - c->sonar_t_s > c->p.stale_s) {
        /* SPEC 7: stop, and stay silent so the mates re-slot without us */
        stop_out(out, ROVER_MODE_SAFE_STOP);
        if (c->have_enc) own_pose(c, &out->o);
        return 0;
    }
    memset(out, 0, sizeof *out);
    team_expire(&c->team, t_s);
    frame_consensus(c, t_s, dt_s);
    own_pose(c, &o);
    self.x_m = o.x_m; self.y_m = o.y_m; self.theta_rad = o.theta_rad;
    self.v_mps = c->v_est_mps; self.w_radps = c->w_est_radps;
    n = team_ids(&c->team, ids, TEAM_MAX + 1);
    k = rover_world_slot(c->fsm.type, n, formation_slot_of(ids, n, c->id));
    {
        /* avoid sees mates that come too near; the passage and dead-zone
         * tests never take a mate for a wall */
        rover_ctl_mask_mates(c, &o, c->p.mate_keep_m, masked);
        behaviour_sonar_groups(&g, masked);
        rover_ctl_mask_mates(c, &o, 0.0, masked);
        behaviour_sonar_groups(&gw, masked);
    }
    own_goal(c, n, k, goal);
    escaping = escape_step(c, &gw, &g, &o, goal, t_s, dt_s, &in.u[BEH_EXCEPTION]);

    /* narrow-passage protocol (not while escaping: the trap is not a passage) */
    if (team_reference(&ref, &c->team, &self, escaping, bp->d_m, t_s) < 0) ref = self;
    ref_heading_to_goal(c, &ref);
    passage = passage_width(c, &o, &ref, &gw, masked);
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
    if (k < 0 || formation_slot(&l_d, &phi_d, c->fsm.type, n, k, c->p.fsm.spacing_m,
                                c->fsm.scale) != 0) {
        l_d = 0.0;
        phi_d = 0.0;
    }
    D = formation_width(c->fsm.type, n, c->p.fsm.spacing_m, c->fsm.scale, bp->robot_width_m);

    rc_goal = behaviour_goal(&in.u[BEH_GOAL], &o, goal, bp);
    if (c->p.formation_law == ROVER_LAW_KANAYAMA)
        behaviour_formation_track(&in.u[BEH_FORMATION], &R_d, &o, &ref, l_d, phi_d, bp);
    else
        behaviour_formation_seed(&in.u[BEH_FORMATION], &R_d, &o, &ref, l_d, phi_d, bp);
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
    /* a robot giving way left the formation but was not trapped itself */
    out->mode = escaping ? (c->esc_yield ? ROVER_MODE_CHANGING : ROVER_MODE_DEAD_ZONE)
              : c->fsm.phase != FORMATION_PHASE_NORMAL ? ROVER_MODE_CHANGING
              : ROVER_MODE_FORMATION;
    if (!escaping && rc_goal == BEH_GOAL_REACHED) {
        u.v_mps = u.w_radps = 0.0;
        out->mode = ROVER_MODE_AT_GOAL;
    }
    if (!escaping) rover_ctl_guard(&u, c->range_m, &o, goal, &c->p);
    /* no rear sonar: never back up blindly */
    if (u.v_mps < 0.0) u.v_mps = 0.0;
    unicycle_saturate(&out->u, &u, bp->v_max_mps, bp->w_max_radps, UNICYCLE_SAT_CLIP);
    out->o = o;
    for (i = 0; i < BEH_COUNT; i++) out->weight[i] = c->blend.weight[i];
    out->slot_err_m = R_d;
    out->team_size = n;

    if (t_s - c->team_tx_t_s >= c->p.team_period_s - 1e-9) {
        team_member *m = &out->team;
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

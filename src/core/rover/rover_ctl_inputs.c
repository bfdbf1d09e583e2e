/* rover_ctl_inputs: what the formation controller takes in (docs/method/
 * formation.md): wheel encoders (odometry), the landmark filter fed by the
 * camera's LED landmarks (localize.h, EKF), sonar ranges, team messages
 * (heartbeat membership, the narrow-passage protocol's announcements
 * adopted through formation_fsm_on_announce) and mates' beacons; the own
 * pose made of them and the frame consensus (team.h); and the mate mask
 * that keeps team-mates' echoes out of the avoid behaviour and the
 * passage and dead-zone tests.
 */
#include "rover_ctl_internal.h"
#include "rover_world.h"
#include "sonar.h"

#include <math.h>
#include <string.h>

int rover_ctl_set_landmarks(rover_ctl_state *c, const double (*lm_m)[2], int n)
{
    int k;
    if (!c || n < 0 || n > LOCALIZE_LANDMARKS_MAX || (n > 0 && !lm_m) || c->have_enc)
        return ROVER_CTL_ERR_ARG;
    for (k = 0; k < n; k++) {
        if (!isfinite(lm_m[k][0]) || !isfinite(lm_m[k][1]))
            return ROVER_CTL_ERR_ARG;
        c->lm_m[k][0] = lm_m[k][0];
        c->lm_m[k][1] = lm_m[k][1];
    }
    c->n_lm = n;
    return ROVER_CTL_OK;
}

/* The localizer starts where the odometry does, with the camera at O. */
static int localize_start(rover_ctl_state *c)
{
    localize_params lp = c->p.loc;
    lp.d_m = c->p.beh.d_m;
    return localize_init(&c->loc, &lp, &c->start_c, c->p.loc_sd0_xy_m, c->p.loc_sd0_theta_rad,
                         (const double(*)[2])c->lm_m, c->n_lm);
}

int rover_ctl_encoders(rover_ctl_state *c, double left_rad, double right_rad, double t_s)
{
    double ds, dth;
    if (!isfinite(left_rad) || !isfinite(right_rad) || !isfinite(t_s))
        return ROVER_CTL_ERR_ARG;
    if (!c->have_enc) {
        if (odometry_init(&c->odo, c->p.wheel_radius_m, c->p.axle_track_m, c->p.beh.d_m,
                          &c->start_c, left_rad, right_rad) != 0 ||
            localize_start(c) != 0)
            return ROVER_CTL_ERR_ARG;
        c->have_enc = 1;
        c->enc_t_s = c->prev_enc_t_s = t_s;
        return ROVER_CTL_OK;
    }
    if (t_s < c->enc_t_s)
        return ROVER_CTL_ERR_ARG;
    if (odometry_update(&c->odo, left_rad, right_rad, &ds, &dth) != 0 ||
        localize_predict(&c->loc, ds, dth) != 0)
        return ROVER_CTL_ERR_ARG;
    if (t_s > c->enc_t_s) {
        const double dt = t_s - c->enc_t_s;
        c->v_est_mps = ds / dt;
        c->w_est_radps = dth / dt;
    }
    c->prev_enc_t_s = c->enc_t_s;
    c->enc_t_s = t_s;
    return ROVER_CTL_OK;
}

int rover_ctl_sonar(rover_ctl_state *c, const double range_m[BEH_SONAR_N], double t_s)
{
    int i;
    if (!range_m || !isfinite(t_s))
        return ROVER_CTL_ERR_ARG;
    for (i = 0; i < BEH_SONAR_N; i++)
        if (!isfinite(range_m[i]) || range_m[i] < 0.0)
            return ROVER_CTL_ERR_ARG;
    memcpy(c->range_m, range_m, sizeof c->range_m);
    c->have_sonar = 1;
    c->sonar_t_s = t_s;
    return ROVER_CTL_OK;
}

int rover_ctl_team_msg(rover_ctl_state *c, const rover_team_msg *msg, double t_s)
{
    team_member m;
    int rc;
    if (!msg || !isfinite(t_s) || msg->m.robot == c->id)
        return ROVER_CTL_ERR_ARG;
    if (msg->m.robot < c->team_lo || msg->m.robot > c->team_hi)
        return ROVER_CTL_ERR_TEAM;
    m = msg->m;
    m.t_s = t_s;
    rc = team_update(&c->team, &m);
    if (rc < 0)
        return ROVER_CTL_ERR_ARG;
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
    } else if (formation_ann_out(m.announce) || m.announce == FORMATION_ANN_REJOIN) {
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
void rover_ctl_own_pose(const rover_ctl_state *c, pose2 *o)
{
    if (localizing(c))
        localize_pose_o(&c->loc, o);
    else
        odometry_pose_o(&c->odo, o);
    o->x_m += c->corr_m[0];
    o->y_m += c->corr_m[1];
}

int rover_ctl_beacon(rover_ctl_state *c, int32_t target, double range_m, double bearing_rad)
{
    pose2 o;
    if (!c->have_enc)
        return ROVER_CTL_ERR_ARG;
    if (target >= ROVER_LANDMARK_ID_BASE) {
        /* a landmark: the localizer's business (ignored with it off) */
        if (!localizing(c))
            return 0;
        return localize_landmark(&c->loc, target - ROVER_LANDMARK_ID_BASE, range_m, bearing_rad);
    }
    rover_ctl_own_pose(c, &o);
    if (target < c->team_lo || target > c->team_hi) {
        /* another team's robot (fleet.h): seen, not fused */
        if (!isfinite(range_m) || !isfinite(bearing_rad) || range_m < 0.0)
            return ROVER_CTL_ERR_ARG;
        rover_ctl_stranger_seen(c, target, &o, range_m, bearing_rad, c->enc_t_s);
        return 0;
    }
    return team_observe(&c->team, target, &o, range_m, bearing_rad, c->p.beacon_alpha, c->enc_t_s);
}

/* Frame consensus (team.h): every robot dead-reckons with its own drift,
 * so after a few metres the mates' frames disagree by decimetres: robots
 * stopped at their goal slots in their own frames, and a mate holding
 * its formation slot relative to them (the camera sees where they really
 * are) could never reach its own goal slot and circled it. Each robot
 * moves its estimate toward the team mean of the offsets it sees, at
 * consensus_gain (a first-order average over the team: the drifts average
 * out, the frames agree). */
void rover_ctl_frame_consensus(rover_ctl_state *c, double t_s, double dt_s)
{
    double off[2], k, dx, dy, len;
    int n;
    /* with landmarks every robot's frame is the world's: nothing to agree on */
    if (localizing(c))
        return;
    n = team_mean_offset(&c->team, t_s, c->p.consensus_age_s, c->p.consensus_range_m, off);
    if (n == 0)
        return;
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

/* Entry and exit distances along a ray from (px, py) with direction
 * (dx, dy) through a box (centre, half extents, heading as cos c, sin s);
 * 0 if it misses, 1 if it meets it (entry 0 when the ray starts inside). */
static int ray_box_m(double px, double py, double dx, double dy, double bx, double by, double hx,
                     double hy, double c, double s, double *t_in, double *t_out)
{
    double n_in[2];
    if (!sonar_line_box(px, py, dx, dy, bx, by, hx, hy, c, s, t_in, t_out, n_in))
        return 0;
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
        if (ray_box_m(px, py, dx, dy, bx, by, hx + MASK_GROW_M, hy + MASK_GROW_M, cth, sth, &t_in,
                      &t_out)) {
            hit = 1;
            if (t_in < *near_m)
                *near_m = t_in;
            if (t_out > *far_m)
                *far_m = t_out;
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
        if (team_position(&c->team, m->robot, xy) != 0)
            continue;
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
        if (isinf(masked[k]))
            masked[k] = c->p.sonar_max_m;
}

/* rover_ctl_mates: the priority order among mates and each robot's wait
 * set (docs/method/formation.md §10: why the wait-for graph is acyclic),
 * and where the mates' chassis are, by the team table, for keeping clear
 * of them while escaping, giving way or waiting (never turning into a
 * mate, whose way we are in, backing clear, the wedge turn, a follower's
 * lane, a command that meets a mate flying on). There is no rear
 * sonar and a mate's echo is masked out of the ring the follower uses, so
 * these answers come from geometry: each chassis a box ROVER_BODY_LENGTH_M
 * x ROVER_BODY_WIDTH_M, centred ROVER_BODY_OFFSET_M ahead of the axle C.
 */
#include "rover_ctl_internal.h"
#include "rover_world.h"

#include <math.h>

/* Chassis corners' reach round C (the box centre is ROVER_BODY_OFFSET_M
 * ahead of C): the circle a robot turning on the spot sweeps, 0.314 m. */
double rover_ctl_turn_reach_m(void)
{
    return hypot(0.5 * ROVER_BODY_LENGTH_M + fabs(ROVER_BODY_OFFSET_M), 0.5 * ROVER_BODY_WIDTH_M);
}

#define SPIN_MARGIN_M 0.03 /* what the team table's positions may be off by at contact range */

/* A box: centre, heading, half sizes. */
typedef struct {
    double x_m, y_m, theta_rad, hx_m, hy_m;
} box2;

/* Distance from (px, py) to box b (0 inside or on it). */
static double box_gap_m(const box2 *b, double px, double py)
{
    const double dx = px - b->x_m, dy = py - b->y_m;
    const double along = fabs(dx * cos(b->theta_rad) + dy * sin(b->theta_rad)) - b->hx_m;
    const double across = fabs(-dx * sin(b->theta_rad) + dy * cos(b->theta_rad)) - b->hy_m;
    return hypot(fmax(along, 0.0), fmax(across, 0.0));
}

static int in_box(double px, double py, const box2 *b)
{
    return box_gap_m(b, px, py) == 0.0;
}

/* Boxes a and b touch: a corner or side midpoint of either inside the
 * other (enough for the sizes here: neither box fits between the other's
 * sample points). */
static int boxes_touch(const box2 *a, const box2 *b)
{
    int k, pass;
    for (pass = 0; pass < 2; pass++) {
        const box2 *p = pass ? b : a, *q = pass ? a : b;
        const double cp = cos(p->theta_rad), sp = sin(p->theta_rad);
        for (k = 0; k < 9; k++) {
            /* NOLINTNEXTLINE(bugprone-integer-division): k / 3 - 1 is the cell row -1, 0 or 1 */
            const double u = (k % 3 - 1) * p->hx_m, v = (k / 3 - 1) * p->hy_m; /* -1, 0, 1 each */
            if (in_box(p->x_m + u * cp - v * sp, p->y_m + u * sp + v * cp, q))
                return 1;
        }
    }
    return 0;
}

/* The chassis box (grown by grow_m) of a robot whose axle C is at c. */
static box2 chassis_box(const pose2 *c, double grow_m)
{
    box2 b;
    double centre[2];
    rover_body_centre_of_c(c, centre);
    b.x_m = centre[0];
    b.y_m = centre[1];
    b.theta_rad = c->theta_rad;
    b.hx_m = 0.5 * ROVER_BODY_LENGTH_M + grow_m;
    b.hy_m = 0.5 * ROVER_BODY_WIDTH_M + grow_m;
    return b;
}

/* Mate i's axle pose C where the team table puts it; 0 or
 * TEAM_ERR_UNKNOWN. */
static int mate_c(const rover_ctl_state *c, int i, pose2 *mc)
{
    const team_member *m = &c->team.m[i];
    double xy[2];
    pose2 mo;
    if (team_position(&c->team, m->robot, xy) != 0)
        return TEAM_ERR_UNKNOWN;
    mo.x_m = xy[0];
    mo.y_m = xy[1];
    mo.theta_rad = m->theta_rad;
    unicycle_c_from_o(mc, &mo, c->p.beh.d_m);
    return 0;
}

/* Mate i's chassis box where the team table puts it, grown by grow_m; 0
 * or TEAM_ERR_UNKNOWN. */
static int mate_box(const rover_ctl_state *c, int i, double grow_m, box2 *b)
{
    pose2 mc;
    if (mate_c(c, i, &mc) != 0)
        return TEAM_ERR_UNKNOWN;
    *b = chassis_box(&mc, grow_m);
    return 0;
}

/* The lane the chassis of a robot whose axle is at c sweeps driving
 * ahead_m straight on, from the axle forward, SPIN_MARGIN_M wider. */
static box2 lane_box(const pose2 *c, double ahead_m)
{
    box2 lane;
    lane.theta_rad = c->theta_rad;
    lane.hx_m = 0.5 * (ROVER_BODY_OFFSET_M + 0.5 * ROVER_BODY_LENGTH_M + ahead_m);
    lane.hy_m = 0.5 * ROVER_BODY_WIDTH_M + SPIN_MARGIN_M;
    lane.x_m = c->x_m + lane.hx_m * cos(lane.theta_rad);
    lane.y_m = c->y_m + lane.hx_m * sin(lane.theta_rad);
    return lane;
}

/* The camera saw m within seen_s of t_s (walls hide beacons: a mate
 * behind a wall is in no conflict with us). */
static int now_seen(const team_member *m, double t_s, double seen_s)
{
    return t_s - m->obs_t_s <= seen_s;
}

/* A mate turning at least this fast (team table) may have its chassis at
 * any heading of its turning circle. */
#define MATE_TURNING_RADPS 0.1

/* ---- the priority order (docs/method/formation.md §10) -------------------
 * Every robot ranks every robot of the team by the same key, made only of
 * what each one broadcasts in its team message: first its class by its
 * announcement (escaping a dead zone, LEAVE, before giving way, GIVE_WAY,
 * before the rest), then its id. Ids are distinct, so the order is total. */
static int rank_class(int announce)
{
    return announce == FORMATION_ANN_LEAVE ? 0 : announce == FORMATION_ANN_GIVE_WAY ? 1 : 2;
}

int rover_ctl_outranks(int announce_a, int32_t id_a, int announce_b, int32_t id_b)
{
    const int ca = rank_class(announce_a), cb = rank_class(announce_b);
    return ca < cb || (ca == cb && id_a < id_b);
}

/* Mate i outranks us. */
static int mate_outranks(const rover_ctl_state *c, int i)
{
    return rover_ctl_outranks(c->team.m[i].announce, c->team.m[i].robot, rover_ctl_own_announce(c),
                              c->id);
}

/* Mate i turns on the spot (by the team table) and outranks us: where two
 * turn side by side it turns first. */
static int mate_turning_first(const rover_ctl_state *c, int i)
{
    const team_member *m = &c->team.m[i];
    return mate_outranks(c, i) && fabs(m->v_mps) <= ROVER_SPIN_V_MPS &&
           fabs(m->w_radps) >= MATE_TURNING_RADPS;
}

int rover_ctl_walls_near(const sonar_groups *gw, const rover_ctl_params *p)
{
    return fmin(fmin(gw->left_m, gw->left_front_m), fmin(gw->right_m, gw->right_front_m)) <
           p->follow_dist_m + p->walls_near_m;
}

/* Our chassis (axle at own_c, grown by SPIN_MARGIN_M) lies within the
 * circle a mate whose axle is at mc sweeps turning on the spot. */
static int in_turn_circle(const pose2 *own_c, const pose2 *mc)
{
    const box2 own = chassis_box(own_c, SPIN_MARGIN_M);
    return box_gap_m(&own, mc->x_m, mc->y_m) < rover_ctl_turn_reach_m();
}

/* Mate i (which outranks us) conflicts with us, as we see it: our chassis
 * within the circle it sweeps turning on the spot, anywhere (its circle is
 * its own: it may have to turn there, and only we can clear it); its axle
 * within yield_near_m of ours where either of us is out of the formation
 * (neither could turn on the spot), or where walls are near and its axle
 * lies ahead of ours (within 90 deg of our heading: a mate beside or
 * behind is not in our way forward, and standing for it stood the middle
 * of a line in a passage's mouth while the flank robot turned across it;
 * the third, standing for the middle, was left at the wall's end and went
 * round the outside: corridor, 3 in line, seeds 9, 11, 14, 44); with walls near, a
 * trapped mate (LEAVE) seen by the camera within give_way_m, ahead or
 * coming our way; both in formation, walls near, a mate within queue_m
 * ahead (queue_cone_rad) that stands or that we close on. In the open
 * nothing conflicts: the formation keeps its own spacing. */
static int mate_conflicts(const rover_ctl_state *c, const pose2 *o, int walls, int i, double t_s)
{
    const rover_ctl_params *p = &c->p;
    const team_member *m = &c->team.m[i];
    const int mate_out = rank_class(m->announce) < 2, self_out = c->esc.phase != ROVER_ESC_NONE;
    pose2 own_c, mc;
    double xy[2], dist, b;
    if (mate_c(c, i, &mc) != 0 || team_position(&c->team, m->robot, xy) != 0)
        return 0;
    unicycle_c_from_o(&own_c, o, p->beh.d_m);
    if (in_turn_circle(&own_c, &mc))
        return 1;
    if (hypot(mc.x_m - own_c.x_m, mc.y_m - own_c.y_m) < p->yield_near_m &&
        (mate_out || self_out ||
         (walls && fabs(vec2_angle_diff_rad(atan2(mc.y_m - own_c.y_m, mc.x_m - own_c.x_m),
                                            own_c.theta_rad)) < 0.5 * VEC2_PI)))
        return 1;
    if (!walls)
        return 0;
    dist = hypot(xy[0] - o->x_m, xy[1] - o->y_m);
    b = vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad);
    if (m->announce == FORMATION_ANN_LEAVE)
        return now_seen(m, t_s, p->give_way_seen_s) && dist < p->give_way_m &&
               (fabs(b) < 0.5 * VEC2_PI || rover_ctl_mate_coming(m, xy, o));
    return !mate_out && !self_out && dist < p->queue_m && fabs(b) < p->queue_cone_rad &&
           fabs(m->v_mps) < fmax(p->queue_slow_mps, c->v_est_mps - p->queue_closing_mps);
}

int rover_ctl_wait_set(const rover_ctl_state *c, const pose2 *o, const sonar_groups *gw, double t_s,
                       int32_t wait[TEAM_MAX])
{
    const int walls = rover_ctl_walls_near(gw, &c->p);
    int i, n = 0;
    for (i = 0; i < c->team.n && n < TEAM_MAX; i++)
        if (mate_outranks(c, i) && mate_conflicts(c, o, walls, i, t_s))
            wait[n++] = c->team.m[i].robot;
    return n;
}

int rover_ctl_mate_coming(const team_member *m, const double mate_xy_m[2], const pose2 *o)
{
    return cos(m->theta_rad) * (o->x_m - mate_xy_m[0]) +
               sin(m->theta_rad) * (o->y_m - mate_xy_m[1]) >
           0.0;
}

/* Turning on the spot now would sweep our chassis into a mate's: the id
 * of a mate whose chassis (where the team table puts it) lies within our
 * turning circle, or whose own turning circle (mate_turning_first) meets
 * ours, or 0 (two robots that turned at once, each clear of the other's
 * chassis as it stood, met tail to tail). Unlike rover_ctl_turn_blocked_by_mate this is
 * never waited out: two robots giving way side by side whose tails met did so when the
 * wait ran out with the other still turning. */
int32_t rover_ctl_spin_hits_mate(const rover_ctl_state *c, const pose2 *o)
{
    const double reach = rover_ctl_turn_reach_m() + SPIN_MARGIN_M;
    pose2 own_c, mc;
    box2 mb;
    int i;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (i = 0; i < c->team.n; i++) {
        if (mate_c(c, i, &mc) != 0)
            continue;
        mb = chassis_box(&mc, 0.0);
        if (box_gap_m(&mb, own_c.x_m, own_c.y_m) < reach ||
            (mate_turning_first(c, i) &&
             hypot(mc.x_m - own_c.x_m, mc.y_m - own_c.y_m) < reach + rover_ctl_turn_reach_m()))
            return c->team.m[i].robot;
    }
    return 0;
}

/* Turning on the spot the way dir (+1 left, -1 right) sweeps our chassis
 * into a mate's box (grown by SPIN_MARGIN_M) within the next
 * SPIN_LOOK_RAD: 1, else 0. Finer than rover_ctl_spin_hits_mate's whole
 * turning circle: a mate behind one flank is hit by the tail turning
 * toward that flank, not the other way. */
#define SPIN_LOOK_RAD 0.6
#define SPIN_LOOK_STEPS 6
int rover_ctl_turn_sweeps_mate(const rover_ctl_state *c, const pose2 *o, int dir)
{
    pose2 own_c;
    box2 mb;
    int i, k;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (i = 0; i < c->team.n; i++) {
        if (mate_box(c, i, SPIN_MARGIN_M, &mb) != 0)
            continue;
        for (k = 0; k <= SPIN_LOOK_STEPS; k++) {
            pose2 turned = own_c;
            box2 own;
            turned.theta_rad += dir * SPIN_LOOK_RAD * k / SPIN_LOOK_STEPS;
            own = chassis_box(&turned, 0.0);
            if (boxes_touch(&own, &mb))
                return 1;
        }
    }
    return 0;
}

/* Our chassis (grown by SPIN_MARGIN_M) is in mate i's way: within the
 * circle it sweeps turning on the spot, or in the lane its chassis sweeps
 * driving ahead_m straight on. The mate cannot know where we can go; we
 * clear its way when it outranks us (rover_ctl_escape.c). */
int rover_ctl_in_way_of(const rover_ctl_state *c, const pose2 *o, int32_t mate, double ahead_m)
{
    const team_member *m = team_find(&c->team, mate);
    pose2 own_c, mc;
    box2 own, lane;
    if (!m || mate_c(c, (int)(m - c->team.m), &mc) != 0)
        return 0;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    own = chassis_box(&own_c, SPIN_MARGIN_M);
    lane = lane_box(&mc, ahead_m);
    return in_turn_circle(&own_c, &mc) || boxes_touch(&own, &lane);
}

/* A mate's chassis (where the team table puts it, grown by SPIN_MARGIN_M)
 * reaches into the lane our chassis sweeps driving ahead_m straight on:
 * its corners and side midpoints against the lane, the lane's corners
 * against it. The follower follows walls (the ring with mates masked) and
 * keeps off mates by where they are: a mate's echo read as a wall ahead
 * froze a robot giving way that had the way out straight ahead, the mate
 * alongside it. */
int rover_ctl_mate_in_lane(const rover_ctl_state *c, const pose2 *o, double ahead_m)
{
    pose2 own_c;
    box2 lane, mb;
    int i;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    lane = lane_box(&own_c, ahead_m);
    for (i = 0; i < c->team.n; i++)
        if (mate_box(c, i, SPIN_MARGIN_M, &mb) == 0 && boxes_touch(&lane, &mb))
            return 1;
    return 0;
}

/* Mate i's chassis touches box b: its box where the team table puts it
 * (grown by SPIN_MARGIN_M), or, if it is turning, any heading of it (the
 * circle it sweeps round its axle). */
static int mate_touches(const rover_ctl_state *c, int i, const box2 *b)
{
    const team_member *m = &c->team.m[i];
    pose2 mc;
    box2 mb;
    if (mate_c(c, i, &mc) != 0)
        return 0;
    if (fabs(m->w_radps) >= MATE_TURNING_RADPS)
        return box_gap_m(b, mc.x_m, mc.y_m) < rover_ctl_turn_reach_m() + SPIN_MARGIN_M;
    mb = chassis_box(&mc, SPIN_MARGIN_M);
    return boxes_touch(b, &mb);
}

/* Backing reach_m along our crumbs keeps our chassis clear of every
 * mate's (mate_touches): our box posed at each crumb within reach_m (and
 * one crumb beyond) of path behind the axle, headed along the path (from
 * the crumb toward the next newer one). The mate we are wedged against
 * beside us is not in the way back; one that has since driven onto our
 * path, or turns on the spot beside it, is. 1 clear, else 0. */
int rover_ctl_crumbs_clear(const rover_ctl_state *c, const pose2 *o, double reach_m)
{
    pose2 own_c, at;
    double next[2], path_m = 0.0;
    box2 own;
    int i, k;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    next[0] = own_c.x_m;
    next[1] = own_c.y_m;
    for (k = c->crumb_n - 1; k >= 0 && path_m <= reach_m; k--) {
        const double seg_m = hypot(next[0] - c->crumb_m[k][0], next[1] - c->crumb_m[k][1]);
        at.x_m = c->crumb_m[k][0];
        at.y_m = c->crumb_m[k][1];
        path_m += seg_m;
        at.theta_rad = seg_m > 1e-6 ? atan2(next[1] - at.y_m, next[0] - at.x_m) : own_c.theta_rad;
        own = chassis_box(&at, 0.0);
        for (i = 0; i < c->team.n; i++)
            if (mate_touches(c, i, &own))
                return 0;
        next[0] = at.x_m;
        next[1] = at.y_m;
    }
    return 1;
}

/* Flying u for the next CMD_LOOK_S sweeps our chassis into the chassis of
 * a mate (mate_touches: its box where the team table puts it,
 * grown by SPIN_MARGIN_M, or its whole turning circle while it turns):
 * that mate's id, else 0. A mate we touch already counts only if the
 * motion brings our chassis nearer to it: driving on away from a mate
 * alongside is allowed (a lane test from the axle forward stopped a robot
 * giving way whose mate stood at its flank, and held three robots wedged
 * in the dead zone's mouth, 3 in line, seed 1). ROVER_SWEEP_WAITED: only
 * the mates of our wait set (c->wait_id), those that outrank us and
 * conflict with us, so that standing for them keeps the wait-for graph
 * acyclic. */
#define CMD_LOOK_S 1.0
#define CMD_LOOK_STEPS 10
/* p flown at v_mps, w_radps for dt_s (one Euler step of the unicycle). */
static void pose_step(pose2 *p, double v_mps, double w_radps, double dt_s)
{
    p->x_m += v_mps * dt_s * cos(p->theta_rad);
    p->y_m += v_mps * dt_s * sin(p->theta_rad);
    p->theta_rad += w_radps * dt_s;
}

/* 1 if mate `id` is in our wait set. */
static int waited_for(const rover_ctl_state *c, int32_t id)
{
    int k;
    for (k = 0; k < c->wait_n; k++)
        if (c->wait_id[k] == id)
            return 1;
    return 0;
}

int32_t rover_ctl_cmd_sweeps_mate(const rover_ctl_state *c, const pose2 *o, const unicycle_cmd *u,
                                  rover_sweep_mates which)
{
    pose2 own_c;
    int k, s;
    if (u->v_mps == 0.0 && u->w_radps == 0.0)
        return 0;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (k = 0; k < c->team.n; k++) {
        const team_member *m = &c->team.m[k];
        const int i = k;
        if (which == ROVER_SWEEP_WAITED && !waited_for(c, m->robot))
            continue;
        pose2 at = own_c, mc;
        box2 own = chassis_box(&own_c, 0.0);
        int touching;
        double d0;
        if (i < 0 || mate_c(c, i, &mc) != 0)
            continue;
        touching = mate_touches(c, i, &own);
        d0 = hypot(own.x_m - mc.x_m, own.y_m - mc.y_m);
        for (s = 1; s <= CMD_LOOK_STEPS; s++) {
            pose_step(&at, u->v_mps, u->w_radps, CMD_LOOK_S / CMD_LOOK_STEPS);
            own = chassis_box(&at, 0.0);
            if (!mate_touches(c, i, &own))
                continue;
            if (!touching || hypot(own.x_m - mc.x_m, own.y_m - mc.y_m) < d0)
                return m->robot;
        }
    }
    return 0;
}

/* Flying u for the next CMD_LOOK_S meets an outranking mate flying on as
 * the team table says it does (its speed and turn rate from its pose
 * there): our chassis and its box, grown by SPIN_MARGIN_M, touch at the
 * same moment, and do not now. Its id, else 0. A mate that stands is
 * rover_ctl_cmd_sweeps_mate's; only outranking ones: standing for them
 * keeps the wait-for graph acyclic. */
int32_t rover_ctl_cmd_meets_mate(const rover_ctl_state *c, const pose2 *o, const unicycle_cmd *u)
{
    const double dt = CMD_LOOK_S / CMD_LOOK_STEPS;
    pose2 own_c;
    int k, s;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (k = 0; k < c->team.n; k++) {
        const team_member *m = &c->team.m[k];
        pose2 at = own_c, mc;
        box2 own = chassis_box(&own_c, 0.0), mb;
        if (!mate_outranks(c, k) || !(fabs(m->v_mps) > c->p.queue_slow_mps) ||
            mate_c(c, k, &mc) != 0)
            continue;
        mb = chassis_box(&mc, SPIN_MARGIN_M);
        if (boxes_touch(&own, &mb))
            continue;
        for (s = 1; s <= CMD_LOOK_STEPS; s++) {
            pose_step(&at, u->v_mps, u->w_radps, dt);
            pose_step(&mc, m->v_mps, m->w_radps, dt);
            own = chassis_box(&at, 0.0);
            mb = chassis_box(&mc, SPIN_MARGIN_M);
            if (boxes_touch(&own, &mb))
                return m->robot;
        }
    }
    return 0;
}
